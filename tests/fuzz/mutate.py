"""Hypothesis strategies that damage valid files: each draws ``(bytes, description)``.

- :func:`binary`: byte flips, truncation, deletion, insertion, splicing (from the same or
  another seed), repetition, and "interesting" integers and floats written over the bytes
  (counts of 0, 2³¹, 2³², a billion; NaN, ±Inf, 3.4e38 in float32);
- :func:`text`: the above plus number tokens replaced (nan, inf, 1e308, 1e999, -1, a billion,
  4294967296, garbage), lines deleted, repeated, swapped or made up;
- :func:`json_doc`: a parsed document changed where it counts — a value replaced by a wrong
  type, a huge, tiny, negative, NaN or infinite number, an empty or very long string, a deep
  nesting (10,000 levels), a huge list; keys deleted or added; lists repeated or emptied;
  subtrees' numbers scaled (×10, ×10⁶, ×−1, ×0, ×1e308) — then written (NaN and Infinity as
  JSON's non-standard literals) and sometimes damaged as text;
- :func:`glb`: the GLB's JSON chunk changed as a JSON document (including claims such as a
  4 GB buffer or a billion-element accessor), the chunk lengths recomputed or left lying, or
  the bytes damaged;
- :func:`ply`, :func:`stl`, :func:`dxf`: headers that claim huge or negative counts; for
  :func:`dxf` also the slips real exports have in a boundary (a vertex written twice, two
  swapped, one moved a little: what the import repairs or refuses).
"""

from __future__ import annotations

import copy
import json
import math
import re
import struct

from hypothesis import strategies as st


class Case:
    """A damaged file and how it was damaged (its repr stays short in failure reports)."""

    def __init__(self, data: bytes, how: str):
        self.data, self.how = data, how

    def __repr__(self) -> str:
        return f"Case({len(self.data):,} bytes: {self.how})"


DEEP = "\x00DEEP\x00"   # replaced by a 10,000-deep nesting when the document is written
HUGE_LIST = "\x00HUGE\x00"   # replaced by a list of 200,000 numbers

INTERESTING = [
    0, -1, 1, 2, 3, 7, 255, 65535, 2**31 - 1, 2**31, 2**32, 2**32 + 1, 2**53, 10**9, 10**12,
    -(2**31), 10**30, 1e308, -1e308, math.nan, math.inf, -math.inf, 1e-320, 0.5, -0.0, 1e6,
    1e9, 1e-9, "", " ", "x", "heavy", "0", "1e308", "nan", "M", "\u00e9\u2603", None, True,
    False, [], {}, [0, 0], [[0, 0]], [0, 0, 0], [math.nan, 0.0], ["a", "b"], {"a": 1},
    "A" * 10_000, DEEP, HUGE_LIST,
]
INT_BYTES = [0, 1, 0x7FFFFFFF, 0x80000000, 0xFFFFFFFF, 1_000_000_000, 0xFFFF, 12, 2**24]
FLOAT32 = [math.nan, math.inf, -math.inf, 3.4e38, -3.4e38, 1e-45, 0.0, 1e20]
TOKENS = ["nan", "NaN", "inf", "-inf", "1e308", "-1e308", "1e999", "0", "-0", "-1",
          "1000000000", "4294967296", "99999999999999999999", "1e-320", "", "x", "1.5.5",
          "0x10", "+", "2147483648", "-2147483649"]
NUMBER = re.compile(rb"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def _pos(draw, n: int) -> int:
    return draw(st.integers(0, max(0, n)))


def _bytes_op(draw, data: bytearray, seeds: list[bytes]) -> str:
    op = draw(st.sampled_from(["flip", "truncate", "delete", "insert", "splice", "repeat",
                               "int", "float"]))
    n = len(data)
    if op == "flip":
        k = draw(st.integers(1, 16))
        # flips near the start hit headers: half of them in the first 4 KiB
        for _ in range(k):
            i = _pos(draw, min(n - 1, 4095) if draw(st.booleans()) else n - 1)
            if n:
                data[i] ^= draw(st.integers(1, 255))
        return f"flip {k} bytes"
    if op == "truncate":
        at = _pos(draw, n - 1)
        del data[at:]
        return f"truncate at {at}"
    if op == "delete":
        a = _pos(draw, n)
        b = min(n, a + draw(st.integers(1, 4096)))
        del data[a:b]
        return f"delete {a}:{b}"
    if op == "insert":
        a = _pos(draw, n)
        junk = draw(st.binary(min_size=1, max_size=64))
        data[a:a] = junk
        return f"insert {len(junk)} bytes at {a}"
    if op == "splice":
        src = seeds[draw(st.integers(0, len(seeds) - 1))]
        a = _pos(draw, len(src) - 1)
        b = min(len(src), a + draw(st.integers(1, 8192)))
        at = _pos(draw, n)
        data[at:at + (b - a) * draw(st.integers(0, 1))] = src[a:b]
        return f"splice {a}:{b} at {at}"
    if op == "repeat":
        a = _pos(draw, n - 1)
        b = min(n, a + draw(st.integers(1, 2048)))
        times = draw(st.integers(2, 50))
        data[a:b] = bytes(data[a:b]) * times
        return f"repeat {a}:{b} ×{times}"
    at = _pos(draw, max(0, n - 4))
    if draw(st.booleans()):
        at -= at % 4
    if op == "int":
        v = draw(st.sampled_from(INT_BYTES))
        data[at:at + 4] = struct.pack("<I", v)
        return f"u32 {v} at {at}"
    v = draw(st.sampled_from(FLOAT32))
    data[at:at + 4] = struct.pack("<f", v)
    return f"f32 {v} at {at}"


def _text_op(draw, data: bytearray, seeds: list[bytes]) -> str:
    op = draw(st.sampled_from(["number", "numbers", "line-delete", "line-repeat", "line-swap",
                               "line-insert", "bytes"]))
    if op in ("number", "numbers"):
        found = list(NUMBER.finditer(data[:2_000_000]))
        if not found:
            return "no numbers"
        k = 1 if op == "number" else draw(st.integers(2, 30))
        picks = sorted({draw(st.integers(0, len(found) - 1)) for _ in range(k)}, reverse=True)
        tok = draw(st.sampled_from(TOKENS))
        for i in picks:
            m = found[i]
            data[m.start():m.end()] = tok.encode()
        return f"{len(picks)} number(s) → {tok!r}"
    if op == "bytes":
        return _bytes_op(draw, data, seeds)
    lines = bytes(data).split(b"\n")
    i = _pos(draw, len(lines) - 1)
    if op == "line-delete":
        del lines[i:i + draw(st.integers(1, 20))]
    elif op == "line-repeat":
        lines[i:i + 1] = [lines[i]] * draw(st.integers(2, 1000))
    elif op == "line-swap":
        j = _pos(draw, len(lines) - 1)
        lines[i], lines[j] = lines[j], lines[i]
    else:
        lines.insert(i, draw(st.sampled_from([
            b"f 1 2 999999999", b"f 0 0 0", b"f -1 -2 -3", b"v nan nan nan", b"v 1e308 0 0",
            b"v inf 0 0", b"f 1/1/1 2/2/2", b"element vertex 1000000000", b"end_header",
            b"facet normal 0 0 0", b"endsolid", b"  0", b"SECTION", b"ENDSEC", b"EOF",
            b" 90\n1000000000", b" 10\n1e308", b" 42\n1e308", b" 70\n1", b"mtllib /dev/zero",
            b"o x", b"usemtl x", b"vt nan nan", b"vn 0 0 0", b"s 1", b"\x00\xff",
        ])))
    data[:] = b"\n".join(lines)
    return op


def _damage(draw, data: bytes, seeds: list[bytes], text: bool, at_most: int = 3
            ) -> tuple[bytes, list[str]]:
    buf = bytearray(data)
    done = []
    for _ in range(draw(st.integers(1, at_most))):
        done.append((_text_op if text else _bytes_op)(draw, buf, seeds))
    return bytes(buf), done


@st.composite
def binary(draw, seeds: list[bytes]):
    i = draw(st.integers(0, len(seeds) - 1))
    data, ops = _damage(draw, seeds[i], seeds, text=False)
    return Case(data, f"seed {i}: " + "; ".join(ops))


@st.composite
def text(draw, seeds: list[bytes]):
    i = draw(st.integers(0, len(seeds) - 1))
    data, ops = _damage(draw, seeds[i], seeds, text=True)
    return Case(data, f"seed {i}: " + "; ".join(ops))


# ------------------------------------------------------------------------------------- JSON

def _paths(node, path=()):
    yield path
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, (*path, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _paths(v, (*path, i))


def _get(doc, path):
    for k in path:
        doc = doc[k]
    return doc


def _scale(node, k):
    if isinstance(node, bool):
        return node
    if isinstance(node, (int, float)):
        try:
            return node * k
        except OverflowError:
            return math.inf
    if isinstance(node, list):
        return [_scale(v, k) for v in node]
    if isinstance(node, dict):
        return {key: _scale(v, k) for key, v in node.items()}
    return node


def _value(draw):
    """An interesting value, copied (the document may be changed further)."""
    return copy.deepcopy(draw(st.sampled_from(INTERESTING)))


def _json_op(draw, doc):
    """One change to the parsed document; returns (doc, description)."""
    paths = list(_paths(doc))
    path = paths[draw(st.integers(0, len(paths) - 1))]
    op = draw(st.sampled_from(["replace", "replace", "replace", "delete", "add", "repeat",
                               "empty", "scale", "retype"]))
    if not path:
        if op in ("replace", "retype"):
            return _value(draw), "document replaced"
        op = "scale" if op not in ("add", "scale") else op
    parent = _get(doc, path[:-1]) if path else None
    node = _get(doc, path)
    key = path[-1] if path else None
    where = "/".join(map(str, path))
    if op == "replace":
        v = _value(draw)
        parent[key] = v
        return doc, f"{where} = {v!r:.40}"
    if op == "retype":
        v = ({str(i): x for i, x in enumerate(node)} if isinstance(node, list) else
             list(node.values()) if isinstance(node, dict) else [node])
        parent[key] = v
        return doc, f"{where} retyped"
    if op == "delete":
        del parent[key]
        return doc, f"{where} deleted"
    if op == "add":
        target = node if isinstance(node, (dict, list)) else parent
        if target is None:
            return doc, "nothing to add to"
        v = _value(draw)
        if isinstance(target, dict):
            target[draw(st.sampled_from(["extra", "name", "type", "sizes", "panels", "x", ""]))] = v
        else:
            target.insert(_pos(draw, len(target)), v)
        return doc, f"{where}: added {v!r:.40}"
    if op == "repeat":
        if isinstance(node, list) and node:
            times = draw(st.sampled_from([2, 3, 100, 5000]))
            node[:] = (node * times)[:200_000]
            return doc, f"{where} repeated ×{times}"
        if parent is not None and isinstance(parent, list):
            parent[key:key + 1] = [node] * draw(st.integers(2, 50))
            return doc, f"{where} repeated in its list"
        return doc, "nothing to repeat"
    if op == "empty":
        if isinstance(node, (dict, list)):
            node.clear()
            return doc, f"{where} emptied"
        return doc, "nothing to empty"
    k = draw(st.sampled_from([10.0, 1e6, -1.0, 0.0, 1e308, 1e-9, 1000.0, 0.01]))
    if parent is None:
        return _scale(doc, k), f"all numbers ×{k}"
    parent[key] = _scale(node, k)
    return doc, f"{where} numbers ×{k}"


#: the largest document the markers are expanded into: a little over the readers' limit on a
#: JSON document (exchange/source.py) — beyond it every reader refuses alike, and a repeated
#: marker expanded every time (a list of 200,000 numbers repeated ×5,000: 4 GB) measured the
#: pipe to the worker, not the reader
MAX_DOC_BYTES = 72 * 2**20


def _expand(text: str, marker: str, expansion: str) -> str:
    """``marker`` replaced by ``expansion`` as often as keeps the text within
    :data:`MAX_DOC_BYTES` (at least once); the rest stay as they are."""
    parts = text.split(marker)
    room = max(1, (MAX_DOC_BYTES - len(text)) // max(1, len(expansion) - len(marker)))
    out = [parts[0]]
    for k, part in enumerate(parts[1:]):
        out.append(expansion if k < room else marker)
        out.append(part)
    return "".join(out)


def dump(doc) -> bytes:
    text = json.dumps(doc, allow_nan=True)
    text = _expand(text, json.dumps(DEEP), "[" * 10_000 + "]" * 10_000)
    text = _expand(text, json.dumps(HUGE_LIST), "[" + ",".join(["0.5"] * 200_000) + "]")
    return text.encode()


@st.composite
def json_doc(draw, seeds: list[bytes]):
    i = draw(st.integers(0, len(seeds) - 1))
    doc = json.loads(seeds[i])
    ops = []
    for _ in range(draw(st.integers(1, 3))):
        doc, d = _json_op(draw, doc)
        ops.append(d)
    data = dump(doc)
    if draw(st.integers(0, 4)) == 0:   # sometimes damaged as text too
        data, more = _damage(draw, data, seeds, text=True, at_most=1)
        ops += more
    return Case(data, f"seed {i}: " + "; ".join(ops))


# -------------------------------------------------------------------------------------- GLB

def split_glb(data: bytes) -> tuple[dict, bytes]:
    (jlen,) = struct.unpack("<I", data[12:16])
    doc = json.loads(data[20:20 + jlen])
    rest = data[20 + jlen:]
    blob = rest[8:] if len(rest) >= 8 else b""
    return doc, blob


def join_glb(doc: dict | bytes, blob: bytes, lie: int | None = None) -> bytes:
    j = doc if isinstance(doc, bytes) else dump(doc)
    j += b" " * (-len(j) % 4)
    blob += b"\0" * (-len(blob) % 4)
    total = 12 + 8 + len(j) + 8 + len(blob)
    out = (b"glTF" + struct.pack("<II", 2, total if lie is None else lie)
           + struct.pack("<I", len(j)) + b"JSON" + j
           + struct.pack("<I", len(blob)) + b"BIN\0" + blob)
    return out


CLAIMS = [
    ("buffers", 0, "byteLength", 2**32), ("buffers", 0, "byteLength", 2**62),
    ("bufferViews", 0, "byteLength", 2**32), ("bufferViews", 0, "byteOffset", 2**40),
    ("bufferViews", 0, "byteStride", 2**20), ("bufferViews", 0, "buffer", 7),
    ("accessors", 0, "count", 10**9), ("accessors", 0, "count", 2**62),
    ("accessors", 1, "count", 10**9), ("accessors", 0, "componentType", 5130),
    ("accessors", 0, "type", "MAT4"), ("accessors", 0, "byteOffset", 2**33),
    ("accessors", 0, "bufferView", 10**6), ("meshes", 0, "primitives", []),
    ("nodes", 0, "mesh", 10**6), ("skins", 0, "joints", [10**6]),
    ("accessors", 0, "count", -1), ("accessors", 0, "count", 0),
]


@st.composite
def glb(draw, seeds: list[bytes]):
    i = draw(st.integers(0, len(seeds) - 1))
    doc, blob = split_glb(seeds[i])
    how = draw(st.sampled_from(["json", "json", "claim", "bytes", "lie"]))
    if how == "bytes":
        data, ops = _damage(draw, seeds[i], seeds, text=False)
        return Case(data, f"seed {i}: " + "; ".join(ops))
    ops = []
    lie = None
    if how == "claim":
        for _ in range(draw(st.integers(1, 2))):
            table, k, key, v = draw(st.sampled_from(CLAIMS))
            items = doc.get(table) or []
            if isinstance(items, list) and items:
                k = min(k, len(items) - 1) if draw(st.booleans()) else \
                    draw(st.integers(0, len(items) - 1))
                if isinstance(items[k], dict):
                    items[k][key] = v
                    ops.append(f"{table}[{k}].{key} = {v}")
    elif how == "lie":
        lie = draw(st.sampled_from([0, 20, 2**32 - 1, len(seeds[i]) - 1, len(seeds[i]) + 8]))
        ops.append(f"total length claimed {lie}")
    else:
        for _ in range(draw(st.integers(1, 3))):
            doc, d = _json_op(draw, doc)
            ops.append(d)
    if draw(st.integers(0, 5)) == 0:
        blob = blob[: _pos(draw, len(blob))]
        ops.append(f"BIN chunk cut to {len(blob)}")
    return Case(join_glb(doc, blob, lie), f"seed {i}: " + "; ".join(ops))


# ----------------------------------------------------------------------- headers that lie

@st.composite
def ply(draw, seeds: list[bytes]):
    i = draw(st.integers(0, len(seeds) - 1))
    data = seeds[i]
    if draw(st.booleans()):
        end = data.find(b"end_header")
        head, rest = data[:end], data[end:]
        which = draw(st.sampled_from([b"vertex", b"face"]))
        n = draw(st.sampled_from([b"1000000000", b"4294967295", b"-1", b"0", b"1", b"x",
                                  b"99999999999999999999", b"2000001"]))
        head = re.sub(rb"element " + which + rb" \d+", b"element " + which + b" " + n, head)
        if draw(st.booleans()):
            head = head.replace(b"property float", draw(st.sampled_from(
                [b"property double", b"property uchar", b"property list uint float",
                 b"property bogus"])), 1)
        data, ops = head + rest, [f"element {which.decode()} {n.decode()}"]
        if draw(st.booleans()):
            data, more = _damage(draw, data, seeds, text=False, at_most=1)
            ops += more
        return Case(data, f"seed {i}: " + "; ".join(ops))
    data, ops = _damage(draw, data, seeds, text=data.find(b"format ascii") >= 0)
    return Case(data, f"seed {i}: " + "; ".join(ops))


@st.composite
def stl(draw, seeds: list[bytes]):
    i = draw(st.integers(0, len(seeds) - 1))
    data = bytearray(seeds[i])
    if draw(st.booleans()) and len(data) >= 84:
        n = draw(st.sampled_from([0, 1, 10**9, 2**32 - 1, 2_000_001, (len(data) - 84) // 50 + 1,
                                  (len(data) - 84) // 50 - 1]))
        data[80:84] = struct.pack("<I", n)
        if draw(st.booleans()):
            data[:5] = b"solid"
        ops = [f"{n} triangles claimed"]
        if draw(st.booleans()):
            data, more = _damage(draw, bytes(data), seeds, text=False, at_most=1)
            ops += more
        return Case(bytes(data), f"seed {i}: " + "; ".join(ops))
    data, ops = _damage(draw, bytes(data), seeds, text=False)
    return Case(data, f"seed {i}: " + "; ".join(ops))


def _vertex_spans(lines: list[bytes]) -> list[tuple[int, int]]:
    """[start, end) line ranges of the R12 POLYLINEs' VERTEX entities (group 0 to group 0)."""
    starts = [k for k in range(1, len(lines)) if lines[k].strip() == b"VERTEX"
              and lines[k - 1].strip() == b"0"]
    spans = []
    for k in starts:
        end = k + 1
        while end + 1 < len(lines) and not (lines[end].strip() == b"0" and end % 2 == (k - 1) % 2):
            end += 1
        spans.append((k - 1, end))
    return spans


def _slips(draw, data: bytes, i: int):
    """What real exports slip into a boundary (issue 46): a vertex written twice (exactly, or a
    hair's breadth off), two vertices swapped (the outline crosses itself), a vertex moved a
    little (a small loop, or none)."""
    lines = data.split(b"\n")
    spans = _vertex_spans(lines)
    if len(spans) < 2:
        return None
    op = draw(st.sampled_from(["repeat", "repeat-off", "swap", "nudge"]))
    a, b = sorted(draw(st.lists(st.integers(0, len(spans) - 1), min_size=2, max_size=2,
                                unique=True)))
    (a0, a1), (b0, b1) = spans[a], spans[b]
    if op == "swap" and b == a + 1:
        lines[a0:b1] = lines[b0:b1] + lines[a0:a1]
    elif op in ("repeat", "repeat-off", "nudge"):
        copy_ = list(lines[a0:a1])
        for k in range(len(copy_) - 1):
            if copy_[k].strip() == b"10" and op != "repeat":
                x = float(copy_[k + 1]) if NUMBER.fullmatch(copy_[k + 1].strip()) else 0.0
                step = draw(st.sampled_from([1e-6, 1e-4, 0.01, 0.5, 3.0])) if op == "nudge" \
                    else 1e-5
                copy_[k + 1] = repr(x + step).encode()
        lines[a0:a1] = copy_ if op == "nudge" else lines[a0:a1] + copy_
    else:
        return None
    return Case(b"\n".join(lines), f"seed {i}: vertex {a} {op}" + (f" with {b}" if op == "swap"
                                                                     else ""))


@st.composite
def dxf(draw, seeds: list[bytes]):
    i = draw(st.integers(0, len(seeds) - 1))
    data = seeds[i]
    if draw(st.integers(0, 3)) == 0:
        slipped = _slips(draw, data, i)
        if slipped is not None:
            return slipped
    if draw(st.integers(0, 3)) == 0:
        # claims: a polyline with a billion vertices, coordinates far away, units nobody uses
        lines = data.split(b"\n")
        claim = draw(st.sampled_from([
            (b" 90", b"1000000000"), (b" 90", b"-1"), (b" 10", b"1e308"), (b" 20", b"1e308"),
            (b" 10", b"nan"), (b" 42", b"1e308"), (b" 42", b"nan"), (b" 70", b"65535"),
            (b" 40", b"1e308"), (b" 50", b"nan"), (b" 51", b"1e308"),
        ]))
        hits = [k for k in range(0, len(lines) - 1) if lines[k].rstrip(b"\r") == claim[0]]
        if hits:
            for _ in range(draw(st.integers(1, 5))):
                k = hits[draw(st.integers(0, len(hits) - 1))]
                lines[k + 1] = claim[1]
            data = b"\n".join(lines)
            return Case(data, f"seed {i}: group {claim[0].strip().decode()} = "
                              f"{claim[1].decode()}")
    data, ops = _damage(draw, data, seeds, text=True)
    return Case(data, f"seed {i}: " + "; ".join(ops))
