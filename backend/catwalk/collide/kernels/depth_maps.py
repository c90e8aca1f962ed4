"""Drawing the depth maps: one slot of the front and back maps over the region the cloth can
reach (:func:`render_maps`) and that region (:func:`map_region`).

The maps' layout (:class:`catwalk.collide.image_pass.DepthMaps`): depths ``D`` (H, W, 2 slots,
2 sides) float32, side :data:`SIDE_FRONT` the surfaces facing the camera (the nearest kept),
:data:`SIDE_BACK` those facing away (the farthest kept), −inf/+inf where none is drawn; each
pixel's attributes ``A`` (H, W, 2 sides, 2 slots, :data:`N_ATTRS`) float32, the interpolated
vertex normal (:data:`ATTR_NORMAL`, xyz) and body velocity (:data:`ATTR_VELOCITY`, xyz); the
triangle drawn ``tri`` (2 slots, 2 sides, H, W) int32, −1 for none.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from catwalk.geometry.raster import row_span

SIDE_FRONT, SIDE_BACK = 0, 1
ATTR_NORMAL, ATTR_VELOCITY = 0, 3
N_ATTRS = 6


@numba.njit(cache=True, _nrt=False)
def render_maps(m, frame, idx, faces, work, maps, slot, region):
    """Draw one slot of the front and back depth maps (see :class:`~catwalk.collide.
    image_pass.DepthMaps`) of the triangles ``faces`` over the mapped vertices ``idx`` of the
    body at one ``frame`` (its vertices ``v``, normals ``n`` and velocities ``w``), only within
    the ``region`` (rows r0…r1 and columns c0…c1: where the cloth can reach): the region is
    cleared and every triangle facing the camera drawn into the front map (nearest kept),
    every triangle facing away into the back map (farthest kept), in one pass. Inside the
    region the result is exactly that of :func:`catwalk.geometry.raster.raster_kernel` with
    back- and front-face culling over the whole map (same coverage rule, same order); outside
    it the maps are left as they were. ``maps``: (``D``, ``A``, ``tri``), the layout above;
    ``work`` (``sv``, ``attrs``): workspaces for the screen positions and attributes of
    ``idx``."""
    v, n, w = frame
    sv, attrs = work
    D, A, tri = maps
    r0, r1, c0, c1 = region
    for k in range(idx.shape[0]):
        i = idx[k]
        x = v[i, 0]
        y = v[i, 1]
        z = v[i, 2]
        for r in range(3):
            sv[k, r] = m[r, 0] * x + m[r, 1] * y + m[r, 2] * z + m[r, 3]
            attrs[k, ATTR_NORMAL + r] = n[i, r]
            attrs[k, ATTR_VELOCITY + r] = w[i, r]
    for i in range(r0, r1 + 1):
        for j in range(c0, c1 + 1):
            D[i, j, slot, SIDE_FRONT] = -np.inf
            D[i, j, slot, SIDE_BACK] = np.inf
            tri[slot, SIDE_FRONT, i, j] = -1
            tri[slot, SIDE_BACK, i, j] = -1
    for t in range(faces.shape[0]):
        _draw_triangle(t, faces, sv, attrs, D, A, tri, slot, region)


@numba.njit(cache=True, _nrt=False, inline="always")
def _draw_triangle(t, faces, sv, attrs, D, A, tri, slot, region):
    """Triangle t (screen positions ``sv``, attributes ``attrs`` of its corners) into the
    front map if it faces the camera, else the back one, within the ``region``: each pixel
    whose centre it covers, where it is nearer (front) or farther (back) than what is there."""
    r0, r1, c0, c1 = region
    eps = 1e-9
    a = faces[t, 0]
    b = faces[t, 1]
    c = faces[t, 2]
    x0 = sv[a, 0]
    y0 = sv[a, 1]
    x1 = sv[b, 0]
    y1 = sv[b, 1]
    x2 = sv[c, 0]
    y2 = sv[c, 1]
    xmin = min(x0, min(x1, x2))
    xmax = max(x0, max(x1, x2))
    ymin = min(y0, min(y1, y2))
    ymax = max(y0, max(y1, y2))
    j0 = max(int(math.ceil(xmin - 0.5)), c0)
    j1 = min(int(math.floor(xmax - 0.5)), c1)
    i0 = max(int(math.ceil(ymin - 0.5)), r0)
    i1 = min(int(math.floor(ymax - 0.5)), r1)
    if j0 > j1 or i0 > i1:
        return
    area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    if not (abs(area) > 1e-14):  # degenerate or NaN
        return
    # rows grow downwards: a triangle facing the camera has area < 0 → front map
    side = SIDE_FRONT if area < 0.0 else SIDE_BACK
    z0 = sv[a, 2]
    z1 = sv[b, 2]
    z2 = sv[c, 2]
    inv = 1.0 / area
    # the reference rasteriser's span arithmetic starts from the unclipped bounds
    jb0 = max(int(math.ceil(xmin - 0.5)), 0)
    jb1 = min(int(math.floor(xmax - 0.5)), D.shape[1] - 1)
    d0 = (y1 - y2) * inv
    d1 = (y2 - y0) * inv
    d2 = -(d0 + d1)
    small = (jb1 - jb0) < 3
    for i in range(i0, i1 + 1):
        ok, ja, jb, w0s, w1s = row_span(x0, y0, x1, y1, x2, y2, inv, d0, d1, d2, jb0, jb1,
                                        i + 0.5, small, eps)
        if not ok:
            continue
        for j in range(max(ja, j0), min(jb, j1) + 1):
            dj = j - jb0
            w0 = w0s + d0 * dj
            w1 = w1s + d1 * dj
            w2 = 1.0 - w0 - w1
            if w0 < -eps or w1 < -eps or w2 < -eps:
                continue
            z = w0 * z0 + w1 * z1 + w2 * z2
            if tri[slot, side, i, j] >= 0:
                if side == SIDE_BACK:
                    if z >= D[i, j, slot, SIDE_BACK]:
                        continue
                elif z <= D[i, j, slot, SIDE_FRONT]:
                    continue
            D[i, j, slot, side] = z
            tri[slot, side, i, j] = t
            for q in range(N_ATTRS):
                A[i, j, side, slot, q] = w0 * attrs[a, q] + w1 * attrs[b, q] + w2 * attrs[c, q]


@numba.njit(cache=True, _nrt=False)
def map_region(m, lo, hi, pad, w, h, out):
    """``out`` = (r0, r1, c0, c1): the rows and columns of the maps' pixels that look-ups of
    points in the box [lo − pad, hi + pad] can read (their 2×2 blocks), clipped to the grid
    of w × h pixels; (0, 0, 0, 0) off the grid."""
    xmin = np.inf
    xmax = -np.inf
    ymin = np.inf
    ymax = -np.inf
    for a in range(2):
        x = lo[0] - pad if a == 0 else hi[0] + pad
        for b in range(2):
            y = lo[1] - pad if b == 0 else hi[1] + pad
            for c in range(2):
                z = lo[2] - pad if c == 0 else hi[2] + pad
                sx = m[0, 0] * x + m[0, 1] * y + m[0, 2] * z + m[0, 3]
                sy = m[1, 0] * x + m[1, 1] * y + m[1, 2] * z + m[1, 3]
                xmin = min(xmin, sx)
                xmax = max(xmax, sx)
                ymin = min(ymin, sy)
                ymax = max(ymax, sy)
    if not (np.isfinite(xmin) and np.isfinite(xmax) and np.isfinite(ymin) and
            np.isfinite(ymax)):
        out[0] = 0
        out[1] = h - 1
        out[2] = 0
        out[3] = w - 1
        return
    c0 = max(int(math.floor(min(max(xmin, -1e9), 1e9) - 0.5)), 0)
    c1 = min(int(math.floor(min(max(xmax, -1e9), 1e9) - 0.5)) + 1, w - 1)
    r0 = max(int(math.floor(min(max(ymin, -1e9), 1e9) - 0.5)), 0)
    r1 = min(int(math.floor(min(max(ymax, -1e9), 1e9) - 0.5)) + 1, h - 1)
    if c0 > c1 or r0 > r1:
        c0 = 0
        c1 = 0
        r0 = 0
        r1 = 0
    out[0] = r0
    out[1] = r1
    out[2] = c0
    out[3] = c1
