"""The dressing check of a merchant's garment version, run by a worker from the try-ons' queue.

Each size is sewn on its sample body (:func:`catwalk.simulate.fitcheck.sample_for`)
standing, with the ``fast`` preset, and reported as ``dressed`` or ``failed`` with the numbers
(:func:`catwalk.simulate.fitcheck.dressing_check`): seams welded, penetration, strain against
the fabric's limit. A size that dressed leaves its dressed .glb (meshopt, as the catalogue's
``dressed.glb``) for the editor's preview; the default size's also becomes the garment's
thumbnail. The reports are written after each size, so the merchant sees them come in.
"""

from __future__ import annotations

import json
import logging
import threading
import time
import traceback

from catwalk.catalogue.bodies import sample_body
from catwalk.config import Config
from catwalk.errors import Cancelled, InputError
from catwalk.exchange.garment_json import load_garment
from catwalk.service import merchant_garments as mg
from catwalk.service.store.files import Storage
from catwalk.service.thumbnails import dressed_files, thumbnail_path
from catwalk.simulate.fitcheck import dressing_check, sample_for

log = logging.getLogger("catwalk.worker")

BEAT_S = 1.0


class _Beat(threading.Thread):
    """Writes the reports so far every second (the check's heartbeat); notices when the check
    is no longer this attempt's."""

    def __init__(self, config: Config, garment_id: str, version: int, attempt: int,
                 dressing: dict):
        super().__init__(name=f"check-{garment_id[:12]}", daemon=True)
        self.args = (config, garment_id, version, attempt)
        self.dressing = dressing
        self.lost = threading.Event()
        self._done = threading.Event()

    def run(self) -> None:
        while not self._done.wait(BEAT_S):
            try:
                if not mg.record_check(*self.args, self.dressing):
                    self.lost.set()
            except Exception as exc:  # noqa: BLE001 - the database away: keep checking
                log.warning(json.dumps({"event": "check_beat_failed",
                                        "error": type(exc).__name__}))

    def finish(self) -> None:
        self._done.set()
        self.join(timeout=5)


def run_check(config: Config, garment_id: str, version: int) -> str:
    """Run the version's dressing check if it is this worker's to run; how it ended."""
    row = mg.claim_check(config, garment_id, version)
    if row is None:
        return "skipped"
    log.info(json.dumps({"event": "check_started", "garment": garment_id, "version": version,
                         "attempt": row.check_attempts}))
    storage = Storage(config.storage_dir)
    folder = storage.merchant_garment_dir(garment_id, version)
    dressing = {size: dict(rep) for size, rep in row.dressing.items()}
    beat = _Beat(config, garment_id, version, row.check_attempts, dressing)
    beat.start()
    t0 = time.perf_counter()
    try:
        _check_sizes(storage, folder, garment_id, row.content, dressing, beat.lost.is_set)
    except Cancelled:
        return "cancelled"
    except Exception as exc:  # noqa: BLE001 - reported on every size not yet checked
        if not isinstance(exc, InputError):
            log.error(json.dumps({"event": "check_crashed", "garment": garment_id,
                                  "trace": traceback.format_exc()[-4000:]}))
        for rep in dressing.values():
            if rep.get("status") not in ("dressed", "failed"):
                rep.update(status="failed", ok=False,
                           message=f"the check could not run: {exc}"[:500])
    finally:
        beat.finish()
    mg.record_check(config, garment_id, version, row.check_attempts, dressing, "done")
    log.info(json.dumps({"event": "check_done", "garment": garment_id, "version": version,
                         "seconds": round(time.perf_counter() - t0, 2),
                         "dressed": sum(r.get("status") == "dressed"
                                        for r in dressing.values()),
                         "sizes": len(dressing)}))
    return "done"


def _check_sizes(storage: Storage, folder, garment_id: str, content: str, dressing: dict,
                 lost) -> None:
    garment = load_garment(folder / "garment.json")
    default = garment.size(None)
    for size in garment.sizes:
        if dressing.get(size, {}).get("status") in ("dressed", "failed"):
            continue   # an earlier attempt checked it
        if lost():
            raise Cancelled("the check was taken over")
        sample = sample_for(garment, size)
        dressing[size] = {"status": "running", "sample": sample}
        body = sample_body(sample, storage.samples_dir())
        report, res = dressing_check(body, garment, size, cancel=lost)
        rep = {**report, "status": "dressed" if report["ok"] else "failed", "sample": sample}
        if res is not None:
            _store_dressed(storage, folder, garment_id, content, size, size == default, res)
            rep["glb"] = True
        dressing[size] = rep


def _store_dressed(storage: Storage, folder, garment_id: str, content: str, size: str,
                   thumbnail: bool, res) -> None:
    """The dressed size as a meshopt .glb beside the version; the default size also as the
    catalogue's thumbnail and dressed view (the paths the API's thumbnails look for)."""
    (storage.root / "garments").mkdir(parents=True, exist_ok=True)
    web, png = dressed_files(res, storage.root / "garments")
    storage.write(folder / "dressed" / f"{size}.glb", web)
    if thumbnail:
        path = thumbnail_path(storage, garment_id, content)
        storage.write(path.with_suffix(".glb"), web)
        storage.write(path, png)
