"""The job queue: one Celery app, configured from catwalk's settings, for every deployment.

At scale the broker is Redis (``CATWALK_BROKER_URL=redis://…``); with nothing configured it is
kombu's filesystem transport in the storage folder, which needs no server. Either way:

- a message is acknowledged only when its job has ended (``acks_late``), and given back if the
  worker process running it dies (``reject_on_worker_lost``); each worker process takes one
  message at a time (prefetch 1);
- Redis hands an unacknowledged message to another worker only after the visibility timeout,
  which is set above the longest job (the hard time limit) so a long job is never run twice
  by the broker;
- the database decides what runs: a duplicate or late message finds its job already claimed
  or ended and does nothing (:func:`catwalk.service.jobs.lifecycle.claim`), and a job whose message
  was lost is sent again by :func:`catwalk.service.jobs.lifecycle.recover`.

The task carries only the job's id.
"""

from __future__ import annotations

import functools

from celery import Celery
from kombu.exceptions import ChannelError

from catwalk.config import Config

TASK = "catwalk.run_tryon"


def _transport_options(config: Config) -> dict:
    if config.broker_url is None:
        folder = config.broker_folder
        for sub in ("queue", "control"):
            (folder / sub).mkdir(parents=True, exist_ok=True)
        return {"data_folder_in": str(folder / "queue"),
                "data_folder_out": str(folder / "queue"),
                "control_folder": str(folder / "control"),
                "store_processed": False, "polling_interval": 0.1}
    # above the hard time limit: Redis never redelivers a job that is still running
    return {"visibility_timeout": int(config.job_time_limit_s + 600)}


@functools.lru_cache(maxsize=4)
def celery_app(config: Config) -> Celery:
    """The Celery app for ``config`` (one per settings object). It knows no task: a message is
    sent by the task's name, and only a worker's process registers the tasks
    (:func:`catwalk.service.jobs.worker.register_tasks`), so the API does not load them."""
    app = Celery("catwalk", broker=config.broker, set_as_current=False)
    app.conf.update(
        task_default_queue=config.queue,
        task_acks_late=True,
        task_reject_on_worker_lost=True,
        worker_prefetch_multiplier=1,
        task_ignore_result=True,
        task_time_limit=config.job_time_limit_s,
        # the soft limit fails the job with its reason before the hard one kills the process
        task_soft_time_limit=config.job_time_limit_s - min(30.0, 0.1 * config.job_time_limit_s),
        broker_transport_options=_transport_options(config),
        broker_connection_retry_on_startup=True,
        broker_connection_timeout=5,
        worker_hijack_root_logger=False,
        worker_redirect_stdouts=False,
        worker_enable_remote_control=config.broker_url is not None,
        worker_send_task_events=False,
        task_serializer="json",
        accept_content=["json"],
    )
    return app


def send(config: Config, job_id: str) -> None:
    """Put the job on the queue."""
    celery_app(config).send_task(TASK, args=[job_id], queue=config.queue,
                                 retry=True, retry_policy={"max_retries": 3})


def queued_messages(config: Config) -> int | None:
    """How many messages wait in the broker's queue (None when it cannot be told). Redis
    deletes an empty list, so there an empty queue answers NOT_FOUND: 0 messages."""
    app = celery_app(config)
    try:
        with app.connection_for_write() as conn:
            ok = conn.default_channel.queue_declare(queue=config.queue, passive=True)
            return int(ok.message_count)
    except ChannelError as exc:
        return 0 if "NOT_FOUND" in str(exc) else None
    except Exception:
        return None


def ping(config: Config) -> None:
    """Raise if the broker cannot be reached."""
    app = celery_app(config)
    with app.connection_for_write() as conn:
        conn.ensure_connection(max_retries=1, timeout=3)
        conn.default_channel.queue_declare(queue=config.queue, durable=True,
                                           auto_delete=False)


CHECK_TASK = "catwalk.check_garment"


def send_check(config: Config, garment_id: str, version: int) -> None:
    """Put the version's dressing check on the queue."""
    celery_app(config).send_task(CHECK_TASK, args=[garment_id, int(version)],
                                 queue=config.queue, retry=True,
                                 retry_policy={"max_retries": 3})
