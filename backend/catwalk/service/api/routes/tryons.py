"""Try-ons: ``POST /api/tryons`` → 202 (queued) or 200 (already made: ``"cached": true``);
``GET`` its status, ``/events`` (server-sent events until it ends), ``DELETE`` (cancel);
``/result.glb`` (meshopt for the web unless ``?compress=0``) and ``/preview.png``."""

from __future__ import annotations

import asyncio
import json
import logging

from fastapi import APIRouter, Depends, Query, Request
from fastapi.responses import JSONResponse, Response
from sqlalchemy.exc import IntegrityError
from sse_starlette.sse import EventSourceResponse

from catwalk.cloth.fabrics import resolve_fabric
from catwalk.config import Config
from catwalk.errors import InputError
from catwalk.service import keys
from catwalk.service.api import deps, schemas
from catwalk.service.api.errors import ApiError, check_id, not_found
from catwalk.service.api.files import file_response
from catwalk.service.jobs import lifecycle as jobs
from catwalk.service.jobs.app import send
from catwalk.service.store import db
from catwalk.service.store.models import FINISHED, BodyRow, ResultRow, TryOnRow, utcnow

router = APIRouter(prefix="/api/tryons", tags=["tryons"])
log = logging.getLogger("catwalk.api")
EVENT_POLL_S = 0.25


def _with_metrics(s, row: TryOnRow) -> dict:
    """The try-on's JSON; a done one with its result's metrics (read in session ``s``)."""
    out = jobs.view(row)
    if row.status == "done" and (res := s.get(ResultRow, row.key)) is not None:
        out["metrics"] = res.metrics
    return out


def _view(config: Config, row: TryOnRow) -> dict:
    with db.session(config) as s:
        return _with_metrics(s, row)


def _view_of(config: Config, job_id: str) -> dict:
    """The try-on's JSON, read in one transaction (the status route's whole work)."""
    check_id(job_id, "try-on")
    with db.session(config) as s:
        row = s.get(TryOnRow, job_id)
        if row is None:
            raise not_found("try-on", job_id)
        return _with_metrics(s, row)


def _job(config: Config, job_id: str) -> TryOnRow:
    check_id(job_id, "try-on")
    row = jobs.get(config, job_id)
    if row is None:
        raise not_found("try-on", job_id)
    return row


def _submit(config: Config, catalogue, storage, req: schemas.TryOnRequest
            ) -> tuple[TryOnRow, bool, dict]:
    """The try-on row for ``req``: a new queued one, this body's running one with the same
    key, or a done one answered from the cache. (row, needs sending, its JSON)."""
    check_id(req.body_id, "body", "body_id")
    try:
        entry = catalogue.get(req.garment_id)
    except InputError:
        entry = None
    with db.session(config) as s:   # the body and its running try-on read at once
        body = s.get(BodyRow, req.body_id)
        if body is None:
            raise not_found("body", req.body_id, "body_id")
        if entry is None:
            raise not_found("garment", req.garment_id, "garment_id")
        g = entry.garment
        if req.size is not None and req.size not in g.sizes:
            raise ApiError(422, f"garment {req.garment_id!r} has no size {req.size!r} (sizes: "
                                f"{', '.join(g.sizes)})", "size")
        size = g.size(req.size)
        fabric = None if req.fabric in (None, entry.fabric) else req.fabric
        if fabric is not None:
            if fabric not in entry.fabrics:
                raise ApiError(422, f"unknown fabric {fabric!r} (choose from "
                                    f"{', '.join(entry.fabrics)})", "fabric")
            resolve_fabric(fabric, "fabric")
        key = keys.tryon_key(body.content_key, entry.id, entry.version, size, fabric,
                             req.seconds, req.preset)
        running = jobs.active_in(s, body.id, key)
        if running is not None:
            return running, False, jobs.view(running)
    # the result, if there is one, cannot be deleted (its last body going) while this try-on
    # is added as answered from it: its row is locked until the new row is in. Two requests
    # at once for the same try-on: the unique index on active (body, key) lets one row in;
    # the other gets that row.
    try:
        return _add(config, storage, body, entry, req, size, fabric, key)
    except IntegrityError:
        running = jobs.active_for(config, body.id, key)
        if running is None:
            raise
        return running, False, jobs.view(running)


def _add(config, storage, body, entry, req, size, fabric, key) -> tuple[TryOnRow, bool, dict]:
    stored = storage.result_file(key, "tryon.glb").is_file()
    with jobs.results_lock(config), db.session(config) as s:
        # shared while the files are there (answers from the cache do not wait for each
        # other); exclusive when the row is to go
        result = jobs.lock_result(s, key, shared=stored)
        if result is not None and not storage.result_file(key, "tryon.glb").is_file():
            s.delete(result)   # its files are gone (storage lost or wiped): make it again
            result = None
        cached = result is not None
        now = utcnow()
        row = TryOnRow(id=jobs.new_id(), key=key, body_id=body.id, garment_id=entry.id,
                       garment_version=entry.version, size=size, fabric=fabric,
                       seconds=req.seconds, preset=req.preset, cancel_requested=False,
                       attempts=0, cached=cached, created_at=now, enqueued_at=now,
                       status="done" if cached else "queued", progress=1.0 if cached else 0.0,
                       stage="done" if cached else "queued",
                       finished_at=now if cached else None)
        s.add(row)
        view = jobs.view(row)
        if cached:
            view["metrics"] = result.metrics
    return row, not cached, view


@router.post("", status_code=202, response_model=schemas.TryOn,
             responses={200: {"model": schemas.TryOn,
                              "description": "already made: answered from the cache"},
                        **schemas.errors(400, 404, 413, 415, 422, 503)})
async def create_tryon(req: schemas.TryOnRequest, request: Request,
                       config: Config = Depends(deps.config),
                       catalogue=Depends(deps.catalogue), storage=Depends(deps.storage),
                       _json=Depends(deps.json_body)):
    """Ask for a try-on of a body in a catalogue garment."""
    row, needs_sending, view = await asyncio.to_thread(_submit, config, catalogue, storage,
                                                       req)
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
def get_tryon(job_id: schemas.JobId, config: Config = Depends(deps.config)) -> dict:
    return _view_of(config, job_id)


@router.get("/{job_id}/events", response_class=Response,
            responses={200: {"description": "`event: progress` on every change, then one "
                                            "`event: done|failed|cancelled`",
                             "content": {"text/event-stream": {"schema": schemas.TRYON_EVENT}}},
                       **schemas.errors(404, 503)})
async def tryon_events(job_id: schemas.JobId, request: Request,
                       config: Config = Depends(deps.config)):
    """The try-on's status as server-sent events (``event: progress`` on every change, then
    one ``event: done|failed|cancelled``), until it ends."""
    row = await asyncio.to_thread(_job, config, job_id)

    async def stream():
        last = last_view = None
        current = row
        while True:
            view = await asyncio.to_thread(_view, config, current) if current else None
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
def cancel_tryon(job_id: schemas.JobId, config: Config = Depends(deps.config)):
    """Cancel the try-on: at once if queued, within half a second if running."""
    row = _job(config, job_id)
    if row.status in FINISHED:
        raise ApiError(409, f"the try-on has already ended ({row.status})", code="finished")
    row = jobs.cancel(config, job_id)
    return JSONResponse(jobs.view(row), status_code=202)


def _result_file(config: Config, storage, job_id: str, name: str):
    row = _job(config, job_id)
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
               config: Config = Depends(deps.config), storage=Depends(deps.storage)):
    """The try-on as glTF: meshopt-compressed (EXT_meshopt_compression) for the web by
    default, the plain file with ``?compress=0``. Immutable: cache it forever."""
    name = "tryon.web.glb" if compress else "tryon.glb"
    res, path = _result_file(config, storage, job_id, name)
    etag = f'"{res.web_sha256 if compress else res.glb_sha256}"'
    return file_response(request, path, "model/gltf-binary", etag,
                         filename=f"tryon-{job_id[:8]}.glb")


@router.get("/{job_id}/preview.png", response_class=Response,
            responses={**schemas.file_responses("image/png"),
                       **schemas.errors(404, 409, 503)},
            openapi_extra=schemas.FILE_HEADERS)
@router.head("/{job_id}/preview.png", include_in_schema=False)
def preview_png(job_id: schemas.JobId, request: Request, config: Config = Depends(deps.config),
                storage=Depends(deps.storage)):
    """Four moments of the walk, front and side, rendered on the CPU."""
    res, path = _result_file(config, storage, job_id, "preview.png")
    return file_response(request, path, "image/png", f'"{res.glb_sha256[:32]}-preview"')
