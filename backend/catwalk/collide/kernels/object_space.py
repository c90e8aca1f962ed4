"""The object pass's kernel (:func:`object_pass`): each cloth point's closest triangle in the
active parts' hierarchies, the point's previous position against it, the response. Its inputs'
groups are in :mod:`catwalk.collide.kernels.object_inputs`.

The hierarchies' node boxes ``nb`` hold each node at the previous and the current frame; at
time ``alpha`` a node's box is their blend, which the pass reads from the nodes' table ``nbl``
(blended once for the call, with the boxes swept over the frame and the nodes' speeds:
:func:`catwalk.collide.bvh.blend_at`). Clearances are measured in the frame that moves with the
body's mean displacement (``ref`` over this frame), so that the body's and the cloth's common
motion does not use them up.

What a point's skips rest on is how far it and the body moved since the point was last seen
here, whatever moved it in between (the solver, a position correction, the image pass):
``last`` (P,3) its position then, ``pclk`` the collider's clocks then (the moving frame's
travel, the body's travel relative to it, the time: ``object_inputs.CLK_TRAVEL`` …), ``clock``
the same clocks now. A point's motion in the moving frame is then
|p − last − (travel now − travel then)|, the body's is the difference of the body clocks (or
``pspeed`` × the time since, within the frame of the point's last search).

Per point (:func:`_see_point`): (1) clearance (:func:`_still_clear`): while ``clear[i]`` (how
much closer the point may come to the boxes swept by the body's leaves over this frame, in the
moving frame; reset every frame) stays positive after subtracting the point's motion, or
``clear_rel[i]`` (how much closer it may come to the body as it was at the last search) stays
positive after subtracting that motion and the body's, nothing else is done; (2) the cached
closest triangle is reused (:func:`_reuse_kept`) while the point moved less than ``reuse_tol``
relative to it and no *other* part has a triangle nearer to the point than it — another part
coming close (a hand swinging over a thigh) is always seen (:func:`_other_part_nearer`). Per
other part, ``csw[i, k]`` bounds how near it comes over frame ``cstamp[i]`` (in the moving
frame: its leaf boxes swept over the frame, looked for within the triangle's distance +
``search_radius``), less ``crel[i]``, the point's motion since; a part beyond the triangle's
distance by that is out of the question. One part that is not: its nearest triangle to the
point ``ct2[i]`` is kept (with the point ``cp2`` and the triangle's centroid ``cc2`` then) and
compared with the closest triangle, reused like it while the point moves less than
``reuse_tol`` relative to it (:func:`_kept_other_nearer`; parts that touch, like the torso and
a thigh in ``object`` mode, meet along a seam: points there have the other part always near);
else those parts' hierarchies are searched at this substep (:func:`_search_other_parts`);
(3) else the hierarchies are searched within ``search_radius`` + the point's motion
(:func:`_search`); (4) signed distance to the closest triangle, collision and response
(:func:`_collide`). A point deeper than ``max_depth`` collides only if its last position, at
its time, was outside.

``rkey`` (P,) int64 and ``rec`` (P, :data:`~catwalk.collide.kernels.record.REC_COLUMNS`)
float32: each point's copy of its closest triangle's vertices for this ``frame`` (see
:func:`~catwalk.collide.kernels.record.fill_record`), read in point order while the triangle
is reused, instead of the scattered vertices. ``pspeed``/``pstamp`` (P,): a speed bound for
``clear_rel`` found by the point's last search in frame ``pstamp`` (the nodes near it move
slower than the fastest vertex): how fast the body's triangles can approach it during the rest
of that frame; in another frame, the body clock. ``left`` (P,3): where the point was left then,
after any push (the crossing test's last position). ``prev``/``alpha_prev``: the previous
positions and time, used for a point never seen.

(Numba caches a kernel by its own file: the helpers this pass inlines from other files —
:mod:`.record`, :mod:`.response`, :mod:`.second_surface`'s bounds and
:mod:`catwalk.collide.bvh`'s box tests — need a change here too when they change, or the cached
kernel keeps the old code.)
"""

from __future__ import annotations

import math

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
    SearchTime,
    TreeAt,
    box_d2,
    closest_triangle_t,
    offset_to_triangle,
    swept_d2,
    vp_at,
)
from catwalk.collide.kernels.object_inputs import (
    CLK_BODY,
    CLK_TIME,
    CLK_TRAVEL,
    N_CLOCKS,
    ObjectBody,
    ObjectCloth,
    ObjectConfig,
    ObjectPoints,
    ObjectTime,
    OtherParts,
    Workspace,
)
from catwalk.collide.kernels.record import (
    fill_record,
    rec_centroid,
    rec_triangle_at,
    rec_velocity,
    signed_rec,
)
from catwalk.collide.kernels.response import Contact, near_plane, record_plane, respond
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


@numba.njit(cache=True, _nrt=False, nogil=True)
def object_pass(cloth, only, part_active, cloth_lo, cloth_hi, now, body, cfg, pts, ws, start,
                stop):
    """Object-space collision of the cloth points ``start`` … ``stop`` − 1 against the active
    parts' hierarchies (the method: the module's docstring).

    The inputs come grouped (:mod:`catwalk.collide.kernels.object_inputs`): ``cloth``
    (:data:`ObjectCloth`: the points, and their ``held`` and ``planes`` written for the points
    seen), ``now`` (:data:`ObjectTime`), ``body`` (:data:`ObjectBody`), ``cfg``
    (:data:`ObjectConfig`), ``pts`` (:data:`ObjectPoints`, what is kept per point between
    calls) and ``ws`` (:data:`Workspace`, a thread's), each a plain tuple in its fields' order.
    ``part_active`` (parts,) bool and ``cloth_lo``/``cloth_hi`` (the cloth's box) select the
    parts looked at.

    ``planes``: for each held point its contact plane, written as it is found
    (:func:`~catwalk.collide.kernels.response.record_plane`); for each point looked at, not
    held but within ``plane_band`` of touching, the same plane unless it has one
    (:func:`~catwalk.collide.kernels.response.near_plane`).

    ``only`` (P,) bool: when not empty, only the points marked are seen (the others are
    left as they are, their clocks too: their next motion counts everything since).

    ``second``: also look, for each held point, for a second part facing the first within the
    thickness, the cloth pinched between
    (:func:`~catwalk.collide.kernels.second_surface.second_surface`).

    ``recheck``: the points seen were pushed earlier in this response (the frame kept looks
    at them again): one found outside is left as it is; one inside a surface facing the plane
    it was pushed onto goes between the two
    (:func:`~catwalk.collide.kernels.second_surface.fold`); another is pushed as usual.

    A point's work reads the body and writes only that point's entries, so disjoint ranges of
    points run at once on several threads (the GIL released), each with its own workspaces
    ``stack``, ``reach``, ``spd``, ``rec2`` and counters ``stats``."""
    cloth = ObjectCloth(*cloth)
    now = ObjectTime(*now)
    body = ObjectBody(*body)
    cfg = ObjectConfig(*cfg)
    pts = ObjectPoints(*pts)
    ws = Workspace(*ws)
    if not _parts_in_reach(part_active, cloth_lo, cloth_hi, body, cfg, ws.reach):
        # nothing is seen: the points' clocks stay where they were, so their next motion
        # counts everything since
        ws.stats[ST_SKIPPED] += stop - start
        return
    rest = 1.0 - now.alpha
    at = SearchTime(now.alpha, now.ref[0], now.ref[1], now.ref[2],
                    1.0 / rest if rest > 1e-9 else 0.0)
    tree = TreeAt(body.vpl, body.lf, body.nbl, body.links, body.tris)
    use_only = only.shape[0] > 0
    for i in range(start, stop):
        if use_only and not only[i]:
            continue
        if cfg.recheck:
            ws.stats[ST_RECHECK] += 1   # seen a second time in this response
        _see_point(i, cloth, part_active, now, at, tree, body, cfg, pts, ws)


@numba.njit(cache=True, _nrt=False, inline="always")
def _parts_in_reach(part_active, cloth_lo, cloth_hi, body, cfg, reach):
    """``reach[k]``: whether active part k's box over the frame comes within the search radius
    of the cloth's box (every active part with the ``far_points`` skip off); returns whether
    any does."""
    nb = body.nb
    any_part = False
    for k in range(body.roots.shape[0]):
        reach[k] = False
        if not part_active[k]:
            continue
        r = body.roots[k]
        ok = True
        for q in range(3):
            if min(nb[r, NB_LO0 + q], nb[r, NB_LO1 + q]) > cloth_hi[q] + cfg.search_radius or \
                    max(nb[r, NB_HI0 + q], nb[r, NB_HI1 + q]) < \
                    cloth_lo[q] - cfg.search_radius:
                ok = False
        reach[k] = ok or not cfg.skip_far
        any_part = any_part or reach[k]
    return any_part


@numba.njit(cache=True, _nrt=False, inline="always")
def _see_point(i, cloth, part_active, now, at, tree, body, cfg, pts, ws):
    """Point i: its motion since it was last seen, its clearance, its closest triangle
    (kept or searched), the collision with it."""
    px = cloth.pos[i, 0]
    py = cloth.pos[i, 1]
    pz = cloth.pos[i, 2]
    rel, bstep, qx, qy, qz, qa, move = _since_seen(i, px, py, pz, cloth.prev, now, pts)
    if cfg.use_clear and _still_clear(i, rel, bstep, pts):
        ws.stats[ST_CLEAR] += 1
        return
    best_t, best_d2, searched = _closest(i, px, py, pz, move, part_active, now, at, tree, body,
                                         cfg, pts, ws)
    if best_t < 0:
        return
    s, nx, ny, nz, bv, bw = signed_rec(px, py, pz, pts.rec, i, at.alpha)
    if cfg.recheck and s >= 0.0:
        # looked at again after a push: outside, it keeps what that push gave it
        return
    touch = cfg.thickness + cfg.slack
    if s >= touch:
        if s < touch + cfg.plane_band:
            bvx, bvy, bvz = rec_velocity(pts.rec, i, at.alpha, bv, bw)
            near_plane(cloth.planes, i, px, py, pz, Contact(s, nx, ny, nz, bvx, bvy, bvz),
                       cfg.thickness, cfg.friction)
        if cfg.use_clear and searched and best_d2 < np.inf:
            # outside: no triangle nearer than √best_d2 now (a point inside has none)
            pts.clear_rel[i] = math.sqrt(best_d2) - touch
        return
    if s <= -cfg.max_depth:
        # deep: a collision only if the point crossed the surface since it was last
        # seen (its position then, against the same triangle at its time)
        sp, _, _, _, _, _ = signed_rec(qx, qy, qz, pts.rec, i, qa)
        if sp < 0.0:
            return
    bvx, bvy, bvz = rec_velocity(pts.rec, i, at.alpha, bv, bw)
    _collide(i, px, py, pz, Contact(s, nx, ny, nz, bvx, bvy, bvz), best_t, cloth, part_active,
             now, at, body, cfg, pts, ws)


@numba.njit(cache=True, _nrt=False, inline="always")
def _since_seen(i, px, py, pz, prev, now, pts):
    """Point i (at p) since it was last seen: its motion in the moving frame ``rel`` and the
    body's ``bstep`` (∞ for a point never seen); where it was left then and when (q, qa: the
    crossing test's last position; the previous position for a point another pass had); how
    far it moved since (``move``, for the search radius). Marks it seen now (before any push:
    a push counts as motion the next time). Returns (rel, bstep, qx, qy, qz, qa, move)."""
    frame = now.frame
    clock = now.clock
    tnow = clock[CLK_TIME]
    last = pts.last
    pclk = pts.pclk
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
        bstep = pts.pspeed[i] * (tnow - ti) if same and pts.pstamp[i] == frame else btrav
    if ti >= frame + now.alpha_prev - 1e-9:
        # seen at the previous call or since: where it was left then
        qx = pts.left[i, 0]
        qy = pts.left[i, 1]
        qz = pts.left[i, 2]
        qa = min(max(ti - frame, 0.0), now.alpha)
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
        qa = now.alpha_prev
        move = 0.0
    dx = px - prev[i, 0]
    dy = py - prev[i, 1]
    dz = pz - prev[i, 2]
    move = max(move, math.sqrt(dx * dx + dy * dy + dz * dz))
    # seen now (before any push: a push counts as motion the next time)
    _mark(last, i, px, py, pz)
    _mark(pts.left, i, px, py, pz)
    for q in range(N_CLOCKS):
        pclk[i, q] = clock[q]
    pts.crel[i] += rel  # the point's motion since the other parts' bounds were taken
    return rel, bstep, qx, qy, qz, qa, move


@numba.njit(cache=True, _nrt=False, inline="always")
def _still_clear(i, rel, bstep, pts):
    """Point i's clearances less its motion ``rel`` (and the body's ``bstep``): whether one of
    them still holds (nothing else to do)."""
    c1 = pts.clear[i] - rel
    c2 = pts.clear_rel[i] - rel - bstep
    pts.clear[i] = c1
    pts.clear_rel[i] = c2
    return c1 > 0.0 or c2 > 0.0


@numba.njit(cache=True, _nrt=False, inline="always")
def _closest(i, px, py, pz, move, part_active, now, at, tree, body, cfg, pts, ws):
    """Point i's closest triangle, within the search radius + its motion ``move``: the kept
    one while it holds (:func:`_reuse_kept`), else searched (:func:`_search`) and kept, its
    record filled. Returns (triangle or −1, its squared distance bound, whether searched)."""
    r = cfg.search_radius + move
    best_d2 = r * r if cfg.skip_far else np.inf
    seed = -1
    # reuse the closest triangle if the point barely moved relative to it and no other
    # part came nearer
    t = pts.cache_tri[i] if cfg.use_cache else -1
    if t >= 0 and part_active[body.face_part[t]]:
        near, d2 = _reuse_kept(i, t, px, py, pz, part_active, now, at, tree, body, cfg, pts, ws)
        if near:
            ws.stats[ST_REUSED] += 1
            return t, best_d2, False
        if d2 < best_d2:
            # the search below starts from this triangle's distance: it prunes more
            best_d2 = d2
            seed = t
    best_t, best_d2 = _search(i, px, py, pz, best_d2, seed, part_active, now, at, tree, body,
                              cfg, pts, ws)
    if best_t < 0:
        if cfg.use_cache:
            pts.cache_tri[i] = -1
        return best_t, best_d2, True
    _fill(pts, i, body, now.frame, best_t)
    if cfg.use_cache:
        pts.cache_tri[i] = best_t
        for q in range(3):
            pts.cache_c[i, q] = rec_centroid(pts.rec, i, q, 1.0 - at.alpha, at.alpha)
        _mark(pts.cache_p, i, px, py, pz)
    return best_t, best_d2, True


@numba.njit(cache=True, _nrt=False, inline="always")
def _fill(pts, i, body, frame, t):
    """Point i's record of triangle t, unless it holds it already for this frame."""
    key = (frame << 32) | t
    if pts.rkey[i] != key:
        fill_record(pts.rec, i, body.vb, body.faces, t)
        pts.rkey[i] = key


@numba.njit(cache=True, _nrt=False, inline="always")
def _reuse_kept(i, t, px, py, pz, part_active, now, at, tree, body, cfg, pts, ws):
    """Whether point i's kept closest triangle t still answers: the point moved less than
    ``reuse_tol`` relative to it, is not inside deeper than that, and no other part came
    nearer. Returns (whether it does, the squared distance to it now)."""
    alpha = at.alpha
    _fill(pts, i, body, now.frame, t)
    rec = pts.rec
    b = 1.0 - alpha
    gx = rec_centroid(rec, i, 0, b, alpha)
    gy = rec_centroid(rec, i, 1, b, alpha)
    gz = rec_centroid(rec, i, 2, b, alpha)
    ex = (px - pts.cache_p[i, 0]) - (gx - pts.cache_c[i, 0])
    ey = (py - pts.cache_p[i, 1]) - (gy - pts.cache_c[i, 1])
    ez = (pz - pts.cache_p[i, 2]) - (gz - pts.cache_c[i, 2])
    tol2 = cfg.reuse_tol * cfg.reuse_tol
    near = ex * ex + ey * ey + ez * ez < tol2
    ax, ay, az, bx, by, bz, cx, cy, cz = rec_triangle_at(rec, i, b, alpha)
    qx_, qy_, qz_ = offset_to_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz)
    d2 = qx_ * qx_ + qy_ * qy_ + qz_ * qz_
    if near and d2 > tol2 and \
            ((by - ay) * (cz - az) - (bz - az) * (cy - ay)) * qx_ + \
            ((bz - az) * (cx - ax) - (bx - ax) * (cz - az)) * qy_ + \
            ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)) * qz_ > 0.0:
        # inside, deeper than reuse_tol: the push is long, and a neighbour's normal
        # would send it elsewhere: search for the closest triangle itself
        near = False
    if near:
        # another part nearer than this triangle (say a hand come over the thigh
        # the point rests on) makes the answer another
        near = not _other_part_nearer(i, body.face_part[t], d2, px, py, pz, part_active, now,
                                      at, tree, body, cfg, pts, ws)
    return near, d2


@numba.njit(cache=True, _nrt=False, inline="always")
def _other_part_nearer(i, kt, d2, px, py, pz, part_active, now, at, tree, body, cfg, pts, ws):
    """Whether a part other than ``kt`` has a triangle nearer to point i than √d2 (the kept
    triangle's distance): the parts whose bound for this frame, less the point's motion, is
    within it (bounds taken afresh in a new frame), then the one such part's kept nearest
    triangle while it holds (:func:`_kept_other_nearer`), else each such part searched
    (:func:`_search_other_parts`)."""
    dt_ = math.sqrt(d2)
    if pts.cstamp[i] != now.frame:
        other_part_bounds(i, kt, dt_ + cfg.search_radius, px, py, pz, at, body, part_active,
                          OtherParts(pts.csw, pts.crel, pts.cstamp), now.frame, ws)
    kn = -1
    nn = 0
    for k2 in range(body.roots.shape[0]):
        if k2 != kt and part_active[k2] and pts.csw[i, k2] - pts.crel[i] <= dt_:
            kn = k2
            nn += 1
    t2 = pts.ct2[i]
    if nn == 1 and t2 >= 0 and body.face_part[t2] == kn:
        decided, nearer = _kept_other_nearer(i, t2, d2, px, py, pz, at, body, cfg, pts)
        if decided:
            return nearer
    if nn > 0:
        return _search_other_parts(i, kt, nn, d2, px, py, pz, part_active, at, tree, body, cfg,
                                   pts, ws)
    return False


@numba.njit(cache=True, _nrt=False, inline="always")
def _kept_other_nearer(i, t2, d2, px, py, pz, at, body, cfg, pts):
    """The other part's nearest triangle ``t2`` kept for point i, while the point moved less
    than ``reuse_tol`` relative to it: returns (whether it decides, whether it is nearer than
    √d2)."""
    alpha = at.alpha
    k = 1.0 - alpha
    faces = body.faces
    ax, ay, az = vp_at(body.vp, faces[t2, 0], k, alpha)
    bx, by, bz = vp_at(body.vp, faces[t2, 1], k, alpha)
    cx, cy, cz = vp_at(body.vp, faces[t2, 2], k, alpha)
    ex = (px - pts.cp2[i, 0]) - ((ax + bx + cx) / 3.0 - pts.cc2[i, 0])
    ey = (py - pts.cp2[i, 1]) - ((ay + by + cy) / 3.0 - pts.cc2[i, 1])
    ez = (pz - pts.cp2[i, 2]) - ((az + bz + cz) / 3.0 - pts.cc2[i, 2])
    if not ex * ex + ey * ey + ez * ez < cfg.reuse_tol * cfg.reuse_tol:
        return False, False
    qx_, qy_, qz_ = offset_to_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz)
    return True, qx_ * qx_ + qy_ * qy_ + qz_ * qz_ < d2


@numba.njit(cache=True, _nrt=False, inline="always")
def _search_other_parts(i, kt, nn, d2, px, py, pz, part_active, at, tree, body, cfg, pts, ws):
    """Each of the ``nn`` other parts whose bound comes within √d2 of point i, searched at
    this substep for a triangle nearer than that (when there is one such part, its nearest
    within the bounds' reach, kept for the next time); returns whether one was found."""
    nearer = False
    dt_ = math.sqrt(d2)
    ro = dt_ + cfg.search_radius
    for k2 in range(body.roots.shape[0]):
        if k2 == kt or not part_active[k2] or pts.csw[i, k2] - pts.crel[i] > dt_:
            continue
        rt = body.roots[k2]
        if nn > 1 and box_d2(px, py, pz, body.nbl, rt) >= d2:
            continue
        d2o, tk, nv, nt, _ = closest_triangle_t(px, py, pz, tree, rt, at,
                                                d2 if nn > 1 else ro * ro, -1, ws.stack,
                                                ws.spd)
        ws.stats[ST_NODES] += nv
        ws.stats[ST_TRIS] += nt
        if tk >= 0 and d2o < d2:
            nearer = True
        if nn == 1:
            pts.ct2[i] = tk
            if tk >= 0:
                _mark(pts.cp2, i, px, py, pz)
                for q in range(3):
                    pts.cc2[i, q] = _vp_centroid(body.vp, body.faces, tk, q, 1.0 - at.alpha,
                                                 at.alpha)
    return nearer


@numba.njit(cache=True, _nrt=False, inline="always")
def _search(i, px, py, pz, best_d2, best_t, part_active, now, at, tree, body, cfg, pts, ws):
    """Point i's closest triangle nearer than √best_d2 (starting from triangle ``best_t``, or
    −1), each part in reach searched, the others bounded; with the clearances and the speed
    bound for the rest of the frame that the search shows. Returns (best_t, best_d2)."""
    pts.cstamp[i] = -1  # the other parts than the closest triangle's: not known
    pts.ct2[i] = -1
    spd = ws.spd
    stats = ws.stats
    nbl = body.nbl
    boxed = False
    spd[SPD_PRUNED] = 0.0
    spd[SPD_LEAVES] = 0.0
    lower = np.inf  # squared bound, over the frame, to every part's triangles
    unsearched = np.inf  # squared bound, now, to the parts not searched
    for k in range(body.roots.shape[0]):
        if not part_active[k]:
            continue
        rt = body.roots[k]
        dr = box_d2(px, py, pz, nbl, rt)
        if not ws.reach[k] or (cfg.skip_far and dr >= best_d2):
            lower = min(lower, swept_d2(px - at.alpha * at.rx, py - at.alpha * at.ry,
                                        pz - at.alpha * at.rz, nbl, rt))
            spd[SPD_PRUNED] = max(spd[SPD_PRUNED], nbl[rt, NL_SPEED] - math.sqrt(dr) * at.inv_t)
            unsearched = min(unsearched, dr)
            continue
        boxed = True
        best_d2, best_t, nv, nt, ld2 = closest_triangle_t(px, py, pz, tree, rt, at, best_d2,
                                                          best_t, ws.stack, spd)
        lower = min(lower, ld2)
        stats[ST_NODES] += nv
        stats[ST_TRIS] += nt
    # a part skipped as out of reach may be nearer than the search radius
    best_d2 = min(best_d2, unsearched)
    if boxed:
        stats[ST_BOXED] += 1
        stats[ST_NARROW] += 1
    else:
        stats[ST_SKIPPED] += 1
    if cfg.use_clear and cfg.skip_far:
        touch = cfg.thickness + cfg.slack
        # no leaf box swept over this frame (moving frame) is nearer than √lower,
        # and no triangle nearer than √best_d2 now
        pts.clear[i] = math.sqrt(lower) - touch
        # and during the rest of this frame none approaches faster than this
        dd = math.sqrt(best_d2)
        pts.pspeed[i] = max(spd[SPD_PRUNED] + dd * at.inv_t, spd[SPD_LEAVES], 0.0) \
            if 1.0 - at.alpha > 1e-9 else 0.0
        pts.pstamp[i] = now.frame
        if best_t < 0:
            pts.clear_rel[i] = dd - touch
    return best_t, best_d2


@numba.njit(cache=True, _nrt=False, inline="always")
def _collide(i, px, py, pz, hit, best_t, cloth, part_active, now, at, body, cfg, pts, ws):
    """Point i (at p) in contact with its closest triangle ``best_t`` (:data:`Contact`
    ``hit``): held, its clearance gone; at the frame kept's look again, put between the faces
    of a fold (:func:`fold`); else its contact plane recorded and, within the thickness,
    pushed out; then a second part facing the first looked for (:func:`second_surface`)."""
    pos, vel, planes = cloth.pos, cloth.vel, cloth.planes
    cloth.held[i] = True
    ws.stats[ST_CONTACT] += 1
    if cfg.use_clear:
        pts.clear[i] = 0.0
    if cfg.recheck and fold(pos, vel, planes, i, hit, cfg.thickness, cfg.friction):
        ws.stats[ST_FOLD] += 1
        _left_here(pts.left, pos, i)
        return
    record_plane(planes, i, px, py, pz, hit, cfg.thickness, cfg.friction)
    s = hit.s
    if s < cfg.thickness:
        respond(pos, vel, i, hit, cfg.thickness, cfg.friction)
        s = cfg.thickness
        # where it was left, for the crossing test (the bounds count the motion from
        # where they hold, before the push: distances change no faster than the point
        # moves)
        _left_here(pts.left, pos, i)
    if cfg.second and second_surface(
            pos, vel, planes, i, body.face_part[best_t],
            Contact(s, hit.nx, hit.ny, hit.nz, hit.wx, hit.wy, hit.wz), at, body, part_active,
            ws.reach, cfg, OtherParts(pts.csw, pts.crel, pts.cstamp), now.frame, ws):
        _left_here(pts.left, pos, i)


@numba.njit(cache=True, _nrt=False, inline="always")
def _vp_centroid(vp, faces, t, q, k, alpha):
    """Coordinate q of triangle t's centroid at time ``alpha`` (k = 1 − alpha), from the
    positions ``vp``."""
    return (k * (vp[faces[t, 0], VP_X0 + q] + vp[faces[t, 1], VP_X0 + q]
                 + vp[faces[t, 2], VP_X0 + q])
            + alpha * (vp[faces[t, 0], VP_X1 + q] + vp[faces[t, 1], VP_X1 + q]
                       + vp[faces[t, 2], VP_X1 + q])) / 3.0


@numba.njit(cache=True, _nrt=False, inline="always")
def _mark(a, i, px, py, pz):
    """``a[i]`` = p."""
    a[i, 0] = px
    a[i, 1] = py
    a[i, 2] = pz


@numba.njit(cache=True, _nrt=False, inline="always")
def _left_here(left, pos, i):
    """Where point i was left (after a push), for the crossing test."""
    left[i, 0] = pos[i, 0]
    left[i, 1] = pos[i, 1]
    left[i, 2] = pos[i, 2]
