"""The body's structure from its coarse horizontal sections: the torso's loop level by level
(:func:`structure`), the crotch where the legs part (:func:`crotch`) and the armpits where the
arms part from the torso (:func:`armpits`)."""

from __future__ import annotations

import numpy as np

from catwalk.body.measure.measurement import Measurement, fail
from catwalk.body.measure.slicing import CX, CZ, PERIM, XMAX, XMIN, largest


def structure(meas: Measurement):
    """Follow the torso's loop through the coarse sections from 58 % of the height: down
    until it parts in two on either side of its centre (the crotch), up until a section has
    no loop over the last one (the top of the head), noting the level each arm's loop parts
    from it (the armpits). Sets ``torso`` (the torso's loop per coarse level, −1 where none),
    ``top_k``, ``crotch_k``, ``armpit_k`` ({side: level})."""
    sec, K = meas.sec, meas.K
    k_start = int(0.58 * K)
    t0 = largest(sec, k_start)
    if t0 < 0:
        raise fail("no surface at mid-height")
    torso = np.full(K, -1)
    torso[k_start] = t0
    crotch_k = None
    for k in range(k_start - 1, -1, -1):
        prev = torso[k + 1]
        box = sec.box(prev)
        pprev = sec.stats[prev, PERIM]
        cand = [c for c in sec.comps(k)
                if sec.inside(c, box, 0.01) and sec.stats[c, PERIM] > 0.15 * pprev]
        if not cand:
            break
        cand.sort(key=lambda c: -sec.stats[c, PERIM])
        if len(cand) >= 2:
            pcx = sec.stats[prev, CX]
            xa, xb = sec.stats[cand[0], CX], sec.stats[cand[1], CX]
            if (xa - pcx) * (xb - pcx) < 0:
                crotch_k = k
                break
        torso[k] = cand[0]
    if crotch_k is None:
        raise fail("no crotch found (the legs never separate)")
    seen = {1: False, -1: False}
    armpit_k: dict[int, int] = {}
    top_k = K - 1
    for k in range(k_start + 1, K):
        prev = torso[k - 1]
        c = largest(sec, k, sec.box(prev), 0.01)
        if c < 0:
            top_k = k - 1
            break
        torso[k] = c
        tb = sec.box(c)
        for side in (1, -1):
            if side in armpit_k:
                continue
            arm = _arm_comp(sec, k, c, tb, side)
            if arm >= 0:
                seen[side] = True
            elif seen[side]:
                armpit_k[side] = k
    if len(armpit_k) < 2:
        raise fail("no armpits found (an arm never separates from the torso)")
    meas.torso = torso
    meas.top_k = top_k
    meas.crotch_k = crotch_k
    meas.armpit_k = armpit_k


def _arm_comp(sec, k, torso_c, tb, side, min_perim=0.03):
    """The largest loop at level k beside the torso's loop ``torso_c`` (box ``tb``) on
    ``side`` (+1: the body's left, +x), at least ``min_perim`` round, or −1."""
    best, bp = -1, -1.0
    for a in sec.comps(k):
        if a == torso_c or sec.stats[a, PERIM] < min_perim:
            continue
        ax = sec.stats[a, CX]
        if (side > 0 and ax > tb[1]) or (side < 0 and ax < tb[0]):
            if sec.stats[a, PERIM] > bp:
                best, bp = a, sec.stats[a, PERIM]
    return best


def _bisect(meas: Measurement, lo, hi, pred, rounds=2, n=16):
    """pred(sections, k) is truthy at lo and not at hi: the switching level, to 1/n**rounds
    of the interval (each round slices n + 1 levels in one call)."""
    for _ in range(rounds):
        lv = np.linspace(lo, hi, n + 1)
        sec = meas.hs.slice(lv)
        j = 0
        while j < n - 1 and pred(sec, j + 1):
            j += 1
        lo, hi = lv[j], lv[j + 1]
    return 0.5 * (lo + hi)


def crotch(meas: Measurement):
    """The crotch: the level where the legs part (bisected between the coarse levels) and
    the point midway between the legs' loops there. Sets ``crotch_y``, ``crotch_pt``."""
    k = meas.crotch_k
    above = meas.torso[k + 1]
    box = meas.sec.box(above)
    pmin = 0.15 * meas.sec.stats[above, PERIM]
    pcx = meas.sec.stats[above, CX]

    def legs(s1, k=0):
        cand = [c for c in s1.comps(k)
                if s1.inside(c, box, 0.01) and s1.stats[c, PERIM] > pmin]
        if len(cand) < 2:
            return None
        cand.sort(key=lambda c: -s1.stats[c, PERIM])
        a, b = cand[0], cand[1]
        if (s1.stats[a, CX] - pcx) * (s1.stats[b, CX] - pcx) >= 0:
            return None
        return s1, a, b

    yc = _bisect(meas, meas.levels[k], meas.levels[k + 1], lambda s1, i: legs(s1, i))
    got = legs(meas.hs.slice(np.array([yc - 1e-4]))) or legs(meas.sec, k)
    s1, a, b = got
    if s1.stats[a, CX] < s1.stats[b, CX]:
        a, b = b, a  # a = left leg (+x)
    x = 0.5 * (s1.stats[a, XMIN] + s1.stats[b, XMAX])
    z = 0.5 * (s1.stats[a, CZ] + s1.stats[b, CZ])
    meas.crotch_y = yc
    meas.crotch_pt = np.array([x, yc, z])


def armpits(meas: Measurement):
    """The armpits: on each side the level where the arm's loop parts from the torso's
    (bisected between the coarse levels) and the point midway between the two loops there.
    Sets ``armpit_pt`` ({side: point}), ``armpit_y`` (the lower)."""
    meas.armpit_pt = {}
    for side, k in meas.armpit_k.items():
        below_t = meas.torso[k - 1]
        box = meas.sec.box(below_t)

        def arm(s1, i=0, side=side, box=box):
            t = largest(s1, i, box, 0.01)
            if t < 0:
                return None
            a = _arm_comp(s1, i, t, s1.box(t), side)
            return None if a < 0 else (s1, t, a)

        ya = _bisect(meas, meas.levels[k - 1], meas.levels[k], lambda s1, i: arm(s1, i))
        got = arm(meas.hs.slice(np.array([ya - 1e-4]))) or arm(meas.sec, k - 1)
        s1, t, a = got
        if side > 0:
            x = 0.5 * (s1.stats[t, XMAX] + s1.stats[a, XMIN])
        else:
            x = 0.5 * (s1.stats[t, XMIN] + s1.stats[a, XMAX])
        z = 0.5 * (s1.stats[t, CZ] + s1.stats[a, CZ])
        meas.armpit_pt[side] = np.array([x, ya, z])
    meas.armpit_y = min(p[1] for p in meas.armpit_pt.values())
