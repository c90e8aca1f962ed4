"""Bodies: ``POST /api/bodies`` (a scan, or measurements), ``GET``, ``DELETE``; never listed.

A scan is multipart with a ``scan`` file part (OBJ, PLY, STL, GLB; units and up axis are
detected) and an optional ``sex`` field (inferred from the shape when missing); measurements
are JSON ``{"sex", "height", "bust", "waist", "hips"}`` in metres. On a shop (its publishable
key, ``api/embed.py``) a body is the shopper's there: made, read and deleted by them only.
"""

from __future__ import annotations

import asyncio
import json
import logging
import time

from fastapi import APIRouter, Depends, Request
from fastapi.responses import Response
from pydantic import ValidationError

from catwalk.config import Config
from catwalk.errors import InputError
from catwalk.exchange.scan import sniff_format
from catwalk.service import bodies
from catwalk.service.api import deps, schemas
from catwalk.service.api.errors import ApiError, UploadTooLarge, check_id, not_found, parse_json
from catwalk.service.api.files import file_response
from catwalk.service.body_maker import make_from_measurements, make_from_scan
from catwalk.service.jobs import lifecycle as jobs
from catwalk.service.store.models import BodyRow

router = APIRouter(prefix="/api/bodies", tags=["bodies"])
log = logging.getLogger("catwalk.api")

SCAN_TYPES = {".obj": "obj", ".ply": "ply", ".stl": "stl", ".glb": "glb"}

_BODY_REQUEST = {
    "requestBody": {"required": True, "content": {
        "application/json": {"schema": schemas.Measurements.model_json_schema()},
        "multipart/form-data": {"schema": {
            "type": "object", "required": ["scan"],
            "properties": {"scan": {"type": "string", "format": "binary",
                                    "description": "OBJ, PLY, STL or GLB; any units and "
                                                   "up axis"},
                           "sex": {"type": "string", "enum": ["female", "male"]}}}}}}}


def _get_row(config: Config, body_id: str, scope: bodies.Scope | None) -> BodyRow:
    check_id(body_id, "body", "body_id")
    row = bodies.get(config, body_id, scope)
    if row is None:
        raise not_found("body", body_id, "body_id")
    return row


async def _measurements(request: Request) -> schemas.Measurements:
    data = parse_json(await request.body())
    if not isinstance(data, dict):
        raise ApiError(422, "measurements are a JSON object {\"sex\", \"height\", \"bust\", "
                            "\"waist\", \"hips\"} in metres")
    try:
        return schemas.Measurements.model_validate(data)
    except ValidationError as exc:
        e = exc.errors()[0]
        field = ".".join(str(p) for p in e.get("loc", ())) or None
        raise ApiError(422, f"{field}: {e['msg']}" if field else e["msg"], field) from None


async def _scan(request: Request) -> tuple[bytes, str, str | None]:
    try:
        form = await request.form(max_files=1, max_fields=4)
    except UploadTooLarge:
        raise
    except Exception as exc:   # a broken multipart body
        raise ApiError(400, f"the multipart body cannot be read ({exc})") from None
    scan = form.get("scan")
    if scan is None or isinstance(scan, str):
        raise ApiError(422, "a scan is sent as a file part named 'scan' (OBJ, PLY, STL or GLB)",
                       "scan")
    sex = form.get("sex")
    if sex not in (None, "", "female", "male"):
        raise ApiError(422, f"sex must be female or male, not {sex!r}", "sex")
    data = await scan.read()
    if not data:
        raise ApiError(422, "the scan is empty", "scan")
    name = (scan.filename or "").lower()
    ext = "." + name.rsplit(".", 1)[-1] if "." in name else ""
    fmt = SCAN_TYPES.get(ext) if ext else sniff_format(data)
    if fmt is None:
        raise ApiError(415, f"the scan {'type ' + repr(ext) if ext else 'format'} is not one "
                            "catwalk reads: send OBJ, PLY, STL or GLB", "scan")
    return data, fmt, sex or None


@router.post("", status_code=201, response_model=schemas.Body, openapi_extra=_BODY_REQUEST,
             responses=schemas.errors(400, 413, 415, 422, 503),
             response_model_exclude_none=True)
async def create_body(request: Request, config: Config = Depends(deps.config),
                      storage=Depends(deps.storage), scope=Depends(deps.shop)) -> dict:
    """A body from a scan (multipart) or from measurements (JSON)."""
    ctype = request.headers.get("content-type", "").split(";")[0].strip().lower()
    body_id = jobs.new_id()
    out = storage.body_glb(body_id)
    maker = request.app.state.maker
    t0 = time.perf_counter()
    try:
        if ctype == "application/json":
            m = await _measurements(request)
            values = {k: getattr(m, k) for k in ("height", "bust", "waist", "hips")}
            made = await maker.run(make_from_measurements, str(out), m.sex, values,
                                   timeout=config.body_timeout_s)
            row = bodies.from_measurements(body_id, m.sex, values, made)
        elif ctype == "multipart/form-data":
            data, fmt, sex = await _scan(request)
            scan_path = await asyncio.to_thread(storage.write, storage.scan_path(body_id, fmt),
                                                data)
            made = await maker.run(make_from_scan, str(scan_path), str(out), sex,
                                   timeout=config.body_timeout_s)
            row = await asyncio.to_thread(bodies.from_scan, body_id, data, fmt, made)
        else:
            raise ApiError(415, "send measurements as application/json or a scan as "
                                "multipart/form-data (a file part named 'scan')")
        await asyncio.to_thread(bodies.add, config, row, scope)
    except InputError as exc:
        storage.remove_body(body_id)
        if ctype.startswith("multipart"):
            request.app.state.metrics.refused.labels("bad_scan").inc()
        raise ApiError(422, str(exc), exc.field or ("scan" if ctype.startswith("multipart")
                                                    else None)) from None
    except ApiError as exc:
        storage.remove_body(body_id)
        if ctype.startswith("multipart") and exc.status in (400, 415, 422):
            request.app.state.metrics.refused.labels(
                {400: "unreadable", 415: "unsupported_type", 422: "bad_scan"}[exc.status]).inc()
        raise
    except TimeoutError:
        storage.remove_body(body_id)
        raise ApiError(503, f"the body was not made within {config.body_timeout_s:g} s; try "
                            "again", code="busy") from None
    except BaseException:
        storage.remove_body(body_id)   # nothing of a body that was not made stays on disk
        raise
    # the body's id and how it went only: measurements and scans are never logged
    log.info(json.dumps({"event": "body_created", "body": body_id, "source": row.source,
                         "seconds": round(time.perf_counter() - t0, 2)}))
    return bodies.view(row)


@router.get("/{body_id}", response_model=schemas.Body, responses=schemas.errors(404, 503),
            response_model_exclude_none=True)
def get_body(body_id: schemas.BodyId, config: Config = Depends(deps.config),
             scope=Depends(deps.shop)) -> dict:
    return bodies.view(_get_row(config, body_id, scope))


@router.get("/{body_id}/body.glb", response_class=Response,
            responses={**schemas.file_responses("model/gltf-binary"),
                       **schemas.errors(404, 503)},
            openapi_extra=schemas.FILE_HEADERS)
@router.head("/{body_id}/body.glb", include_in_schema=False)
def body_glb(body_id: schemas.BodyId, request: Request, config: Config = Depends(deps.config),
             storage=Depends(deps.storage), scope=Depends(deps.shop)):
    """The rigged body (skinned mesh, skeleton, landmarks) as glTF."""
    _get_row(config, body_id, scope)
    path = storage.body_glb(body_id)
    if not path.is_file():
        raise not_found("body file", body_id, "body_id")
    st = path.stat()
    return file_response(request, path, "model/gltf-binary",
                         f'"{st.st_size:x}-{st.st_mtime_ns:x}"', "private, max-age=3600")


@router.delete("/{body_id}", status_code=204, response_class=Response,
               responses=schemas.errors(404, 503))
def delete_body(body_id: schemas.BodyId, config: Config = Depends(deps.config),
                storage=Depends(deps.storage), scope=Depends(deps.shop)) -> Response:
    """Delete the body, its scan, every try-on made from it and their results (those no
    other body shares). A running try-on of it stops."""
    _get_row(config, body_id, scope)
    bodies.delete(config, storage, body_id)
    return Response(status_code=204)
