"""The object pass's kernel (:func:`object_pass`): each cloth point's closest triangle in the
active parts' hierarchies, the point's previous position against it, the response; with its
inputs' groups (:data:`ObjectTime`, :data:`ObjectBody`, :data:`ObjectConfig`,
:data:`ObjectPoints`, :data:`Workspace`)."""

from __future__ import annotations

import math
from collections import namedtuple

import numba
import numpy as np

from catwalk.collide.bvh import (
    NB_HI0,
    NB_HI1,
    NB_LO0,
    NB_LO1,
    NL_SPEED,
    SPD_LEAVES,
    SPD_PRUNED,
    VP_X0,
    VP_X1,
    box_d2,
    closest_triangle_t,
    swept_d2,
    vp_at,
)
from catwalk.collide.kernels.record import (
    fill_record,
    rec_centroid,
    rec_triangle_at,
    rec_velocity,
    signed_rec,
)
from catwalk.collide.kernels.response import near_plane, record_plane, respond
from catwalk.collide.kernels.second_surface import fold, other_part_bounds, second_surface
from catwalk.collide.kernels.stats import (
    ST_BOXED,
    ST_CLEAR,
    ST_CONTACT,
    ST_FOLD,
    ST_NARROW,
    ST_NODES,
    ST_RECHECK,
    ST_REUSED,
    ST_SKIPPED,
    ST_TRIS,
)
from catwalk.geometry.triangles import closest_on_triangle

#: the collider's clocks (``clock`` (N_CLOCKS,), and each point's copy when it was last seen,
#: ``pclk`` (P, N_CLOCKS)): the moving frame's travel (CLK_TRAVEL, xyz), the body's travel
#: relative to it (CLK_BODY: an upper bound of how far any limb vertex moved), the time
#: (CLK_TIME: frame + alpha; < 0: never seen)
CLK_TRAVEL, CLK_BODY, CLK_TIME = 0, 3, 4
N_CLOCKS = 5

# the object pass's inputs, grouped (numba takes named tuples of arrays and numbers; the pass
# unpacks them, see :func:`object_pass`)
ObjectTime = namedtuple("ObjectTime", "alpha alpha_prev frame ref clock body_speed")
ObjectBody = namedtuple("ObjectBody", "vb vp faces face_part nb links tris roots lf nbl vpl")
ObjectConfig = namedtuple("ObjectConfig", "thickness friction slack search_radius max_depth "
                          "skip_far use_cache reuse_tol use_clear second plane_band recheck")
ObjectPoints = namedtuple("ObjectPoints", "cache_tri cache_p cache_c clear clear_rel rkey rec "
                          "pspeed pstamp last pclk csw crel cstamp ct2 cp2 cc2 left")
Workspace = namedtuple("Workspace", "stack reach spd rec2 stats")


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
    pass): ``last`` (P,3) its position then, ``pclk`` (P, :data:`N_CLOCKS`) the collider's
    clocks then — the moving frame's travel (:data:`CLK_TRAVEL`) and the body's
    (:data:`CLK_BODY`: an upper bound of how far any limb vertex moved relative to it), and the
    time (:data:`CLK_TIME`: frame + alpha; < 0: never seen). ``clock`` (:data:`N_CLOCKS`,) the
    same clocks now. A point's motion in the moving frame is then
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

    ``rkey`` (P,) int64 and ``rec`` (P, :data:`~catwalk.collide.kernels.record.REC_COLUMNS`)
    float32: each point's copy of its closest triangle's vertices for this ``frame`` (see
    :func:`~catwalk.collide.kernels.record.fill_record`), read in point order
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
    thickness, the cloth pinched between (:func:`second_surface`); ``rec2`` (1, REC_COLUMNS)
    float32: workspace.

    ``recheck``: the points seen were pushed earlier in this response (the frame kept looks
    at them again): one found outside is left as it is; one inside a surface facing the plane
    it was pushed onto goes between the two (:func:`fold`); another is pushed as usual.

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
            if min(nb[r, NB_LO0 + q], nb[r, NB_LO1 + q]) > cloth_hi[q] + search_radius or \
                    max(nb[r, NB_HI0 + q], nb[r, NB_HI1 + q]) < cloth_lo[q] - search_radius:
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
    tnow = clock[CLK_TIME]
    use_only = only.shape[0] > 0
    for i in range(start, stop):
        if use_only and not only[i]:
            continue
        if recheck:
            stats[ST_RECHECK] += 1   # seen a second time in this response
        px = pos[i, 0]
        py = pos[i, 1]
        pz = pos[i, 2]
        ti = pclk[i, CLK_TIME]
        rel = np.inf   # never seen: no bound on its motion or the body's
        bstep = np.inf
        if ti >= 0.0:
            # since the point was last seen: its motion in the moving frame, the body's
            ex = px - last[i, 0] - (clock[CLK_TRAVEL] - pclk[i, CLK_TRAVEL])
            ey = py - last[i, 1] - (clock[CLK_TRAVEL + 1] - pclk[i, CLK_TRAVEL + 1])
            ez = pz - last[i, 2] - (clock[CLK_TRAVEL + 2] - pclk[i, CLK_TRAVEL + 2])
            rel = math.sqrt(ex * ex + ey * ey + ez * ez)
            btrav = abs(clock[CLK_BODY] - pclk[i, CLK_BODY])
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
        for q in range(N_CLOCKS):
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
                fill_record(rec, i, vb, faces, t)
                rkey[i] = fkey | t
            gx = rec_centroid(rec, i, 0, b, alpha)
            gy = rec_centroid(rec, i, 1, b, alpha)
            gz = rec_centroid(rec, i, 2, b, alpha)
            ex = (px - cache_p[i, 0]) - (gx - cache_c[i, 0])
            ey = (py - cache_p[i, 1]) - (gy - cache_c[i, 1])
            ez = (pz - cache_p[i, 2]) - (gz - cache_c[i, 2])
            near = ex * ex + ey * ey + ez * ez < reuse_tol * reuse_tol
            k = 1.0 - alpha
            ax, ay, az, bx, by, bz, cx, cy, cz = rec_triangle_at(rec, i, k, alpha)
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
                    other_part_bounds(i, kt, dt_ + cert_reach, px, py, pz, alpha, rx, ry, rz,
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
                    ax, ay, az = vp_at(vp, ia, k, alpha)
                    bx, by, bz = vp_at(vp, ib, k, alpha)
                    cx, cy, cz = vp_at(vp, ic, k, alpha)
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
                        if nn > 1 and box_d2(px, py, pz, nbl, rt) >= d2:
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
                                    cc2[i, q] = _vp_centroid(vp, faces, tk, q, k, alpha)
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
            spd[SPD_PRUNED] = 0.0
            spd[SPD_LEAVES] = 0.0
            lower = np.inf  # squared bound, over the frame, to every part's triangles
            now = np.inf  # squared bound, now, to the parts not searched
            for k in range(n_parts):
                if not part_active[k]:
                    continue
                rt = roots[k]
                dr = box_d2(px, py, pz, nbl, rt)
                if not reach[k] or (skip_far and dr >= best_d2):
                    lower = min(lower, swept_d2(px - alpha * rx, py - alpha * ry,
                                                 pz - alpha * rz, nbl, rt))
                    spd[SPD_PRUNED] = max(spd[SPD_PRUNED],
                                          nbl[rt, NL_SPEED] - math.sqrt(dr) * inv_t)
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
                pspeed[i] = max(spd[SPD_PRUNED] + dd * inv_t, spd[SPD_LEAVES], 0.0) \
                    if rest > 1e-9 else 0.0
                pstamp[i] = frame
                if best_t < 0:
                    clear_rel[i] = dd - touch
            if best_t < 0:
                if use_cache:
                    cache_tri[i] = -1
                continue
            if rkey[i] != fkey | best_t:
                fill_record(rec, i, vb, faces, best_t)
                rkey[i] = fkey | best_t
            if use_cache:
                cache_tri[i] = best_t
                for q in range(3):
                    cache_c[i, q] = rec_centroid(rec, i, q, b, alpha)
                cache_p[i, 0] = px
                cache_p[i, 1] = py
                cache_p[i, 2] = pz
        s, nx, ny, nz, bv, bw = signed_rec(px, py, pz, rec, i, alpha)
        if recheck and s >= 0.0:
            # looked at again after a push: outside, it keeps what that push gave it
            continue
        if s >= touch:
            if s < touch + plane_band:
                bvx, bvy, bvz = rec_velocity(rec, i, alpha, bv, bw)
                near_plane(planes, i, px, py, pz, nx, ny, nz, s, thickness, bvx, bvy, bvz,
                           friction)
            if use_clear and searched and best_d2 < np.inf:
                # outside: no triangle nearer than √best_d2 now (a point inside has none)
                clear_rel[i] = math.sqrt(best_d2) - touch
            continue
        if s <= -max_depth:
            # deep: a collision only if the point crossed the surface since it was last
            # seen (its position then, against the same triangle at its time)
            sp, _, _, _, _, _ = signed_rec(qx, qy, qz, rec, i, qa)
            if sp < 0.0:
                continue
        held[i] = True
        stats[ST_CONTACT] += 1
        if use_clear:
            clear[i] = 0.0
        bvx, bvy, bvz = rec_velocity(rec, i, alpha, bv, bw)
        if recheck and fold(pos, vel, i, s, nx, ny, nz, bvx, bvy, bvz, thickness, friction,
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
            if second_surface(pos, vel, i, face_part[best_t], s, nx, ny, nz, bvx, bvy, bvz,
                               alpha, rx, ry, rz, vb, vpl, lf, faces, nbl, links, tris, roots,
                               part_active, reach, thickness, friction, touch, cert_reach,
                               stack, inv_t, spd, rec2, csw, crel, cstamp, frame, planes,
                               stats):
                _left_here(left, pos, i)


@numba.njit(cache=True, _nrt=False, inline="always")
def _vp_centroid(vp, faces, t, q, k, alpha):
    """Coordinate q of triangle t's centroid at time ``alpha`` (k = 1 − alpha), from the
    positions ``vp``."""
    return (k * (vp[faces[t, 0], VP_X0 + q] + vp[faces[t, 1], VP_X0 + q]
                 + vp[faces[t, 2], VP_X0 + q])
            + alpha * (vp[faces[t, 0], VP_X1 + q] + vp[faces[t, 1], VP_X1 + q]
                       + vp[faces[t, 2], VP_X1 + q])) / 3.0


@numba.njit(cache=True, _nrt=False, inline="always")
def _left_here(left, pos, i):
    """Where point i was left (after a push), for the crossing test."""
    left[i, 0] = pos[i, 0]
    left[i, 1] = pos[i, 1]
    left[i, 2] = pos[i, 2]
