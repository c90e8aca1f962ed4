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
MAX_RANGES = 100   # as Starlette's FileResponse: more ranges get the whole file (200)
# ASCII digits only (``\d`` takes any script's), at most 18: no file is 10¹⁸ bytes, and Python
# (so Starlette, which answers a plain-text 400) refuses to read more than 4,300 digits
_RANGE = re.compile(r"^[ \t]*([0-9]{0,18})[ \t]*-[ \t]*([0-9]{0,18})[ \t]*$")


class WholeFile(FileResponse):
    """Starlette's ``FileResponse`` reading 1 MiB at a time, not 64 KiB: each read is a hop to
    the thread pool, and a try-on's web copy (0.3–2 MB) was 5–30 of them."""

    chunk_size = 1 << 20


def not_modified(request: Request, etag: str) -> bool:
    tags = request.headers.get("if-none-match")
    return bool(tags) and (tags.strip() == "*" or etag in [t.strip().removeprefix("W/")
                                                            for t in tags.split(",")])


def check_range(header: str | None, size: int) -> None:
    """Refuse a ``Range`` header that is not ``bytes=…`` ranges (400) or one of whose ranges
    no byte of the file satisfies (416, as Starlette would, but in the API's JSON)."""
    if header is None:
        return
    shown = repr(header[:100] + ("…" if len(header) > 100 else ""))
    unit, _, spec = header.partition("=")
    if unit.strip().lower() != "bytes" or not spec.strip():
        raise ApiError(400, f"Range {shown}: only byte ranges (bytes=start-end) are served",
                       "Range", code="bad_range")
    parts = spec.split(",")
    if len(parts) > MAX_RANGES:
        return
    for part in parts:
        m = _RANGE.match(part)
        if m is None or (not m.group(1) and not m.group(2)):
            raise ApiError(400, f"Range {shown}: {part.strip()[:40]!r} is not start-end "
                                f"(at most 18 digits each)",
                           "Range", code="bad_range")
        start, end = m.group(1), m.group(2)
        if start and end and int(end) < int(start):
            raise ApiError(400, f"Range {shown}: {part.strip()[:40]!r} ends before it starts",
                           "Range", code="bad_range")
        if (start and int(start) >= size) or (not start and int(end) == 0):
            raise ApiError(416, f"Range {shown}: the file has {size:,} bytes", "Range",
                           code="bad_range", headers={"Content-Range": f"bytes */{size}"})


def file_response(request: Request, path: Path, media_type: str, etag: str,
                  cache_control: str = IMMUTABLE, filename: str | None = None) -> Response:
    headers = {"ETag": etag, "Cache-Control": cache_control}
    if not_modified(request, etag):
        return Response(status_code=304, headers=headers)
    try:
        st = path.stat()
    except FileNotFoundError:   # deleted since it was looked up (its body, say)
        raise ApiError(404, "the file is no longer there") from None
    check_range(request.headers.get("range"), st.st_size)
    return WholeFile(path, media_type=media_type, headers=headers, filename=filename,
                     content_disposition_type="inline", stat_result=st)
