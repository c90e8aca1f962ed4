"""What readers accept: a path, bytes, or a binary file object.

:func:`read_source` returns the bytes and a name to use in messages (the path, the file
object's ``name``, or the caller's ``what``), so every reader takes all three the same way and
names the input in its errors.
"""

from __future__ import annotations

import io
import os
from pathlib import Path

from catwalk.errors import InputError

Source = str | os.PathLike | bytes | bytearray | memoryview | io.IOBase


def source_name(source, what: str) -> str:
    """How messages name ``source``: its path, a file object's name, or ``what``."""
    if isinstance(source, (str, os.PathLike)):
        return str(source)
    name = getattr(source, "name", None)
    return str(name) if isinstance(name, str) and name else what


def source_suffix(source, name: str | None = None) -> str:
    """The lower-case file extension of ``name`` or of the source's path ('' if none)."""
    return Path(name or source_name(source, "")).suffix.lower()


def read_source(source, what: str = "input", *, max_bytes: int | None = None) -> tuple[bytes, str]:
    """``(data, name)`` of a path, a bytes-like object or a binary file object. A missing
    path, an unreadable file or more than ``max_bytes`` raise :class:`InputError` naming it."""
    name = source_name(source, what)
    if isinstance(source, (bytes, bytearray, memoryview)):
        data = bytes(source)
    elif isinstance(source, (str, os.PathLike)):
        path = Path(source)
        if not path.is_file():
            raise InputError(f"{path}: no such file")
        if max_bytes is not None and path.stat().st_size > max_bytes:
            raise InputError(f"{path}: {path.stat().st_size:,} bytes; at most {max_bytes:,} "
                             "are accepted")
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise InputError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    elif hasattr(source, "read"):
        try:
            data = source.read() if max_bytes is None else source.read(max_bytes + 1)
        except OSError as exc:
            raise InputError(f"{name}: cannot be read ({exc})") from None
        if isinstance(data, str):
            data = data.encode()
        if not isinstance(data, (bytes, bytearray)):
            raise InputError(f"{name}: not a binary file object")
        data = bytes(data)
    else:
        raise InputError(f"{what}: expected a path, bytes or a file object, "
                         f"got {type(source).__name__}")
    if max_bytes is not None and len(data) > max_bytes:
        raise InputError(f"{name}: more than {max_bytes:,} bytes; at most {max_bytes:,} are "
                         "accepted")
    return data, name


def read_json(source, what: str = "input", *, max_bytes: int | None = None):
    """``(parsed, name)`` of a JSON document given as a path, bytes or a file object."""
    import json

    data, name = read_source(source, what, max_bytes=max_bytes)
    try:
        return json.loads(data.decode("utf-8")), name
    except (UnicodeDecodeError, ValueError) as exc:
        raise InputError(f"{name}: not readable JSON ({exc})") from None
