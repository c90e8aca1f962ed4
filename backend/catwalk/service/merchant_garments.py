"""A merchant's garments: uploads checked and stored as immutable versions, published into the
catalogue, deleted; the dressing check of each version as a job.

An upload is a garment JSON with its texture files, or a DXF cutting pattern with its markup
(``docs/garment-format.md``). It is read and checked exactly as ``catwalk garment check``
does, in a hidden folder of the storage; every problem comes back at once
(:class:`UploadRejected`), and nothing is stored. A sound upload becomes version ``n`` of the
garment: its folder ``garments/<id>/<n>/`` (``garment.json`` as catwalk writes it, and the
textures at the paths it names) is renamed into place whole, then its row is written. Versions
are never changed: a try-on made with one stays valid, cached under that version's content
hash. Publishing puts a version in the catalogue (``GET /api/garments``).

Each version's dressing check (the garment sewn on each size's sample body, in a worker, from
the try-ons' queue) is a small job of its own: ``queued`` → ``running`` (claimed, with a
heartbeat) → ``done``; a check whose worker died is run again by the recovery loop.
"""

from __future__ import annotations

import os
import re
import secrets
import shutil
import tempfile
from dataclasses import dataclass, field
from datetime import timedelta
from pathlib import Path

from sqlalchemy import and_, or_, select, update

from catwalk.config import Config
from catwalk.errors import InputError
from catwalk.exchange.dxf import pieces_to_garment, read_dxf
from catwalk.exchange.garment_json import garment_bytes, garment_from_dict
from catwalk.exchange.markup import apply_markup, load_markup
from catwalk.exchange.source import read_json
from catwalk.garment.check import check_garment, problem
from catwalk.service.keys import garment_version
from catwalk.service.store import db
from catwalk.service.store.files import Storage
from catwalk.service.store.models import GarmentVersionRow, MerchantGarmentRow, utcnow

MAX_FILES = 64                      # texture files of one upload
TEXTURE_SUFFIXES = (".png", ".jpg", ".jpeg", ".webp")
_FILE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}(/[A-Za-z0-9][A-Za-z0-9._-]{0,99}){0,3}")
MAX_CHECK_ATTEMPTS = 3


class UploadRejected(InputError):
    """An upload with problems: ``problems`` lists each as ``{"panel"?, "edge"?, "message"}``."""

    def __init__(self, problems: list[dict]):
        n = len(problems)
        super().__init__(f"the garment has {n} problem{'s' if n != 1 else ''}: "
                         + "; ".join(p["message"] for p in problems[:5])
                         + (" …" if n > 5 else ""))
        self.problems = problems


class Conflict(InputError):
    """Another request made the same version of the garment at the same time (HTTP 409)."""

    def __init__(self, garment_id: str):
        super().__init__(f"garment {garment_id!r} was changed by another request at the same "
                         "time; send it again", "version")


@dataclass
class Upload:
    """What a merchant sent: the garment JSON (``garment``), or a DXF and its markup; texture
    files by the paths the garment names."""
    garment: bytes | None = None
    dxf: bytes | None = None
    markup: bytes | None = None
    units: str | None = None
    files: dict[str, bytes] = field(default_factory=dict)


@dataclass
class Prepared:
    folder: Path            # the checked files, in a hidden folder of the storage
    garment: object         # catwalk.garment.model.Garment
    content: str            # catalogue.garment_version of the files
    warnings: list[dict]    # {"code", "message", "panel"?, "piece"?, "size"?, …}


def _problems(messages: list[str]) -> list[dict]:
    return [problem(m) for m in messages]


def warning_objects(warnings: list) -> list[dict]:
    """Warnings as objects (versions stored before they were: their text as the message)."""
    return [w if isinstance(w, dict) else {"message": str(w)} for w in warnings]


def panel_names(warnings: list[dict], g, markup: dict | None = None) -> list[dict]:
    """The import's warnings with the panel each concerns, as named after the markup's
    renames (``panel``, beside the DXF's ``piece``)."""
    raw = markup.get("panels") if isinstance(markup, dict) else None
    renames = {k: v["name"] for k, v in (raw or {}).items()
               if isinstance(v, dict) and isinstance(v.get("name"), str)}
    names = {p.name for p in g.panels}
    out = []
    for w in warnings:
        panel = renames.get(w.get("piece"), w.get("piece"))
        out.append(w | {"panel": panel} if panel in names else w)
    return out


def _check_file_name(name: str) -> str:
    if not isinstance(name, str) or not _FILE_NAME.fullmatch(name) or ".." in name.split("/"):
        raise UploadRejected([{"message": f"file {str(name)[:80]!r}: a texture's file name is "
                                          "the relative path the garment names (letters, "
                                          "digits, '.', '_', '-', at most 4 folders deep)"}])
    if not name.lower().endswith(TEXTURE_SUFFIXES):
        raise UploadRejected([{"message": f"file {name!r}: a texture is an image "
                                          f"({', '.join(TEXTURE_SUFFIXES)})"}])
    return name


def _read_garment(upload: Upload, folder: Path, messages: list[str]):
    """The garment the upload describes (its reader's first refusal raised as a problem)."""
    if upload.garment is not None:
        parsed, _ = read_json(upload.garment, "garment")
        return garment_from_dict(parsed, folder / "garment.json", name="garment",
                                 problems=messages)

    markup = load_markup(upload.markup)
    pieces, warnings = read_dxf(upload.dxf, units=upload.units)
    g = pieces_to_garment(pieces, str(markup.get("name") or "garment")[:200],
                          source={"importer": "catwalk merchant upload"})
    apply_markup(g, markup, "markup")
    g.path = folder / "garment.json"
    return g, panel_names(warnings, g, markup)


def prepare(storage: Storage, upload: Upload, previous: Path | None = None) -> Prepared:
    """Read and check ``upload`` in a hidden folder of the storage; raises
    :class:`UploadRejected` listing every problem (the folder removed). ``previous``: the
    garment's latest version's folder, whose textures stand in for those not sent again."""
    if (upload.garment is None) == (upload.dxf is None):
        raise InputError("send either `garment` (a garment JSON) or `dxf` with `markup`",
                         "garment")
    if upload.dxf is not None and upload.markup is None:
        raise InputError("a `dxf` comes with its `markup` (seams, panel types, placement, "
                         "fabric, sizes)", "markup")
    if len(upload.files) > MAX_FILES:
        raise InputError(f"{len(upload.files)} files; at most {MAX_FILES} textures", "files")
    root = storage.root / "garments"
    root.mkdir(parents=True, exist_ok=True)
    folder = Path(tempfile.mkdtemp(prefix=".upload-", dir=root))
    try:
        for name, data in upload.files.items():
            target = folder / _check_file_name(name)
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
        messages: list[str] = []
        warnings: list[dict] = []
        try:
            got = _read_garment(upload, folder, messages)
        except InputError as exc:
            raise UploadRejected(_problems([str(exc)])) from None
        g, warnings = got if isinstance(got, tuple) else (got, [])
        named = {str(p.texture["image"]) for p in g.panels if p.texture is not None}
        for name in sorted(named - set(upload.files)):   # kept from the previous version
            old = previous / name if previous is not None else None
            if old is not None and old.is_file() and _FILE_NAME.fullmatch(name):
                (folder / name).parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(old, folder / name)
        for name in sorted(set(upload.files) - named):
            warnings.append({"code": "file-not-kept", "file": name,
                             "message": f"file {name!r} is not named by any panel's texture: "
                                        "not kept"})
            (folder / name).unlink()
        report = check_garment(g, folder)
        messages.extend(report.errors)
        if messages:   # the storage's own paths are not the merchant's business
            raise UploadRejected(_problems([m.replace(f"{folder}/", "") for m in messages]))
        warnings.extend({"code": "check"} | problem(w) for w in report.warnings)
        (folder / "garment.json").write_bytes(garment_bytes(g))
        return Prepared(folder, g, garment_version(folder / "garment.json", g), warnings)
    except BaseException:
        shutil.rmtree(folder, ignore_errors=True)
        raise


def _new_id(name: str) -> str:
    slug = re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-")[:40] or "garment"
    return f"{slug}-{secrets.token_hex(4)}"


def _version_view(v: GarmentVersionRow, garment_id: str) -> dict:
    dressing = {}
    for size, rep in (v.dressing or {}).items():
        rep = dict(rep)
        if rep.get("status") in ("dressed", "failed") and rep.get("glb"):
            rep["glb_url"] = (f"/api/merchant/garments/{garment_id}/versions/{v.version}/"
                              f"dressed/{size}.glb")
        rep.pop("glb", None)
        dressing[size] = rep
    return {"version": v.version, "content": v.content,
            "created_at": v.created_at.isoformat() + "Z", "sizes": list(v.sizes),
            "warnings": warning_objects(v.warnings), "check_status": v.check_status,
            "dressing": dressing}


def view(row: MerchantGarmentRow, versions: list[GarmentVersionRow]) -> dict:
    return {"id": row.id, "name": row.name, "type": row.type, "version": row.version,
            "published_version": row.published_version,
            "sizes": list(next((v.sizes for v in versions if v.version == row.version), [])),
            "created_at": row.created_at.isoformat() + "Z",
            "updated_at": row.updated_at.isoformat() + "Z",
            "catalogue_url": f"/api/garments/{row.id}" if row.published_version else None,
            "versions": [_version_view(v, row.id) for v in
                         sorted(versions, key=lambda v: -v.version)]}


def _queued_report(sizes: list[str]) -> dict:
    return {s: {"status": "queued"} for s in sizes}


def store(config: Config, storage: Storage, merchant_id: str, prepared: Prepared,
          garment_id: str | None = None, taken: set[str] = frozenset()) -> dict:
    """Store a checked upload as a new garment (``garment_id`` None; ``taken``: the catalogue
    ids already in use) or as the next version of the merchant's garment ``garment_id``.
    Returns the version's answer (``id``, ``version``, ``sizes``, ``warnings``, ``dressing``)."""
    g = prepared.garment
    now = utcnow()
    with db.session(config) as s:
        if garment_id is None:
            garment_id = _new_id(g.name)
            while garment_id in taken or s.get(MerchantGarmentRow, garment_id) is not None:
                garment_id = _new_id(g.name)
            n = 1
        else:
            row = _own(s, merchant_id, garment_id)
            n = row.version + 1
        final = storage.merchant_garment_dir(garment_id, n)
        final.parent.mkdir(parents=True, exist_ok=True)
        try:
            os.rename(prepared.folder, final)   # fails if another upload took version n
        except OSError:
            shutil.rmtree(prepared.folder, ignore_errors=True)
            raise Conflict(garment_id) from None
        try:
            if n == 1:
                s.add(MerchantGarmentRow(id=garment_id, merchant_id=merchant_id, name=g.name,
                                         type=g.type, version=1, created_at=now,
                                         updated_at=now))
                s.flush()
            else:
                done = s.execute(update(MerchantGarmentRow)
                                 .where(MerchantGarmentRow.id == garment_id,
                                        MerchantGarmentRow.version == n - 1)
                                 .values(version=n, name=g.name, type=g.type, updated_at=now)
                                 .execution_options(synchronize_session=False))
                if done.rowcount != 1:
                    raise Conflict(garment_id)
            s.add(GarmentVersionRow(garment_id=garment_id, version=n, content=prepared.content,
                                    created_at=now, sizes=list(g.sizes),
                                    warnings=prepared.warnings,
                                    dressing=_queued_report(list(g.sizes)),
                                    check_status="queued", check_attempts=0))
            s.flush()
        except BaseException:
            shutil.rmtree(final, ignore_errors=True)
            raise
    return {"id": garment_id, "version": n, "sizes": list(g.sizes),
            "warnings": prepared.warnings, "dressing": _queued_report(list(g.sizes))}


def _own(session, merchant_id: str, garment_id: str) -> MerchantGarmentRow:
    """The merchant's own garment (not deleted); another's, or none, is "no such garment"."""
    row = session.get(MerchantGarmentRow, garment_id)
    if row is None or row.merchant_id != merchant_id or row.deleted_at is not None:
        raise LookupError(garment_id)
    return row


def _versions(session, garment_id: str) -> list[GarmentVersionRow]:
    return list(session.scalars(select(GarmentVersionRow)
                                .where(GarmentVersionRow.garment_id == garment_id)))


def own_garments(config: Config, merchant_id: str) -> list[dict]:
    with db.session(config) as s:
        rows = s.scalars(select(MerchantGarmentRow)
                         .where(MerchantGarmentRow.merchant_id == merchant_id,
                                MerchantGarmentRow.deleted_at.is_(None))
                         .order_by(MerchantGarmentRow.created_at)).all()
        versions: dict[str, list] = {r.id: [] for r in rows}
        if rows:
            for v in s.scalars(select(GarmentVersionRow)
                               .where(GarmentVersionRow.garment_id.in_(list(versions)))):
                versions[v.garment_id].append(v)
        return [view(r, versions[r.id]) for r in rows]


def own_garment(config: Config, merchant_id: str, garment_id: str) -> dict:
    """The merchant's garment (raises LookupError if it is not theirs)."""
    with db.session(config) as s:
        row = _own(s, merchant_id, garment_id)
        return view(row, _versions(s, garment_id))


def latest_folder(config: Config, storage: Storage, merchant_id: str, garment_id: str) -> Path:
    with db.session(config) as s:
        row = _own(s, merchant_id, garment_id)
        return storage.merchant_garment_dir(garment_id, row.version)


def version_folder(config: Config, storage: Storage, merchant_id: str, garment_id: str,
                   version: int) -> Path:
    with db.session(config) as s:
        _own(s, merchant_id, garment_id)
        if s.get(GarmentVersionRow, (garment_id, version)) is None:
            raise LookupError(f"{garment_id} v{version}")
    return storage.merchant_garment_dir(garment_id, version)


def publish(config: Config, merchant_id: str, garment_id: str, version: int | None) -> dict:
    """Put ``version`` (default: the latest) in the catalogue."""
    with db.session(config) as s:
        row = _own(s, merchant_id, garment_id)
        n = row.version if version is None else version
        if s.get(GarmentVersionRow, (garment_id, n)) is None:
            raise InputError(f"garment {garment_id!r} has no version {n} (versions 1…"
                             f"{row.version})", "version")
        row.published_version = n
        row.updated_at = utcnow()
        s.flush()
        return view(row, _versions(s, garment_id))


def delete(config: Config, merchant_id: str, garment_id: str) -> None:
    """Take the garment out of the catalogue and the merchant's list. Its versions' files stay
    (try-ons made with them keep their results; a try-on asked for it now is refused)."""
    with db.session(config) as s:
        row = _own(s, merchant_id, garment_id)
        row.deleted_at = utcnow()
        row.published_version = None


def published(config: Config) -> list[tuple[str, int, str, str]]:
    """(id, version, content, merchant id) of every published garment, for the catalogue."""
    with db.session(config) as s:
        rows = s.execute(select(MerchantGarmentRow.id, MerchantGarmentRow.published_version,
                                GarmentVersionRow.content, MerchantGarmentRow.merchant_id)
                         .join(GarmentVersionRow, and_(
                             GarmentVersionRow.garment_id == MerchantGarmentRow.id,
                             GarmentVersionRow.version == MerchantGarmentRow.published_version))
                         .where(MerchantGarmentRow.deleted_at.is_(None))
                         .order_by(MerchantGarmentRow.created_at)).all()
        return [(r[0], int(r[1]), r[2], r[3]) for r in rows]


# ---------------------------------------------------------------- the dressing check as a job

def claim_check(config: Config, garment_id: str, version: int) -> GarmentVersionRow | None:
    """Take the version's dressing check if it is queued, or running with a stale heartbeat."""
    now = utcnow()
    stale = now - timedelta(seconds=config.job_stale_s)
    with db.session(config) as s:
        res = s.execute(
            update(GarmentVersionRow)
            .where(GarmentVersionRow.garment_id == garment_id,
                   GarmentVersionRow.version == version,
                   or_(GarmentVersionRow.check_status == "queued",
                       and_(GarmentVersionRow.check_status == "running",
                            GarmentVersionRow.check_beat_at < stale)),
                   GarmentVersionRow.check_attempts < MAX_CHECK_ATTEMPTS)
            .values(check_status="running", check_beat_at=now,
                    check_attempts=GarmentVersionRow.check_attempts + 1)
            .execution_options(synchronize_session=False))
        if res.rowcount != 1:
            return None
        return s.get(GarmentVersionRow, (garment_id, version))


def record_check(config: Config, garment_id: str, version: int, attempt: int, dressing: dict,
                 status: str = "running") -> bool:
    """Write the check's reports so far (and beat); False if the check is no longer this
    attempt's."""
    with db.session(config) as s:
        res = s.execute(
            update(GarmentVersionRow)
            .where(GarmentVersionRow.garment_id == garment_id,
                   GarmentVersionRow.version == version,
                   GarmentVersionRow.check_attempts == attempt,
                   GarmentVersionRow.check_status == "running")
            .values(dressing=dressing, check_status=status, check_beat_at=utcnow())
            .execution_options(synchronize_session=False))
        return res.rowcount == 1


def recover_checks(config: Config, send) -> list[tuple[str, int]]:
    """Checks whose worker stopped beating go back to the queue (``send(id, version)``), or
    end after MAX_CHECK_ATTEMPTS with every unfinished size failed."""
    now = utcnow()
    stale = now - timedelta(seconds=config.job_stale_s)
    again = []
    with db.session(config) as s:
        dead = s.scalars(select(GarmentVersionRow).where(
            GarmentVersionRow.check_status == "running",
            GarmentVersionRow.check_beat_at < stale)).all()
        for v in dead:
            if v.check_attempts >= MAX_CHECK_ATTEMPTS:
                dressing = {size: rep if rep.get("status") in ("dressed", "failed") else
                            {"status": "failed", "ok": False,
                             "message": f"the check's worker stopped {MAX_CHECK_ATTEMPTS} "
                                        "times (a crash, or the time limit)"}
                            for size, rep in v.dressing.items()}
                values = {"check_status": "done", "dressing": dressing}
            else:
                values = {"check_status": "queued"}
                again.append((v.garment_id, v.version))
            s.execute(update(GarmentVersionRow)
                      .where(GarmentVersionRow.garment_id == v.garment_id,
                             GarmentVersionRow.version == v.version,
                             GarmentVersionRow.check_status == "running",
                             GarmentVersionRow.check_beat_at < stale)
                      .values(**values).execution_options(synchronize_session=False))
    for garment_id, version in again:
        send(garment_id, version)
    return again
