"""``GET /metrics``: the service in Prometheus's text format (prometheus-client).

Counted by this API process as it answers: the cache (``catwalk_tryon_cache_total{result}``),
refused uploads (``catwalk_uploads_refused_total{reason}``), requests from shops' pages refused
(``catwalk_shop_requests_refused_total{reason}``: key, origin, route, shopper, secret_key,
rate) and every request's seconds by route
(``catwalk_http_request_seconds``). Read at each scrape from the database and the broker — the
truth every process shares, so the figures cover workers on any host: jobs by state
(``catwalk_jobs{state}``), messages waiting in the broker (``catwalk_queue_messages``), worker
processes seen in the last 30 s (``catwalk_workers_alive``, ``catwalk_worker_slots``), and
the seconds of each stage of the try-ons that ended since the last scrape
(``catwalk_tryon_stage_seconds{stage}``, ``catwalk_tryon_seconds{status}``: histograms; a job's
stage timings are written by its worker). With several API processes, scrape one of them for
the histograms (each observes every job). And this API process's own CPU seconds, memory and
open files (``process_*``, prometheus-client's process collector).
"""

from __future__ import annotations

import threading
from datetime import timedelta

from prometheus_client import (
    CollectorRegistry,
    Counter,
    Histogram,
    ProcessCollector,
    generate_latest,
)
from prometheus_client.core import GaugeMetricFamily
from sqlalchemy import func, select

from catwalk.config import Config
from catwalk.service.jobs import app as queue
from catwalk.service.store import db
from catwalk.service.store.models import STATES, TryOnRow, WorkerRow, utcnow

WORKER_ALIVE_S = 30.0
STAGE_BUCKETS = (0.05, 0.1, 0.25, 0.5, 1, 2, 5, 10, 20, 40, 80, 160, 320)
REQUEST_BUCKETS = (0.002, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10)


class JobsCollector:
    """Gauges read at each scrape: jobs by state, the broker's queue, workers alive."""

    def __init__(self, config: Config):
        self.config = config

    def collect(self):
        jobs = GaugeMetricFamily("catwalk_jobs", "Try-on jobs by state", labels=["state"])
        alive = GaugeMetricFamily("catwalk_workers_alive",
                                  "Worker processes seen in the last 30 s")
        slots = GaugeMetricFamily("catwalk_worker_slots",
                                  "Try-ons the live workers run at once")
        try:
            with db.session(self.config) as s:
                counts = dict(s.execute(select(TryOnRow.status, func.count())
                                        .group_by(TryOnRow.status)).all())
                since = utcnow() - timedelta(seconds=WORKER_ALIVE_S)
                live = s.execute(select(func.count(), func.coalesce(
                    func.sum(WorkerRow.concurrency), 0)).where(WorkerRow.seen_at >= since)).one()
        except Exception:   # the database is away: no gauges this time (readyz says why)
            return
        for state in STATES:
            jobs.add_metric([state], counts.get(state, 0))
        yield jobs
        alive.add_metric([], live[0])
        yield alive
        slots.add_metric([], live[1])
        yield slots
        held = queue.queued_messages(self.config)
        if held is not None:
            q = GaugeMetricFamily("catwalk_queue_messages", "Messages waiting in the broker")
            q.add_metric([], held)
            yield q


class Metrics:
    """This API process's metrics."""

    def __init__(self, config: Config):
        self.config = config
        self.registry = CollectorRegistry()
        self.cache = Counter("catwalk_tryon_cache", "Try-on requests answered from the cache "
                             "(hit) or sent to a worker (miss)", ["result"],
                             registry=self.registry)
        self.refused = Counter("catwalk_uploads_refused", "Uploads refused, by reason",
                               ["reason"], registry=self.registry)
        self.shops_refused = Counter("catwalk_shop_requests_refused", "Requests from shops' "
                                     "pages refused, by reason", ["reason"],
                                     registry=self.registry)
        self.requests = Histogram("catwalk_http_request_seconds", "Seconds to answer a request",
                                  ["route", "method", "code"], buckets=REQUEST_BUCKETS,
                                  registry=self.registry)
        self.stage = Histogram("catwalk_tryon_stage_seconds", "Seconds a try-on spent in each "
                               "stage", ["stage"], buckets=STAGE_BUCKETS, registry=self.registry)
        self.total = Histogram("catwalk_tryon_seconds", "Seconds a try-on ran, by how it ended",
                               ["status"], buckets=STAGE_BUCKETS, registry=self.registry)
        self.registry.register(JobsCollector(config))
        ProcessCollector(registry=self.registry)   # this process's CPU seconds, memory, files
        self._seen_until = utcnow()
        self._lock = threading.Lock()

    def observe_finished(self) -> None:
        """Add the stage timings of the jobs that ended since the last call."""
        with self._lock:
            try:
                with db.session(self.config) as s:
                    rows = s.execute(
                        select(TryOnRow.finished_at, TryOnRow.status, TryOnRow.timings)
                        .where(TryOnRow.finished_at > self._seen_until,
                               TryOnRow.cached.is_(False))
                        .order_by(TryOnRow.finished_at)).all()
            except Exception:
                return
            for finished, status, timings in rows:
                self._seen_until = max(self._seen_until, finished)
                if not timings:
                    continue
                for stage, seconds in timings.items():
                    self.stage.labels(stage).observe(float(seconds))
                self.total.labels(status).observe(float(sum(timings.values())))

    def exposition(self) -> bytes:
        self.observe_finished()
        return generate_latest(self.registry)
