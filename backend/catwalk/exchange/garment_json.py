"""The garment's open JSON format (``docs/garment-format.md``): reader beside writer.

:func:`load_garment` / :func:`garment_from_dict` read it (from a path, bytes, a file object or
a parsed dict), raising :class:`catwalk.errors.InputError` with the panel and edge named;
:func:`garment_to_dict` / :func:`save_garment` / :func:`garment_bytes` write it.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.exchange.source import check_depth, read_json
from catwalk.fileio import atomic_path
from catwalk.garment.geometry import KINDS, Segment
from catwalk.garment.model import (
    BODY_PARTS,
    GARMENT_TYPES,
    PANEL_TYPES,
    SIDES,
    Garment,
    Panel,
    Placement,
    Seam,
    SeamSide,
    Shape,
)

FORMAT = "catwalk-garment"
VERSION = 1
# what one garment may hold (docs/garment-format.md, "Limits"); the catalogue's largest:
# 3 sizes, 8 panels, 21 edges an outline, 23 seams
MAX_SIZES = 50
MAX_PANELS = 200
MAX_EDGES = 5000        # segments of one outline
MAX_NOTCHES = 1000      # of one shape
MAX_SEAMS = 2000
MAX_NAME = 200          # characters of a size or panel name


# --- reading -------------------------------------------------------------------------------

MAX_COORDINATE_M = 1000.0   # a pattern point farther from the origin is no garment in metres

def _pt(value, where: str) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{where}: expected a point [x, y] in metres, got {value!r}") from None
    if arr.shape != (2,) or not np.all(np.isfinite(arr)) or isinstance(value, (str, bytes)):
        raise InputError(f"{where}: expected a point [x, y] in metres, got {value!r}")
    if np.abs(arr).max() > MAX_COORDINATE_M:
        raise InputError(f"{where}: {value!r} is more than {MAX_COORDINATE_M:g} m from the "
                         "origin: not garment-sized (a pattern's unit is the metre)")
    return arr


def _num(v, where: str, lo: float | None = None) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise InputError(f"{where}: expected a number, got {v!r}")
    if lo is not None and v < lo:
        raise InputError(f"{where}: must be ≥ {lo}, got {v!r}")
    return float(v)


def _int(v, where: str) -> int:
    if isinstance(v, bool) or not isinstance(v, int):
        raise InputError(f"{where}: expected a whole number, got {v!r}")
    return v


def _bool(v, where: str) -> bool:
    if not isinstance(v, bool):
        raise InputError(f"{where}: expected true or false, got {v!r}")
    return v


def _obj(v, where: str, what: str = "an object") -> dict:
    if not isinstance(v, dict):
        raise InputError(f"{where}: expected {what}, got {v!r}")
    return v


def _list(v, where: str, what: str = "a list") -> list:
    if not isinstance(v, list):
        raise InputError(f"{where}: expected {what}, got {v!r}")
    return v


def _str(v, where: str) -> str:
    if not isinstance(v, str):
        raise InputError(f"{where}: expected a string, got {v!r}")
    return v


def check_name(v, where: str, what: str) -> str:
    """A size or panel name: a non-empty string without surrounding spaces."""
    if not isinstance(v, str) or not v.strip() or v != v.strip() or len(v) > MAX_NAME:
        raise InputError(f"{where}: {what} {v!r:.60} is not a name (a non-empty string without "
                         f"surrounding spaces, at most {MAX_NAME} characters)")
    return v


def _plain(v, where: str):
    """A free-form JSON value (source, meta, texture, fabric) checked to hold only finite
    numbers, so that the garment is written back as standard JSON."""
    todo = [v]
    while todo:
        x = todo.pop()
        if isinstance(x, float) and not math.isfinite(x):
            raise InputError(f"{where}: {x!r} is not a number JSON allows")
        if isinstance(x, dict):
            todo.extend(x.values())
        elif isinstance(x, list):
            todo.extend(x)
    return v


def _segments(raw, where: str) -> list[Segment]:
    if not isinstance(raw, list) or len(raw) < 2:
        raise InputError(f"{where}: outline must be a list of at least 2 segments")
    if len(raw) > MAX_EDGES:
        raise InputError(f"{where}: {len(raw):,} segments; an outline has at most "
                         f"{MAX_EDGES:,}")
    segs = []
    for i, s in enumerate(raw):
        w = f"{where}, edge {i}"
        if not isinstance(s, dict):
            raise InputError(f"{w}: a segment is an object like {{\"type\": \"line\", "
                             f"\"start\": [x, y]}}")
        kind = s.get("type", "line")
        if kind not in KINDS:
            raise InputError(f"{w}: unknown segment type {kind!r} (known: {', '.join(KINDS)})")
        start = _pt(s.get("start"), f"{w}, start")
        controls = [_pt(c, f"{w}, control {j}") for j, c in
                    enumerate(_list(s.get("controls", []), f"{w}, controls"))]
        need = {"line": 0, "arc": 0, "quadratic": 1, "cubic": 2}[kind]
        if len(controls) != need:
            raise InputError(f"{w}: a {kind} segment needs {need} control point(s), "
                             f"got {len(controls)}")
        bulge = _num(s.get("bulge", 0.0), f"{w}, bulge")
        end = _pt(s["end"], f"{w}, end") if "end" in s else None  # optional, checked
        segs.append(Segment(kind, start, controls, bulge, end))
    return segs


def _shape(raw, where: str) -> Shape:
    if not isinstance(raw, dict) or "outline" not in raw:
        raise InputError(f"{where}: a shape needs an \"outline\"")
    outline = _segments(raw["outline"], where)
    grain = None
    if raw.get("grain") is not None:
        g = raw["grain"]
        if not isinstance(g, list) or len(g) != 2:
            raise InputError(f"{where}: grain is [[x0, y0], [x1, y1]] (from → to)")
        grain = np.stack([_pt(g[0], f"{where}, grain"), _pt(g[1], f"{where}, grain")])
    raw_notches = _list(raw.get("notches", []), f"{where}, notches")
    if len(raw_notches) > MAX_NOTCHES:
        raise InputError(f"{where}: {len(raw_notches):,} notches; at most {MAX_NOTCHES:,}")
    notches = np.array([_pt(p, f"{where}, notch {i}") for i, p in enumerate(raw_notches)],
                       dtype=float).reshape(-1, 2)
    labels = {}
    for k, v in _obj(raw.get("labels") or {}, f"{where}, labels").items():
        try:
            labels[int(k)] = _str(v, f"{where}, label {k}")
        except ValueError:
            raise InputError(f"{where}: label keys are vertex numbers, got {k!r}") from None
    return Shape(outline, grain, notches, labels)


def _placement(raw, where: str) -> Placement | None:
    if raw is None:
        return None
    w = f"{where}: placement"
    _obj(raw, w)
    known = set(Placement.__dataclass_fields__)
    extra = set(raw) - known
    if extra:
        raise InputError(f"{w}: unknown field(s) {', '.join(sorted(map(str, extra)))}")
    pl = Placement()
    if "part" in raw:
        pl.part = raw["part"]
    if "side" in raw:
        pl.side = raw["side"]
    if pl.part not in BODY_PARTS:
        raise InputError(f"{w}: part {pl.part!r} is not one of {', '.join(BODY_PARTS)}")
    if pl.side not in SIDES:
        raise InputError(f"{w}: side {pl.side!r} is not one of {', '.join(SIDES)}")
    if raw.get("anchor") is not None:
        pl.anchor = _str(raw["anchor"], f"{w}, anchor")
    if raw.get("anchor_point") is not None:
        pl.anchor_point = [float(x) for x in _pt(raw["anchor_point"], f"{w}, anchor_point")]
    if raw.get("anchor_vertex") is not None:
        pl.anchor_vertex = _int(raw["anchor_vertex"], f"{w}, anchor_vertex")
    if "offset" in raw:
        off = _list(raw["offset"], f"{w}, offset", "[dx, dy, dz] in metres")
        if len(off) != 3:
            raise InputError(f"{w}, offset: expected [dx, dy, dz] in metres, got {off!r}")
        pl.offset = [_num(x, f"{w}, offset") for x in off]
    if "rotation" in raw:
        pl.rotation = _num(raw["rotation"], f"{w}, rotation")
    if "wrap" in raw:
        pl.wrap = _bool(raw["wrap"], f"{w}, wrap")
    if "distance" in raw:
        pl.distance = _num(raw["distance"], f"{w}, distance", 0.0)
    if raw.get("transform") is not None:
        t = _obj(raw["transform"], f"{w}, transform")
        try:
            r = np.asarray(t["rotation"], dtype=float)
            tr = np.asarray(t["translation"], dtype=float)
        except (KeyError, TypeError, ValueError):
            raise InputError(f"{w}, transform: needs rotation (3×3) and translation (3)") \
                from None
        if r.shape != (3, 3) or tr.shape != (3,) or not (np.all(np.isfinite(r))
                                                         and np.all(np.isfinite(tr))):
            raise InputError(f"{w}, transform: needs rotation (3×3) and translation (3)")
        pl.transform = dict(_plain(t, f"{w}, transform"))
    return pl


def _side(raw, where: str) -> SeamSide:
    if not isinstance(raw, dict) or not {"panel", "start", "end"} <= set(raw):
        raise InputError(f"{where}: a seam side is {{\"panel\": name, \"start\": vertex, "
                         f"\"end\": vertex}}")
    for k in ("start", "end"):
        _int(raw[k], f"{where}, {k}")
    half = raw.get("half", "cut")
    if half not in ("cut", "mirror"):
        raise InputError(f"{where}: half must be \"cut\" or \"mirror\"")
    return SeamSide(_str(raw["panel"], f"{where}, panel"), raw["start"], raw["end"], half)


def garment_from_dict(data: dict, path: str | Path | None = None, *,
                      name: str | None = None, problems: list[str] | None = None) -> Garment:
    """A garment from its parsed JSON. ``path``: the file it came from (textures are relative
    to its folder); ``name``: how messages call it (default: the path, or "garment");
    ``problems``: where a seam naming no panel is reported (and left out) instead of raised,
    so that the checker can list it beside the garment's other problems."""
    src = name or (f"{path}" if path else "garment")
    if not isinstance(data, dict):
        raise InputError(f"{src}: not a garment (expected a JSON object)")
    check_depth(data, src)
    if data.get("format") != FORMAT:
        raise InputError(f"{src}: not a catwalk garment (\"format\" must be {FORMAT!r})")
    version = data.get("version")
    if version != VERSION or isinstance(version, bool):
        raise InputError(f"{src}: garment format version {version!r} is not supported "
                         f"(this catwalk reads version {VERSION})")
    for k in ("name", "type", "sizes", "panels"):
        if k not in data:
            raise InputError(f"{src}: missing {k!r}")
    name = _str(data["name"], f"{src}: name")
    gtype = data["type"]
    if not isinstance(gtype, str) or gtype not in GARMENT_TYPES:
        raise InputError(f"{src}: garment type {gtype!r} is not one of {', '.join(GARMENT_TYPES)}")
    sizes = data["sizes"]
    if (not isinstance(sizes, list) or not sizes or not all(isinstance(s, str) for s in sizes)
            or len(set(sizes)) != len(sizes)):
        raise InputError(f"{src}: sizes must be a non-empty list of distinct names")
    if len(sizes) > MAX_SIZES:
        raise InputError(f"{src}: {len(sizes):,} sizes; a garment has at most {MAX_SIZES}")
    for s in sizes:
        check_name(s, f"{src}: sizes", "size")
    panels = []
    seen = set()
    if not isinstance(data["panels"], list) or not data["panels"]:
        raise InputError(f"{src}: panels must be a non-empty list")
    if len(data["panels"]) > MAX_PANELS:
        raise InputError(f"{src}: {len(data['panels']):,} panels; a garment has at most "
                         f"{MAX_PANELS}")
    for i, rp in enumerate(data["panels"]):
        if not isinstance(rp, dict) or not isinstance(rp.get("name"), str):
            raise InputError(f"{src}: panel {i} has no name")
        pname = check_name(rp["name"], f"{src}: panel {i}", "name")
        w = f"{src}: panel {pname!r}"
        if pname in seen:
            raise InputError(f"{w}: two panels have this name")
        seen.add(pname)
        ptype = rp.get("type", "other")
        if not isinstance(ptype, str) or ptype not in PANEL_TYPES:
            raise InputError(f"{w}: panel type {ptype!r} is not one of {', '.join(PANEL_TYPES)}")
        shapes = {}
        for size, rs in _obj(rp.get("shapes") or {}, f"{w}, shapes",
                             "an object mapping sizes to shapes").items():
            if size not in sizes:
                raise InputError(f"{w}: shape for size {size!r}, which is not in sizes")
            shapes[size] = _shape(rs, f"{w} (size {size})")
        fold = rp.get("fold")
        if fold is not None:
            fold = _int(fold, f"{w}: fold (the number of the straight edge cut on the fold)")
        copy = rp.get("copy_of")
        if copy is None:
            if not shapes:   # a panel of some sizes only has outlines in those
                raise InputError(f"{w}: no outline in any size (sizes: {', '.join(sizes)})")
        else:
            copy = _str(copy, f"{w}: copy_of")
            if shapes:
                raise InputError(f"{w}: a copy_of panel takes its outline from {copy!r}; "
                                 f"it has no shapes of its own")
        texture = _plain(rp.get("texture"), f"{w}: texture")
        if texture is not None:
            if not isinstance(texture, dict) or not isinstance(texture.get("image"), str):
                raise InputError(f"{w}: texture is {{\"image\": path, \"size\": [w, h]}}")
            if "size" in texture:
                sz = _list(texture["size"], f"{w}: texture size", "[w, h] in metres")
                if len(sz) != 2 or any(_num(x, f"{w}: texture size") <= 0 for x in sz):
                    raise InputError(f"{w}: texture size is [w, h] in metres, both > 0")
        fabric = _plain(rp.get("fabric"), f"{w}: fabric")
        if fabric is not None and not isinstance(fabric, (str, dict)):
            raise InputError(f"{w}: fabric is a preset name or a custom fabric object")
        panels.append(Panel(pname, ptype, shapes, fold, copy,
                            _bool(rp.get("mirror", False), f"{w}: mirror"), fabric, texture,
                            _placement(rp.get("placement"), f"{w}"),
                            dict(_plain(_obj(rp.get("meta", {}), f"{w}: meta"), f"{w}: meta"))))
    for s in sizes:
        if not any(s in p.shapes for p in panels):
            raise InputError(f"{src}: size {s}: no panel has an outline in this size")
    names = {p.name for p in panels}
    for p in panels:
        if p.copy_of is not None:
            if p.copy_of not in names:
                raise InputError(f"{src}: panel {p.name!r}: copy_of names no panel "
                                 f"({p.copy_of!r})")
            chain, q = {p.name}, p
            while q.copy_of is not None:
                if q.copy_of in chain:
                    raise InputError(f"{src}: panel {p.name!r}: copy_of goes round in a circle")
                chain.add(q.copy_of)
                q = next(x for x in panels if x.name == q.copy_of)
            if p.fold is None:
                p.fold = q.fold
    seams = []
    raw_seams = _list(data.get("seams", []), f"{src}: seams")
    if len(raw_seams) > MAX_SEAMS:
        raise InputError(f"{src}: {len(raw_seams):,} seams; a garment has at most {MAX_SEAMS}")
    for i, rs in enumerate(raw_seams):
        w = f"{src}: seam {i}"
        if not isinstance(rs, dict) or "a" not in rs or "b" not in rs:
            raise InputError(f"{w}: a seam is {{\"a\": side, \"b\": side, \"reverse\": bool}}")
        a = _side(rs["a"], f"{w}, side a")
        b = _side(rs["b"], f"{w}, side b")
        unknown = [f"{w}, side {lab}: no panel named {side.panel!r}"
                   for side, lab in ((a, "a"), (b, "b")) if side.panel not in names]
        if unknown and problems is None:
            raise InputError(unknown[0])
        if unknown:
            problems.extend(unknown)
            continue
        ease = _num(rs.get("ease", 0.0), f"{w}: ease", 0.0)
        if ease >= 1.0:
            raise InputError(f"{w}: ease is a fraction in [0, 1), got {ease!r}")
        seams.append(Seam(a, b, _bool(rs.get("reverse", False), f"{w}: reverse"),
                          _str(rs.get("name", ""), f"{w}: name"),
                          _str(rs.get("kind", "seam"), f"{w}: kind"), ease))
    default = data.get("default_size")
    if default is not None and default not in sizes:
        raise InputError(f"{src}: default_size {default!r} is not in sizes")
    fabric = _plain(data.get("fabric", "cotton-jersey"), f"{src}: fabric")
    if not isinstance(fabric, (str, dict)):
        raise InputError(f"{src}: fabric is a preset name or a custom fabric object")
    fit = data.get("fit", {})
    if not isinstance(fit, dict) or not all(k in sizes and isinstance(v, str)
                                            for k, v in fit.items()):
        raise InputError(f"{src}: fit maps sizes to sample-body names (bodies/recipes.json)")
    return Garment(name, gtype, list(sizes), panels, seams, fabric, default,
                   _str(data.get("description", ""), f"{src}: description"),
                   dict(_plain(_obj(data.get("source", {}), f"{src}: source"), f"{src}: source")),
                   dict(fit),
                   Path(path) if path else None)


def load_garment(source, *, base_dir: str | Path | None = None) -> Garment:
    """Read a garment from a path, bytes, a binary file object or an already parsed dict.
    Texture paths are relative to the file's folder, or to ``base_dir`` when the garment
    comes without one (bytes, a dict)."""
    if isinstance(source, dict):
        where = Path(base_dir) / "garment.json" if base_dir is not None else None
        return garment_from_dict(source, where)
    if isinstance(source, (str, Path)) and not Path(source).is_file():
        raise InputError(f"{source}: no such garment file")
    parsed, name = read_json(source, "garment")
    path = Path(source) if isinstance(source, (str, Path)) else (
        Path(base_dir) / Path(name).name if base_dir is not None else None)
    return garment_from_dict(parsed, path, name=name)


# --- writing -------------------------------------------------------------------------------

def _r(x: float) -> float:
    return round(float(x), 6)


def _seg_dict(s: Segment) -> dict:
    d = {"type": s.kind, "start": [_r(s.start[0]), _r(s.start[1])]}
    if s.controls:
        d["controls"] = [[_r(c[0]), _r(c[1])] for c in s.controls]
    if s.kind == "arc":
        d["bulge"] = round(float(s.bulge), 9)
    return d


def shape_to_dict(sh: Shape) -> dict:
    d = {"outline": [_seg_dict(s) for s in sh.outline]}
    if sh.grain is not None:
        d["grain"] = [[_r(x) for x in p] for p in sh.grain]
    if len(sh.notches):
        d["notches"] = [[_r(x) for x in p] for p in sh.notches]
    if sh.labels:
        d["labels"] = {str(k): v for k, v in sorted(sh.labels.items())}
    return d


def garment_to_dict(g: Garment) -> dict:
    panels = []
    for p in g.panels:
        d = {"name": p.name, "type": p.type}
        if p.copy_of is not None:
            d["copy_of"] = p.copy_of
            d["mirror"] = bool(p.mirror)
        else:
            d["shapes"] = {s: shape_to_dict(p.shapes[s]) for s in g.sizes if s in p.shapes}
            if p.fold is not None:
                d["fold"] = int(p.fold)
        if p.fabric is not None:
            d["fabric"] = p.fabric
        if p.texture is not None:
            d["texture"] = p.texture
        if p.placement is not None:
            d["placement"] = p.placement.as_dict()
        if p.meta:
            d["meta"] = p.meta
        panels.append(d)
    seams = []
    for s in g.seams:
        d = {"a": s.a.as_dict(), "b": s.b.as_dict(), "reverse": bool(s.reverse)}
        if s.name:
            d["name"] = s.name
        if s.kind != "seam":
            d["kind"] = s.kind
        if s.ease:
            d["ease"] = round(float(s.ease), 4)
        seams.append(d)
    out = {"format": FORMAT, "version": VERSION, "name": g.name, "type": g.type,
           "sizes": list(g.sizes)}
    if g.default_size:
        out["default_size"] = g.default_size
    if g.description:
        out["description"] = g.description
    if g.source:
        out["source"] = g.source
    if g.fit:
        out["fit"] = dict(g.fit)
    out["fabric"] = g.fabric
    out["panels"] = panels
    out["seams"] = seams
    return out


def garment_bytes(g: Garment) -> bytes:
    """The garment as the JSON file :func:`save_garment` writes."""
    return (json.dumps(garment_to_dict(g), indent=1) + "\n").encode()


def save_garment(g: Garment, path: str | Path, flag: str | None = None) -> None:
    """Write the garment's JSON to ``path`` atomically (``flag``: the option that named the
    path, for messages)."""
    data = garment_bytes(g)
    with atomic_path(path, flag) as tmp:
        tmp.write_bytes(data)
