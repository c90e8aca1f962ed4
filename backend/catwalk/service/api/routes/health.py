"""``/healthz`` (the process answers) and ``/readyz`` (database, broker, storage reachable)."""

from __future__ import annotations

import asyncio
import time

from fastapi import APIRouter, Depends, Request
from fastapi.responses import JSONResponse, PlainTextResponse, Response
from prometheus_client import CONTENT_TYPE_LATEST

from catwalk.config import Config
from catwalk.service.api import deps, schemas
from catwalk.service.jobs import app as queue
from catwalk.service.store import db

router = APIRouter(tags=["health"])


@router.get("/healthz", response_model=schemas.Health)
def healthz() -> dict:
    return {"status": "ok"}


def _probe(name: str, fn) -> dict:
    t0 = time.perf_counter()
    try:
        fn()
        return {"ok": True, "ms": round(1e3 * (time.perf_counter() - t0), 1)}
    except Exception as exc:
        return {"ok": False, "error": f"{type(exc).__name__}: {exc}"[:300]}


@router.get("/metrics", response_class=PlainTextResponse,
            responses={200: {"description": "Prometheus's text format",
                             "content": {"text/plain": {"schema": {"type": "string"}}}}})
async def metrics(request: Request):
    """The service's metrics in Prometheus's text format (catwalk/service/metrics.py)."""
    body = await asyncio.to_thread(request.app.state.metrics.exposition)
    return Response(body, media_type=CONTENT_TYPE_LATEST)


@router.get("/readyz", response_model=schemas.Readiness,
            responses={503: {"model": schemas.Readiness,
                             "description": "a check failed (its `error` says why)"}})
async def readyz(config: Config = Depends(deps.config), storage=Depends(deps.storage)):
    checks = await asyncio.to_thread(lambda: {
        "database": _probe("database", lambda: db.ping(config)),
        "broker": _probe("broker", lambda: queue.ping(config)),
        "storage": _probe("storage", storage.check)})
    ok = all(c["ok"] for c in checks.values())
    return JSONResponse({"status": "ready" if ok else "not ready", "checks": checks},
                        status_code=200 if ok else 503)
