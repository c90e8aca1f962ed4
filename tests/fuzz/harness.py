"""Running readers on fuzzed inputs: a separate process per reader run, with a time limit.

:class:`Worker` keeps one ``worker.py`` process; :meth:`Worker.run` sends it one input and
waits at most ``TIME_LIMIT`` seconds, killing and restarting it past that (a hang), or when
it dies (a crash). :func:`check` turns an answer into a test failure unless the reader either
succeeded with a sane result or raised :class:`catwalk.errors.InputError`.

How many inputs each fuzzer tries: ``CATWALK_FUZZ_EXAMPLES`` (default
:data:`DEFAULT_EXAMPLES`, so the whole suite stays within a minute); ``make fuzz`` runs
10,000 (``FUZZ_EXAMPLES=N`` for another count). ``CATWALK_FUZZ_SEED`` makes the run random
with that seed (default: hypothesis's derandomised, repeatable run).
"""

from __future__ import annotations

import os
import pickle
import select
import struct
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

TIME_LIMIT = 5.0          # seconds per input (the limit)
START_LIMIT = 120.0       # seconds for a fresh worker to import catwalk
DEFAULT_EXAMPLES = 25

# per fuzzer: inputs tried and outcomes (printed at the end of the session)
TALLY: dict[str, Counter] = {}


def examples() -> int:
    raw = os.environ.get("CATWALK_FUZZ_EXAMPLES", "")
    try:
        return max(1, int(raw)) if raw else DEFAULT_EXAMPLES
    except ValueError:
        return DEFAULT_EXAMPLES


def fuzz_settings(**kw):
    """Hypothesis settings for the fuzzers: the example count from the environment, no
    deadline (the worker enforces :data:`TIME_LIMIT`), no shrinking (a reader run may take
    seconds; the failing input is reported as found)."""
    from hypothesis import HealthCheck, Phase, settings

    seed = os.environ.get("CATWALK_FUZZ_SEED")
    return settings(max_examples=examples(), deadline=None, database=None,
                    derandomize=seed is None, print_blob=False,
                    phases=[Phase.explicit, Phase.generate],
                    suppress_health_check=list(HealthCheck), **kw)


class Worker:
    def __init__(self) -> None:
        self.proc: subprocess.Popen | None = None
        self.restarts = 0

    def _start(self) -> None:
        env = dict(os.environ)
        env.setdefault("NUMBA_NUM_THREADS", "2")
        self.proc = subprocess.Popen([sys.executable, str(Path(__file__).with_name("worker.py"))],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.DEVNULL, env=env)
        ready = self._read(1, START_LIMIT)
        if ready != b"R":
            self.close()
            raise RuntimeError("the fuzz worker did not start")

    def _read(self, n: int, limit: float) -> bytes | None:
        """``n`` bytes from the worker within ``limit`` seconds (None: too late or it died)."""
        fd = self.proc.stdout.fileno()
        buf = b""
        end = time.monotonic() + limit
        while len(buf) < n:
            left = end - time.monotonic()
            if left <= 0:
                return None
            r, _, _ = select.select([fd], [], [], left)
            if not r:
                return None
            chunk = os.read(fd, n - len(buf))
            if not chunk:
                return None
            buf += chunk
        return buf

    def run(self, reader: str, data: bytes, extra: dict | None = None,
            limit: float = TIME_LIMIT) -> dict:
        if self.proc is None or self.proc.poll() is not None:
            self._start()
        msg = pickle.dumps((reader, bytes(data), extra or {}))
        t0 = time.monotonic()
        try:
            self.proc.stdin.write(struct.pack("<Q", len(msg)) + msg)
            self.proc.stdin.flush()
        except BrokenPipeError:
            return self._lost(t0, "the worker died")
        head = self._read(8, limit)
        if head is None:
            return self._lost(t0, "no answer")
        (n,) = struct.unpack("<Q", head)
        body = self._read(n, 30.0)
        if body is None:
            return self._lost(t0, "a garbled answer")
        return pickle.loads(body)

    def _lost(self, t0: float, why: str) -> dict:
        waited = time.monotonic() - t0
        code = self.proc.poll()
        self.close()
        self.restarts += 1
        if code is None or waited >= TIME_LIMIT:
            return {"outcome": "hang", "message": f"{why} within {waited:.1f} s (limit "
                    f"{TIME_LIMIT:g} s)", "seconds": waited}
        return {"outcome": "bug", "message": f"{why}: the reader process died with status "
                f"{code} (a crash, or killed for memory)", "seconds": waited}

    def close(self) -> None:
        if self.proc is not None:
            if self.proc.poll() is None:
                self.proc.kill()
            self.proc.wait()
            for s in (self.proc.stdin, self.proc.stdout):
                try:
                    s.close()
                except OSError:
                    pass
            self.proc = None


def check(name: str, answer: dict, data: bytes, describe: str = "") -> None:
    """Fail the test unless the reader succeeded sanely or raised InputError; tally it."""
    TALLY.setdefault(name, Counter())[answer["outcome"]] += 1
    if answer["outcome"] in ("ok", "input_error"):
        return
    keep = os.environ.get("CATWALK_FUZZ_KEEP")
    where = ""
    if keep:   # keep the failing input to reproduce it
        Path(keep).mkdir(parents=True, exist_ok=True)
        f = Path(keep) / f"{name}-{len(list(Path(keep).iterdir()))}.bin"
        f.write_bytes(data)
        where = f" (input kept in {f})"
    raise AssertionError(f"{name}: {answer['outcome']}: {answer['message']}{where}\n"
                         f"{describe}\n{answer.get('traceback', '')}")
