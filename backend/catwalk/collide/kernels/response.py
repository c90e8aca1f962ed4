"""The response to a contact: the point pushed out to the surface plus the cloth thickness, its
normal velocity made the body's and Coulomb friction on the tangential part (:func:`respond`);
the contact plane it leaves for the cloth solver (:func:`record_plane`, :func:`near_plane`); and
a point between two facing surfaces put between them (:func:`pinch`)."""

from __future__ import annotations

import math

import numba

from catwalk.cloth.contact_planes import contact_velocity
from catwalk.cloth.state import PLANE_FRICTION, PLANE_NORMAL, PLANE_OFFSET, PLANE_VELOCITY


@numba.njit(cache=True, _nrt=False)
def respond(pos, vel, i, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction):
    """Move point i along n by (thickness − s); make its normal velocity the body's, reduce
    the tangential relative velocity by Coulomb friction (μ·|Δv_n|)."""
    d = thickness - s
    pos[i, 0] += d * nx
    pos[i, 1] += d * ny
    pos[i, 2] += d * nz
    vel[i, 0], vel[i, 1], vel[i, 2] = contact_velocity(vel[i, 0], vel[i, 1], vel[i, 2], nx, ny,
                                                       nz, bvx, bvy, bvz, friction)


@numba.njit(cache=True, _nrt=False, inline="always")
def record_plane(planes, i, px, py, pz, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction):
    """Point i (at p, signed distance s along the unit normal n) is held: its contact plane
    (``planes[i]``, :data:`catwalk.cloth.state.PLANE_COLUMNS` numbers) is the body's surface
    offset by ``thickness``, n·x ≥ n·p + thickness − s (``PLANE_NORMAL``: n, ``PLANE_OFFSET``:
    that offset), moving with the body's velocity there (``PLANE_VELOCITY``), with the friction
    coefficient (``PLANE_FRICTION``); the cloth solver keeps the point on its side until the
    next response (:func:`catwalk.cloth.contact_planes.apply_planes`)."""
    planes[i, PLANE_NORMAL] = nx
    planes[i, PLANE_NORMAL + 1] = ny
    planes[i, PLANE_NORMAL + 2] = nz
    planes[i, PLANE_OFFSET] = nx * px + ny * py + nz * pz + thickness - s
    planes[i, PLANE_VELOCITY] = bvx
    planes[i, PLANE_VELOCITY + 1] = bvy
    planes[i, PLANE_VELOCITY + 2] = bvz
    planes[i, PLANE_FRICTION] = friction


@numba.njit(cache=True, _nrt=False, inline="always")
def has_no_plane(planes, i):
    """Whether point i has no contact plane (a zero normal)."""
    return planes[i, PLANE_NORMAL] == 0.0 and planes[i, PLANE_NORMAL + 1] == 0.0 and \
        planes[i, PLANE_NORMAL + 2] == 0.0


@numba.njit(cache=True, _nrt=False, inline="always")
def near_plane(planes, i, px, py, pz, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction):
    """Point i is not held but within the plane band of the surface: the same plane as
    :func:`record_plane`, unless the point already has one (a held point's plane, or the
    nearer surface's), so that between two responses the solver stops it at the surface
    instead of the next response finding it inside."""
    if has_no_plane(planes, i):
        record_plane(planes, i, px, py, pz, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction)


@numba.njit(cache=True, _nrt=False)
def pinch(pos, vel, i, s1, n1x, n1y, n1z, w1x, w1y, w1z, s2, n2x, n2y, n2z, w2x, w2y, w2z,
          thickness, friction, planes):
    """Point i between two surfaces, at signed distances ``s1`` along n1 and ``s2`` along n2
    (moving at w1 and w2): if they face each other (n1·n2 ≤ −0.3) and do not overlap
    (s1 + s2 ≥ 0), it moves along u = (n1 − n2)/|n1 − n2| to keep the thickness from both
    where the gap allows it, else to the middle of the gap; its velocity into the first
    surface, relative to the two surfaces' mean velocity, goes (with friction); its contact
    plane is the one through it along u. Returns whether it was moved (not: surfaces that
    do not face each other, or overlap)."""
    c = n1x * n2x + n1y * n2y + n1z * n2z
    gap = s1 + s2
    if c > -0.3 or gap < 0.0:
        return False
    ux = n1x - n2x
    uy = n1y - n2y
    uz = n1z - n2z
    ul = math.sqrt(ux * ux + uy * uy + uz * uz)
    ux /= ul
    uy /= ul
    uz /= ul
    a = ul * 0.5  # n1·u = −n2·u
    target = min(thickness, 0.5 * gap)
    d = (target - s2) / a  # along −u: s2 grows by a·d, s1 shrinks by as much
    px = pos[i, 0] - d * ux
    py = pos[i, 1] - d * uy
    pz = pos[i, 2] - d * uz
    pos[i, 0] = px
    pos[i, 1] = py
    pos[i, 2] = pz
    mx = 0.5 * (w1x + w2x)
    my = 0.5 * (w1y + w2y)
    mz = 0.5 * (w1z + w2z)
    # motion into the first surface (relative to the two surfaces' mean) goes, with
    # friction; motion toward the second is left to the next response (taking it too made
    # the walks worse: docs/collide.md)
    vel[i, 0], vel[i, 1], vel[i, 2] = contact_velocity(vel[i, 0], vel[i, 1], vel[i, 2], ux, uy,
                                                       uz, mx, my, mz, friction)
    record_plane(planes, i, px, py, pz, ux, uy, uz, thickness, thickness, mx, my, mz, friction)
    return True
