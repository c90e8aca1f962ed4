"""numba kernels of the cloth solver: forces (eq. 2), semi-implicit Euler (eq. 3), strain limits.

All kernels are single-threaded ``@numba.njit(cache=True)`` loops over flat arrays; the solver
(:mod:`catwalk.cloth.solver`) calls :func:`run_steps` once per step (or once for many steps when
no collider needs Python between them). Inside a step, positions and velocities are (3, n)
arrays and the springs are grouped in runs of consecutive points, so that the force loop
vectorises; the ordered pass visits only points near over-long springs. The results are those
of the plain loops to the last bit (see the comment above :func:`spring_runs` and
``tests/cloth/test_kernels.py``).
"""

from __future__ import annotations

from collections import namedtuple

import numba
import numpy as np

METHOD_NONE, METHOD_ORDERED, METHOD_VASSILEV, METHOD_PROVOT = 0, 1, 2, 3

STATUS_OK, STATUS_NONFINITE, STATUS_EXPLODED = 0, 1, 2


#: compressive strain over which stretch/shear stiffness blends from k down to compress·k
SOFT_BAND = 0.01



# The velocity strain limits correct at most this much closing speed per spring and step (m/s):
# a spring that starts far beyond its limit (panels placed on the body, a point pushed out by
# the collider, a seam pulling) is brought back over a few steps instead of in one, which would
# throw its points at (excess / dt) — tens of m/s. At rest the excess is far below this cap.
MAX_CORRECTION_SPEED = 2.0

# A seam spring pulls as if its gap were at most this long (m): partners placed far apart
# (a trouser inseam, a sleeve cap) approach at a bounded speed instead of being flung together.
SEAM_REACH = 0.01

# run_steps' inputs, grouped (numba takes named tuples of arrays and numbers)
StepModel = namedtuple("StepModel", "mass w_int w_lim sa sb rest k c n_lim runs n_runs_lim "
                       "compress gravity air")
StepSeams = namedtuple("StepSeams", "seam_a seam_b seam_k seam_c")
StepLimit = namedtuple("StepLimit", "method tau sweeps react share passes provot_iterations "
                       "vmax")
StepOrder = namedtuple("StepOrder", "ord_pts ord_ptr ord_oth ord_cross ord_lim ord_lim2 "
                       "pt_cross adj_ptr adj_other")
StepPlanes = namedtuple("StepPlanes", "plane_idx planes plane_t")
StepWork = namedtuple("StepWork", "X V XP XPREV F R dirty")


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


# The step works on structure-of-arrays copies of positions and velocities (``X``, ``V``: (3, n),
# one row per axis) so that the loops over springs and points vectorise; :func:`run_steps` copies
# the caller's (n, 3) arrays in and out once per call.
#
# Springs are processed in *runs* (:func:`spring_runs`): storage-order springs ``s0 … s0+L−1``
# that join points ``a0+t`` and ``b0+t`` (t < L). On Provot's grid a row of stretch, shear or
# bend springs is one run, so every load is contiguous; an irregular outline spring is a run of
# length 1. Runs keep the springs' storage order and each point receives its spring forces in
# that order, with no fused multiply-add and no reassociation, so that the results are the same
# to the last bit as those of the plain loop over springs (the tests compare them).

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
def accumulate_forces(X, V, mass, runs, n_runs_lim, rest, k, c, compress, gravity, air, seam_a,
                      seam_b, seam_k, F):
    """F = Σ springs (eq. 2 + damping along the spring) + seams' springs + m·g − air·m·v, on
    (3, n) arrays (the seams' damping is taken implicitly: :func:`damp_seams`).

    ``runs``: the springs in runs (:func:`spring_runs`); the first ``n_runs_lim`` runs are the
    stretch/shear springs, which push back ``compress`` times as hard as they pull: woven and
    knitted fabrics buckle under almost no in-plane compression."""
    n = X.shape[1]
    x0 = X[0]
    x1 = X[1]
    x2 = X[2]
    v0 = V[0]
    v1 = V[1]
    v2 = V[2]
    f0 = F[0]
    f1 = F[1]
    f2 = F[2]
    g0 = gravity[0]
    g1 = gravity[1]
    g2 = gravity[2]
    for i in range(n):
        m = mass[i]
        f0[i] = m * (g0 - air * v0[i])
        f1[i] = m * (g1 - air * v1[i])
        f2[i] = m * (g2 - air * v2[i])
    maxl = 1
    for q in range(runs.shape[0]):
        maxl = max(maxl, runs[q, 3])
    b0 = np.empty(maxl)
    b1 = np.empty(maxl)
    b2 = np.empty(maxl)
    for q in range(runs.shape[0]):
        # max(…, 0): tells the compiler that the indices are not negative (no wrap-around), so
        # that the loops below vectorise
        s0 = max(runs[q, 0], 0)
        a0 = max(runs[q, 1], 0)
        c0 = max(runs[q, 2], 0)
        nl = runs[q, 3]
        comp = q < n_runs_lim
        if nl == 1:  # an irregular (outline) spring: no loop set-up
            fx, fy, fz = _spring_force(x0[c0] - x0[a0], x1[c0] - x1[a0], x2[c0] - x2[a0],
                                       v0[c0] - v0[a0], v1[c0] - v1[a0], v2[c0] - v2[a0],
                                       rest[s0], k[s0], c[s0], comp, compress)
            f0[a0] += fx
            f1[a0] += fy
            f2[a0] += fz
            f0[c0] -= fx
            f1[c0] -= fy
            f2[c0] -= fz
            continue
        for t in range(nl):
            a = a0 + t
            b = c0 + t
            s = s0 + t
            b0[t], b1[t], b2[t] = _spring_force(
                x0[b] - x0[a], x1[b] - x1[a], x2[b] - x2[a], v0[b] - v0[a], v1[b] - v1[a],
                v2[b] - v2[a], rest[s], k[s], c[s], comp, compress)
        # scatter, one array at a time (vectorises: the a0+t are distinct within a run). A point
        # that is the b end of spring t' and the a end of spring t of this run (a0+t = c0+t')
        # gets them in storage order: b first when c0 > a0 (then t' < t), else a first. (x − y
        # and x + (−1·y) are the same number.)
        if c0 > a0:
            p0, p1, g = c0, a0, -1.0
        else:
            p0, p1, g = a0, c0, 1.0
        for t in range(nl):
            f0[p0 + t] += g * b0[t]
        for t in range(nl):
            f1[p0 + t] += g * b1[t]
        for t in range(nl):
            f2[p0 + t] += g * b2[t]
        for t in range(nl):
            f0[p1 + t] -= g * b0[t]
        for t in range(nl):
            f1[p1 + t] -= g * b1[t]
        for t in range(nl):
            f2[p1 + t] -= g * b2[t]
    for s in range(seam_a.shape[0]):
        a = seam_a[s]
        b = seam_b[s]
        gx = X[0, b] - X[0, a]
        gy = X[1, b] - X[1, a]
        gz = X[2, b] - X[2, a]
        gl = np.sqrt(gx * gx + gy * gy + gz * gz)
        ks = seam_k if gl <= SEAM_REACH else seam_k * SEAM_REACH / gl
        fx = ks * gx
        fy = ks * gy
        fz = ks * gz
        F[0, a] += fx
        F[1, a] += fy
        F[2, a] += fz
        F[0, b] -= fx
        F[1, b] -= fy
        F[2, b] -= fz


@numba.njit(cache=True, error_model="numpy")
def damp_seams(V, seam_a, seam_b, w_int, seam_c, dt):
    """The seams' damping (force ``seam_c``·(v_b − v_a) on a), backward Euler pair by pair:
    the pair's relative velocity becomes v_rel / (1 + dt·c·(w_a + w_b)), momentum kept. Taken
    explicitly, this damping (critical for the seam springs) would bound the sewing step
    below the fabric's own stable step."""
    for s in range(seam_a.shape[0]):
        a = seam_a[s]
        b = seam_b[s]
        wa = w_int[a]
        wb = w_int[b]
        g = dt * seam_c / (1.0 + dt * seam_c * (wa + wb))
        jx = g * (V[0, b] - V[0, a])
        jy = g * (V[1, b] - V[1, a])
        jz = g * (V[2, b] - V[2, a])
        V[0, a] += wa * jx
        V[1, a] += wa * jy
        V[2, a] += wa * jz
        V[0, b] -= wb * jx
        V[1, b] -= wb * jy
        V[2, b] -= wb * jz


@numba.njit(cache=True, error_model="numpy")
def integrate_velocities(V, F, w_int, dt, vmax):
    """v += dt·f/m for free points (eq. 3); returns (status, index of the first bad point)."""
    n = V.shape[1]
    v0 = V[0]
    v1 = V[1]
    v2 = V[2]
    f0 = F[0]
    f1 = F[1]
    f2 = F[2]
    v2max = vmax * vmax
    nbad = 0
    for i in range(n):
        wi = w_int[i]
        c = dt * wi
        vx = v0[i] + c * f0[i]
        vy = v1[i] + c * f1[i]
        vz = v2[i] + c * f2[i]
        s = vx * vx + vy * vy + vz * vz
        free = wi != 0.0
        nbad += free & (not (s <= v2max))  # catches NaN as well
        v0[i] = vx if free else v0[i]
        v1[i] = vy if free else v1[i]
        v2[i] = vz if free else v2[i]
    if nbad == 0:
        return 0, -1
    for i in range(n):
        if w_int[i] != 0.0:
            s = v0[i] * v0[i] + v1[i] * v1[i] + v2[i] * v2[i]
            if not (s <= v2max):
                return (1 if s != s else 2), i
    return 0, -1


@numba.njit(cache=True, error_model="numpy")
def predict(X, V, dt, XP):
    """XP = X + dt·V."""
    for q in range(3):
        x = X[q]
        v = V[q]
        xp = XP[q]
        for i in range(x.shape[0]):
            xp[i] = x[i] + dt * v[i]


@numba.njit(cache=True, error_model="numpy")
def mark_overstretched(XP, runs, n_runs_lim, rest, tau, dirty):
    """dirty[p] = 1 for both ends of every stretch/shear spring whose predicted length exceeds
    (1+τ)·rest (with a margin of 1e-9, so that no spring the exact test in the ordered pass
    would correct is missed), 0 for all other points."""
    dirty[:] = 0
    x0 = XP[0]
    x1 = XP[1]
    x2 = XP[2]
    c = (1.0 + tau) * (1.0 + tau) * (1.0 - 1e-9)
    maxl = 1
    for q in range(n_runs_lim):
        maxl = max(maxl, runs[q, 3])
    over = np.empty(maxl, dtype=np.uint8)
    for q in range(n_runs_lim):
        s0 = max(runs[q, 0], 0)
        a0 = max(runs[q, 1], 0)
        c0 = max(runs[q, 2], 0)
        nl = runs[q, 3]
        if nl == 1:
            dx = x0[c0] - x0[a0]
            dy = x1[c0] - x1[a0]
            dz = x2[c0] - x2[a0]
            r = rest[s0]
            if dx * dx + dy * dy + dz * dz > c * r * r:
                dirty[a0] = 1
                dirty[c0] = 1
            continue
        for t in range(nl):
            a = a0 + t
            b = c0 + t
            dx = x0[b] - x0[a]
            dy = x1[b] - x1[a]
            dz = x2[b] - x2[a]
            r = rest[s0 + t]
            over[t] = dx * dx + dy * dy + dz * dz > c * r * r
        for t in range(nl):
            dirty[a0 + t] |= over[t]
        for t in range(nl):
            dirty[c0 + t] |= over[t]


@numba.njit(cache=True, error_model="numpy", inline="always")
def _mark_neighbours(p, adj_ptr, adj_other, dirty):
    for j in range(adj_ptr[p], adj_ptr[p + 1]):
        dirty[adj_other[j]] = 1


@numba.njit(cache=True, error_model="numpy")
def limit_ordered_velocity(XP, V, w_lim, dt, ord_pts, ord_ptr, ord_oth, ord_cross, ord_lim,
                           ord_lim2, pt_cross, sweeps, react, R, share, dirty, adj_ptr, adj_other,
                           qbuf, dbuf):
    """The paper's pass: points in order from the high-tension centres outward; each point's
    velocity is changed along its springs to already-processed points (which are not moved
    again in this pass), so that none of those springs ends the step longer than (1+τ)·rest.

    ``XP`` holds the predicted positions x + dt·v (:func:`predict`) and is kept up to date. A
    point with several such springs takes the mean of their corrections, up to ``sweeps`` times
    (a point whose parents disagree — where the fronts from two centres meet — settles on a
    compromise instead of being thrown back and forth); with ``share``, what is still left over
    is then shared with the parents by inverse mass. The opposite impulse, × ``react``, goes to
    each parent's velocity *after* the position update (accumulated in ``R``), as Müller et al.
    2012 do for follow-the-leader, so that momentum is kept over steps while this step's
    positions satisfy the limit. ``ord_lim`` is (1+τ)·rest of each entry's spring and
    ``ord_lim2`` a bound a little below its square (a squared length up to it is surely within
    the limit); ``pt_cross`` marks the points with a spring across a cluster boundary
    (``ord_cross``).

    Only points marked in ``dirty`` are visited (:func:`mark_overstretched` marks the ends of
    the springs over the limit; a point that moves here marks its neighbours): any other point
    has no spring over the limit to a processed point and would be left as it is, so the result
    is that of visiting every point.
    """
    inv_dt = 1.0 / dt
    cap = MAX_CORRECTION_SPEED * dt
    xp0 = XP[0]
    xp1 = XP[1]
    xp2 = XP[2]
    v0 = V[0]
    v1 = V[1]
    v2 = V[2]
    for k in range(ord_pts.shape[0]):
        p = ord_pts[k]
        if dirty[p] == 0:
            continue
        wp = w_lim[p]
        if wp == 0.0:
            continue
        j0 = ord_ptr[k]
        j1 = ord_ptr[k + 1]
        if j0 == j1:
            continue
        moved = False
        for _sw in range(sweeps):
            cnt = 0
            nr = 0
            sx = 0.0
            sy = 0.0
            sz = 0.0
            for j in range(j0, j1):
                if ord_cross[j]:
                    continue
                q = ord_oth[j]
                dx = xp0[p] - xp0[q]
                dy = xp1[p] - xp1[q]
                dz = xp2[p] - xp2[q]
                l2 = dx * dx + dy * dy + dz * dz
                if l2 <= ord_lim2[j]:  # surely within the limit: no square root needed
                    continue
                ll = np.sqrt(l2)
                lim = ord_lim[j]
                if ll <= lim:
                    continue
                g = min(ll - lim, cap) / ll
                sx += g * dx
                sy += g * dy
                sz += g * dz
                cnt += 1
                if react > 0.0 and w_lim[q] > 0.0:
                    qbuf[nr] = q
                    dbuf[nr, 0] = g * dx
                    dbuf[nr, 1] = g * dy
                    dbuf[nr, 2] = g * dz
                    nr += 1
            if cnt == 0:
                break
            moved = True
            inv = 1.0 / cnt
            xp0[p] -= sx * inv
            xp1[p] -= sy * inv
            xp2[p] -= sz * inv
            v0[p] -= sx * inv * inv_dt
            v1[p] -= sy * inv * inv_dt
            v2[p] -= sz * inv * inv_dt
            for t in range(nr):
                q = qbuf[t]
                gq = react * inv * inv_dt * w_lim[q] / wp
                R[0, q] += gq * dbuf[t, 0]
                R[1, q] += gq * dbuf[t, 1]
                R[2, q] += gq * dbuf[t, 2]
        if share or pt_cross[k]:
            for j in range(j0, j1):
                if not (share or ord_cross[j]):
                    continue
                q = ord_oth[j]
                wq = w_lim[q]
                dx = xp0[p] - xp0[q]
                dy = xp1[p] - xp1[q]
                dz = xp2[p] - xp2[q]
                ll = np.sqrt(dx * dx + dy * dy + dz * dz)
                lim = ord_lim[j]
                if ll <= lim:
                    continue
                moved = True
                g = min(ll - lim, cap) / (ll * (wp + wq))
                gp = wp * g
                gq = wq * g
                xp0[p] -= gp * dx
                xp1[p] -= gp * dy
                xp2[p] -= gp * dz
                v0[p] -= gp * dx * inv_dt
                v1[p] -= gp * dy * inv_dt
                v2[p] -= gp * dz * inv_dt
                xp0[q] += gq * dx
                xp1[q] += gq * dy
                xp2[q] += gq * dz
                v0[q] += gq * dx * inv_dt
                v1[q] += gq * dy * inv_dt
                v2[q] += gq * dz * inv_dt
                _mark_neighbours(q, adj_ptr, adj_other, dirty)
        if moved:
            _mark_neighbours(p, adj_ptr, adj_other, dirty)


@numba.njit(cache=True, error_model="numpy")
def limit_unordered_velocity(X, V, w_lim, sa, sb, rest, n_lim, tau, dt):
    """Vassilev et al. 2001: for each stretch/shear spring in storage order, change the end points'
    velocities along the spring so that its length after the step is at most (1+τ)·rest; the
    change is shared by inverse mass (pinned and held points take none)."""
    inv_dt = 1.0 / dt
    for s in range(n_lim):
        a = sa[s]
        b = sb[s]
        wa = w_lim[a]
        wb = w_lim[b]
        wsum = wa + wb
        if wsum == 0.0:
            continue
        dx = (X[0, b] + dt * V[0, b]) - (X[0, a] + dt * V[0, a])
        dy = (X[1, b] + dt * V[1, b]) - (X[1, a] + dt * V[1, a])
        dz = (X[2, b] + dt * V[2, b]) - (X[2, a] + dt * V[2, a])
        ll = np.sqrt(dx * dx + dy * dy + dz * dz)
        lim = (1.0 + tau) * rest[s]
        if ll <= lim:
            continue
        g = min(ll - lim, MAX_CORRECTION_SPEED * dt) * inv_dt / (ll * wsum)
        V[0, a] += wa * g * dx
        V[1, a] += wa * g * dy
        V[2, a] += wa * g * dz
        V[0, b] -= wb * g * dx
        V[1, b] -= wb * g * dy
        V[2, b] -= wb * g * dz


@numba.njit(cache=True, error_model="numpy")
def limit_provot_positions(X, V, w_lim, sa, sb, rest, n_lim, tau, dt, iterations):
    """Provot 1995: after the position update, move the end points of every over-long
    stretch/shear spring towards each other (shared by inverse mass), in storage order, repeated
    ``iterations`` times; the velocities take the same change / dt so that they stay consistent
    with the positions (semi-implicit Euler needs it to stay stable).

    After the first round a spring is measured again only if an end moved since it was last
    measured (``moved``: when each point last moved, counted in spring visits): any other is
    as long as it was then, within its limit, and would be left as it is — the result is that
    of measuring every spring every round."""
    inv_dt = 1.0 / dt
    moved = np.zeros(X.shape[1], dtype=np.int64)
    for it in range(iterations):
        changed = False
        for s in range(n_lim):
            a = sa[s]
            b = sb[s]
            # this spring's visit in the previous round (negative in the first: measure)
            last = (it - 1) * n_lim + s
            if moved[a] <= last and moved[b] <= last:
                continue
            wa = w_lim[a]
            wb = w_lim[b]
            wsum = wa + wb
            if wsum == 0.0:
                continue
            dx = X[0, b] - X[0, a]
            dy = X[1, b] - X[1, a]
            dz = X[2, b] - X[2, a]
            ll = np.sqrt(dx * dx + dy * dy + dz * dz)
            lim = (1.0 + tau) * rest[s]
            if ll <= lim:
                continue
            changed = True
            g = (ll - lim) / (ll * wsum)
            ga = wa * g
            gb = wb * g
            X[0, a] += ga * dx
            X[1, a] += ga * dy
            X[2, a] += ga * dz
            X[0, b] -= gb * dx
            X[1, b] -= gb * dy
            X[2, b] -= gb * dz
            V[0, a] += ga * dx * inv_dt
            V[1, a] += ga * dy * inv_dt
            V[2, a] += ga * dz * inv_dt
            V[0, b] -= gb * dx * inv_dt
            V[1, b] -= gb * dy * inv_dt
            V[2, b] -= gb * dz * inv_dt
            # moved after this visit (the spring itself is measured again next round)
            moved[a] = it * n_lim + s + 1
            moved[b] = it * n_lim + s + 1
        if not changed:
            break


@numba.njit(cache=True, error_model="numpy")
def advance_positions(X, V, R, dt, use_r, XPREV):
    """XPREV = X; X += dt·V; then, with ``use_r``, V += R (the ordered pass's reactions)."""
    for q in range(3):
        x = X[q]
        v = V[q]
        r = R[q]
        xprev = XPREV[q]
        if use_r:
            for i in range(x.shape[0]):
                xprev[i] = x[i]
                x[i] += dt * v[i]
                v[i] += r[i]
        else:
            for i in range(x.shape[0]):
                xprev[i] = x[i]
                x[i] += dt * v[i]


@numba.njit(cache=True, inline="always")
def contact_velocity(vx, vy, vz, nx, ny, nz, wx, wy, wz, friction):
    """A point's velocity v after it meets a surface of unit normal n moving at w: if it moves
    into the surface (relative to it), that normal part goes and, by Coulomb friction, μ times
    as much of its sliding speed (stopping at zero). Shared by the collider's response
    (:func:`catwalk.collide.kernels.respond`) and the contact planes (:func:`apply_planes`)."""
    rx = vx - wx
    ry = vy - wy
    rz = vz - wz
    vn = rx * nx + ry * ny + rz * nz
    if vn >= 0.0:
        return vx, vy, vz
    rx -= vn * nx
    ry -= vn * ny
    rz -= vn * nz
    tl = np.sqrt(rx * rx + ry * ry + rz * rz)
    dv = -friction * vn
    f = 1.0 - dv / tl if tl > dv else 0.0
    return wx + f * rx, wy + f * ry, wz + f * rz


@numba.njit(cache=True, error_model="numpy")
def apply_planes(X, V, idx, planes, t):
    """Contact planes between two collision responses: point ``idx[k]`` stays on the side
    n·x ≥ c + (n·w)·t of its plane ``planes[k]`` = (n, c, w, μ) (w: the body's velocity
    there, ``t``: the time since the plane was set, μ: friction). A point behind it goes back
    onto it; its velocity relative to the body loses its part into the plane and, by Coulomb
    friction, μ times that much of its sliding speed (as the collider's response does).
    Cheap (no search), it stops cloth held by the body sinking in step after step between two
    responses of the collider, whose next push would come back as a jolt."""
    for k in range(idx.shape[0]):
        i = idx[k]
        nx = planes[k, 0]
        ny = planes[k, 1]
        nz = planes[k, 2]
        wx = planes[k, 4]
        wy = planes[k, 5]
        wz = planes[k, 6]
        d = nx * X[0, i] + ny * X[1, i] + nz * X[2, i] - planes[k, 3] - \
            (nx * wx + ny * wy + nz * wz) * t
        if d < 0.0:
            X[0, i] -= d * nx
            X[1, i] -= d * ny
            X[2, i] -= d * nz
            V[0, i], V[1, i], V[2, i] = contact_velocity(V[0, i], V[1, i], V[2, i], nx, ny,
                                                         nz, wx, wy, wz, planes[k, 7])


@numba.njit(cache=True, error_model="numpy")
def planes_set(planes, idx, rows):
    """The points with a contact plane (a unit normal in ``planes[i, :3]``; a zero normal:
    none): their indices into ``idx`` and their planes into ``rows`` (both at least (P,)
    long), in point order; returns how many (what :func:`apply_planes` takes)."""
    m = 0
    for i in range(planes.shape[0]):
        if planes[i, 0] * planes[i, 0] + planes[i, 1] * planes[i, 1] + \
                planes[i, 2] * planes[i, 2] > 0.5:
            idx[m] = i
            for c in range(planes.shape[1]):
                rows[m, c] = planes[i, c]
            m += 1
    return m


@numba.njit(cache=True, error_model="numpy")
def cap_speed(v, vmax):
    """No point faster than ``vmax``: a faster one's velocity (``v`` (P, 3)) is scaled down
    to that speed, in place; returns how many were."""
    n = 0
    v2max = vmax * vmax
    for i in range(v.shape[0]):
        s2 = v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2]
        if s2 > v2max:
            f = vmax / np.sqrt(s2)
            v[i, 0] *= f
            v[i, 1] *= f
            v[i, 2] *= f
            n += 1
    return n


@numba.njit(cache=True, error_model="numpy")
def _first_nonfinite(X):
    """Index of the first point with a non-finite coordinate, or −1."""
    n = X.shape[1]
    bad = 0
    for q in range(3):
        x = X[q]
        for i in range(n):
            bad += not np.isfinite(x[i])
    if bad == 0:
        return -1
    for i in range(n):
        if not (np.isfinite(X[0, i]) and np.isfinite(X[1, i]) and np.isfinite(X[2, i])):
            return i
    return -1


@numba.njit(cache=True, error_model="numpy")
def _order_buffers(ord_pts, ord_ptr):
    """Scratch for the ordered pass: room for the most springs any point has to earlier
    points."""
    maxp = 1
    for o in range(ord_pts.shape[0]):
        maxp = max(maxp, ord_ptr[o + 1] - ord_ptr[o])
    return np.empty(maxp, dtype=np.int64), np.empty((maxp, 3))


@numba.njit(cache=True, error_model="numpy")
def limit_and_advance(X, V, dt, t_planes, model, limit, order, contact, work, qbuf, dbuf):
    """The end of a step, once its velocities ``V`` are known: the strain limit on them
    (``ordered``: the paper's pass, ``passes`` times; ``vassilev``), x += dt·v (the ordered
    pass's reactions then added to the velocities), the contact planes (``t_planes``: the
    time since they were set), then ``provot``'s position correction. The groups are
    :func:`run_steps`'s; ``qbuf``/``dbuf`` from :func:`_order_buffers`."""
    (mass, w_int, w_lim, sa, sb, rest, k, c, n_lim, runs, n_runs_lim, compress, gravity,
     air) = model
    method, tau, sweeps, react, share, passes, provot_iterations, vmax = limit
    ord_pts, ord_ptr, ord_oth, ord_cross, ord_lim, ord_lim2, pt_cross, adj_ptr, adj_other = order
    plane_idx, planes, _ = contact
    _, _, XP, XPREV, _, R, dirty = work
    if method == METHOD_ORDERED:
        if react > 0.0:
            R[:, :] = 0.0
        for _pass in range(passes):
            predict(X, V, dt, XP)
            mark_overstretched(XP, runs, n_runs_lim, rest, tau, dirty)
            limit_ordered_velocity(XP, V, w_lim, dt, ord_pts, ord_ptr, ord_oth, ord_cross,
                                   ord_lim, ord_lim2, pt_cross, sweeps, react, R, share,
                                   dirty, adj_ptr, adj_other, qbuf, dbuf)
    elif method == METHOD_VASSILEV:
        limit_unordered_velocity(X, V, w_lim, sa, sb, rest, n_lim, tau, dt)
    advance_positions(X, V, R, dt, method == METHOD_ORDERED and react > 0.0, XPREV)
    if plane_idx.shape[0]:
        apply_planes(X, V, plane_idx, planes, t_planes)
    if method == METHOD_PROVOT:
        limit_provot_positions(X, V, w_lim, sa, sb, rest, n_lim, tau, dt, provot_iterations)


@numba.njit(cache=True, error_model="numpy")
def clamp_step(x, v, xprev, dt, model, limit, order, contact, work):
    """The end of :func:`run_steps`'s step (:func:`limit_and_advance`) applied to a step
    another integrator took from ``xprev`` to ``x``: its velocities (given in ``v``) limited,
    the positions taken again from ``xprev``, the planes kept (``contact``'s time: since they
    were set, this step included). ``x``, ``v``, ``xprev`` (n, 3) are changed in place."""
    X, V = work[0], work[1]
    to_soa(xprev, X)
    to_soa(v, V)
    qbuf, dbuf = _order_buffers(order[0], order[1])
    limit_and_advance(X, V, dt, contact[2], model, limit, order, contact, work, qbuf, dbuf)
    from_soa(X, x)
    from_soa(V, v)
    from_soa(work[3], xprev)


@numba.njit(cache=True, error_model="numpy")
def run_steps(x, v, xprev, dt, nsteps, model, seams, limit, order, contact, work, out_bad):
    """``nsteps`` steps of forces + semi-implicit Euler + the chosen strain limit.

    The inputs come grouped (named tuples, unpacked here): ``model`` (:data:`StepModel`: the
    masses, the inverse masses for the integration ``w_int`` and the strain limit ``w_lim``,
    the springs ``sa``/``sb``/``rest``/``k``/``c``, the ``n_lim`` limited ones, their ``runs``,
    ``compress``, ``gravity``, ``air``), ``seams`` (:data:`StepSeams`), ``limit``
    (:data:`StepLimit`: the ``method`` and its settings, ``vmax``), ``order``
    (:data:`StepOrder`: the ordered pass's order and the points' adjacency), ``contact``
    (:data:`StepPlanes`: contact planes kept after every step, :func:`apply_planes`;
    ``plane_t``: the time since they were set at the call's start) and ``work``
    (:data:`StepWork`).

    ``x``, ``v``, ``xprev`` are the caller's (n, 3) arrays, copied into the (3, n) work arrays
    ``X``, ``V``, ``XPREV`` and back; ``XP``, ``F``, ``R``, ``dirty`` are scratch. Returns a
    status (0 ok, 1 non-finite, 2 a speed above ``vmax``) and writes the step and the point
    where it happened to ``out_bad``; on a bad status it stops before moving positions.
    """
    (mass, w_int, w_lim, sa, sb, rest, k, c, n_lim, runs, n_runs_lim, compress, gravity,
     air) = model
    seam_a, seam_b, seam_k, seam_c = seams
    vmax = limit[7]
    plane_t = contact[2]
    X, V, XP, XPREV, F, R, dirty = work
    to_soa(x, X)
    to_soa(v, V)
    qbuf, dbuf = _order_buffers(order[0], order[1])
    status = STATUS_OK
    moved = False
    for step in range(nsteps):
        accumulate_forces(X, V, mass, runs, n_runs_lim, rest, k, c, compress, gravity, air,
                          seam_a, seam_b, seam_k, F)
        st, bad = integrate_velocities(V, F, w_int, dt, vmax)
        if st != 0:
            out_bad[0] = step
            out_bad[1] = bad
            status = st
            break
        damp_seams(V, seam_a, seam_b, w_int, seam_c, dt)
        limit_and_advance(X, V, dt, plane_t + (step + 1) * dt, model, limit, order, contact,
                          work, qbuf, dbuf)
        moved = True
    if status == STATUS_OK:
        i = _first_nonfinite(X)
        if i >= 0:
            out_bad[0] = nsteps - 1
            out_bad[1] = i
            status = STATUS_NONFINITE
    from_soa(X, x)
    from_soa(V, v)
    if moved:
        from_soa(XPREV, xprev)
    return status


@numba.njit(cache=True, error_model="numpy", inline="always")
def _dist(p, a, b):
    dx = p[b, 0] - p[a, 0]
    dy = p[b, 1] - p[a, 1]
    dz = p[b, 2] - p[a, 2]
    return np.sqrt(dx * dx + dy * dy + dz * dz)


@numba.njit(cache=True, error_model="numpy", inline="always")
def _xpbd_distance(p, x, a, b, wa, wb, rest, at, gam, lam):
    """One XPBD projection of the compliant distance constraint |p_b − p_a| = ``rest``
    (compliance/dt² ``at``, damping ``gam``, multiplier so far ``lam``): moves p_a and p_b,
    returns the multiplier's change (0 when both ends are immovable or coincide)."""
    if wa + wb == 0.0:
        return 0.0
    dx = p[b, 0] - p[a, 0]
    dy = p[b, 1] - p[a, 1]
    dz = p[b, 2] - p[a, 2]
    ll = np.sqrt(dx * dx + dy * dy + dz * dz)
    if ll < 1e-12:
        return 0.0
    inv = 1.0 / ll
    dx *= inv
    dy *= inv
    dz *= inv
    # ∇C·(p − x): the constraint's lengthening speed × dt
    dl = ((p[b, 0] - x[b, 0]) - (p[a, 0] - x[a, 0])) * dx + \
        ((p[b, 1] - x[b, 1]) - (p[a, 1] - x[a, 1])) * dy + \
        ((p[b, 2] - x[b, 2]) - (p[a, 2] - x[a, 2])) * dz
    dlam = (-(ll - rest) - at * lam - gam * dl) / ((1.0 + gam) * (wa + wb) + at)
    p[a, 0] -= wa * dlam * dx
    p[a, 1] -= wa * dlam * dy
    p[a, 2] -= wa * dlam * dz
    p[b, 0] += wb * dlam * dx
    p[b, 1] += wb * dlam * dy
    p[b, 2] += wb * dlam * dz
    return dlam


@numba.njit(cache=True, error_model="numpy")
def run_steps_xpbd(x, v, xprev, p, lam, mass, w_int, w_lim, sa, sb, rest, k, c, n_lim, compress,
                   gravity, air, seam_a, seam_b, seam_k, seam_c, lam_seam, dt, nsteps,
                   iterations, limit, tau, vmax, out_bad):
    """``nsteps`` steps of XPBD (Macklin, Müller & Chentanez 2016, "XPBD: position-based
    simulation of compliant constrained dynamics"), the alternative integrator.

    Per step: v += dt·(g − air·v) for free points; p = x + dt·v; ``iterations`` Gauss–Seidel
    sweeps (storage order) over the springs as compliant distance constraints (compliance
    1/k, ``compress``·k for a compressed stretch/shear spring, Rayleigh damping along the
    spring with the spring's c: Macklin et al.'s eq. 26), the seam pairs as zero-length
    constraints (compliance 1/``seam_k``), and, with ``limit``, every stretch/shear spring as a
    hard inequality constraint length ≤ (1+τ)·rest (pinned and held points immovable, ``w_lim``);
    then v = (p − x)/dt, x = p. Returns a status as :func:`run_steps` does.
    """
    n = x.shape[0]
    v2max = vmax * vmax
    inv_dt = 1.0 / dt
    status = STATUS_OK
    for step in range(nsteps):
        for i in range(n):
            if w_int[i] != 0.0:
                for q in range(3):
                    v[i, q] += dt * (gravity[q] - air * v[i, q])
            s2 = v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2]
            if w_int[i] != 0.0 and not (s2 <= v2max) and status == STATUS_OK:
                status = STATUS_NONFINITE if s2 != s2 else STATUS_EXPLODED
                out_bad[0] = step
                out_bad[1] = i
            for q in range(3):
                p[i, q] = x[i, q] + dt * v[i, q]
        if status != STATUS_OK:
            break
        lam[:] = 0.0
        lam_seam[:] = 0.0
        for _it in range(iterations):
            for s in range(sa.shape[0]):
                a = sa[s]
                b = sb[s]
                ll = _dist(p, a, b)
                kk = k[s]
                if ll < rest[s] and s < n_lim:
                    kk *= compress
                ikd = 1.0 / (kk * dt)
                # compliance / dt², and α̃·β̃/dt with β̃ = dt²·c
                lam[s] += _xpbd_distance(p, x, a, b, w_int[a], w_int[b], rest[s],
                                         ikd * inv_dt, c[s] * ikd, lam[s])
            at_seam = 1.0 / (seam_k * dt * dt)
            gam_seam = seam_c / (seam_k * dt)
            for s in range(seam_a.shape[0]):
                a = seam_a[s]
                b = seam_b[s]
                lam_seam[s] += _xpbd_distance(p, x, a, b, w_int[a], w_int[b], 0.0, at_seam,
                                              gam_seam, lam_seam[s])
            if limit:
                for s in range(n_lim):
                    a = sa[s]
                    b = sb[s]
                    wa = w_lim[a]
                    wb = w_lim[b]
                    wsum = wa + wb
                    if wsum == 0.0:
                        continue
                    dx = p[b, 0] - p[a, 0]
                    dy = p[b, 1] - p[a, 1]
                    dz = p[b, 2] - p[a, 2]
                    ll = np.sqrt(dx * dx + dy * dy + dz * dz)
                    lim = (1.0 + tau) * rest[s]
                    if ll <= lim:
                        continue
                    g = (ll - lim) / (ll * wsum)
                    p[a, 0] += wa * g * dx
                    p[a, 1] += wa * g * dy
                    p[a, 2] += wa * g * dz
                    p[b, 0] -= wb * g * dx
                    p[b, 1] -= wb * g * dy
                    p[b, 2] -= wb * g * dz
        for i in range(n):
            if w_int[i] != 0.0:
                for q in range(3):
                    v[i, q] = (p[i, q] - x[i, q]) * inv_dt
            s2 = v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2]
            if w_int[i] != 0.0 and not (s2 <= v2max) and status == STATUS_OK:
                status = STATUS_NONFINITE if s2 != s2 else STATUS_EXPLODED
                out_bad[0] = step
                out_bad[1] = i
        if status != STATUS_OK:
            break
        for i in range(n):
            for q in range(3):
                xprev[i, q] = x[i, q]
                x[i, q] = p[i, q]
    if status == STATUS_OK:
        for i in range(n):
            for q in range(3):
                if not np.isfinite(x[i, q]):
                    out_bad[0] = nsteps - 1
                    out_bad[1] = i
                    return STATUS_NONFINITE
    return status


@numba.njit(cache=True, error_model="numpy")
def tension_order(n, adj_ptr, adj_spring, adj_other, centre, x):
    """Breadth-first order over the stretch/shear spring graph from the centres.

    Returns ``(ord_pts, ord_ptr, ord_spr, ord_oth, level, cross)``: every point in processing
    order (centres first), and for the k-th point the springs (``ord_spr[ord_ptr[k]:ord_ptr[k+1]]``)
    linking it to points that come before it, with those points (``ord_oth``); ``level`` is each
    point's breadth-first distance from the centres. Centres joined by springs form one cluster
    and every point belongs to the cluster it was reached from; ``cross`` marks springs to an
    earlier point of another cluster (where two fronts meet), which the pass corrects
    symmetrically. A connected piece with no centre is seeded at its point nearest its
    centroid.
    """
    rank = np.full(n, -1, dtype=np.int64)
    level = np.zeros(n, dtype=np.int64)
    queue = np.empty(n, dtype=np.int32)
    cluster = np.full(n, -1, dtype=np.int64)
    tail = 0
    ncl = 0
    for i in range(n):
        if centre[i] and cluster[i] < 0:
            # a cluster: centres joined by springs (the points held by one body part, ...)
            cluster[i] = ncl
            rank[i] = tail
            queue[tail] = i
            tail += 1
            h2 = tail - 1
            while h2 < tail:
                p = queue[h2]
                h2 += 1
                for j in range(adj_ptr[p], adj_ptr[p + 1]):
                    q = adj_other[j]
                    if centre[q] and cluster[q] < 0:
                        cluster[q] = ncl
                        rank[q] = tail
                        queue[tail] = q
                        tail += 1
            ncl += 1
    head = 0
    comp = np.empty(n, dtype=np.int32)
    seen = np.zeros(n, dtype=np.uint8)
    next_free = 0
    while True:
        while head < tail:
            p = queue[head]
            head += 1
            for j in range(adj_ptr[p], adj_ptr[p + 1]):
                q = adj_other[j]
                if rank[q] < 0:
                    rank[q] = tail
                    level[q] = level[p] + 1
                    cluster[q] = cluster[p]
                    queue[tail] = q
                    tail += 1
        if tail >= n:
            break
        while rank[next_free] >= 0:
            next_free += 1
        # collect the unreached piece containing next_free, seed it at its middle
        nc = 1
        comp[0] = next_free
        seen[next_free] = 1
        r = 0
        cx = 0.0
        cy = 0.0
        cz = 0.0
        while r < nc:
            p = comp[r]
            r += 1
            cx += x[p, 0]
            cy += x[p, 1]
            cz += x[p, 2]
            for j in range(adj_ptr[p], adj_ptr[p + 1]):
                q = adj_other[j]
                if rank[q] < 0 and seen[q] == 0:
                    seen[q] = 1
                    comp[nc] = q
                    nc += 1
        cx /= nc
        cy /= nc
        cz /= nc
        best = comp[0]
        bd = 1e300
        for r in range(nc):
            p = comp[r]
            d = (x[p, 0] - cx) ** 2 + (x[p, 1] - cy) ** 2 + (x[p, 2] - cz) ** 2
            if d < bd:
                bd = d
                best = p
        rank[best] = tail
        queue[tail] = best
        cluster[best] = ncl
        ncl += 1
        tail += 1
    ptr = np.zeros(n + 1, dtype=np.int32)
    for k in range(n):
        p = queue[k]
        cnt = 0
        for j in range(adj_ptr[p], adj_ptr[p + 1]):
            q = adj_other[j]
            if rank[q] < k:
                cnt += 1
        ptr[k + 1] = ptr[k] + cnt
    spr = np.empty(ptr[n], dtype=np.int32)
    oth = np.empty(ptr[n], dtype=np.int32)
    cross = np.zeros(ptr[n], dtype=np.uint8)
    for k in range(n):
        p = queue[k]
        o = ptr[k]
        for j in range(adj_ptr[p], adj_ptr[p + 1]):
            q = adj_other[j]
            if rank[q] < k:
                spr[o] = adj_spring[j]
                oth[o] = q
                cross[o] = cluster[q] != cluster[p] and not centre[q]
                o += 1
    return queue, ptr, spr, oth, level, cross


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


@numba.njit(cache=True, error_model="numpy")
def shadow_area(x, z, tris, lo_x, lo_z, pixel, nx, nz):
    """Area covered by the triangles' projection on the XZ plane, by rasterising them on an
    ``nx`` × ``nz`` grid of square pixels (side ``pixel``) from (lo_x, lo_z); pixel centres."""
    cover = np.zeros((nz, nx), dtype=np.uint8)
    for t in range(tris.shape[0]):
        a = tris[t, 0]
        b = tris[t, 1]
        c = tris[t, 2]
        ax = (x[a] - lo_x) / pixel
        az = (z[a] - lo_z) / pixel
        bx = (x[b] - lo_x) / pixel
        bz = (z[b] - lo_z) / pixel
        cx = (x[c] - lo_x) / pixel
        cz = (z[c] - lo_z) / pixel
        area = (bx - ax) * (cz - az) - (bz - az) * (cx - ax)
        if area == 0.0:
            continue
        i0 = max(int(np.floor(min(ax, bx, cx))), 0)
        i1 = min(int(np.ceil(max(ax, bx, cx))), nx - 1)
        j0 = max(int(np.floor(min(az, bz, cz))), 0)
        j1 = min(int(np.ceil(max(az, bz, cz))), nz - 1)
        for j in range(j0, j1 + 1):
            pz = j + 0.5
            for i in range(i0, i1 + 1):
                px = i + 0.5
                w0 = (bx - px) * (cz - pz) - (bz - pz) * (cx - px)
                w1 = (cx - px) * (az - pz) - (cz - pz) * (ax - px)
                w2 = (ax - px) * (bz - pz) - (az - pz) * (bx - px)
                if area > 0:
                    if w0 >= 0 and w1 >= 0 and w2 >= 0:
                        cover[j, i] = 1
                elif w0 <= 0 and w1 <= 0 and w2 <= 0:
                    cover[j, i] = 1
    total = 0
    for j in range(nz):
        for i in range(nx):
            total += cover[j, i]
    return total * pixel * pixel
