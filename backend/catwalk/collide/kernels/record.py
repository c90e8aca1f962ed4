"""The body packed for the object pass (:func:`pack_body`) and each cloth point's copy of its
closest triangle (:func:`fill_record`), read in point order while the triangle is reused: the
signed distance to it (:func:`signed_rec`) and the body's velocity on it (:func:`rec_velocity`)."""

from __future__ import annotations

import math

import numba

from catwalk.collide.kernels.boxes import body_motion
from catwalk.geometry.triangles import closest_on_triangle


@numba.njit(cache=True, _nrt=False)
def pack_body(v0, v1, n0, n1, w0, w1, idx, vb, vp, ref):
    """Per frame, for the vertices ``idx`` (those of the parts in hierarchies): interleave
    the two frames' positions, normals, velocities per vertex into ``vb`` (N,18) float32
    (previous frame 0–2, 6–8, 12–14; current 3–5, 9–11, 15–17), one vertex in 72 bytes; and
    the positions alone into ``vp`` (N,6) float32, small enough to stay in cache during the
    hierarchy walks. Returns :func:`body_motion` (``ref`` gets the frame's mean displacement)."""
    for k in range(idx.shape[0]):
        i = idx[k]
        for q in range(3):
            vp[i, q] = v0[i, q]
            vp[i, 3 + q] = v1[i, q]
            vb[i, q] = v0[i, q]
            vb[i, 3 + q] = v1[i, q]
            vb[i, 6 + q] = n0[i, q]
            vb[i, 9 + q] = n1[i, q]
            vb[i, 12 + q] = w0[i, q]
            vb[i, 15 + q] = w1[i, q]
    return body_motion(v0, v1, idx, ref)


@numba.njit(cache=True, _nrt=False, inline="always")
def fill_record(rec, i, vb, faces, t):
    """Copy triangle t's three vertices (positions, normals, velocities of both frames:
    18 floats each, as in ``vb``) into the point's record ``rec[i]`` (54 floats)."""
    for c in range(3):
        v = faces[t, c]
        for q in range(18):
            rec[i, 18 * c + q] = vb[v, q]


@numba.njit(cache=True, _nrt=False)
def signed_rec(px, py, pz, rec, i, alpha):
    """Signed distance of p to the triangle copied in ``rec[i]`` (:func:`fill_record`) at time
    alpha: (p − q)·n_s with q the closest point and n_s the interpolated vertex normal there;
    returns (s, nx, ny, nz, bary v, bary w)."""
    k = 1.0 - alpha
    ax = k * rec[i, 0] + alpha * rec[i, 3]
    ay = k * rec[i, 1] + alpha * rec[i, 4]
    az = k * rec[i, 2] + alpha * rec[i, 5]
    bx = k * rec[i, 18] + alpha * rec[i, 21]
    by = k * rec[i, 19] + alpha * rec[i, 22]
    bz = k * rec[i, 20] + alpha * rec[i, 23]
    cx = k * rec[i, 36] + alpha * rec[i, 39]
    cy = k * rec[i, 37] + alpha * rec[i, 40]
    cz = k * rec[i, 38] + alpha * rec[i, 41]
    v, w = closest_on_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz)
    u = 1.0 - v - w
    qx = ax + v * (bx - ax) + w * (cx - ax)
    qy = ay + v * (by - ay) + w * (cy - ay)
    qz = az + v * (bz - az) + w * (cz - az)
    nx = u * (k * rec[i, 6] + alpha * rec[i, 9]) + v * (k * rec[i, 24] + alpha * rec[i, 27]) + \
        w * (k * rec[i, 42] + alpha * rec[i, 45])
    ny = u * (k * rec[i, 7] + alpha * rec[i, 10]) + v * (k * rec[i, 25] + alpha * rec[i, 28]) + \
        w * (k * rec[i, 43] + alpha * rec[i, 46])
    nz = u * (k * rec[i, 8] + alpha * rec[i, 11]) + v * (k * rec[i, 26] + alpha * rec[i, 29]) + \
        w * (k * rec[i, 44] + alpha * rec[i, 47])
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
def rec_velocity(rec, i, alpha, bv, bw):
    """The body's velocity at barycentric (1 − bv − bw, bv, bw) of the triangle in ``rec[i]``
    at time alpha."""
    b = 1.0 - alpha
    bu = 1.0 - bv - bw
    vx = b * (bu * rec[i, 12] + bv * rec[i, 30] + bw * rec[i, 48]) + \
        alpha * (bu * rec[i, 15] + bv * rec[i, 33] + bw * rec[i, 51])
    vy = b * (bu * rec[i, 13] + bv * rec[i, 31] + bw * rec[i, 49]) + \
        alpha * (bu * rec[i, 16] + bv * rec[i, 34] + bw * rec[i, 52])
    vz = b * (bu * rec[i, 14] + bv * rec[i, 32] + bw * rec[i, 50]) + \
        alpha * (bu * rec[i, 17] + bv * rec[i, 35] + bw * rec[i, 53])
    return vx, vy, vz
