"""The arms and legs: each arm's wrist, elbow, length and upper-arm girth along its own axis
(:func:`arms`), each leg's ankle and knee from the chain of its loops (:func:`legs`)."""

from __future__ import annotations

import numpy as np

from catwalk.body.measure.measurement import Measurement, fail
from catwalk.body.measure.profiles import golden_max, parabola_vertex
from catwalk.body.measure.slicing import CX, CZ, PERIM, Slicer
from catwalk.body.measure.topology import flood, tris_within

#: where the upper-arm girth is looked for: fractions of the way from the acromion to the elbow
UPPER_ARM_RANGE = (0.4, 0.9)


def arms(meas: Measurement):
    """Each arm (the surface below the armpits reachable from its most lateral vertex) along
    its own axis: the wrist (its least girth near the hand), the elbow (48 % of the way from
    the wrist to the acromion), the arm's length (acromion–elbow–wrist) and the upper arm's
    greatest girth. Sets ``wrist``, ``elbow``, ``arm_length``, ``upper_arm`` ({side: …})."""
    V, topo = meas.V, meas.topo
    y_cut = meas.armpit_y - 0.005
    below = V[:, 1] < y_cut
    meas.wrist, meas.elbow, meas.arm_length, meas.upper_arm = {}, {}, {}, {}
    for side in (1, -1):
        ap = meas.armpit_pt[side]
        in_arm = _arm_surface(meas, side, below)
        P = V[np.nonzero(in_arm)[0]]
        tip = P[np.argmax(np.einsum("ij,ij->i", P - ap, P - ap))]
        d, e1, e2 = _arm_axes(P, tip - ap)
        tmask = tris_within(in_arm, topo.faces)
        sl = Slicer(topo, V @ d, V @ e1, V @ e2, tri_mask=tmask).with_bands()
        tw = _wrist_level(sl, float(tip @ d) - meas.H * np.linspace(0.16, 0.06, 26))
        W = _axis_point(sl, tw, d, e1, e2)
        A = meas.acromion[side]
        t_a = float(A @ d)
        t_e = tw - 0.48 * (tw - t_a)
        E = _axis_point(sl, t_e, d, e1, e2)
        if E is None:
            E = A + (t_e - t_a) / max(tw - t_a, 1e-9) * (W - A)
        meas.wrist[side] = W
        meas.elbow[side] = E
        meas.arm_length[side] = float(np.linalg.norm(E - A) + np.linalg.norm(W - E))
        meas.upper_arm[side] = _upper_arm_girth(sl, t_a, float(E @ d))


def _arm_surface(meas: Measurement, side, below):
    """(N,) bool: the arm on ``side``: the surface ``below`` the armpits reachable from its
    most lateral vertex without going above them (it must not reach the feet: then it touches
    the body)."""
    V, topo = meas.V, meas.topo
    ptr, nbr = topo.adjacency()
    used = topo.used
    foot = used[np.argmin(V[used, 1])]
    sx = np.where(below, side * V[:, 0], -np.inf)
    sx[topo.n_orig:] = -np.inf  # seed on the given surface, not on a hole's fan
    seed = int(np.argmax(sx))
    if not np.isfinite(sx[seed]) or side * (V[seed, 0] - meas.crotch_pt[0]) <= 0:
        raise fail("no arm found below the armpit")
    in_arm = flood(seed, below, ptr, nbr)
    if in_arm[foot]:
        raise fail("an arm touches the body below the armpit")
    return in_arm


def _arm_axes(P, out):
    """The arm's axis d (the principal direction of its vertices ``P``, pointing ``out``
    towards the hand) and two directions across it (e1, e2)."""
    c = P.mean(axis=0)
    _, _, vt = np.linalg.svd(P - c, full_matrices=False)
    d = vt[0]
    if d @ out < 0:
        d = -d
    e1 = np.array([d[1], -d[0], 0.0])  # d x z
    if e1 @ e1 < 1e-12:
        e1 = np.array([0.0, d[2], -d[1]])  # d x x
    e1 /= np.sqrt(e1 @ e1)
    e2 = np.array([d[1] * e1[2] - d[2] * e1[1], d[2] * e1[0] - d[0] * e1[2],
                   d[0] * e1[1] - d[1] * e1[0]])
    return d, e1, e2


def _neg_girth(sl, t):
    """Minus the greatest girth of the arm's slicer ``sl`` at t (−∞: no section)."""
    s2 = sl.slice(np.array([t]))
    cs = s2.comps(0)
    return -float(s2.stats[cs, PERIM].max()) if len(cs) else -np.inf


def _wrist_level(sl, lv):
    """The wrist along the arm's axis: its least girth over the levels ``lv`` (towards the
    hand), refined by golden-section search."""
    s1 = sl.slice(lv)
    gw = np.full(len(lv), np.inf)
    for i in range(len(lv)):
        cs = s1.comps(i)
        if len(cs):
            gw[i] = s1.stats[cs, PERIM].max()
    i = int(np.argmin(gw))
    if not np.isfinite(gw[i]):
        raise fail("no wrist found")
    return golden_max(lambda t: _neg_girth(sl, t), lv[max(i - 1, 0)],
                      lv[min(i + 1, len(lv) - 1)])


def _upper_arm_girth(sl, t_a, t_e):
    """The upper-arm girth: the greatest girth across the arm between 40 % and 90 % of the
    way from the acromion (at ``t_a`` along the axis) to the elbow (``t_e``; above that,
    sections run into the cut under the armpit and come out short)."""
    lu = t_a + (t_e - t_a) * np.linspace(UPPER_ARM_RANGE[0], UPPER_ARM_RANGE[1], 12)
    s3 = sl.slice(lu)
    gu = np.array([s3.stats[s3.comps(i), PERIM].max() if len(s3.comps(i)) else -np.inf
                   for i in range(len(lu))])
    i = int(np.argmax(gu))
    if not np.isfinite(gu[i]):
        raise fail("no upper arm found")
    tu = golden_max(lambda t: -_neg_girth(sl, t), lu[max(i - 1, 0)],
                    lu[min(i + 1, len(lu) - 1)])
    return max(-_neg_girth(sl, tu), float(gu[i]))


def _axis_point(sl, t, d, e1, e2):
    """The centre of the largest loop at t along the arm's axis d, in the world (None: no
    section there)."""
    s1 = sl.slice(np.array([t]))
    cs = s1.comps(0)
    if not len(cs):
        return None
    c = cs[int(np.argmax(s1.stats[cs, PERIM]))]
    u, w = s1.stats[c, CX], s1.stats[c, CZ]
    return t * d + u * e1 + w * e2


def legs(meas: Measurement):
    """Each leg's ankle (above its least girth near the floor, at the malleolus height at
    most) and knee (53 % of the way from the ankle up to the crotch), along the chain of its
    loops down from the crotch. Sets ``ankle``, ``knee`` ({side: point})."""
    sec = meas.sec
    k = meas.crotch_k
    # the two leg loops just below the crotch
    above = meas.torso[k + 1]
    box = sec.box(above)
    cand = [c for c in sec.comps(k) if sec.inside(c, box, 0.01)]
    cand.sort(key=lambda c: -sec.stats[c, PERIM])
    a, b = cand[0], cand[1]
    if sec.stats[a, CX] < sec.stats[b, CX]:
        a, b = b, a
    meas.knee, meas.ankle = {}, {}
    for side, c0 in ((1, a), (-1, b)):
        chain = _leg_chain(sec, k, c0)
        ks = np.nonzero(chain >= 0)[0]
        ys = meas.levels[ks]
        st = sec.stats[chain[ks]]
        m = (ys >= meas.ymin + 0.03 * meas.H) & (ys <= meas.ymin + 0.15 * meas.H)
        idx = np.nonzero(m)[0]
        if not len(idx):
            raise fail("no ankle found")
        i = idx[int(np.argmin(st[idx, PERIM]))]
        # least ankle girth, above the malleoli
        y_g, _ = parabola_vertex(ys, -st[:, PERIM], i)
        ax = float(np.interp(y_g, ys, st[:, CX]))
        az = float(np.interp(y_g, ys, st[:, CZ]))
        y_a = min(y_g, meas.ymin + 0.042 * meas.H)  # the ankle joint (malleolus height)
        meas.ankle[side] = np.array([ax, y_a, az])
        y_k = y_g + 0.53 * (meas.crotch_y - y_g)
        meas.knee[side] = np.array([float(np.interp(y_k, ys, st[:, CX])), y_k,
                                    float(np.interp(y_k, ys, st[:, CZ]))])


def _leg_chain(sec, k, c0):
    """A leg's loop per coarse level from the crotch's (k, loop ``c0``) down: at each level
    the loop nearest the one above among those under it, while there is one (−1 below)."""
    chain = np.full(k + 1, -1)
    chain[k] = c0
    for kk in range(k - 1, -1, -1):
        prev = chain[kk + 1]
        px, pz = sec.stats[prev, CX], sec.stats[prev, CZ]
        best, bd = -1, np.inf
        for c in sec.comps(kk):
            if sec.stats[c, PERIM] < 0.05 or not sec.inside(c, sec.box(prev), 0.02):
                continue
            dd = (sec.stats[c, CX] - px) ** 2 + (sec.stats[c, CZ] - pz) ** 2
            if dd < bd:
                best, bd = c, dd
        if best < 0:
            break
        chain[kk] = best
    return chain
