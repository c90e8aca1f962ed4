"""The try-on job, as a worker runs it (:data:`~catwalk.service.jobs.app.TASK`). A job:

1. is claimed in the database (:func:`catwalk.service.jobs.lifecycle.claim`): a duplicate
   message, or one for a job that ended or was cancelled, does nothing;
2. runs ``catwalk.tryon`` with a heartbeat thread that writes the progress (one fraction, the
   stage) every 0.25 s and reads back whether the job was cancelled, deleted or taken over —
   the simulation then stops within half a second;
3. writes its files (the .glb, its meshopt copy for the web, a preview sheet, the metrics) into
   ``results/<key>/`` whole, then marks the job done and adds the result's row: a result is
   stored exactly once, and nothing half-written is ever served.
"""

from __future__ import annotations

import io
import json
import logging
import shutil
import threading
import time
import traceback

from PIL import Image
from sqlalchemy.exc import InterfaceError, OperationalError

from catwalk.config import Config
from catwalk.errors import Cancelled, CatwalkError, InputError, SetupError, SimulationError
from catwalk.exchange.compress import compress_bytes
from catwalk.exchange.gltf import read_body
from catwalk.exchange.scene import scene_of
from catwalk.render.sheet import render_sheet
from catwalk.service.catalogue import Catalogue
from catwalk.service.jobs import lifecycle
from catwalk.service.jobs.lifecycle import worker_name
from catwalk.service.keys import sha256
from catwalk.service.store.files import Storage
from catwalk.simulate.progress import Progress, export_weight, tryon_plan
from catwalk.simulate.settings import preset
from catwalk.simulate.tryon import tryon
from catwalk.simulate.walking import blend_frame_count

log = logging.getLogger("catwalk.worker")




PREVIEW_TIMES = (0.2, 0.4, 0.6, 0.8)    # fractions of the walk


PREVIEW_SIZE = (360, 540)


BEAT_S = 0.25


# extra stages after the simulation, in the units of catwalk.simulate.progress.tryon_plan
COMPRESS_WEIGHT = 25.0


PREVIEW_WEIGHT = 40.0


class Beat(threading.Thread):
    """The job's heartbeat: progress out to the database, cancellation back in."""

    def __init__(self, config: Config, job_id: str, attempt: int):
        super().__init__(name=f"beat-{job_id[:8]}", daemon=True)
        self.config, self.job_id, self.attempt = config, job_id, attempt
        self.fraction, self.stage = 0.0, "starting"
        self.stop_asked = threading.Event()     # the job was cancelled, deleted, taken over
        self._done = threading.Event()
        self.timings: dict[str, float] = {}     # seconds spent in each stage
        self._since = time.perf_counter()

    def report(self, stage: str, fraction: float, total: float = 1.0) -> None:
        """The try-on's overall progress (:class:`~catwalk.simulate.progress.Progress`'s
        report: ``total`` is 1)."""
        if stage != self.stage:
            self.lap()
        self.fraction, self.stage = fraction, stage

    def lap(self) -> dict[str, float]:
        """Add the time since the last change of stage to the stage's; the timings so far."""
        now = time.perf_counter()
        self.timings[self.stage] = round(self.timings.get(self.stage, 0.0) + now - self._since, 4)
        self._since = now
        return self.timings

    def cancelled(self) -> bool:
        return self.stop_asked.is_set()

    def run(self) -> None:
        while not self._done.wait(BEAT_S):
            try:
                if not lifecycle.heartbeat(self.config, self.job_id, self.attempt, self.fraction,
                                           self.stage):
                    self.stop_asked.set()
            except Exception as exc:   # the database is away: keep simulating, try again
                log.warning(json.dumps({"event": "heartbeat_failed", "job": self.job_id,
                                        "error": type(exc).__name__}))

    def finish(self) -> None:
        self._done.set()
        self.join(timeout=5)


def _recorded(write, config: Config, job_id: str, *args):
    """``write(config, job_id, *args)`` (a job's end written to the database), tried again
    while the database cannot be reached, for up to ``job_stale_s``: a job done during a short
    outage is recorded by its own attempt (past that, it looks dead and recovery runs it
    again, which finds its result stored)."""
    deadline = time.monotonic() + config.job_stale_s
    while True:
        try:
            return write(config, job_id, *args)
        except (OperationalError, InterfaceError) as exc:
            if time.monotonic() >= deadline:
                raise
            log.warning(json.dumps({"event": "database_away", "job": job_id,
                                    "error": type(exc).__name__}))
            time.sleep(0.5)


def run_job(config: Config, job_id: str) -> str:
    """Run one job if it is this worker's to run; returns how it ended."""
    row = lifecycle.claim(config, job_id, worker_name())
    if row is None:
        log.info(json.dumps({"event": "skipped", "job": job_id}))
        return "skipped"
    log.info(json.dumps({"event": "started", "job": job_id, "attempt": row.attempts,
                         "garment": row.garment_id, "size": row.size, "preset": row.preset}))
    beat = Beat(config, job_id, row.attempts)
    beat.start()
    t0 = time.perf_counter()
    try:
        outcome = _execute(config, row, beat)
    except Cancelled:
        _recorded(lifecycle.end, config, job_id, row.attempts, "cancelled", "cancelled", beat.lap())
        outcome = "cancelled"
    except (InputError, SimulationError) as exc:
        _recorded(lifecycle.end, config, job_id, row.attempts, "failed", str(exc), beat.lap())
        outcome = "failed"
    except CatwalkError as exc:
        _recorded(lifecycle.end, config, job_id, row.attempts, "failed",
                  f"the service could not run it: {exc}", beat.lap())
        outcome = "failed"
    except Exception as exc:
        from celery.exceptions import SoftTimeLimitExceeded

        if isinstance(exc, SoftTimeLimitExceeded):
            reason = f"over the {config.job_time_limit_s:g} s time limit"
        else:
            log.error(json.dumps({"event": "crashed", "job": job_id,
                                  "trace": traceback.format_exc()[-4000:]}))
            reason = f"internal error ({type(exc).__name__}); the job was not finished"
        _recorded(lifecycle.end, config, job_id, row.attempts, "failed", reason, beat.lap())
        outcome = "failed"
    finally:
        beat.finish()
    log.info(json.dumps({"event": outcome, "job": job_id,
                         "seconds": round(time.perf_counter() - t0, 3)}))
    return outcome


def _execute(config: Config, row, beat: Beat) -> str:
    storage = Storage(config.storage_dir)
    if storage.result_file(row.key, "metrics.json").is_file():
        return _finish_stored(config, row, storage, beat)   # an earlier attempt stored it
    entry = _catalogue(config).get(row.garment_id)
    if entry.version != row.garment_version:   # changed within the last second? look again
        entry = _catalogue(config).get(row.garment_id, recheck=True)
    if entry.version != row.garment_version:
        raise InputError(f"garment {row.garment_id!r} has changed since this try-on was asked "
                         "for; ask for it again", "garment_id")
    body_path = storage.body_glb(row.body_id)
    if not body_path.is_file():
        raise InputError("the body has been deleted", "body_id")
    settings = preset(row.preset)
    frames = int(round(row.seconds * 30.0))
    plan = tryon_plan(settings, frames, blend_frame_count(settings, 30.0), True,
                      extra=[("exporting", export_weight(frames)),
                             ("compressing", COMPRESS_WEIGHT), ("preview", PREVIEW_WEIGHT)])
    progress = Progress(plan, beat.report, beat.cancelled)
    res = tryon(read_body(body_path), entry.garment, size=row.size, fabric=row.fabric,
                seconds=row.seconds, preset=row.preset, garment_id=row.garment_id,
                progress=progress)
    progress.enter("exporting")
    glb = res.glb()
    _check_space(storage, 3 * len(glb))
    progress.enter("compressing")   # the web copy: no normal targets (the player makes them)
    web, compression = compress_bytes(res.glb(normals=False), cancel=progress.cancelled,
                                      workdir=storage.root / "results")   # swept, not /tmp
    progress.enter("preview")
    png = preview_png(res, progress.cancelled)
    progress.check()
    metrics = dict(res.metrics, compression=compression)
    files = {"tryon.glb": glb, "tryon.web.glb": web, "preview.png": png,
             "metrics.json": (json.dumps(metrics, indent=2) + "\n").encode()}
    try:
        stored = storage.store_result(row.key, files)
    except OSError as exc:   # the folder is whole or absent: never half a result
        raise SetupError(f"the result could not be stored: {exc.strerror or exc}") from None
    sizes = {"glb_bytes": len(glb), "web_bytes": len(web), "glb_sha256": sha256(glb),
             "web_sha256": sha256(web)}
    if not _recorded(lifecycle.finish, config, row.id, row.attempts, row.key, metrics, sizes,
                     beat.lap()):
        # cancelled, deleted (its body too) or taken over meanwhile
        if stored and lifecycle.result(config, row.key) is None and \
                not lifecycle.result_in_use(config, row.key):
            storage.remove_result(row.key)
        raise Cancelled("the job was cancelled or taken over while it was being stored")
    return "done"


def _check_space(storage: Storage, need: int) -> None:
    """Refuse before writing when the storage cannot hold the result (with room to spare)."""
    where = storage.root / "results"
    where.mkdir(parents=True, exist_ok=True)
    free = shutil.disk_usage(where).free
    if free < need:
        raise SetupError(f"the storage is full: {free / 1e6:.1f} MB free where the result needs "
                         f"about {need / 1e6:.1f} MB")


def _finish_stored(config: Config, row, storage: Storage, beat: Beat) -> str:
    """Finish a job whose result is already stored under its key (an earlier attempt wrote
    it and died before its row, or a twin job of the same key did)."""
    glb = storage.result_file(row.key, "tryon.glb").read_bytes()
    web = storage.result_file(row.key, "tryon.web.glb").read_bytes()
    metrics = json.loads(storage.result_file(row.key, "metrics.json").read_text())
    sizes = {"glb_bytes": len(glb), "web_bytes": len(web), "glb_sha256": sha256(glb),
             "web_sha256": sha256(web)}
    if not _recorded(lifecycle.finish, config, row.id, row.attempts, row.key, metrics, sizes,
                     beat.lap()):
        raise Cancelled("the job was cancelled or taken over")
    return "done"


_CATALOGUES: dict = {}


def _catalogue(config: Config) -> Catalogue:
    """This process's catalogue (read again only when a file in it changes)."""
    if config not in _CATALOGUES:
        _CATALOGUES[config] = Catalogue(config)
    return _CATALOGUES[config]


def preview_png(res, cancel=None) -> bytes:
    """A contact sheet of the try-on: four moments of the walk, front and side (the sheet
    ``catwalk render`` draws)."""
    if cancel is not None and cancel():
        raise Cancelled("try-on cancelled")
    scene = scene_of(res.body, res.motion, [res.frames()])
    # on recorded frames: between two the garment holds its frame (STEP) while the body moves
    fps = res.motion.fps if res.motion is not None else 30.0
    frames = scene.garments[0].frames
    times = [round(f * (frames - 1)) / fps for f in PREVIEW_TIMES] if frames > 1 else [0.0]
    image = render_sheet(scene, times, ["front", "side"], PREVIEW_SIZE, cancel)
    buf = io.BytesIO()
    Image.fromarray(image).save(buf, format="PNG")
    return buf.getvalue()
