"""Build a cloth :class:`~catwalk.cloth.model.ClothModel` from 2D panels (paper §2, §5).

Usage::

    from catwalk.cloth.builder import Panel, Seam, build_cloth
    front = Panel(outline_front, name="front", placement=M_front)   # (N, 2) metres
    back = Panel(outline_back, name="back", placement=M_back)
    seams = [Seam(0, 3, 5, 1, 7, 9, reverse=True)]                   # outline vertex ranges
    model = build_cloth([front, back], seams, fabric="cotton-jersey", h=0.015)

**Panels.** ``Panel.outline`` is a closed polygon in metres (first vertex not repeated; curves
flattened to polylines beforehand), in the pattern plane whose +y is the grain line (warp) and
+x the weft. ``Panel.placement`` puts the panel in the world: ``None`` (u, v) → (u, v, 0), a
(3, 4) affine matrix applied to (u, v, 0, 1), or a callable ``f(uv (n, 2)) -> (n, 3)`` (e.g. to
curve a panel round a cylinder). Panels are independent: points are never shared between panels.

**Seams.** ``Seam(panel_a, start_a, end_a, panel_b, start_b, end_b, reverse=False)`` joins the
outline run of panel ``a`` from vertex ``start_a`` forward (increasing index, wrapping) to vertex
``end_a`` with the run ``start_b`` → ``end_b`` of panel ``b``. Both runs get the same number of
points, spaced uniformly by arc length (so corners strictly inside a seam run are not kept);
point k of ``a`` is paired with point k of ``b``, or with point k from the end of ``b`` when
``reverse`` is true (two panels of the same orientation sewn edge to edge need ``reverse``).
The pairs are ``model.seam_a[i], model.seam_b[i]`` (``model.seam_id[i]`` is the seam's index in
``seams``). Runs of one panel must not overlap.

**Points.** Outline edges outside seams are sampled at spacing ≤ h with their vertices kept;
inside, a grid at spacing h anchored at the panel's lower-left bounding-box corner, keeping grid
points at least 0.45·h from the outline. The same points are triangulated (Delaunay, triangles
whose centroid is inside the outline) for rendering and collision; ``model.uv`` holds the
pattern coordinates (texture coordinates).

**Springs** (Provot): stretch [i,j]–[i+1,j], [i,j]–[i,j+1]; shear (both diagonals); bend
[i,j]–[i+2,j], [i,j]–[i,j+2]. Outline points that fall on grid nodes are grid points (an aligned
rectangle is exactly Provot's grid); the others get equivalent springs: every triangle edge at
them (shear when it runs diagonally, stretch otherwise), bend to the next-but-one outline point
and to the grid point two steps inward. Rest lengths from the 2D pattern, constants from the
fabric by :func:`catwalk.cloth.fabrics.spring_constants`, masses = density × area (a third of each
triangle to each corner, at least ¼·h² each, rescaled to the panel's total).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.spatial import Delaunay

from catwalk.cloth.fabrics import Fabric, get_fabric, spring_constants
from catwalk.cloth.model import BEND, SHEAR, STRETCH, ClothModel
from catwalk.errors import InputError

DEFAULT_H = 0.015
MAX_POINTS = 400_000
_CLEARANCE = 0.45  # grid points closer than this × h to the outline are dropped
_MIN_AREA = 0.5  # least area (× h²) a point's mass stands for: a straight edge point's
_MAX_OMEGA2 = 1.5  # no point's Σk/m above this × the median point's (see build_cloth)


@dataclass
class Panel:
    outline: np.ndarray
    name: str = ""
    placement: np.ndarray | Callable | None = None


@dataclass
class Seam:
    panel_a: int
    start_a: int
    end_a: int
    panel_b: int
    start_b: int
    end_b: int
    reverse: bool = False


def rectangle(width: float, height: float) -> np.ndarray:
    """Outline of a ``width`` × ``height`` rectangle with its lower-left corner at the origin."""
    return np.array([[0.0, 0.0], [width, 0.0], [width, height], [0.0, height]])


def circle(radius: float, segments: int = 256, centre=(0.0, 0.0)) -> np.ndarray:
    """Outline of a circle (a regular polygon of ``segments`` vertices)."""
    t = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    return np.column_stack([centre[0] + radius * np.cos(t), centre[1] + radius * np.sin(t)])


def horizontal(height: float = 0.0) -> np.ndarray:
    """Placement laying a panel flat at ``y = height``: (u, v) → (u, height, −v), normal +Y."""
    return np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, height], [0.0, -1.0, 0.0, 0.0]])


def vertical(offset=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Placement hanging a panel in the XY plane: (u, v) → (u, v, 0) + offset, normal +Z."""
    m = np.zeros((3, 4))
    m[0, 0] = m[1, 1] = 1.0
    m[:, 3] = offset
    return m


# --- geometry helpers ------------------------------------------------------------------------

def _polygon_area(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _inside(poly: np.ndarray, pts: np.ndarray) -> np.ndarray:
    inside = np.zeros(len(pts), dtype=bool)
    px, py = pts[:, 0], pts[:, 1]
    n = len(poly)
    for k in range(n):
        x1, y1 = poly[k]
        x2, y2 = poly[(k + 1) % n]
        if y1 == y2:
            continue
        cond = (y1 > py) != (y2 > py)
        xint = x1 + (py - y1) * (x2 - x1) / (y2 - y1)
        inside ^= cond & (px < xint)
    return inside


def _distance_to_outline(poly: np.ndarray, pts: np.ndarray) -> np.ndarray:
    best = np.full(len(pts), np.inf)
    n = len(poly)
    for k in range(n):
        a = poly[k]
        b = poly[(k + 1) % n]
        ab = b - a
        ll = float(ab @ ab)
        if ll == 0.0:
            d = np.linalg.norm(pts - a, axis=1)
        else:
            t = np.clip((pts - a) @ ab / ll, 0.0, 1.0)
            d = np.linalg.norm(pts - (a + t[:, None] * ab), axis=1)
        np.minimum(best, d, out=best)
    return best


def _run(poly: np.ndarray, start: int, end: int) -> np.ndarray:
    n = len(poly)
    idx = [start]
    k = start
    while k != end:
        k = (k + 1) % n
        idx.append(k)
    return poly[idx]


def _sample(path: np.ndarray, intervals: int) -> np.ndarray:
    """``intervals`` points spaced uniformly by arc length along ``path``, the start included and
    the end excluded."""
    seg = np.linalg.norm(np.diff(path, axis=0), axis=1)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    s = cum[-1] * np.arange(intervals) / intervals
    return np.column_stack([np.interp(s, cum, path[:, 0]), np.interp(s, cum, path[:, 1])])


def _place(panel: Panel, uv: np.ndarray, index: int) -> np.ndarray:
    pl = panel.placement
    if pl is None:
        return np.column_stack([uv, np.zeros(len(uv))])
    if callable(pl):
        out = np.asarray(pl(uv), dtype=np.float64)
        if out.shape != (len(uv), 3) or not np.all(np.isfinite(out)):
            raise InputError(f"panel {index}: placement callable must return finite "
                               f"({len(uv)}, 3) positions")
        return out
    m = np.asarray(pl, dtype=np.float64)
    if m.shape != (3, 4) or not np.all(np.isfinite(m)):
        raise InputError(f"panel {index}: placement must be a finite (3, 4) matrix, a callable "
                           "or None")
    return uv @ m[:, :2].T + m[:, 3]


# --- the builder -----------------------------------------------------------------------------

def _check_panels(panels: Sequence[Panel]) -> list[np.ndarray]:
    if not panels:
        raise InputError("no panels to build a cloth from")
    outlines = []
    for i, p in enumerate(panels):
        if not isinstance(p, Panel):
            raise InputError(f"panel {i}: expected a Panel, got {type(p).__name__}")
        o = np.asarray(p.outline, dtype=np.float64)
        if o.ndim != 2 or o.shape[1] != 2 or len(o) < 3:
            raise InputError(f"panel {i} ({p.name}): outline must be (N ≥ 3, 2) metres, "
                               f"got shape {o.shape}")
        if not np.all(np.isfinite(o)):
            raise InputError(f"panel {i} ({p.name}): outline has non-finite coordinates")
        if np.allclose(o[0], o[-1]):
            o = o[:-1]
        if abs(_polygon_area(o)) < 1e-8:
            raise InputError(f"panel {i} ({p.name}): outline encloses no area")
        outlines.append(o)
    return outlines


def _seam_runs(seams, outlines):
    """For each seam: both runs (paths) and the shared interval count is set later."""
    runs = []  # (panel, start, end, seam index, side)
    for si, s in enumerate(seams):
        if not isinstance(s, Seam):
            raise InputError(f"seam {si}: expected a Seam, got {type(s).__name__}")
        for side, (p, a, b) in enumerate(((s.panel_a, s.start_a, s.end_a),
                                          (s.panel_b, s.start_b, s.end_b))):
            if not (0 <= p < len(outlines)):
                raise InputError(f"seam {si}: panel {p} does not exist")
            n = len(outlines[p])
            if not (0 <= a < n and 0 <= b < n):
                raise InputError(f"seam {si}: outline index out of range for panel {p} "
                                   f"({a}, {b}; the outline has {n} vertices)")
            if a == b:
                raise InputError(f"seam {si}: a seam run needs two different vertices")
            runs.append((p, a, b, si, side))
    return runs


def _seam_intervals(seams, runs, outlines, h: float) -> dict:
    """Each seam's interval count, shared by its two runs (the longer run at spacing ≤ h)."""
    lengths = {}
    for p, a, b, si, side in runs:
        path = _run(outlines[p], a, b)
        lengths[(si, side)] = float(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1)))
    seam_n = {si: max(1, math.ceil(max(lengths[(si, 0)], lengths[(si, 1)]) / h - 1e-9))
              for si in range(len(seams))}
    for si in range(len(seams)):
        if min(lengths[(si, 0)], lengths[(si, 1)]) <= 0:
            raise InputError(f"seam {si}: a seam run has zero length")
    return seam_n


def _outline_points(pi: int, o: np.ndarray, my_runs: list, seam_n: dict, h: float):
    """The panel's outline points (the seam runs at their seams' intervals, the other edges
    at spacing ≤ h), walked from a run's start (or vertex 0); and where each run's first
    point is among them."""
    n = len(o)
    owner = -np.ones(n, dtype=np.int64)  # edge k = (k, k+1) belongs to run index
    for ri, (_, a, b, _si, _side) in enumerate(my_runs):
        k = a
        while k != b:
            if owner[k] >= 0:
                raise InputError(f"panel {pi}: seam runs overlap at outline edge {k}")
            owner[k] = ri
            k = (k + 1) % n
    start = my_runs[0][1] if my_runs else 0
    pts, run_first = [], {}
    k = start
    walked = 0
    while walked < n:
        ri = owner[k]
        if ri >= 0:
            _, a, b, si, side = my_runs[ri]
            path = _run(o, a, b)
            run_first[ri] = len(pts)
            pts.extend(_sample(path, seam_n[si]))
            steps = (b - a) % n
            k = b
            walked += steps
        else:
            path = o[[k, (k + 1) % n]]
            length = float(np.linalg.norm(path[1] - path[0]))
            if length > 1e-12:
                pts.extend(_sample(path, max(1, math.ceil(length / h - 1e-9))))
            k = (k + 1) % n
            walked += 1
    return np.asarray(pts), run_first


def _interior_grid(o: np.ndarray, h: float):
    """Provot's grid inside the outline, off it by at least _CLEARANCE·h: (uv, i, j, ni, nj,
    the grid's origin)."""
    lo = o.min(axis=0)
    hi = o.max(axis=0)
    ni = int(math.floor((hi[0] - lo[0]) / h + 1e-9)) + 1
    nj = int(math.floor((hi[1] - lo[1]) / h + 1e-9)) + 1
    ii, jj = np.meshgrid(np.arange(ni), np.arange(nj))  # row-major: j outer
    ii, jj = ii.ravel(), jj.ravel()
    g_uv = lo + h * np.column_stack([ii, jj]).astype(np.float64)
    keep = _inside(o, g_uv)
    keep[keep] = _distance_to_outline(o, g_uv[keep]) >= _CLEARANCE * h
    return g_uv[keep], ii[keep], jj[keep], ni, nj, lo


def _triangulate(panel_uv: np.ndarray, o: np.ndarray, h: float) -> np.ndarray:
    """The panel's points triangulated (Delaunay), the triangles inside the outline and not
    degenerate, counter-clockwise in the pattern plane."""
    tri = Delaunay(panel_uv).simplices
    c = panel_uv[tri].mean(axis=1)
    e1 = panel_uv[tri[:, 1]] - panel_uv[tri[:, 0]]
    e2 = panel_uv[tri[:, 2]] - panel_uv[tri[:, 0]]
    area = 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    ok = _inside(o, c) & (np.abs(area) > 1e-6 * h * h)
    tri = tri[ok]
    flip = area[ok] < 0
    tri[flip] = tri[flip][:, [0, 2, 1]]
    return tri


@dataclass
class _Points:
    """Every panel's points as they are made (the panels' outline points first, then their
    grids), in global numbering."""
    uv: list = field(default_factory=list)
    panel: list = field(default_factory=list)
    boundary: list = field(default_factory=list)
    grid: list = field(default_factory=list)      # per panel: (index, i, j, ni, nj)
    outline: list = field(default_factory=list)   # per panel: its outline's indices, in order
    seam_pts: dict = field(default_factory=dict)  # (si, side) -> indices along the run
    triangles: list = field(default_factory=list)
    count: int = 0


def _add_panel(pts: _Points, pi: int, panel: Panel, o: np.ndarray, runs, seam_n, h) -> None:
    """The panel's points, triangles and grid, appended to ``pts``."""
    base = pts.count
    my_runs = [r for r in runs if r[0] == pi]
    b_uv, run_first = _outline_points(pi, o, my_runs, seam_n, h)
    nb = len(b_uv)
    for ri, (_, _a, _b, si, side) in enumerate(my_runs):
        first = run_first[ri]
        idx = (first + np.arange(seam_n[si] + 1)) % nb
        pts.seam_pts[(si, side)] = base + idx
    g_uv, ii, jj, ni, nj, lo = _interior_grid(o, h)
    panel_uv = np.vstack([b_uv, g_uv])
    tri = _triangulate(panel_uv, o, h)
    used = np.zeros(len(panel_uv), dtype=bool)
    used[tri.ravel()] = True
    if not used[:nb].all():
        raise InputError(f"panel {pi} ({panel.name}): outline too fine for h = {h} "
                         "(an outline point is in no triangle); smooth the outline or "
                         "use a smaller h")
    pts.uv.append(panel_uv)
    pts.panel.append(np.full(len(panel_uv), pi, dtype=np.int32))
    bnd = np.zeros(len(panel_uv), dtype=bool)
    bnd[:nb] = True
    pts.boundary.append(bnd)
    # outline points that sit on grid nodes join the grid (an aligned rectangle becomes
    # exactly Provot's grid)
    fb = (b_uv - lo) / h
    rb = np.rint(fb)
    on = np.all(np.abs(fb - rb) < 1e-7, axis=1)
    on &= (rb[:, 0] >= 0) & (rb[:, 0] < ni) & (rb[:, 1] >= 0) & (rb[:, 1] < nj)
    gidx = np.concatenate([base + np.where(on)[0], base + nb + np.arange(len(g_uv))])
    gi = np.concatenate([rb[on, 0].astype(np.int64), ii])
    gj = np.concatenate([rb[on, 1].astype(np.int64), jj])
    pts.grid.append((gidx, gi, gj, ni, nj))
    pts.outline.append(base + np.arange(nb))
    pts.triangles.append(tri + base)
    pts.count = base + len(panel_uv)


def _grid_springs(grid, pairs: list) -> None:
    """Provot's springs between grid points: stretch to the neighbours, shear across the
    diagonals, bend to the points two apart."""
    for gidx, ii, jj, ni, nj in grid:
        lut = -np.ones((nj + 2, ni + 2), dtype=np.int64)
        lut[jj, ii] = gidx
        for di, dj, kind in ((1, 0, STRETCH), (0, 1, STRETCH), (1, 1, SHEAR), (-1, 1, SHEAR),
                             (2, 0, BEND), (0, 2, BEND)):
            i2, j2 = ii + di, jj + dj
            ok = (i2 >= 0) & (i2 < ni) & (j2 >= 0) & (j2 < nj)
            other = np.full(len(gidx), -1)
            other[ok] = lut[j2[ok], i2[ok]]
            m = other >= 0
            pairs.append((gidx[m], other[m], np.full(int(m.sum()), kind)))


def _outline_springs(uv, triangles, boundary, pairs: list) -> np.ndarray:
    """Triangle edges at outline points: stretch, or shear where the edge runs diagonally.
    Returns those edges."""
    e = np.vstack([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    e = np.sort(e, axis=1)
    e = e[boundary[e[:, 0]] | boundary[e[:, 1]]]
    e = np.unique(e, axis=0)
    d = uv[e[:, 1]] - uv[e[:, 0]]
    cos2t = (d[:, 0] ** 2 - d[:, 1] ** 2) / np.maximum(np.sum(d * d, axis=1), 1e-300)
    pairs.append((e[:, 0], e[:, 1], np.where(np.abs(cos2t) < 0.5, SHEAR, STRETCH)))
    return e


def _outline_bend_springs(pts: _Points, uv, boundary, e, npts: int, pairs: list) -> None:
    """Bend springs for outline points off the grid: to the next-but-one outline point, and
    to the grid point two steps inward."""
    on_grid = np.zeros(npts, dtype=bool)
    for gidx, *_ in pts.grid:
        on_grid[gidx] = True
    for seq in pts.outline:
        if len(seq) >= 5:
            nxt = np.roll(seq, -2)
            m = ~(on_grid[seq] & on_grid[nxt])
            pairs.append((seq[m], nxt[m], np.full(int(m.sum()), BEND)))
    for gidx, ii, jj, ni, nj in pts.grid:
        if len(gidx) == 0:
            continue
        lut = -np.ones((nj, ni), dtype=np.int64)
        lut[jj, ii] = gidx
        pos = -np.ones(npts, dtype=np.int64)
        pos[gidx] = np.arange(len(gidx))
        for b_col, g_col in ((0, 1), (1, 0)):
            bb, gg = e[:, b_col], e[:, g_col]
            m = boundary[bb] & ~on_grid[bb] & (pos[gg] >= 0)
            bb, gg = bb[m], gg[m]
            d = uv[gg] - uv[bb]
            ax = np.abs(d[:, 0]) >= np.abs(d[:, 1])
            di = np.where(ax, np.sign(d[:, 0]), 0).astype(np.int64)
            dj = np.where(ax, 0, np.sign(d[:, 1])).astype(np.int64)
            i2 = ii[pos[gg]] + di
            j2 = jj[pos[gg]] + dj
            ok = (i2 >= 0) & (i2 < ni) & (j2 >= 0) & (j2 < nj)
            g2 = np.full(len(bb), -1)
            g2[ok] = lut[j2[ok], i2[ok]]
            m2 = g2 >= 0
            pairs.append((bb[m2], g2[m2], np.full(int(m2.sum()), BEND)))


def _springs(pts: _Points, uv, triangles, boundary, npts: int, n_seams: int):
    """Every spring (a, b, kind), none across a seam's gap, each pair once, the
    strain-limited ones (stretch, shear) first, each group in data-structure order."""
    pairs = []  # (a, b, kind) in the order of the data structure
    _grid_springs(pts.grid, pairs)
    e = _outline_springs(uv, triangles, boundary, pairs)
    _outline_bend_springs(pts, uv, boundary, e, npts, pairs)
    sa = np.concatenate([p[0] for p in pairs]).astype(np.int64)
    sb = np.concatenate([p[1] for p in pairs]).astype(np.int64)
    kind = np.concatenate([p[2] for p in pairs]).astype(np.int8)
    keep = sa != sb
    sa, sb, kind = sa[keep], sb[keep], kind[keep]
    # no spring spans a seam's gap (e.g. across a dart, where the next-but-one outline bend
    # spring and thin tip triangles join the two legs): the seam closes that gap
    key = np.minimum(sa, sb) * npts + np.maximum(sa, sb)
    across = _across_seams(pts.seam_pts, n_seams, npts)
    if len(across):
        keep = ~np.isin(key, across)
        sa, sb, kind, key = sa[keep], sb[keep], kind[keep], key[keep]
    # dedupe by unordered pair, keeping the first occurrence (grid springs come first)
    _, first = np.unique(key, return_index=True)
    first = np.sort(first)
    sa, sb, kind = sa[first], sb[first], kind[first]
    order = np.argsort(kind == BEND, kind="stable")
    return sa[order], sb[order], kind[order]


def _masses(uv, triangles, fab: Fabric, h: float, sa, sb, k) -> np.ndarray:
    """The points' masses: each triangle's area in thirds, at least half a cell's area a point
    (outline points on thin triangles would get tiny masses, and the smallest mass sets the
    time step), the stiffest points for their mass floored (:func:`_stiffness_floor`), the
    total the fabric's density × the pattern's area."""
    e1 = uv[triangles[:, 1]] - uv[triangles[:, 0]]
    e2 = uv[triangles[:, 2]] - uv[triangles[:, 0]]
    tarea = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    mass = np.zeros(len(uv))
    for c in range(3):
        np.add.at(mass, triangles[:, c], tarea / 3.0)
    area = float(tarea.sum())
    mass = np.maximum(mass, _MIN_AREA * h * h)
    mass *= fab.density * area / mass.sum()
    # no point's ω² = Σk/m above _MAX_OMEGA2 × the median point's (its stable step at least
    # 1/√_MAX_OMEGA2 of the median's), then rescale to the total
    mass = _stiffness_floor(mass, sa, sb, k)
    mass *= fab.density * area / mass.sum()
    return mass


def _seam_pairs(seams, seam_pts: dict):
    """The seams' matched point pairs (a, b) and the seam of each."""
    sea, seb, sid = [], [], []
    for si, s in enumerate(seams):
        ia = seam_pts[(si, 0)]
        ib = seam_pts[(si, 1)]
        if s.reverse:
            ib = ib[::-1]
        sea.append(ia)
        seb.append(ib)
        sid.append(np.full(len(ia), si))
    return _cat(sea), _cat(seb), _cat(sid)


def build_cloth(panels: Sequence[Panel], seams: Sequence[Seam] = (), fabric="cotton-jersey",
                h: float = DEFAULT_H) -> ClothModel:
    """Build a cloth from panels and seams (see the module docstring)."""
    fab: Fabric = get_fabric(fabric)
    if not (isinstance(h, (int, float)) and math.isfinite(h) and h > 0):
        raise InputError(f"grid spacing h must be a positive number of metres, got {h!r}")
    outlines = _check_panels(panels)
    total_area = sum(abs(_polygon_area(o)) for o in outlines)
    if total_area / (h * h) > MAX_POINTS:
        raise InputError(f"h = {h} m would make ~{int(total_area / h / h)} points "
                         f"(limit {MAX_POINTS}); use a larger h")
    runs = _seam_runs(seams, outlines)
    seam_n = _seam_intervals(seams, runs, outlines, h)
    pts = _Points()
    for pi, o in enumerate(outlines):
        _add_panel(pts, pi, panels[pi], o, runs, seam_n, h)
    uv = np.vstack(pts.uv)
    npts = len(uv)
    panel_of = np.concatenate(pts.panel)
    boundary = np.concatenate(pts.boundary)
    triangles = np.vstack(pts.triangles).astype(np.int32)

    sa, sb, kind = _springs(pts, uv, triangles, boundary, npts, len(seams))
    d2 = uv[sb] - uv[sa]
    rest = np.linalg.norm(d2, axis=1)
    if np.any(rest < 1e-9):
        raise InputError("two cloth points coincide in the pattern; check the outlines")
    k = spring_constants(fab, kind, d2, rest, h)
    mass = _masses(uv, triangles, fab, h, sa, sb, k)
    m_red = mass[sa] * mass[sb] / (mass[sa] + mass[sb])
    c_damp = 2.0 * fab.damping * np.sqrt(k * m_red)

    rest_pos = np.empty((npts, 3))
    for pi, p in enumerate(panels):
        m = panel_of == pi
        rest_pos[m] = _place(p, uv[m], pi)
    seam_a, seam_b, seam_id = _seam_pairs(seams, pts.seam_pts)
    n_lim = int(np.sum(kind != BEND))
    adj_ptr, adj_spring, adj_other = adjacency(npts, sa[:n_lim], sb[:n_lim])
    return ClothModel(
        h=float(h), fabric=fab, uv=uv, rest_positions=rest_pos, mass=mass, panel=panel_of,
        boundary=boundary, spring_a=sa.astype(np.int32), spring_b=sb.astype(np.int32),
        spring_rest=rest, spring_k=k, spring_c=c_damp, spring_kind=kind, n_limited=n_lim,
        adj_ptr=adj_ptr, adj_spring=adj_spring, adj_other=adj_other, triangles=triangles,
        seam_a=seam_a, seam_b=seam_b, seam_id=seam_id,
        panel_names=[p.name for p in panels])


def _stiffness_floor(mass: np.ndarray, sa: np.ndarray, sb: np.ndarray,
                     k: np.ndarray) -> np.ndarray:
    """Masses raised where a point's ω² = Σk/m exceeds ``_MAX_OMEGA2`` × the median point's."""
    ksum = np.bincount(sa, weights=k, minlength=len(mass)) + \
        np.bincount(sb, weights=k, minlength=len(mass))
    w2 = ksum / mass
    if not len(w2) or not np.any(w2 > 0):
        return mass
    cap = _MAX_OMEGA2 * float(np.median(w2[w2 > 0]))
    return np.maximum(mass, ksum / cap)


def _across_seams(seam_pts: dict, n_seams: int, npts: int) -> np.ndarray:
    """Keys (min·npts + max) of the point pairs that lie on the two sides of one seam (points on
    both sides, like a dart tip, excluded)."""
    keys = []
    for si in range(n_seams):
        a = np.unique(seam_pts[(si, 0)])
        b = np.unique(seam_pts[(si, 1)])
        a, b = np.setdiff1d(a, b), np.setdiff1d(b, a)
        if len(a) and len(b):
            aa, bb = np.meshgrid(a, b)
            aa, bb = aa.ravel().astype(np.int64), bb.ravel().astype(np.int64)
            keys.append(np.minimum(aa, bb) * npts + np.maximum(aa, bb))
    return np.unique(np.concatenate(keys)) if keys else np.zeros(0, np.int64)


def _cat(xs) -> np.ndarray:
    return np.concatenate(xs).astype(np.int32) if xs else np.zeros(0, np.int32)


def adjacency(n: int, sa: np.ndarray, sb: np.ndarray):
    """CSR point → springs (and the other end) for the springs (sa[i], sb[i])."""
    ends = np.concatenate([sa, sb])
    other = np.concatenate([sb, sa])
    spring = np.concatenate([np.arange(len(sa)), np.arange(len(sa))])
    order = np.argsort(ends, kind="stable")
    ptr = np.zeros(n + 1, dtype=np.int32)
    np.cumsum(np.bincount(ends, minlength=n), out=ptr[1:])
    return ptr, spring[order].astype(np.int32), other[order].astype(np.int32)


def with_fabric(model: ClothModel, fabric: Fabric | str) -> ClothModel:
    """The same points and springs with another fabric's masses and spring constants."""
    fab = get_fabric(fabric)
    d2 = model.uv[model.spring_b] - model.uv[model.spring_a]
    k = spring_constants(fab, model.spring_kind, d2, model.spring_rest, model.h)
    mass = model.mass * (fab.density / model.fabric.density)
    sa, sb = model.spring_a, model.spring_b
    m_red = mass[sa] * mass[sb] / (mass[sa] + mass[sb])
    return replace(model, fabric=fab, mass=mass, spring_k=k,
                   spring_c=2.0 * fab.damping * np.sqrt(k * m_red))
