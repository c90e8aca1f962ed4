"""Logs: one JSON object per line on stderr, each event with its job or body id.

Code logs ``json.dumps({"event": …, "job": …})``; this formatter adds the time, level and
logger. Nothing personal is ever passed to it: no measurements, no scan, no key.
"""

from __future__ import annotations

import json
import logging
import sys
import time


class JsonLines(logging.Formatter):
    def format(self, record: logging.LogRecord) -> str:
        msg = record.getMessage()
        try:
            data = json.loads(msg)
            if not isinstance(data, dict):
                data = {"message": msg}
        except ValueError:
            data = {"message": msg}
        out = {"time": time.strftime("%Y-%m-%dT%H:%M:%S", time.gmtime(record.created))
               + f".{int(record.msecs):03d}Z", "level": record.levelname.lower(),
               "logger": record.name, **data}
        if record.exc_info and "trace" not in out:
            out["trace"] = self.formatException(record.exc_info)[-4000:]
        return json.dumps(out, default=str)


def configure(level: str = "INFO") -> None:
    """JSON lines on stderr for catwalk's loggers and the servers under it."""
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(JsonLines())
    root = logging.getLogger()
    root.handlers[:] = [handler]
    root.setLevel(level.upper())
    for name in ("uvicorn", "uvicorn.error", "uvicorn.access", "celery"):
        lg = logging.getLogger(name)
        lg.handlers[:] = []
        lg.propagate = True
    for name in ("alembic", "kombu"):   # their start-up chatter
        logging.getLogger(name).setLevel(max(logging.WARNING, root.level))
