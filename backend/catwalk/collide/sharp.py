"""Sharp body features through cloth triangles: the body's side of the collision.

The collider's passes test cloth *points* against the body. A body feature narrower than the
cloth's triangles (a bust point, a knuckle, an elbow's tip) can come up through the middle of
a cloth triangle while every cloth point stays outside the body: the rendered garment shows
the body through it. Here, once per body frame (after the last resolve), each *sharp* body
vertex — one that stands more than ``SHARP_HEIGHT`` out of the mean of its neighbours within
``SHARP_RADIUS``, along its normal, found once from the first pose — casts a ray along its
normal; a cloth triangle it meets less than the cloth thickness out (or up to
``SHARP_DEPTH`` behind it: poked through) is pushed out along that normal to the thickness,
its three points moved by their barycentric weights (w_i / Σ w_j², so the point of the
triangle over the vertex moves by exactly the amount needed).

Cloth points are found through a uniform grid built per call (cells of ``cell`` metres);
the cloth's point → triangle incidence is a CSR (``render.raster.incident_faces``) built once
per triangle array.
"""

from __future__ import annotations

import numba
import numpy as np

from catwalk.geometry.triangles import ray_triangle

#: a body vertex is sharp when it stands this far (m) out of the mean of its neighbours within
#: SHARP_RADIUS, along its normal (on the 1.68 m sample bodies: bust points 4–6 mm, fingers,
#: toes, nose, ears; about a third of the vertices, mostly far from any garment)
SHARP_HEIGHT = 0.002
SHARP_RADIUS = 0.015
#: how far behind a cloth triangle a sharp vertex may be and still push it out (m)
SHARP_DEPTH = 0.01


def sharp_vertices(vertices: np.ndarray, normals: np.ndarray, radius: float = SHARP_RADIUS,
                   height: float = SHARP_HEIGHT) -> np.ndarray:
    """Indices of the vertices that stand more than ``height`` out of the mean of their
    neighbours within ``radius``, along their unit ``normals``."""
    from scipy.spatial import cKDTree  # deferred: scipy loads in ≈ 0.3 s; only this path needs it

    v = np.asarray(vertices, dtype=np.float64)
    tree = cKDTree(v)
    k = min(len(v), 48)
    d, idx = tree.query(v, k=k, distance_upper_bound=radius)
    ok = np.isfinite(d)
    idx = np.where(ok, idx, 0)
    cnt = ok.sum(axis=1)
    mean = (v[idx] * ok[..., None]).sum(axis=1) / np.maximum(cnt, 1)[:, None]
    h = np.einsum("ij,ij->i", v - mean, normals)
    return np.nonzero((h > height) & (cnt >= 4))[0].astype(np.int64)


@numba.njit(cache=True)
def push_off_sharp(x, tris, ptr, pt_tri, cand, V, N, thickness, depth, cell, moved):
    """Push the cloth triangles a sharp body vertex comes through (module docstring) out of
    it; ``x`` (P, 3) cloth positions, changed in place; ``tris`` the cloth's triangles, each
    point's in ``pt_tri[ptr[i] : ptr[i + 1]]``; ``cand`` the sharp vertices of the body
    ``V``/``N`` (positions, unit normals); ``moved`` (P,) bool: set for the points moved
    (empty: not kept). Returns how many pushes were made."""
    P = x.shape[0]
    if P == 0 or cand.shape[0] == 0:
        return 0
    lo, cell, dims, start, order = _point_grid(x, cell)
    pushes = 0
    reach2 = (2.0 * cell) * (2.0 * cell)
    for ci in range(cand.shape[0]):
        j = cand[ci]
        px = V[j, 0]
        py = V[j, 1]
        pz = V[j, 2]
        gx = int((px - lo[0]) / cell)
        gy = int((py - lo[1]) / cell)
        gz = int((pz - lo[2]) / cell)
        if gx < 0 or gy < 0 or gz < 0 or gx >= dims[0] or gy >= dims[1] or gz >= dims[2]:
            continue
        for ax in range(max(gx - 1, 0), min(gx + 2, dims[0])):
            for ay in range(max(gy - 1, 0), min(gy + 2, dims[1])):
                for az in range(max(gz - 1, 0), min(gz + 2, dims[2])):
                    c = (ax * dims[1] + ay) * dims[2] + az
                    for s in range(start[c], start[c + 1]):
                        i = order[s]
                        dx = x[i, 0] - px
                        dy = x[i, 1] - py
                        dz = x[i, 2] - pz
                        if dx * dx + dy * dy + dz * dz > reach2:
                            continue
                        pushes += _push_triangles_of(x, i, tris, ptr, pt_tri, V, N, j,
                                                     thickness, depth, moved)
    return pushes


@numba.njit(cache=True)
def _point_grid(x, cell):
    """The cloth points ``x`` in a uniform grid over their box grown by a cell (cells of
    ``cell`` metres, coarser when that would make more than ~2 million: coarser cells only
    look further). Returns (the grid's corner ``lo``, the cell size, the cells a side
    ``dims``, each cell's start in ``order`` (``start``, cells + 1), the points cell after
    cell ``order``)."""
    P = x.shape[0]
    lo = np.empty(3)
    hi = np.empty(3)
    for q in range(3):
        lo[q] = x[0, q]
        hi[q] = x[0, q]
    for i in range(P):
        for q in range(3):
            lo[q] = min(lo[q], x[i, q])
            hi[q] = max(hi[q], x[i, q])
    vol = (hi[0] - lo[0] + 2.0 * cell) * (hi[1] - lo[1] + 2.0 * cell) * (hi[2] - lo[2] + 2.0 * cell)
    cell = max(cell, (vol / 2.0e6) ** (1.0 / 3.0))
    dims = np.empty(3, np.int64)
    for q in range(3):
        lo[q] -= cell
        dims[q] = int((hi[q] + cell - lo[q]) / cell) + 1
    ncell = dims[0] * dims[1] * dims[2]
    start = np.zeros(ncell + 1, np.int64)
    key = np.empty(P, np.int64)
    for i in range(P):
        cx = int((x[i, 0] - lo[0]) / cell)
        cy = int((x[i, 1] - lo[1]) / cell)
        cz = int((x[i, 2] - lo[2]) / cell)
        key[i] = (cx * dims[1] + cy) * dims[2] + cz
        start[key[i] + 1] += 1
    for c in range(ncell):
        start[c + 1] += start[c]
    fill = start[:-1].copy()
    order = np.empty(P, np.int64)
    for i in range(P):
        order[fill[key[i]]] = i
        fill[key[i]] += 1
    return lo, cell, dims, start, order


@numba.njit(cache=True)
def _push_triangles_of(x, i, tris, ptr, pt_tri, V, N, j, thickness, depth, moved):
    """The triangles of cloth point i that body vertex j's ray (from it along its normal)
    meets less than ``thickness`` out or up to ``depth`` behind: each pushed out along the
    normal to the thickness, its points moved by their barycentric weights (w_i / Σ w_j²).
    Returns how many."""
    px = V[j, 0]
    py = V[j, 1]
    pz = V[j, 2]
    nx = N[j, 0]
    ny = N[j, 1]
    nz = N[j, 2]
    pushes = 0
    for e in range(ptr[i], ptr[i + 1]):
        t = pt_tri[e]
        a = tris[t, 0]
        b = tris[t, 1]
        cc = tris[t, 2]
        # ray p + s·n against the triangle
        hit, dist, u, v = ray_triangle(
            px, py, pz, nx, ny, nz, x[a, 0], x[a, 1], x[a, 2], x[b, 0],
            x[b, 1], x[b, 2], x[cc, 0], x[cc, 1], x[cc, 2], 1e-14)
        if not hit:
            continue
        if dist >= thickness - 1e-6 or dist <= -depth:
            continue
        push = thickness - dist
        w0 = 1.0 - u - v
        den = w0 * w0 + u * u + v * v
        for q, wq in ((a, w0), (b, u), (cc, v)):
            k = push * wq / den
            x[q, 0] += k * nx
            x[q, 1] += k * ny
            x[q, 2] += k * nz
            if moved.shape[0]:
                moved[q] = True
        pushes += 1
    return pushes
