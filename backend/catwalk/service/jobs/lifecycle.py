"""A try-on job's life in the database, the source of truth.

``queued`` → (a worker claims it) ``running`` → ``done`` | ``failed`` | ``cancelled``.

Every change is one conditional UPDATE, so any number of API processes, workers and recovery
loops can act at once and exactly one wins: a worker *claims* a job only if it is queued (or
running with a heartbeat older than ``job_stale_s``: its worker died), and each claim counts
an attempt (a job's progress never goes back: a run again reports the larger of its own
fraction and the one already shown); a worker's heartbeat, result and failure only land while
the job is still its own attempt, running. A job whose worker died is run again (at most
``MAX_ATTEMPTS`` times); a queued job the broker no longer holds is sent again
(:func:`recover`).
"""

from __future__ import annotations

import contextlib
import os
import secrets
import socket
import threading
from datetime import timedelta

from sqlalchemy import and_, case, delete, func, or_, select, update

from catwalk.config import Config
from catwalk.service.store import db
from catwalk.service.store.models import ACTIVE, ResultRow, TryOnRow, WorkerRow, utcnow

MAX_ATTEMPTS = 3


def new_id() -> str:
    """An unguessable id (192 random bits, URL-safe)."""
    return secrets.token_urlsafe(24)


def view(row: TryOnRow) -> dict:
    """A job as the API shows it (``GET /api/tryons/{id}``). It does not name its body: a
    try-on's id, shared, must not open the body's measurements to whoever holds it."""
    out = {"id": row.id, "status": row.status, "progress": round(float(row.progress), 4),
           "stage": row.stage, "garment_id": row.garment_id,
           "garment_version": row.garment_version, "size": row.size, "fabric": row.fabric,
           "seconds": row.seconds, "preset": row.preset, "cached": bool(row.cached),
           "attempts": row.attempts,
           "created_at": row.created_at.isoformat() + "Z",
           "status_url": f"/api/tryons/{row.id}"}
    if row.error:
        out["error"] = row.error
    if row.status == "done":
        out["result_url"] = f"/api/tryons/{row.id}/result.glb"
        out["preview_url"] = f"/api/tryons/{row.id}/preview.png"
    if row.finished_at is not None:
        out["finished_at"] = row.finished_at.isoformat() + "Z"
    return {k: v for k, v in out.items() if v is not None}   # no key without a value


def get(config: Config, job_id: str) -> TryOnRow | None:
    with db.session(config) as s:
        return s.get(TryOnRow, job_id)


def result(config: Config, key: str) -> ResultRow | None:
    with db.session(config) as s:
        return s.get(ResultRow, key)


def claim(config: Config, job_id: str, worker: str) -> TryOnRow | None:
    """Take the job for ``worker`` if it is queued, or running with a stale heartbeat. Returns
    the row (``attempts`` is this attempt's number) or None when another has it or it ended."""
    now = utcnow()
    stale = now - timedelta(seconds=config.job_stale_s)
    with db.session(config) as s:
        res = s.execute(
            update(TryOnRow)
            .where(TryOnRow.id == job_id, TryOnRow.cancel_requested.is_(False),
                   or_(TryOnRow.status == "queued",
                       and_(TryOnRow.status == "running", TryOnRow.heartbeat_at < stale)),
                   TryOnRow.attempts < MAX_ATTEMPTS)
            .values(status="running", attempts=TryOnRow.attempts + 1, worker=worker,
                    started_at=now, heartbeat_at=now, stage="starting", error=None)
            .execution_options(synchronize_session=False))
        if res.rowcount != 1:
            return None
        return s.get(TryOnRow, job_id)


def _mine(job_id: str, attempt: int):
    return (TryOnRow.id == job_id, TryOnRow.attempts == attempt, TryOnRow.status == "running")


def heartbeat(config: Config, job_id: str, attempt: int, progress: float, stage: str) -> bool:
    """Record progress; False when the job should stop (cancelled, deleted, or taken over)."""
    with db.session(config) as s:
        res = s.execute(
            update(TryOnRow).where(*_mine(job_id, attempt), TryOnRow.cancel_requested.is_(False))
            .values(progress=case((TryOnRow.progress > progress, TryOnRow.progress),
                                  else_=progress),
                    stage=stage, heartbeat_at=utcnow())
            .execution_options(synchronize_session=False))
        return res.rowcount == 1


def finish(config: Config, job_id: str, attempt: int, key: str, metrics: dict,
           sizes: dict, timings: dict | None = None) -> bool:
    """Mark the job done with its result (the files are already stored); the result's row is
    added if the key has none. False when the job is no longer this attempt's."""
    now = utcnow()
    with db.session(config) as s:
        res = s.execute(
            update(TryOnRow).where(*_mine(job_id, attempt), TryOnRow.cancel_requested.is_(False))
            .values(status="done", progress=1.0, stage="done", finished_at=now,
                    heartbeat_at=now, timings=timings)
            .execution_options(synchronize_session=False))
        if res.rowcount != 1:
            return False
        # two jobs of one key (two bodies of the same content) may finish together: the first
        # row stays (the simulation is deterministic: the same bytes, the same metrics but for
        # wall-clock times)
        s.execute(_insert_ignoring(s, ResultRow).values(key=key, metrics=metrics,
                                                        created_at=now, **sizes))
        return True


def _insert_ignoring(session, table):
    """INSERT … ON CONFLICT DO NOTHING, in the session's dialect."""
    if session.bind.dialect.name == "postgresql":
        from sqlalchemy.dialects.postgresql import insert
    else:
        from sqlalchemy.dialects.sqlite import insert
    return insert(table).on_conflict_do_nothing()


def end(config: Config, job_id: str, attempt: int, status: str, error: str | None,
        timings: dict | None = None) -> bool:
    """Mark the job ``failed`` or ``cancelled`` (with its reason and its stage timings)."""
    with db.session(config) as s:
        res = s.execute(
            update(TryOnRow).where(TryOnRow.id == job_id, TryOnRow.attempts == attempt,
                                   TryOnRow.status == "running")
            .values(status=status, error=error, stage=status, finished_at=utcnow(),
                    timings=timings)
            .execution_options(synchronize_session=False))
        return res.rowcount == 1


def cancel(config: Config, job_id: str) -> TryOnRow | None:
    """Cancel a job: a queued one at once, a running one by asking its worker (it stops within
    half a second and marks it cancelled). Returns the row as it is now."""
    now = utcnow()
    with db.session(config) as s:
        s.execute(update(TryOnRow).where(TryOnRow.id == job_id, TryOnRow.status == "queued")
                  .values(status="cancelled", stage="cancelled", cancel_requested=True,
                          finished_at=now, error="cancelled before it started")
                  .execution_options(synchronize_session=False))
        s.execute(update(TryOnRow).where(TryOnRow.id == job_id, TryOnRow.status == "running")
                  .values(cancel_requested=True)
                  .execution_options(synchronize_session=False))
    return get(config, job_id)


def result_in_use(config: Config, key: str) -> bool:
    with db.session(config) as s:
        return s.scalar(select(func.count()).select_from(TryOnRow)
                        .where(TryOnRow.key == key)) > 0


def recover(config: Config, send, queued_in_broker) -> dict:
    """One pass of recovery. Jobs running with a heartbeat older than ``job_stale_s`` go back
    to the queue (or fail after ``MAX_ATTEMPTS``); queued jobs older than ``requeue_after_s``
    are sent again when the broker holds fewer messages than there are such jobs (it lost
    some). A job that has run longer than the hard time limit is failed, not run again: it was
    killed for its time. ``send(job_id)`` enqueues, ``queued_in_broker()`` counts the broker's
    messages (None: unknown). Returns what it did."""
    now = utcnow()
    stale = now - timedelta(seconds=config.job_stale_s)
    done = {"requeued": [], "failed": [], "resent": []}
    with db.session(config) as s:
        dead = s.scalars(select(TryOnRow.id).where(TryOnRow.status == "running",
                                                   TryOnRow.heartbeat_at < stale)).all()
        too_long = now - timedelta(seconds=config.job_time_limit_s)
        for job_id in dead:
            res = s.execute(
                update(TryOnRow).where(TryOnRow.id == job_id, TryOnRow.status == "running",
                                       TryOnRow.heartbeat_at < stale,
                                       TryOnRow.started_at < too_long)
                .values(status="failed", stage="failed", finished_at=now,
                        error=f"over the {config.job_time_limit_s:g} s time limit")
                .execution_options(synchronize_session=False))
            if res.rowcount:
                done["failed"].append(job_id)
                continue
            res = s.execute(
                update(TryOnRow).where(TryOnRow.id == job_id, TryOnRow.status == "running",
                                       TryOnRow.heartbeat_at < stale,
                                       TryOnRow.attempts >= MAX_ATTEMPTS)
                .values(status="failed", stage="failed", finished_at=now,
                        error=f"the job's worker stopped {MAX_ATTEMPTS} times (a crash, or "
                              f"the {config.job_time_limit_s:g} s time limit)")
                .execution_options(synchronize_session=False))
            if res.rowcount:
                done["failed"].append(job_id)
                continue
            res = s.execute(
                update(TryOnRow).where(TryOnRow.id == job_id, TryOnRow.status == "running",
                                       TryOnRow.heartbeat_at < stale)
                .values(status="queued", stage="queued", enqueued_at=now)
                .execution_options(synchronize_session=False))
            if res.rowcount:
                done["requeued"].append(job_id)
        # a cancel asked of a job whose worker died: it ends here
        s.execute(update(TryOnRow).where(TryOnRow.status == "queued",
                                         TryOnRow.cancel_requested.is_(True))
                  .values(status="cancelled", stage="cancelled", finished_at=now)
                  .execution_options(synchronize_session=False))
        old = now - timedelta(seconds=config.requeue_after_s)
        waiting = s.scalars(select(TryOnRow.id).where(TryOnRow.status == "queued",
                                                      TryOnRow.enqueued_at < old)).all()
    for job_id in done["requeued"]:
        send(job_id)
    if waiting:
        held = queued_in_broker()
        if held is not None and held < len(waiting):   # some were lost: send them all again
            # (a duplicate finds its job claimed or ended and does nothing)
            with db.session(config) as s:
                s.execute(update(TryOnRow).where(TryOnRow.id.in_(waiting),
                                                 TryOnRow.status == "queued")
                          .values(enqueued_at=now).execution_options(synchronize_session=False))
            for job_id in waiting:
                send(job_id)
            done["resent"] = list(waiting)
    return done


# In one process (the SQLite default: one API process) the cached answer and the deletion of a
# result take turns here; on PostgreSQL the result's row is locked (SELECT … FOR UPDATE).
RESULTS_LOCK = threading.Lock()


def results_lock(config: Config):
    """This process's lock around result rows where the database has no row locks (SQLite);
    with PostgreSQL, nothing: :func:`lock_result` locks the row itself."""
    return RESULTS_LOCK if config.db_url.startswith("sqlite") else contextlib.nullcontext()


def lock_result(session, key: str, *, shared: bool = False) -> ResultRow | None:
    """The result's row, locked until the session ends (PostgreSQL; SQLite: hold
    :func:`results_lock`). ``shared``: FOR SHARE — answers from the cache do not wait for each
    other, only for a deletion (FOR UPDATE) of the row."""
    return session.scalars(select(ResultRow).where(ResultRow.key == key)
                           .with_for_update(read=shared)).first()


def delete_for_body(config: Config, body_id: str) -> list[str]:
    """Delete the body's try-ons (a running one is asked to stop; its worker finds its row
    gone) and return the result keys no other try-on uses any more (their rows deleted)."""
    with results_lock(config), db.session(config) as s:
        keys = sorted(set(s.scalars(select(TryOnRow.key).where(TryOnRow.body_id == body_id))))
        for key in keys:   # in key order: two deletions never wait for each other in a circle
            lock_result(s, key)
        s.execute(delete(TryOnRow).where(TryOnRow.body_id == body_id)
                  .execution_options(synchronize_session=False))
        orphaned = []
        for key in keys:
            left = s.scalar(select(func.count()).select_from(TryOnRow).where(TryOnRow.key == key))
            if not left:
                s.execute(delete(ResultRow).where(ResultRow.key == key)
                          .execution_options(synchronize_session=False))
                orphaned.append(key)
        return orphaned


def active_in(session, body_id: str, key: str) -> TryOnRow | None:
    """This body's queued or running try-on with this key, if any (in ``session``)."""
    return session.scalars(select(TryOnRow).where(TryOnRow.body_id == body_id,
                                                  TryOnRow.key == key,
                                                  TryOnRow.status.in_(ACTIVE))
                           .limit(1)).first()


def active_for(config: Config, body_id: str, key: str) -> TryOnRow | None:
    """This body's queued or running try-on with this key, if any."""
    with db.session(config) as s:
        return active_in(s, body_id, key)


def seen(config: Config, worker: str, concurrency: int) -> None:
    """The worker process ``worker`` (host:pid) is alive, running ``concurrency`` jobs at once."""
    now = utcnow()
    with db.session(config) as s:
        res = s.execute(update(WorkerRow).where(WorkerRow.id == worker)
                        .values(seen_at=now, concurrency=concurrency)
                        .execution_options(synchronize_session=False))
        if res.rowcount == 0:
            host, _, pid = worker.rpartition(":")
            s.execute(_insert_ignoring(s, WorkerRow).values(
                id=worker, host=host, pid=int(pid or 0), concurrency=concurrency,
                started_at=now, seen_at=now))


def gone(config: Config, worker: str) -> None:
    """The worker process stopped cleanly."""
    with contextlib.suppress(Exception), db.session(config) as s:
        s.execute(delete(WorkerRow).where(WorkerRow.id == worker)
                  .execution_options(synchronize_session=False))


def worker_name() -> str:
    return f"{socket.gethostname()}:{os.getpid()}"
