"""Try-ons: ``POST /api/tryons`` → 202 (queued) or 200 (already made: ``"cached": true``);
``GET`` its status, ``/events`` (server-sent events until it ends), ``DELETE`` (cancel);
``/result.glb`` (meshopt for the web unless ``?compress=0``) and ``/preview.png``. On a shop
(its publishable key) a try-on is of the shopper's body there and the merchant's garment, and
is reached through that shop only."""

from __future__ import annotations

import asyncio
import json
import logging

from fastapi import APIRouter, Depends, Query, Request
from fastapi.responses import JSONResponse, Response
from sse_starlette.sse import EventSourceResponse

from catwalk.config import Config
from catwalk.service import tryons
from catwalk.service.api import deps, schemas
from catwalk.service.api.errors import ApiError, check_id, not_found
from catwalk.service.api.files import file_response
from catwalk.service.jobs import lifecycle as jobs
from catwalk.service.jobs.app import send
from catwalk.service.store.models import FINISHED, TryOnRow

router = APIRouter(prefix="/api/tryons", tags=["tryons"])
log = logging.getLogger("catwalk.api")
EVENT_POLL_S = 0.25


def _job(config: Config, job_id: str, scope=None) -> TryOnRow:
    check_id(job_id, "try-on")
    row = tryons.get(config, job_id, scope)
    if row is None:
        raise not_found("try-on", job_id)
    return row


@router.post("", status_code=202, response_model=schemas.TryOn,
             responses={200: {"model": schemas.TryOn,
                              "description": "already made: answered from the cache"},
                        **schemas.errors(400, 404, 413, 415, 422, 503)})
async def create_tryon(req: schemas.TryOnRequest, request: Request,
                       config: Config = Depends(deps.config),
                       catalogue=Depends(deps.catalogue), storage=Depends(deps.storage),
                       _json=Depends(deps.json_body), scope=Depends(deps.shop)):
    """Ask for a try-on of a body in a catalogue garment."""
    check_id(req.body_id, "body", "body_id")
    row, needs_sending, view = await asyncio.to_thread(
        tryons.submit, config, catalogue, storage, req.body_id, req.garment_id, req.size,
        req.fabric, req.seconds, req.preset, scope)
    request.app.state.metrics.cache.labels("hit" if row.cached else "miss").inc()
    if needs_sending:
        try:
            await asyncio.to_thread(send, config, row.id)
        except Exception as exc:   # the recovery loop sends it once the broker is back
            log.warning(json.dumps({"event": "send_failed", "job": row.id,
                                    "error": type(exc).__name__}))
    log.info(json.dumps({"event": "tryon_asked", "job": row.id, "status": row.status,
                         "cached": row.cached, "garment": row.garment_id}))
    return JSONResponse(view, status_code=200 if row.status == "done" else 202)


@router.get("/{job_id}", response_model=schemas.TryOn, response_model_exclude_none=True,
            responses=schemas.errors(404, 503))
def get_tryon(job_id: schemas.JobId, config: Config = Depends(deps.config),
              scope=Depends(deps.shop)) -> dict:
    check_id(job_id, "try-on")
    return tryons.view_of(config, job_id, scope)


@router.get("/{job_id}/events", response_class=Response,
            responses={200: {"description": "`event: progress` on every change, then one "
                                            "`event: done|failed|cancelled`",
                             "content": {"text/event-stream": {"schema": schemas.TRYON_EVENT}}},
                       **schemas.errors(404, 503)})
async def tryon_events(job_id: schemas.JobId, request: Request,
                       config: Config = Depends(deps.config), scope=Depends(deps.shop)):
    """The try-on's status as server-sent events (``event: progress`` on every change, then
    one ``event: done|failed|cancelled``), until it ends."""
    row = await asyncio.to_thread(_job, config, job_id, scope)

    async def stream():
        last = last_view = None
        current = row
        while True:
            view = await asyncio.to_thread(tryons.view, config, current) if current else None
            if view is None:   # deleted (with its body) while it was followed
                gone = dict(last_view or {"id": job_id, "progress": 0.0},
                            status="failed", stage="deleted", error="the try-on was deleted")
                yield {"event": "failed", "data": json.dumps(gone)}
                return
            last_view = view
            state = (view["status"], view["progress"], view["stage"])
            if view["status"] in FINISHED:
                yield {"event": view["status"], "data": json.dumps(view)}
                return
            if state != last:
                yield {"event": "progress", "data": json.dumps(view)}
                last = state
            if await request.is_disconnected():
                return
            await asyncio.sleep(EVENT_POLL_S)
            current = await asyncio.to_thread(jobs.get, config, job_id)

    return EventSourceResponse(stream(), ping=10)


@router.delete("/{job_id}", status_code=202, response_model=schemas.TryOn,
               response_model_exclude_none=True, responses=schemas.errors(404, 409, 503))
def cancel_tryon(job_id: schemas.JobId, config: Config = Depends(deps.config),
                 scope=Depends(deps.shop)):
    """Cancel the try-on: at once if queued, within half a second if running."""
    row = _job(config, job_id, scope)
    if row.status in FINISHED:
        raise ApiError(409, f"the try-on has already ended ({row.status})", code="finished")
    row = jobs.cancel(config, job_id)
    return JSONResponse(jobs.view(row), status_code=202)


def _result_file(config: Config, storage, job_id: str, name: str, scope):
    row = _job(config, job_id, scope)
    if row.status != "done":
        raise ApiError(409, f"the try-on is {row.status}, not done", code="not_done")
    res = jobs.result(config, row.key)
    path = storage.result_file(row.key, name)
    if res is None or not path.is_file():
        raise not_found("result for try-on", job_id)
    return res, path


@router.get("/{job_id}/result.glb", response_class=Response,
            responses={**schemas.file_responses("model/gltf-binary"),
                       **schemas.errors(404, 409, 422, 503)},
            openapi_extra=schemas.FILE_HEADERS)
@router.head("/{job_id}/result.glb", include_in_schema=False)
def result_glb(job_id: schemas.JobId, request: Request,
               compress: int = Query(1, ge=0, le=1, description="0: the plain file"),
               config: Config = Depends(deps.config), storage=Depends(deps.storage),
               scope=Depends(deps.shop)):
    """The try-on as glTF: meshopt-compressed (EXT_meshopt_compression) for the web by
    default, the plain file with ``?compress=0``. Immutable: cache it forever."""
    name = "tryon.web.glb" if compress else "tryon.glb"
    res, path = _result_file(config, storage, job_id, name, scope)
    etag = f'"{res.web_sha256 if compress else res.glb_sha256}"'
    return file_response(request, path, "model/gltf-binary", etag,
                         filename=f"tryon-{job_id[:8]}.glb")


@router.get("/{job_id}/preview.png", response_class=Response,
            responses={**schemas.file_responses("image/png"),
                       **schemas.errors(404, 409, 503)},
            openapi_extra=schemas.FILE_HEADERS)
@router.head("/{job_id}/preview.png", include_in_schema=False)
def preview_png(job_id: schemas.JobId, request: Request, config: Config = Depends(deps.config),
                storage=Depends(deps.storage), scope=Depends(deps.shop)):
    """Four moments of the walk, front and side, rendered on the CPU."""
    res, path = _result_file(config, storage, job_id, "preview.png", scope)
    return file_response(request, path, "image/png", f'"{res.glb_sha256[:32]}-preview"')
