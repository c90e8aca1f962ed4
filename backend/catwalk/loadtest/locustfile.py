"""The shoppers ``catwalk loadtest`` sends (Locust; run in its own process: gevent patches the
standard library of whatever imports it).

Each simulated shopper browses the catalogue and garment pages, fetches thumbnails, follows a
try-on's status, asks again for a finished try-on (answered from the cache) and downloads its
result, now and then asks for a new fast try-on (a worker simulates it) and, rarely, makes a
body from measurements. The body and a finished try-on for the cached routes are made before
(``$CATWALK_LOADTEST_BODY``, ``$CATWALK_LOADTEST_DONE``). At the end a summary is written as
JSON to ``$CATWALK_LOADTEST_OUT``.
"""

from __future__ import annotations

import json
import os
import random
import time

import httpx
from locust import FastHttpUser, between, events, tag, task

from catwalk.loadtest.run import BODY

STATE: dict = {"garments": [], "body": None, "done": None, "asked": [], "started": None,
               "server_errors": {}, "timeline": {}}
GARMENT = os.environ.get("CATWALK_LOADTEST_GARMENT", "pencil-skirt")


@events.test_start.add_listener
def _prepare(environment, **_):
    """The body and the finished try-on ``catwalk loadtest`` made before starting."""
    STATE["body"] = os.environ["CATWALK_LOADTEST_BODY"]
    STATE["done"] = os.environ["CATWALK_LOADTEST_DONE"]
    with httpx.Client(base_url=environment.host, timeout=60) as http:
        STATE["garments"] = [g["id"] for g in http.get("/api/garments").json()["garments"]]
    STATE["started"] = time.monotonic()


@events.request.add_listener
def _record(request_type, name, response_time, response_length, response=None,
            exception=None, **_):
    """Every request's second (since the start) and time, for the timeline; every 5xx by its
    status, a 503 told apart by whether it says when to come back (``Retry-After``)."""
    if STATE["started"] is None:
        return
    second = int(time.monotonic() - STATE["started"])
    STATE["timeline"].setdefault(second, []).append(response_time)
    status = getattr(response, "status_code", 0) or 0
    if status >= 500:
        headers = getattr(response, "headers", None) or {}
        retry = status == 503 and bool(headers.get("Retry-After") or headers.get("retry-after"))
        key = f"{status}{' Retry-After' if retry else ''} {request_type} {name}"
        STATE["server_errors"][key] = STATE["server_errors"].get(key, 0) + 1


def _timeline() -> list[list]:
    """[second, requests, p99 ms] for every second of the run."""
    out = []
    for second in sorted(STATE["timeline"]):
        times = sorted(STATE["timeline"][second])
        out.append([second, len(times), round(times[min(len(times) - 1,
                                                          int(0.99 * len(times)))], 1)])
    return out


@events.test_stop.add_listener
def _summarise(environment, **_):
    out = os.environ.get("CATWALK_LOADTEST_OUT")
    if not out:
        return
    elapsed = max(1e-9, time.monotonic() - (STATE["started"] or time.monotonic()))
    stats = environment.stats
    per_route = {}
    for (name, method), e in sorted(stats.entries.items()):
        if not e.num_requests:
            continue
        per_route[f"{method} {name}"] = {
            "requests": e.num_requests, "failures": e.num_failures,
            "p50_ms": e.get_response_time_percentile(0.5),
            "p95_ms": e.get_response_time_percentile(0.95),
            "p99_ms": e.get_response_time_percentile(0.99),
            "rps": round(e.num_requests / elapsed, 2)}
    done = 0
    with httpx.Client(base_url=environment.host, timeout=30) as http:
        for job_id in STATE["asked"]:
            try:
                if http.get(f"/api/tryons/{job_id}").json().get("status") == "done":
                    done += 1
            except Exception:
                pass
    total = stats.total
    with open(out, "w") as fh:
        json.dump({"requests": total.num_requests, "failures": total.num_failures,
                   "seconds": round(elapsed, 2), "rps": round(total.num_requests / elapsed, 2),
                   "per_route": per_route, "tryons_asked": len(STATE["asked"]),
                   "tryons_done": done, "tryons_per_minute": round(60 * done / elapsed, 2),
                   "errors": [f"{e.method} {e.name}: {e.error} ×{e.occurrences}"
                              for e in list(stats.errors.values())[:10]],
                   "asked_ids": STATE["asked"], "server_errors": STATE["server_errors"],
                   "timeline": _timeline()}, fh)


class Shopper(FastHttpUser):
    # FastHttpUser (geventhttpclient): several times less CPU a request than HttpUser (Locust's
    # documentation), so that on a small machine the load generator takes less of the cores
    # the service is measured on
    wait_time = between(0.05, 0.2)

    def _garment(self) -> str:
        return random.choice(STATE["garments"])

    @task(10)
    def catalogue(self):
        self.client.get("/api/garments", name="/api/garments")

    @task(5)
    def garment(self):
        self.client.get(f"/api/garments/{self._garment()}", name="/api/garments/{id}")

    @task(8)
    def thumbnail(self):
        self.client.get(f"/api/garments/{self._garment()}/thumbnail.png",
                        name="/api/garments/{id}/thumbnail.png")

    @task(10)
    def status(self):
        self.client.get(f"/api/tryons/{STATE['done']}", name="/api/tryons/{id}")

    def _ask(self, name: str, seconds: float):
        """POST /api/tryons for the prepared body (fast preset), checked by the caller."""
        return self.client.post("/api/tryons", name=name, catch_response=True,
                                json={"body_id": STATE["body"], "garment_id": GARMENT,
                                      "preset": "fast", "seconds": seconds})

    @task(5)
    def cached_tryon(self):
        with self._ask("/api/tryons (cached)", 0.5) as r:   # the prepared try-on's settings
            if r.status_code != 200 or not r.json().get("cached"):
                r.failure(f"not answered from the cache: {r.status_code}")

    @task(3)
    def cached_result(self):
        self.client.get(f"/api/tryons/{STATE['done']}/result.glb",
                        name="/api/tryons/{id}/result.glb")

    @task(1)
    def new_tryon(self):
        seconds = round(random.uniform(0.5, 1.0), 3)   # a new content key: a worker simulates
        with self._ask("/api/tryons (new)", seconds) as r:
            if r.status_code in (200, 202):
                STATE["asked"].append(r.json()["id"])
            else:
                r.failure(f"HTTP {r.status_code}")

    @tag("bodies")   # left out by ``--mix api``
    @task(1)
    def new_body(self):
        if random.random() < 0.2:   # making a body costs 2–3 s of the API's CPU: rarely
            self.client.post("/api/bodies", json=BODY, name="/api/bodies")
