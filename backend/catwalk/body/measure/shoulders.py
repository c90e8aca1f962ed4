"""The shoulders: the acromions and the side neck points from the upper contour of sections
across the shoulder (:func:`shoulders`), and the shoulder width across the back
(:func:`shoulder_width`)."""

from __future__ import annotations

import numpy as np

from catwalk.body.measure.measurement import Measurement, fail
from catwalk.body.measure.profiles import soft_arg
from catwalk.body.measure.slicing import CZ, XMAX, XMIN, Slicer, tri_range


def shoulders(meas: Measurement):
    """The acromions and the side neck points, on each side from the upper contour of the
    sections across the shoulder (planes x = const. from the neck outwards, over the band
    from just below the armpits to the neck). Sets ``acromion``, ``side_neck`` ({side:
    point})."""
    V, topo = meas.V, meas.topo
    y_lo = meas.armpit_y - 0.06 * meas.H
    y_hi = meas.neck_y
    tlo, thi = tri_range(V[:, 1], topo.faces)
    band = (tlo >= y_lo) & (thi <= y_hi)
    vb = (V[:, 1] >= y_lo) & (V[:, 1] <= y_hi)
    xs_band = V[vb, 0]
    vs = Slicer(topo, V[:, 0], V[:, 1], V[:, 2], tri_mask=band).with_bands()
    meas.acromion = {}
    meas.side_neck = {}
    for side in (1, -1):
        xn = meas.neck_row[XMAX] if side > 0 else meas.neck_row[XMIN]
        xd, yt, zt = _upper_contour(meas, vs, xs_band, xn, side)
        da = _acromion_offset(abs(meas.armpit_pt[side][0] - xn), xd, yt)
        ya = float(np.interp(da, xd, yt))
        za = float(np.interp(da, xd, zt))
        meas.acromion[side] = np.array([xn + side * da, ya, za])
        dd = _side_neck_offset(xd, yt, da)
        meas.side_neck[side] = np.array([xn + side * dd, float(np.interp(dd, xd, yt)),
                                         float(np.interp(dd, xd, zt))])


def _upper_contour(meas: Measurement, vs, xs_band, xn, side):
    """The shoulder's upper contour on ``side``, from the neck's edge ``xn`` outwards (64
    sections of the band's slicer ``vs``, as far as the band's vertices ``xs_band`` reach, at
    most 13 % of the height), up to the first section with none: (distance from the neck,
    the section's top y, the z of the hull centre of the loop holding it) per section."""
    xfar = xs_band.max() if side > 0 else xs_band.min()
    reach = min(0.13 * meas.H, abs(xfar - xn) - 0.002)
    if reach <= 0.02:
        raise fail("no shoulder found")
    xl = xn + side * np.linspace(0.002, reach, 64)
    order = np.argsort(xl)
    lv = xl[order]
    s1 = vs.slice(lv)
    ytop = np.full(len(lv), np.nan)
    ztop = np.full(len(lv), np.nan)
    b = np.searchsorted(s1.comp_level, np.arange(len(lv) + 1))
    pb = np.searchsorted(s1.pcomp, b) if len(s1.pcomp) else b
    for i in range(len(lv)):
        if pb[i + 1] > pb[i]:
            seg = slice(pb[i], pb[i + 1])
            j = pb[i] + int(np.argmax(s1.X[seg]))
            # y: the top of the section; z: the hull centre of the loop holding it
            # (continuous in the shape, unlike the z of the single highest point)
            ytop[i] = s1.X[j]
            ztop[i] = s1.stats[s1.pcomp[j], CZ]
    inv = np.empty_like(order)
    inv[order] = np.arange(len(order))
    ytop, ztop = ytop[inv], ztop[inv]  # ordered from the neck outwards
    ok = ~np.isnan(ytop)
    n_ok = int(np.argmin(ok)) if not ok.all() else len(ok)
    if n_ok < 8:
        raise fail("no shoulder contour found")
    return np.abs(xl[:n_ok] - xn), ytop[:n_ok], ztop[:n_ok]


def _acromion_offset(xa, xd, yt):
    """The acromion's distance from the neck along the contour (``xd``, ``yt``): the convex
    corner of the upper contour (farthest above the chord), on the stretch from 5 cm inside to
    10 cm outside the armpit (at ``xa``; a bulky trapezius makes the whole contour a dome, so
    the neck is kept out of the chord)."""
    x0 = float(np.clip(xa - 0.05, xd[0], xd[-1] - 0.02))
    x1 = float(np.clip(xa + 0.10, x0 + 0.02, xd[-1]))
    p0 = np.array([x0, np.interp(x0, xd, yt)])
    p1 = np.array([x1, np.interp(x1, xd, yt)])
    chord = (p1 - p0) / np.linalg.norm(p1 - p0)

    def above(x, y):
        return chord[0] * (y - p0[1]) - chord[1] * (x - p0[0])

    # soft arg-max over the outline samples (a rounded shoulder has a broad corner;
    # averaging keeps scan noise from throwing it about)
    return soft_arg(xd, -above(xd, yt), 0.003, x0, x1, taper=0.01)


def _side_neck_offset(xd, yt, da):
    """The side neck point's distance from the neck along the contour: going out from the
    neck, where the outline's descent first flattens below 45 degrees (the neck's wall meets
    the shoulder slope), before the acromion (at ``da``)."""
    dd = xd[0]
    ia = int(np.searchsorted(xd, da))
    st = 3  # slopes over ~1 cm, so that scan noise does not fake a flat spot
    if ia > st:
        slope = -(yt[st: ia + 1] - yt[: ia + 1 - st]) / (xd[st: ia + 1] - xd[: ia + 1 - st])
        xm = 0.5 * (xd[st: ia + 1] + xd[: ia + 1 - st])
        below = np.nonzero(slope < 1.0)[0]
        if len(below):
            j = int(below[0])
            if j == 0:
                dd = xm[0]
            else:  # interpolate the crossing of slope = 1
                t = (slope[j - 1] - 1.0) / (slope[j - 1] - slope[j])
                dd = float(xm[j - 1] + t * (xm[j] - xm[j - 1]))
    return dd


def shoulder_width(meas: Measurement):
    """Tape length across the back from acromion to acromion, in the plane through both
    acromions that contains the front-back (z) direction."""
    A_l, A_r = meas.acromion[1], meas.acromion[-1]
    eu = A_l - A_r
    eu /= np.linalg.norm(eu)
    n = np.cross(eu, [0.0, 0.0, 1.0])
    n /= np.linalg.norm(n)
    if n[1] < 0:
        n = -n
    ew = np.cross(n, eu)  # in-plane, ~ +z or -z
    if ew[2] < 0:
        ew = -ew
    V = meas.V
    mask = tri_range(V[:, 1], meas.topo.faces)[0] >= meas.armpit_y
    sl = Slicer(meas.topo, V @ n, V @ eu, V @ ew, tri_mask=mask)
    s0 = float(A_l @ n)
    s1 = sl.slice(np.array([s0]))
    ul, ur = float(A_l @ eu), float(A_r @ eu)
    keep = (s1.X > ur) & (s1.X < ul)
    u = np.concatenate([[ur], s1.X[keep], [ul]])
    w = np.concatenate([[float(A_r @ ew)], s1.Z[keep], [float(A_l @ ew)]])
    return _lower_chain_length(u, w)


def _lower_chain_length(u, w):
    """Length of the lower convex hull (smallest w) of the points, from min u to max u."""
    order = np.lexsort((w, u))
    pu, pw = u[order], w[order]
    hu, hw = [], []
    for a, b in zip(pu.tolist(), pw.tolist(), strict=True):
        while len(hu) >= 2 and ((hu[-1] - hu[-2]) * (b - hw[-2])
                                - (hw[-1] - hw[-2]) * (a - hu[-2])) <= 0.0:
            hu.pop()
            hw.pop()
        hu.append(a)
        hw.append(b)
    return float(np.sum(np.hypot(np.diff(hu), np.diff(hw))))
