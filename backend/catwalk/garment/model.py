"""The garment model and its open JSON format (``docs/garment-format.md``).

A :class:`Garment` is what a merchant uploads: a garment type, its sizes, panels (each with a
closed outline per size, grain line, cut-on-fold or mirrored copy, texture, fabric, placement
hint) and seams between outline runs. :func:`load_garment` / :func:`garment_from_dict` read it
(raising :class:`catwalk.errors.InputError` with the panel and edge named),
:func:`garment_to_dict` / :func:`save_garment` write it; :mod:`catwalk.garment.check` validates
the geometry and the seams.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.fileio import atomic_path
from catwalk.garment.geometry import (
    KINDS,
    Flat,
    Segment,
    flatten,
    line_mirror_matrix,
    mirror_matrix,
    rotate_matrix,
    transform_points,
    transform_segments,
)

FORMAT = "catwalk-garment"
VERSION = 1

GARMENT_TYPES = ("dress", "tshirt", "shirt", "blouse", "top", "bodice", "skirt", "trousers",
                 "shorts", "jacket", "coat", "hoodie", "jumpsuit", "other")
PANEL_TYPES = ("front", "back", "sleeve", "collar", "cuff", "waistband", "skirt", "leg", "yoke",
               "pocket", "facing", "hood", "placket", "neckband", "other")
BODY_PARTS = ("torso", "left_arm", "right_arm", "left_leg", "right_leg", "legs")
SIDES = ("front", "back", "left", "right")


@dataclass
class Shape:
    """A panel's geometry in one size (pattern coordinates, metres)."""
    outline: list[Segment]
    grain: np.ndarray | None = None            # (2, 2): from → to, the warp direction
    notches: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    labels: dict[int, str] = field(default_factory=dict)  # vertex → name (e.g. "armhole-top")

    def flat(self, tolerance: float = 1e-3) -> Flat:
        return flatten(self.outline, tolerance)

    def transformed(self, matrix: np.ndarray) -> Shape:
        """The shape under a 2×3 affine map (reflections keep the loop counter-clockwise:
        vertex ``i`` becomes vertex ``(-i) mod n``; labels follow)."""
        det = float(np.linalg.det(matrix[:, :2]))
        n = len(self.outline)
        labels = dict(self.labels) if det > 0 else {(-v) % n: s for v, s in self.labels.items()}
        return Shape(transform_segments(self.outline, matrix),
                     None if self.grain is None else transform_points(self.grain, matrix),
                     transform_points(self.notches, matrix).reshape(-1, 2), labels)


@dataclass
class Placement:
    """Where a panel goes on the body (hints for :mod:`catwalk.garment.place`)."""
    part: str = "torso"
    side: str = "front"
    anchor: str | None = None              # landmark name, e.g. "waist", "shoulder_left"
    anchor_point: list[float] | None = None   # panel point (pattern coords) put at the anchor
    anchor_vertex: int | None = None       # or this outline vertex (numbered as stored)
    offset: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])  # metres, world
    rotation: float = 0.0                  # degrees, about the outward normal
    wrap: bool = True                      # curve the panel round the part
    distance: float = 0.03                 # metres between body surface and panel
    transform: dict | None = None          # explicit 3D placement on a reference body

    def as_dict(self) -> dict:
        d = {"part": self.part, "side": self.side}
        if self.anchor is not None:
            d["anchor"] = self.anchor
        if self.anchor_point is not None:
            d["anchor_point"] = [float(x) for x in self.anchor_point]
        if self.anchor_vertex is not None:
            d["anchor_vertex"] = int(self.anchor_vertex)
        if any(self.offset):
            d["offset"] = [float(x) for x in self.offset]
        if self.rotation:
            d["rotation"] = float(self.rotation)
        d["wrap"] = bool(self.wrap)
        d["distance"] = float(self.distance)
        if self.transform is not None:
            d["transform"] = self.transform
        return d


@dataclass
class Panel:
    name: str
    type: str = "other"
    shapes: dict[str, Shape] = field(default_factory=dict)   # size → shape
    fold: int | None = None               # cut on fold along this (straight) segment
    copy_of: str | None = None            # shape taken from that panel …
    mirror: bool = False                  # … mirrored (x → −x) when true
    fabric: str | dict | None = None      # overrides the garment's fabric
    texture: dict | None = None           # {"image": path, "size": [w, h] metres per repeat}
    placement: Placement | None = None
    meta: dict = field(default_factory=dict)


@dataclass
class SeamSide:
    panel: str
    start: int
    end: int
    half: str = "cut"    # "cut" or "mirror": which half of a cut-on-fold panel

    def as_dict(self) -> dict:
        d = {"panel": self.panel, "start": int(self.start), "end": int(self.end)}
        if self.half != "cut":
            d["half"] = self.half
        return d


@dataclass
class Seam:
    """Panel A's outline run (vertex ``start`` forward to vertex ``end``) sewn to panel B's;
    A's start meets B's start, or B's end when ``reverse``."""
    a: SeamSide
    b: SeamSide
    reverse: bool = False
    name: str = ""
    kind: str = "seam"   # "seam", "dart", "hem-join"…; informative
    ease: float = 0.0    # relative excess length the designer eases or gathers in (0.25 = 25 %)

    def label(self, i: int) -> str:
        return f"seam {i}" + (f" ({self.name!r})" if self.name else "")


@dataclass
class Garment:
    name: str
    type: str
    sizes: list[str]
    panels: list[Panel]
    seams: list[Seam] = field(default_factory=list)
    fabric: str | dict = "cotton-jersey"
    default_size: str | None = None
    description: str = ""
    source: dict = field(default_factory=dict)
    fit: dict[str, str] = field(default_factory=dict)   # size → sample body it was made for
    path: Path | None = None   # the file it came from (textures are relative to it)

    def panel(self, name: str) -> Panel:
        for p in self.panels:
            if p.name == name:
                return p
        raise InputError(f"{self._where()}no panel named {name!r}")

    def _where(self) -> str:
        return f"{self.path}: " if self.path else ""

    def size(self, size: str | None) -> str:
        if size is None:
            return self.default_size or self.sizes[len(self.sizes) // 2]
        if size not in self.sizes:
            raise InputError(f"{self._where()}garment {self.name!r} has no size {size!r} "
                             f"(sizes: {', '.join(self.sizes)})")
        return size

    def shape(self, panel: str | Panel, size: str) -> Shape:
        """The panel's shape as stored (a copy's shape comes from its source, mirrored)."""
        p = self.panel(panel) if isinstance(panel, str) else panel
        if p.copy_of is not None:
            src = self.shape(p.copy_of, size)
            return src.transformed(mirror_matrix("x")) if p.mirror else src
        if size not in p.shapes:
            raise InputError(f"{self._where()}panel {p.name!r} has no outline for size {size!r}")
        return p.shapes[size]

    def source_vertex_map(self, panel: str | Panel) -> tuple[str, bool]:
        """(panel whose indices a seam on ``panel`` uses, whether they are mirrored)."""
        p = self.panel(panel) if isinstance(panel, str) else panel
        if p.copy_of is None:
            return p.name, False
        base, mir = self.source_vertex_map(p.copy_of)
        return base, mir ^ p.mirror


# --- cut pieces: what the cloth builder gets ------------------------------------------------

@dataclass
class Piece:
    """One panel as cut, in one size: folds opened, copies made, curves flattened."""
    name: str
    panel: Panel
    shape: Shape                 # the full outline as segments (fold opened)
    flat: Flat                   # flattened; flat.vertex_index maps shape vertices
    fold_map: np.ndarray | None  # for folded panels: (n, 2) full-outline vertex of each stored
                                 # vertex in the cut half (col 0) and the mirrored half (col 1)
    grain_rotation: float = 0.0  # degrees the panel was turned to put its grain along ±y


def unfold(shape: Shape, k: int) -> tuple[Shape, np.ndarray]:
    """Open a half cut on fold along segment ``k``: the full outline and the vertex map.

    The full outline starts at vertex k+1, walks the stored half to vertex k, then the
    mirrored half back; stored vertex v is full vertex ``(v-k-1) mod n`` and its mirror image
    is full vertex ``n + ((k-1-v) mod n)`` (v ∉ {k, k+1}, which lie on the fold)."""
    segs = shape.outline
    n = len(segs)
    p, q = segs[k].start, segs[(k + 1) % n].start
    m = line_mirror_matrix(p, q)
    kept = [segs[(k + 1 + j) % n].copy() for j in range(n - 1)]  # vertices k+1 … k-1 → k
    mirrored = []
    for j in range(n - 1):   # images of stored segments k-1, k-2, …, k+1, walked backwards
        src = segs[(k - 1 - j) % n]
        mirrored.append(Segment(src.kind, transform_points(segs[(k - j) % n].start, m),
                                [transform_points(c, m) for c in reversed(src.controls)],
                                src.bulge))  # reversed and reflected: the bulge keeps its sign
    full = kept + mirrored
    vmap = _fold_map(n, k)
    labels = {int(vmap[v, 0]): s for v, s in shape.labels.items()}
    notches = shape.notches
    if len(notches):
        notches = np.concatenate([notches, transform_points(notches, m)])
    return Shape(full, shape.grain, notches, labels), vmap


def cut_pieces(garment: Garment, size: str | None = None, tolerance: float = 2e-3,
               align_grain: bool = True) -> tuple[list[Piece], list[tuple]]:
    """Pieces as cut in ``size`` and seams as ``(piece_a, start_a, end_a, piece_b, start_b,
    end_b, reverse)`` in *flattened* point indices, ready for
    :class:`catwalk.cloth.builder.Seam` (runs go forward from start to end).

    With ``align_grain`` a piece whose grain line is not along ±y (the builder's warp) is
    turned about the grain line's start by the smallest angle that makes it so (a grain line
    has no preferred sense, so a piece is never turned by more than 90°)."""
    size = garment.size(size)
    pieces, index = [], {}
    for p in garment.panels:
        shape = garment.shape(p, size)
        fold_map = None
        if p.fold is not None:
            n = len(shape.outline)
            _, mirrored = garment.source_vertex_map(p)
            k = (-p.fold - 1) % n if mirrored else p.fold % n
            shape, fold_map = unfold(shape, k)
        turn = 0.0
        if align_grain and shape.grain is not None:
            d = shape.grain[1] - shape.grain[0]
            if np.linalg.norm(d) > 0:
                turn = math.degrees(math.atan2(d[0], d[1]))   # angle from +y, clockwise
                turn = (turn + 90.0) % 180.0 - 90.0              # the nearer of ±y
                if abs(turn) > 0.01:
                    shape = shape.transformed(rotate_matrix(turn, shape.grain[0]))
                else:
                    turn = 0.0
        index[p.name] = len(pieces)
        pieces.append(Piece(p.name, p, shape, shape.flat(tolerance), fold_map, turn))
    seams = []
    for s in garment.seams:
        ends = []
        for side in (s.a, s.b):
            piece = pieces[index[side.panel]]
            start, end, flipped = side_vertices(garment, piece.panel, side, size)
            vi = piece.flat.vertex_index
            ends.append((index[side.panel], int(vi[start]), int(vi[end]), flipped))
        (pa, sa, ea, fa), (pb, sb, eb, fb) = ends
        seams.append((pa, sa, ea, pb, sb, eb, bool(s.reverse) ^ fa ^ fb))
    return pieces, seams


def side_vertices(garment: Garment, panel: Panel, side: SeamSide, size: str
                  ) -> tuple[int, int, bool]:
    """A seam side's run as (start, end) vertices of the panel's outline as cut (mirrored copy
    made, fold opened), and whether the run now walks the other way."""
    n = len(garment.shape(panel, size).outline)
    start, end = side.start % n, side.end % n
    _, mirrored = garment.source_vertex_map(panel)
    flipped = False
    if mirrored:   # stored vertex v is vertex (-v) mod n of the copy, and runs walk backwards
        start, end = (-end) % n, (-start) % n
        flipped = True
    if panel.fold is not None:
        k = (-panel.fold - 1) % n if mirrored else panel.fold % n
        fm = _fold_map(n, k)
        if side.half == "mirror":
            return int(fm[end, 1]), int(fm[start, 1]), not flipped
        return int(fm[start, 0]), int(fm[end, 0]), flipped
    return start, end, flipped


def piece_vertex(garment: Garment, piece: Piece, vertex: int, size: str,
                 half: str = "cut") -> np.ndarray:
    """Where stored vertex ``vertex`` of the piece's panel lies in the cut piece."""
    n = len(garment.shape(piece.panel, size).outline)
    v = vertex % n
    _, mirrored = garment.source_vertex_map(piece.panel)
    if mirrored:
        v = (-v) % n
    if piece.panel.fold is not None:
        k = (-piece.panel.fold - 1) % n if mirrored else piece.panel.fold % n
        v = int(_fold_map(n, k)[v, 1 if half == "mirror" else 0])
    return piece.flat.points[piece.flat.vertex_index[v]]


def _fold_map(n: int, k: int) -> np.ndarray:
    vmap = np.zeros((n, 2), dtype=np.int64)
    for v in range(n):
        vmap[v, 0] = (v - k - 1) % n
        vmap[v, 1] = n + ((k - 1 - v) % n) if v not in (k, (k + 1) % n) else vmap[v, 0]
    return vmap


# --- reading -------------------------------------------------------------------------------

def _pt(value, where: str) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{where}: expected a point [x, y] in metres, got {value!r}") from None
    if arr.shape != (2,) or not np.all(np.isfinite(arr)) or isinstance(value, (str, bytes)):
        raise InputError(f"{where}: expected a point [x, y] in metres, got {value!r}")
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


def _segments(raw, where: str) -> list[Segment]:
    if not isinstance(raw, list) or len(raw) < 2:
        raise InputError(f"{where}: outline must be a list of at least 2 segments")
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
    notches = np.array([_pt(p, f"{where}, notch {i}") for i, p in
                        enumerate(_list(raw.get("notches", []), f"{where}, notches"))],
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
        pl.transform = dict(t)
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


def garment_from_dict(data: dict, path: str | Path | None = None) -> Garment:
    src = f"{path}" if path else "garment"
    if not isinstance(data, dict):
        raise InputError(f"{src}: not a garment (expected a JSON object)")
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
    panels = []
    seen = set()
    if not isinstance(data["panels"], list) or not data["panels"]:
        raise InputError(f"{src}: panels must be a non-empty list")
    for i, rp in enumerate(data["panels"]):
        if not isinstance(rp, dict) or not isinstance(rp.get("name"), str):
            raise InputError(f"{src}: panel {i} has no name")
        pname = rp["name"]
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
            missing = [s for s in sizes if s not in shapes]
            if missing:
                raise InputError(f"{w}: no outline for size(s) {', '.join(missing)}")
        else:
            copy = _str(copy, f"{w}: copy_of")
            if shapes:
                raise InputError(f"{w}: a copy_of panel takes its outline from {copy!r}; "
                                 f"it has no shapes of its own")
        texture = rp.get("texture")
        if texture is not None:
            if not isinstance(texture, dict) or not isinstance(texture.get("image"), str):
                raise InputError(f"{w}: texture is {{\"image\": path, \"size\": [w, h]}}")
            if "size" in texture:
                sz = _list(texture["size"], f"{w}: texture size", "[w, h] in metres")
                if len(sz) != 2 or any(_num(x, f"{w}: texture size") <= 0 for x in sz):
                    raise InputError(f"{w}: texture size is [w, h] in metres, both > 0")
        fabric = rp.get("fabric")
        if fabric is not None and not isinstance(fabric, (str, dict)):
            raise InputError(f"{w}: fabric is a preset name or a custom fabric object")
        panels.append(Panel(pname, ptype, shapes, fold, copy,
                            _bool(rp.get("mirror", False), f"{w}: mirror"), fabric, texture,
                            _placement(rp.get("placement"), f"{w}"),
                            dict(_obj(rp.get("meta", {}), f"{w}: meta"))))
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
    for i, rs in enumerate(_list(data.get("seams", []), f"{src}: seams")):
        w = f"{src}: seam {i}"
        if not isinstance(rs, dict) or "a" not in rs or "b" not in rs:
            raise InputError(f"{w}: a seam is {{\"a\": side, \"b\": side, \"reverse\": bool}}")
        a = _side(rs["a"], f"{w}, side a")
        b = _side(rs["b"], f"{w}, side b")
        for side, lab in ((a, "a"), (b, "b")):
            if side.panel not in names:
                raise InputError(f"{w}, side {lab}: no panel named {side.panel!r}")
        ease = _num(rs.get("ease", 0.0), f"{w}: ease", 0.0)
        if ease >= 1.0:
            raise InputError(f"{w}: ease is a fraction in [0, 1), got {ease!r}")
        seams.append(Seam(a, b, _bool(rs.get("reverse", False), f"{w}: reverse"),
                          _str(rs.get("name", ""), f"{w}: name"),
                          _str(rs.get("kind", "seam"), f"{w}: kind"), ease))
    default = data.get("default_size")
    if default is not None and default not in sizes:
        raise InputError(f"{src}: default_size {default!r} is not in sizes")
    fabric = data.get("fabric", "cotton-jersey")
    if not isinstance(fabric, (str, dict)):
        raise InputError(f"{src}: fabric is a preset name or a custom fabric object")
    fit = data.get("fit", {})
    if not isinstance(fit, dict) or not all(k in sizes and isinstance(v, str)
                                            for k, v in fit.items()):
        raise InputError(f"{src}: fit maps sizes to sample-body names (bodies/recipes.json)")
    return Garment(name, gtype, list(sizes), panels, seams, fabric, default,
                   _str(data.get("description", ""), f"{src}: description"),
                   dict(_obj(data.get("source", {}), f"{src}: source")), dict(fit),
                   Path(path) if path else None)


def load_garment(path: str | Path) -> Garment:
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such garment file")
    try:
        data = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise InputError(f"{path}: not readable JSON ({exc})") from None
    return garment_from_dict(data, path)


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


def save_garment(g: Garment, path: str | Path) -> None:
    text = json.dumps(garment_to_dict(g), indent=1) + "\n"
    with atomic_path(path) as tmp:
        tmp.write_text(text)
