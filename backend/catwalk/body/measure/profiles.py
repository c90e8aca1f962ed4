"""Searches over a profile (a quantity sampled along levels), so that the levels they find move
smoothly with the shape (the body fitter takes finite differences): an extremum refined by a
parabola (:func:`parabola_vertex`), a soft arg-min (:func:`soft_arg`) and a golden-section
search (:func:`golden_max`)."""

from __future__ import annotations

import numpy as np


def parabola_vertex(y, g, i):
    """Refine an extremum of samples g(y) at interior index i by a parabola through i-1, i, i+1.
    Returns (y*, g*); at an end of the range the sample itself."""
    n = len(g)
    if i <= 0 or i >= n - 1:
        return float(y[i]), float(g[i])
    g0, g1, g2 = g[i - 1], g[i], g[i + 1]
    den = g0 - 2.0 * g1 + g2
    if abs(den) < 1e-15:
        return float(y[i]), float(g1)
    d = 0.5 * (g0 - g2) / den
    d = max(-1.0, min(1.0, d))
    h = y[i + 1] - y[i]
    return float(y[i] + d * h), float(g1 - 0.25 * (g0 - g2) * d)


def soft_arg(y, f, tau, lo, hi, taper=0.015):
    """Soft arg-min of samples f(y) over the window [lo, hi]: the mean level weighted by
    exp(-(f - min f) / tau), the weights tapering to zero over ``taper`` at the window's ends.
    Unlike a hard arg-min it moves continuously as the profile and the window change (two
    near-equal minima average instead of jumping)."""
    wt = np.clip((y - lo) / taper, 0.0, 1.0) * np.clip((hi - y) / taper, 0.0, 1.0)
    inside = wt > 0
    if not inside.any():
        return float(0.5 * (lo + hi))
    w = wt * np.exp(-(f - f[inside].min()) / tau)
    return float(np.sum(w * y) / np.sum(w))


def golden_max(f, a, b, iters=12):
    """Golden-section search for the maximum of f on [a, b]."""
    r = 0.6180339887498949
    c = b - r * (b - a)
    d = a + r * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(iters):
        if fc >= fd:
            b, d, fd = d, c, fc
            c = b - r * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + r * (b - a)
            fd = f(d)
    return 0.5 * (a + b)
