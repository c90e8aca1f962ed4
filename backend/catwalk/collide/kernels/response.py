"""The response to a contact: the point pushed out to the surface plus the cloth thickness, its
normal velocity made the body's and Coulomb friction on the tangential part (:func:`respond`);
the contact plane it leaves for the cloth solver (:func:`record_plane`, :func:`near_plane`); and
a point between two facing surfaces put between them (:func:`pinch`).

A point's contact with a surface is a :data:`Contact`: its signed distance ``s`` along the
surface's unit normal n (``nx``, ``ny``, ``nz``), and the surface's velocity w there (``wx``,
``wy``, ``wz``). The kernels build and take it inside compiled code (a plain tuple of seven
numbers to numba, at no cost)."""

from __future__ import annotations

import math
from collections import namedtuple

import numba

from catwalk.cloth.contact_planes import contact_velocity
from catwalk.cloth.state import PLANE_FRICTION, PLANE_NORMAL, PLANE_OFFSET, PLANE_VELOCITY

Contact = namedtuple("Contact", "s nx ny nz wx wy wz")


@numba.njit(cache=True, _nrt=False)
def respond(pos, vel, i, hit, thickness, friction):
    """Move point i along n by (thickness − s) (its :data:`Contact` ``hit``); make its normal
    velocity the body's, reduce the tangential relative velocity by Coulomb friction
    (μ·|Δv_n|)."""
    d = thickness - hit.s
    pos[i, 0] += d * hit.nx
    pos[i, 1] += d * hit.ny
    pos[i, 2] += d * hit.nz
    vel[i, 0], vel[i, 1], vel[i, 2] = contact_velocity(vel[i, 0], vel[i, 1], vel[i, 2], hit.nx,
                                                       hit.ny, hit.nz, hit.wx, hit.wy, hit.wz,
                                                       friction)


@numba.njit(cache=True, _nrt=False, inline="always")
def record_plane(planes, i, px, py, pz, hit, thickness, friction):
    """Point i (at p, its :data:`Contact` ``hit``: signed distance s along the unit normal n)
    is held: its contact plane (``planes[i]``, :data:`catwalk.cloth.state.PLANE_COLUMNS`
    numbers) is the body's surface offset by ``thickness``, n·x ≥ n·p + thickness − s
    (``PLANE_NORMAL``: n, ``PLANE_OFFSET``: that offset), moving with the body's velocity
    there (``PLANE_VELOCITY``), with the friction coefficient (``PLANE_FRICTION``); the cloth
    solver keeps the point on its side until the next response
    (:func:`catwalk.cloth.contact_planes.apply_planes`)."""
    planes[i, PLANE_NORMAL] = hit.nx
    planes[i, PLANE_NORMAL + 1] = hit.ny
    planes[i, PLANE_NORMAL + 2] = hit.nz
    planes[i, PLANE_OFFSET] = hit.nx * px + hit.ny * py + hit.nz * pz + thickness - hit.s
    planes[i, PLANE_VELOCITY] = hit.wx
    planes[i, PLANE_VELOCITY + 1] = hit.wy
    planes[i, PLANE_VELOCITY + 2] = hit.wz
    planes[i, PLANE_FRICTION] = friction


@numba.njit(cache=True, _nrt=False, inline="always")
def has_no_plane(planes, i):
    """Whether point i has no contact plane (a zero normal)."""
    return planes[i, PLANE_NORMAL] == 0.0 and planes[i, PLANE_NORMAL + 1] == 0.0 and \
        planes[i, PLANE_NORMAL + 2] == 0.0


@numba.njit(cache=True, _nrt=False, inline="always")
def near_plane(planes, i, px, py, pz, hit, thickness, friction):
    """Point i is not held but within the plane band of the surface: the same plane as
    :func:`record_plane`, unless the point already has one (a held point's plane, or the
    nearer surface's), so that between two responses the solver stops it at the surface
    instead of the next response finding it inside."""
    if has_no_plane(planes, i):
        record_plane(planes, i, px, py, pz, hit, thickness, friction)


@numba.njit(cache=True, _nrt=False)
def pinch(pos, vel, planes, i, first, second, thickness, friction):
    """Point i between two surfaces, its :data:`Contact` with each (``first``: signed distance
    s1 along n1, the surface moving at w1; ``second``: s2, n2, w2): if they face each other
    (n1·n2 ≤ −0.3) and do not overlap (s1 + s2 ≥ 0), it moves along u = (n1 − n2)/|n1 − n2| to
    keep the thickness from both where the gap allows it, else to the middle of the gap; its
    velocity into the first surface, relative to the two surfaces' mean velocity, goes (with
    friction); its contact plane is the one through it along u. Returns whether it was moved
    (not: surfaces that do not face each other, or overlap)."""
    c = first.nx * second.nx + first.ny * second.ny + first.nz * second.nz
    gap = first.s + second.s
    if c > -0.3 or gap < 0.0:
        return False
    ux = first.nx - second.nx
    uy = first.ny - second.ny
    uz = first.nz - second.nz
    ul = math.sqrt(ux * ux + uy * uy + uz * uz)
    ux /= ul
    uy /= ul
    uz /= ul
    a = ul * 0.5  # n1·u = −n2·u
    target = min(thickness, 0.5 * gap)
    d = (target - second.s) / a  # along −u: s2 grows by a·d, s1 shrinks by as much
    px = pos[i, 0] - d * ux
    py = pos[i, 1] - d * uy
    pz = pos[i, 2] - d * uz
    pos[i, 0] = px
    pos[i, 1] = py
    pos[i, 2] = pz
    mx = 0.5 * (first.wx + second.wx)
    my = 0.5 * (first.wy + second.wy)
    mz = 0.5 * (first.wz + second.wz)
    # motion into the first surface (relative to the two surfaces' mean) goes, with
    # friction; motion toward the second is left to the next response (taking it too made
    # the walks worse: docs/collide.md)
    vel[i, 0], vel[i, 1], vel[i, 2] = contact_velocity(vel[i, 0], vel[i, 1], vel[i, 2], ux, uy,
                                                       uz, mx, my, mz, friction)
    record_plane(planes, i, px, py, pz, Contact(thickness, ux, uy, uz, mx, my, mz), thickness,
                 friction)
    return True
