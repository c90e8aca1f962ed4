"""``catwalk demo`` (what ``make demo`` runs): the service on the embedded default, and the
sample try-on through its HTTP API as a client would do it.

It starts ``catwalk serve`` (unless ``--url`` names a running service), makes a body from
measurements, asks for the try-on, shows its progress from the server-sent events, writes
``demo/tryon.glb`` (the plain file), ``demo/tryon.png`` (the preview) and ``demo/metrics.json``,
prints the URL and keeps serving until Ctrl-C (``--exit`` or ``DEMO_EXIT=1``: stop there).
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from catwalk.console import ProgressBar
from catwalk.errors import InputError, SetupError, SimulationError
from catwalk.fileio import atomic_path
from catwalk.service.client import ApiFailure, Client

BODY = {"sex": "female", "height": 1.68, "bust": 0.90, "waist": 0.72, "hips": 0.98}


def _start_service(port: int) -> subprocess.Popen:
    cmd = [sys.executable, "-m", "catwalk.cli.main", "serve", "--port", str(port)]
    return subprocess.Popen(cmd, start_new_session=True)


def _stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)   # `catwalk serve` stops its worker, then itself
        try:
            proc.wait(40)
        except subprocess.TimeoutExpired:
            pass
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)   # whatever is left of its process group
    proc.wait()


def main(args) -> int:
    stay = not (args.exit or os.environ.get("DEMO_EXIT", "") not in ("", "0"))
    out = Path(args.out_dir)
    url = args.url or f"http://127.0.0.1:{args.port}"
    proc = None if args.url else _start_service(args.port)
    try:
        with Client(url, timeout=120) as api:
            print(f"demo: waiting for the service at {url}", file=sys.stderr)
            try:
                api.wait_ready(timeout=180)
            except TimeoutError as exc:
                raise SetupError(f"the service did not become ready: {exc}") from None
            try:
                body = api.create_body(**BODY)
                print(f"demo: body {body['id'][:8]}… made from {json.dumps(BODY)}",
                      file=sys.stderr)
                job = api.create_tryon(body_id=body["id"], garment_id=args.garment,
                                       size=args.size, seconds=args.seconds,
                                       preset=args.preset)
            except ApiFailure as exc:
                raise InputError(f"the service refused the demo: {exc}") from None
            t0 = time.perf_counter()
            bar = ProgressBar()
            if job["status"] != "done":
                job = api.follow(job["id"], lambda ev, j: bar(j["stage"], j["progress"], 1.0))
                bar.done()
            if job["status"] != "done":
                raise SimulationError(f"the try-on {job['status']}: {job.get('error')}")
            job = api.tryon(job["id"])
            files = {"tryon.glb": api.result(job["id"], compress=False),
                     "tryon.png": api.preview(job["id"]),
                     "metrics.json": (json.dumps(job.get("metrics"), indent=2) + "\n").encode()}
            for name, data in files.items():
                with atomic_path(out / name) as tmp:
                    tmp.write_bytes(data)
            cached = " (from the cache)" if job.get("cached") else ""
            print(f"demo: try-on done in {time.perf_counter() - t0:.1f} s{cached}: wrote "
                  f"{out}/tryon.glb, {out}/tryon.png, {out}/metrics.json", file=sys.stderr)
            print(f"demo: open {url}/tryon/{job['id']} to watch it walk (the catalogue: "
                  f"{url}/, the API: {url}/docs)")
        if proc is not None and stay:
            print("demo: serving until Ctrl-C", file=sys.stderr)
            try:
                proc.wait()
            except KeyboardInterrupt:
                pass
    finally:
        if proc is not None:
            _stop(proc)
    return 0
