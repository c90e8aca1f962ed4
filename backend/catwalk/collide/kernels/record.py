"""The body packed for the object pass (:func:`pack_body`) and each cloth point's copy of its
closest triangle (:func:`fill_record`), read in point order while the triangle is reused: the
triangle at a time of the frame (:func:`rec_triangle_at`), the signed distance to it
(:func:`signed_rec`) and the body's velocity on it (:func:`rec_velocity`).

The layouts, by name (the readers never count columns):

* a body vertex packed for the object pass, a row of ``vb`` (N, :data:`VB_COLUMNS`) float32
  (72 bytes): its position, normal and velocity at the previous frame (:data:`VB_X0`,
  :data:`VB_N0`, :data:`VB_W0`, three columns each) and at the current one (:data:`VB_X1`,
  :data:`VB_N1`, :data:`VB_W1`: each :data:`FRAME_STEP` after the previous frame's);
* a point's record of its closest triangle, a row of ``rec`` (P, :data:`REC_COLUMNS`)
  float32: the triangle's corners a, b, c in turn (:data:`REC_A`, :data:`REC_B`,
  :data:`REC_C`), each a packed vertex (``REC_B + VB_N1``: corner b's normal at the current
  frame);
* the positions alone, ``vp`` (N, 6) float32: :data:`catwalk.collide.bvh.VP_X0`,
  :data:`~catwalk.collide.bvh.VP_X1` (the hierarchy's refit reads them).
"""

from __future__ import annotations

import math

import numba

from catwalk.collide.bvh import VP_X0, VP_X1
from catwalk.collide.kernels.boxes import body_motion
from catwalk.geometry.triangles import closest_on_triangle

VB_X0, VB_X1, VB_N0, VB_N1, VB_W0, VB_W1 = 0, 3, 6, 9, 12, 15
#: a quantity's columns at the current frame follow its columns at the previous one by this
FRAME_STEP = 3
VB_COLUMNS = 18
REC_A, REC_B, REC_C = 0, VB_COLUMNS, 2 * VB_COLUMNS
REC_COLUMNS = 3 * VB_COLUMNS


@numba.njit(cache=True, _nrt=False)
def pack_body(v0, v1, n0, n1, w0, w1, idx, vb, vp, ref):
    """Per frame, for the vertices ``idx`` (those of the parts in hierarchies): interleave
    the two frames' positions, normals, velocities per vertex into ``vb`` (:data:`VB_X0` …),
    one vertex in 72 bytes; and the positions alone into ``vp`` (N,6) float32, small enough to
    stay in cache during the hierarchy walks. Returns :func:`body_motion` (``ref`` gets the
    frame's mean displacement)."""
    for k in range(idx.shape[0]):
        i = idx[k]
        for q in range(3):
            vp[i, VP_X0 + q] = v0[i, q]
            vp[i, VP_X1 + q] = v1[i, q]
            vb[i, VB_X0 + q] = v0[i, q]
            vb[i, VB_X1 + q] = v1[i, q]
            vb[i, VB_N0 + q] = n0[i, q]
            vb[i, VB_N1 + q] = n1[i, q]
            vb[i, VB_W0 + q] = w0[i, q]
            vb[i, VB_W1 + q] = w1[i, q]
    return body_motion(v0, v1, idx, ref)


@numba.njit(cache=True, _nrt=False, inline="always")
def fill_record(rec, i, vb, faces, t):
    """Copy triangle t's three vertices (each a packed vertex, as in ``vb``) into the point's
    record ``rec[i]``: corner c at ``REC_A + c·VB_COLUMNS``."""
    for c in range(3):
        v = faces[t, c]
        for q in range(VB_COLUMNS):
            rec[i, REC_A + VB_COLUMNS * c + q] = vb[v, q]


@numba.njit(cache=True, _nrt=False, inline="always")
def rec_at(rec, i, col, k, alpha):
    """The xyz of the record's columns ``col`` (a corner, :data:`REC_A` …, plus a quantity at
    the previous frame, :data:`VB_X0` …) at time ``alpha`` of the frame: k × the previous
    frame's + alpha × the current one's (k = 1 − alpha)."""
    c = col + FRAME_STEP
    return (k * rec[i, col] + alpha * rec[i, c],
            k * rec[i, col + 1] + alpha * rec[i, c + 1],
            k * rec[i, col + 2] + alpha * rec[i, c + 2])


@numba.njit(cache=True, _nrt=False, inline="always")
def rec_triangle_at(rec, i, k, alpha):
    """The record's triangle at time ``alpha`` (k = 1 − alpha): its corners a, b, c, xyz
    each."""
    ax, ay, az = rec_at(rec, i, REC_A + VB_X0, k, alpha)
    bx, by, bz = rec_at(rec, i, REC_B + VB_X0, k, alpha)
    cx, cy, cz = rec_at(rec, i, REC_C + VB_X0, k, alpha)
    return ax, ay, az, bx, by, bz, cx, cy, cz


@numba.njit(cache=True, _nrt=False, inline="always")
def rec_centroid(rec, i, q, b, alpha):
    """Coordinate q of the record's triangle's centroid at time ``alpha`` (b = 1 − alpha)."""
    return (b * (rec[i, REC_A + VB_X0 + q] + rec[i, REC_B + VB_X0 + q]
                 + rec[i, REC_C + VB_X0 + q])
            + alpha * (rec[i, REC_A + VB_X1 + q] + rec[i, REC_B + VB_X1 + q]
                       + rec[i, REC_C + VB_X1 + q])) / 3.0


@numba.njit(cache=True, _nrt=False)
def signed_rec(px, py, pz, rec, i, alpha):
    """Signed distance of p to the triangle copied in ``rec[i]`` (:func:`fill_record`) at time
    alpha: (p − q)·n_s with q the closest point and n_s the interpolated vertex normal there;
    returns (s, nx, ny, nz, bary v, bary w)."""
    k = 1.0 - alpha
    ax, ay, az, bx, by, bz, cx, cy, cz = rec_triangle_at(rec, i, k, alpha)
    v, w = closest_on_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz)
    u = 1.0 - v - w
    qx = ax + v * (bx - ax) + w * (cx - ax)
    qy = ay + v * (by - ay) + w * (cy - ay)
    qz = az + v * (bz - az) + w * (cz - az)
    nax, nay, naz = rec_at(rec, i, REC_A + VB_N0, k, alpha)
    nbx, nby, nbz = rec_at(rec, i, REC_B + VB_N0, k, alpha)
    ncx, ncy, ncz = rec_at(rec, i, REC_C + VB_N0, k, alpha)
    nx = u * nax + v * nbx + w * ncx
    ny = u * nay + v * nby + w * ncy
    nz = u * naz + v * nbz + w * ncz
    nl = math.sqrt(nx * nx + ny * ny + nz * nz)
    if nl < 1e-12:  # degenerate: use the face normal
        nx = (by - ay) * (cz - az) - (bz - az) * (cy - ay)
        ny = (bz - az) * (cx - ax) - (bx - ax) * (cz - az)
        nz = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
        nl = math.sqrt(nx * nx + ny * ny + nz * nz) + 1e-300
    nx /= nl
    ny /= nl
    nz /= nl
    s = (px - qx) * nx + (py - qy) * ny + (pz - qz) * nz
    return s, nx, ny, nz, v, w


@numba.njit(cache=True, _nrt=False, inline="always")
def _rec_bary(rec, i, col, bu, bv, bw):
    """The xyz of a quantity's columns ``col`` (:data:`VB_W0` …) at barycentric
    (bu, bv, bw) of the record's triangle."""
    return (bu * rec[i, REC_A + col] + bv * rec[i, REC_B + col] + bw * rec[i, REC_C + col],
            bu * rec[i, REC_A + col + 1] + bv * rec[i, REC_B + col + 1]
            + bw * rec[i, REC_C + col + 1],
            bu * rec[i, REC_A + col + 2] + bv * rec[i, REC_B + col + 2]
            + bw * rec[i, REC_C + col + 2])


@numba.njit(cache=True, _nrt=False, inline="always")
def rec_velocity(rec, i, alpha, bv, bw):
    """The body's velocity at barycentric (1 − bv − bw, bv, bw) of the triangle in ``rec[i]``
    at time alpha."""
    b = 1.0 - alpha
    bu = 1.0 - bv - bw
    w0x, w0y, w0z = _rec_bary(rec, i, VB_W0, bu, bv, bw)
    w1x, w1y, w1z = _rec_bary(rec, i, VB_W1, bu, bv, bw)
    vx = b * w0x + alpha * w1x
    vy = b * w0y + alpha * w1y
    vz = b * w0z + alpha * w1z
    return vx, vy, vz
