"""Fixtures for the service's tests: real servers, real processes.

Redis and PostgreSQL are the ones at ``CATWALK_TEST_REDIS_URL`` / ``CATWALK_TEST_DATABASE_URL``
(default: the local servers, which ``make test`` starts when they are not running); a test that
needs one and cannot reach it fails with the reason, it is never skipped. Each test session
gets its own PostgreSQL database and its own queue name, removed at the end. Workers and
``catwalk serve`` run as subprocesses (``python -m catwalk.cli.main``).
"""

from __future__ import annotations

import uuid
from pathlib import Path

import pytest

from .helpers import DB_URL, REDIS_URL, Proc, one_garment_catalogue


@pytest.fixture(scope="session")
def catalogue_dir(tmp_path_factory) -> Path:
    """A catalogue of one garment (the pencil skirt and its textures): fewer thumbnails."""
    return one_garment_catalogue(tmp_path_factory.mktemp("catalogue"))


@pytest.fixture
def procs(tmp_path):
    """Start ``catwalk`` subprocesses; every one is stopped at the end of the test."""
    started: list[Proc] = []

    def start(args, env, name=None) -> Proc:
        p = Proc(args, env, tmp_path / f"{name or args[0]}-{len(started)}.log")
        started.append(p)
        return p

    yield start
    for p in started:
        p.stop()


@pytest.fixture(scope="session")
def redis_url() -> str:
    import redis

    try:
        redis.Redis.from_url(REDIS_URL, socket_connect_timeout=3).ping()
    except Exception as exc:
        pytest.fail(f"Redis at {REDIS_URL} cannot be reached ({exc}); `make test` starts it, "
                    "or set CATWALK_TEST_REDIS_URL", pytrace=False)
    return REDIS_URL


@pytest.fixture(scope="session")
def pg_url() -> str:
    """A fresh PostgreSQL database for this session (dropped at the end)."""
    import psycopg

    plain = DB_URL.replace("+psycopg", "")
    name = f"catwalk_test_{uuid.uuid4().hex[:12]}"
    try:
        with psycopg.connect(plain, autocommit=True, connect_timeout=5) as c:
            c.execute(f'CREATE DATABASE "{name}"')
    except Exception as exc:
        pytest.fail(f"PostgreSQL at {DB_URL} cannot be reached ({exc}); `make test` starts "
                    "it, or set CATWALK_TEST_DATABASE_URL", pytrace=False)
    base, _, _ = DB_URL.rpartition("/")
    yield f"{base}/{name}"
    from catwalk.service.store import db

    for (_pid, url), (eng, _) in list(db._engines.items()):
        if name in url:
            eng.dispose()
    with psycopg.connect(plain, autocommit=True) as c:
        c.execute(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)')


@pytest.fixture(scope="session")
def queue_name(redis_url) -> str:
    name = f"catwalk-test-{uuid.uuid4().hex[:10]}"
    yield name
    import redis

    r = redis.Redis.from_url(redis_url)
    for key in r.scan_iter(f"*{name}*"):
        r.delete(key)
