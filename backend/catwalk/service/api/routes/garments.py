"""The catalogue: ``GET /api/garments``, ``/api/garments/{id}``, its thumbnail and pattern.
On a shop (its publishable key) a garment is one of that merchant's published garments."""

from __future__ import annotations

import asyncio
import functools

from fastapi import APIRouter, Depends, Query, Request
from fastapi.responses import Response

from catwalk.catalogue.bodies import load_recipes
from catwalk.errors import InputError
from catwalk.render.pattern import pattern_png
from catwalk.service import bodies
from catwalk.service.api import deps, schemas
from catwalk.service.api.errors import ApiError, check_id, not_found
from catwalk.service.api.files import PUBLIC_IMMUTABLE, file_response, not_modified
from catwalk.service.sizes import advise

router = APIRouter(prefix="/api/garments", tags=["garments"])


def _entry(catalogue, garment_id: str, scope=None):
    try:
        return catalogue.get(garment_id, merchant_id=scope.merchant_id if scope else None)
    except InputError:
        raise not_found("garment", garment_id, "garment_id") from None


@router.get("", response_model=schemas.Garments, responses=schemas.errors(422))
async def list_garments(type: str | None = Query(None, description="only garments of this type"),
                        catalogue=Depends(deps.catalogue)) -> dict:
    """Every garment in the catalogue."""
    items = catalogue.listing()
    if type:
        items = [g for g in items if g["type"] == type]
    return {"garments": items}


@router.get("/{garment_id}", response_model=schemas.GarmentDetail,
            responses=schemas.errors(404, 422))
async def get_garment(garment_id: schemas.GarmentId, catalogue=Depends(deps.catalogue),
                      scope=Depends(deps.shop)) -> dict:
    return _entry(catalogue, garment_id, scope).detail()


@router.get("/{garment_id}/thumbnail.png", response_class=Response,
            responses={**schemas.file_responses("image/png"), **schemas.errors(404, 422)},
            openapi_extra=schemas.FILE_HEADERS)
@router.head("/{garment_id}/thumbnail.png", include_in_schema=False)
async def thumbnail(garment_id: schemas.GarmentId, request: Request,
                    catalogue=Depends(deps.catalogue), scope=Depends(deps.shop)):
    """The garment dressed on a sample body (front view). Until it has been rendered, the
    flat cutting pattern (not cached)."""
    entry = _entry(catalogue, garment_id, scope)
    thumbs = request.app.state.thumbnails
    path = thumbs.path(entry)
    if not path.is_file():
        task = thumbs.ensure(entry)
        if task is not None:
            await asyncio.wait({task}, timeout=2.0)
    if path.is_file():
        return file_response(request, path, "image/png", f'"{path.stem}"', PUBLIC_IMMUTABLE)
    png = await asyncio.to_thread(_pattern, entry, None)
    return Response(png, media_type="image/png", headers={"Cache-Control": "no-store"})


@router.get("/{garment_id}/dressed.glb", response_class=Response,
            responses={**schemas.file_responses("model/gltf-binary"),
                       **schemas.errors(404, 422, 503)},
            openapi_extra=schemas.FILE_HEADERS)
@router.head("/{garment_id}/dressed.glb", include_in_schema=False)
async def dressed(garment_id: schemas.GarmentId, request: Request,
                  catalogue=Depends(deps.catalogue), scope=Depends(deps.shop)):
    """The garment in its default size dressed on that size's sample body, standing: a
    meshopt-compressed try-on file of one frame (made with the thumbnail)."""
    entry = _entry(catalogue, garment_id, scope)
    thumbs = request.app.state.thumbnails
    path = thumbs.path(entry).with_suffix(".glb")
    if not path.is_file():
        task = thumbs.ensure(entry)
        if task is not None:
            await asyncio.wait({task}, timeout=30.0)
    if not path.is_file():
        raise ApiError(503, "the dressed garment is still being made; try again in a few "
                            "seconds", code="not_ready", headers={"Retry-After": "5"})
    return file_response(request, path, "model/gltf-binary", f'"{path.stem}"',
                         PUBLIC_IMMUTABLE)


def _pattern(entry, size):
    return pattern_png(entry.garment, size)


@router.get("/{garment_id}/pattern.png", response_class=Response,
            responses={**schemas.file_responses("image/png", ranges=False),
                       **schemas.errors(404, 422)},
            openapi_extra=schemas.CONDITIONAL_HEADERS)
@router.head("/{garment_id}/pattern.png", include_in_schema=False)
async def pattern(garment_id: schemas.GarmentId, request: Request, size: str | None = None,
                  catalogue=Depends(deps.catalogue), scope=Depends(deps.shop)):
    """The garment's cutting pattern in one size, drawn flat."""
    entry = _entry(catalogue, garment_id, scope)
    if size is not None and size not in entry.garment.sizes:
        raise ApiError(422, f"garment {garment_id!r} has no size {size!r} (sizes: "
                            f"{', '.join(entry.garment.sizes)})", "size")
    etag = f'"{entry.version}-{size or "default"}"'
    headers = {"Cache-Control": "public, max-age=3600", "ETag": etag}
    if not_modified(request, etag):
        return Response(status_code=304, headers=headers)
    png = await asyncio.to_thread(_pattern, entry, size)
    return Response(png, media_type="image/png", headers=headers)


def _recipes(path) -> list[dict]:
    """The sample bodies' recipes, read once per change of the file (not per request)."""
    st = path.stat()
    return _recipes_of(path, st.st_mtime_ns, st.st_size)


@functools.lru_cache(maxsize=4)
def _recipes_of(path, _mtime_ns: int, _size: int) -> list[dict]:
    return load_recipes(path)


@router.get("/{garment_id}/sizes", response_model=schemas.SizeAdvice,
            responses=schemas.errors(404, 422, 503))
def sizes(garment_id: schemas.GarmentId, body_id: schemas.BodyIdQuery,
          config=Depends(deps.config), catalogue=Depends(deps.catalogue),
          scope=Depends(deps.shop)) -> dict:
    """Size advice: each size's chart (the sample body it was made for) against the body's
    girths, the ease (chart − body, metres), whether it fits, and the size recommended."""
    entry = _entry(catalogue, garment_id, scope)
    check_id(body_id, "body", "body_id")
    body = bodies.get(config, body_id, scope)
    if body is None:
        raise not_found("body", body_id, "body_id")
    girths = {k: v for k, v in (body.measurements or {}).items() if not k.startswith("_")}
    out = advise(entry.garment, girths, _recipes(config.bodies_dir / "recipes.json"))
    return {"garment_id": entry.id, "body_id": body_id, **out}
