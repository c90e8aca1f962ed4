"""What the DXF import repairs in a piece's boundary, and how it says so.

Real pattern exports carry slips a merchant cannot fix in their CAD: the same point twice in a
row (a zero-length edge), and a corner or a notch drawn twice so that the outline crosses
itself in a small loop. Each repair is a :class:`Note` (the import's warnings); nothing is
changed without one.

A boundary here is a closed loop of ``(x, y, bulge)`` vertices in metres (the first not
repeated at the end; the bulge is that of the edge to the next vertex, DXF's tan(θ/4)).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from catwalk.errors import InputError
from catwalk.garment.check import CROSSING_TOLERANCE, MAX_OUTLINE_WORK
from catwalk.garment.geometry import (
    Segment,
    crossing_work,
    flatten,
    polygon_area,
    self_crossings,
)

DUPLICATE = 5e-5      # metres: consecutive points closer than this are one point
MAX_LOOP = 6.5e-3     # metres: a self-crossing loop at most this across is removed (a corner,
                      # or a quarter-inch notch, drawn twice)
MAX_LOOP_SHARE = 0.01  # … and at most this share of the piece's area
MAX_REPAIRS = 50      # loops removed (and crossing arcs made chords) in one boundary


@dataclass
class Note:
    """One repair or assumption of the import: ``code`` (what kind), ``text`` (what was done,
    without the file and the piece), the piece and size it concerns (None: the whole file, or
    every size of the piece) and the numbers the text gives (``data``)."""
    code: str
    text: str
    piece: str | None = None
    size: str | None = None
    data: dict = field(default_factory=dict)

    def where(self) -> str:
        if self.piece is None:
            return ""
        return f"piece {self.piece!r}" + (f" (size {self.size})" if self.size else "") + ": "

    def as_warning(self, path: str) -> dict:
        """The warning as the CLI prints it and the API returns it: ``{"code", "message",
        "piece"?, "size"?, …data}``."""
        out = {"code": self.code, "message": f"{path}: {self.where()}{self.text}"}
        if self.piece is not None:
            out["piece"] = self.piece
        if self.size is not None:
            out["size"] = self.size
        return out | self.data

    def on_panel(self) -> dict:
        """The note as the panel keeps it (``meta.import_warnings``): the size, not the piece
        (the panel is the piece, whatever it is renamed to)."""
        text = f"size {self.size}: {self.text}" if self.size else self.text
        return {"code": self.code, "message": text} | ({"size": self.size} if self.size else {})


def drop_repeats(loop: list[tuple]) -> tuple[list[tuple], int]:
    """The loop without a vertex closer than :data:`DUPLICATE` to the one before it (the last
    one compared with the first too): the edge between them has no length. The first copy's
    position is kept, with the last copy's bulge (the edge that leaves it). Returns the loop
    and how many vertices were dropped."""
    out: list[tuple] = []
    for x, y, b in loop:
        if out and abs(out[-1][0] - x) < DUPLICATE and abs(out[-1][1] - y) < DUPLICATE \
                and np.hypot(out[-1][0] - x, out[-1][1] - y) < DUPLICATE:
            out[-1] = (out[-1][0], out[-1][1], b)
            continue
        out.append((x, y, b))
    while len(out) > 1 and np.hypot(out[-1][0] - out[0][0], out[-1][1] - out[0][1]) < DUPLICATE:
        out.pop()
    return out, len(loop) - len(out)


def segments_of(loop: list[tuple]) -> list[Segment]:
    return [Segment("arc" if abs(b) > 1e-12 else "line", np.array([x, y]), bulge=b)
            for x, y, b in loop]


def _meet(a, b, c, d) -> np.ndarray:
    """Where segment a–b meets segment c–d (they cross or touch): their intersection, or for
    parallel ones an end of one lying on the other."""
    r, s = b - a, d - c
    den = r[0] * s[1] - r[1] * s[0]
    scale = max(float(np.linalg.norm(r) * np.linalg.norm(s)), 1e-300)
    if abs(den) > 1e-12 * scale:
        t = ((c[0] - a[0]) * s[1] - (c[1] - a[1]) * s[0]) / den
        return a + min(max(t, 0.0), 1.0) * r

    def dist(p, u, v):
        w = v - u
        t = min(max(float(np.dot(p - u, w) / max(float(np.dot(w, w)), 1e-300)), 0.0), 1.0)
        return float(np.linalg.norm(u + t * w - p))

    candidates = [(dist(c, a, b), c), (dist(b, c, d), b), (dist(d, a, b), d), (dist(a, c, d), a)]
    return min(candidates, key=lambda q: q[0])[1].copy()


def _flat(loop: list[tuple]):
    """The loop flattened for the crossing test as the checker flattens it: its points and,
    per polyline edge, the vertex (edge of the loop) it belongs to."""
    flat = flatten(segments_of(loop), CROSSING_TOLERANCE)
    p = flat.points
    keep = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1) > 1e-9
    return p[keep], flat.edge_segment[keep]


def _extent(points: np.ndarray) -> float:
    return float(np.ptp(points, axis=0).max())


def remove_small_loops(loop: list[tuple], where: str, add) -> list[tuple]:
    """The loop with every small self-crossing loop (at most :data:`MAX_LOOP` across and
    :data:`MAX_LOOP_SHARE` of the piece's area) cut off at the crossing, each told by
    ``add(code, text, **data)``; a larger crossing refused (InputError naming the
    place). Coordinates in the messages are from the loop's lower-left corner (the piece's, as
    it is placed at the origin). Arcs that cross are first made chords (within 0.1 mm)."""
    for _ in range(MAX_REPAIRS + 1):
        pts, edge = _flat(loop)
        if len(pts) < 4 or crossing_work(pts) > MAX_OUTLINE_WORK:
            return loop   # nothing to cross, or too convoluted to test: the checker says so
        hits = self_crossings(pts, eps=1e-9, limit=1)
        if not hits:
            return loop
        i, j, at = hits[0]
        si, sj = int(edge[i]), int(edge[j])
        arcs = [k for k in {si, sj} if abs(loop[k][2]) > 1e-12]
        if arcs:   # a crossing curve: its chords (within the checker's tolerance) instead
            loop = _arcs_to_chords(loop, arcs)
            continue
        loop = _cut_loop(loop, pts, i, j, si, sj, where, add)
    raise InputError(f"{where}: the outline crosses itself more than {MAX_REPAIRS} times: "
                     "not a drawing slip; correct the outline in the pattern CAD")


def _arcs_to_chords(loop: list[tuple], arcs: list[int]) -> list[tuple]:
    out = []
    n = len(loop)
    for k, (x, y, b) in enumerate(loop):
        if k not in arcs:
            out.append((x, y, b))
            continue
        seg = Segment("arc", np.array([x, y]), bulge=b)
        nxt = np.array(loop[(k + 1) % n][:2])
        out.extend((float(px), float(py), 0.0)
                   for px, py in seg.points(nxt, CROSSING_TOLERANCE))
    return out


def _cut_loop(loop, pts, i, j, si, sj, where, add) -> list[tuple]:
    """Cut off the smaller of the two loops the crossing of straight edges si and sj (flat
    edges i and j) makes, or refuse the crossing when it is not small."""
    x = _meet(pts[i], pts[(i + 1) % len(pts)], pts[j], pts[(j + 1) % len(pts)])
    inner = np.vstack([pts[i + 1:j + 1], x])
    outer = np.vstack([pts[j + 1:], pts[:i + 1], x])
    sizes = (_extent(inner), _extent(outer))
    k = int(np.argmin(sizes))
    small, rest = (inner, outer) if k == 0 else (outer, inner)
    area, whole = abs(polygon_area(small)), abs(polygon_area(rest))
    at = x - pts.min(axis=0)
    if sizes[k] > MAX_LOOP or area > MAX_LOOP_SHARE * whole:
        raise InputError(
            f"{where}: the outline crosses itself near ({at[0] * 100:.1f}, {at[1] * 100:.1f}) "
            f"cm from the piece's lower-left corner, making a loop {sizes[k] * 100:.1f} cm "
            f"across ({area * 1e4:.1f} cm²): more than a drawing slip (a loop at most "
            f"{MAX_LOOP * 1000:g} mm across is removed); correct the outline in the pattern "
            "CAD")
    xs = (float(x[0]), float(x[1]), 0.0)
    if k == 0:    # vertices si+1 … sj form the loop: the crossing takes their place
        out = loop[:si + 1] + [xs] + loop[sj + 1:]
    else:         # vertices sj+1 … (wrapping) … si form it
        out = [xs] + loop[si + 1:sj + 1]
    add("loop-removed",
        f"the outline crossed itself in a small loop near ({at[0] * 100:.1f}, "
        f"{at[1] * 100:.1f}) cm from the piece's lower-left corner: the loop "
        f"({sizes[k] * 1000:.1f} mm across, {area * 1e6:.1f} mm²) removed",
        at=[round(float(at[0]), 5), round(float(at[1]), 5)],
        loop_mm=round(sizes[k] * 1000, 2), area_mm2=round(area * 1e6, 2))
    return drop_repeats(out)[0]
