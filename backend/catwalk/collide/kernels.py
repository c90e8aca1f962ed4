"""The collider's per-substep numba kernels: the object-space pass (closest triangle in the
limbs' hierarchies, previous/current position against it) and the image-space pass (front/back
depth-map look-up), both with the same response (pushed out to the surface plus the cloth
thickness; normal velocity set to the body's, Coulomb friction on the tangential part).

Stats written by the passes (``stats`` int64 array, accumulated):
0 points that passed a part's box test, 1 narrow-phase searches (hierarchy walks or map
look-ups), 2 contacts, 3 closest-triangle results reused, 4 hierarchy nodes visited,
5 points skipped by the box tests, 6 points skipped by their clearance, 7 triangles tested
(closest point computed), 8 points the maps left to object space, 9 held points within the
thickness of a second part (:func:`_second_surface`), 10 of them pinched between two facing
surfaces. (Numba caches a kernel by its own file: a change to the inlined
helpers of bvh.py needs a change here too, or the cached kernel keeps the old code.)
"""

from __future__ import annotations

import math
from collections import namedtuple

import numba
import numpy as np

from catwalk.cloth.contact_planes import contact_velocity
from catwalk.collide.bvh import _box_d2, _swept_d2, closest_triangle_t, swept_lower
from catwalk.geometry.raster import row_span
from catwalk.geometry.triangles import closest_on_triangle

(ST_BOXED, ST_NARROW, ST_CONTACT, ST_REUSED, ST_NODES, ST_SKIPPED, ST_CLEAR, ST_TRIS,
 ST_EDGE, ST_SECOND, ST_PINCH, ST_FOLD, ST_RECHECK) = range(13)
N_STATS = 13
EDGE_WINDOW = 2  # pixels round a point's block that count as near the torso's silhouette
STAT_NAMES = ("boxed", "narrow", "contacts", "reused", "nodes", "skipped", "clearance_skips",
              "triangles_tested", "edge_fallbacks", "second_surface", "pinched", "folds",
              "rechecked")

# the object pass's inputs, grouped (numba takes named tuples of arrays and numbers; the pass
# unpacks them, see :func:`object_pass`)
ObjectTime = namedtuple("ObjectTime", "alpha alpha_prev frame ref clock body_speed")
ObjectBody = namedtuple("ObjectBody", "vb vp faces face_part nb links tris roots lf nbl vpl")
ObjectConfig = namedtuple("ObjectConfig", "thickness friction slack search_radius max_depth "
                          "skip_far use_cache reuse_tol use_clear second plane_band recheck")
ObjectPoints = namedtuple("ObjectPoints", "cache_tri cache_p cache_c clear clear_rel rkey rec "
                          "pspeed pstamp last pclk csw crel cstamp ct2 cp2 cc2 left")
Workspace = namedtuple("Workspace", "stack reach spd rec2 stats")


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
    (``planes[i]``, 8 numbers) is the body's surface offset by ``thickness``,
    n·x ≥ n·p + thickness − s (0–2: n, 3: that offset), moving with the body's velocity there
    (4–6), with the friction coefficient (7); the cloth solver keeps the point on its side
    until the next response (:func:`catwalk.cloth.contact_planes.apply_planes`)."""
    planes[i, 0] = nx
    planes[i, 1] = ny
    planes[i, 2] = nz
    planes[i, 3] = nx * px + ny * py + nz * pz + thickness - s
    planes[i, 4] = bvx
    planes[i, 5] = bvy
    planes[i, 6] = bvz
    planes[i, 7] = friction


@numba.njit(cache=True, _nrt=False, inline="always")
def near_plane(planes, i, px, py, pz, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction):
    """Point i is not held but within the plane band of the surface: the same plane as
    :func:`record_plane`, unless the point already has one (a held point's plane, or the
    nearer surface's), so that between two responses the solver stops it at the surface
    instead of the next response finding it inside."""
    if planes[i, 0] == 0.0 and planes[i, 1] == 0.0 and planes[i, 2] == 0.0:
        record_plane(planes, i, px, py, pz, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction)


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
def _fill_record(rec, i, vb, faces, t):
    """Copy triangle t's three vertices (positions, normals, velocities of both frames:
    18 floats each, as in ``vb``) into the point's record ``rec[i]`` (54 floats)."""
    for c in range(3):
        v = faces[t, c]
        for q in range(18):
            rec[i, 18 * c + q] = vb[v, q]


@numba.njit(cache=True, _nrt=False)
def _signed_rec(px, py, pz, rec, i, alpha):
    """Signed distance of p to the triangle copied in ``rec[i]`` (:func:`_fill_record`) at time
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
def _rec_velocity(rec, i, alpha, bv, bw):
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


@numba.njit(cache=True, _nrt=False, inline="always")
def _other_part_bounds(i, kt, ro, px, py, pz, alpha, rx, ry, rz, nbl, links, roots,
                       part_active, csw, crel, cstamp, frame, stack, stats):
    """``csw[i, k]``: how near each active part other than ``kt`` comes to point i over this
    frame (in the moving frame: its leaf boxes swept over the frame), looked for within
    ``ro`` (a bound of ``ro`` means "no nearer"); the point's motion since (``crel``) restarts
    from 0 and ``cstamp[i]`` marks the frame."""
    for k2 in range(roots.shape[0]):
        csw[i, k2] = np.inf
        if k2 != kt and part_active[k2]:
            bo, nv = swept_lower(px - alpha * rx, py - alpha * ry, pz - alpha * rz, nbl, links,
                                 roots[k2], ro * ro, stack)
            csw[i, k2] = math.sqrt(bo)
            stats[ST_NODES] += nv
    crel[i] = 0.0
    cstamp[i] = frame


@numba.njit(cache=True, _nrt=False)
def _second_surface(pos, vel, i, kt, s1, n1x, n1y, n1z, w1x, w1y, w1z, alpha, rx, ry, rz, vb,
                    vpl, lf, faces, nbl, links, tris, roots, part_active, reach, thickness,
                    friction, radius, cert_reach, stack, inv_t, spd, rec2, csw, crel, cstamp,
                    frame, planes, stats):
    """A point held by part ``kt`` (signed distance ``s1`` along n1 after its response, the
    body moving at w1 there) may be pinched: another part's surface faces it within the
    thickness (a hand over the thigh, the thighs, with the cloth between), and pushing it off
    the first part alone pushed it against the second.

    Each other part that may come within ``radius`` (its bound ``csw`` for this frame less
    the point's motion since; the bounds are taken within ``cert_reach`` beyond the first
    surface, as a reused closest triangle's check takes them, so that one set serves both) is
    searched for its nearest triangle within ``radius`` (the caller passes thickness +
    contact slack: with s1 no more than that and s1 + s2 ≥ 0, a second surface that matters
    is no farther). If the point is within the thickness of it (signed s2 along n2 <
    thickness), the surfaces face each other (n1·n2 ≤ −0.3) and do not overlap
    (s1 + s2 ≥ 0), the point moves along u = (n1 − n2)/|n1 − n2| to keep the thickness from
    both where the gap allows it, else to the middle of the gap; its velocity into the first
    surface, relative to the two surfaces' mean velocity, goes (with friction); its contact
    plane is the one through it along u (the solver keeps it off the first part; the next
    response sees the second again). Overlapping parts (a body touching itself: no position
    is outside both) and creases where two parts meet are left to the nearest surface:
    putting such points in the middle of the overlap made the armpit walks worse
    (docs/collide.md, "Pinched between two facing surfaces").

    Returns whether the point was moved."""
    px = pos[i, 0]
    py = pos[i, 1]
    pz = pos[i, 2]
    n_parts = roots.shape[0]
    if cstamp[i] != frame:
        # the bounds a reused closest triangle's check takes, looked for as far (one set
        # serves both for the rest of the frame)
        _other_part_bounds(i, kt, max(s1, 0.0) + cert_reach, px, py, pz, alpha, rx, ry, rz,
                           nbl, links, roots, part_active, csw, crel, cstamp, frame, stack,
                           stats)
    best = np.inf
    t2 = -1
    s0 = spd[0]
    s1_ = spd[1]
    for k2 in range(n_parts):
        if k2 == kt or not part_active[k2] or not reach[k2] or csw[i, k2] - crel[i] > radius:
            continue
        d2o, tk, nv, nt, _ = closest_triangle_t(px, py, pz, vpl, lf, alpha, rx, ry, rz, nbl,
                                                links, tris, roots[k2], radius * radius, -1,
                                                stack, inv_t, spd)
        stats[ST_NODES] += nv
        stats[ST_TRIS] += nt
        if tk >= 0 and d2o < best:
            best = d2o
            t2 = tk
    spd[0] = s0
    spd[1] = s1_
    if t2 < 0:
        return False
    _fill_record(rec2, 0, vb, faces, t2)
    s2, n2x, n2y, n2z, bv, bw = _signed_rec(px, py, pz, rec2, 0, alpha)
    if s2 >= thickness:
        return False
    w2x, w2y, w2z = _rec_velocity(rec2, 0, alpha, bv, bw)
    stats[ST_SECOND] += 1
    if not pinch(pos, vel, i, s1, n1x, n1y, n1z, w1x, w1y, w1z, s2, n2x, n2y, n2z, w2x, w2y,
                 w2z, thickness, friction, planes):
        return False
    stats[ST_PINCH] += 1
    return True


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


@numba.njit(cache=True, _nrt=False)
def body_motion(v0, v1, idx, ref):
    """The body's motion over a frame: ``ref`` (3,) gets the mean displacement over all
    vertices (the body's walk); returns the farthest any vertex ``idx`` moves relative to it
    (2-norm)."""
    n = v0.shape[0]
    rx = 0.0
    ry = 0.0
    rz = 0.0
    for i in range(n):
        rx += v1[i, 0] - v0[i, 0]
        ry += v1[i, 1] - v0[i, 1]
        rz += v1[i, 2] - v0[i, 2]
    if n > 0:
        rx /= n
        ry /= n
        rz /= n
    ref[0] = rx
    ref[1] = ry
    ref[2] = rz
    best = 0.0
    for k in range(idx.shape[0]):
        i = idx[k]
        dx = v1[i, 0] - v0[i, 0] - rx
        dy = v1[i, 1] - v0[i, 1] - ry
        dz = v1[i, 2] - v0[i, 2] - rz
        d = dx * dx + dy * dy + dz * dz
        if d > best:
            best = d
    return math.sqrt(best)


@numba.njit(cache=True, _nrt=False, nogil=True)
def object_pass(pos, vel, prev, held, planes, only, part_active, cloth_lo, cloth_hi, now, body,
                cfg, pts, ws, start, stop):
    """Object-space collision of the cloth points ``start`` … ``stop`` − 1 against the active
    parts' hierarchies.

    The inputs come grouped: ``now`` (:data:`ObjectTime`: the substep's ``alpha``, the last
    call's ``alpha_prev``, the ``frame`` number, the moving frame's travel ``ref`` over this
    frame, the collider's ``clock`` and the ``body_speed`` bound), ``body``
    (:data:`ObjectBody`: the packed body ``vb``/``vp``, ``faces``, ``face_part``, the
    hierarchies' node boxes ``nb``, ``links``, ``tris``, ``roots``, ``lf``, and the active
    parts' pose at ``alpha``, ``nbl``/``vpl``: :func:`catwalk.collide.bvh.blend_at`), ``cfg``
    (:data:`ObjectConfig`: thickness, friction, contact slack, search radius, max depth, which
    skips are on, ``reuse_tol``, ``second``, ``plane_band``, ``recheck``), ``pts``
    (:data:`ObjectPoints`: what is kept per point between calls, below) and ``ws``
    (:data:`Workspace`: a thread's ``stack``, ``reach``, ``spd``, ``rec2`` and counters
    ``stats``). ``held`` (P,) bool and
    ``planes`` (P,8) are written for the points seen; ``part_active`` (parts,) bool and
    ``cloth_lo``/``cloth_hi`` (the cloth's box) select the parts looked at.

    The hierarchies' node boxes ``nb`` (K,16) hold each node at the previous and the
    current frame; at time ``alpha`` a node's box is their blend, which the pass reads from
    the nodes' table ``nbl`` (blended once for the call, with the boxes swept over the frame
    and the nodes' speeds: :func:`catwalk.collide.bvh.blend_at`). Clearances are measured in
    the frame that moves with the body's mean displacement (``ref`` over this frame), so
    that the body's and the cloth's common motion does not use them up.

    What a point's skips rest on is how far it and the body moved since the point was last
    seen here, whatever moved it in between (the solver, a position correction, the image
    pass): ``last`` (P,3) its position then, ``pclk`` (P,5) the collider's clocks then —
    the moving frame's travel (0–2) and the body's (3: an upper bound of how far any limb
    vertex moved relative to it), and the time (4: frame + alpha; < 0: never seen). ``clock``
    (5,) the same clocks now. A point's motion in the moving frame is then
    |p − last − (travel now − travel then)|, the body's is the difference of the body
    clocks (or ``pspeed`` × the time since, within the frame of the point's last search).

    Per point: (1) clearance: while ``clear[i]`` (how much closer the point may come to the
    boxes swept by the body's leaves over this frame, in the moving frame; reset every
    frame) stays positive after subtracting the point's motion, or ``clear_rel[i]`` (how
    much closer it may come to the body as it was at the last search) stays positive after
    subtracting that motion and the body's, nothing else is done; (2) the cached closest
    triangle is reused while the point moved less than ``reuse_tol`` relative to it and no
    *other* part has a triangle nearer to the point than it — another part coming close (a
    hand swinging over a thigh) is always seen. Per other part, ``csw[i, k]`` bounds how
    near it comes over frame ``cstamp[i]`` (in the moving frame: its leaf boxes swept over
    the frame, looked for within the triangle's distance + ``search_radius``), less
    ``crel[i]``, the point's motion since; a part beyond the triangle's distance by that is
    out of the question. One part that is not: its nearest triangle to the point ``ct2[i]``
    is kept (with the point ``cp2`` and the triangle's centroid ``cc2`` then) and compared
    with the closest triangle, reused like it while the point moves less than
    ``reuse_tol`` relative to it (parts that touch, like the torso and a thigh in ``object``
    mode, meet along a seam: points there have the other part always near); else those
    parts' hierarchies are searched at this substep; (3) else the hierarchies are searched
    within ``search_radius`` + the point's motion; (4) signed distance to the closest
    triangle, collision and response. A point deeper than ``max_depth`` collides only if
    its last position, at its time, was outside.

    ``rkey`` (P,) int64 and ``rec`` (P,54) float32: each point's copy of its closest
    triangle's vertices for this ``frame`` (see :func:`_fill_record`), read in point order
    while the triangle is reused, instead of the scattered vertices. ``pspeed``/``pstamp``
    (P,): a speed bound for ``clear_rel`` found by the point's last search in
    frame ``pstamp`` (the nodes near it move slower than the fastest vertex): how fast the
    body's triangles can approach it during the rest of that frame; in another frame, the
    body clock. ``spd`` (2,): workspace.
    ``left`` (P,3): where the point was left then, after any push (the crossing test's last
    position). ``prev``/``alpha_prev``: the previous positions and time, used for a point
    never seen. ``lf`` (R,3) int32: the vertices of each reference in ``tris``.

    ``planes`` (P,8): for each held point its contact plane, written as it is found (the unit
    normal, the offset of the surface plus the thickness, the body's velocity, the friction
    coefficient; :func:`record_plane`); for each point looked at, not held but within
    ``plane_band`` of touching, the same plane unless it has one (:func:`near_plane`).

    ``only`` (P,) bool: when not empty, only the points marked are seen (the others are
    left as they are, their clocks too: their next motion counts everything since).

    ``second``: also look, for each held point, for a second part facing the first within the
    thickness, the cloth pinched between (:func:`_second_surface`); ``rec2`` (1,54) float32:
    workspace.

    ``recheck``: the points seen were pushed earlier in this response (the frame kept looks
    at them again): one found outside is left as it is; one inside a surface facing the plane
    it was pushed onto goes between the two (:func:`_fold`); another is pushed as usual.

    A point's work reads the body and writes only that point's entries, so disjoint ranges of
    points run at once on several threads (the GIL released), each with its own workspaces
    ``stack``, ``reach``, ``spd``, ``rec2`` and counters ``stats``."""
    alpha, alpha_prev, frame, ref, clock, body_speed = now
    vb, vp, faces, face_part, nb, links, tris, roots, lf, nbl, vpl = body
    (thickness, friction, slack, search_radius, max_depth, skip_far, use_cache, reuse_tol,
     use_clear, second, plane_band, recheck) = cfg
    # how far beyond the closest triangle the other parts' bounds are looked for
    cert_reach = search_radius
    (cache_tri, cache_p, cache_c, clear, clear_rel, rkey, rec, pspeed, pstamp, last, pclk, csw,
     crel, cstamp, ct2, cp2, cc2, left) = pts
    stack, reach, spd, rec2, stats = ws
    n_parts = roots.shape[0]
    fkey = frame << 32
    any_part = False
    for k in range(n_parts):
        reach[k] = False
        if not part_active[k]:
            continue
        r = roots[k]
        ok = True
        for q in range(3):
            if min(nb[r, q], nb[r, 6 + q]) > cloth_hi[q] + search_radius or \
                    max(nb[r, 3 + q], nb[r, 9 + q]) < cloth_lo[q] - search_radius:
                ok = False
        reach[k] = ok or not skip_far
        any_part = any_part or reach[k]
    if not any_part:
        # nothing is seen: the points' clocks stay where they were, so their next motion
        # counts everything since
        stats[ST_SKIPPED] += stop - start
        return
    touch = thickness + slack
    b = 1.0 - alpha
    rx = ref[0]
    ry = ref[1]
    rz = ref[2]
    rest = 1.0 - alpha
    inv_t = 1.0 / rest if rest > 1e-9 else 0.0
    tnow = clock[4]
    use_only = only.shape[0] > 0
    for i in range(start, stop):
        if use_only and not only[i]:
            continue
        if recheck:
            stats[ST_RECHECK] += 1   # seen a second time in this response
        px = pos[i, 0]
        py = pos[i, 1]
        pz = pos[i, 2]
        ti = pclk[i, 4]
        rel = np.inf   # never seen: no bound on its motion or the body's
        bstep = np.inf
        if ti >= 0.0:
            # since the point was last seen: its motion in the moving frame, the body's
            ex = px - last[i, 0] - (clock[0] - pclk[i, 0])
            ey = py - last[i, 1] - (clock[1] - pclk[i, 1])
            ez = pz - last[i, 2] - (clock[2] - pclk[i, 2])
            rel = math.sqrt(ex * ex + ey * ey + ez * ez)
            btrav = abs(clock[3] - pclk[i, 3])
            same = ti >= frame and tnow >= ti  # seen earlier in this frame
            bstep = pspeed[i] * (tnow - ti) if same and pstamp[i] == frame else btrav
        if ti >= frame + alpha_prev - 1e-9:
            # seen at the previous call or since: where it was left then
            qx = left[i, 0]
            qy = left[i, 1]
            qz = left[i, 2]
            qa = min(max(ti - frame, 0.0), alpha)
            dx = px - qx
            dy = py - qy
            dz = pz - qz
            move = math.sqrt(dx * dx + dy * dy + dz * dz)
        else:
            # never seen, or not since before the previous call (another pass had it: the
            # hybrid's maps and limbs take turns): where it was then is no crossing test and
            # no search radius, the previous positions are
            qx = prev[i, 0]
            qy = prev[i, 1]
            qz = prev[i, 2]
            qa = alpha_prev
            move = 0.0
        dx = px - prev[i, 0]
        dy = py - prev[i, 1]
        dz = pz - prev[i, 2]
        move = max(move, math.sqrt(dx * dx + dy * dy + dz * dz))
        # seen now (before any push: a push counts as motion the next time)
        last[i, 0] = px
        last[i, 1] = py
        last[i, 2] = pz
        left[i, 0] = px
        left[i, 1] = py
        left[i, 2] = pz
        for q in range(5):
            pclk[i, q] = clock[q]
        crel[i] += rel  # the point's motion since the other parts' bounds were taken
        if use_clear:
            c1 = clear[i] - rel
            c2 = clear_rel[i] - rel - bstep
            clear[i] = c1
            clear_rel[i] = c2
            if c1 > 0.0 or c2 > 0.0:
                stats[ST_CLEAR] += 1
                continue
        r = search_radius + move
        best_d2 = r * r if skip_far else np.inf
        best_t = -1
        seed = -1
        searched = False
        # reuse the closest triangle if the point barely moved relative to it and no other
        # part came nearer
        t = cache_tri[i] if use_cache else -1
        if t >= 0 and part_active[face_part[t]]:
            if rkey[i] != fkey | t:
                _fill_record(rec, i, vb, faces, t)
                rkey[i] = fkey | t
            gx = (b * (rec[i, 0] + rec[i, 18] + rec[i, 36])
                  + alpha * (rec[i, 3] + rec[i, 21] + rec[i, 39])) / 3.0
            gy = (b * (rec[i, 1] + rec[i, 19] + rec[i, 37])
                  + alpha * (rec[i, 4] + rec[i, 22] + rec[i, 40])) / 3.0
            gz = (b * (rec[i, 2] + rec[i, 20] + rec[i, 38])
                  + alpha * (rec[i, 5] + rec[i, 23] + rec[i, 41])) / 3.0
            ex = (px - cache_p[i, 0]) - (gx - cache_c[i, 0])
            ey = (py - cache_p[i, 1]) - (gy - cache_c[i, 1])
            ez = (pz - cache_p[i, 2]) - (gz - cache_c[i, 2])
            near = ex * ex + ey * ey + ez * ez < reuse_tol * reuse_tol
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
            qx_ = ax + v * (bx - ax) + w * (cx - ax) - px
            qy_ = ay + v * (by - ay) + w * (cy - ay) - py
            qz_ = az + v * (bz - az) + w * (cz - az) - pz
            d2 = qx_ * qx_ + qy_ * qy_ + qz_ * qz_
            if near and d2 > reuse_tol * reuse_tol and \
                    ((by - ay) * (cz - az) - (bz - az) * (cy - ay)) * qx_ + \
                    ((bz - az) * (cx - ax) - (bx - ax) * (cz - az)) * qy_ + \
                    ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)) * qz_ > 0.0:
                # inside, deeper than reuse_tol: the push is long, and a neighbour's normal
                # would send it elsewhere: search for the closest triangle itself
                near = False
            if near:
                # another part nearer than this triangle (say a hand come over the thigh
                # the point rests on) makes the answer another
                kt = face_part[t]
                dt_ = math.sqrt(d2)
                if cstamp[i] != frame:
                    _other_part_bounds(i, kt, dt_ + cert_reach, px, py, pz, alpha, rx, ry, rz,
                                       nbl, links, roots, part_active, csw, crel, cstamp, frame,
                                       stack, stats)
                kn = -1
                nn = 0
                for k2 in range(n_parts):
                    if k2 != kt and part_active[k2] and csw[i, k2] - crel[i] <= dt_:
                        kn = k2
                        nn += 1
                t2 = ct2[i]
                if nn == 1 and t2 >= 0 and face_part[t2] == kn:
                    # the other part's nearest triangle, kept while the point moved little
                    # relative to it
                    ia = faces[t2, 0]
                    ib = faces[t2, 1]
                    ic = faces[t2, 2]
                    ax = k * vp[ia, 0] + alpha * vp[ia, 3]
                    ay = k * vp[ia, 1] + alpha * vp[ia, 4]
                    az = k * vp[ia, 2] + alpha * vp[ia, 5]
                    bx = k * vp[ib, 0] + alpha * vp[ib, 3]
                    by = k * vp[ib, 1] + alpha * vp[ib, 4]
                    bz = k * vp[ib, 2] + alpha * vp[ib, 5]
                    cx = k * vp[ic, 0] + alpha * vp[ic, 3]
                    cy = k * vp[ic, 1] + alpha * vp[ic, 4]
                    cz = k * vp[ic, 2] + alpha * vp[ic, 5]
                    ex = (px - cp2[i, 0]) - ((ax + bx + cx) / 3.0 - cc2[i, 0])
                    ey = (py - cp2[i, 1]) - ((ay + by + cy) / 3.0 - cc2[i, 1])
                    ez = (pz - cp2[i, 2]) - ((az + bz + cz) / 3.0 - cc2[i, 2])
                    if ex * ex + ey * ey + ez * ez < reuse_tol * reuse_tol:
                        v, w = closest_on_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy,
                                                   cz)
                        qx_ = ax + v * (bx - ax) + w * (cx - ax) - px
                        qy_ = ay + v * (by - ay) + w * (cy - ay) - py
                        qz_ = az + v * (bz - az) + w * (cz - az) - pz
                        if qx_ * qx_ + qy_ * qy_ + qz_ * qz_ < d2:
                            near = False
                        nn = 0  # decided
                if nn > 0:
                    # look, at this substep: each such part's nearest triangle (kept when
                    # there is one such part)
                    ro = dt_ + cert_reach
                    for k2 in range(n_parts):
                        if k2 == kt or not part_active[k2] or csw[i, k2] - crel[i] > dt_:
                            continue
                        rt = roots[k2]
                        if nn > 1 and _box_d2(px, py, pz, nbl, rt) >= d2:
                            continue
                        d2o, tk, nv, nt, _ = closest_triangle_t(
                            px, py, pz, vpl, lf, alpha, rx, ry, rz, nbl, links, tris, rt,
                            d2 if nn > 1 else ro * ro, -1, stack, inv_t, spd)
                        stats[ST_NODES] += nv
                        stats[ST_TRIS] += nt
                        if tk >= 0 and d2o < d2:
                            near = False
                        if nn == 1:
                            ct2[i] = tk
                            if tk >= 0:
                                cp2[i, 0] = px
                                cp2[i, 1] = py
                                cp2[i, 2] = pz
                                for q in range(3):
                                    cc2[i, q] = (k * (vp[faces[tk, 0], q] + vp[faces[tk, 1], q]
                                                      + vp[faces[tk, 2], q])
                                                 + alpha * (vp[faces[tk, 0], 3 + q]
                                                            + vp[faces[tk, 1], 3 + q]
                                                            + vp[faces[tk, 2], 3 + q])) / 3.0
            if near:
                best_t = t
                stats[ST_REUSED] += 1
            elif d2 < best_d2:
                # the search below starts from this triangle's distance: it prunes more
                best_d2 = d2
                seed = t
        if best_t < 0:
            best_t = seed
            cstamp[i] = -1  # the other parts than the closest triangle's: not known
            ct2[i] = -1
            boxed = False
            spd[0] = 0.0
            spd[1] = 0.0
            lower = np.inf  # squared bound, over the frame, to every part's triangles
            now = np.inf  # squared bound, now, to the parts not searched
            for k in range(n_parts):
                if not part_active[k]:
                    continue
                rt = roots[k]
                dr = _box_d2(px, py, pz, nbl, rt)
                if not reach[k] or (skip_far and dr >= best_d2):
                    lower = min(lower, _swept_d2(px - alpha * rx, py - alpha * ry,
                                                 pz - alpha * rz, nbl, rt))
                    spd[0] = max(spd[0], nbl[rt, 15] - math.sqrt(dr) * inv_t)
                    now = min(now, dr)
                    continue
                boxed = True
                best_d2, best_t, nv, nt, ld2 = closest_triangle_t(
                    px, py, pz, vpl, lf, alpha, rx, ry, rz, nbl, links, tris, rt, best_d2,
                    best_t, stack, inv_t, spd)
                lower = min(lower, ld2)
                stats[ST_NODES] += nv
                stats[ST_TRIS] += nt
            # a part skipped as out of reach may be nearer than the search radius
            best_d2 = min(best_d2, now)
            searched = True
            if boxed:
                stats[ST_BOXED] += 1
                stats[ST_NARROW] += 1
            else:
                stats[ST_SKIPPED] += 1
            if use_clear and skip_far:
                # no leaf box swept over this frame (moving frame) is nearer than √lower,
                # and no triangle nearer than √best_d2 now
                clear[i] = math.sqrt(lower) - touch
                # and during the rest of this frame none approaches faster than this
                dd = math.sqrt(best_d2)
                pspeed[i] = max(spd[0] + dd * inv_t, spd[1], 0.0) if rest > 1e-9 else 0.0
                pstamp[i] = frame
                if best_t < 0:
                    clear_rel[i] = dd - touch
            if best_t < 0:
                if use_cache:
                    cache_tri[i] = -1
                continue
            if rkey[i] != fkey | best_t:
                _fill_record(rec, i, vb, faces, best_t)
                rkey[i] = fkey | best_t
            if use_cache:
                cache_tri[i] = best_t
                for q in range(3):
                    cache_c[i, q] = (b * (rec[i, q] + rec[i, 18 + q] + rec[i, 36 + q]) + alpha * (
                        rec[i, 3 + q] + rec[i, 21 + q] + rec[i, 39 + q])) / 3.0
                cache_p[i, 0] = px
                cache_p[i, 1] = py
                cache_p[i, 2] = pz
        s, nx, ny, nz, bv, bw = _signed_rec(px, py, pz, rec, i, alpha)
        if recheck and s >= 0.0:
            # looked at again after a push: outside, it keeps what that push gave it
            continue
        if s >= touch:
            if s < touch + plane_band:
                bvx, bvy, bvz = _rec_velocity(rec, i, alpha, bv, bw)
                near_plane(planes, i, px, py, pz, nx, ny, nz, s, thickness, bvx, bvy, bvz,
                           friction)
            if use_clear and searched and best_d2 < np.inf:
                # outside: no triangle nearer than √best_d2 now (a point inside has none)
                clear_rel[i] = math.sqrt(best_d2) - touch
            continue
        if s <= -max_depth:
            # deep: a collision only if the point crossed the surface since it was last
            # seen (its position then, against the same triangle at its time)
            sp, _, _, _, _, _ = _signed_rec(qx, qy, qz, rec, i, qa)
            if sp < 0.0:
                continue
        held[i] = True
        stats[ST_CONTACT] += 1
        if use_clear:
            clear[i] = 0.0
        bvx, bvy, bvz = _rec_velocity(rec, i, alpha, bv, bw)
        if recheck and _fold(pos, vel, i, s, nx, ny, nz, bvx, bvy, bvz, thickness, friction,
                             planes):
            stats[ST_FOLD] += 1
            _left_here(left, pos, i)
            continue
        record_plane(planes, i, px, py, pz, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction)
        if s < thickness:
            respond(pos, vel, i, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction)
            s = thickness
            # where it was left, for the crossing test (the bounds count the motion from
            # where they hold, before the push: distances change no faster than the point
            # moves)
            _left_here(left, pos, i)
        if second:
            if _second_surface(pos, vel, i, face_part[best_t], s, nx, ny, nz, bvx, bvy, bvz,
                               alpha, rx, ry, rz, vb, vpl, lf, faces, nbl, links, tris, roots,
                               part_active, reach, thickness, friction, touch, cert_reach,
                               stack, inv_t, spd, rec2, csw, crel, cstamp, frame, planes,
                               stats):
                _left_here(left, pos, i)


@numba.njit(cache=True, _nrt=False)
def _fold(pos, vel, i, s2, n2x, n2y, n2z, w2x, w2y, w2z, thickness, friction, planes):
    """Point i, pushed off a surface earlier in this response (its contact plane
    ``planes[i]``), is behind another (signed ``s2`` < 0 along n2, moving at w2): where the
    body folds onto itself (the skinned arm under the armpit, two fingers) the two may face
    each other, and a push off the second alone would put the point behind the first. Such a
    point goes between the two (:func:`pinch`). A point outside the second surface is left
    to the plain push (it keeps it outside the first: s1 = thickness before, less at most
    thickness − s2), and a point already put between two parts (whose plane says thickness
    for a narrower gap) is left to the second-surface check. Returns whether it was moved."""
    n1x = planes[i, 0]
    n1y = planes[i, 1]
    n1z = planes[i, 2]
    if s2 >= 0.0 or (n1x == 0.0 and n1y == 0.0 and n1z == 0.0):
        return False
    s1 = n1x * pos[i, 0] + n1y * pos[i, 1] + n1z * pos[i, 2] - planes[i, 3] + thickness
    return pinch(pos, vel, i, s1, n1x, n1y, n1z, planes[i, 4], planes[i, 5], planes[i, 6], s2,
                 n2x, n2y, n2z, w2x, w2y, w2z, thickness, friction, planes)


@numba.njit(cache=True, _nrt=False, inline="always")
def _left_here(left, pos, i):
    """Where point i was left (after a push), for the crossing test."""
    left[i, 0] = pos[i, 0]
    left[i, 1] = pos[i, 1]
    left[i, 2] = pos[i, 2]


@numba.njit(cache=True, _nrt=False, inline="always")
def _window_covered(D, i0, j0, s0, s1, h, w):
    """1 if any pixel within ``EDGE_WINDOW`` of the 2×2 block at (i0, j0) is covered in
    either slot, on either side (under the crotch only surfaces facing away from the front
    camera are drawn: the front map is empty there, the back map is not), else 0."""
    for ii in range(max(i0 - EDGE_WINDOW, 0), min(i0 + 2 + EDGE_WINDOW, h)):
        for jj in range(max(j0 - EDGE_WINDOW, 0), min(j0 + 2 + EDGE_WINDOW, w)):
            if D[ii, jj, s0, 0] > -np.inf or D[ii, jj, s1, 0] > -np.inf or \
                    D[ii, jj, s0, 1] < np.inf or D[ii, jj, s1, 1] < np.inf:
                return 1
    return 0


@numba.njit(cache=True, _nrt=False, nogil=True)
def image_pass(pos, vel, alpha, m, D, A, s0, s1, version, box_lo, box_hi, thickness, friction,
               slack, plane_band, min_nz, skip_far, held, stats, pkey, pdep, patt, planes, edge,
               edge_nz, pwin):
    """Image-space collision of the cloth points against front/back depth maps at time
    ``alpha`` between the previous (slot ``s0``) and the current (slot ``s1``) frame's maps,
    on one thread (a point's work writes only its own entries, but a look-up is cheap:
    handing slices of it to other threads cost more than it saved, docs/collide.md "Both
    cores").

    ``m`` (3×4) world → map (x col, y row, z = depth towards the front camera). ``D``
    (H,W,2 slots,2 sides) float32 depth (side 0 front = nearest, 1 back = farthest;
    −inf/+inf where empty), bilinear over the covered pixels; ``A`` (H,W,2 sides,2 slots,6)
    float32 per-pixel normal (3) and body velocity (3), taken from the nearest covered pixel.

    The maps do not change during a frame and a point's pixel changes slowly, so each point
    keeps a copy of what it read (``version`` numbers the maps' contents): ``pkey`` (P,3)
    int64 (its 2×2 pixel block; the pixels and side its attributes came from), ``pdep``
    (P,16) float32 (the block's depths: pixel q, slot u, side k at 4u + 8k + q... see below),
    ``patt`` (P,12) float32 (normal and velocity, both slots). Read in order, one point after
    the other, they stay cheap where the maps' scattered pixels would miss the cache.
    (The object pass's clearances count these pushes as the points' motion: it measures
    each point's motion from where it last saw it.)

    ``edge`` (P,) bool: when not empty, points marked on entry are skipped (the caller
    sends them to object space), and the points the maps cannot answer well are marked
    there and left alone (not held, not moved) for the caller to collide in object space:
    those whose 2×2 pixel block is not fully covered in both slots but has a covered pixel
    within ``EDGE_WINDOW`` pixels (the silhouette, where the torso's surface turns away from
    both cameras: the crotch's underside, seen edge-on, is drawn in no pixel at all; and the
    open rim where a limb joins), and those whose surface turns too far from the camera
    (n·view < ``edge_nz``), where a depth difference is a poor measure of the distance.
    ``pwin`` (P,) int8: each point's "covered pixel in the window" for its cached block
    (−1: not needed yet; looked at only for blocks not fully covered).
    Empty ``edge``: the paper's image space, where such points are answered by the maps
    (the normal leaned towards the view axis at the silhouette).

    ``planes`` (P,8): each held point's contact plane (:func:`record_plane`), and the same for
    each point not held but within ``plane_band`` of touching, unless it has one
    (:func:`near_plane`)."""
    h = D.shape[0]
    w = D.shape[1]
    cx = m[2, 0]
    cy = m[2, 1]
    cz = m[2, 2]
    reach = (thickness + slack) / min_nz
    vkey = version << 40
    akey = version << 30
    st = math.sqrt(1.0 - min_nz * min_nz)
    n_skip = 0
    n_box = 0
    n_narrow = 0
    n_contact = 0
    n_edge = 0
    use_edge = edge.shape[0] > 0
    for i in range(pos.shape[0]):
        if use_edge and edge[i]:
            n_edge += 1  # marked by the caller: left to object space
            continue
        px = pos[i, 0]
        py = pos[i, 1]
        pz = pos[i, 2]
        if skip_far and (px < box_lo[0] or px > box_hi[0] or py < box_lo[1] or
                         py > box_hi[1] or pz < box_lo[2] or pz > box_hi[2]):
            n_skip += 1
            continue
        n_box += 1
        x = m[0, 0] * px + m[0, 1] * py + m[0, 2] * pz + m[0, 3]
        y = m[1, 0] * px + m[1, 1] * py + m[1, 2] * pz + m[1, 3]
        z = cx * px + cy * py + cz * pz + m[2, 3]
        if not (x >= 0.0 and x < w and y >= 0.0 and y < h):
            continue
        n_narrow += 1
        fx = x - 0.5
        fy = y - 0.5
        j0 = int(math.floor(fx))
        i0 = int(math.floor(fy))
        tx = fx - j0
        ty = fy - i0
        key = vkey | ((i0 + 1) << 20) | (j0 + 1)
        if pkey[i, 0] != key:
            # the 2×2 block's depths, both slots and sides (−inf/+inf off the map)
            for q in range(4):
                ii = i0 + (q >> 1)
                jj = j0 + (q & 1)
                inside = ii >= 0 and ii < h and jj >= 0 and jj < w
                for u in range(2):
                    sl = s0 if u == 0 else s1
                    if inside:
                        pdep[i, 4 * u + q] = D[ii, jj, sl, 0]
                        pdep[i, 8 + 4 * u + q] = D[ii, jj, sl, 1]
                    else:
                        pdep[i, 4 * u + q] = -np.inf
                        pdep[i, 8 + 4 * u + q] = np.inf
            pkey[i, 0] = key
            pwin[i] = -1  # not looked at yet for this block
        w00 = (1.0 - tx) * (1.0 - ty)
        w01 = tx * (1.0 - ty)
        w10 = (1.0 - tx) * ty
        w11 = tx * ty
        # per slot: bilinear over the covered pixels (front and back both drawn: at the open
        # rim where a limb joins, a pixel can hold a surface facing one camera and none
        # facing the other, and an empty side's ±inf would put every point beyond reach),
        # and the covered pixel of most weight
        ws0 = 0.0
        zf0 = 0.0
        zb0 = 0.0
        q0 = -1
        wq0 = -1.0
        nc0 = 0
        nc1 = 0
        ws1 = 0.0
        zf1 = 0.0
        zb1 = 0.0
        q1 = -1
        wq1 = -1.0
        for q in range(4):
            wq = w00 if q == 0 else (w01 if q == 1 else (w10 if q == 2 else w11))
            f = pdep[i, q]
            if f > -np.inf and pdep[i, 8 + q] < np.inf:
                nc0 += 1
                ws0 += wq
                zf0 += wq * f
                zb0 += wq * pdep[i, 8 + q]
                if wq > wq0:
                    wq0 = wq
                    q0 = q
            f = pdep[i, 4 + q]
            if f > -np.inf and pdep[i, 12 + q] < np.inf:
                nc1 += 1
                ws1 += wq
                zf1 += wq * f
                zb1 += wq * pdep[i, 12 + q]
                if wq > wq1:
                    wq1 = wq
                    q1 = q
        if use_edge and (nc0 < 4 or nc1 < 4):
            # at or near the silhouette (or the open rim where a limb joins): the surface
            # there turns away from both cameras (the crotch's underside is seen edge-on and
            # drawn in no pixel at all): object space answers
            if pwin[i] < 0:
                pwin[i] = _window_covered(D, i0, j0, s0, s1, h, w)
            if pwin[i]:
                edge[i] = True
                n_edge += 1
            continue
        if ws0 > 0.0 and ws1 > 0.0:
            ka = 1.0 - alpha
            kb = alpha
        elif ws1 > 0.0:
            ka = 0.0
            kb = 1.0
        elif ws0 > 0.0:
            ka = 1.0
            kb = 0.0
        else:
            continue
        zf = 0.0
        zb = 0.0
        if ka > 0.0:
            zf += ka * zf0 / ws0
            zb += ka * zb0 / ws0
        if kb > 0.0:
            zf += kb * zf1 / ws1
            zb += kb * zb1 / ws1
        # beyond reach along the view axis (at a slope n_z ≥ min_nz the gap is ≤ d / min_nz)
        if z >= zf + reach or z <= zb - reach:
            continue
        front = (zf - z) <= (z - zb)
        side = 0 if front else 1
        # normal and velocity from the covered pixel of the block nearest the point
        pix0 = (i0 + (q0 >> 1)) * w + j0 + (q0 & 1) if (ka > 0.0 and q0 >= 0) else -1
        pix1 = (i0 + (q1 >> 1)) * w + j0 + (q1 & 1) if (kb > 0.0 and q1 >= 0) else -1
        k0 = akey | (side << 28) | (pix0 + 1)
        k1 = akey | (side << 28) | (pix1 + 1)
        if pkey[i, 1] != k0:
            if pix0 >= 0:
                ii = pix0 // w
                jj = pix0 - ii * w
                for c in range(6):
                    patt[i, c] = A[ii, jj, side, s0, c]
            pkey[i, 1] = k0
        if pkey[i, 2] != k1:
            if pix1 >= 0:
                ii = pix1 // w
                jj = pix1 - ii * w
                for c in range(6):
                    patt[i, 6 + c] = A[ii, jj, side, s1, c]
            pkey[i, 2] = k1
        nx = 0.0
        ny = 0.0
        nz = 0.0
        bvx = 0.0
        bvy = 0.0
        bvz = 0.0
        if ka > 0.0:
            nx += ka * patt[i, 0]
            ny += ka * patt[i, 1]
            nz += ka * patt[i, 2]
            bvx += ka * patt[i, 3]
            bvy += ka * patt[i, 4]
            bvz += ka * patt[i, 5]
        if kb > 0.0:
            nx += kb * patt[i, 6]
            ny += kb * patt[i, 7]
            nz += kb * patt[i, 8]
            bvx += kb * patt[i, 9]
            bvy += kb * patt[i, 10]
            bvz += kb * patt[i, 11]
        sgn = 1.0 if front else -1.0
        nl = math.sqrt(nx * nx + ny * ny + nz * nz)
        if nl > 1e-12:
            nx /= nl
            ny /= nl
            nz /= nl
        ndc = sgn * (nx * cx + ny * cy + nz * cz)  # > 0 for a surface facing its camera
        if ndc < edge_nz and use_edge:
            edge[i] = True
            n_edge += 1
            continue
        if ndc < min_nz:
            # at the silhouette (or a bad normal) lean the normal towards the camera axis
            tx_ = nx - sgn * ndc * cx
            ty_ = ny - sgn * ndc * cy
            tz_ = nz - sgn * ndc * cz
            tl = math.sqrt(tx_ * tx_ + ty_ * ty_ + tz_ * tz_)
            if tl > 1e-12:
                nx = tx_ / tl * st + sgn * min_nz * cx
                ny = ty_ / tl * st + sgn * min_nz * cy
                nz = tz_ / tl * st + sgn * min_nz * cz
            else:
                nx = sgn * cx
                ny = sgn * cy
                nz = sgn * cz
            ndc = min_nz
        # signed distance to the surface's tangent plane at the pixel (p − S)·n
        s = (z - zf) * ndc if front else (zb - z) * ndc
        if s >= thickness + slack:
            if s < thickness + slack + plane_band:
                near_plane(planes, i, pos[i, 0], pos[i, 1], pos[i, 2], nx, ny, nz, s,
                           thickness, bvx, bvy, bvz, friction)
            continue
        held[i] = True
        n_contact += 1
        record_plane(planes, i, pos[i, 0], pos[i, 1], pos[i, 2], nx, ny, nz, s, thickness, bvx,
                     bvy, bvz, friction)
        if s < thickness:
            respond(pos, vel, i, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction)
    stats[ST_SKIPPED] += n_skip
    stats[ST_BOXED] += n_box
    stats[ST_NARROW] += n_narrow
    stats[ST_CONTACT] += n_contact
    stats[ST_EDGE] += n_edge


@numba.njit(cache=True, _nrt=False)
def gather(m, v, n, w, idx, sv, attrs):
    """Screen positions of vertices ``idx`` under ``m`` and their (normal, velocity)."""
    for k in range(idx.shape[0]):
        i = idx[k]
        x = v[i, 0]
        y = v[i, 1]
        z = v[i, 2]
        for r in range(3):
            sv[k, r] = m[r, 0] * x + m[r, 1] * y + m[r, 2] * z + m[r, 3]
            attrs[k, r] = n[i, r]
            attrs[k, 3 + r] = w[i, r]


@numba.njit(cache=True, _nrt=False)
def bounds(p, lo, hi):
    """Axis-aligned box of points ``p`` into ``lo``/``hi`` (taking the union with what is
    there already)."""
    for i in range(p.shape[0]):
        for q in range(3):
            x = p[i, q]
            if x < lo[q]:
                lo[q] = x
            if x > hi[q]:
                hi[q] = x


@numba.njit(cache=True, _nrt=False)
def bounds_of(p, idx, lo, hi):
    """Like :func:`bounds` over the rows ``idx`` of ``p``."""
    for k in range(idx.shape[0]):
        i = idx[k]
        for q in range(3):
            x = p[i, q]
            if x < lo[q]:
                lo[q] = x
            if x > hi[q]:
                hi[q] = x


@numba.njit(cache=True, _nrt=False)
def max_displacement(a, b, idx):
    """max over vertices idx of |a − b|∞ (did this part move?)."""
    best = 0.0
    for k in range(idx.shape[0]):
        i = idx[k]
        for q in range(3):
            d = abs(a[i, q] - b[i, q])
            if d > best:
                best = d
    return best


@numba.njit(cache=True, _nrt=False)
def render_maps(m, v, n, w, idx, faces, sv, attrs, slot, D, A, tri, r0, r1, c0, c1):
    """Draw one slot of the front and back depth maps (see :class:`~catwalk.collide.
    image_pass.DepthMaps`) of the triangles ``faces`` (over the mapped vertices ``idx`` of ``v``,
    with normals ``n`` and velocities ``w``), only within rows r0…r1 and columns c0…c1 (the
    region the cloth can reach): the region is cleared and every triangle facing the camera
    drawn into the front map (nearest kept), every triangle facing away into the back map
    (farthest kept), in one pass. Inside the region the result is exactly that of
    :func:`catwalk.geometry.raster.raster_kernel` with back- and front-face culling over the
    whole map (same coverage rule, same order); outside it the maps are left as they were.
    ``sv``/``attrs``: workspaces for the screen positions and attributes of ``idx``."""
    for k in range(idx.shape[0]):
        i = idx[k]
        x = v[i, 0]
        y = v[i, 1]
        z = v[i, 2]
        for r in range(3):
            sv[k, r] = m[r, 0] * x + m[r, 1] * y + m[r, 2] * z + m[r, 3]
            attrs[k, r] = n[i, r]
            attrs[k, 3 + r] = w[i, r]
    for i in range(r0, r1 + 1):
        for j in range(c0, c1 + 1):
            D[i, j, slot, 0] = -np.inf
            D[i, j, slot, 1] = np.inf
            tri[slot, 0, i, j] = -1
            tri[slot, 1, i, j] = -1
    eps = 1e-9
    for t in range(faces.shape[0]):
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
            continue
        area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
        if not (abs(area) > 1e-14):  # degenerate or NaN
            continue
        # rows grow downwards: a triangle facing the camera has area < 0 → front map
        side = 0 if area < 0.0 else 1
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
            ja = max(ja, j0)
            jb = min(jb, j1)
            for j in range(ja, jb + 1):
                dj = j - jb0
                w0 = w0s + d0 * dj
                w1 = w1s + d1 * dj
                w2 = 1.0 - w0 - w1
                if w0 < -eps or w1 < -eps or w2 < -eps:
                    continue
                z = w0 * z0 + w1 * z1 + w2 * z2
                if tri[slot, side, i, j] >= 0:
                    if side == 1:
                        if z >= D[i, j, slot, 1]:
                            continue
                    elif z <= D[i, j, slot, 0]:
                        continue
                D[i, j, slot, side] = z
                tri[slot, side, i, j] = t
                for q in range(6):
                    A[i, j, side, slot, q] = w0 * attrs[a, q] + w1 * attrs[b, q] + \
                        w2 * attrs[c, q]


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
