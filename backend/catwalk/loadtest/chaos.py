"""``catwalk loadtest --chaos``: the shoppers' load against a service of its own while its
parts fail, and what was lost.

The run starts its own stack (:class:`~catwalk.loadtest.stack.Stack`: Redis and PostgreSQL
in a temporary folder, ``catwalk serve --workers 0`` and two ``catwalk worker`` processes),
runs the Locust shoppers against it for ``seconds`` and meanwhile SIGKILLs a worker (its whole
process group) every ``kill_every`` seconds, starting another in its place, restarts Redis
once (a third of the way in: the broker's queue is lost) and PostgreSQL once (two thirds in).
After the load it waits for every try-on asked to end, then reports:

- the try-ons asked, done, failed (with their reasons), **lost** (asked and never ended) and
  **done twice** (a worker finished the same job more than once: the workers' logs);
- every 5xx answered, a 503 that says when to come back (``Retry-After``) told apart from the
  **unexpected** ones;
- requests/s and p99 before the first fault, and in the seconds after each fault.
"""

from __future__ import annotations

import collections
import contextlib
import json
import os
import re
import subprocess
import tempfile
import threading
import time
from pathlib import Path

import psycopg

from catwalk.errors import InputError
from catwalk.loadtest.run import locust_command, prepare, summary
from catwalk.loadtest.stack import Stack

WINDOW_S = 10    # a fault's "during": the seconds after it; "after": the last WINDOW_S
DRAIN_S = 600    # how long the run waits after the load for the try-ons still going


def _faults(seconds: float, kill_every: float) -> list[tuple[float, str]]:
    """(second, fault) in order: a worker killed every ``kill_every`` s, Redis restarted at a
    third of the run, PostgreSQL at two thirds."""
    out = [(t, "kill_worker") for t in _range(kill_every, seconds - WINDOW_S, kill_every)]
    out += [(seconds / 3 + 2, "restart_redis"), (2 * seconds / 3 + 2, "restart_postgres")]
    return sorted(out)


def _range(start: float, stop: float, step: float) -> list[float]:
    out, t = [], start
    while t < stop:
        out.append(t)
        t += step
    return out


def _inject(stack: Stack, faults, t0: float, done: threading.Event, log: list) -> None:
    """Apply the faults at their seconds (a thread beside the load)."""
    for at, fault in faults:
        wait = t0 + at - time.monotonic()
        if wait > 0 and done.wait(wait):
            return
        started = time.monotonic() - t0
        if fault == "kill_worker":
            detail = f"pid {stack.kill_worker()}"
        elif fault == "restart_redis":
            stack.stop_redis()
            stack.start_redis()
            detail = "its queue lost (no persistence)"
        else:
            stack.stop_postgres("fast")
            stack.start_postgres()
            detail = "fast shutdown, then started"
        log.append({"at_s": round(started, 1), "fault": fault, "detail": detail,
                    "took_s": round(time.monotonic() - t0 - started, 1)})


def _window(timeline: list, lo: float, hi: float) -> dict:
    """Requests/s and the worst second's p99 (ms) over seconds [lo, hi)."""
    rows = [r for r in timeline if lo <= r[0] < hi]
    span = max(1.0, hi - lo)
    return {"from_s": round(lo, 1), "to_s": round(hi, 1),
            "rps": round(sum(r[1] for r in rows) / span, 1),
            "p99_ms": max((r[2] for r in rows), default=None)}


def _outcomes(stack: Stack, asked: list[str]) -> dict:
    """Every try-on asked: how it ended (from the database) and how often a worker said it
    finished it (from the workers' logs)."""
    url = stack.env["CATWALK_DATABASE_URL"].replace("+psycopg", "")
    with psycopg.connect(url) as conn:
        rows = conn.execute("SELECT id, status, error FROM tryons WHERE id = ANY(%s)",
                            (asked,)).fetchall()
    status = {r[0]: (r[1], r[2]) for r in rows}
    finished = collections.Counter()
    for log in stack.worker_logs:
        for line in log.read_text(errors="replace").splitlines():
            m = re.search(r'"event": "done", "job": "([^"]+)"', line)
            if m:
                finished[m.group(1)] += 1
    failed = collections.Counter(status[j][1] or "?" for j in asked
                                 if j in status and status[j][0] == "failed")
    return {"asked": len(asked),
            "done": sum(1 for j in asked if status.get(j, ("",))[0] == "done"),
            "failed": sum(failed.values()), "failed_reasons": dict(failed),
            "cancelled": sum(1 for j in asked if status.get(j, ("",))[0] == "cancelled"),
            "lost": sorted(j for j in asked if status.get(j, ("",))[0] not in
                           ("done", "failed", "cancelled")),
            "done_twice": sorted(j for j, n in finished.items() if n > 1 and j in status)}


def _drain(stack: Stack, asked: list[str], seconds: float) -> None:
    """Wait until every try-on asked has ended (or ``seconds`` passed)."""
    url = stack.env["CATWALK_DATABASE_URL"].replace("+psycopg", "")
    t0 = time.monotonic()
    while time.monotonic() - t0 < seconds:
        with contextlib.suppress(psycopg.Error), psycopg.connect(url) as conn:
            going = conn.execute("SELECT count(*) FROM tryons WHERE id = ANY(%s) AND status "
                                 "IN ('queued', 'running')", (asked,)).fetchone()[0]
            if going == 0:
                return
        time.sleep(2)


def run(users: int = 20, seconds: float = 180.0, kill_every: float = 20.0,
        garment: str = "pencil-skirt", keep: str | None = None) -> dict:
    """The chaos run (module docstring); ``keep``: a folder to keep the stack's logs in."""
    if seconds < 60:
        raise InputError(f"--seconds must be at least 60 for a chaos run, got {seconds:g}")
    if kill_every < 5:
        raise InputError(f"--kill-every must be at least 5 s, got {kill_every:g}")
    with tempfile.TemporaryDirectory(prefix="catwalk-chaos-") as tmp:
        if os.geteuid() == 0:
            # PostgreSQL runs as its own user (stack.py): it must pass through the folder
            os.chmod(tmp, 0o711)
        root = Path(keep) if keep else Path(tmp)
        root.mkdir(parents=True, exist_ok=True)
        stack = Stack(root / "stack")
        try:
            stack.start()
            body, done_id = prepare(stack.url, garment)
            out = root / "locust.json"
            cmd, env = locust_command(stack.url, users, seconds, "shoppers", garment, body,
                                      done_id, out)
            faults = _faults(seconds, kill_every)
            log: list = []
            stop = threading.Event()
            locust = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE,
                                      stderr=subprocess.STDOUT, text=True)
            t0 = time.monotonic()
            injector = threading.Thread(target=_inject, args=(stack, faults, t0, stop, log),
                                        daemon=True)
            injector.start()
            output, _ = locust.communicate(timeout=seconds + 900)
            stop.set()
            injector.join(timeout=120)
            load = summary(out, locust.returncode, output or "", "shoppers", users)
            _drain(stack, load["asked_ids"], DRAIN_S)
            outcomes = _outcomes(stack, load["asked_ids"])
        finally:
            stack.stop()
    return _report(users, seconds, load, log, outcomes)


def _report(users: int, seconds: float, load: dict, log: list, outcomes: dict) -> dict:
    timeline = load["timeline"]
    first = log[0]["at_s"] if log else seconds
    windows = {"before": _window(timeline, 0, first),
               "after": _window(timeline, seconds - WINDOW_S, seconds)}
    for f in log:
        f["during"] = _window(timeline, f["at_s"], f["at_s"] + WINDOW_S)
    errors = load["server_errors"]
    unexpected = {k: n for k, n in errors.items() if not k.startswith("503 Retry-After")}
    return {"users": users, "seconds": seconds, "requests": load["requests"],
            "rps": load["rps"], "faults": log, "windows": windows,
            "tryons": {k: v for k, v in outcomes.items() if k not in ("lost", "done_twice")}
            | {"lost": len(outcomes["lost"]), "lost_ids": outcomes["lost"][:20],
               "done_twice": len(outcomes["done_twice"]),
               "done_twice_ids": outcomes["done_twice"][:20]},
            "server_errors": errors, "unexpected_5xx": sum(unexpected.values()),
            "ok": not outcomes["lost"] and not outcomes["done_twice"] and not unexpected}


def format_report(r: dict) -> str:
    t = r["tryons"]
    lines = [f"catwalk loadtest --chaos: {r['users']} shoppers for {r['seconds']:.0f} s, "
             f"{r['requests']} requests ({r['rps']:.0f}/s): "
             f"{'OK' if r['ok'] else 'NOT OK'}",
             f"  try-ons asked {t['asked']}, done {t['done']}, failed {t['failed']}, "
             f"cancelled {t['cancelled']}, lost {t['lost']}, done twice {t['done_twice']}",
             f"  5xx: {json.dumps(r['server_errors'])} (unexpected: {r['unexpected_5xx']})",
             f"  {'window':28s} {'req/s':>7s} {'p99 ms':>8s}",
             f"  {'before the first fault':28s} {r['windows']['before']['rps']:7.1f} "
             f"{r['windows']['before']['p99_ms'] or 0:8.0f}"]
    for f in r["faults"]:
        d = f["during"]
        lines.append(f"  {f['fault'] + ' @' + str(f['at_s']) + ' s':28s} {d['rps']:7.1f} "
                     f"{d['p99_ms'] or 0:8.0f}")
    a = r["windows"]["after"]
    lines.append(f"  {'the last ' + str(WINDOW_S) + ' s':28s} {a['rps']:7.1f} "
                 f"{a['p99_ms'] or 0:8.0f}")
    lines += [f"  failed: {reason} ×{n}" for reason, n in t["failed_reasons"].items()]
    return "\n".join(lines)
