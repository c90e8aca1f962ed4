"""The spring law every cloth solver shares: a spring's force and energy under stretch and
under compression (softened below rest by the fabric's ``compression`` share over a band of
``SOFT_BAND``), the strain of the stretch and shear springs, and the springs grouped in runs of
consecutive points (the layout the force loops vectorise over)."""

from __future__ import annotations

import numba
import numpy as np

#: compressive strain over which stretch/shear stiffness blends from k down to compress·k
SOFT_BAND = 0.01


@numba.njit(cache=True, error_model="numpy", inline="always")
def _compressed(e, rest, compress):
    """Spring force / k at a compression e < 0: the stiffness falls linearly from k to
    compress·k over a band of SOFT_BAND·rest (smooth, so the explicit scheme keeps its energy),
    then stays at compress·k."""
    d = SOFT_BAND * rest
    if e > -d:
        return e + (1.0 - compress) * e * e / (2.0 * d)
    return compress * e - (1.0 - compress) * 0.5 * d


@numba.njit(cache=True, error_model="numpy", inline="always")
def _compressed_energy(e, rest, compress):
    d = SOFT_BAND * rest
    if e > -d:
        return 0.5 * e * e + (1.0 - compress) * e * e * e / (6.0 * d)
    e0 = -d
    w0 = 0.5 * e0 * e0 + (1.0 - compress) * e0 * e0 * e0 / (6.0 * d)
    return w0 + 0.5 * compress * (e * e - e0 * e0) - (1.0 - compress) * 0.5 * d * (e - e0)


#: longest run (springs) a force call handles at once; longer runs are split (small buffers)
RUN_CHUNK = 256


def spring_runs(sa: np.ndarray, sb: np.ndarray, chunk: int = RUN_CHUNK) -> np.ndarray:
    """Runs of springs, in storage order: (R, 4) int64 rows ``(s0, a0, b0, L)`` meaning that
    springs ``s0 … s0+L−1`` join points ``a0+t`` and ``b0+t``; at most ``chunk`` long."""
    sa = np.asarray(sa, dtype=np.int64)
    sb = np.asarray(sb, dtype=np.int64)
    if len(sa) == 0:
        return np.zeros((0, 4), dtype=np.int64)
    brk = np.ones(len(sa), dtype=bool)
    brk[1:] = (sa[1:] != sa[:-1] + 1) | (sb[1:] != sb[:-1] + 1)
    starts = np.flatnonzero(brk)
    lens = np.diff(np.append(starts, len(sa)))
    rows = [(s0 + o, sa[s0 + o], sb[s0 + o], min(chunk, n - o))
            for s0, n in zip(starts.tolist(), lens.tolist(), strict=True)
            for o in range(0, n, chunk)]
    return np.array(rows, dtype=np.int64).reshape(-1, 4)


def model_runs(sa: np.ndarray, sb: np.ndarray, n_lim: int) -> tuple[np.ndarray, int]:
    """The run table of a model's springs (stretch/shear runs first, then bend; a run never
    crosses ``n_lim``) and the number of stretch/shear runs."""
    lim = spring_runs(sa[:n_lim], sb[:n_lim])
    bend = spring_runs(sa[n_lim:], sb[n_lim:])
    bend[:, 0] += n_lim
    return np.ascontiguousarray(np.vstack([lim, bend])), len(lim)


@numba.njit(cache=True, error_model="numpy", inline="always")
def run_buffers(runs):
    """Three scratch arrays as long as the longest run of ``runs`` (a run's three force
    components, computed before they are scattered)."""
    maxl = 1
    for q in range(runs.shape[0]):
        maxl = max(maxl, runs[q, 3])
    return np.empty(maxl), np.empty(maxl), np.empty(maxl)


@numba.njit(cache=True, error_model="numpy")
def to_soa(x, X):
    """X[q, i] = x[i, q]."""
    for i in range(x.shape[0]):
        X[0, i] = x[i, 0]
        X[1, i] = x[i, 1]
        X[2, i] = x[i, 2]


@numba.njit(cache=True, error_model="numpy")
def from_soa(X, x):
    """x[i, q] = X[q, i]."""
    for i in range(x.shape[0]):
        x[i, 0] = X[0, i]
        x[i, 1] = X[1, i]
        x[i, 2] = X[2, i]


@numba.njit(cache=True, error_model="numpy")
def _spring_force(dx, dy, dz, dvx, dvy, dvz, r, kk, cc, comp, compress):
    """Force on the a end of a spring from a to b (dx = x_b − x_a, dv = v_b − v_a): eq. 2 plus
    damping along the spring; ``comp``: a stretch/shear spring (softer under compression)."""
    ll = np.sqrt(dx * dx + dy * dy + dz * dz)
    inv = 1.0 / max(ll, 1e-12)
    dx *= inv
    dy *= inv
    dz *= inv
    rv = dvx * dx + dvy * dy + dvz * dz
    e = ll - r
    # _compressed(e, r, compress), written out so that it vectorises
    d = SOFT_BAND * r
    ec = e + (1.0 - compress) * e * e / (2.0 * d) if e > -d else \
        compress * e - (1.0 - compress) * 0.5 * d
    ee = ec if (comp and e < 0.0) else e
    fs = kk * ee + cc * rv
    fs = 0.0 if ll < 1e-12 else fs  # (a NaN stays NaN: it must be detected)
    return fs * dx, fs * dy, fs * dz


@numba.njit(cache=True, error_model="numpy")
def max_strain(x, sa, sb, rest, n_lim):
    """max over stretch/shear springs of |x_b − x_a| / rest − 1."""
    worst = -1.0
    for s in range(n_lim):
        a = sa[s]
        b = sb[s]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        e = np.sqrt(dx * dx + dy * dy + dz * dz) / rest[s] - 1.0
        if e > worst:
            worst = e
    return worst


@numba.njit(cache=True, error_model="numpy")
def spring_energy(x, sa, sb, rest, k, n_lim, compress):
    """Elastic energy of the springs (compressed stretch/shear springs at ``compress`` × k)."""
    e = 0.0
    for s in range(sa.shape[0]):
        a = sa[s]
        b = sb[s]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        d = np.sqrt(dx * dx + dy * dy + dz * dz) - rest[s]
        if d < 0.0 and s < n_lim:
            e += k[s] * _compressed_energy(d, rest[s], compress)
        else:
            e += 0.5 * k[s] * d * d
    return e
