"""The garment model (``docs/garment-format.md``).

A :class:`Garment` is what a merchant uploads: a garment type, its sizes, panels (each with a
closed outline per size — a panel of some sizes only, such as a label or a pocket of the larger
sizes, has outlines in those and is not cut in the others —, grain line, cut-on-fold or
mirrored copy, texture, fabric, placement hint) and seams between outline runs. Its JSON
format is read and written by
:mod:`catwalk.exchange.garment_json`; :mod:`catwalk.garment.check` validates the geometry and
the seams.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.garment.geometry import (
    Flat,
    Segment,
    flatten,
    line_mirror_matrix,
    mirror_matrix,
    rotate_matrix,
    transform_points,
    transform_segments,
)

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

    def source_panel(self, panel: str | Panel) -> Panel:
        """The panel whose outlines ``panel`` uses (itself, or the source of a copy)."""
        p = self.panel(panel) if isinstance(panel, str) else panel
        seen = set()
        while p.copy_of is not None and p.name not in seen:
            seen.add(p.name)
            p = self.panel(p.copy_of)
        return p

    def cut_in(self, panel: str | Panel, size: str) -> bool:
        """Whether the panel is cut in ``size``: it has an outline there (a copy: its source)."""
        return size in self.source_panel(panel).shapes

    def panel_sizes(self, panel: str | Panel) -> list[str]:
        """The sizes the panel is cut in, in grading order."""
        shapes = self.source_panel(panel).shapes
        return [s for s in self.sizes if s in shapes]

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
    """Pieces as cut in ``size`` (the panels it has; seams on another size's panels left out)
    and seams as ``(piece_a, start_a, end_a, piece_b, start_b, end_b, reverse)`` in *flattened*
    point indices, ready for :class:`catwalk.cloth.builder.Seam` (runs go forward from start
    to end).

    With ``align_grain`` a piece whose grain line is not along ±y (the builder's warp) is
    turned about the grain line's start by the smallest angle that makes it so (a grain line
    has no preferred sense, so a piece is never turned by more than 90°)."""
    size = garment.size(size)
    pieces, index = [], {}
    for p in garment.panels:
        if not garment.cut_in(p, size):
            continue   # a panel of other sizes only
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
        if s.a.panel not in index or s.b.panel not in index:
            continue   # a seam on a panel this size does not have
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
