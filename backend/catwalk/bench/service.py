"""``catwalk bench service``: try-ons through the HTTP API against the same work in one process.

It starts ``catwalk serve`` on the embedded default in a temporary storage folder (SQLite, the
filesystem broker, ``--workers`` processes), makes a body, and asks for ``--tryons`` fast
try-ons at once (the catalogue's pencil skirt, each one frame longer than the last, so none is
answered from the cache). Reported:

- ``per_minute``: try-ons finished per minute, from the first request to the last result
  downloaded; ``p50_s`` / ``p95_s``: each try-on's seconds from its POST to its result
  downloaded;
- ``library_s``: the same try-ons through ``catwalk.tryon`` one after another in this process,
  with what a worker does after the simulation (the .glb, its meshopt copy, the preview);
- ``overhead_ratio``: the service's wall time × its workers / ``library_s`` (1.0: the service
  adds nothing; the target is ≤ 1.1);
- ``cached_ms``: the median latency of asking again for a finished try-on (answered from the
  cache, no worker involved; the target is ≤ 50 ms);
- ``cancel_ms``: from ``DELETE`` of a running try-on (a third of the way through a balanced
  4 s walk) until its status says cancelled.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from catwalk.bench import check_walk_seconds, cpu_model
from catwalk.config import _cores, get_config
from catwalk.errors import InputError, SimulationError
from catwalk.exchange.compress import compress_bytes
from catwalk.service.client import Client
from catwalk.service.jobs.tryon import preview_png
from catwalk.service.jobs.worker import warm_up
from catwalk.simulate.tryon import tryon

GARMENT = "pencil-skirt"
PRESET = "fast"
BODY = {"sex": "female", "height": 1.68, "bust": 0.90, "waist": 0.72, "hips": 0.98}


def _percentile(xs: list[float], q: float) -> float:
    xs = sorted(xs)
    if not xs:
        return float("nan")
    k = (len(xs) - 1) * q
    lo, hi = int(k), min(int(k) + 1, len(xs) - 1)
    return xs[lo] + (xs[hi] - xs[lo]) * (k - lo)


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def _start(port: int, workers: int, storage: Path):
    env = {k: v for k, v in os.environ.items() if not k.startswith("CATWALK_")
           or k in ("CATWALK_DATA_DIR", "CATWALK_DATA", "CATWALK_CATALOGUE_DIR",
                    "CATWALK_NODE_TOOLS_DIR", "CATWALK_BODIES_DIR", "CATWALK_FRONTEND_DIR")}
    env["CATWALK_STORAGE_DIR"] = str(storage)
    log = open(storage.parent / "serve.log", "wb")
    proc = subprocess.Popen([sys.executable, "-m", "catwalk.cli.main", "serve", "--port", str(port),
                             "--workers", str(workers)], env=env, stdout=log,
                            stderr=subprocess.STDOUT, start_new_session=True)
    return proc, log


def _stop(proc) -> None:
    proc.send_signal(signal.SIGINT)
    try:
        proc.wait(40)
    except subprocess.TimeoutExpired:
        pass
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()


def _through_api(url: str, body_id: str, requests: list[dict]) -> tuple[list[float], float]:
    """Ask for every try-on at once, each from its own thread; (latencies, wall seconds)."""
    lat: list[float | None] = [None] * len(requests)
    errors: list[str] = []

    def one(i: int, req: dict) -> None:
        try:
            _one(i, req)
        except Exception as exc:   # counted, not lost with the thread
            errors.append(f"{type(exc).__name__}: {exc}")

    def _one(i: int, req: dict) -> None:
        with Client(url, timeout=600) as api:
            t0 = time.perf_counter()
            job = api.create_tryon(body_id=body_id, **req)
            job = api.follow(job["id"], timeout=1800)   # the server-sent events, as a page
            if job["status"] != "done":
                errors.append(f"{job['status']}: {job.get('error')}")
                return
            api.result(job["id"])
            lat[i] = time.perf_counter() - t0

    t0 = time.perf_counter()
    threads = [threading.Thread(target=one, args=(i, r)) for i, r in enumerate(requests)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    wall = time.perf_counter() - t0
    if errors or any(x is None for x in lat):
        raise SimulationError(f"{len(errors) or sum(x is None for x in lat)} of "
                              f"{len(requests)} try-ons through the API failed: {errors[:3]}")
    return lat, wall


def _cancel_latency(api, body_id: str) -> dict:
    """Cancel a balanced 4 s try-on a third of the way through: the milliseconds from the
    DELETE until its status says cancelled (polled every 10 ms), and the stage it was in."""
    job = api.create_tryon(body_id=body_id, garment_id=GARMENT, preset="balanced", seconds=4.0)
    while (state := api.tryon(job["id"]))["progress"] < 0.33:
        if state["status"] in ("done", "failed", "cancelled"):
            raise SimulationError(f"the try-on to cancel ended first: {state['status']}")
        time.sleep(0.02)
    stage, progress = state["stage"], state["progress"]
    t0 = time.perf_counter()
    api.cancel(job["id"])
    while (state := api.tryon(job["id"]))["status"] != "cancelled":
        if state["status"] in ("done", "failed"):
            raise SimulationError(f"the cancelled try-on ended {state['status']}")
        time.sleep(0.01)
    return {"ms": round(1e3 * (time.perf_counter() - t0), 1), "stage": stage,
            "at_progress": round(progress, 3)}


def _through_library(body: bytes, garment: Path, requests: list[dict]) -> float:
    """The same try-ons one after another in this process, with a worker's after-work."""
    warm_up()   # what a worker does before its first job: every kernel loaded
    t0 = time.perf_counter()
    for req in requests:
        res = tryon(body, garment, preset=req["preset"], seconds=req["seconds"],
                    garment_id=GARMENT)
        compress_bytes(res.glb())
        preview_png(res)
    return time.perf_counter() - t0


def run(tryons: int = 4, workers: int = 1, seconds: float = 2.0, log=None) -> dict:
    say = log or (lambda msg: None)
    requests = [{"garment_id": GARMENT, "preset": PRESET, "seconds": round(seconds + i / 30, 4)}
                for i in range(tryons)]
    tmp = Path(tempfile.mkdtemp(prefix="catwalk-bench-service-"))
    try:
        return _run(tmp, requests, tryons, workers, seconds, say)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _run(tmp: Path, requests, tryons, workers, seconds, say) -> dict:
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    proc, logf = _start(port, workers, tmp / "storage")
    try:
        with Client(url, timeout=300) as api:
            api.wait_ready(timeout=300)
            body = api.create_body(**BODY)
            say(f"service up at {url} with {workers} worker process(es); body made")
            # the workers load their kernels before taking jobs: wait for one to be done
            warm = api.create_tryon(body_id=body["id"], garment_id=GARMENT, preset=PRESET,
                                    seconds=0.5)
            api.wait(warm["id"], timeout=1800)
            body_glb = api.http.get(f"/api/bodies/{body['id']}/body.glb").content
            say(f"{tryons} try-ons through the API …")
            lat, wall = _through_api(url, body["id"], requests)
            cancel = _cancel_latency(api, body["id"])
            cached = []
            for req in requests * max(1, 20 // tryons):
                t0 = time.perf_counter()
                job = api.create_tryon(body_id=body["id"], **req)
                cached.append(1e3 * (time.perf_counter() - t0))
                if not job.get("cached"):
                    raise SimulationError("a finished try-on was not answered from the cache")
    finally:
        _stop(proc)
        logf.close()
    say("the same try-ons through the library …")
    library_s = _through_library(body_glb, get_config().catalogue_dir / f"{GARMENT}.json",
                                 requests)
    return {
        "tryons": tryons, "workers": workers, "cores": _cores(),
        "garment": GARMENT, "preset": PRESET, "seconds": seconds,
        "per_minute": round(60.0 * tryons / wall, 2),
        "p50_s": round(_percentile(lat, 0.5), 3), "p95_s": round(_percentile(lat, 0.95), 3),
        "wall_s": round(wall, 3),
        "library_s": round(library_s, 3),
        "overhead_ratio": round(wall * workers / library_s, 3),
        "cached_ms": round(statistics.median(cached), 2),
        "cached_p95_ms": round(_percentile(cached, 0.95), 2),
        "cancel_ms": cancel["ms"], "cancel_stage": cancel["stage"],
        "machine": cpu_model(),
    }


def format_table(r: dict) -> str:
    return "\n".join([
        f"catwalk bench service: {r['tryons']} fast try-ons ({r['garment']}, "
        f"{r['seconds']} s walks) at once, {r['workers']} worker process(es), "
        f"{r['cores']} cores ({r['machine']})",
        f"  through the API   {r['per_minute']:.1f} try-ons/min, {r['wall_s']:.1f} s in all; "
        f"POST → result p50 {r['p50_s']:.2f} s, p95 {r['p95_s']:.2f} s",
        f"  through the library, one process: {r['library_s']:.1f} s",
        f"  overhead ratio    {r['overhead_ratio']:.3f} (wall × workers / library; "
        "target ≤ 1.1)",
        f"  cached answer     {r['cached_ms']:.1f} ms median, {r['cached_p95_ms']:.1f} ms p95 "
        "(target ≤ 50 ms)",
        f"  cancel            {r['cancel_ms']:.0f} ms from DELETE to cancelled (running, "
        f"{r['cancel_stage']})"])


def main(args) -> int:
    if args.tryons < 1:
        raise InputError(f"--tryons must be at least 1, got {args.tryons}")
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be at least 1, got {args.workers}")
    check_walk_seconds(args.seconds)
    log = None if args.json else (lambda m: print(f"bench service: {m}", file=sys.stderr))
    r = run(args.tryons, args.workers or 1, args.seconds, log)
    print(json.dumps(r, indent=2) if args.json else format_table(r))
    return 0
