"""Files answered by the API: ``ETag`` with ``If-None-Match`` → 304, ``Range`` → 206 (one or
several ranges, by Starlette's ``FileResponse``), and a malformed or unsatisfiable range as
the API's JSON error (400 / 416) instead of a plain-text one."""

from __future__ import annotations

import re
from pathlib import Path

from fastapi import Request
from fastapi.responses import FileResponse, Response

from catwalk.service.api.errors import ApiError

# results carry a person's body: browsers may keep them, shared caches may not
IMMUTABLE = "private, max-age=31536000, immutable"
PUBLIC_IMMUTABLE = "public, max-age=31536000, immutable"
_RANGE = re.compile(r"^\s*(\d*)\s*-\s*(\d*)\s*$")


def not_modified(request: Request, etag: str) -> bool:
    tags = request.headers.get("if-none-match")
    return bool(tags) and (tags.strip() == "*" or etag in [t.strip().removeprefix("W/")
                                                            for t in tags.split(",")])


def check_range(header: str | None, size: int) -> None:
    """Refuse a ``Range`` header that is not ``bytes=…`` ranges (400) or one of whose ranges
    no byte of the file satisfies (416, as Starlette would, but in the API's JSON)."""
    if header is None:
        return
    unit, _, spec = header.partition("=")
    if unit.strip().lower() != "bytes" or not spec.strip():
        raise ApiError(400, f"Range {header!r}: only byte ranges (bytes=start-end) are served",
                       "Range", code="bad_range")
    for part in spec.split(","):
        m = _RANGE.match(part)
        if m is None or (not m.group(1) and not m.group(2)):
            raise ApiError(400, f"Range {header!r}: {part.strip()!r} is not start-end",
                           "Range", code="bad_range")
        start, end = m.group(1), m.group(2)
        if start and end and int(end) < int(start):
            raise ApiError(400, f"Range {header!r}: {part.strip()!r} ends before it starts",
                           "Range", code="bad_range")
        if (start and int(start) >= size) or (not start and int(end) == 0):
            raise ApiError(416, f"Range {header!r}: the file has {size:,} bytes", "Range",
                       code="bad_range", headers={"Content-Range": f"bytes */{size}"})


def file_response(request: Request, path: Path, media_type: str, etag: str,
                  cache_control: str = IMMUTABLE, filename: str | None = None) -> Response:
    headers = {"ETag": etag, "Cache-Control": cache_control}
    if not_modified(request, etag):
        return Response(status_code=304, headers=headers)
    check_range(request.headers.get("range"), path.stat().st_size)
    return FileResponse(path, media_type=media_type, headers=headers, filename=filename,
                        content_disposition_type="inline")
