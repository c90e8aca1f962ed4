"""The torso's girths: the torso's loop at any level (:func:`torso_at`), an extremum of its
girth refined on exact sections (:func:`_refine_extremum`), the hips, bust, underbust, bust
points and waist (:func:`girths`) and the neck (:func:`neck`)."""

from __future__ import annotations

import numpy as np

from catwalk.body.measure.measurement import Measurement, fail
from catwalk.body.measure.profiles import golden_max, soft_arg
from catwalk.body.measure.slicing import CX, CZ, N_STATS, PERIM, XMAX, XMIN, ZMAX, ZMIN, largest


def _coarse_box(meas: Measurement, y):
    """The box of the torso's loop in the coarse section nearest level y, or None."""
    k = int(np.clip(np.round((y - meas.ymin) / meas.dy - 0.5), 0, meas.K - 1))
    c = meas.torso[k]
    if c < 0:
        return None
    return meas.sec.box(c)


def torso_at(meas: Measurement, levels):
    """Torso loop at arbitrary levels: (girth, stats rows) per level."""
    levels = np.atleast_1d(np.asarray(levels, dtype=np.float64))
    s1 = meas.hs.slice(levels)
    g = np.full(len(levels), np.nan)
    rows = np.full((len(levels), N_STATS), np.nan)
    for i, h in enumerate(levels):
        box = _coarse_box(meas, h)
        c = largest(s1, i, box, 0.02)
        if c >= 0:
            g[i] = s1.stats[c, PERIM]
            rows[i] = s1.stats[c]
    return g, rows


def _refine_extremum(meas: Measurement, y_c, sign, what: str, half=1.5, n=9, lo=None,
                     hi=None, width=False):
    """Refine a max (sign=+1) or min (sign=-1) of the torso girth (or, with ``width``, of
    its left-right width) near y_c (within [lo, hi] if given): a grid, then a
    golden-section search on the exact section, so the extremum moves continuously with
    the shape. Returns (level, girth there, the loop's stats row). Where no section near
    y_c closes round the torso (the surface is open: a scan of one side), refuses the body
    (``what`` names the girth)."""
    a = y_c - half * meas.dy if lo is None else lo
    b = y_c + half * meas.dy if hi is None else hi
    lv = np.linspace(a, b, n)

    def value(g, rows):
        return rows[:, XMAX] - rows[:, XMIN] if width else g

    g, rows = torso_at(meas, lv)
    g = value(g, rows)
    gg = np.where(np.isnan(g), -np.inf, sign * g)
    # the grid's local maxima; search the best two exactly (two peaks may swap places)
    left = np.concatenate([[-np.inf], gg[:-1]])
    right = np.concatenate([gg[1:], [-np.inf]])
    peaks = np.nonzero((gg >= left) & (gg >= right) & np.isfinite(gg))[0]
    if not len(peaks):
        peaks = np.array([int(np.argmax(gg))])
    peaks = peaks[np.argsort(-gg[peaks])][:2]
    if len(peaks) == 2 and gg[peaks[1]] < gg[peaks[0]] - 0.003:
        peaks = peaks[:1]  # a runner-up 3 mm behind on the grid cannot win

    def f(y):
        v = value(*torso_at(meas, [y]))[0]
        return -np.inf if np.isnan(v) else sign * v

    best_y, best_f = None, -np.inf
    for i in peaks:
        y = golden_max(f, lv[max(i - 1, 0)], lv[min(i + 1, n - 1)])
        fy = f(y)
        if fy > best_f:
            best_y, best_f = y, fy
    if best_y is None:
        raise fail(f"the {what} girth does not close round the body (the surface is open "
                   "there: a partial scan?)")
    g1, r1 = torso_at(meas, [best_y])
    return best_y, float(g1[0]), r1[0]


def _centre(y, row):
    """A loop's landmark: its hull's centroid at level y."""
    return [float(row[CX]), float(y), float(row[CZ])]


def girths(meas: Measurement, sex):
    """The torso's girths between the crotch and the armpits — hips, bust (= chest), and but
    for men the underbust and the bust points' span, waist — and their landmarks; returns
    (girths, landmarks). Sets ``bust_y``."""
    ks = np.arange(meas.crotch_k + 1, min(meas.armpit_k.values()))
    ks = ks[meas.torso[ks] >= 0]
    ys = meas.levels[ks]
    st = meas.sec.stats[meas.torso[ks]]
    g, zmin, zmax = st[:, PERIM], st[:, ZMIN], st[:, ZMAX]
    span = meas.armpit_y - meas.crotch_y
    out = {}
    lm = {}
    # hips: level of greatest buttock prominence (most posterior torso point)
    y_hip = soft_arg(ys, zmin, 0.003, meas.crotch_y, meas.crotch_y + 0.4 * span)
    gh, rh = torso_at(meas, [y_hip])
    out["hips"] = float(gh[0])
    lm["hips"] = _centre(y_hip, rh[0])
    y_bp = _bust_point_level(meas, ys, zmax, span)
    hi = min(y_bp + 0.03, meas.armpit_y - 0.015)
    lo = min(y_bp - 0.03, hi - 0.01)
    y_b, gbust, r1 = _refine_extremum(meas, y_bp, 1.0, "bust", n=13, lo=lo, hi=hi)
    out["bust"] = out["chest"] = gbust
    lm["bust"] = _centre(y_b, r1)
    y_top_waist = y_bp - 0.04
    if sex != "male":
        y_ub, out["underbust"], lm["underbust"] = _underbust(meas, y_bp)
        y_top_waist = min(y_top_waist, y_ub - 0.01)
        lm.update(_bust_points(meas, y_b, r1))
        out["bust_span"] = abs(lm["bust_point_left"][0] - lm["bust_point_right"][0])
    # waist: least torso girth between the hips and the underbust / bust
    m = (ys > y_hip + 0.02) & (ys < y_top_waist)
    idx = np.nonzero(m)[0]
    if not len(idx):
        raise fail("no waist between the hips and the bust")
    i = idx[int(np.argmin(g[idx]))]
    y_w, gw, rw = _refine_extremum(meas, ys[i], -1.0, "waist")
    out["waist"] = gw
    lm["waist"] = _centre(y_w, rw)
    meas.bust_y = y_b
    return out, lm


def _bust_point_level(meas: Measurement, ys, zmax, span):
    """The bust point level: the uppermost peak of front protrusion (``zmax`` along the levels
    ``ys``) below the armpits (the bust points sit at 85-95 % of the way from crotch to
    armpits, ``span``; an obese belly makes a second, lower and often larger peak at 45-67 %;
    no peak above 72 %: 90 %), refined by a soft arg-max around it."""
    top = meas.armpit_y - 0.01
    cand = np.nonzero((ys >= meas.crotch_y + 0.72 * span) & (ys <= top))[0]
    peaks = [i for i in cand if 0 < i < len(ys) - 1
             and zmax[i] >= zmax[i - 1] and zmax[i] >= zmax[i + 1]]
    if peaks:
        y_peak = ys[max(peaks)]
        return soft_arg(ys, -zmax, 0.002, max(y_peak - 0.04, meas.crotch_y + 0.55 * span),
                        min(y_peak + 0.04, top))
    return meas.crotch_y + 0.9 * span


def _underbust(meas: Measurement, y_bp):
    """The underbust: the fold under the breast = least front protrusion just below the bust
    point level ``y_bp``. Returns (its level, girth, landmark)."""
    # the fold's minimum is sharp and the girth steep around it: use a fine profile
    a, b = y_bp - 0.06 * meas.H, y_bp - 0.005
    fy = np.linspace(a, b, max(8, int((b - a) / 0.002) + 1))
    _g, frows = torso_at(meas, fy)
    fz = np.where(np.isnan(frows[:, ZMAX]), np.inf, frows[:, ZMAX])
    y_ub = soft_arg(fy, fz, 0.001, a, b)
    gu, ru = torso_at(meas, [y_ub])
    return y_ub, float(gu[0]), _centre(y_ub, ru[0])


def _bust_points(meas: Measurement, y_b, row):
    """The bust points: on each side, the most forward point of the breast, by a soft
    arg-max (τ = 2 mm) of the surface's forward protrusion within 5 cm of the bust level
    ``y_b`` (the bust loop's stats ``row``; the breast's front is nearly flat across: a plain
    maximum, or one slice's, jumps by centimetres when the surface is remeshed or
    smoothed)."""
    V = meas.V
    lm = {}
    near = (np.abs(V[:, 1] - y_b) < 0.05) & (V[:, 2] > row[CZ])
    for side, name in ((1, "bust_point_left"), (-1, "bust_point_right")):
        dx = side * (V[:, 0] - row[CX])
        P = V[near & (dx > 0.01) & (dx < 0.16)]
        if len(P) < 3:
            raise fail("no bust point found")
        w = np.exp((P[:, 2] - P[:, 2].max()) / 0.002)
        lm[name] = [float(t) for t in (w[:, None] * P).sum(axis=0) / w.sum()]
    return lm


def neck(meas: Measurement):
    """The neck girth: the least torso girth above the armpits (below the head's top 10 %).
    Sets ``neck_y``, ``neck_row``."""
    ks = np.arange(max(meas.armpit_k.values()), meas.top_k + 1)
    ks = ks[(meas.torso[ks] >= 0) & (meas.levels[ks] <= meas.ymax - 0.10 * meas.H)]
    if not len(ks):
        raise fail("no neck found")
    g = meas.sec.stats[meas.torso[ks], PERIM]
    i = int(np.argmin(g))
    y_n, gn, rn = _refine_extremum(meas, meas.levels[ks[i]], -1.0, "neck")
    meas.neck_y = y_n
    meas.neck_row = rn
    return gn
