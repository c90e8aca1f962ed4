"""numba kernels of the cloth solver: forces (eq. 2), semi-implicit Euler (eq. 3), strain limits.

All kernels are single-threaded ``@numba.njit(cache=True)`` loops over flat arrays; the solver
(:mod:`catwalk.cloth.solvers.explicit.solver`) calls :func:`run_steps` once per step (or once for
many steps when no collider needs Python between them). Inside a step, positions and velocities are
(3, n) arrays and the springs are grouped in runs of consecutive points, so that the force loop
vectorises; the ordered pass visits only points near over-long springs. The results are those
of the plain loops to the last bit (see the comment above :func:`spring_runs` and
``tests/cloth/test_kernels.py``).
"""

from __future__ import annotations

from collections import namedtuple

import numba
import numpy as np

from catwalk.cloth.bending import add_bending_forces
from catwalk.cloth.contact_planes import apply_planes
from catwalk.cloth.solvers import STATUS_NONFINITE, STATUS_OK
from catwalk.cloth.springs import _spring_force, from_soa, run_buffers, to_soa
from catwalk.cloth.strain_limit import (
    METHOD_ORDERED,
    METHOD_PROVOT,
    METHOD_VASSILEV,
    _order_buffers,
    limit_ordered_velocity,
    limit_provot_positions,
    limit_unordered_velocity,
    mark_overstretched,
)

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
#: the quadratic bending −Q·x − C·v as pairs in runs (:func:`catwalk.cloth.bending.bending_pairs`,
#: :func:`~catwalk.cloth.bending.pair_damping`; none with the paper's bend springs)
StepBend = namedtuple("StepBend", "runs k c every phase held")


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
    b0, b1, b2 = run_buffers(runs)
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
def _add_held(F, held):
    """F += held, on (3, n) arrays."""
    for q in range(3):
        f = F[q]
        h = held[q]
        for i in range(f.shape[0]):
            f[i] += h[i]


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
def run_steps(x, v, xprev, dt, nsteps, model, seams, limit, order, contact, work, bend,
              out_bad):
    """``nsteps`` steps of forces + semi-implicit Euler + the chosen strain limit.

    The inputs come grouped (named tuples, unpacked here): ``model`` (:data:`StepModel`: the
    masses, the inverse masses for the integration ``w_int`` and the strain limit ``w_lim``,
    the springs ``sa``/``sb``/``rest``/``k``/``c``, the ``n_lim`` limited ones, their ``runs``,
    ``compress``, ``gravity``, ``air``), ``seams`` (:data:`StepSeams`), ``limit``
    (:data:`StepLimit`: the ``method`` and its settings, ``vmax``), ``order``
    (:data:`StepOrder`: the ordered pass's order and the points' adjacency), ``contact``
    (:data:`StepPlanes`: contact planes kept after every step, :func:`apply_planes`;
    ``plane_t``: the time since they were set at the call's start) and ``work``
    (:data:`StepWork`), ``bend`` (:data:`StepBend`: the quadratic bending's pairs, none with
    the paper's bend springs, which are then among the model's springs; evaluated into
    ``held`` at the steps where (``phase`` + step) % ``every`` is 0, and ``held`` added to the
    forces at every step).

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
    bend_runs, bend_k, bend_c, bend_every, bend_phase, held = bend
    to_soa(x, X)
    to_soa(v, V)
    qbuf, dbuf = _order_buffers(order[0], order[1])
    status = STATUS_OK
    moved = False
    for step in range(nsteps):
        accumulate_forces(X, V, mass, runs, n_runs_lim, rest, k, c, compress, gravity, air,
                          seam_a, seam_b, seam_k, F)
        if bend_runs.shape[0]:
            # the slow bending force evaluated every ``bend_every`` steps and held in between
            if (bend_phase + step) % bend_every == 0:
                held[:] = 0.0
                add_bending_forces(X, V, bend_runs, bend_k, bend_c, held)
            _add_held(F, held)
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


