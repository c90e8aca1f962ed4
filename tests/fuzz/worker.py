"""The fuzzers' reader process: runs one reader on one input at a time, in its own process.

Started by :class:`fuzz.harness.Worker` as ``python worker.py``; reads requests from stdin and
answers on stdout, each a length-prefixed pickle. A request is ``(reader, data, extra)``; the
answer is a dict: ``outcome`` (``ok``: the reader succeeded and its result is sane,
``input_error``: it raised :class:`catwalk.errors.InputError`, ``bug``: anything else — another
exception, an insane result, a printed warning, a memory error or a jump of more than
``MAX_RSS_GROWTH`` in peak memory), ``message`` and ``seconds``.

The process limits its address space to ``ADDRESS_SPACE`` so a huge allocation fails here
(``MemoryError``, reported as a bug) instead of taking the machine down; the harness kills
and restarts it when a reader runs past its time limit.
"""

from __future__ import annotations

import io
import json
import math
import os
import pickle
import resource
import struct
import sys
import time
import traceback
import warnings

ADDRESS_SPACE = 6 << 30          # bytes of virtual memory the process may map
MAX_RSS_GROWTH = 1 << 30         # one input may raise the peak resident set by at most this

HUMAN = (1.0, 2.3)   # metres


class Insane(Exception):
    """A reader returned without an error but its result is not usable."""


def _require(cond, what: str) -> None:
    if not cond:
        raise Insane(what)


def _finite(a, what: str) -> None:
    import numpy as np

    a = np.asarray(a)
    _require(a.dtype.kind in "fiu", f"{what}: not numeric ({a.dtype})")
    _require(bool(np.all(np.isfinite(a))), f"{what}: not finite")


def _json_clean(obj, what: str) -> None:
    """The object serialises as strict JSON (no NaN / Infinity) and reads back."""
    try:
        text = json.dumps(obj, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise Insane(f"{what}: not writable as JSON ({exc})") from None
    json.loads(text)


# ---------------------------------------------------------------------------------- readers

def _mesh_sane(v, f, what: str) -> None:
    import numpy as np

    v = np.asarray(v)
    f = np.asarray(f)
    _require(v.ndim == 2 and v.shape[1] == 3 and len(v) > 0, f"{what}: vertices {v.shape}")
    _require(f.ndim == 2 and f.shape[1] == 3 and len(f) > 0, f"{what}: faces {f.shape}")
    _finite(v, f"{what}: vertices")
    _require(f.dtype.kind in "iu", f"{what}: faces not integers")
    _require(int(f.min()) >= 0 and int(f.max()) < len(v), f"{what}: face index out of range")


def read_scan(data: bytes, extra: dict):
    from catwalk.exchange.scan import load_scan

    s = load_scan(data, format=extra["format"], name=f"fuzz.{extra['format']}")
    _mesh_sane(s.vertices, s.faces, "scan")
    _require(HUMAN[0] - 1e-6 <= s.height <= HUMAN[1] + 1e-6, f"scan height {s.height}")
    _require(s.units in ("m", "dm", "cm", "mm"), f"scan units {s.units}")
    _finite(s.transform, "scan transform")
    _json_clean(s.info(), "scan info")
    return f"{len(s.vertices)} vertices, {s.units}"


def read_body(data: bytes, extra: dict):
    import numpy as np

    from catwalk.exchange.gltf import read_body as rb

    b = rb(io.BytesIO(data))
    _mesh_sane(b.vertices, b.faces, "body")
    h = float(np.ptp(b.vertices[:, 1]))
    _require(HUMAN[0] - 1e-6 <= h <= HUMAN[1] + 1e-6, f"body height {h}")
    n = len(b.vertices)
    if b.parts is not None:
        _require(np.asarray(b.parts).shape == (n,), "body parts shape")
    _require(isinstance(b.landmarks, dict) and isinstance(b.meta, dict), "landmarks / meta")
    for k, p in b.landmarks.items():
        _require(isinstance(k, str), "landmark name")
        _require(np.asarray(p).shape == (3,), f"landmark {k!r} shape")
        _finite(p, f"landmark {k!r}")
    if b.skeleton is not None:
        sk = b.skeleton
        j = len(sk.names)
        _require(j > 0 and np.asarray(sk.rest_local).shape == (j, 4, 4), "rest_local shape")
        _finite(sk.rest_local, "rest_local")
        _finite(sk.inverse_bind, "inverse bind")
        _require(b.skin_joints.shape == (n, 4) and b.skin_weights.shape == (n, 4),
                 "skin shapes")
        _require(int(b.skin_joints.max()) < j, "skin joint out of range")
        _finite(b.skin_weights, "skin weights")
    return f"{n} vertices"


def read_dxf(data: bytes, extra: dict):
    from catwalk.exchange.dxf import pieces_to_garment
    from catwalk.exchange.dxf import read_dxf as rd
    from catwalk.exchange.garment_json import garment_to_dict
    from catwalk.garment.check import check_garment

    pieces, warn = rd(data, units=extra.get("units"))
    _require(pieces, "no pieces")
    _json_clean(warn, "warnings")
    _require(all(isinstance(w, dict) and isinstance(w.get("code"), str)
                 and isinstance(w.get("message"), str) for w in warn),
             "warnings are {code, message, …} objects")
    for p in pieces:
        s = p.summary()
        _json_clean(s, "piece summary")
        _require(s["area_m2"] > 0 and s["perimeter_m"] > 0, f"piece {p.name!r} area / perimeter")
        for seg in p.segments:
            _finite(seg.start, f"piece {p.name!r} outline")
    g = pieces_to_garment(pieces, "fuzz")
    rep = check_garment(g)
    _json_clean(rep.as_dict(), "check report")
    _json_clean(garment_to_dict(g), "garment")
    # what the reader repairs it leaves repaired: no edge of no length, no crossing (a piece
    # opened on its fold is checked only by the checker)
    unrepaired = [e for e in rep.errors if "has zero length" in e
                  or ("intersects itself" in e and "opened on its fold" not in e)]
    _require(not unrepaired, f"read but not repaired: {unrepaired[:2]}")
    repairs = sum(w["code"] in ("duplicate-points", "loop-removed") for w in warn)
    return f"{len(pieces)} pieces, {repairs} repairs, {len(rep.errors)} check errors"


def _garment_sane(g, what: str):
    from catwalk.exchange.garment_json import garment_from_dict, garment_to_dict
    from catwalk.garment.check import check_garment

    d = garment_to_dict(g)
    _json_clean(d, what)
    g2 = garment_from_dict(json.loads(json.dumps(d)))   # what it writes, it reads back
    _require(len(g2.panels) == len(g.panels), f"{what}: panels lost writing it")
    rep = check_garment(g)
    _json_clean(rep.as_dict(), f"{what}: check report")
    return rep


def read_garment(data: bytes, extra: dict):
    from catwalk.simulate.tryon import load_checked_garment

    g = load_checked_garment(data, base_dir=extra["base_dir"])
    rep = _garment_sane(g, "garment")
    _require(rep.ok, f"garment passed the check once but not twice: {rep.errors[:2]}")
    return f"{len(g.panels)} panels, {len(g.seams)} seams"


def read_markup(data: bytes, extra: dict):
    import copy

    from catwalk.exchange.markup import apply_markup, load_markup

    base = _base_garment(extra)
    markup = load_markup(data)
    g = apply_markup(copy.deepcopy(base), markup, "fuzz-markup")
    rep = _garment_sane(g, "marked-up garment")
    return f"{len(g.panels)} panels, {len(g.seams)} seams, {len(rep.errors)} check errors"


_BASES: dict = {}


def _base_garment(extra: dict):
    key = extra["base"]
    if key not in _BASES:
        from catwalk.exchange.dxf import pieces_to_garment
        from catwalk.exchange.dxf import read_dxf as rd
        from catwalk.exchange.freesewing import load_freesewing

        if key.endswith(".dxf"):
            pieces, _ = rd(key)
            _BASES[key] = pieces_to_garment(pieces, "skirt")
        else:
            _BASES[key] = load_freesewing(key)
    return _BASES[key]


def read_garmentcode(data: bytes, extra: dict):
    from catwalk.exchange.garmentcode import load_garmentcode
    from catwalk.garment.model import GARMENT_TYPES

    g = load_garmentcode(data, name="fuzz", garment_type=extra.get("type"),
                         size=extra.get("size", "M"))
    _require(g.type in GARMENT_TYPES, f"garment type {g.type!r}")
    _require(g.panels, "no panels")
    _require(all(isinstance(s, str) and s.strip() for s in g.sizes), f"sizes {g.sizes!r}")
    rep = _garment_sane(g, "converted garment")
    return f"{len(g.panels)} panels, {len(rep.errors)} check errors"


def read_scene(data: bytes, extra: dict):
    import numpy as np

    from catwalk.exchange.scene import load_scene

    sc = load_scene(io.BytesIO(data))
    _require(math.isfinite(sc.duration) and sc.duration >= 0, f"duration {sc.duration}")
    for t in (0.0, sc.duration):
        for name, v, f, rgb in sc.meshes_at(t):
            _mesh_sane(v, f, f"scene mesh {name!r} at {t}")
            c = np.asarray(rgb)
            _finite(c, f"scene mesh {name!r} colours")
    return f"{len(sc.garments)} garments"


READERS = {"scan": read_scan, "body": read_body, "dxf": read_dxf, "garment": read_garment,
           "markup": read_markup, "garmentcode": read_garmentcode, "scene": read_scene}


# ---------------------------------------------------------------------------------- the loop

def _peak_rss() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def handle(reader: str, data: bytes, extra: dict) -> dict:
    from catwalk.errors import InputError

    t0 = time.perf_counter()
    rss0 = _peak_rss()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            detail = READERS[reader](data, extra)
            out = {"outcome": "ok", "message": detail}
        except InputError as exc:
            out = {"outcome": "input_error", "message": str(exc)}
        except Insane as exc:
            out = {"outcome": "bug", "message": f"insane result: {exc}"}
        except BaseException as exc:  # noqa: BLE001 - the point: anything else is a bug
            tb = traceback.format_exc(limit=-6)
            out = {"outcome": "bug", "message": f"{type(exc).__name__}: {exc}"[:2000],
                   "traceback": tb}
    runtime = [w for w in caught if issubclass(w.category, (RuntimeWarning, UserWarning))]
    if runtime and out["outcome"] != "bug":
        w = runtime[0]
        out = {"outcome": "bug", "message": f"printed a warning ({out['outcome']}): "
               f"{w.category.__name__}: {w.message} at {w.filename}:{w.lineno}"}
    grew = _peak_rss() - rss0
    if grew > MAX_RSS_GROWTH and out["outcome"] != "bug":
        out = {"outcome": "bug", "message": f"peak memory grew by {grew >> 20} MiB "
               f"({out['outcome']}: {out['message'][:200]})"}
    out["seconds"] = time.perf_counter() - t0
    out["rss_growth"] = max(0, grew)
    return out


def _read_exact(stream, n: int) -> bytes:
    buf = b""
    while len(buf) < n:
        chunk = stream.read(n - len(buf))
        if not chunk:
            raise EOFError
        buf += chunk
    return buf


def main() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))
    stdin, stdout = sys.stdin.buffer, sys.stdout.buffer
    sys.stdout = sys.stderr   # anything a reader prints must not garble the answers
    # warm up: import the readers before the first timed request
    for mod in ("catwalk.exchange.scan", "catwalk.exchange.gltf", "catwalk.exchange.dxf",
                "catwalk.exchange.markup", "catwalk.exchange.garmentcode",
                "catwalk.exchange.scene", "catwalk.simulate.tryon", "trimesh", "ezdxf"):
        __import__(mod)
    stdout.write(b"R")
    stdout.flush()
    while True:
        try:
            (n,) = struct.unpack("<Q", _read_exact(stdin, 8))
            reader, data, extra = pickle.loads(_read_exact(stdin, n))
        except EOFError:
            return
        answer = pickle.dumps(handle(reader, data, extra))
        stdout.write(struct.pack("<Q", len(answer)) + answer)
        stdout.flush()


if __name__ == "__main__":
    os.environ.setdefault("PYTHONWARNINGS", "default")
    main()
