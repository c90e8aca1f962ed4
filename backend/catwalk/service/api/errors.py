"""Every error the API answers is JSON: ``{"error": {"code", "message", "field"?}}``.

Bad input is a 4xx naming what is wrong and where (400 unreadable, 404 unknown id, 409 not
possible in the current state, 413 too large, 415 wrong content type, 422 invalid); nothing
the client sends produces a 500 or a traceback.
"""

from __future__ import annotations

import json
import logging
import re
import traceback

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from sqlalchemy.exc import DBAPIError, InterfaceError, OperationalError
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.routing import Match

from catwalk.errors import InputError, NotFound
from catwalk.exchange import source

log = logging.getLogger("catwalk.api")

CODES = {400: "bad_request", 401: "unauthorized", 404: "not_found", 405: "method_not_allowed",
         409: "conflict", 413: "too_large", 414: "uri_too_long", 415: "unsupported_media_type",
         416: "bad_range", 422: "invalid", 503: "unavailable"}


class UploadTooLarge(Exception):
    """The request body passed the upload limit while it was being read (answered 413 by
    :class:`catwalk.service.api.app.LimitUploads`)."""


class ApiError(Exception):
    def __init__(self, status: int, message: str, field: str | None = None,
                 code: str | None = None, headers: dict | None = None):
        super().__init__(message)
        self.status, self.message, self.field = status, message, field
        self.code = code or CODES.get(status, "error")
        self.headers = headers


def not_found(what: str, ident: str, field: str | None = None) -> ApiError:
    return ApiError(404, str(NotFound(what, ident)), field)


_ID = re.compile(r"[A-Za-z0-9_-]{8,64}")


def check_id(ident: str, what: str, field: str | None = None) -> str:
    """A body's or try-on's id as the service makes them (URL-safe, 8–64 characters), or 404
    before any query (a NUL byte or 10 kB of junk never reaches the database)."""
    if not isinstance(ident, str) or not _ID.fullmatch(ident):
        raise not_found(what, str(ident), field)
    return ident


def parse_json(raw: bytes):
    """A request body's JSON, or 400 naming what is wrong: not JSON, or nested too deeply
    (:func:`catwalk.exchange.source.parse_json`: the readers' own limits)."""
    try:
        return source.parse_json(raw or b"null", "the request body")
    except InputError as exc:
        raise ApiError(400, str(exc)) from None


def internal_error(request_path: str) -> JSONResponse:
    """The 500 for an exception nothing else answered, its trace logged (the request's body and
    headers never are)."""
    log.error(json.dumps({"event": "internal_error", "path": request_path,
                          "trace": traceback.format_exc()[-4000:]}))
    return _json(500, error_body(500, "internal error; it has been logged", code="internal"))


class ServerErrors:
    """An exception no handler answered becomes the JSON 500 here, inside the app, and the
    connection stays open: Starlette's own last-resort handler answers too but raises the
    exception on to the server, which then drops the keep-alive connection without saying so
    (the client's next request on it is reset)."""

    def __init__(self, app):
        self.app = app

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        started = False

        async def watched(msg):
            nonlocal started
            if msg["type"] == "http.response.start":
                started = True
            await send(msg)

        try:
            await self.app(scope, receive, watched)
        except Exception:
            if started:   # half a response is out: only the server can end it
                raise
            await internal_error(scope.get("path", ""))(scope, receive, send)


def error_body(status: int, message: str, field: str | None = None,
               code: str | None = None, **extra) -> dict:
    err = {"code": code or CODES.get(status, "error"), "message": message}
    if field:
        err["field"] = field
    err.update(extra)
    return {"error": err}


def _json(status: int, body: dict, headers: dict | None = None) -> JSONResponse:
    return JSONResponse(body, status_code=status, headers=headers)


def _printable(text: str, limit: int) -> str:
    """``text`` cut to ``limit`` characters, control characters escaped (for a message)."""
    cut = text[:limit] + ("…" if len(text) > limit else "")
    return "".join(c if c.isprintable() else ascii(c)[1:-1] for c in cut)


def _path(request: Request) -> str:
    return _printable(request.url.path, 200)


METHODS = ("GET", "HEAD", "POST", "PUT", "PATCH", "DELETE")


def allowed_methods(request: Request) -> list[str]:
    """Every method some route answers on this request's path (Starlette names only the first
    route's in a 405's ``Allow``: ``GET`` where ``DELETE`` is allowed too). Each method is
    tried against the routes (FastAPI nests included routers), the pages' GET fallback
    left out."""
    allowed = []
    for method in METHODS:
        scope = {**request.scope, "method": method}
        for route in request.app.router.routes:
            match, child = route.matches(scope)
            path = getattr(child.get("route", route), "path", None)
            if match is Match.FULL and path != "/{path:path}":
                allowed.append(method)
                break
    return allowed


def _field(loc) -> str | None:
    parts = [str(p) for p in loc if p not in ("body", "query", "path", "header")]
    return ".".join(parts) or None


def install(app: FastAPI) -> None:
    @app.exception_handler(ApiError)
    async def _api_error(request: Request, exc: ApiError):
        return _json(exc.status, error_body(exc.status, exc.message, exc.field, exc.code),
                     exc.headers)

    @app.exception_handler(InputError)
    async def _input_error(request: Request, exc: InputError):
        status = 404 if isinstance(exc, NotFound) else 422
        return _json(status, error_body(status, str(exc), exc.field))

    @app.exception_handler(RequestValidationError)
    async def _invalid(request: Request, exc: RequestValidationError):
        errs = exc.errors()
        details = [{"field": _field(e.get("loc", ())), "message": e.get("msg", "invalid")}
                   for e in errs]
        first = details[0] if details else {"field": None, "message": "invalid request"}
        if any(e.get("type") == "json_invalid" for e in errs):
            return _json(400, error_body(400, "the request body is not valid JSON"))
        msg = f"{first['field']}: {first['message']}" if first["field"] else first["message"]
        return _json(422, error_body(422, msg, first["field"], details=details))

    @app.exception_handler(StarletteHTTPException)
    async def _http(request: Request, exc: StarletteHTTPException):
        msg = exc.detail if isinstance(exc.detail, str) else "request refused"
        headers = getattr(exc, "headers", None)
        status = exc.status_code
        allow = allowed_methods(request) if status == 405 else []
        if status == 405 and not allow:   # only the pages' GET fallback matched the path
            status, msg = 404, "Not Found"
        if status == 404 and msg == "Not Found":
            msg = f"no such route: {request.method} {_path(request)}"
        elif status == 405:
            headers = {**(headers or {}), "Allow": ", ".join(allow)}
            msg = (f"{_printable(request.method, 20)} is not allowed on {_path(request)}; "
                   f"allowed: {', '.join(allow)}")
        return _json(status, error_body(status, msg), headers)

    @app.exception_handler(DBAPIError)
    async def _database_away(request: Request, exc: DBAPIError):
        # the database cannot be reached (a restart, the network): nothing was changed; the
        # client may try again (pool_pre_ping gives the next request a fresh connection)
        if not exc.connection_invalidated and not isinstance(exc, (OperationalError,
                                                                   InterfaceError)):
            return await _unexpected(request, exc)
        log.warning(json.dumps({"event": "database_unreachable", "path": request.url.path,
                                "error": type(exc.orig).__name__ if exc.orig else "?"}))
        return _json(503, error_body(503, "the database cannot be reached; try again in a few "
                                          "seconds", code="unavailable"),
                     {"Retry-After": "5"})

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception):
        return internal_error(request.url.path)
