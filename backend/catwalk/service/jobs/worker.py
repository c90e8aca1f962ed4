"""The worker: runs try-on jobs from the queue (``catwalk worker [--concurrency N]``).

One task, :data:`~catwalk.service.jobs.app.TASK`, for every deployment. A job:

1. is claimed in the database (:func:`catwalk.service.jobs.lifecycle.claim`): a duplicate message,
or one
   for a job that ended or was cancelled, does nothing;
2. runs ``catwalk.tryon`` with a heartbeat thread that writes the progress (one fraction, the
   stage) every 0.25 s and reads back whether the job was cancelled, deleted or taken over —
   the simulation then stops within half a second;
3. writes its files (the .glb, its meshopt copy for the web, a preview sheet, the metrics) into
   ``results/<key>/`` whole, then marks the job done and adds the result's row: a result is
   stored exactly once, and nothing half-written is ever served.

The numba kernels are loaded once, in the worker's main process before the pool forks (a small
try-on at start), so no job pays for them.
"""

from __future__ import annotations

import json
import logging
import os
import socket
import time

from celery.signals import worker_ready, worker_shutdown

from catwalk.body.rig import measured_base_body
from catwalk.catalogue.garments import catalogue_dir
from catwalk.config import Config, get_config
from catwalk.errors import CatwalkError
from catwalk.exchange.garment_json import load_garment
from catwalk.exchange.scene import scene_of
from catwalk.service import logs
from catwalk.service.jobs import lifecycle
from catwalk.service.jobs.app import CHECK_TASK, TASK, celery_app
from catwalk.service.jobs.check import run_check
from catwalk.service.jobs.lifecycle import worker_name
from catwalk.service.jobs.recovery import Recovery
from catwalk.service.jobs.tryon import preview_png, run_job
from catwalk.service.store import db
from catwalk.service.store.files import Storage
from catwalk.simulate.tryon import tryon

log = logging.getLogger("catwalk.worker")


def register_tasks(app, config: Config) -> None:
    @app.task(name=TASK, acks_late=True, reject_on_worker_lost=True, ignore_result=True)
    def run_tryon(job_id: str) -> str:
        return run_job(config, job_id)


    @app.task(name=CHECK_TASK, acks_late=True, reject_on_worker_lost=True, ignore_result=True)
    def check_garment(garment_id: str, version: int) -> str:
        return run_check(config, garment_id, version)


# ------------------------------------------------------------------------------ starting

def warm_up() -> float:
    """Load every kernel a try-on uses (a small one, 0.3 s of walk); returns the seconds."""
    t0 = time.perf_counter()
    files = sorted(catalogue_dir().glob("*.json"))
    skirt = catalogue_dir() / "pencil-skirt.json"
    for path in ([skirt] if skirt.is_file() else []) + files:
        try:
            garment = load_garment(path)
            break
        except CatwalkError:
            continue
    else:
        log.warning(json.dumps({"event": "no_warm_up", "reason": "no readable garment in "
                                "the catalogue: the first job loads the kernels"}))
        return 0.0
    res = tryon(measured_base_body(0.0), garment, preset="fast", h=0.04,
                seconds=0.3)
    res.glb()
    scene_of(res.body, res.motion, [res.frames()]).meshes_at(0.0)
    preview_png(res)
    return time.perf_counter() - t0


def main(concurrency: int | None = None, loglevel: str | None = None) -> int:
    """``catwalk worker``: migrate, load the kernels, then consume jobs until stopped."""
    config = get_config()
    logs.configure(loglevel or config.log_level)
    db.migrate(config)
    Storage(config.storage_dir).check()
    n = concurrency or max(1, config.workers)
    log.info(json.dumps({"event": "warming_up", "worker": worker_name()}))
    log.info(json.dumps({"event": "ready", "worker": worker_name(), "concurrency": n,
                         "warm_up_s": round(warm_up(), 2), "queue": config.queue}))

    # after the pool's first children are made (replacements are forked later with it
    # running: the engines are per process and db's lock is made anew in a child)
    worker_ready.connect(lambda **_: Recovery(config, concurrency=n).start(), weak=False)

    worker_shutdown.connect(lambda **_: lifecycle.gone(config, worker_name()), weak=False)
    app = celery_app(config)
    register_tasks(app, config)
    argv = ["--quiet", "worker", f"--concurrency={n}", f"--queues={config.queue}", "--pool=prefork",
            f"--loglevel={(loglevel or config.log_level).upper()}", "--without-gossip",
            "--without-mingle", "--without-heartbeat", "-O", "fair",
            f"--hostname=catwalk-{os.getpid()}@{socket.gethostname()}"]
    app.worker_main(argv)
    return 0
