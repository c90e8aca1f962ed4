"""Outline geometry: straight and curved segments, flattening, lengths, areas, crossings.

An outline is a closed loop of :class:`Segment` s. Segment ``i`` starts at vertex ``i``
(``segment.start``) and ends where segment ``i + 1`` starts (the last one ends at vertex 0), so
an outline is closed by construction and vertex ``i`` is the start of segment ``i``.

Kinds:

- ``line``: straight to the next vertex;
- ``quadratic``: quadratic Bézier with one control point;
- ``cubic``: cubic Bézier with two control points;
- ``arc``: circular arc given by its DXF ``bulge`` = tan(θ/4) (θ the included angle, positive
  counter-clockwise); bulge 0 is a straight line, ±1 a half circle.

:func:`flatten` turns an outline into a polyline within a chord tolerance and tells where each
vertex landed (``vertex_index``), so seam ranges given in vertices stay valid after flattening.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

KINDS = ("line", "quadratic", "cubic", "arc")
_MAX_PIECES = 2000  # per segment


@dataclass
class Segment:
    kind: str
    start: np.ndarray                     # (2,) metres
    controls: list[np.ndarray] = field(default_factory=list)  # quadratic: 1, cubic: 2
    bulge: float = 0.0                    # arc only
    declared_end: np.ndarray | None = None   # an "end" the file stated (checked, not used)

    def copy(self) -> Segment:
        return Segment(self.kind, np.array(self.start, dtype=float),
                       [np.array(c, dtype=float) for c in self.controls], float(self.bulge))

    def pieces(self, end: np.ndarray, tolerance: float) -> int:
        """How many chords keep this segment within ``tolerance``."""
        p0 = np.asarray(self.start, dtype=float)
        p3 = np.asarray(end, dtype=float)
        if self.kind == "line" or (self.kind == "arc" and abs(self.bulge) < 1e-12):
            return 1
        if self.kind == "quadratic":
            return _pieces(2.0 * np.linalg.norm(p0 - 2 * self.controls[0] + p3), tolerance)
        if self.kind == "cubic":
            c1, c2 = self.controls
            return _pieces(6.0 * max(np.linalg.norm(p0 - 2 * c1 + c2),
                                     np.linalg.norm(c1 - 2 * c2 + p3)), tolerance)
        _, radius, _, theta = arc_geometry(p0, p3, self.bulge)
        if radius <= tolerance:
            return 1
        step = 2.0 * math.acos(max(-1.0, 1.0 - tolerance / radius))
        return int(min(_MAX_PIECES, max(1, math.ceil(abs(theta) / max(step, 1e-9)))))

    def points(self, end: np.ndarray, tolerance: float, pieces: int | None = None
               ) -> np.ndarray:
        """Points from ``start`` (included) to ``end`` (excluded) within chord ``tolerance``
        (or exactly ``pieces`` chords, equal steps of the curve's parameter)."""
        p0 = np.asarray(self.start, dtype=float)
        p3 = np.asarray(end, dtype=float)
        n_fixed = pieces
        if self.kind == "line" or (self.kind == "arc" and abs(self.bulge) < 1e-12):
            if n_fixed and n_fixed > 1:
                t = np.arange(n_fixed)[:, None] / n_fixed
                return p0 + t * (p3 - p0)
            return p0[None, :]
        if self.kind == "quadratic":
            c = np.asarray(self.controls[0], dtype=float)
            m = 2.0 * np.linalg.norm(p0 - 2 * c + p3)
            n = n_fixed or _pieces(m, tolerance)
            t = np.arange(n)[:, None] / n
            return (1 - t) ** 2 * p0 + 2 * (1 - t) * t * c + t ** 2 * p3
        if self.kind == "cubic":
            c1, c2 = (np.asarray(c, dtype=float) for c in self.controls)
            m = 6.0 * max(np.linalg.norm(p0 - 2 * c1 + c2), np.linalg.norm(c1 - 2 * c2 + p3))
            n = n_fixed or _pieces(m, tolerance)
            t = np.arange(n)[:, None] / n
            return ((1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * c1 + 3 * (1 - t) * t ** 2 * c2
                    + t ** 3 * p3)
        if self.kind == "arc":
            centre, radius, a0, theta = arc_geometry(p0, p3, self.bulge)
            n = n_fixed or self.pieces(p3, tolerance)
            a = a0 + theta * np.arange(n) / n
            return centre + radius * np.stack([np.cos(a), np.sin(a)], axis=1)
        raise ValueError(f"unknown segment kind {self.kind!r}")


def _pieces(second_derivative_bound: float, tolerance: float) -> int:
    # a curve with |B''| ≤ M cut into n equal parameter steps deviates ≤ M/(8 n²) from chords
    if second_derivative_bound <= 0:
        return 1
    n = math.ceil(math.sqrt(second_derivative_bound / (8.0 * tolerance)))
    return int(min(_MAX_PIECES, max(1, n)))


def arc_geometry(p0: np.ndarray, p1: np.ndarray, bulge: float):
    """(centre, radius, start angle, signed included angle) of a bulge arc from p0 to p1."""
    theta = 4.0 * math.atan(bulge)
    chord = p1 - p0
    c = float(np.linalg.norm(chord))
    if c == 0.0:
        return p0.copy(), 0.0, 0.0, 0.0
    radius = c / (2.0 * abs(math.sin(theta / 2.0)))
    mid = 0.5 * (p0 + p1)
    normal = np.array([-chord[1], chord[0]]) / c  # left of the chord
    # distance from the chord midpoint to the centre, signed towards the left for a CCW arc
    d = radius * math.cos(theta / 2.0) * (1.0 if theta > 0 else -1.0)
    centre = mid + normal * d
    a0 = math.atan2(p0[1] - centre[1], p0[0] - centre[0])
    return centre, radius, a0, theta


@dataclass
class Flat:
    """A flattened outline: ``points`` (M, 2), ``vertex_index`` (n,) where each outline vertex
    is in ``points``, ``edge_segment`` (M,) the segment that polyline edge k → k+1 belongs to."""
    points: np.ndarray
    vertex_index: np.ndarray
    edge_segment: np.ndarray


def flatten(segments: list[Segment], tolerance: float = 1e-3,
            pieces: list[int] | None = None) -> Flat:
    """The closed outline as a polyline within ``tolerance`` metres (first point not repeated).

    Vertex ``i`` (the start of segment ``i``) is ``points[vertex_index[i]]``: stable indices
    for seam ranges. ``pieces`` fixes the number of chords per segment instead (graded sizes
    flattened to the same point count)."""
    if tolerance <= 0:
        raise ValueError("flatten: tolerance must be positive")
    n = len(segments)
    chunks, vidx, eseg = [], [], []
    count = 0
    for i, seg in enumerate(segments):
        end = segments[(i + 1) % n].start
        pts = seg.points(end, tolerance, None if pieces is None else int(pieces[i]))
        vidx.append(count)
        chunks.append(pts)
        eseg.append(np.full(len(pts), i, dtype=np.int64))
        count += len(pts)
    return Flat(np.concatenate(chunks, axis=0), np.asarray(vidx, dtype=np.int64),
                np.concatenate(eseg))


def polygon_area(points: np.ndarray) -> float:
    """Signed area (positive counter-clockwise) of a closed polygon (first point not repeated)."""
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def polyline_length(points: np.ndarray, closed: bool = True) -> float:
    p = np.concatenate([points, points[:1]]) if closed else points
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


def segment_lengths(segments: list[Segment], tolerance: float = 1e-5) -> np.ndarray:
    """Arc length of every segment."""
    flat = flatten(segments, tolerance)
    p = flat.points
    d = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
    return np.bincount(flat.edge_segment, weights=d, minlength=len(segments))


def run_length(lengths: np.ndarray, start: int, end: int) -> float:
    """Length of the run from vertex ``start`` forward (wrapping) to vertex ``end``."""
    n = len(lengths)
    k = (end - start) % n
    if k == 0:
        k = n  # the whole loop
    idx = (start + np.arange(k)) % n
    return float(lengths[idx].sum())


def _x_candidates(lo: np.ndarray, hi: np.ndarray, tol: float):
    """For each edge i: (order, left, right) such that the edges ``order[left[i]:right[i]]``
    are those whose x range starts within edge i's (widened by ``tol``). Every pair of edges
    whose x ranges overlap is among them, found from the edge whose range starts first."""
    order = np.argsort(lo[:, 0], kind="stable")
    starts = lo[order, 0]
    left = np.searchsorted(starts, lo[:, 0] - tol, side="left")
    right = np.searchsorted(starts, hi[:, 0] + tol, side="right")
    return order, left, right


def crossing_work(points: np.ndarray, eps: float = 1e-9) -> int:
    """How many edge pairs :func:`self_crossings` tests exactly (its cost, known cheaply)."""
    p = np.asarray(points, dtype=float)
    if len(p) < 4:
        return 0
    b = np.roll(p, -1, axis=0)
    lo, hi = np.minimum(p, b), np.maximum(p, b)
    tol = eps * max(float(np.ptp(p, axis=0).max()), 1e-12)
    _, left, right = _x_candidates(lo, hi, tol)
    return int(np.sum(right - left))


def self_crossings(points: np.ndarray, eps: float = 1e-9, limit: int = 5) -> list[tuple]:
    """Pairs (i, j, point) of non-adjacent edges of the closed polyline that touch or cross,
    the first ``limit`` in (i, j) order (i < j).

    Edge k joins points k and k+1 (mod M). Candidates come from a sweep over the edges' x
    ranges (sorted), so an outline costs about M log M rather than M²; they are tested in
    vectorised blocks."""
    p = np.asarray(points, dtype=float)
    m = len(p)
    if m < 4:
        return []
    a = p
    b = np.roll(p, -1, axis=0)
    lo = np.minimum(a, b)
    hi = np.maximum(a, b)
    scale = max(float(np.ptp(p, axis=0).max()), 1e-12)
    tol = eps * scale
    order, left, right = _x_candidates(lo, hi, tol)
    counts = right - left
    best = np.zeros(0, dtype=np.int64)   # the smallest hit keys i·m + j so far (≤ limit)
    edges = np.arange(m)
    start = 0
    while start < m:   # blocks of edges with at most ~2M candidate pairs each
        cum = np.cumsum(counts[start:])
        stop = start + max(1, int(np.searchsorted(cum, 2_000_000, side="right")))
        blk = edges[start:stop]
        n = counts[blk]
        src = np.repeat(blk, n)
        offs = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)
        dst = order[np.repeat(left[blk], n) + offs]
        start = stop
        i, j = np.minimum(src, dst), np.maximum(src, dst)
        keep = (j > i) & (j != (i + 1) % m) & (i != (j + 1) % m)
        i, j = i[keep], j[keep]
        ov = ((lo[i, 0] <= hi[j, 0] + tol) & (lo[j, 0] <= hi[i, 0] + tol)
              & (lo[i, 1] <= hi[j, 1] + tol) & (lo[j, 1] <= hi[i, 1] + tol))
        i, j = i[ov], j[ov]
        if len(i) == 0:
            continue
        hit = _touch(a[i], b[i], a[j], b[j], tol)
        keys = np.unique(np.concatenate([best, i[hit].astype(np.int64) * m + j[hit]]))
        best = keys[:limit]
    out = []
    for key in best:
        i, j = divmod(int(key), m)
        a1, b1 = a[i], b[i]
        o3 = _orient(a[[j]], b[[j]], a1[None])[0]
        o4 = _orient(a[[j]], b[[j]], b1[None])[0]
        den = o3 - o4
        t = o3 / den if abs(den) > 1e-300 else 0.0
        out.append((i, j, a1 + t * (b1 - a1)))
    return out


def _touch(a1, b1, a2, b2, tol: float) -> np.ndarray:
    """Whether segments a1–b1 and a2–b2 (whose boxes overlap) touch or cross; collinear
    segments whose boxes overlap touch."""
    o1 = _orient(a1, b1, a2)
    o2 = _orient(a1, b1, b2)
    o3 = _orient(a2, b2, a1)
    o4 = _orient(a2, b2, b1)
    l1 = np.linalg.norm(b1 - a1, axis=1) * tol
    l2 = np.linalg.norm(b2 - a2, axis=1) * tol
    return (o1 * o2 <= (l1 ** 2)) & (o3 * o4 <= (l2 ** 2))


def _orient(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


# --- rigid edits (the paper's editor: move, rotate, mirror) ---------------------------------

def transform_points(pts: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """Apply a 2×3 affine ``matrix`` to (…, 2) points."""
    pts = np.asarray(pts, dtype=float)
    return pts @ matrix[:, :2].T + matrix[:, 2]


def move_matrix(dx: float, dy: float) -> np.ndarray:
    return np.array([[1.0, 0.0, dx], [0.0, 1.0, dy]])


def rotate_matrix(degrees: float, centre=(0.0, 0.0)) -> np.ndarray:
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    cx, cy = centre
    return np.array([[c, -s, cx - c * cx + s * cy], [s, c, cy - s * cx - c * cy]])


def mirror_matrix(axis: str = "x", at: float = 0.0) -> np.ndarray:
    """Mirror across the vertical line x = ``at`` (axis ``"x"``: x → 2at − x) or the
    horizontal line y = ``at`` (axis ``"y"``)."""
    if axis == "x":
        return np.array([[-1.0, 0.0, 2 * at], [0.0, 1.0, 0.0]])
    if axis == "y":
        return np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 2 * at]])
    raise ValueError(f"mirror axis must be 'x' or 'y', not {axis!r}")


def line_mirror_matrix(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Reflection across the line through p and q."""
    d = np.asarray(q, dtype=float) - np.asarray(p, dtype=float)
    d = d / np.linalg.norm(d)
    r = 2.0 * np.outer(d, d) - np.eye(2)
    t = np.asarray(p, dtype=float) - r @ np.asarray(p, dtype=float)
    return np.concatenate([r, t[:, None]], axis=1)


def transform_segments(segments: list[Segment], matrix: np.ndarray) -> list[Segment]:
    """Segments under an affine map; a reflection (det < 0) reverses the loop so that it keeps
    its orientation, and vertex ``i`` of the result is the image of vertex ``(-i) mod n``."""
    n = len(segments)
    det = float(np.linalg.det(matrix[:, :2]))
    out = []
    for s in segments:
        out.append(Segment(s.kind, transform_points(s.start, matrix),
                           [transform_points(c, matrix) for c in s.controls],
                           s.bulge if det > 0 else -s.bulge))
    if det > 0:
        return out
    return reverse_segments(out) if n else out


def reverse_segments(segments: list[Segment]) -> list[Segment]:
    """The same loop walked the other way: vertex ``i`` of the result is vertex ``(-i) mod n``
    of the input; segment ``i`` of the result is input segment ``(-i - 1) mod n`` reversed."""
    n = len(segments)
    out = []
    for i in range(n):
        src = segments[(-i - 1) % n]
        start = segments[(-i) % n].start  # the end of src
        out.append(Segment(src.kind, np.array(start, dtype=float),
                           [np.array(c, dtype=float) for c in reversed(src.controls)],
                           -src.bulge))
    return out


# --- splitting an edge (to put a seam end where no vertex is) --------------------------------

def _split_segment(seg: Segment, end: np.ndarray, t: float) -> tuple[Segment, Segment]:
    p0, p1 = np.asarray(seg.start, float), np.asarray(end, float)
    if seg.kind == "line" or (seg.kind == "arc" and abs(seg.bulge) < 1e-12):
        m = p0 + t * (p1 - p0)
        return Segment(seg.kind, p0.copy()), Segment(seg.kind, m)
    if seg.kind == "quadratic":
        c = seg.controls[0]
        a, b = p0 + t * (c - p0), c + t * (p1 - c)
        m = a + t * (b - a)
        return Segment("quadratic", p0.copy(), [a]), Segment("quadratic", m, [b])
    if seg.kind == "cubic":
        c1, c2 = seg.controls
        a, b, c = p0 + t * (c1 - p0), c1 + t * (c2 - c1), c2 + t * (p1 - c2)
        d, e = a + t * (b - a), b + t * (c - b)
        m = d + t * (e - d)
        return Segment("cubic", p0.copy(), [a, d]), Segment("cubic", m, [e, c])
    centre, radius, a0, theta = arc_geometry(p0, p1, seg.bulge)
    am = a0 + t * theta
    m = centre + radius * np.array([math.cos(am), math.sin(am)])
    return (Segment("arc", p0.copy(), bulge=math.tan(t * theta / 4.0)),
            Segment("arc", m, bulge=math.tan((1.0 - t) * theta / 4.0)))


def split_at_length(segments: list[Segment], vertex: int, length: float
                    ) -> tuple[list[Segment], int]:
    """Insert a vertex at arc ``length`` forward from ``vertex``; returns the new segments
    and the new vertex's number (vertices after it shift by one)."""
    n = len(segments)
    lens = segment_lengths(segments)
    acc = 0.0
    for step in range(n):
        k = (vertex + step) % n
        if acc + lens[k] > length:
            local = length - acc
            seg, end = segments[k], segments[(k + 1) % n].start
            pts = np.concatenate([seg.points(end, 1e-6), np.asarray(end, float)[None]])
            cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0),
                                                                  axis=1))])
            params = np.linspace(0.0, 1.0, len(pts))
            if seg.kind == "arc" or seg.kind == "line":
                t = local / max(lens[k], 1e-300)
            else:   # Bézier points were sampled at uniform parameter steps
                t = float(np.interp(local, cum, params))
            t = min(max(t, 1e-6), 1.0 - 1e-6)
            first, second = _split_segment(seg, end, t)
            out = list(segments[:k]) + [first, second] + list(segments[k + 1:])
            return out, k + 1
        acc += lens[k]
    raise ValueError(f"length {length} is longer than the outline")
