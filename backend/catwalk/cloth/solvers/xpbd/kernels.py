"""XPBD (Macklin et al. 2016, "XPBD: position-based simulation of compliant constrained
dynamics"), the alternative integrator of the explicit solver (``Solver(integrator="xpbd")``):
the springs as compliant distance constraints, Gauss–Seidel sweeps a step."""

from __future__ import annotations

from collections import namedtuple

import numba
import numpy as np

from catwalk.cloth.solvers import STATUS_EXPLODED, STATUS_NONFINITE, STATUS_OK

# run_steps_xpbd's inputs, grouped (passed as plain tuples: numba types a named tuple a few µs
# slower a call)
XpbdWork = namedtuple("XpbdWork", "p lam")
XpbdModel = namedtuple("XpbdModel", "mass w_int w_lim sa sb rest k c n_lim compress gravity air")
XpbdSeams = namedtuple("XpbdSeams", "seam_a seam_b seam_k seam_c lam_seam")
XpbdSteps = namedtuple("XpbdSteps", "dt nsteps iterations limit tau vmax")


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
def run_steps_xpbd(x, v, xprev, work, model, seams, steps, out_bad):
    """``nsteps`` steps of XPBD (Macklin, Müller & Chentanez 2016, "XPBD: position-based
    simulation of compliant constrained dynamics"), the alternative integrator.

    The inputs come grouped (tuples in the fields' order, unpacked here): ``work``
    (:data:`XpbdWork`: the predicted positions, the springs' multipliers), ``model``
    (:data:`XpbdModel`: masses, inverse masses for the integration and the limit, the
    springs, ``compress``, ``gravity``, ``air``), ``seams`` (:data:`XpbdSeams`) and ``steps``
    (:data:`XpbdSteps`: ``dt``, ``nsteps``, ``iterations``, ``limit``, ``tau``, ``vmax``).

    Per step: v += dt·(g − air·v) for free points; p = x + dt·v; ``iterations`` Gauss–Seidel
    sweeps (storage order) over the springs as compliant distance constraints (compliance
    1/k, ``compress``·k for a compressed stretch/shear spring, Rayleigh damping along the
    spring with the spring's c: Macklin et al.'s eq. 26), the seam pairs as zero-length
    constraints (compliance 1/``seam_k``), and, with ``limit``, every stretch/shear spring as a
    hard inequality constraint length ≤ (1+τ)·rest (pinned and held points immovable, ``w_lim``);
    then v = (p − x)/dt, x = p. Returns a status as :func:`run_steps` does.
    """
    p, lam = work
    mass, w_int, w_lim, sa, sb, rest, k, c, n_lim, compress, gravity, air = model
    seam_a, seam_b, seam_k, seam_c, lam_seam = seams
    dt, nsteps, iterations, limit, tau, vmax = steps
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
