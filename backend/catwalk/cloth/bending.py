"""The bending law every cloth solver shares: a quadratic bending energy, anisotropic
(warp, weft and bias), the same at every grid spacing (issue 44).

**The energy.** For a flat rest pattern, a bent, unstretched cloth's positions x(u, v) have
second derivatives ∂ᵤᵤx, ∂ᵥᵥx along the weft (u, the pattern's x) and the warp (v, its y)
whose lengths are the fold's curvature along each: a cylindrical fold of curvature κ whose
curvature runs at θ to the weft has |∂ᵤᵤx| = κ·cos²θ, |∂ᵥᵥx| = κ·sin²θ. The law is

    E = ½ ∫ |√B_weft·∂ᵤᵤx + √B_warp·∂ᵥᵥx|² dA,

so the fold stores ½·B(θ)·κ² per area with B(θ) = (√B_weft·cos²θ + √B_warp·sin²θ)²: B_weft
across the weft, B_warp across the warp and ((√B_warp + √B_weft)/2)² on the bias — Huber's
orthotropic plate (Huber 1923; B_12 + 2·B_66 = √(B_warp·B_weft)), the usual closure when, as
in KES data, the bias is not measured. With B_warp = B_weft = B it is Wardetzky et al. 2007's
½·B·|Δx|² (the mean-curvature normal squared; Bergou et al. 2006). It is quadratic in the
positions, so its Hessian Q is constant: the implicit solver factors it, the explicit solver
applies −Q·x each step (:func:`add_bending_forces`).

**On the mesh.** Linear finite elements on the pattern's triangles: at point i the weak
operator (R·x)ᵢ = ∫ φᵢ·(√B_weft·∂ᵤᵤx + √B_warp·∂ᵥᵥx) = −Σ_T A_T·(√B_weft·∂ᵤφᵢ·∂ᵤx +
√B_warp·∂ᵥφᵢ·∂ᵥx) (symmetric: R = Rᵀ), and E = ½·Σᵢ |(R·x)ᵢ|² / Aᵢ, Aᵢ = ∫φᵢ (lumped). A
point on a free edge (a hem, a cantilever's sides) also takes the edge's term of the
integration by parts, ½·ℓ·(√B_weft·n_u·∂ᵤx + √B_warp·n_v·∂ᵥx) — its row is then zero on any
affine field, so a flat cloth, moved or stretched, stores nothing, and a fold along the edge
is counted whole (the symmetric operator alone does not vanish there, so the implicit
solver's :func:`bending`, which keeps R symmetric, leaves those points out). On a grid the
rows are √B_weft and √B_warp times the second differences along the grid's axes, whichever
way Delaunay split each cell; each cell is taken as both its splits, half each, so that every
grid point has the area h². Measured (``tests/cloth/test_bending.py``): a cylindrical fold at
0°, 30°, 45°, 90° stores ½·B(θ)·κ² within 1 % inside a grid at 1 and 2 cm.

A triangle whose points' ``uv`` do not match its rest edge lengths (one across a welded seam:
a welded point keeps one panel's ``uv``) is laid out from its rest lengths in a frame of its
own and bends isotropically with B̄ = (B_warp + B_weft)/2. A triangle whose points are all
held still (a cantilever's platform, the drape tester's clamp: ``still``) lends no area to
its points: a kink at its edge is curvature on the free side.

(The hinge form of Bergou et al. 2006, one term per interior edge, was measured on a Provot
grid and not kept: a fold along the grid stored 2.8 × ½Bκ², one at 45° 4.7 ×. The rest
triangles come from the springs' rest lengths — each triangle edge is a spring.)"""

from __future__ import annotations

import math

import numba
import numpy as np
import scipy.sparse as sp

from catwalk.cloth import springs
from catwalk.cloth.model import ClothModel


def _edge_rest(model: ClothModel) -> dict:
    """Rest length of every triangle edge from the springs joining its two points."""
    lo = np.minimum(model.spring_a, model.spring_b).astype(np.int64)
    hi = np.maximum(model.spring_a, model.spring_b).astype(np.int64)
    keys = lo * model.n_points + hi
    lim = model.spring_kind != 2
    return dict(zip(keys[lim].tolist(), model.spring_rest[lim].tolist(), strict=True))


def _tri_rest_lengths(model: ClothModel) -> np.ndarray:
    """(t, 3) rest lengths of each triangle's edges (opposite corners 0, 1, 2): the springs'
    where a spring joins the two points, else the rest positions' distance."""
    t = model.triangles.astype(np.int64)
    n = model.n_points
    rest = _edge_rest(model)
    out = np.empty((len(t), 3))
    x = model.rest_positions
    for c in range(3):
        p, q = t[:, (c + 1) % 3], t[:, (c + 2) % 3]
        key = np.minimum(p, q) * n + np.maximum(p, q)
        geo = np.linalg.norm(x[p] - x[q], axis=1)
        out[:, c] = [rest.get(k, g) for k, g in zip(key.tolist(), geo.tolist(), strict=True)]
    return out


def _cot_from_lengths(la, lb, lc):
    """Cotangent of the angle opposite side ``la`` in a triangle of sides la, lb, lc, and the
    triangle's area."""
    s2 = 2.0 * (la * la * lb * lb + lb * lb * lc * lc + lc * lc * la * la) - \
        (la ** 4 + lb ** 4 + lc ** 4)
    area = 0.25 * np.sqrt(np.maximum(s2, 1e-300))
    return (lb * lb + lc * lc - la * la) / (4.0 * area), area


def cotan_laplacian(model: ClothModel) -> tuple[sp.csr_matrix, np.ndarray]:
    """(For comparison: the law's operator for an isotropic fabric on a grid.) The rest
    pattern's cotangent Laplacian (n × n, Σⱼ ½(cot α + cot β)(xⱼ − xᵢ) in row i)
    and each point's area (a third of its triangles')."""
    t = model.triangles.astype(np.int64)
    n = model.n_points
    L = _tri_rest_lengths(model)
    rows, cols, vals = [], [], []
    area = np.zeros(n)
    for c in range(3):
        cot, a = _cot_from_lengths(L[:, c], L[:, (c + 1) % 3], L[:, (c + 2) % 3])
        p, q = t[:, (c + 1) % 3], t[:, (c + 2) % 3]
        w = 0.5 * cot
        rows += [p, q, p, q]
        cols += [q, p, p, q]
        vals += [w, w, -w, -w]
        np.add.at(area, t[:, c], a / 3.0)
    lap = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                        shape=(n, n)).tocsr()
    lap.sum_duplicates()
    return lap, area


def bending_rigidity(model: ClothModel, scale: float = 1.0) -> float:
    """B̄ (N·m): the mean of the fabric's warp and weft bending rigidity, times ``scale``."""
    f = model.fabric
    return scale * 0.5 * (f.bend_warp + f.bend_weft)


def fold_rigidity(fabric, theta) -> np.ndarray:
    """B(θ) (N·m): what a cylindrical fold whose curvature runs at θ to the weft (the
    pattern's x axis) stores per area and κ² (E = ½·B(θ)·κ²): (√B_weft·cos²θ +
    √B_warp·sin²θ)² (0: the weft yarns bend, 90°: the warp yarns)."""
    c2 = np.cos(theta) ** 2
    return (math.sqrt(fabric.bend_weft) * c2 + math.sqrt(fabric.bend_warp) * (1.0 - c2)) ** 2


#: a triangle's corners are taken in its panel's pattern frame (warp +y, weft +x) when their
#: ``uv`` agree with the triangle's rest edge lengths to this relative tolerance
FRAME_TOLERANCE = 1e-6


def _triangle_corners(model: ClothModel) -> tuple[np.ndarray, np.ndarray]:
    """(t, 3, 2) each triangle's corners in 2D and (t,) whether that is its panel's pattern
    frame (:data:`FRAME_TOLERANCE`); a triangle not in it is laid out from its rest edge
    lengths (corner 0 at the origin, corner 1 on +x, counter-clockwise)."""
    t = model.triangles.astype(np.int64)
    lengths = _tri_rest_lengths(model)
    uv = model.uv[t]
    trusted = np.ones(len(t), bool)
    for c in range(3):
        d = np.linalg.norm(uv[:, (c + 2) % 3] - uv[:, (c + 1) % 3], axis=1)
        trusted &= np.abs(d - lengths[:, c]) <= FRAME_TOLERANCE * lengths[:, c]
    e1, e2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    trusted &= e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] > 0
    out = uv.copy()
    bad = ~trusted
    if bad.any():
        l0, l1, l2 = lengths[bad, 0], lengths[bad, 1], lengths[bad, 2]
        x = (l2 * l2 + l1 * l1 - l0 * l0) / (2.0 * l2)
        out[bad] = 0.0
        out[bad, 1, 0] = l2
        out[bad, 2, 0] = x
        out[bad, 2, 1] = np.sqrt(np.maximum(l1 * l1 - x * x, 0.0))
    return out, trusted


def _hat_gradients(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(t, 3, 2) the gradients of each corner's hat function and (t,) the areas of
    triangles with corners ``p`` (t, 3, 2), counter-clockwise."""
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    area = 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    g = np.empty_like(p)
    for k in range(3):
        e = p[:, (k + 2) % 3] - p[:, (k + 1) % 3]
        g[:, k, 0] = -e[:, 1]
        g[:, k, 1] = e[:, 0]
    return g / (2.0 * np.maximum(area, 1e-300))[:, None, None], area


def _edge_keys(t: np.ndarray, n: int) -> np.ndarray:
    """(3, t) the key (lo·n + hi) of each triangle's edge opposite each corner."""
    return np.stack([np.minimum(t[:, (c + 1) % 3], t[:, (c + 2) % 3]) * n +
                     np.maximum(t[:, (c + 1) % 3], t[:, (c + 2) % 3]) for c in range(3)])


#: two right isosceles triangles sharing their hypotenuse are a grid cell when their legs
#: agree to this relative tolerance
_SQUARE_TOLERANCE = 1e-6


def _both_splits(t: np.ndarray, p: np.ndarray, n: int, trusted: np.ndarray):
    """The triangles with each grid cell (two right isosceles triangles on one hypotenuse)
    taken as both of its splits, half each: Delaunay splits the cocircular corners of a
    cell either way, and the twist's weak form depends on the split. Only triangles in their
    panel's pattern frame (``trusted``) pair up: a triangle laid out from its rest lengths has
    a frame of its own, and a welded seam's triangles' corners may lie in two panels' frames,
    so the other split of such a pair would mix frames (and may be degenerate). Returns
    (triangles,
    corners (·, 3, 2), weights)."""
    keys = _edge_keys(t, n)
    legs = np.stack([np.linalg.norm(p[:, (c + 2) % 3] - p[:, (c + 1) % 3], axis=1)
                     for c in range(3)])
    # the corner at the right angle: its opposite edge is the hypotenuse (legs equal)
    hyp = np.argmax(legs, axis=0)
    idx = np.arange(len(t))
    l_h = legs[hyp, idx]
    l_a, l_b = legs[(hyp + 1) % 3, idx], legs[(hyp + 2) % 3, idx]
    right = (np.abs(l_a - l_b) <= _SQUARE_TOLERANCE * l_h) & \
        (np.abs(l_h - math.sqrt(2.0) * l_a) <= _SQUARE_TOLERANCE * l_h)
    hk = keys[hyp, idx]
    cand = np.flatnonzero(right & trusted)
    order = cand[np.argsort(hk[cand], kind="stable")]
    ks = hk[order]
    first = np.flatnonzero((ks[1:] == ks[:-1]) &
                           np.r_[True, ks[1:-1] != ks[:-2]] & np.r_[ks[2:] != ks[1:-1], True])
    t1, t2 = order[first], order[first + 1]
    if len(t1) == 0:
        return t, p, np.ones(len(t))
    c1, c2 = hyp[t1], hyp[t2]
    # the cell's corners: a (right angle of t1), b, d (the hypotenuse), c (right angle of t2)
    a, b, d = t[t1, c1], t[t1, (c1 + 1) % 3], t[t1, (c1 + 2) % 3]
    c = t[t2, c2]
    pa, pb, pd = p[t1, c1], p[t1, (c1 + 1) % 3], p[t1, (c1 + 2) % 3]
    pc = p[t2, c2]
    # the other split (diagonal a–c), counter-clockwise as a, b, d is: (a, b, c), (a, c, d)
    new_t = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    new_p = np.concatenate([np.stack([pa, pb, pc], 1), np.stack([pa, pc, pd], 1)])
    w = np.ones(len(t))
    w[t1] = w[t2] = 0.5
    return (np.concatenate([t, new_t]), np.concatenate([p, new_p]),
            np.concatenate([w, np.full(len(new_t), 0.5)]))


def _operator(model: ClothModel, fabric, still: np.ndarray | None = None):
    """The law's operator on ``model`` (module docstring): (R, the free edges' term F — the
    rows of R + F are zero on affine fields —, the points' bending areas, the points on a
    free edge)."""
    t0 = model.triangles.astype(np.int64)
    n = model.n_points
    p0, trusted = _triangle_corners(model)
    e0 = _edge_keys(t0, n).ravel()
    uniq, counts = np.unique(e0, return_counts=True)
    free_keys = uniq[counts == 1]
    on_free = np.zeros(n, bool)
    on_free[free_keys // n] = True
    on_free[free_keys % n] = True
    t, p, wt = _both_splits(t0, p0, n, trusted)
    ok = np.concatenate([trusted, np.ones(len(t) - len(t0), bool)])   # (cells: trusted)
    g, area = _hat_gradients(p)
    area = area * wt
    b_mean = math.sqrt(0.5 * (fabric.bend_warp + fabric.bend_weft))
    # √B along each axis, per triangle (an untrusted one bends isotropically)
    m = np.where(ok[:, None], [math.sqrt(fabric.bend_weft), math.sqrt(fabric.bend_warp)],
                 b_mean)
    rows, cols, vals = [], [], []
    for i in range(3):
        for k in range(3):
            rows.append(t[:, i])
            cols.append(t[:, k])
            vals.append(-area * (m[:, 0] * g[:, i, 0] * g[:, k, 0] +
                                 m[:, 1] * g[:, i, 1] * g[:, k, 1]))
    r = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(n, n))
    # the free edges' term: corner c's opposite edge, its outward normal −∇φ_c/|∇φ_c|
    free = np.isin(_edge_keys(t, n), free_keys)
    rows, cols, vals = [], [], []
    for c in range(3):
        f = free[c]
        if not f.any():
            continue
        nrm = -g[f, c] / np.linalg.norm(g[f, c], axis=1)[:, None]
        ell = wt[f] * np.linalg.norm(p[f, (c + 2) % 3] - p[f, (c + 1) % 3], axis=1)
        for end in ((c + 1) % 3, (c + 2) % 3):
            for k in range(3):
                rows.append(t[f, end])
                cols.append(t[f, k])
                vals.append(0.5 * ell * (m[f, 0] * nrm[:, 0] * g[f, k, 0] +
                                         m[f, 1] * nrm[:, 1] * g[f, k, 1]))
    flux = sp.csr_matrix((np.concatenate(vals) if vals else np.zeros(0),
                          (np.concatenate(rows) if rows else np.zeros(0, np.int64),
                           np.concatenate(cols) if cols else np.zeros(0, np.int64))),
                         shape=(n, n))
    for a in (r, flux):     # entries that cancel to rounding (a cell's diagonals) are none
        a.sum_duplicates()
        a.data[np.abs(a.data) <= 1e-12 * np.abs(r.data).max(initial=0.0)] = 0.0
        a.eliminate_zeros()
    bends = np.ones(len(t), bool) if still is None else ~np.all(still[t], axis=1)
    point_area = np.zeros(n)
    for c in range(3):
        np.add.at(point_area, t[:, c], np.where(bends, area, 0.0) / 3.0)
    return r, flux, point_area, on_free


def _inverse(area: np.ndarray) -> np.ndarray:
    return np.where(area > 0, 1.0 / np.maximum(area, 1e-300), 0.0)


def bending(model: ClothModel, rigidity: float):
    """The implicit solver's form of the law: ``(R (symmetric CSR), coef (n,), Q)`` with
    E = ½·Σᵢ coefᵢ·|(R·x)ᵢ|², Q = R·diag(coef)·R; the law's weights (``rigidity`` / B̄, B̄ the
    fabric's mean rigidity: the fabric's own law when ``rigidity`` is
    :func:`bending_rigidity`) over the points not on a free edge (there R alone is not zero on
    an affine field; :func:`bending_matrix` has them)."""
    f = model.fabric
    r, _, area, on_free = _operator(model, f)
    r = (0.5 * (r + r.T)).tocsr()     # (symmetric to the last bit: the solver uses it twice)
    coef = np.where(on_free, 0.0, rigidity / bending_rigidity(model) * _inverse(area))
    q = (r @ sp.diags(coef) @ r).tocsc()
    return r, coef, q


def bending_matrix(model: ClothModel, fabric=None, scale: float = 1.0,
                   still: np.ndarray | None = None) -> sp.csr_matrix:
    """Q (n × n, symmetric, CSR): the Hessian of the law's energy (module docstring) of
    ``fabric`` (default the model's) on ``model``'s rest pattern, every point counted (the
    free edges' with their edge term), times ``scale``; ``still``: the points held still."""
    f = model.fabric if fabric is None else fabric
    r, flux, area, _ = _operator(model, f, still)
    h = (r + flux).tocsr()
    q = h.T @ sp.diags(scale * _inverse(area)) @ h
    q = (0.5 * (q + q.T)).tocsr()
    # entries that cancel to rounding (a stencil's corners) are no coupling
    q.data[np.abs(q.data) <= 1e-12 * np.abs(q.data).max(initial=0.0)] = 0.0
    q.eliminate_zeros()
    return q


def bending_pairs(q: sp.spmatrix) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Q as pairs: Q's rows sum to zero (it is zero on a translation), so −Q·x at point i
    is Σⱼ kᵢⱼ·(xⱼ − xᵢ) with kᵢⱼ = −Qᵢⱼ — linear springs of zero rest length, some of them
    negative. Returns (a, b, k) over i < j, sorted so that pairs of one offset b − a along
    consecutive points follow each other, and their runs
    (:func:`catwalk.cloth.springs.spring_runs`), which the force loop vectorises over."""
    u = sp.triu(q, k=1).tocoo()
    a, b, k = u.row.astype(np.int64), u.col.astype(np.int64), -u.data
    keep = k != 0.0
    a, b, k = a[keep], b[keep], k[keep]
    order = np.lexsort((a, b - a))
    a, b, k = a[order], b[order], np.ascontiguousarray(k[order])
    return a, b, k, springs.spring_runs(a, b)


def row_bound(q: sp.spmatrix) -> np.ndarray:
    """(n,) Σⱼ |Qᵢⱼ|: Gershgorin's bound of Q's eigenvalues at each point (the explicit
    solver's stable step takes half of it as a point's spring constant sum, as a spring of
    constant k adds 2k to both its ends' rows)."""
    return np.asarray(abs(q).sum(axis=1)).ravel()


def bending_energy(q: sp.spmatrix, x: np.ndarray) -> float:
    """½·Σ xᵀQx over the three coordinates (J)."""
    return 0.5 * float(np.sum(x * (q @ x)))


def pair_damping(a: np.ndarray, b: np.ndarray, k: np.ndarray, mass: np.ndarray,
                 ratio: float) -> np.ndarray:
    """Damping along each pair of :func:`bending_pairs` as along a spring (the fabric's
    damping ``ratio`` ζ of the pair's own critical damping): c = 2ζ·√(|k|·m_red) ≥ 0, so the
    damping only ever takes energy out (without it the bending's grid-scale modes are damped
    by the air alone, and the ordered pass fed a soft fabric's flapping: silk charmeuse on
    the drape tester at h = 1 cm reached 10–27 m/s)."""
    m_red = mass[a] * mass[b] / (mass[a] + mass[b])
    return np.ascontiguousarray(2.0 * ratio * np.sqrt(np.abs(k) * m_red))


@numba.njit(cache=True, error_model="numpy")
def add_bending_forces(X, V, runs, k, c, F):
    """F += −Q·X − C·V on (3, n) arrays, Q as the pairs of :func:`bending_pairs` in runs and C
    their damping (:func:`pair_damping`): for a pair (a, b), k·(x_b − x_a) + c·(v_b − v_a) on a
    and its opposite on b."""
    b0, b1, b2 = springs.run_buffers(runs)
    x0 = X[0]
    x1 = X[1]
    x2 = X[2]
    v0 = V[0]
    v1 = V[1]
    v2 = V[2]
    f0 = F[0]
    f1 = F[1]
    f2 = F[2]
    for q in range(runs.shape[0]):
        s0 = max(runs[q, 0], 0)
        a0 = max(runs[q, 1], 0)
        c0 = max(runs[q, 2], 0)
        nl = runs[q, 3]
        for t in range(nl):
            kk = k[s0 + t]
            cc = c[s0 + t]
            b0[t] = kk * (x0[c0 + t] - x0[a0 + t]) + cc * (v0[c0 + t] - v0[a0 + t])
            b1[t] = kk * (x1[c0 + t] - x1[a0 + t]) + cc * (v1[c0 + t] - v1[a0 + t])
            b2[t] = kk * (x2[c0 + t] - x2[a0 + t]) + cc * (v2[c0 + t] - v2[a0 + t])
        for t in range(nl):
            f0[a0 + t] += b0[t]
        for t in range(nl):
            f1[a0 + t] += b1[t]
        for t in range(nl):
            f2[a0 + t] += b2[t]
        for t in range(nl):
            f0[c0 + t] -= b0[t]
        for t in range(nl):
            f1[c0 + t] -= b1[t]
        for t in range(nl):
            f2[c0 + t] -= b2[t]
