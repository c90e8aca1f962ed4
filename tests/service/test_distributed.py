"""At scale: real Redis as the broker, real PostgreSQL as the database, two real ``catwalk
worker`` processes sharing one storage folder. Both take jobs; a worker killed (SIGKILL)
mid-job leaves its job to the other, which finishes it and stores it once; the bytes are
the embedded deployment's and the library's."""

from __future__ import annotations

import os
import signal
import time

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import func, select

from .helpers import (
    MEASURES,
    SKIRT,
    library_glb,
    make_config,
    service_env,
    start_worker,
    wait_job,
)


@pytest.fixture
def scaled(tmp_path, catalogue_dir, pg_url, redis_url, queue_name):
    env = service_env(tmp_path / "storage", catalogue_dir, database_url=pg_url,
                      broker_url=redis_url, queue=queue_name)
    return env, make_config(env)


def _row(config, job_id):
    from catwalk.service.jobs import lifecycle as jobs

    return jobs.get(config, job_id)


def test_two_workers_share_the_queue_and_survive_a_kill(scaled, procs, catalogue_dir):
    from catwalk.service.api.app import create_app
    from catwalk.service.store import db
    from catwalk.service.store.models import ResultRow, TryOnRow

    env, config = scaled
    workers = [start_worker(procs, env, f"worker-{i}") for i in range(2)]
    with TestClient(create_app(config)) as client:
        body = client.post("/api/bodies", json=MEASURES).json()
        # four different try-ons at once: both workers take some
        asked = [client.post("/api/tryons", json={"body_id": body["id"], **SKIRT,
                                                  "seconds": s}).json()
                 for s in (0.5, 0.6, 0.7, 0.8)]
        assert all(a["status"] == "queued" for a in asked)
        done = [wait_job(client, a["id"]) for a in asked]
        assert [d["status"] for d in done] == ["done"] * 4, done
        hosts = {_row(config, a["id"]).worker.rsplit(":", 1)[1] for a in asked}
        parents = {os.getpgid(int(pid)) for pid in hosts}
        assert parents == {w.pid for w in workers}, (hosts, parents)

        # a job whose worker is killed mid-walk finishes on the other, stored once
        job = client.post("/api/tryons", json={"body_id": body["id"], **SKIRT,
                                               "seconds": 3.0}).json()
        wait_job(client, job["id"], until=("running",))
        t0 = time.monotonic()
        while client.get(f"/api/tryons/{job['id']}").json()["progress"] < 0.2:
            assert time.monotonic() - t0 < 120
            time.sleep(0.05)
        first = _row(config, job["id"])
        victim = next(w for w in workers if w.pid == os.getpgid(int(first.worker.split(":")[1])))
        os.killpg(victim.pid, signal.SIGKILL)
        survivor = next(w for w in workers if w is not victim)
        end = wait_job(client, job["id"], timeout=300)
        assert end["status"] == "done", end
        row = _row(config, job["id"])
        assert row.attempts == 2
        assert os.getpgid(int(row.worker.split(":")[1])) == survivor.pid
        with db.session(config) as s:
            assert s.scalar(select(func.count()).select_from(ResultRow)
                            .where(ResultRow.key == row.key)) == 1
            assert s.scalar(select(func.count()).select_from(TryOnRow)
                            .where(TryOnRow.key == row.key)) == 1
        results = sorted(p.name for p in (config.storage_dir / "results").iterdir())
        assert len(results) == 5 and all(not n.startswith(".") for n in results)

        # the same bytes as the library (and so as the embedded deployment)
        plain = client.get(f"/api/tryons/{asked[0]['id']}/result.glb",
                           params={"compress": 0}).content
        assert plain == library_glb(client, body["id"], catalogue_dir, seconds=0.5,
                                    preset="fast")


def test_jobs_redis_lost_are_sent_again(scaled, procs, redis_url, queue_name):
    """Redis restarted (it keeps nothing on disk here): the queued jobs' messages are gone;
    the database still has them queued, so they are sent again and finish."""
    import redis

    from catwalk.service.api.app import create_app

    env, config = scaled
    with TestClient(create_app(config)) as client:
        body = client.post("/api/bodies", json=MEASURES).json()
        # (other seconds than the test above: the session's database has those results)
        asked = [client.post("/api/tryons", json={"body_id": body["id"], **SKIRT,
                                                  "seconds": s}).json() for s in (0.55, 0.65)]
        assert [a["status"] for a in asked] == ["queued", "queued"]
        r = redis.Redis.from_url(redis_url)
        lost = [k for k in r.scan_iter(f"{queue_name}*") if r.type(k) == b"list"]
        assert lost and sum(r.llen(k) for k in lost) == 2
        r.delete(*lost)                                   # what a restart does
        start_worker(procs, env)
        for a in asked:
            end = wait_job(client, a["id"], timeout=180)
            assert end["status"] == "done", end
