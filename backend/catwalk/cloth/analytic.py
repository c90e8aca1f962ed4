"""Analytic colliders for tests and the drape benchmark: a disc (the Cusick support), a plane, a
sphere. Each has ``resolve(positions, velocities, previous_positions) -> held mask`` (the
collider hook of :class:`catwalk.cloth.solvers.explicit.solver.Solver`): points that crossed into
the body are put back on its surface plus ``thickness``, the normal part of their velocity is
removed and the tangential part is reduced by Coulomb friction (``friction`` × the removed normal
speed); points in contact are reported as held (high-tension centres of the ordered pass). With
``stick=True`` a point in contact stops; a disc's ``clamp_gap`` also holds it from above (the
Cusick instrument clamps the specimen between two discs).
"""

from __future__ import annotations

import numba
import numpy as np

_KIND_DISC, _KIND_PLANE, _KIND_SPHERE = 0, 1, 2


@numba.njit(cache=True, error_model="numpy")
def _resolve(kind, x, v, xprev, centre, normal, radius, thickness, friction, stick, gap, held):
    n = x.shape[0]
    for i in range(n):
        held[i] = False
        if kind == _KIND_SPHERE:
            dx = x[i, 0] - centre[0]
            dy = x[i, 1] - centre[1]
            dz = x[i, 2] - centre[2]
            d = np.sqrt(dx * dx + dy * dy + dz * dz)
            r = radius + thickness
            if d >= r or d == 0.0:
                continue
            nx = dx / d
            ny = dy / d
            nz = dz / d
            depth = r - d
        else:
            nx = normal[0]
            ny = normal[1]
            nz = normal[2]
            h = ((x[i, 0] - centre[0]) * nx + (x[i, 1] - centre[1]) * ny
                 + (x[i, 2] - centre[2]) * nz)
            if h >= thickness + (gap if kind == _KIND_DISC else 0.0):
                continue
            if kind == _KIND_DISC:
                # inside the disc's radius, and arriving from above its top face
                px = x[i, 0] - centre[0] - h * nx
                py = x[i, 1] - centre[1] - h * ny
                pz = x[i, 2] - centre[2] - h * nz
                if px * px + py * py + pz * pz > radius * radius:
                    continue
                hp = ((xprev[i, 0] - centre[0]) * nx + (xprev[i, 1] - centre[1]) * ny
                      + (xprev[i, 2] - centre[2]) * nz)
                if hp < -thickness:
                    continue  # was already below the disc: not ours
            depth = thickness - h
        held[i] = True
        if stick:
            # clamped: back to where it was along the surface, pushed out along the normal
            tx = x[i, 0] - xprev[i, 0]
            ty = x[i, 1] - xprev[i, 1]
            tz = x[i, 2] - xprev[i, 2]
            dn = tx * nx + ty * ny + tz * nz
            x[i, 0] -= tx - dn * nx - depth * nx
            x[i, 1] -= ty - dn * ny - depth * ny
            x[i, 2] -= tz - dn * nz - depth * nz
            v[i, 0] = 0.0
            v[i, 1] = 0.0
            v[i, 2] = 0.0
            continue
        x[i, 0] += depth * nx
        x[i, 1] += depth * ny
        x[i, 2] += depth * nz
        vn = v[i, 0] * nx + v[i, 1] * ny + v[i, 2] * nz
        if vn < 0.0:
            v[i, 0] -= vn * nx
            v[i, 1] -= vn * ny
            v[i, 2] -= vn * nz
            tx = v[i, 0]
            ty = v[i, 1]
            tz = v[i, 2]
            vt = np.sqrt(tx * tx + ty * ty + tz * tz)
            dv = -friction * vn
            if vt <= dv:
                v[i, 0] = 0.0
                v[i, 1] = 0.0
                v[i, 2] = 0.0
            else:
                s = 1.0 - dv / vt
                v[i, 0] = tx * s
                v[i, 1] = ty * s
                v[i, 2] = tz * s


class _Analytic:
    """A :class:`~catwalk.cloth.solvers.Collider` of one analytic shape; it leaves no contact
    planes (the solver's step resolves it after every substep)."""

    kind = _KIND_PLANE
    planes = None

    def __init__(self, centre, normal=(0.0, 1.0, 0.0), radius=0.0, thickness=0.002,
                 friction=0.4, stick=False):
        self.centre = np.asarray(centre, dtype=np.float64).reshape(3)
        nrm = np.asarray(normal, dtype=np.float64).reshape(3)
        self.normal = nrm / np.linalg.norm(nrm)
        self.radius = float(radius)
        self.thickness = float(thickness)
        self.friction = float(friction)
        self.stick = bool(stick)
        self.clamp_gap = 0.0
        self._held = None

    def resolve(self, positions, velocities, previous_positions):
        n = len(positions)
        if self._held is None or len(self._held) != n:
            self._held = np.zeros(n, dtype=np.bool_)
        _resolve(self.kind, positions, velocities, previous_positions, self.centre, self.normal,
                 self.radius, self.thickness, self.friction, self.stick, self.clamp_gap,
                 self._held)
        return self._held


class DiscCollider(_Analytic):
    """A horizontal (by default) disc of ``radius`` centred at ``centre``, seen from above.

    ``clamp_gap`` > 0 adds the Cusick instrument's upper disc: points over the disc less than
    ``thickness + clamp_gap`` above it are pulled down onto it too (use with ``stick``)."""

    kind = _KIND_DISC

    def __init__(self, centre, radius, normal=(0.0, 1.0, 0.0), clamp_gap=0.0, **kw):
        super().__init__(centre, normal, radius, **kw)
        self.clamp_gap = float(clamp_gap)


class PlaneCollider(_Analytic):
    """The half-space below the plane through ``point`` with ``normal`` (default: the floor)."""

    kind = _KIND_PLANE

    def __init__(self, point=(0.0, 0.0, 0.0), normal=(0.0, 1.0, 0.0), **kw):
        super().__init__(point, normal, 0.0, **kw)


class SphereCollider(_Analytic):
    kind = _KIND_SPHERE

    def __init__(self, centre, radius, **kw):
        super().__init__(centre, (0.0, 1.0, 0.0), radius, **kw)
