"""Helpers for the service's tests: processes, settings, URLs (the fixtures: conftest.py)."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
REDIS_URL = os.environ.get("CATWALK_TEST_REDIS_URL", "redis://127.0.0.1:6379/15")
DB_URL = os.environ.get("CATWALK_TEST_DATABASE_URL",
                        "postgresql+psycopg://postgres@127.0.0.1:5432/postgres")
SKIRT = {"garment_id": "pencil-skirt", "preset": "fast", "seconds": 1.0}
MEASURES = {"sex": "female", "height": 1.68, "bust": 0.90, "waist": 0.72, "hips": 0.98}


def one_garment_catalogue(dest: Path) -> Path:
    """A catalogue of one garment in ``dest`` (the pencil skirt and its textures): fewer
    thumbnails to make than the whole catalogue's."""
    import shutil

    shutil.copy(REPO / "garments" / "pencil-skirt.json", dest)
    shutil.copytree(REPO / "garments" / "textures", dest / "textures")
    return dest


def dxf_fixtures():
    """tests/garment/dxf_fixtures.py (DXF patterns written as Gerber and CLO export them)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "dxf_fixtures", REPO / "tests" / "garment" / "dxf_fixtures.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def service_env(storage: Path, catalogue: Path, **extra) -> dict[str, str]:
    """The environment of a service process: this storage and catalogue, short recovery
    times, and ``extra`` as ``CATWALK_<KEY>``."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("CATWALK_")
           or k in ("CATWALK_DATA_DIR", "CATWALK_DATA")}
    env.update({"CATWALK_STORAGE_DIR": str(storage), "CATWALK_CATALOGUE_DIR": str(catalogue),
                "CATWALK_JOB_STALE_S": "4", "CATWALK_REQUEUE_AFTER_S": "5",
                "CATWALK_WORKERS": "1", "PYTHONUNBUFFERED": "1"})
    env.update({f"CATWALK_{k.upper()}": str(v) for k, v in extra.items()})
    return env


def make_config(env: dict[str, str]):
    """The Config a process started with ``env`` reads."""
    from catwalk.config import Config

    fields = {k[len("CATWALK_"):].lower(): v for k, v in env.items()
              if k.startswith("CATWALK_") and k not in ("CATWALK_DATA", "CATWALK_DATA_DIR")}
    return Config(**fields)


class Proc:
    """A ``catwalk`` subprocess in its own process group, its output in a log file."""

    def __init__(self, args: list[str], env: dict[str, str], log: Path):
        self.args, self.log = args, log
        self.out = open(log, "wb")
        self.p = subprocess.Popen([sys.executable, "-m", "catwalk.cli.main", *args], env=env,
                                  stdout=self.out, stderr=subprocess.STDOUT,
                                  start_new_session=True, cwd=REPO)

    @property
    def pid(self) -> int:
        return self.p.pid

    def text(self) -> str:
        return self.log.read_text(errors="replace")

    def wait_for(self, needle: str, timeout: float = 180.0) -> None:
        t0 = time.monotonic()
        while needle not in self.text():
            if self.p.poll() is not None:
                raise AssertionError(f"catwalk {' '.join(self.args)} exited "
                                     f"({self.p.returncode}):\n{self.text()[-3000:]}")
            if time.monotonic() - t0 > timeout:
                raise AssertionError(f"no {needle!r} from catwalk {' '.join(self.args)} in "
                                     f"{timeout:g} s:\n{self.text()[-3000:]}")
            time.sleep(0.2)

    def kill(self, sig=signal.SIGKILL) -> None:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.p.pid, sig)
        with contextlib.suppress(subprocess.TimeoutExpired):
            self.p.wait(30)

    def stop(self) -> None:
        if self.p.poll() is None:
            self.p.send_signal(signal.SIGTERM if self.args[0] == "worker" else signal.SIGINT)
            with contextlib.suppress(subprocess.TimeoutExpired):
                self.p.wait(30)
        self.kill()
        self.out.close()


def start_worker(procs, env, name="worker", concurrency=1) -> Proc:
    w = procs(["worker", f"--concurrency={concurrency}"], env, name)
    w.wait_for("ready.", timeout=300)   # Celery's "…@host ready." after catwalk's warm-up
    return w


def storage_files(root: Path) -> list[Path]:
    return [p for p in root.rglob("*") if p.is_file()]


def wait_job(client, job_id: str, until=("done", "failed", "cancelled"),
             timeout: float = 300.0) -> dict:
    """Poll ``GET /api/tryons/{id}`` (any httpx-like client) until its status is in
    ``until``."""
    t0 = time.monotonic()
    while True:
        job = client.get(f"/api/tryons/{job_id}").json()
        if job["status"] in until:
            return job
        assert time.monotonic() - t0 < timeout, job
        time.sleep(0.1)


def library_glb(client, body_id: str, catalogue: Path, garment_id: str = "pencil-skirt",
                **options) -> bytes:
    """The same try-on through ``catwalk.tryon`` in this process, on the service's body."""
    import catwalk

    body = client.get(f"/api/bodies/{body_id}/body.glb").content
    return catwalk.tryon(body, catalogue / f"{garment_id}.json", garment_id=garment_id,
                         **options).glb()


# ---------------------------------------------------------------------- merchants and shops

def create_merchant(env, name: str) -> str:
    """``catwalk merchant create NAME`` as an operator runs it: the key is the last line."""
    out = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "merchant", "create", name],
                         env=env, capture_output=True, text=True, timeout=120, cwd=REPO)
    assert out.returncode == 0, out.stderr
    return out.stdout.strip().splitlines()[-1]


def bearer(key: str) -> dict:
    return {"Authorization": f"Bearer {key}"}


def skirt_json(**changes) -> dict:
    g = json.loads((REPO / "garments" / "pencil-skirt.json").read_text())
    g.update(changes)
    return g


def upload_json(client, key, garment: dict, files=(), method="POST", gid=None):
    parts = [("garment", ("garment.json", json.dumps(garment).encode(), "application/json"))]
    parts += [("files", (name, data, "image/png")) for name, data in files]
    url = "/api/merchant/garments" + (f"/{gid}" if gid else "")
    return client.request(method, url, files=parts, headers=bearer(key))


def textures(garment: dict) -> list[tuple[str, bytes]]:
    """The catalogue's texture files the garment names (those that exist)."""
    names = sorted({p["texture"]["image"] for p in garment["panels"] if p.get("texture")})
    return [(n, (REPO / "garments" / n).read_bytes()) for n in names
            if (REPO / "garments" / n).is_file()]


def wait_dressing(client, key, gid, version, timeout=600.0) -> dict:
    t0 = time.monotonic()
    while True:
        item = client.get(f"/api/merchant/garments/{gid}", headers=bearer(key)).json()
        v = next(v for v in item["versions"] if v["version"] == version)
        if v["check_status"] == "done":
            return v
        assert time.monotonic() - t0 < timeout, v
        time.sleep(0.5)
