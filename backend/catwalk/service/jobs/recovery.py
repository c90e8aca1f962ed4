"""Recovery: jobs and dressing checks whose worker died, or whose message the broker lost,
sent again — a thread in the API's process and in every worker's main process."""

from __future__ import annotations

import contextlib
import json
import logging
import threading

from catwalk.config import Config
from catwalk.service.jobs import lifecycle
from catwalk.service.jobs.app import queued_messages, send, send_check
from catwalk.service.jobs.lifecycle import worker_name
from catwalk.service.merchant_garments import recover_checks

log = logging.getLogger("catwalk.worker")



class Recovery(threading.Thread):
    """Runs :func:`catwalk.service.jobs.lifecycle.recover` every few seconds (in the API and in
    every worker's main process: their updates are conditional, so several never clash). In a
    worker it also marks the worker as seen (``concurrency``: its pool's size)."""

    def __init__(self, config: Config, every_s: float = 2.0, concurrency: int | None = None):
        super().__init__(name="recovery", daemon=True)
        self.config, self.every_s, self.concurrency = config, every_s, concurrency
        self.stop = threading.Event()

    def run(self) -> None:
        while not self.stop.wait(self.every_s):
            if self.concurrency is not None:
                with contextlib.suppress(Exception):
                    lifecycle.seen(self.config, worker_name(), self.concurrency)
            try:
                did = lifecycle.recover(self.config, lambda j: send(self.config, j),
                                        lambda: queued_messages(self.config))
                did["checks"] = recover_checks(
                    self.config, lambda g, v: send_check(self.config, g, v))
                if any(did.values()):
                    log.info(json.dumps({"event": "recovered", **did}))
            except Exception as exc:
                log.warning(json.dumps({"event": "recovery_failed",
                                        "error": f"{type(exc).__name__}: {exc}"[:300]}))
