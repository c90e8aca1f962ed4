"""Running the load test: Locust headless in its own process, its summary read back."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import httpx

from catwalk.errors import InputError, SetupError
from catwalk.service.client import ApiFailure, Client

LOCUSTFILE = Path(__file__).resolve().with_name("locustfile.py")


BODY = {"sex": "female", "height": 1.68, "bust": 0.90, "waist": 0.72, "hips": 0.98}


def prepare(url: str, garment: str) -> tuple[str, str]:
    """A body and a finished fast try-on of ``garment`` (waits for a worker): their ids."""
    try:
        with Client(url, timeout=300) as api:
            body = api.create_body(**BODY)
            job = api.create_tryon(body_id=body["id"], garment_id=garment, preset="fast",
                                   seconds=0.5)
            if job["status"] != "done":
                job = api.wait(job["id"], timeout=900, poll=0.5)
    except ApiFailure as exc:
        raise InputError(f"the service refused the load test's set-up: {exc}") from None
    if job["status"] != "done":
        raise SetupError(f"the load test's first try-on {job['status']}: {job.get('error')} "
                         "(is a worker running?)")
    return body["id"], job["id"]


MIXES = {
    "shoppers": [],                             # everything a shopper does
    "api": ["--exclude-tags", "bodies"],        # no bodies made: the API's own routes, and new
}                                               # try-ons so that the workers simulate


def run(url: str, users: int, seconds: float, garment: str = "pencil-skirt",
        mix: str = "shoppers") -> dict:
    """Run ``users`` shoppers for ``seconds`` against ``url``; the summary (docstring of
    :mod:`catwalk.loadtest.locustfile`). ``mix``: a key of :data:`MIXES`."""
    if mix not in MIXES:
        raise InputError(f"mix {mix!r}: one of {', '.join(MIXES)}", "mix")


    try:
        httpx.get(f"{url.rstrip('/')}/readyz", timeout=5).raise_for_status()
    except Exception as exc:
        raise InputError(f"--url {url}: the service does not answer as ready ({exc})") from None
    body, done = prepare(url, garment)
    with tempfile.TemporaryDirectory(prefix="catwalk-loadtest-") as tmp:
        out = Path(tmp) / "summary.json"
        cmd, env = locust_command(url, users, seconds, mix, garment, body, done, out)
        res = subprocess.run(cmd, env=env, capture_output=True, text=True,
                             timeout=seconds + 900)
        return summary(out, res.returncode, res.stderr or res.stdout, mix, users)


def locust_command(url: str, users: int, seconds: float, mix: str, garment: str, body: str,
                   done: str, out: Path) -> tuple[list[str], dict]:
    """Locust headless as ``catwalk loadtest`` runs it (the command and its environment): the
    summary is written to ``out``."""
    env = dict(os.environ, CATWALK_LOADTEST_OUT=str(out), CATWALK_LOADTEST_GARMENT=garment,
               CATWALK_LOADTEST_BODY=body, CATWALK_LOADTEST_DONE=done)
    cmd = [sys.executable, "-m", "locust", "-f", str(LOCUSTFILE), "--headless",
           "--host", url.rstrip("/"), "-u", str(users), "-r", str(max(1, users // 2)),
           "-t", f"{max(1, round(seconds))}s", "--only-summary", "--stop-timeout", "10",
           "--exit-code-on-error", "0", "--loglevel", "WARNING", *MIXES[mix]]
    return cmd, env


def summary(out: Path, returncode: int, output: str, mix: str, users: int) -> dict:
    """The summary Locust wrote to ``out`` (:class:`SetupError` if it wrote none)."""
    if not out.is_file():
        raise SetupError(f"locust ended ({returncode}) without a summary: {output[-2000:]}")
    return {"mix": mix, "users": users, **json.loads(out.read_text())}


def format_table(r: dict) -> str:
    lines = [f"catwalk loadtest ({r['mix']} mix, {r['users']} users): {r['requests']} requests "
             f"in {r['seconds']:.0f} s "
             f"({r['rps']:.0f}/s), {r['failures']} failures; try-ons asked "
             f"{r['tryons_asked']}, done {r['tryons_done']} ({r['tryons_per_minute']:.1f}/min)",
             f"  {'route':44s} {'requests':>9s} {'rps':>7s} {'p50':>6s} {'p95':>6s} {'p99':>6s}"
             f" {'fail':>5s}"]
    for name, s in r["per_route"].items():
        lines.append(f"  {name:44s} {s['requests']:9d} {s['rps']:7.1f} {s['p50_ms']:6.0f} "
                     f"{s['p95_ms']:6.0f} {s['p99_ms']:6.0f} {s['failures']:5d}")
    lines += [f"  error: {e}" for e in r.get("errors", [])]
    return "\n".join(lines)


def main(args) -> int:
    if args.users < 1:
        raise InputError(f"--users must be at least 1, got {args.users}")
    if not 1 <= args.seconds <= 3600:
        raise InputError(f"--seconds must be within 1–3600, got {args.seconds}")
    r = run(args.url, args.users, args.seconds, args.garment, args.mix)
    print(json.dumps(r, indent=2) if args.json else format_table(r))
    return 0
