"""What readers accept: a path, bytes, or a binary file object.

:func:`read_source` returns the bytes and a name to use in messages (the path, the file
object's ``name``, or the caller's ``what``), so every reader takes all three the same way and
names the input in its errors.
"""

from __future__ import annotations

import io
import json
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


MAX_JSON_BYTES = 64 << 20   # a JSON document catwalk reads (garments, markup, patterns)
MAX_JSON_DEPTH = 64         # nesting: catwalk's documents need about ten levels


def parse_json(data: bytes, name: str):
    """The JSON document in ``data`` (UTF-8), nested at most :data:`MAX_JSON_DEPTH` deep;
    anything else raises :class:`InputError` naming ``name``."""
    try:
        doc = json.loads(data.decode("utf-8"))
    except RecursionError:
        raise InputError(f"{name}: not readable JSON (nested too deeply; at most "
                         f"{MAX_JSON_DEPTH} levels are read)") from None
    except (UnicodeDecodeError, ValueError) as exc:
        raise InputError(f"{name}: not readable JSON ({exc})") from None
    check_depth(doc, name)
    return doc


def check_depth(doc, name: str, limit: int = MAX_JSON_DEPTH) -> None:
    """Refuse a parsed JSON document nested more than ``limit`` levels deep (its readers and
    writers recurse)."""
    todo = [(doc, 1)]
    while todo:
        node, depth = todo.pop()
        if isinstance(node, dict):
            children = node.values()
        elif isinstance(node, (list, tuple)):
            children = node
        else:
            continue
        if depth > limit:
            raise InputError(f"{name}: nested too deeply ({depth} levels or more; at most "
                             f"{limit} are read)")
        todo.extend((c, depth + 1) for c in children if isinstance(c, (dict, list, tuple)))


def read_json(source, what: str = "input", *, max_bytes: int | None = MAX_JSON_BYTES):
    """``(parsed, name)`` of a JSON document given as a path, bytes or a file object."""
    data, name = read_source(source, what, max_bytes=max_bytes)
    return parse_json(data, name), name
