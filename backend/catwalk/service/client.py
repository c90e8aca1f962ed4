"""A small client of the HTTP API (httpx), as a page or script would use it: ``catwalk demo``,
``catwalk bench service`` and the tests drive the service through it."""

from __future__ import annotations

import json
import time
from collections.abc import Callable

import httpx


class ApiFailure(Exception):
    """The service answered with an error (its JSON ``error`` is in ``body``)."""

    def __init__(self, status: int, body):
        self.status, self.body = status, body
        err = body.get("error", {}) if isinstance(body, dict) else {}
        super().__init__(f"HTTP {status}: {err.get('message', body)}")


class Client:
    def __init__(self, base_url: str, timeout: float = 60.0):
        self.base = base_url.rstrip("/")
        self.http = httpx.Client(base_url=self.base, timeout=timeout)

    def close(self) -> None:
        self.http.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _json(self, resp: httpx.Response, ok=(200, 201, 202)) -> dict:
        try:
            body = resp.json()
        except ValueError:
            body = resp.text
        if resp.status_code not in ok:
            raise ApiFailure(resp.status_code, body)
        return body

    def wait_ready(self, timeout: float = 120.0) -> dict:
        """Wait until ``/readyz`` says ready (database, broker, storage)."""
        t0 = time.monotonic()
        last = None
        while time.monotonic() - t0 < timeout:
            try:
                r = self.http.get("/readyz", timeout=5)
                if r.status_code == 200:
                    return r.json()
                last = r.text
            except httpx.HTTPError as exc:
                last = str(exc)
            time.sleep(0.2)
        raise TimeoutError(f"{self.base} not ready after {timeout:g} s ({last})")

    def garments(self) -> list[dict]:
        return self._json(self.http.get("/api/garments"))["garments"]

    def create_body(self, **measurements) -> dict:
        return self._json(self.http.post("/api/bodies", json=measurements))

    def upload_scan(self, data: bytes, filename: str, sex: str | None = None) -> dict:
        form = {"sex": sex} if sex else None
        return self._json(self.http.post("/api/bodies", files={"scan": (filename, data)},
                                         data=form))

    def create_tryon(self, **request) -> dict:
        return self._json(self.http.post("/api/tryons", json=request))

    def tryon(self, job_id: str) -> dict:
        return self._json(self.http.get(f"/api/tryons/{job_id}"))

    def cancel(self, job_id: str) -> dict:
        return self._json(self.http.delete(f"/api/tryons/{job_id}"))

    def follow(self, job_id: str, on_event: Callable[[str, dict], None] | None = None,
               timeout: float = 600.0) -> dict:
        """Follow the job's server-sent events until it ends; its last state."""
        last = None
        with self.http.stream("GET", f"/api/tryons/{job_id}/events",
                              timeout=httpx.Timeout(timeout, read=timeout)) as resp:
            if resp.status_code != 200:
                resp.read()
                self._json(resp, ok=(200,))
            event = None
            for line in resp.iter_lines():
                if line.startswith("event:"):
                    event = line[6:].strip()
                elif line.startswith("data:") and event:
                    last = json.loads(line[5:].strip())
                    if on_event is not None:
                        on_event(event, last)
                    if event in ("done", "failed", "cancelled"):
                        return last
        return last if last is not None else self.tryon(job_id)

    def wait(self, job_id: str, timeout: float = 600.0, poll: float = 0.2) -> dict:
        """Poll the job until it ends; its last state."""
        t0 = time.monotonic()
        while True:
            job = self.tryon(job_id)
            if job["status"] in ("done", "failed", "cancelled"):
                return job
            if time.monotonic() - t0 > timeout:
                raise TimeoutError(f"try-on {job_id} still {job['status']} after {timeout:g} s")
            time.sleep(poll)

    def result(self, job_id: str, compress: bool = True) -> bytes:
        r = self.http.get(f"/api/tryons/{job_id}/result.glb",
                          params={"compress": int(compress)})
        if r.status_code != 200:
            self._json(r, ok=(200,))
        return r.content

    def preview(self, job_id: str) -> bytes:
        r = self.http.get(f"/api/tryons/{job_id}/preview.png")
        if r.status_code != 200:
            self._json(r, ok=(200,))
        return r.content
