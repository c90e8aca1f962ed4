"""Quadratic bending (Wardetzky, Bergou, Harmon, Zorin & Grinspun 2007, "Discrete quadratic
curvature energies"; Bergou et al. 2006): E = ½·Σᵢ B·Aᵢ·|Δxᵢ|², Δ the rest pattern's cotangent
Laplacian over the point's area — its mean-curvature normal — over the points not on a free
edge. A fold of curvature κ stores ½·B·κ² per area whatever its direction and the grid
spacing; for a flat rest pattern the energy is exactly quadratic in the positions, so its
Hessian Q = Δᵀ·diag(B/Aᵢ)·Δ is constant (the implicit solver's matrix holds it whole). (The
hinge form of Bergou et al. 2006, one term per interior edge, was measured on a Provot grid
and not kept: a fold along the grid stored 2.8 × ½Bκ², one at 45° 4.7 ×.) The rest triangles
come from the springs' rest lengths (each triangle edge is a spring), so seams and welded
points need no 2D coordinates of their own."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

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


def surface_boundary(model: ClothModel) -> np.ndarray:
    """(n,) bool: the points on an edge that only one triangle has (the garment's free
    edges: hems, necklines, cuffs; seams welded shut are not)."""
    t = model.triangles.astype(np.int64)
    n = model.n_points
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    key = np.minimum(e[:, 0], e[:, 1]) * n + np.maximum(e[:, 0], e[:, 1])
    uniq, counts = np.unique(key, return_counts=True)
    once = uniq[counts == 1]
    out = np.zeros(n, bool)
    out[once // n] = True
    out[once % n] = True
    return out


def cotan_laplacian(model: ClothModel) -> tuple[sp.csr_matrix, np.ndarray]:
    """The rest pattern's cotangent Laplacian (n × n, Σⱼ ½(cot α + cot β)(xⱼ − xᵢ) in row i)
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
    """B (N·m): the mean of the fabric's warp and weft bending rigidity, times ``scale``."""
    f = model.fabric
    return scale * 0.5 * (f.bend_warp + f.bend_weft)


def bending(model: ClothModel, rigidity: float):
    """The quadratic bending energy ½·Σᵢ B·Aᵢ·|Δxᵢ|² over the points not on a free edge
    (Δ the cotangent Laplacian over the point's area: its mean-curvature normal 2H·n; on a
    cylinder of curvature κ this is ½·B·κ² per area, in every direction of the fold, at every
    h): ``(lap (CSR), coef (n,) = B/Aᵢ or 0 on a free edge, Q = lapᵀ·diag(coef)·lap)``."""
    lap, area = cotan_laplacian(model)
    coef = np.where(surface_boundary(model) | (area <= 0), 0.0,
                    rigidity / np.maximum(area, 1e-300))
    q = (lap.T @ sp.diags(coef) @ lap).tocsc()
    return lap, coef, q
