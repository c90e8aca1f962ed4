"""Point and ray queries on one triangle, over scalar coordinates (numba, no arrays): the
closest point of a triangle to a point, and where a line meets it. The collider's hierarchy
(:mod:`catwalk.collide.bvh`), the sharp-vertex push and the body's surface
(:mod:`catwalk.geometry.surface`) all call these two."""

from __future__ import annotations

import numba


@numba.njit(cache=True, _nrt=False)
def closest_on_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz):
    """Barycentric (v, w) of the point of triangle abc closest to p (Ericson 2005, §5.1.5):
    the point is a + v·(b − a) + w·(c − a)."""
    abx = bx - ax
    aby = by - ay
    abz = bz - az
    acx = cx - ax
    acy = cy - ay
    acz = cz - az
    apx = px - ax
    apy = py - ay
    apz = pz - az
    d1 = abx * apx + aby * apy + abz * apz
    d2 = acx * apx + acy * apy + acz * apz
    if d1 <= 0.0 and d2 <= 0.0:
        return 0.0, 0.0
    bpx = px - bx
    bpy = py - by
    bpz = pz - bz
    d3 = abx * bpx + aby * bpy + abz * bpz
    d4 = acx * bpx + acy * bpy + acz * bpz
    if d3 >= 0.0 and d4 <= d3:
        return 1.0, 0.0
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        return d1 / (d1 - d3), 0.0
    cpx = px - cx
    cpy = py - cy
    cpz = pz - cz
    d5 = abx * cpx + aby * cpy + abz * cpz
    d6 = acx * cpx + acy * cpy + acz * cpz
    if d6 >= 0.0 and d5 <= d6:
        return 0.0, 1.0
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        return 0.0, d2 / (d2 - d6)
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return 1.0 - w, w
    den = va + vb + vc
    if not (den > 0.0):
        return 0.0, 0.0
    den = 1.0 / den
    return vb * den, vc * den


@numba.njit(cache=True, _nrt=False, inline="always")
def ray_triangle(ox, oy, oz, dx, dy, dz, ax, ay, az, bx, by, bz, cx, cy, cz, eps):
    """Where the line o + t·d meets triangle abc (Möller & Trumbore 1997): (hit, t, u, v), the
    point a + u·(b − a) + v·(c − a); no hit where it misses the triangle or runs parallel to
    it (|det| < ``eps``)."""
    e1x = bx - ax
    e1y = by - ay
    e1z = bz - az
    e2x = cx - ax
    e2y = cy - ay
    e2z = cz - az
    hx = dy * e2z - dz * e2y
    hy = dz * e2x - dx * e2z
    hz = dx * e2y - dy * e2x
    det = e1x * hx + e1y * hy + e1z * hz
    if abs(det) < eps:
        return False, 0.0, 0.0, 0.0
    inv = 1.0 / det
    sx = ox - ax
    sy = oy - ay
    sz = oz - az
    u = (sx * hx + sy * hy + sz * hz) * inv
    if u < 0.0 or u > 1.0:
        return False, 0.0, u, 0.0
    qx = sy * e1z - sz * e1y
    qy = sz * e1x - sx * e1z
    qz = sx * e1y - sy * e1x
    v = (dx * qx + dy * qy + dz * qz) * inv
    if v < 0.0 or u + v > 1.0:
        return False, 0.0, u, v
    return True, (e2x * qx + e2y * qy + e2z * qz) * inv, u, v
