"""The FastAPI app: ``create_app(config)``; served by ``catwalk serve`` (uvicorn).

At start it brings the database schema up to date, starts the recovery loop (jobs whose worker
died run again; jobs the broker lost are sent again), warms the body pool and starts the
catalogue's missing thumbnails. Uploads larger than ``CATWALK_UPLOAD_MAX_BYTES`` are refused
with 413 as soon as their size is known (the header, or the bytes counted so far): never read
whole. Requests from merchants' shop pages (a publishable key) are checked by
:class:`~catwalk.service.api.embed.Shops`; the component those pages load is served at
``/embed/`` (:func:`_serve_embed`).
"""

from __future__ import annotations

import contextlib
import gc
import json
import logging
import time
from pathlib import Path

from fastapi import FastAPI, Request
from fastapi.responses import FileResponse

from catwalk.config import Config, get_config
from catwalk.service.api import errors
from catwalk.service.api.embed import Shops
from catwalk.service.api.errors import ApiError, UploadTooLarge
from catwalk.service.api.routes import bodies, garments, health, merchant, tryons
from catwalk.service.body_maker import BodyMaker
from catwalk.service.catalogue import Catalogue
from catwalk.service.jobs.recovery import Recovery
from catwalk.service.metrics import Metrics
from catwalk.service.store import db
from catwalk.service.store.files import Storage
from catwalk.service.thumbnails import Thumbnails

log = logging.getLogger("catwalk.api")


class LimitUploads:
    """ASGI middleware: a request body over ``limit`` bytes gets 413 without being read whole
    (refused on its Content-Length, or as soon as the bytes received pass the limit)."""

    def __init__(self, app, limit: int, refused=None):
        self.app, self.limit, self.refused = app, limit, refused

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http" or scope["method"] not in ("POST", "PUT", "PATCH"):
            return await self.app(scope, receive, send)
        headers = dict(scope.get("headers") or [])
        length = headers.get(b"content-length")
        if length is not None and length.isdigit() and int(length) > self.limit:
            return await self._refuse(send, int(length))
        seen = 0
        over = False

        async def counted():
            nonlocal seen, over
            msg = await receive()
            if msg["type"] == "http.request":
                seen += len(msg.get("body", b""))
                if seen > self.limit:
                    over = True
                    raise UploadTooLarge()
            return msg

        async def watched(msg):
            if not over:   # once over the limit the app's own answer (say, a 400 for a
                await send(msg)   # body it could not parse) is replaced by the 413

        try:
            await self.app(scope, counted, watched)
        except UploadTooLarge:
            pass
        if over:
            await self._refuse(send, None)

    async def _refuse(self, send, length):
        if self.refused is not None:
            self.refused.labels("too_large").inc()
        told = f" ({length:,} bytes)" if length else ""
        body = json.dumps(errors.error_body(
            413, f"the upload{told} is over the limit of {self.limit:,} bytes"),
            separators=(",", ":")).encode()
        await send({"type": "http.response.start", "status": 413,
                    "headers": [(b"content-type", b"application/json"),
                                (b"content-length", str(len(body)).encode()),
                                (b"connection", b"close")]})
        await send({"type": "http.response.body", "body": body})


#: the longest path and query string the API reads (a longer one is answered 414, as JSON);
#: a request line beyond the HTTP parser's own limit (httptools: about 64 KiB) is refused by
#: the server before the app, as plain text (docs/api.md)
MAX_PATH = 4096
MAX_QUERY = 16384


class LimitRequestLine:
    """A path longer than :data:`MAX_PATH` characters or a query string longer than
    :data:`MAX_QUERY` bytes is answered 414 in the API's JSON shape, before any route."""

    def __init__(self, app):
        self.app = app

    async def __call__(self, scope, receive, send):
        if scope["type"] == "http":
            path, query = scope.get("path", ""), scope.get("query_string", b"")
            what = ("path", len(path), MAX_PATH) if len(path) > MAX_PATH else \
                ("query string", len(query), MAX_QUERY) if len(query) > MAX_QUERY else None
            if what is not None:
                name, size, limit = what
                body = errors.error_body(414, f"the {name} is {size:,} long; at most "
                                              f"{limit:,}", code="uri_too_long")
                return await errors.JSONResponse(body, status_code=414)(scope, receive, send)
        return await self.app(scope, receive, send)


class TimeRequests:
    """ASGI middleware: each request's seconds into ``histogram`` by route template (``/api/
    tryons/{job_id}``, not the id: no personal data, few series), method and status."""

    def __init__(self, app, histogram):
        self.app, self.histogram = app, histogram

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)

        t0 = time.perf_counter()
        code = [500]

        async def watched(msg):
            if msg["type"] == "http.response.start":
                code[0] = msg["status"]
            await send(msg)

        try:
            await self.app(scope, receive, watched)
        finally:
            route = scope.get("route")
            path = getattr(route, "path", None) or "unmatched"
            if path == "/{path:path}":
                path = "pages"
            self.histogram.labels(path, scope["method"], str(code[0])).observe(
                time.perf_counter() - t0)


# paths that are the API's, never a page: an unknown one is the API's JSON 404
_NOT_PAGES = ("api/", "healthz", "readyz", "metrics", "docs", "redoc", "openapi.json", "embed/")


def _serve_embed(app: FastAPI, root: Path) -> None:
    """The shops' component (``frontend/dist/embed``: ``/embed/v1/catwalk.js`` and its chunks)
    for any page to load: public code, so ``Access-Control-Allow-Origin: *`` (a module script
    from another origin is fetched with CORS) and no credentials. The entry is cached 5
    minutes (a new release reaches the shops soon); its hashed chunks forever."""
    root = root.resolve()

    @app.get("/embed/{path:path}", include_in_schema=False)
    async def embed(path: str):
        target = (root / path).resolve()
        if not (path and target.is_file() and target.is_relative_to(root)):
            raise ApiError(404, f"no such file: /embed/{path[:200]}")
        hashed = "/chunks/" in f"/{path}"
        return FileResponse(target, headers={
            "Cache-Control": "public, max-age=31536000, immutable" if hashed
            else "public, max-age=300",
            "Access-Control-Allow-Origin": "*", "Cross-Origin-Resource-Policy": "cross-origin",
            "X-Content-Type-Options": "nosniff"})


def _serve_pages(app: FastAPI, root: Path) -> None:
    """The built pages at ``/``: a file of ``root`` if the path names one, else ``index.html``
    (the pages route on the path themselves: /garments/{id}, /body, /tryon/{id}, /compare).
    Hashed assets are immutable; index.html is revalidated."""
    root = root.resolve()

    @app.get("/{path:path}", include_in_schema=False)
    async def page(path: str, request: Request):
        if path.startswith(_NOT_PAGES):
            allow = errors.allowed_methods(request)
            if allow:   # an API route answers this path, to another method
                raise ApiError(405, f"GET is not allowed on /{path[:200]}; allowed: "
                                    f"{', '.join(allow)}", headers={"Allow": ", ".join(allow)})
            raise ApiError(404, f"no such route: {request.method} /{path}")
        target = (root / path).resolve()
        if path and target.is_file() and target.is_relative_to(root):
            cache = ("public, max-age=31536000, immutable" if path.startswith("assets/")
                     else "no-cache")
            return FileResponse(target, headers={"Cache-Control": cache})
        return FileResponse(root / "index.html", headers={"Cache-Control": "no-cache"})


# OpenAPI links (what a client, or a stateful fuzzer, does next with an answer): source
# (method, path, status) → link name → (target method, path, parameters, request body)
_BODY = {"body_id": "$response.body#/id"}
_JOB = {"job_id": "$response.body#/id"}
_TRYON_LINKS = {
    "GetTryOn": ("get", "/api/tryons/{job_id}", _JOB, None),
    "TryOnEvents": ("get", "/api/tryons/{job_id}/events", _JOB, None),
    "CancelTryOn": ("delete", "/api/tryons/{job_id}", _JOB, None),
    "TryOnResult": ("get", "/api/tryons/{job_id}/result.glb", _JOB, None),
    "TryOnPreview": ("get", "/api/tryons/{job_id}/preview.png", _JOB, None),
}
_GARMENT = {"garment_id": "$response.body#/garments/0/id"}
LINKS = {
    ("post", "/api/bodies", "201"): {
        "GetBody": ("get", "/api/bodies/{body_id}", _BODY, None),
        "GetBodyGlb": ("get", "/api/bodies/{body_id}/body.glb", _BODY, None),
        "DeleteBody": ("delete", "/api/bodies/{body_id}", _BODY, None),
        "SizeAdvice": ("get", "/api/garments/{garment_id}/sizes",
                       {"query.body_id": "$response.body#/id"}, None),
        "TryOn": ("post", "/api/tryons", {}, _BODY),
    },
    ("post", "/api/tryons", "202"): _TRYON_LINKS,
    ("post", "/api/tryons", "200"): _TRYON_LINKS,
    ("get", "/api/garments", "200"): {
        "GetGarment": ("get", "/api/garments/{garment_id}", _GARMENT, None),
        "Thumbnail": ("get", "/api/garments/{garment_id}/thumbnail.png", _GARMENT, None),
        "Pattern": ("get", "/api/garments/{garment_id}/pattern.png", _GARMENT, None),
        "Dressed": ("get", "/api/garments/{garment_id}/dressed.glb", _GARMENT, None),
    },
    ("get", "/api/garments/{garment_id}", "200"): {
        "PatternOfASize": ("get", "/api/garments/{garment_id}/pattern.png",
                           {"garment_id": "$response.body#/id",
                            "query.size": "$response.body#/sizes/0"}, None),
        "TryItOn": ("post", "/api/tryons", {}, {"garment_id": "$response.body#/id"}),
    },
}


def _document(app: FastAPI) -> None:
    """The OpenAPI document FastAPI makes, and: the links above; a refused request's 422 as
    the API's JSON error (FastAPI names its own ``{"detail"}`` shape, never answered here)."""
    generate = app.openapi

    def openapi() -> dict:
        if app.openapi_schema is not None:
            return app.openapi_schema
        spec = generate()
        paths = spec.get("paths", {})
        for (method, path, status), links in LINKS.items():
            response = paths[path][method]["responses"][status]
            response["links"] = {}
            for name, (t_method, t_path, params, body) in links.items():
                link = {"operationId": paths[t_path][t_method]["operationId"]}
                if params:
                    link["parameters"] = params
                if body:
                    link["requestBody"] = body
                response["links"][name] = link
        refused = "#/components/schemas/HTTPValidationError"
        for ops in paths.values():
            for op in ops.values():
                r422 = op.get("responses", {}).get("422")
                content = (r422 or {}).get("content", {}).get("application/json", {})
                if content.get("schema", {}).get("$ref") == refused:
                    content["schema"] = {"$ref": "#/components/schemas/Error"}
                    r422["description"] = "a parameter FastAPI could not read (`invalid`)"
        schemas = spec.get("components", {}).get("schemas", {})
        if refused not in json.dumps(paths):
            schemas.pop("HTTPValidationError", None)
            schemas.pop("ValidationError", None)
        return spec

    app.openapi = openapi


def create_app(config: Config | None = None, *, recovery: bool = True,
               frontend: Path | None = None) -> FastAPI:
    """The API. ``recovery``: run the recovery loop in this process; ``frontend``: the built
    pages (a folder with index.html), served at ``/`` when it exists."""
    config = config or get_config()

    @contextlib.asynccontextmanager
    async def lifespan(app: FastAPI):
        db.migrate(config)
        app.state.storage.ensure()
        swept = app.state.storage.sweep()   # what a process killed mid-write left
        if swept:
            log.info(json.dumps({"event": "swept", "leftovers": swept}))
        loop_thread = None
        if recovery:
            loop_thread = Recovery(config)
            loop_thread.start()
        app.state.maker.warm()
        with contextlib.suppress(Exception):
            for entry in app.state.catalogue.entries().values():
                app.state.thumbnails.ensure(entry)
        # what start-up made (modules, the catalogue, numba's types) lives as long as the
        # process: out of the collector's sight, so that a full collection does not walk it
        # while requests wait (gc.freeze, as CPython's documentation advises for servers)
        gc.freeze()
        log.info(json.dumps({"event": "api_ready", "embedded": config.embedded}))
        yield
        if loop_thread is not None:
            loop_thread.stop.set()
        app.state.maker.close()

    app = FastAPI(
        title="catwalk", version=__import__("catwalk").__version__, lifespan=lifespan,
        description="A shopper's body walks a catwalk in a simulated garment. Bodies (from a "
                    "scan or measurements), the garment catalogue, try-on jobs with progress "
                    "as server-sent events, and their results as glTF.")
    app.state.config = config
    app.state.storage = Storage(config.storage_dir)
    app.state.catalogue = Catalogue(config)
    app.state.maker = BodyMaker(1)
    app.state.thumbnails = Thumbnails(app.state.storage, app.state.maker)
    app.state.metrics = Metrics(config)
    errors.install(app)
    for r in (health.router, garments.router, bodies.router, tryons.router, merchant.router):
        app.include_router(r)
    _document(app)
    if frontend is not None and (frontend / "embed").is_dir():
        _serve_embed(app, frontend / "embed")
    if frontend is not None and (frontend / "index.html").is_file():
        _serve_pages(app, frontend)
    app.add_middleware(errors.ServerErrors)   # innermost: a 500 keeps the connection
    app.add_middleware(LimitUploads, limit=config.upload_max_bytes,
                       refused=app.state.metrics.refused)
    app.add_middleware(LimitRequestLine)
    app.add_middleware(Shops, config=config, refused=app.state.metrics.shops_refused)
    app.add_middleware(TimeRequests, histogram=app.state.metrics.requests)
    return app
