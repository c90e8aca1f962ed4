"""The embedded default (SQLite and the filesystem broker in one storage folder) with real
worker processes: a try-on through the API end to end, its files and caching headers, the
cache answering without a worker, cancellation, deleting a body, and ``catwalk serve`` as a
subprocess giving the same bytes as the library."""

from __future__ import annotations

import json
import struct
import time

import pytest
from fastapi.testclient import TestClient

from .helpers import (
    MEASURES,
    SKIRT,
    free_port,
    library_glb,
    make_config,
    service_env,
    start_worker,
    storage_files,
    wait_job,
)


def glb_json(data: bytes) -> dict:
    n = struct.unpack("<I", data[12:16])[0]
    return json.loads(data[20:20 + n])


@pytest.fixture
def embedded(tmp_path, catalogue_dir):
    env = service_env(tmp_path / "storage", catalogue_dir)
    return env, make_config(env)


def test_a_tryon_end_to_end_then_cached_without_a_worker(embedded, procs, catalogue_dir):
    from catwalk.service.api.app import create_app

    env, config = embedded
    worker = start_worker(procs, env)
    with TestClient(create_app(config)) as client:
        body = client.post("/api/bodies", json=MEASURES).json()
        r = client.post("/api/tryons", json={"body_id": body["id"], **SKIRT})
        assert r.status_code == 202, r.text
        job = r.json()
        assert job["status"] == "queued" and job["status_url"] == f"/api/tryons/{job['id']}"
        # the server-sent events: progress, monotonic, then done
        seen = []
        with client.stream("GET", f"/api/tryons/{job['id']}/events") as ev:
            assert ev.headers["content-type"].startswith("text/event-stream")
            name = None
            for line in ev.iter_lines():
                if line.startswith("event:"):
                    name = line[6:].strip()
                elif line.startswith("data:"):
                    seen.append((name, json.loads(line[5:])))
                    if name in ("done", "failed", "cancelled"):
                        break
        assert seen[-1][0] == "done", seen[-1]
        fractions = [d["progress"] for _, d in seen]
        assert fractions == sorted(fractions) and fractions[-1] == 1.0
        stages = {d["stage"] for _, d in seen}
        assert stages & {"sewing", "settling", "walking", "compressing", "preview"}, stages
        done = client.get(f"/api/tryons/{job['id']}").json()
        assert done["status"] == "done" and done["metrics"]["frames"] >= 25
        assert done["metrics"]["max_penetration_mm"] is not None

        web = client.get(done["result_url"])
        assert web.status_code == 200
        assert web.headers["content-type"] == "model/gltf-binary"
        assert "immutable" in web.headers["cache-control"] and web.headers["etag"]
        assert "EXT_meshopt_compression" in glb_json(web.content)["extensionsUsed"]
        plain = client.get(done["result_url"], params={"compress": 0})
        assert "extensionsUsed" not in glb_json(plain.content) or \
            "EXT_meshopt_compression" not in glb_json(plain.content)["extensionsUsed"]
        assert len(plain.content) > 2 * len(web.content)
        again = client.get(done["result_url"], headers={"If-None-Match": web.headers["etag"]})
        assert again.status_code == 304
        part = client.get(done["result_url"], headers={"Range": "bytes=0-99"})
        assert part.status_code == 206 and part.content == web.content[:100]
        past = client.get(done["result_url"], headers={"Range": f"bytes={10**9}-"})
        assert past.status_code == 416 and past.json()["error"]["code"] == "bad_range"
        assert client.get(done["result_url"], headers={"Range": "lines=1-2"}
                          ).status_code == 400
        head = client.head(done["result_url"])
        assert head.status_code == 200 and head.content == b""
        assert int(head.headers["content-length"]) == len(web.content)
        assert "body_id" not in done   # a shared try-on id does not open the body
        # nor the person's measurements: no file a try-on id unlocks carries them
        for doc in (glb_json(plain.content), glb_json(web.content), done["metrics"]):
            keys, todo = set(), [doc]
            while todo:
                node = todo.pop()
                if isinstance(node, dict):
                    keys |= set(node)
                    todo += list(node.values())
                elif isinstance(node, list):
                    todo += node
            assert not keys & {"requested", "measured", "sex", "measurements"}, keys
            assert "female" not in json.dumps(doc)
        png = client.get(done["preview_url"])
        assert png.status_code == 200 and png.content[:4] == b"\x89PNG"
        # the worker wrote its stage timings; the metrics see the job and the worker
        metrics = client.get("/metrics").text
        assert 'catwalk_tryon_stage_seconds_count{stage="walking"} 1.0' in metrics
        assert 'catwalk_tryon_seconds_count{status="done"} 1.0' in metrics
        assert "catwalk_workers_alive 1.0" in metrics and "catwalk_worker_slots 1.0" in metrics
        assert 'catwalk_jobs{state="done"} 1.0' in metrics
                # the same inputs through the library: the same bytes
        assert plain.content == library_glb(client, body["id"], catalogue_dir,
                                            seconds=SKIRT["seconds"], preset="fast")

        # no worker any more: the same try-on is answered from the cache
        worker.stop()
        t0 = time.perf_counter()
        cached = client.post("/api/tryons", json={"body_id": body["id"], **SKIRT})
        assert time.perf_counter() - t0 < 2.0
        assert cached.status_code == 200 and cached.json()["cached"] is True
        assert cached.json()["status"] == "done" and cached.json()["id"] != job["id"]
        assert client.get(cached.json()["result_url"], params={"compress": 0}).content == \
            plain.content
        # the same measurements in another body share the cache, too
        twin = client.post("/api/bodies", json=MEASURES).json()
        shared = client.post("/api/tryons", json={"body_id": twin["id"], **SKIRT})
        assert shared.status_code == 200 and shared.json()["cached"] is True


def test_cancel_a_running_tryon_and_delete_the_body(embedded, procs, catalogue_dir):
    from catwalk.service.api.app import create_app

    env, config = embedded
    start_worker(procs, env)
    storage = config.storage_dir
    with TestClient(create_app(config)) as client:
        body = client.post("/api/bodies", json=MEASURES).json()
        long = {**SKIRT, "seconds": 10.0, "preset": "balanced"}
        job = client.post("/api/tryons", json={"body_id": body["id"], **long}).json()
        running = wait_job(client, job["id"], until=("running",))
        t_run = time.monotonic()
        while client.get(f"/api/tryons/{job['id']}").json()["progress"] < 0.05:
            assert time.monotonic() - t_run < 60
            time.sleep(0.05)
        assert running["status"] == "running"
        t0 = time.monotonic()
        c = client.delete(f"/api/tryons/{job['id']}")
        assert c.status_code == 202
        end = wait_job(client, job["id"], timeout=10)
        latency = time.monotonic() - t0
        assert end["status"] == "cancelled", end
        assert latency < 2.0, latency     # the worker stops within 0.5 s of seeing it
        assert not [p for p in storage_files(storage) if "results" in p.parts]

        # a finished try-on, then the body deleted: nothing of it is left
        short = client.post("/api/tryons", json={"body_id": body["id"], **SKIRT,
                                                 "seconds": 0.5}).json()
        assert wait_job(client, short["id"])["status"] == "done"
        files = [p for p in storage_files(storage) if "results" in p.parts]
        assert files
        r = client.delete(f"/api/bodies/{body['id']}")
        assert r.status_code == 204
        assert client.get(f"/api/bodies/{body['id']}").status_code == 404
        assert client.get(f"/api/tryons/{short['id']}").status_code == 404
        assert client.get(f"/api/tryons/{job['id']}").status_code == 404
        left = [p for p in storage_files(storage)
                if body["id"] in str(p) or "results" in p.parts]
        assert left == []


def test_catwalk_serve_subprocess_and_a_restart_with_jobs_queued(tmp_path, catalogue_dir,
                                                                 procs):
    """``catwalk serve`` (the API and its worker): jobs asked for while no worker runs are
    queued; the service stopped and started again finishes them; the bytes are the
    library's."""
    import httpx

    env = service_env(tmp_path / "storage", catalogue_dir)
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    api = procs(["serve", f"--port={port}", "--workers=0"], env, "serve-api-only")
    api.wait_for('"api_ready"', timeout=120)
    with httpx.Client(base_url=url, timeout=60) as http:
        body = http.post("/api/bodies", json=MEASURES).json()
        jobs = [http.post("/api/tryons", json={"body_id": body["id"], **SKIRT,
                                               "seconds": s}).json() for s in (0.5, 0.6)]
        assert all(j["status"] == "queued" for j in jobs)
    api.stop()
    served = procs(["serve", f"--port={port}", "--workers=1"], env, "serve")
    served.wait_for('"api_ready"', timeout=120)
    with httpx.Client(base_url=url, timeout=60) as http:
        for j in jobs:
            state = wait_job(http, j["id"])
            assert state["status"] == "done", state
        plain = http.get(f"/api/tryons/{jobs[0]['id']}/result.glb",
                         params={"compress": 0}).content
        assert plain == library_glb(http, body["id"], catalogue_dir, seconds=0.5,
                                    preset="fast")


def test_a_job_the_broker_lost_is_sent_again(embedded, procs):
    """The database is the source of truth: a queued job whose message the broker lost (here:
    its message file removed before any worker ran) is sent again and finishes."""
    from catwalk.service.api.app import create_app

    env, config = embedded
    with TestClient(create_app(config)) as client:
        body = client.post("/api/bodies", json=MEASURES).json()
        job = client.post("/api/tryons", json={"body_id": body["id"], **SKIRT,
                                               "seconds": 0.5}).json()
        messages = list((config.storage_dir / "broker" / "queue").glob("*.msg"))
        assert len(messages) == 1
        messages[0].unlink()                      # the broker lost it
        start_worker(procs, env)
        end = wait_job(client, job["id"], timeout=120)
        assert end["status"] == "done", end
        assert end["attempts"] == 1


def test_a_job_that_cannot_run_fails_with_its_reason(tmp_path, catalogue_dir, procs):
    """A garment edited between the request and the run: the job fails, saying why."""
    import shutil

    from catwalk.service.api.app import create_app

    catalogue = tmp_path / "catalogue"
    shutil.copytree(catalogue_dir, catalogue)
    env = service_env(tmp_path / "storage", catalogue)
    config = make_config(env)
    with TestClient(create_app(config)) as client:
        body = client.post("/api/bodies", json=MEASURES).json()
        job = client.post("/api/tryons", json={"body_id": body["id"], **SKIRT,
                                               "seconds": 0.5}).json()
        skirt = catalogue / "pencil-skirt.json"
        skirt.write_text(skirt.read_text() + "\n")      # a new version of the garment
        start_worker(procs, env)
        end = wait_job(client, job["id"], timeout=120)
        assert end["status"] == "failed"
        assert "has changed" in end["error"] and "Traceback" not in end["error"]
        assert end["progress"] < 1.0
        r = client.get(f"/api/tryons/{job['id']}/result.glb")
        assert r.status_code == 409
