"""A service of its own for the chaos run: Redis and PostgreSQL servers started in a temporary
folder on free ports (never the machine's own services), ``catwalk serve --workers 0`` and
``catwalk worker`` processes on them; each part can be killed or restarted while the load
runs."""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import httpx

from catwalk.errors import SetupError

PG_BIN_GLOB = "/usr/lib/postgresql/*/bin"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _answers(port: int) -> bool:
    with socket.socket() as s:
        s.settimeout(0.5)
        return s.connect_ex(("127.0.0.1", port)) == 0


def _wait(what: str, check, seconds: float) -> None:
    t0 = time.monotonic()
    while not check():
        if time.monotonic() - t0 > seconds:
            raise SetupError(f"chaos: {what} did not come up within {seconds:g} s")
        time.sleep(0.2)


def _run(what: str, argv: list[str]) -> None:
    """Run a set-up command; :class:`SetupError` with its output when it fails."""
    res = subprocess.run(argv, capture_output=True, text=True, timeout=120)
    if res.returncode != 0:
        raise SetupError(f"chaos: {what} failed ({res.returncode}): "
                         f"{(res.stderr or res.stdout)[-1000:]}")


def _pg_bin(name: str) -> str:
    found = sorted(Path("/").glob(PG_BIN_GLOB.lstrip("/")))
    for folder in reversed(found):
        if (folder / name).is_file():
            return str(folder / name)
    path = shutil.which(name)
    if path is None:
        raise SetupError(f"chaos: PostgreSQL's {name} is not installed (Debian's postgresql "
                         "package: tools/services/ensure.sh installs it)")
    return path


class Stack:
    """The processes of one chaos run, under ``root`` (their logs in ``root/logs``)."""

    def __init__(self, root: Path, workers: int = 2):
        self.root = root
        self.logs = root / "logs"
        self.logs.mkdir(parents=True, exist_ok=True)
        self.redis_port, self.pg_port, self.api_port = free_port(), free_port(), free_port()
        self.n_workers = workers
        self.workers: list[subprocess.Popen] = []
        self.worker_logs: list[Path] = []
        self.procs: list[subprocess.Popen] = []
        self.redis: subprocess.Popen | None = None
        self.api: subprocess.Popen | None = None
        self.env = dict(os.environ,
                        CATWALK_DATABASE_URL=f"postgresql+psycopg://postgres@127.0.0.1:"
                                             f"{self.pg_port}/catwalk",
                        CATWALK_BROKER_URL=f"redis://127.0.0.1:{self.redis_port}/0",
                        CATWALK_STORAGE_DIR=str(root / "storage"), CATWALK_QUEUE="chaos",
                        CATWALK_LOG_LEVEL="INFO")
        self.url = f"http://127.0.0.1:{self.api_port}"

    # ---- the servers
    def start_redis(self) -> None:
        log = open(self.logs / "redis.log", "ab")
        self.redis = subprocess.Popen(
            ["redis-server", "--port", str(self.redis_port), "--bind", "127.0.0.1",
             "--save", "", "--appendonly", "no", "--dir", str(self.root)],
            stdout=log, stderr=subprocess.STDOUT)
        _wait("Redis", lambda: _answers(self.redis_port), 20)

    def stop_redis(self) -> None:
        if self.redis is not None:
            self.redis.terminate()
            self.redis.wait(timeout=20)

    def _as_postgres(self, argv: list[str]) -> list[str]:
        """``argv`` as the ``postgres`` user when run as root (PostgreSQL refuses root)."""
        if os.geteuid() == 0:
            return ["runuser", "-u", "postgres", "--", *argv]
        return argv

    def init_postgres(self) -> None:
        data = self.root / "pg"
        data.mkdir()
        if os.geteuid() == 0:
            for folder in (self.root, data, self.logs):
                shutil.chown(folder, "postgres")
        _run("initdb", self._as_postgres([_pg_bin("initdb"), "-D", str(data), "-U", "postgres",
                                          "--auth=trust", "-E", "UTF8"]))

    def start_postgres(self) -> None:
        data = self.root / "pg"
        _run("PostgreSQL's start", self._as_postgres(
            [_pg_bin("pg_ctl"), "-D", str(data), "-l", str(self.logs / "postgres.log"), "-w",
             "-o", f"-p {self.pg_port} -k {data} -c listen_addresses=127.0.0.1", "start"]))
        _wait("PostgreSQL", lambda: _answers(self.pg_port), 30)

    def stop_postgres(self, mode: str = "fast") -> None:
        subprocess.run(self._as_postgres([_pg_bin("pg_ctl"), "-D", str(self.root / "pg"), "-w",
                                          "-m", mode, "stop"]),
                       capture_output=True, timeout=120)

    def create_database(self) -> None:
        _run("CREATE DATABASE", [_pg_bin("psql"), "-q", "-h", "127.0.0.1", "-p",
                                 str(self.pg_port), "-U", "postgres", "-c",
                                 "CREATE DATABASE catwalk"])

    # ---- catwalk
    def _catwalk(self, args: list[str], log: Path) -> subprocess.Popen:
        fh = open(log, "ab")
        return subprocess.Popen([sys.executable, "-m", "catwalk.cli.main", *args], env=self.env,
                                stdout=fh, stderr=subprocess.STDOUT, start_new_session=True)

    def start_api(self) -> None:
        self.api = self._catwalk(["serve", "--port", str(self.api_port), "--workers", "0"],
                                 self.logs / "serve.log")

        def ready() -> bool:
            with contextlib.suppress(httpx.HTTPError):
                return httpx.get(f"{self.url}/readyz", timeout=2).status_code == 200
            return False

        _wait("the API", ready, 300)

    def start_worker(self) -> None:
        log = self.logs / f"worker-{len(self.worker_logs)}.log"
        self.worker_logs.append(log)
        self.workers.append(self._catwalk(["worker", "--concurrency", "1"], log))

    def wait_workers_ready(self, seconds: float = 300) -> None:
        _wait("the workers", lambda: all('"event": "ready"' in p.read_text(errors="replace")
                                         for p in self.worker_logs[-self.n_workers:]), seconds)

    def kill_worker(self) -> int:
        """SIGKILL the oldest live worker (its whole process group: the pool's children too)
        and start another in its place; the killed one's pid."""
        victim = next(p for p in self.workers if p.poll() is None)
        os.killpg(victim.pid, signal.SIGKILL)
        victim.wait(timeout=20)
        self.start_worker()
        return victim.pid

    def start(self) -> None:
        self.start_redis()
        self.init_postgres()
        self.start_postgres()
        self.create_database()
        self.start_api()
        for _ in range(self.n_workers):
            self.start_worker()
        self.wait_workers_ready()

    def stop(self) -> None:
        for p in [*self.workers, self.api]:
            if p is not None and p.poll() is None:
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(p.pid, signal.SIGTERM)
        for p in [*self.workers, self.api]:
            if p is not None:
                with contextlib.suppress(subprocess.TimeoutExpired):
                    p.wait(timeout=30)
                if p.poll() is None:
                    with contextlib.suppress(ProcessLookupError):
                        os.killpg(p.pid, signal.SIGKILL)
        self.stop_redis()
        self.stop_postgres("immediate")
