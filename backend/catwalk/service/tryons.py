"""The try-ons shoppers ask for, as the service keeps them: a request answered from the cache
(its result stored under the same key), joined to this body's running try-on of the same key,
or queued as a new job; and a try-on's view (with its result's metrics once done).

On a shop (a :class:`~catwalk.service.bodies.Scope`) a try-on is asked for the shopper's own
body there and one of that merchant's published garments; it is read through that shop only
(its id reached from anywhere else is unknown), like its body (:mod:`catwalk.service.bodies`).

Two requests at once for the same try-on: the unique index on active (body, key) lets one row
in; the other gets that row. A result answered from the cache cannot be deleted (its last body
going) while the new try-on is added: its row is locked until the new row is in."""

from __future__ import annotations

from sqlalchemy.exc import IntegrityError

from catwalk.cloth.fabrics import resolve_fabric
from catwalk.config import Config
from catwalk.errors import InputError, NotFound
from catwalk.service import keys
from catwalk.service.bodies import Scope, visible
from catwalk.service.jobs import lifecycle
from catwalk.service.store import db
from catwalk.service.store.files import Storage
from catwalk.service.store.models import BodyRow, ResultRow, TryOnRow, utcnow


def _with_metrics(s, row: TryOnRow) -> dict:
    """The try-on's JSON; a done one with its result's metrics (read in session ``s``)."""
    out = lifecycle.view(row)
    if row.status == "done" and (res := s.get(ResultRow, row.key)) is not None:
        out["metrics"] = res.metrics
    return out


def view(config: Config, row: TryOnRow) -> dict:
    """The try-on's JSON (:func:`catwalk.service.jobs.lifecycle.view`, with its metrics)."""
    with db.session(config) as s:
        return _with_metrics(s, row)


def _reachable(s, row: TryOnRow | None, scope: Scope | None) -> bool:
    """Whether who asks reaches the try-on: from the shop its body was made on (any shopper
    of it: a try-on's id, like a link, opens its result but never its body), or, for a body of
    catwalk's own pages, without a shop."""
    if row is None:
        return False
    body = s.get(BodyRow, row.body_id)
    owner = body.merchant_id if body is not None else None
    return owner == (scope.merchant_id if scope is not None else None)


def get(config: Config, job_id: str, scope: Scope | None = None) -> TryOnRow | None:
    """The try-on, if who asks (``scope``) can reach it."""
    with db.session(config) as s:
        row = s.get(TryOnRow, job_id)
        return row if _reachable(s, row, scope) else None


def view_of(config: Config, job_id: str, scope: Scope | None = None) -> dict:
    """The try-on's JSON, read in one transaction (:class:`NotFound` for an unknown id, or
    one who asks cannot reach)."""
    with db.session(config) as s:
        row = s.get(TryOnRow, job_id)
        if not _reachable(s, row, scope):
            raise NotFound("try-on", job_id)
        return _with_metrics(s, row)


def submit(config: Config, catalogue, storage: Storage, body_id: str, garment_id: str,
           size: str | None, fabric: str | None, seconds: float, preset: str,
           scope: Scope | None = None) -> tuple[TryOnRow, bool, dict]:
    """The try-on row for the request: a new queued one, this body's running one with the
    same key, or a done one answered from the cache; (row, needs sending, its JSON).
    :class:`NotFound` for an unknown body or garment (on a shop: a body not the shopper's
    there, a garment not the merchant's published one), :class:`InputError` for a size or
    fabric the garment does not have."""
    try:
        entry = catalogue.get(garment_id, merchant_id=scope.merchant_id if scope else None)
    except InputError:
        entry = None
    with db.session(config) as s:   # the body and its running try-on read at once
        body = s.get(BodyRow, body_id)
        if not visible(body, scope):
            raise NotFound("body", body_id, "body_id")
        if entry is None:
            raise NotFound("garment", garment_id, "garment_id")
        g = entry.garment
        if size is not None and size not in g.sizes:
            raise InputError(f"garment {garment_id!r} has no size {size!r} (sizes: "
                             f"{', '.join(g.sizes)})", "size")
        size = g.size(size)
        fabric = None if fabric in (None, entry.fabric) else fabric
        if fabric is not None:
            if fabric not in entry.fabrics:
                raise InputError(f"unknown fabric {fabric!r} (choose from "
                                 f"{', '.join(entry.fabrics)})", "fabric")
            resolve_fabric(fabric, "fabric")
        key = keys.tryon_key(body.content_key, entry.id, entry.version, size, fabric, seconds,
                             preset)
        running = lifecycle.active_in(s, body.id, key)
        if running is not None:
            return running, False, lifecycle.view(running)
    try:
        return _add(config, storage, body, entry, size, fabric, seconds, preset, key)
    except IntegrityError:
        running = lifecycle.active_for(config, body.id, key)
        if running is None:
            raise
        return running, False, lifecycle.view(running)


def _add(config, storage, body, entry, size, fabric, seconds, preset, key
         ) -> tuple[TryOnRow, bool, dict]:
    stored = storage.result_file(key, "tryon.glb").is_file()
    with lifecycle.results_lock(config), db.session(config) as s:
        # shared while the files are there (answers from the cache do not wait for each
        # other); exclusive when the row is to go
        result = lifecycle.lock_result(s, key, shared=stored)
        if result is not None and not storage.result_file(key, "tryon.glb").is_file():
            s.delete(result)   # its files are gone (storage lost or wiped): make it again
            result = None
        cached = result is not None
        now = utcnow()
        row = TryOnRow(id=lifecycle.new_id(), key=key, body_id=body.id, garment_id=entry.id,
                       garment_version=entry.version, size=size, fabric=fabric,
                       seconds=seconds, preset=preset, cancel_requested=False,
                       attempts=0, cached=cached, created_at=now, enqueued_at=now,
                       status="done" if cached else "queued", progress=1.0 if cached else 0.0,
                       stage="done" if cached else "queued",
                       finished_at=now if cached else None)
        s.add(row)
        view = lifecycle.view(row)
        if cached:
            view["metrics"] = result.metrics
    return row, not cached, view
