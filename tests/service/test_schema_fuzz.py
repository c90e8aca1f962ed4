"""Schemathesis against the service's own OpenAPI document (``/openapi.json``), in-process.

The app is ``create_app(config)`` on a temporary storage folder and a one-garment catalogue,
the embedded default (SQLite, the filesystem broker), no worker: a try-on asked for stays
queued. Schemathesis's engine (what ``schemathesis run`` does) drives it through its ASGI
transport, every route, in every phase: the coverage phase (boundary values, missing and
extra parameters, methods a path does not take), fuzzing (valid and invalid data, positive
and negative), and the stateful phase following the document's links (``POST /api/bodies``
→ ``GET``/``DELETE /api/bodies/{body_id}``, its ``body.glb``, size advice, a try-on;
``POST /api/tryons`` → its status, events, cancel, result and preview; the catalogue → a
garment's routes).

Checked on every response: never a 5xx (nor an exception out of the app), the status code
documented for the route, the content type documented for that status, the body valid
against its schema, documented headers present, ``Allow`` naming exactly the path's methods,
invalid data refused, a deleted resource gone. ``positive_data_acceptance`` is off: whether a
schema-valid request is accepted depends on what the schema cannot say (a scan's content, the
garment's sizes and fabrics, a ``Range`` inside the file), and those refusals are 4xx by
design.

A body made from valid measurements costs 1–3 s in the body pool, so ``POST /api/bodies`` gets
few examples and the stateful phase few scenarios; the ≥ 1,000 requests come mostly from the
cheap routes and invalid inputs. About a minute on 2 cores.
"""

from __future__ import annotations

import collections
import os
import time

import pytest
import schemathesis

from .helpers import make_config, service_env

MIN_REQUESTS = 1000

SETTINGS = {
    "seed": 20261125,   # the same requests on every run (a failure reproduces)
    # `make fuzz` runs deeper: CATWALK_FUZZ_API_EXAMPLES examples per operation
    "generation": {"mode": "all", "database": "none",
                   "max-examples": int(os.environ.get("CATWALK_FUZZ_API_EXAMPLES") or 60)},
    # use_after_free off: DELETE of a try-on cancels it, and the try-on stays to be read
    # ("cancelled", docs/api.md); a deleted body answering 404: test_embedded.py
    "checks": {"enabled": True, "positive_data_acceptance": {"enabled": False},
               "use_after_free": {"enabled": False}},
    "continue-on-failure": True,
    "max-failures": 100_000,
    # the stateful phase sends valid data only: with invalid data too, whether one of its
    # scenarios made a body or a try-on to follow a link to hung on the draws (a change in
    # any response, an ETag, reshuffles them: 4 of 6 seeds followed none); the coverage and
    # fuzzing phases send the invalid data
    "phases": {"stateful": {"max-steps": 8, "generation": {"max-examples": 12,
                                                           "mode": "positive"}}},
    "operations": [
        # a valid body is 1–3 s of CPU: few of them
        {"include-name": "POST /api/bodies", "generation": {"max-examples": 6},
         "request-timeout": 60},
        # the merchants' routes: the coverage and fuzzing phases (their links would take the
        # stateful phase's few scenarios away from the shoppers' bodies and try-ons)
        {"include-tag": "merchant", "phases": {"stateful": {"enabled": False}}},
        # a queued try-on's events never end (no worker here): its first event is enough
        {"include-name": "GET /api/tryons/{job_id}/events", "request-timeout": 2,
         "max-stream-events": 1},
    ],
}


class Recorded:
    """The app, counting the requests it gets: (phase, method, route template, status)."""

    def __init__(self, app):
        self.app = app
        self.phase = "setup"
        self.seen: collections.Counter = collections.Counter()

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        status = [None]

        async def watched(msg):
            if msg["type"] == "http.response.start":
                status[0] = msg["status"]
            await send(msg)

        try:
            await self.app(scope, receive, watched)
        finally:
            route = getattr(scope.get("route"), "path", None) or "unmatched"
            route = route.replace(":path}", "}")   # as the document writes the template
            self.seen[(self.phase, scope["method"], route, status[0])] += 1

    def count(self, phase=None, method=None, route=None, status=None) -> int:
        return sum(n for (p, m, r, s), n in self.seen.items()
                   if (phase is None or p == phase) and (method is None or m == method)
                   and (route is None or r == route)
                   and (status is None or (s is not None and status(s))))


@pytest.fixture(scope="module")
def service(tmp_path_factory, catalogue_dir):
    from schemathesis.python import asgi

    from catwalk.service import merchants
    from catwalk.service.api.app import create_app
    from catwalk.service.store import db

    config = make_config(service_env(tmp_path_factory.mktemp("fuzz-storage"), catalogue_dir))
    app = Recorded(create_app(config))
    # every request as a merchant (the merchant routes past their 401; the others ignore it)
    db.migrate(config)
    key = merchants.create(config, "fuzzer")
    settings = {**SETTINGS, "headers": {"Authorization": f"Bearer {key}"}}
    # loading the document starts the app's lifespan (the schema migrated, the body pool warm)
    schema = schemathesis.openapi.from_asgi("/openapi.json", app,
                                            config=schemathesis.Config.from_dict(settings))
    try:
        # the catalogue's thumbnail and dressed garment are made at start (≈ 7 s in the body
        # pool): wait for them, so the fuzzing meets the routes' steady state
        with asgi.get_client(app) as client:
            r = client.get("/api/garments/pencil-skirt/dressed.glb", timeout=120)
            assert r.status_code == 200, (r.status_code, r.text[:300])
        yield schema, app
    finally:
        asgi.shutdown_lifespans()   # the body pool and the recovery loop stop


def _finding(failure, code_sample: str) -> str:
    message = failure.message.strip().replace("\n", "\n      ")
    return (f"{failure.operation}: {failure.title}\n      {message}\n"
            f"      reproduce: {code_sample.strip()}")


def test_schemathesis_finds_nothing(service):
    from schemathesis.engine import Status, events, from_schema

    schema, app = service
    app.seen.clear()
    findings: dict[tuple, str] = {}
    errors: list[str] = []
    stateful = None
    t0 = time.monotonic()
    for event in from_schema(schema).execute():
        if isinstance(event, events.PhaseStarted):
            app.phase = event.phase.name.value
            if app.phase == "stateful":
                stateful = event.payload
        elif isinstance(event, events.ScenarioFinished):
            for checks in event.recorder.checks.values():
                for check in checks:
                    if check.failure_info is not None:
                        f = check.failure_info.failure
                        key = (f.operation, check.name, f.title)
                        findings.setdefault(key, _finding(f, check.failure_info.code_sample))
            if event.status == Status.ERROR:
                errors.append(f"{event.recorder.label}: a scenario ended in error")
        elif isinstance(event, events.NonFatalError):
            errors.append(f"{event.label}: {event.info.format()}")
        elif isinstance(event, events.FatalError):
            errors.append(f"fatal: {event.exception!r}")
        elif isinstance(event, events.EngineFinished):
            for f in event.failures:
                findings.setdefault((f.operation, f.title), _finding(f, ""))
    seconds = time.monotonic() - t0
    total = app.count()
    bodies = app.count(method="POST", route="/api/bodies", status=lambda s: s == 201)
    summary = (f"{total} requests in {seconds:.0f} s ({bodies} bodies made); by phase: "
               + ", ".join(f"{p} {app.count(phase=p)}"
                           for p in ("coverage", "fuzzing", "stateful")))
    print(summary)
    for k, n in sorted(app.seen.items(), key=str):
        if k[0] == "stateful":
            print(k, n)
    report = [*errors, *findings.values()]
    assert not report, (f"schemathesis found {len(report)} problem(s) ({summary}):\n\n"
                        + "\n\n".join(report))
    assert total >= MIN_REQUESTS, f"only {summary}"
    # every route was exercised, and the stateful phase followed the document's links
    ops = {(op.ok().method.upper(), op.ok().path) for op in schema.get_all_operations()}
    missed = sorted(f"{m} {p}" for m, p in ops if not app.count(method=m, route=p))
    assert not missed, f"routes never called: {missed}"
    assert stateful is not None and stateful.transitions_total >= 20, stateful
    linked = app.count(phase="stateful", route="/api/bodies/{body_id}",
                       status=lambda s: s < 300) + \
        app.count(phase="stateful", route="/api/tryons/{job_id}", status=lambda s: s < 300)
    assert linked, f"no link followed to a made body or try-on ({summary})"
