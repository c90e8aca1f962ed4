"""The body's signed distance field in its first pose, carried along by the skin: what lets
the object pass keep a point's closest triangle after the point slid, without a search.

The field (:class:`RestField`) samples the body's signed distance on a grid over the first
pose the collider was given (the rest pose a walk starts from: only the walk's collider uses
it, ``Settings.collider_options``), within a band round the surface (beyond it the grid
holds + the band). In a later pose a point is carried back by
its kept triangle's own frame (:func:`carry_back`: the triangle's edge, normal and their cross
product, posed and in the first pose — the skin moves rigidly over one triangle) and the
field is read there (:func:`field_distance`, trilinear). The field answers "how near is any
of the body's surface" to within its error (the grid's interpolation, the skin's bending
between the triangle and the surface nearest the point); the kept triangle is as good as a
search's answer when it is no farther than that (:func:`catwalk.collide.kernels.object_pass`,
``field``).

What the field cannot see: surfaces that the pose brings together but the first pose holds
apart (a hand over the thigh, the inside of a bent elbow). The object pass keeps its own
checks of the other parts for the first; the frame kept searches its pushed points afresh
for the second (docs/collide.md, "The rest-pose field").
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import numba
import numpy as np

from catwalk.collide.bvh import closest_on_triangle
from catwalk.errors import InputError
from catwalk.render.raster import vertex_normals

#: m: the grid's spacing and the band round the surface where it holds distances
FIELD_SPACING = 0.004
FIELD_BAND = 0.016


@dataclass(frozen=True)
class RestField:
    """A signed distance grid of the body in its first pose: ``grid`` (X, Y, Z) float32, the
    distance at ``origin + spacing · (i, j, k)`` (negative inside; + ``band`` farther than
    ``band`` from the surface, on either side),
    and ``rest`` (N, 3): the body's vertices in that pose."""

    grid: np.ndarray
    origin: np.ndarray
    spacing: float
    band: float
    rest: np.ndarray

    def kernel_args(self) -> tuple:
        """The field as the object pass takes it: the last five of
        :data:`catwalk.collide.kernels.ObjectField`."""
        return self.grid, self.origin, 1.0 / self.spacing, self.band, self.rest

    def distance(self, points: np.ndarray) -> np.ndarray:
        """The field's signed distance at ``points`` (P, 3) in the first pose."""
        p = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3)
        out = np.empty(len(p))
        _distances(self.grid, self.origin, 1.0 / self.spacing, self.band, p, out)
        return out


@numba.njit(cache=True)
def _splat(v, n, faces, origin, h, band, grid):
    """Each triangle's exact distance to the grid points in its box dilated by the band;
    each grid point keeps the nearest (``grid`` starts at + band), signed by the
    interpolated vertex normal there."""
    nx_, ny_, nz_ = grid.shape
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        lo = np.empty(3, np.int64)
        hi = np.empty(3, np.int64)
        dims = (nx_, ny_, nz_)
        for q in range(3):
            mn = min(v[a, q], v[b, q], v[c, q]) - band
            mx = max(v[a, q], v[b, q], v[c, q]) + band
            lo[q] = max(int(math.ceil((mn - origin[q]) / h)), 0)
            hi[q] = min(int(math.floor((mx - origin[q]) / h)), dims[q] - 1)
        for i in range(lo[0], hi[0] + 1):
            px = origin[0] + i * h
            for j in range(lo[1], hi[1] + 1):
                py = origin[1] + j * h
                for k in range(lo[2], hi[2] + 1):
                    pz = origin[2] + k * h
                    u, w = closest_on_triangle(px, py, pz, v[a, 0], v[a, 1], v[a, 2],
                                               v[b, 0], v[b, 1], v[b, 2],
                                               v[c, 0], v[c, 1], v[c, 2])
                    s = 1.0 - u - w
                    dx = px - (s * v[a, 0] + u * v[b, 0] + w * v[c, 0])
                    dy = py - (s * v[a, 1] + u * v[b, 1] + w * v[c, 1])
                    dz = pz - (s * v[a, 2] + u * v[b, 2] + w * v[c, 2])
                    d2 = dx * dx + dy * dy + dz * dz
                    g = grid[i, j, k]
                    if d2 < g * g:
                        sn = (dx * (s * n[a, 0] + u * n[b, 0] + w * n[c, 0])
                              + dy * (s * n[a, 1] + u * n[b, 1] + w * n[c, 1])
                              + dz * (s * n[a, 2] + u * n[b, 2] + w * n[c, 2]))
                        d = math.sqrt(d2)
                        grid[i, j, k] = d if sn >= 0.0 else -d


@numba.njit(cache=True, _nrt=False, inline="always")
def field_distance(grid, origin, inv_h, band, qx, qy, qz):
    """The field's signed distance at (qx, qy, qz) (trilinear between its grid points; + band
    outside the grid)."""
    fx = (qx - origin[0]) * inv_h
    fy = (qy - origin[1]) * inv_h
    fz = (qz - origin[2]) * inv_h
    i = int(math.floor(fx))
    j = int(math.floor(fy))
    k = int(math.floor(fz))
    if i < 0 or j < 0 or k < 0 or i + 1 >= grid.shape[0] or j + 1 >= grid.shape[1] or \
            k + 1 >= grid.shape[2]:
        return band
    tx = fx - i
    ty = fy - j
    tz = fz - k
    c00 = grid[i, j, k] * (1.0 - tx) + grid[i + 1, j, k] * tx
    c10 = grid[i, j + 1, k] * (1.0 - tx) + grid[i + 1, j + 1, k] * tx
    c01 = grid[i, j, k + 1] * (1.0 - tx) + grid[i + 1, j, k + 1] * tx
    c11 = grid[i, j + 1, k + 1] * (1.0 - tx) + grid[i + 1, j + 1, k + 1] * tx
    c0 = c00 * (1.0 - ty) + c10 * ty
    c1 = c01 * (1.0 - ty) + c11 * ty
    return c0 * (1.0 - tz) + c1 * tz


@numba.njit(cache=True, _nrt=False, inline="always")
def _triangle_frame(ax, ay, az, bx, by, bz, cx, cy, cz):
    """The triangle's frame: the unit edge a→b, the unit normal's cross with it, the unit
    normal (9 numbers), and whether the triangle has one (not degenerate)."""
    ex, ey, ez = bx - ax, by - ay, bz - az
    fx, fy, fz = cx - ax, cy - ay, cz - az
    nx = ey * fz - ez * fy
    ny = ez * fx - ex * fz
    nz = ex * fy - ey * fx
    le = math.sqrt(ex * ex + ey * ey + ez * ez)
    ln = math.sqrt(nx * nx + ny * ny + nz * nz)
    if le < 1e-12 or ln < 1e-18:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, False
    ex /= le
    ey /= le
    ez /= le
    nx /= ln
    ny /= ln
    nz /= ln
    return (ex, ey, ez, ny * ez - nz * ey, nz * ex - nx * ez, nx * ey - ny * ex, nx, ny, nz,
            True)


@numba.njit(cache=True, _nrt=False, inline="always")
def carry_back(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz, rax, ray, raz, rbx, rby, rbz,
               rcx, rcy, rcz):
    """The point p carried from the posed triangle (a, b, c) to the same place relative to
    it in the first pose (vertices ra, rb, rc): its coordinates in the posed triangle's
    frame (:func:`_triangle_frame`, origin a) put in the first pose's. Returns (qx, qy, qz,
    ok): ok False for a degenerate triangle."""
    ex, ey, ez, gx, gy, gz, nx, ny, nz, ok = _triangle_frame(ax, ay, az, bx, by, bz, cx, cy,
                                                             cz)
    rex, rey, rez, rgx, rgy, rgz, rnx, rny, rnz, rok = _triangle_frame(
        rax, ray, raz, rbx, rby, rbz, rcx, rcy, rcz)
    if not (ok and rok):
        return 0.0, 0.0, 0.0, False
    dx, dy, dz = px - ax, py - ay, pz - az
    u = dx * ex + dy * ey + dz * ez
    w = dx * gx + dy * gy + dz * gz
    s = dx * nx + dy * ny + dz * nz
    return (rax + u * rex + w * rgx + s * rnx, ray + u * rey + w * rgy + s * rny,
            raz + u * rez + w * rgz + s * rnz, True)


@numba.njit(cache=True)
def _distances(grid, origin, inv_h, band, p, out):
    for i in range(p.shape[0]):
        out[i] = field_distance(grid, origin, inv_h, band, p[i, 0], p[i, 1], p[i, 2])


def build_field(vertices, faces, spacing: float = FIELD_SPACING,
                band: float = FIELD_BAND) -> RestField:
    """The signed distance field of the mesh (``vertices`` (N, 3), ``faces`` (M, 3)) on a grid
    of ``spacing`` over its box grown by ``band``, exact within ``band`` of the surface."""
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.int64)
    if not (spacing > 0 and band >= 2 * spacing):
        raise InputError(f"field spacing must be > 0 and the band at least twice it, got "
                         f"{spacing!r}, {band!r}")
    lo = v.min(axis=0) - band
    dims = np.ceil((v.max(axis=0) + band - lo) / spacing).astype(np.int64) + 1
    grid = np.full(tuple(dims), band, np.float32)
    # beyond the band the grid keeps + band, inside the body too (which side is not asked
    # there: the object pass reads the field only within band − 2 spacings of a kept
    # triangle, where every grid point round the point read is within the band; filling
    # the inside would also fill the outside pockets the band's shell closes, between an
    # arm and the torso)
    _splat(v, vertex_normals(v, f), f, lo, float(spacing), float(band), grid)
    return RestField(grid, lo, float(spacing), float(band), v.copy())


#: the fields per first pose (a digest of the vertices and faces): a worker dresses and walks
#: many garments on one body, and a field costs ≈ 0.4 s and ≈ 43 MB (the last two kept)
_FIELD_CACHE: dict = {}
_FIELDS_KEPT = 2


def rest_field(vertices, faces) -> RestField:
    """The field of this pose, made once per pose and process (the last two kept)."""
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    hsh = hashlib.blake2b(v.astype(np.float32).tobytes(), digest_size=16)
    hsh.update(np.ascontiguousarray(faces, dtype=np.int64).tobytes())
    key = hsh.digest()
    if key not in _FIELD_CACHE:
        if len(_FIELD_CACHE) >= _FIELDS_KEPT:
            _FIELD_CACHE.pop(next(iter(_FIELD_CACHE)))
        _FIELD_CACHE[key] = build_field(v, faces)
    return _FIELD_CACHE[key]
