"""Faults the service survives, each test asserting that nothing is lost or duplicated: the
database unreachable for a moment, the storage full, 200 requests at once, and an unexpected
error answered with the connection kept open. (A worker killed mid-job and Redis losing its
messages: test_distributed.py.)"""

from __future__ import annotations

import asyncio
import contextlib
import subprocess
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import pytest
from fastapi.testclient import TestClient

from .helpers import (
    MEASURES,
    SKIRT,
    free_port,
    make_config,
    service_env,
    start_worker,
    storage_files,
    wait_job,
)


class Proxy:
    """A TCP forwarder 127.0.0.1:port → target that can be cut (every connection closed, the
    port refusing) and restored: the database 'unreachable for a moment'."""

    def __init__(self, target_port: int):
        self.target = target_port
        self.port = free_port()
        self.loop = asyncio.new_event_loop()
        self.server = None
        self.conns: set = set()
        threading.Thread(target=self.loop.run_forever, daemon=True).start()
        self.restore()

    async def _pipe(self, reader, writer):
        with contextlib.suppress(Exception):
            while data := await reader.read(65536):
                writer.write(data)
                await writer.drain()
        writer.close()

    async def _handle(self, reader, writer):
        try:
            up_r, up_w = await asyncio.open_connection("127.0.0.1", self.target)
        except OSError:
            writer.close()
            return
        self.conns |= {writer, up_w}
        await asyncio.gather(self._pipe(reader, up_w), self._pipe(up_r, writer))

    def _call(self, coro):
        return asyncio.run_coroutine_threadsafe(coro, self.loop).result(10)

    def restore(self):
        async def start():
            self.server = await asyncio.start_server(self._handle, "127.0.0.1", self.port,
                                                     reuse_address=True)
        self._call(start())

    def cut(self):
        async def stop():
            self.server.close()
            for w in list(self.conns):
                w.transport.abort()
            self.conns.clear()
        self._call(stop())

    def close(self):
        with contextlib.suppress(Exception):
            self.cut()
        self.loop.call_soon_threadsafe(self.loop.stop)


def test_the_database_unreachable_for_a_moment(tmp_path, catalogue_dir, pg_url, redis_url,
                                               queue_name, procs):
    """PostgreSQL cut for 3 s while a try-on runs: routes that need it answer 503 and recover
    by themselves; the job finishes, stored once, in its first attempt (an outage shorter
    than ``job_stale_s`` — 20 s here, 30 s by default — does not make a running job look dead;
    with the suite's 4 s the checks below plus the 3 s could pass for a dead worker)."""
    from catwalk.service.api.app import create_app

    proxy = Proxy(5432)
    try:
        url = pg_url.replace("127.0.0.1:5432", f"127.0.0.1:{proxy.port}")
        assert url != pg_url
        env = service_env(tmp_path / "storage", catalogue_dir, database_url=url,
                          broker_url=redis_url, queue=f"{queue_name}-db", job_stale_s=20)
        config = make_config(env)
        start_worker(procs, env)
        with TestClient(create_app(config)) as client:
            body = client.post("/api/bodies", json=MEASURES).json()
            job = client.post("/api/tryons", json={"body_id": body["id"], **SKIRT,
                                                   "seconds": 1.9}).json()
            wait_job(client, job["id"], until=("running",))
            proxy.cut()
            away = client.get(f"/api/tryons/{job['id']}")
            assert away.status_code == 503, away.text
            assert away.json()["error"]["code"] == "unavailable"
            assert away.headers["retry-after"] == "5"
            assert client.post("/api/tryons", json={"body_id": body["id"], **SKIRT}
                               ).status_code == 503
            assert client.get("/readyz").status_code == 503
            assert client.get("/api/garments").status_code == 200    # needs no database
            time.sleep(3)
            proxy.restore()
            t0 = time.monotonic()
            while client.get(f"/api/tryons/{job['id']}").status_code != 200:
                assert time.monotonic() - t0 < 30, "the API did not recover"
                time.sleep(0.2)
            end = wait_job(client, job["id"], timeout=240)
            assert end["status"] == "done", end
            assert end["attempts"] == 1
            assert client.get("/readyz").status_code == 200
            results = [p for p in (config.storage_dir / "results").iterdir()
                       if not p.name.startswith(".")]
            assert len(results) == 1
    finally:
        proxy.close()


def test_the_storage_full(tmp_path, catalogue_dir, procs):
    """The results' folder on a 256 kB filesystem: the job fails saying so; nothing half
    written is left or served."""
    storage = tmp_path / "storage"
    results = storage / "results"
    results.mkdir(parents=True)
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(results)],
                             capture_output=True, text=True)
    if mounted.returncode != 0:
        pytest.fail(f"cannot mount a small tmpfs for the test (root is needed): "
                    f"{mounted.stderr.strip()}", pytrace=False)
    try:
        from catwalk.service.api.app import create_app

        env = service_env(storage, catalogue_dir)
        config = make_config(env)
        start_worker(procs, env)
        with TestClient(create_app(config)) as client:
            body = client.post("/api/bodies", json=MEASURES).json()
            job = client.post("/api/tryons", json={"body_id": body["id"], **SKIRT}).json()
            end = wait_job(client, job["id"], timeout=240)
            assert end["status"] == "failed", end
            assert "storage is full" in end["error"], end["error"]
            assert client.get(f"/api/tryons/{job['id']}/result.glb").status_code == 409
            assert storage_files(results) == []
    finally:
        subprocess.run(["umount", str(results)], capture_output=True)


def test_two_hundred_requests_at_once(tmp_path, catalogue_dir, procs):
    """20 bodies and 180 try-on requests (10 different try-ons, each asked for 18 times) at
    once against `catwalk serve`: every one answered 2xx, no 5xx; one job per try-on; all done."""
    import httpx

    env = service_env(tmp_path / "storage", catalogue_dir)
    port = free_port()
    serve = procs(["serve", f"--port={port}", "--workers=1"], env, "serve")
    serve.wait_for('"api_ready"', timeout=120)
    base = f"http://127.0.0.1:{port}"
    with httpx.Client(base_url=base, timeout=60) as http:
        bodies = [http.post("/api/bodies", json={**MEASURES, "height": h}).json()["id"]
                  for h in (1.66, 1.70)]

    async def storm():
        limits = httpx.Limits(max_connections=200, max_keepalive_connections=200)
        async with httpx.AsyncClient(base_url=base, timeout=600, limits=limits) as c:
            made = [c.post("/api/bodies", json={**MEASURES, "height": round(1.60 + i / 100, 2)})
                    for i in range(20)]
            asked = [c.post("/api/tryons", json={"body_id": bodies[i % 2], **SKIRT,
                                                 "seconds": 0.5 + (i % 5) / 10})
                     for i in range(180)]
            return await asyncio.gather(*made, *asked, return_exceptions=True)

    # In a thread of its own: a session-wide Playwright (tests/frontend) keeps an event loop
    # running in the main thread, where asyncio.run() refuses to start another.
    with ThreadPoolExecutor(1) as pool:
        answers = pool.submit(asyncio.run, storm()).result()
    failed = [a for a in answers if isinstance(a, Exception) or a.status_code >= 300]
    assert not failed, [str(a) if isinstance(a, Exception) else (a.status_code, a.text[:200])
                        for a in failed[:5]]
    bodies_made, tryons = answers[:20], answers[20:]
    assert all(a.status_code == 201 for a in bodies_made)
    assert len({a.json()["id"] for a in bodies_made}) == 20
    jobs = {a.json()["id"] for a in tryons}
    assert len(jobs) == 10, f"{len(jobs)} jobs for 10 different try-ons"
    with httpx.Client(base_url=base, timeout=60) as http:
        for job_id in jobs:
            assert wait_job(http, job_id, timeout=600)["status"] == "done"


def test_an_unexpected_error_is_a_json_500_and_the_connection_stays_open(tmp_path,
                                                                          catalogue_dir):
    """A real server (uvicorn, its HTTP parser) on one keep-alive connection: a route that
    raises answers 500 in the API's JSON shape, and the next request on the same connection is
    answered (Starlette's last-resort handler would raise on to the server, which drops the
    connection unannounced)."""
    import http.client
    import json

    import uvicorn

    from catwalk.service.api.app import create_app

    app = create_app(make_config(service_env(tmp_path / "storage", catalogue_dir)),
                     recovery=False)

    @app.get("/api/boom")
    async def boom():
        raise RuntimeError("a bug")

    port = free_port()
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port, log_config=None,
                                           access_log=False))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    try:
        t0 = time.monotonic()
        while not server.started:
            assert time.monotonic() - t0 < 60, "the server did not start"
            time.sleep(0.05)
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
        for _ in range(2):
            conn.request("GET", "/api/boom")
            r = conn.getresponse()
            body = json.loads(r.read())
            assert r.status == 500 and body["error"]["code"] == "internal", body
            assert "a bug" not in json.dumps(body)           # no trace reaches the client
            conn.request("GET", "/healthz")                  # the same connection
            ok = conn.getresponse()
            assert ok.status == 200 and json.loads(ok.read()) == {"status": "ok"}
        conn.close()
    finally:
        server.should_exit = True
        thread.join(timeout=10)
