"""A held point near a second surface: another part facing the first within the thickness, the
cloth pinched between (:func:`second_surface`), and a point pushed behind another surface where
the body folds onto itself (:func:`fold`); with the other parts' bounds over the frame that
both this and the object pass's reuse of a closest triangle take (:func:`other_part_bounds`).
The inputs' groups: :mod:`catwalk.collide.kernels.object_inputs`."""

from __future__ import annotations

import math

import numba
import numpy as np

from catwalk.cloth.state import PLANE_NORMAL, PLANE_OFFSET, PLANE_VELOCITY
from catwalk.collide.bvh import (
    SPD_LEAVES,
    SPD_PRUNED,
    TreeAt,
    closest_triangle_t,
    swept_lower,
)
from catwalk.collide.kernels.record import fill_record, rec_velocity, signed_rec
from catwalk.collide.kernels.response import Contact, pinch
from catwalk.collide.kernels.stats import ST_NODES, ST_PINCH, ST_SECOND, ST_TRIS


@numba.njit(cache=True, _nrt=False, inline="always")
def other_part_bounds(i, kt, ro, px, py, pz, at, body, part_active, others, frame, ws):
    """``others.csw[i, k]``: how near each active part other than ``kt`` comes to point i
    (at p, the search's time ``at``) over this frame (in the moving frame: its leaf boxes
    swept over the frame), looked for within ``ro`` (a bound of ``ro`` means "no nearer");
    the point's motion since (``crel``) restarts from 0 and ``cstamp[i]`` marks the
    ``frame``."""
    for k2 in range(body.roots.shape[0]):
        others.csw[i, k2] = np.inf
        if k2 != kt and part_active[k2]:
            bo, nv = swept_lower(px - at.alpha * at.rx, py - at.alpha * at.ry,
                                 pz - at.alpha * at.rz, body.nbl, body.links, body.roots[k2],
                                 ro * ro, ws.stack)
            others.csw[i, k2] = math.sqrt(bo)
            ws.stats[ST_NODES] += nv
    others.crel[i] = 0.0
    others.cstamp[i] = frame


@numba.njit(cache=True, _nrt=False)
def second_surface(pos, vel, planes, i, kt, first, at, body, part_active, reach, cfg, others,
                   frame, ws):
    """A point held by part ``kt`` (its :data:`~.response.Contact` ``first`` after its
    response: signed distance s1 along n1, the body moving at w1 there) may be pinched:
    another part's surface faces it within the thickness (a hand over the thigh, the thighs,
    with the cloth between), and pushing it off the first part alone pushed it against the
    second.

    Each other part that may come within thickness + contact slack (its bound ``csw`` for
    this frame less the point's motion since; the bounds are taken within the search radius
    beyond the first surface, as a reused closest triangle's check takes them, so that one
    set serves both) is searched for its nearest triangle within that (with s1 no more than
    that and s1 + s2 ≥ 0, a second surface that matters is no farther). If the point is
    within the thickness of it (signed s2 along n2 < thickness), the surfaces face each other
    (n1·n2 ≤ −0.3) and do not overlap (s1 + s2 ≥ 0), the point moves along
    u = (n1 − n2)/|n1 − n2| to keep the thickness from both where the gap allows it, else to
    the middle of the gap; its velocity into the first surface, relative to the two surfaces'
    mean velocity, goes (with friction); its contact plane is the one through it along u (the
    solver keeps it off the first part; the next response sees the second again)
    (:func:`~.response.pinch`). Overlapping parts (a body touching itself: no position is
    outside both) and creases where two parts meet are left to the nearest surface: putting
    such points in the middle of the overlap made the armpit walks worse (docs/collide.md,
    "Pinched between two facing surfaces").

    The inputs: the search's time ``at`` and the object pass's groups (``body``, ``cfg``, the
    per-point bounds ``others``, the thread's workspace ``ws``: its record ``rec2``). Returns
    whether the point was moved."""
    px = pos[i, 0]
    py = pos[i, 1]
    pz = pos[i, 2]
    if others.cstamp[i] != frame:
        # the bounds a reused closest triangle's check takes, looked for as far (one set
        # serves both for the rest of the frame)
        other_part_bounds(i, kt, max(first.s, 0.0) + cfg.search_radius, px, py, pz, at, body,
                          part_active, others, frame, ws)
    t2 = _nearest_other(i, kt, px, py, pz, cfg.thickness + cfg.slack, at, body, part_active,
                        reach, others, ws)
    if t2 < 0:
        return False
    rec2 = ws.rec2
    fill_record(rec2, 0, body.vb, body.faces, t2)
    s2, n2x, n2y, n2z, bv, bw = signed_rec(px, py, pz, rec2, 0, at.alpha)
    if s2 >= cfg.thickness:
        return False
    w2x, w2y, w2z = rec_velocity(rec2, 0, at.alpha, bv, bw)
    ws.stats[ST_SECOND] += 1
    if not pinch(pos, vel, planes, i, first, Contact(s2, n2x, n2y, n2z, w2x, w2y, w2z),
                 cfg.thickness, cfg.friction):
        return False
    ws.stats[ST_PINCH] += 1
    return True


@numba.njit(cache=True, _nrt=False, inline="always")
def _nearest_other(i, kt, px, py, pz, radius, at, body, part_active, reach, others, ws):
    """The nearest triangle within ``radius`` of point i among the active parts in reach other
    than ``kt`` whose bound allows one, or −1 (the search's speed accumulators ``spd`` are the
    point's own search's: kept)."""
    best = np.inf
    t2 = -1
    spd = ws.spd
    s0 = spd[SPD_PRUNED]
    s1_ = spd[SPD_LEAVES]
    tree = TreeAt(body.vpl, body.lf, body.nbl, body.links, body.tris)
    for k2 in range(body.roots.shape[0]):
        if k2 == kt or not part_active[k2] or not reach[k2] or \
                others.csw[i, k2] - others.crel[i] > radius:
            continue
        d2o, tk, nv, nt, _ = closest_triangle_t(px, py, pz, tree, body.roots[k2], at,
                                                radius * radius, -1, ws.stack, spd)
        ws.stats[ST_NODES] += nv
        ws.stats[ST_TRIS] += nt
        if tk >= 0 and d2o < best:
            best = d2o
            t2 = tk
    spd[SPD_PRUNED] = s0
    spd[SPD_LEAVES] = s1_
    return t2


@numba.njit(cache=True, _nrt=False)
def fold(pos, vel, planes, i, second, thickness, friction):
    """Point i, pushed off a surface earlier in this response (its contact plane
    ``planes[i]``), is behind another (its :data:`~.response.Contact` ``second``: signed
    s2 < 0 along n2, moving at w2): where the body folds onto itself (the skinned arm under
    the armpit, two fingers) the two may face each other, and a push off the second alone
    would put the point behind the first. Such a point goes between the two
    (:func:`~.response.pinch`). A point outside the second surface is left to the plain push
    (it keeps it outside the first: s1 = thickness before, less at most thickness − s2), and a
    point already put between two parts (whose plane says thickness for a narrower gap) is
    left to the second-surface check. Returns whether it was moved."""
    n1x = planes[i, PLANE_NORMAL]
    n1y = planes[i, PLANE_NORMAL + 1]
    n1z = planes[i, PLANE_NORMAL + 2]
    if second.s >= 0.0 or (n1x == 0.0 and n1y == 0.0 and n1z == 0.0):
        return False
    s1 = n1x * pos[i, 0] + n1y * pos[i, 1] + n1z * pos[i, 2] - planes[i, PLANE_OFFSET] + \
        thickness
    first = Contact(s1, n1x, n1y, n1z, planes[i, PLANE_VELOCITY], planes[i, PLANE_VELOCITY + 1],
                    planes[i, PLANE_VELOCITY + 2])
    return pinch(pos, vel, planes, i, first, second, thickness, friction)
