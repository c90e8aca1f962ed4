"""The database: one engine per process, sessions, and migrations to the newest schema.

SQLite (the embedded default, a file in the storage folder) or PostgreSQL (by URL). An engine
is made per process id, so forked worker processes never share a parent's connections, and
with ``hide_parameters``: an error's message never carries a row's values (a body's
measurements) into a log. SQLite
runs in WAL mode with a busy timeout, so the API, its threads and the worker processes can
write to one file. :func:`migrate` brings the schema up to date with Alembic (run by
``catwalk serve``, ``catwalk worker`` and the API at start; concurrent runs wait for one
another on PostgreSQL through an advisory lock).
"""

from __future__ import annotations

import contextlib
import os
import threading
from pathlib import Path

from sqlalchemy import create_engine, event, text
from sqlalchemy.engine import Engine
from sqlalchemy.orm import Session, sessionmaker

from catwalk.config import Config

_lock = threading.Lock()
_engines: dict[tuple[int, str], tuple[Engine, sessionmaker]] = {}
MIGRATIONS = Path(__file__).resolve().parent / "migrations"


def _after_fork_in_child() -> None:
    global _lock
    _lock = threading.Lock()   # a fork while another thread held it must not deadlock


os.register_at_fork(after_in_child=_after_fork_in_child)


def _sqlite_pragmas(dbapi_conn, _record) -> None:
    cur = dbapi_conn.cursor()
    cur.execute("PRAGMA journal_mode=WAL")
    cur.execute("PRAGMA busy_timeout=30000")
    cur.execute("PRAGMA foreign_keys=ON")
    cur.execute("PRAGMA synchronous=NORMAL")
    cur.execute("PRAGMA secure_delete=ON")   # a deleted body's measurements are overwritten
    cur.close()


def _private_file(path: Path) -> None:
    """The embedded database's file made before SQLite opens it, readable by the service's
    user only (SQLite gives its -wal and -shm files the database file's mode)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    os.close(os.open(path, os.O_CREAT | os.O_RDWR, 0o600))
    os.chmod(path, 0o600)


def forget(config: Config) -> None:
    """After a deletion: SQLite's write-ahead log still holds the pages a deleted row was
    written in (``secure_delete`` zeroes the database's own copy); a TRUNCATE checkpoint
    copies the log into the database and empties it. PostgreSQL: docs/operations.md ("What
    deletion guarantees")."""
    if not config.db_url.startswith("sqlite"):
        return
    eng, _ = engine_for(config.db_url)
    with eng.connect() as conn:
        conn.exec_driver_sql("PRAGMA wal_checkpoint(TRUNCATE)")


def engine_for(url: str) -> tuple[Engine, sessionmaker]:
    """This process's engine and session factory for ``url``."""
    key = (os.getpid(), url)
    with _lock:
        got = _engines.get(key)
        if got is None:
            if url.startswith("sqlite"):
                path = url.split("///", 1)[-1]
                if path and path != ":memory:":
                    _private_file(Path(path))
                eng = create_engine(url, connect_args={"check_same_thread": False,
                                                       "timeout": 30}, hide_parameters=True)
                event.listen(eng, "connect", _sqlite_pragmas)
            else:
                eng = create_engine(url, pool_pre_ping=True, pool_size=10, max_overflow=20,
                                    hide_parameters=True)
            got = (eng, sessionmaker(eng, expire_on_commit=False))
            _engines[key] = got
        return got


@contextlib.contextmanager
def session(config: Config):
    """A session that commits on success and rolls back on error."""
    _, factory = engine_for(config.db_url)
    s: Session = factory()
    try:
        yield s
        s.commit()
    except BaseException:
        s.rollback()
        raise
    finally:
        s.close()


def ping(config: Config) -> None:
    """Raise if the database cannot be reached."""
    eng, _ = engine_for(config.db_url)
    with eng.connect() as c:
        c.execute(text("SELECT 1"))


def migrate(config: Config) -> None:
    """Bring the schema to the newest revision (idempotent)."""
    from alembic import command  # deferred: alembic loads in ≈ 0.3 s; only migrations need it
    from alembic.config import (
        Config as AlembicConfig,  # deferred: alembic loads in ≈ 0.3 s; only migrations need it
    )

    eng, _ = engine_for(config.db_url)
    cfg = AlembicConfig()
    cfg.set_main_option("script_location", str(MIGRATIONS))
    cfg.set_main_option("path_separator", "os")
    with eng.begin() as conn:
        if conn.dialect.name == "postgresql":   # one migrator at a time
            conn.execute(text("SELECT pg_advisory_xact_lock(7426001)"))
        cfg.attributes["connection"] = conn
        command.upgrade(cfg, "head")
