"""Contact planes in the cloth's steps: the planes a collision response leaves in
:attr:`~catwalk.cloth.state.State.planes` (normal, offset, the body's velocity, friction), the
points kept on their side with Coulomb friction between two responses, and the speed cap after
a response."""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, inline="always")
def contact_velocity(vx, vy, vz, nx, ny, nz, wx, wy, wz, friction):
    """A point's velocity v after it meets a surface of unit normal n moving at w: if it moves
    into the surface (relative to it), that normal part goes and, by Coulomb friction, μ times
    as much of its sliding speed (stopping at zero). Shared by the collider's response
    (:func:`catwalk.collide.kernels.response.respond`) and the contact planes
    (:func:`apply_planes`)."""
    rx = vx - wx
    ry = vy - wy
    rz = vz - wz
    vn = rx * nx + ry * ny + rz * nz
    if vn >= 0.0:
        return vx, vy, vz
    rx -= vn * nx
    ry -= vn * ny
    rz -= vn * nz
    tl = np.sqrt(rx * rx + ry * ry + rz * rz)
    dv = -friction * vn
    f = 1.0 - dv / tl if tl > dv else 0.0
    return wx + f * rx, wy + f * ry, wz + f * rz


@numba.njit(cache=True, error_model="numpy")
def apply_planes(X, V, idx, planes, t):
    """Contact planes between two collision responses: point ``idx[k]`` stays on the side
    n·x ≥ c + (n·w)·t of its plane ``planes[k]`` = (n, c, w, μ) (w: the body's velocity
    there, ``t``: the time since the plane was set, μ: friction). A point behind it goes back
    onto it; its velocity relative to the body loses its part into the plane and, by Coulomb
    friction, μ times that much of its sliding speed (as the collider's response does).
    Cheap (no search), it stops cloth held by the body sinking in step after step between two
    responses of the collider, whose next push would come back as a jolt."""
    for k in range(idx.shape[0]):
        i = idx[k]
        nx = planes[k, 0]
        ny = planes[k, 1]
        nz = planes[k, 2]
        wx = planes[k, 4]
        wy = planes[k, 5]
        wz = planes[k, 6]
        d = nx * X[0, i] + ny * X[1, i] + nz * X[2, i] - planes[k, 3] - \
            (nx * wx + ny * wy + nz * wz) * t
        if d < 0.0:
            X[0, i] -= d * nx
            X[1, i] -= d * ny
            X[2, i] -= d * nz
            V[0, i], V[1, i], V[2, i] = contact_velocity(V[0, i], V[1, i], V[2, i], nx, ny,
                                                         nz, wx, wy, wz, planes[k, 7])


@numba.njit(cache=True, error_model="numpy")
def planes_set(planes, idx, rows):
    """The points with a contact plane (a unit normal in ``planes[i, :3]``; a zero normal:
    none): their indices into ``idx`` and their planes into ``rows`` (both at least (P,)
    long), in point order; returns how many (what :func:`apply_planes` takes)."""
    m = 0
    for i in range(planes.shape[0]):
        if planes[i, 0] * planes[i, 0] + planes[i, 1] * planes[i, 1] + \
                planes[i, 2] * planes[i, 2] > 0.5:
            idx[m] = i
            for c in range(planes.shape[1]):
                rows[m, c] = planes[i, c]
            m += 1
    return m


@numba.njit(cache=True, error_model="numpy")
def cap_speed(v, vmax):
    """No point faster than ``vmax``: a faster one's velocity (``v`` (P, 3)) is scaled down
    to that speed, in place; returns how many were."""
    n = 0
    v2max = vmax * vmax
    for i in range(v.shape[0]):
        s2 = v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2]
        if s2 > v2max:
            f = vmax / np.sqrt(s2)
            v[i, 0] *= f
            v[i, 1] *= f
            v[i, 2] *= f
            n += 1
    return n
