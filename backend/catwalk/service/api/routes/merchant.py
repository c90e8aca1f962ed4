"""Merchants' garments (``Authorization: Bearer KEY``; ``catwalk merchant create`` makes keys).

``POST /api/merchant/garments`` (multipart: ``garment`` + texture ``files``, or ``dxf`` +
``markup``) → 201, checked like ``catwalk garment check`` (every problem in one 422);
``GET`` the merchant's own garments, ``GET/PUT/DELETE /{id}`` (a PUT is a new version),
``POST /{id}/publish``; each version's dressing check per size, its dressed .glb and files;
``POST /api/merchant/import``: a DXF read into garment JSON for the editor (nothing stored).
Another merchant's garment is answered 404, exactly like one that does not exist.
``GET /me`` also shows the publishable key (``pk_…``, for the shop's pages) and the origins
allowed for it, ``PUT /origins`` replaces those; a publishable key never opens these routes.
"""

from __future__ import annotations

import asyncio
import json
import mimetypes

from fastapi import APIRouter, Depends, Request
from fastapi.responses import JSONResponse, Response
from pydantic import ValidationError

from catwalk.config import Config
from catwalk.errors import InputError
from catwalk.exchange.dxf import pieces_to_garment, read_dxf
from catwalk.exchange.garment_json import garment_to_dict
from catwalk.service import merchant_garments as mg
from catwalk.service import merchants
from catwalk.service.api import deps, schemas
from catwalk.service.api.errors import ApiError, UploadTooLarge, error_body, parse_json
from catwalk.service.api.files import file_response
from catwalk.service.jobs.app import send_check

router = APIRouter(prefix="/api/merchant", tags=["merchant"])

_AUTH = {"WWW-Authenticate": 'Bearer realm="catwalk merchants"'}
_FILE = {"type": "string", "format": "binary"}
_UPLOAD = {"requestBody": {"required": True, "content": {"multipart/form-data": {"schema": {
    "type": "object",
    "properties": {
        "garment": {**_FILE, "description": "the garment JSON (docs/garment-format.md)"},
        "dxf": {**_FILE, "description": "an AAMA/ASTM or plain DXF cutting pattern"},
        "markup": {**_FILE, "description": "the DXF's markup JSON: seams, panel types, "
                                           "placement, fabric, sizes"},
        "units": {"type": "string", "enum": ["in", "mm", "cm", "m"],
                  "description": "the DXF's units when it does not say"},
        "files": {"type": "array", "items": _FILE,
                  "description": "texture images; each part's file name is the path the "
                                 "garment names"}}}}}}}
_IMPORT = {"requestBody": {"required": True, "content": {"multipart/form-data": {"schema": {
    "type": "object", "required": ["dxf"],
    "properties": {"dxf": _UPLOAD["requestBody"]["content"]["multipart/form-data"]["schema"]
                   ["properties"]["dxf"],
                   "units": {"type": "string", "enum": ["in", "mm", "cm", "m"]}}}}}}}


async def merchant(request: Request, config: Config = Depends(deps.config)):
    """The merchant the request's ``Authorization: Bearer KEY`` names; 401 otherwise."""
    auth = request.headers.get("authorization", "")
    scheme, _, key = auth.partition(" ")
    if not auth:
        raise ApiError(401, "send the merchant's API key: Authorization: Bearer KEY",
                       headers=_AUTH)
    if scheme.lower() != "bearer" or not key.strip():
        raise ApiError(401, "the Authorization header is 'Bearer KEY'", headers=_AUTH)
    if key.strip().startswith(merchants.PUBLISHABLE_PREFIX):
        raise ApiError(401, "a publishable key (pk_…) opens only the shoppers' routes, from "
                            "the shop's pages; the merchant's routes take its secret API key "
                            "(cwk_…)", headers=_AUTH)
    row = await asyncio.to_thread(merchants.authenticate, config, key.strip())
    if row is None:
        raise ApiError(401, "the API key is not valid (unknown or revoked)", headers=_AUTH)
    return row


def _not_found(garment_id: str) -> ApiError:
    return ApiError(404, f"you have no garment with id {garment_id[:80]!r}", "garment_id")


async def _own(fn, *args):
    """``fn(*args)`` in a thread; a garment that is not the merchant's is a 404."""
    try:
        return await asyncio.to_thread(fn, *args)
    except LookupError as exc:
        raise _not_found(str(exc.args[0]) if exc.args else "?") from None


async def _form(request: Request, max_files: int):
    ctype = request.headers.get("content-type", "").split(";")[0].strip().lower()
    if ctype != "multipart/form-data":
        raise ApiError(415, f"send the garment as multipart/form-data, not {ctype or 'nothing'}")
    try:
        return await request.form(max_files=max_files, max_fields=16)
    except UploadTooLarge:
        raise
    except Exception as exc:   # a broken multipart body, too many parts
        raise ApiError(400, f"the multipart body cannot be read ({exc})") from None


async def _part(form, name: str) -> bytes | None:
    """A part's bytes: a file part's content, or a plain field's text."""
    value = form.get(name)
    if value is None:
        return None
    if isinstance(value, str):
        return value.encode()
    return await value.read()


async def _upload(request: Request) -> mg.Upload:
    form = await _form(request, mg.MAX_FILES + 3)
    files: dict[str, bytes] = {}
    for part in form.getlist("files"):
        if isinstance(part, str):
            raise ApiError(422, "each of `files` is a file part whose file name is the path "
                                "the garment names", "files")
        name = part.filename or ""
        if name in files:
            raise ApiError(422, f"two `files` parts are named {name[:80]!r}", "files")
        files[name] = await part.read()
    units = form.get("units")
    if units is not None and not isinstance(units, str):
        raise ApiError(422, "units is a field (in, mm, cm, m)", "units")
    return mg.Upload(garment=await _part(form, "garment"), dxf=await _part(form, "dxf"),
                     markup=await _part(form, "markup"), units=units or None, files=files)


def _validated(model, body, shape: str, field: str):
    """``body`` (parsed JSON) read as ``model``; 422 naming the field at fault, or ``shape``
    when it is not a JSON object."""
    if not isinstance(body, dict):
        raise ApiError(422, shape, field)
    try:
        return model.model_validate(body)
    except ValidationError as exc:
        e = exc.errors()[0]
        at = ".".join(str(p) for p in e.get("loc", ())) or None
        raise ApiError(422, f"{at}: {e['msg']}" if at else e["msg"], at) from None


def _rejected(exc: mg.UploadRejected) -> JSONResponse:
    return JSONResponse(error_body(422, str(exc), code="invalid_garment",
                                   problems=exc.problems), status_code=422)


def _save(config: Config, storage, catalogue, who, upload: mg.Upload,
          garment_id: str | None) -> dict:
    """Check and store the upload as a new garment or the next version; queue its check."""
    previous = None if garment_id is None else \
        mg.latest_folder(config, storage, who.id, garment_id)
    prepared = mg.prepare(storage, upload, previous)
    out = mg.store(config, storage, who.id, prepared, garment_id,
                   taken=set(catalogue.entries()))
    send_check(config, out["id"], out["version"])
    return out


@router.get("/me", response_model=schemas.Merchant, responses=schemas.errors(401))
async def me(who=Depends(merchant)) -> dict:
    """The merchant the key belongs to, its publishable key and the origins allowed for it."""
    return _me(who)


def _me(who, origins: list[str] | None = None) -> dict:
    return {"name": who.name, "created_at": who.created_at.isoformat() + "Z",
            "publishable_key": who.publishable_key,
            "origins": list(who.origins or []) if origins is None else origins}


@router.put("/origins", response_model=schemas.Merchant, responses=schemas.errors(400, 401, 422))
async def set_origins(request: Request, config: Config = Depends(deps.config),
                      who=Depends(merchant)) -> dict:
    """Replace the origins the shop's pages may use the publishable key from
    (``{"origins": ["https://shop.example"]}``)."""
    asked = _validated(schemas.Origins, parse_json(await request.body()),
                       'the body is {"origins": ["https://shop.example", …]}', "origins").origins
    origins = await asyncio.to_thread(merchants.set_origins, config, who.id, asked)
    return _me(who, origins)


@router.post("/garments", status_code=201, response_model=schemas.GarmentVersionCreated,
             openapi_extra=_UPLOAD,
             responses=schemas.errors(400, 401, 413, 415, 422, 503))
async def create_garment(request: Request, config: Config = Depends(deps.config),
                         storage=Depends(deps.storage), catalogue=Depends(deps.catalogue),
                         who=Depends(merchant)):
    """Upload a garment: checked, stored as version 1 (a draft), its dressing check queued."""
    upload = await _upload(request)
    try:
        out = await asyncio.to_thread(_save, config, storage, catalogue, who, upload, None)
    except mg.UploadRejected as exc:
        return _rejected(exc)
    return JSONResponse(out, status_code=201)


@router.get("/garments", response_model=schemas.MerchantGarments,
            responses=schemas.errors(401))
async def list_garments(config: Config = Depends(deps.config), who=Depends(merchant)) -> dict:
    """The merchant's own garments, drafts included, with every version and its dressing."""
    return {"garments": await asyncio.to_thread(mg.own_garments, config, who.id)}


@router.get("/garments/{garment_id}", response_model=schemas.MerchantGarmentDetail,
            responses=schemas.errors(401, 404))
async def get_garment(garment_id: str, config: Config = Depends(deps.config),
                      storage=Depends(deps.storage), who=Depends(merchant)) -> dict:
    """One of the merchant's garments, with its latest version's garment JSON."""
    item = await _own(mg.own_garment, config, who.id, garment_id)
    path = storage.merchant_garment_dir(garment_id, item["version"]) / "garment.json"
    item["garment"] = json.loads(await asyncio.to_thread(path.read_bytes))
    return item


@router.put("/garments/{garment_id}", response_model=schemas.GarmentVersionCreated,
            openapi_extra=_UPLOAD,
            responses=schemas.errors(400, 401, 404, 409, 413, 415, 422, 503))
async def update_garment(garment_id: str, request: Request,
                         config: Config = Depends(deps.config), storage=Depends(deps.storage),
                         catalogue=Depends(deps.catalogue), who=Depends(merchant)):
    """A new version of the garment (textures not sent again are kept from the latest). The
    published version stays in the catalogue until the new one is published."""
    upload = await _upload(request)
    try:
        return await _own(_save, config, storage, catalogue, who, upload, garment_id)
    except mg.UploadRejected as exc:
        return _rejected(exc)
    except mg.Conflict as exc:
        raise ApiError(409, str(exc), "version") from None


@router.delete("/garments/{garment_id}", status_code=204, response_class=Response,
               responses=schemas.errors(401, 404))
async def delete_garment(garment_id: str, config: Config = Depends(deps.config),
                         catalogue=Depends(deps.catalogue), who=Depends(merchant)):
    """Take the garment out of the catalogue and the list (try-ons made with it keep their
    results)."""
    await _own(mg.delete, config, who.id, garment_id)
    await asyncio.to_thread(catalogue.entries, recheck=True)
    return Response(status_code=204)


@router.post("/garments/{garment_id}/publish", response_model=schemas.MerchantGarment,
             responses=schemas.errors(400, 401, 404, 422))
async def publish_garment(garment_id: str, request: Request,
                          config: Config = Depends(deps.config),
                          catalogue=Depends(deps.catalogue), who=Depends(merchant)) -> dict:
    """Put a version (``{"version": n}``; default the latest) in the public catalogue."""
    raw = await request.body()
    version = None
    if raw.strip():
        version = _validated(schemas.PublishRequest, parse_json(raw),
                             "the body is {\"version\": n} or empty", "version").version
    out = await _own(mg.publish, config, who.id, garment_id, version)
    await asyncio.to_thread(catalogue.entries, recheck=True)
    return out


def _version_path(config, storage, who, garment_id: str, version: int, *parts: str):
    if any(not p.isprintable() for p in parts):   # a NUL or control character names no file
        raise LookupError(garment_id)
    folder = mg.version_folder(config, storage, who.id, garment_id, version)
    path = folder.joinpath(*parts).resolve()
    if not path.is_relative_to(folder.resolve()) or not path.is_file():
        raise LookupError(garment_id)
    return path


@router.get("/garments/{garment_id}/versions/{version}/dressed/{size}.glb",
            response_class=Response,
            responses={**schemas.file_responses("model/gltf-binary"),
                       **schemas.errors(401, 404)})
async def dressed(garment_id: str, version: schemas.Version, size: str, request: Request,
                  config: Config = Depends(deps.config), storage=Depends(deps.storage),
                  who=Depends(merchant)):
    """The size dressed on its sample body by the version's check (404 until it is made)."""
    try:
        path = await asyncio.to_thread(_version_path, config, storage, who, garment_id, version,
                                       "dressed", f"{size}.glb")
    except LookupError:
        raise ApiError(404, f"no dressed size {size[:40]!r} of version {version} of garment "
                            f"{garment_id[:80]!r} (not yours, not checked yet, or it did not "
                            "dress)") from None
    return file_response(request, path, "model/gltf-binary", f'"{garment_id}-{version}-{size}"',
                         "private, max-age=3600")


@router.get("/garments/{garment_id}/versions/{version}/files/{name:path}",
            response_class=Response, responses={**schemas.file_responses("image/png"),
                                                **schemas.errors(401, 404)})
async def version_file(garment_id: str, version: schemas.Version, name: str, request: Request,
                       config: Config = Depends(deps.config), storage=Depends(deps.storage),
                       who=Depends(merchant)):
    """A file of the version: ``garment.json`` or a texture it names."""
    try:
        path = await asyncio.to_thread(_version_path, config, storage, who, garment_id, version,
                                       name)
    except LookupError:
        raise ApiError(404, f"no file {name[:80]!r} in version {version} of garment "
                            f"{garment_id[:80]!r}") from None
    kind = mimetypes.guess_type(path.name)[0] or "application/octet-stream"
    return file_response(request, path, kind, f'"{garment_id}-{version}-{path.name}"',
                         "private, max-age=3600")


def _import(upload: mg.Upload) -> dict:
    pieces, warnings = read_dxf(upload.dxf, units=upload.units)
    g = pieces_to_garment(pieces, "garment", source={"importer": "catwalk merchant editor"})
    return {"garment": garment_to_dict(g), "pieces": [p.summary() for p in pieces],
            "warnings": mg.panel_names(warnings, g)}


@router.post("/import", response_model=schemas.DxfImport, openapi_extra=_IMPORT,
             responses=schemas.errors(400, 401, 413, 415, 422))
async def import_dxf(request: Request, who=Depends(merchant)) -> dict:
    """A DXF cutting pattern read into a garment JSON without seams (for the editor; nothing
    is stored)."""
    upload = await _upload(request)
    if upload.dxf is None:
        raise ApiError(422, "send the pattern as a file part named 'dxf'", "dxf")
    try:
        return await asyncio.to_thread(_import, upload)
    except InputError as exc:
        raise ApiError(422, str(exc), "dxf") from None
