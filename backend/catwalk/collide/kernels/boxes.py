"""Boxes and motion bounds of vertex sets: a box (:func:`bounds`, :func:`bounds_of`), whether a
part moved (:func:`max_displacement`), and the body's motion over a frame (:func:`body_motion`)."""

from __future__ import annotations

import math

import numba


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
