"""Independent accuracy checks of a try-on: how deep cloth points are inside the body, and
which cloth springs cross it.

This does not use the collider: the body surface is searched from the k nearest body vertices
(scipy's cKDTree) through their incident triangles, and a point's signed distance is measured
along the body's interpolated vertex normal at its closest surface point (negative = inside).
A spring crosses the body when the segment between its two points meets a body triangle
(:func:`segments_crossing`: every triangle tested, for the few springs asked about).
"""

from __future__ import annotations

import numba
import numpy as np
from scipy.spatial import cKDTree

from catwalk.errors import InputError
from catwalk.geometry.raster import incident_faces, vertex_normals
from catwalk.geometry.triangles import closest_on_triangle, ray_triangle


@numba.njit(cache=True)
def _closest(points, near, verts, normals, faces, ptr, inc, out_d, out_q, out_t, out_b):
    for i in range(points.shape[0]):
        px, py, pz = points[i, 0], points[i, 1], points[i, 2]
        best = 1e30
        for j in range(near.shape[1]):
            v = near[i, j]
            for t in range(ptr[v], ptr[v + 1]):
                f = inc[t]
                a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
                u, w = closest_on_triangle(
                    px, py, pz, verts[a, 0], verts[a, 1], verts[a, 2], verts[b, 0], verts[b, 1],
                    verts[b, 2], verts[c, 0], verts[c, 1], verts[c, 2])
                s = 1.0 - u - w
                qx = s * verts[a, 0] + u * verts[b, 0] + w * verts[c, 0]
                qy = s * verts[a, 1] + u * verts[b, 1] + w * verts[c, 1]
                qz = s * verts[a, 2] + u * verts[b, 2] + w * verts[c, 2]
                dx, dy, dz = px - qx, py - qy, pz - qz
                d2 = dx * dx + dy * dy + dz * dz
                if d2 < best:
                    best = d2
                    nx = s * normals[a, 0] + u * normals[b, 0] + w * normals[c, 0]
                    ny = s * normals[a, 1] + u * normals[b, 1] + w * normals[c, 1]
                    nz = s * normals[a, 2] + u * normals[b, 2] + w * normals[c, 2]
                    dn = dx * nx + dy * ny + dz * nz
                    d = np.sqrt(d2)
                    out_d[i] = d if dn >= 0.0 else -d
                    out_q[i, 0] = qx
                    out_q[i, 1] = qy
                    out_q[i, 2] = qz
                    out_t[i] = f
                    out_b[i, 0] = s
                    out_b[i, 1] = u
                    out_b[i, 2] = w


class BodySurface:
    """Signed distances of points to one posed body surface (or any triangle mesh)."""

    def __init__(self, faces: np.ndarray, n_vertices: int, k: int = 8):
        self.faces = np.ascontiguousarray(faces, dtype=np.int64)
        self.ptr, self.inc = incident_faces(self.faces, n_vertices)
        self.k = int(k)

    def closest(self, vertices: np.ndarray, points: np.ndarray, tree: cKDTree | None = None,
                normals: np.ndarray | None = None):
        """(closest surface points (P, 3), signed distances (P,), their triangles (P,), the
        points' barycentric coordinates on them (P, 3)).

        ``tree`` and ``normals``: a cKDTree of ``vertices`` and their vertex normals, already
        made (several queries on one surface). A point whose nearest vertices are on no
        triangle (a mesh with unused vertices) is an :class:`InputError`."""
        v = np.ascontiguousarray(vertices, dtype=np.float64)
        p = np.ascontiguousarray(points, dtype=np.float64)
        nrm = vertex_normals(v, self.faces) if normals is None else normals
        k = min(self.k, len(v))
        _, near = (tree or cKDTree(v)).query(p, k=k)
        near = np.ascontiguousarray(np.reshape(near, (len(p), k)), dtype=np.int64)
        d = np.full(len(p), np.inf)
        q = np.zeros((len(p), 3))
        t = np.full(len(p), -1, dtype=np.int64)
        b = np.zeros((len(p), 3))
        _closest(p, near, v, nrm, self.faces, self.ptr, self.inc, d, q, t, b)
        if len(t) and t.min() < 0:
            raise InputError("surface: points whose nearest vertices are on no triangle (the "
                             "mesh has unused vertices)")
        return q, d, t, b

    def signed_distance(self, vertices: np.ndarray, points: np.ndarray) -> np.ndarray:
        return self.closest(vertices, points)[1]


def penetration(surface: BodySurface, vertices: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Depth (m, ≥ 0) of every point inside the body (0 outside)."""
    return np.maximum(-surface.signed_distance(vertices, points), 0.0)


@numba.njit(cache=True)
def _crossings(a, b, verts, faces, out):
    for i in range(a.shape[0]):
        ox, oy, oz = a[i, 0], a[i, 1], a[i, 2]
        dx, dy, dz = b[i, 0] - ox, b[i, 1] - oy, b[i, 2] - oz
        lox, hix = min(ox, b[i, 0]), max(ox, b[i, 0])
        loy, hiy = min(oy, b[i, 1]), max(oy, b[i, 1])
        loz, hiz = min(oz, b[i, 2]), max(oz, b[i, 2])
        for f in range(faces.shape[0]):
            ia, ib, ic = faces[f, 0], faces[f, 1], faces[f, 2]
            if max(verts[ia, 0], verts[ib, 0], verts[ic, 0]) < lox or \
                    min(verts[ia, 0], verts[ib, 0], verts[ic, 0]) > hix or \
                    max(verts[ia, 1], verts[ib, 1], verts[ic, 1]) < loy or \
                    min(verts[ia, 1], verts[ib, 1], verts[ic, 1]) > hiy or \
                    max(verts[ia, 2], verts[ib, 2], verts[ic, 2]) < loz or \
                    min(verts[ia, 2], verts[ib, 2], verts[ic, 2]) > hiz:
                continue
            hit, t, _, _ = ray_triangle(ox, oy, oz, dx, dy, dz, verts[ia, 0], verts[ia, 1],
                                        verts[ia, 2], verts[ib, 0], verts[ib, 1],
                                        verts[ib, 2], verts[ic, 0], verts[ic, 1],
                                        verts[ic, 2], 1e-18)
            if hit and 0.0 <= t <= 1.0:
                out[i] = True
                break


def segments_crossing(vertices: np.ndarray, faces: np.ndarray, a: np.ndarray,
                      b: np.ndarray) -> np.ndarray:
    """Whether each segment from ``a[i]`` to ``b[i]`` meets the body surface (a cloth spring
    whose two points are outside the body and that meets it hangs across a body part)."""
    a = np.ascontiguousarray(a, dtype=np.float64).reshape(-1, 3)
    b = np.ascontiguousarray(b, dtype=np.float64).reshape(-1, 3)
    out = np.zeros(len(a), dtype=np.bool_)
    if len(a):
        _crossings(a, b, np.ascontiguousarray(vertices, dtype=np.float64),
                   np.ascontiguousarray(faces, dtype=np.int64), out)
    return out
