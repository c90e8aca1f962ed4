"""``catwalk serve``: the API and local workers on one machine.

With nothing configured this is the embedded default: SQLite and the filesystem broker in the
storage folder, the API on 127.0.0.1:8000 and one ``catwalk worker`` process running as many
jobs at once as the machine has cores. The worker is a child process in its own process group;
if it dies it is started again (its jobs are recovered from the database), and it is stopped
with the API. ``--workers 0`` runs the API alone (workers elsewhere, against the same
database, broker and storage).
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import signal
import subprocess
import sys
import threading
import time

import uvicorn

from catwalk.config import get_config
from catwalk.service import logs
from catwalk.service.api.app import create_app
from catwalk.service.children import die_with_parent
from catwalk.service.store import db

log = logging.getLogger("catwalk.serve")


class WorkerProcess(threading.Thread):
    """Keeps one ``catwalk worker --concurrency N`` child running."""

    def __init__(self, concurrency: int):
        super().__init__(name="worker-process", daemon=True)
        self.concurrency = concurrency
        self.proc: subprocess.Popen | None = None
        self.stopping = threading.Event()

    def _start(self) -> subprocess.Popen:
        cmd = [sys.executable, "-m", "catwalk.cli.main", "worker",
               f"--concurrency={self.concurrency}"]
        return subprocess.Popen(cmd, start_new_session=True, preexec_fn=die_with_parent)

    def run(self) -> None:
        backoff = 1.0
        while not self.stopping.is_set():
            t0 = time.monotonic()
            self.proc = self._start()
            log.info(json.dumps({"event": "worker_started", "pid": self.proc.pid,
                                 "concurrency": self.concurrency}))
            code = self.proc.wait()
            if self.stopping.is_set():
                return
            log.warning(json.dumps({"event": "worker_exited", "code": code}))
            backoff = 1.0 if time.monotonic() - t0 > 60 else min(backoff * 2, 30.0)
            self.stopping.wait(backoff)

    def stop(self, timeout: float = 20.0) -> None:
        self.stopping.set()
        p = self.proc
        if p is None or p.poll() is not None:
            return
        with contextlib.suppress(ProcessLookupError):
            p.send_signal(signal.SIGTERM)   # Celery's warm shutdown: it stops its pool
        try:
            p.wait(timeout)
        except subprocess.TimeoutExpired:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(p.pid, signal.SIGKILL)
            p.wait()


def main(host: str = "127.0.0.1", port: int = 8000, workers: int | None = None) -> int:
    config = get_config()
    logs.configure(config.log_level)
    db.migrate(config)
    n = config.workers if workers is None else workers
    worker = None
    if n > 0:
        worker = WorkerProcess(n)
        worker.start()
    app = create_app(config, frontend=config.frontend_dir)
    log.info(json.dumps({"event": "serving", "url": f"http://{host}:{port}",
                         "storage": str(config.storage_dir), "embedded": config.embedded,
                         "workers": n}))
    try:
        uvicorn.run(app, host=host, port=port, log_config=None, access_log=False,
                    timeout_graceful_shutdown=5)
    finally:
        if worker is not None:
            worker.stop()
    return 0
