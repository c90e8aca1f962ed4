"""An orthographic z-buffer triangle rasteriser on the CPU (numba), shared by the preview
renderer and the collider's depth maps.

Screen space: ``x`` is the column and ``y`` the row, in pixels, with pixel ``(row i, col j)``
covering ``[j, j+1) × [i, i+1)`` and sampled at its centre ``(j + 0.5, i + 0.5)``; row 0 is the
top of the image. ``z`` is the depth coordinate along the axis that points *towards* the camera,
in whatever unit the caller uses (the helpers below keep metres), so the *nearest* surface is the
one with the *largest* ``z``.

:func:`rasterize` keeps per pixel either the nearest (``keep="near"``, a normal z-buffer: the
front depth map) or the farthest (``keep="far"``: the back depth map, on the same pixel grid)
surface, with per-pixel attributes interpolated barycentrically from per-vertex ones (normals,
velocities, colours: any ``k`` floats; under an orthographic projection this interpolation is
exact for any attribute linear over the triangle) and the id of the triangle seen. Pixels that no
triangle covers have depth ``-inf`` (near) or ``+inf`` (far), triangle id ``-1`` and attributes
zero (:func:`clear_depth` alone leaves them stale: read attributes only where covered).

:func:`ortho_view` builds the world → screen transform of an orthographic camera that looks at
a bounding box horizontally from any yaw angle (``front`` = camera on +Z looking −Z, ``side``
= camera on +X, the body's left, ``back`` = camera on −Z), fitted to the box. The transform is a
3×4 matrix ``M`` so that ``screen = M[:, :3] @ p + M[:, 3]``; :func:`to_screen` applies it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from catwalk.errors import InputError

NAMED_VIEWS = {"front": 0.0, "side": 90.0, "left": 90.0, "back": 180.0, "right": 270.0}


@numba.njit(cache=True, _nrt=False)
def clear_depth(keep_far, depth, tri):
    """Reset depth and triangle ids to empty in place (attributes are left as they are: they
    are meaningful only where ``tri >= 0``)."""
    h, w = depth.shape
    fill = np.inf if keep_far else -np.inf
    for i in range(h):
        for j in range(w):
            depth[i, j] = fill
            tri[i, j] = -1


@numba.njit(cache=True, _nrt=False)
def clear_buffers(keep_far, depth, attrs, tri):
    """Reset buffers to empty (no triangle seen, attributes zero) in place."""
    clear_depth(keep_far, depth, tri)
    attrs[:] = 0.0


CULL_NONE, CULL_BACK, CULL_FRONT = 0, 1, -1


@numba.njit(cache=True, _nrt=False, inline="always")
def _weight_span(w, d, eps, lo, hi):
    """Narrow the column offsets [lo, hi] to where a barycentric weight w + d·offset is
    >= −eps; (False, …) when it is nowhere."""
    if d > 0.0:
        lo = max(lo, (-eps - w) / d)
    elif d < 0.0:
        hi = min(hi, (-eps - w) / d)
    elif w < -eps:
        return False, lo, hi
    return True, lo, hi


@numba.njit(cache=True, _nrt=False, inline="always")
def row_span(x0, y0, x1, y1, x2, y2, inv, d0, d1, d2, j0, j1, py, small, eps):
    """The columns of pixel row ``py`` (its centre's y) that the triangle covers, within
    [j0, j1]: returns (ok, ja, jb, w0s, w1s) with w0s, w1s the barycentric weights at column j0
    (a weight at column j is w(j0) + d·(j − j0)); ``small``: test every column (no span
    arithmetic; the caller tests each pixel's weights anyway). Shared by the image rasteriser
    and the collider's depth maps."""
    px0 = j0 + 0.5
    w0s = ((x1 - px0) * (y2 - py) - (x2 - px0) * (y1 - py)) * inv
    w1s = ((x2 - px0) * (y0 - py) - (x0 - px0) * (y2 - py)) * inv
    w2s = 1.0 - w0s - w1s
    if small:
        return True, j0, j1, w0s, w1s
    # the span of columns where all three weights are >= −eps
    ok, lo, hi = _weight_span(w0s, d0, eps, 0.0, float(j1 - j0))
    if ok:
        ok, lo, hi = _weight_span(w1s, d1, eps, lo, hi)
    if ok:
        ok, lo, hi = _weight_span(w2s, d2, eps, lo, hi)
    if not ok or lo > hi:
        return False, j0, j1, w0s, w1s
    ja = max(j0 + int(math.ceil(lo - 1e-7)), j0)
    jb = min(j0 + int(math.floor(hi + 1e-7)), j1)
    return True, ja, jb, w0s, w1s


@numba.njit(cache=True, _nrt=False)
def raster_kernel(sv, faces, vattr, keep_far, depth, attrs, tri, cull=0):
    """Rasterise triangles ``faces`` (M,3) of screen vertices ``sv`` (N,3) into the buffers.

    ``vattr`` (N,k) per-vertex attributes; ``depth`` (H,W), ``attrs`` (H,W,k), ``tri`` (H,W)
    are updated in place (clear them first for a fresh frame); any strides and float
    precision. A pixel is covered when its centre lies inside the triangle or on its edge.
    ``cull``: 0 every triangle; 1 (``CULL_BACK``) only triangles facing the camera
    (counter-clockwise seen from it), −1 (``CULL_FRONT``) only those facing away — on a closed
    surface the nearest layer faces the camera and the farthest faces away, so depth maps may
    cull. Returns the number of pixel writes.
    """
    h, w = depth.shape
    k = vattr.shape[1]
    written = 0
    eps = 1e-9
    for t in range(faces.shape[0]):
        a = faces[t, 0]
        b = faces[t, 1]
        c = faces[t, 2]
        x0 = sv[a, 0]
        y0 = sv[a, 1]
        z0 = sv[a, 2]
        x1 = sv[b, 0]
        y1 = sv[b, 1]
        z1 = sv[b, 2]
        x2 = sv[c, 0]
        y2 = sv[c, 1]
        z2 = sv[c, 2]
        area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
        if not (abs(area) > 1e-14):  # degenerate or NaN
            continue
        # rows grow downwards, so a triangle counter-clockwise from the camera has area < 0
        if cull == 1 and area > 0.0:
            continue
        if cull == -1 and area < 0.0:
            continue
        inv = 1.0 / area
        xmin = min(x0, min(x1, x2))
        xmax = max(x0, max(x1, x2))
        ymin = min(y0, min(y1, y2))
        ymax = max(y0, max(y1, y2))
        j0 = max(int(math.ceil(xmin - 0.5)), 0)
        j1 = min(int(math.floor(xmax - 0.5)), w - 1)
        i0 = max(int(math.ceil(ymin - 0.5)), 0)
        i1 = min(int(math.floor(ymax - 0.5)), h - 1)
        if j0 > j1 or i0 > i1:
            continue
        # barycentric weights are linear in the pixel column: w = w(j0) + d·(j − j0)
        d0 = (y1 - y2) * inv
        d1 = (y2 - y0) * inv
        d2 = -(d0 + d1)
        small = (j1 - j0) < 3  # narrow: test every pixel, no span arithmetic
        for i in range(i0, i1 + 1):
            ok, ja, jb, w0s, w1s = row_span(x0, y0, x1, y1, x2, y2, inv, d0, d1, d2, j0, j1,
                                            i + 0.5, small, eps)
            if not ok:
                continue
            for j in range(ja, jb + 1):
                dj = j - j0
                w0 = w0s + d0 * dj
                w1 = w1s + d1 * dj
                w2 = 1.0 - w0 - w1
                if w0 < -eps or w1 < -eps or w2 < -eps:
                    continue
                z = w0 * z0 + w1 * z1 + w2 * z2
                # nearest = largest z (z points towards the camera); farthest = smallest
                if tri[i, j] >= 0:
                    if keep_far:
                        if z >= depth[i, j]:
                            continue
                    elif z <= depth[i, j]:
                        continue
                depth[i, j] = z
                tri[i, j] = t
                for q in range(k):
                    attrs[i, j, q] = w0 * vattr[a, q] + w1 * vattr[b, q] + w2 * vattr[c, q]
                written += 1
    return written


@numba.njit(cache=True, _nrt=False)
def transform_points(m, p, out):
    """``out[i] = m[:, :3] @ p[i] + m[:, 3]`` for a 3×4 matrix ``m``."""
    for i in range(p.shape[0]):
        x = p[i, 0]
        y = p[i, 1]
        z = p[i, 2]
        for r in range(3):
            out[i, r] = m[r, 0] * x + m[r, 1] * y + m[r, 2] * z + m[r, 3]


@dataclass
class Raster:
    """Buffers of one rasterisation: ``depth`` (H,W), ``attributes`` (H,W,k), ``triangle``
    (H,W) int32 (−1 where empty), ``keep_far``."""

    depth: np.ndarray
    attributes: np.ndarray
    triangle: np.ndarray
    keep_far: bool

    @classmethod
    def empty(cls, width: int, height: int, k: int = 0, keep: str = "near") -> Raster:
        keep_far = _keep_far(keep)
        r = cls(np.empty((height, width)), np.zeros((height, width, k)),
                np.empty((height, width), np.int32), keep_far)
        r.clear()
        return r

    def clear(self) -> None:
        clear_buffers(self.keep_far, self.depth, self.attributes, self.triangle)

    @property
    def covered(self) -> np.ndarray:
        return self.triangle >= 0


def _keep_far(keep: str) -> bool:
    if keep not in ("near", "far"):
        raise InputError(f"keep must be 'near' or 'far', not {keep!r}")
    return keep == "far"


def rasterize(screen_vertices, faces, attributes=None, size=(256, 256), keep="near",
              out: Raster | None = None, cull: int = 0) -> Raster:
    """Rasterise a triangle mesh already in screen space (see the module docstring).

    ``screen_vertices`` (N,3) float, ``faces`` (M,3) int, ``attributes`` (N,k) float or None,
    ``size`` = (width, height). ``out``: a :class:`Raster` to reuse (cleared first); its shape
    and ``keep`` then win. ``cull``: see :func:`raster_kernel`. Returns the :class:`Raster`.
    """
    sv = np.ascontiguousarray(screen_vertices, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.int64)
    if sv.ndim != 2 or sv.shape[1] != 3:
        raise InputError(f"screen vertices must be (N, 3), got {sv.shape}")
    if f.size and (f.ndim != 2 or f.shape[1] != 3 or f.min() < 0 or f.max() >= len(sv)):
        raise InputError("faces must be (M, 3) indices into the vertices")
    f = f.reshape(-1, 3)
    if attributes is None:
        va = np.zeros((len(sv), 0))
    else:
        va = np.ascontiguousarray(attributes, dtype=np.float64)
        if va.ndim == 1:
            va = va[:, None]
        if va.shape[0] != len(sv):
            raise InputError(f"attributes must have one row per vertex, got {va.shape}")
    if out is None:
        w, h = int(size[0]), int(size[1])
        if w < 1 or h < 1:
            raise InputError(f"image size must be positive, got {size}")
        out = Raster.empty(w, h, va.shape[1], keep)
    else:
        if out.attributes.shape[2] != va.shape[1]:
            raise InputError("reused raster has a different number of attributes")
        out.clear()
    if cull not in (CULL_NONE, CULL_BACK, CULL_FRONT):
        raise InputError(f"cull must be 0, 1 or -1, not {cull!r}")
    raster_kernel(sv, f, va, out.keep_far, out.depth, out.attributes, out.triangle, cull)
    return out


# --------------------------------------------------------------------------- views


@dataclass
class OrthoView:
    """An orthographic camera: ``matrix`` (3×4) maps world points to screen (x col, y row,
    z towards the camera, metres); ``size`` = (width, height) in pixels; ``yaw_deg`` the yaw;
    ``pixel`` = (metres per pixel in x, in y)."""

    matrix: np.ndarray
    size: tuple[int, int]
    yaw_deg: float
    pixel: tuple[float, float]

    @property
    def right(self) -> np.ndarray:
        return self.matrix[0, :3] / np.linalg.norm(self.matrix[0, :3])

    @property
    def up(self) -> np.ndarray:
        return -self.matrix[1, :3] / np.linalg.norm(self.matrix[1, :3])

    @property
    def toward_camera(self) -> np.ndarray:
        return self.matrix[2, :3].copy()

    def to_screen(self, points) -> np.ndarray:
        return to_screen(self.matrix, points)


def to_screen(matrix, points) -> np.ndarray:
    p = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3)
    out = np.empty_like(p)
    transform_points(np.ascontiguousarray(matrix, dtype=np.float64), p, out)
    return out


def view_yaw(view) -> float:
    """Yaw in degrees of a named view (front, side/left, back, right) or a number."""
    if isinstance(view, str) and view in NAMED_VIEWS:
        return NAMED_VIEWS[view]
    try:
        yaw = float(view)
    except (TypeError, ValueError):
        yaw = math.nan
    if not math.isfinite(yaw):
        raise InputError(f"unknown view {view!r}: use front, side, back, right or a yaw in "
                         "degrees")
    return yaw


def camera_axes(yaw_deg: float):
    """(right, up, toward_camera) unit vectors of a horizontal camera at yaw ``yaw_deg``
    (0 = on +Z looking −Z; 90 = on +X)."""
    t = math.radians(yaw_deg)
    c = np.array([math.sin(t), 0.0, math.cos(t)])
    r = np.array([math.cos(t), 0.0, -math.sin(t)])
    u = np.array([0.0, 1.0, 0.0])
    return r, u, c


def ortho_view(bbox_min, bbox_max, view="front", size=(256, 256), margin=0.0,
               square_pixels=True) -> OrthoView:
    """An orthographic camera looking at the box ``[bbox_min, bbox_max]`` from ``view``.

    The box's projection (all 8 corners) fills the image, less ``margin`` (a fraction of the
    image on each side), centred; with ``square_pixels`` one scale for x and y (the box fits in
    the tighter direction), else x and y are stretched independently to fill the image exactly
    (what depth maps over a bounding box want). Depth ``z`` is in metres along the axis pointing
    to the camera, measured from the box's centre.
    """
    lo = np.asarray(bbox_min, dtype=np.float64)
    hi = np.asarray(bbox_max, dtype=np.float64)
    if lo.shape != (3,) or hi.shape != (3,) or not np.all(np.isfinite(lo)) or \
            not np.all(np.isfinite(hi)) or np.any(hi < lo):
        raise InputError("bounding box must be two finite 3-vectors with min <= max")
    w, h = int(size[0]), int(size[1])
    if w < 1 or h < 1:
        raise InputError(f"image size must be positive, got {size}")
    if not 0.0 <= margin < 0.5:
        raise InputError(f"margin must be in [0, 0.5), got {margin}")
    yaw = view_yaw(view)
    r, u, c = camera_axes(yaw)
    centre = 0.5 * (lo + hi)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])]) - centre
    ext_r = max(float(np.abs(corners @ r).max()) * 2.0, 1e-9)
    ext_u = max(float(np.abs(corners @ u).max()) * 2.0, 1e-9)
    avail_w = w * (1.0 - 2.0 * margin)
    avail_h = h * (1.0 - 2.0 * margin)
    sx = avail_w / ext_r
    sy = avail_h / ext_u
    if square_pixels:
        sx = sy = min(sx, sy)
    m = np.zeros((3, 4))
    m[0, :3] = r * sx
    m[0, 3] = 0.5 * w - sx * float(r @ centre)
    m[1, :3] = -u * sy
    m[1, 3] = 0.5 * h + sy * float(u @ centre)
    m[2, :3] = c
    m[2, 3] = -float(c @ centre)
    return OrthoView(m, (w, h), yaw, (1.0 / sx, 1.0 / sy))


# --------------------------------------------------------------------------- normals


@numba.njit(cache=True, _nrt=False)
def vertex_normals_kernel(v, faces, out):
    """Area-weighted per-vertex normals (unit; zero for unused vertices) into ``out`` (N,3)."""
    out[:] = 0.0
    for t in range(faces.shape[0]):
        a = faces[t, 0]
        b = faces[t, 1]
        c = faces[t, 2]
        e1x = v[b, 0] - v[a, 0]
        e1y = v[b, 1] - v[a, 1]
        e1z = v[b, 2] - v[a, 2]
        e2x = v[c, 0] - v[a, 0]
        e2y = v[c, 1] - v[a, 1]
        e2z = v[c, 2] - v[a, 2]
        nx = e1y * e2z - e1z * e2y
        ny = e1z * e2x - e1x * e2z
        nz = e1x * e2y - e1y * e2x
        for q in (a, b, c):
            out[q, 0] += nx
            out[q, 1] += ny
            out[q, 2] += nz
    for i in range(v.shape[0]):
        n = math.sqrt(out[i, 0] ** 2 + out[i, 1] ** 2 + out[i, 2] ** 2)
        if n > 0.0:
            out[i, 0] /= n
            out[i, 1] /= n
            out[i, 2] /= n


def vertex_normals(vertices, faces) -> np.ndarray:
    """Area-weighted unit vertex normals of a triangle mesh (counter-clockwise faces point out)."""
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    out = np.empty_like(v)
    vertex_normals_kernel(v, np.ascontiguousarray(faces, dtype=np.int64), out)
    return out


def incident_faces(faces, n_vertices: int) -> tuple[np.ndarray, np.ndarray]:
    """The faces at each vertex as CSR: (pointer (n+1,), face ids), ids ascending per vertex."""
    f = np.asarray(faces, dtype=np.int64).ravel()
    order = np.argsort(f, kind="stable")
    ptr = np.zeros(n_vertices + 1, dtype=np.int64)
    np.cumsum(np.bincount(f, minlength=n_vertices), out=ptr[1:])
    return ptr, (order // 3).astype(np.int64)
