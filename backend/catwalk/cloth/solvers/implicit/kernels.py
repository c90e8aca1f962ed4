"""numba kernels of the implicit solver (:mod:`catwalk.cloth.solvers.implicit.solver`).

One implicit Euler step minimises g(x) = ½(x − y)ᵀM(x − y)/h² + E(x), y = xₙ + h·vₙ, by
iterations of ``x ← x + A⁻¹·r(x)``, r = −∇g the residual force (:func:`residual`: the springs'
forces — the explicit solver's force loop,
:func:`catwalk.cloth.solvers.explicit.kernels.accumulate_forces`, with the velocities (x − xₙ)/h,
so the damping along the springs is implicit too —, gravity, air drag, the quadratic bending −Q·x,
the inertia −M(x − y)/h²); A the constant matrix that
:class:`~catwalk.cloth.solvers.implicit.factor.Factor` holds factored. For a spring this is Liu
et al. 2013's local/global step (the local step's projection at rest length is the force
k·(l − r)·n̂; the global step the solve), written as a preconditioned gradient step so that the
softer compression and the damping along the springs come from the same force loop
(Liu, Bouaziz & Kavan 2017 note the equivalence). Chebyshev semi-iterative acceleration (Wang
2015) over the iterates, then each point with a contact plane is put back on its side of it
(the plane moving with the body), every iteration.

Arrays are (3, n) inside a step (as the explicit kernels'); the factor's solve takes them
directly (:func:`solve_soa`).
"""

from __future__ import annotations

from collections import namedtuple

import numba

from catwalk.cloth.contact_planes import contact_velocity
from catwalk.cloth.solvers.explicit.kernels import accumulate_forces

# the step's inputs, grouped (numba takes tuples of arrays and numbers)
ImplicitModel = namedtuple("ImplicitModel", "mass fixed runs n_runs_lim rest k c compress "
                           "gravity air seam_a seam_b seam_k")
Bending = namedtuple("Bending", "ptr idx val coef")
FactorArrays = namedtuple("FactorArrays", "lp li lx perm chains")
Iteration = namedtuple("Iteration", "iterations rho gamma cheby_start")
Work = namedtuple("Work", "X0 Y V F R D XPREV T W")


@numba.njit(cache=True, error_model="numpy", inline="always")
def _forward(lp, li, lx, j, c, W):
    """L·y = b over the chain of ``c`` (1–3) columns from ``j`` (each column's pattern the
    previous one's without its diagonal): its diagonal block solved, then every row below
    updated once for the whole chain (one pass over those rows of ``W`` instead of ``c``)."""
    p = lp[j]
    d = 1.0 / lx[p]
    a0 = W[3 * j] * d
    a1 = W[3 * j + 1] * d
    a2 = W[3 * j + 2] * d
    W[3 * j] = a0
    W[3 * j + 1] = a1
    W[3 * j + 2] = a2
    b0 = b1 = b2 = c0 = c1 = c2 = 0.0
    q = r = 0
    if c >= 2:
        q = lp[j + 1]
        l10 = lx[p + 1]
        d1 = 1.0 / lx[q]
        b0 = (W[3 * j + 3] - l10 * a0) * d1
        b1 = (W[3 * j + 4] - l10 * a1) * d1
        b2 = (W[3 * j + 5] - l10 * a2) * d1
        W[3 * j + 3] = b0
        W[3 * j + 4] = b1
        W[3 * j + 5] = b2
        q += c - 1
    if c == 3:
        r = lp[j + 2]
        l20 = lx[p + 2]
        l21 = lx[lp[j + 1] + 1]
        d2 = 1.0 / lx[r]
        c0 = (W[3 * j + 6] - l20 * a0 - l21 * b0) * d2
        c1 = (W[3 * j + 7] - l20 * a1 - l21 * b1) * d2
        c2 = (W[3 * j + 8] - l20 * a2 - l21 * b2) * d2
        W[3 * j + 6] = c0
        W[3 * j + 7] = c1
        W[3 * j + 8] = c2
        r += 1
    pe = lp[j + 1]
    p += c
    if c == 1:
        for t in range(p, pe):
            i = 3 * li[t]
            u = lx[t]
            W[i] -= u * a0
            W[i + 1] -= u * a1
            W[i + 2] -= u * a2
    elif c == 2:
        for t in range(pe - p):
            i = 3 * li[p + t]
            u = lx[p + t]
            v = lx[q + t]
            W[i] -= u * a0 + v * b0
            W[i + 1] -= u * a1 + v * b1
            W[i + 2] -= u * a2 + v * b2
    else:
        for t in range(pe - p):
            i = 3 * li[p + t]
            u = lx[p + t]
            v = lx[q + t]
            w = lx[r + t]
            W[i] -= u * a0 + v * b0 + w * c0
            W[i + 1] -= u * a1 + v * b1 + w * c1
            W[i + 2] -= u * a2 + v * b2 + w * c2


@numba.njit(cache=True, error_model="numpy", inline="always")
def _backward(lp, li, lx, j, c, W):
    """Lᵀ·x = y over the chain of ``c`` columns from ``j`` (:func:`_forward`'s): the rows
    below read once for the whole chain, then its diagonal block."""
    p = lp[j]
    pe = lp[j + 1]
    a0 = W[3 * j]
    a1 = W[3 * j + 1]
    a2 = W[3 * j + 2]
    if c == 1:
        for t in range(p + 1, pe):
            i = 3 * li[t]
            u = lx[t]
            a0 -= u * W[i]
            a1 -= u * W[i + 1]
            a2 -= u * W[i + 2]
        d = 1.0 / lx[p]
        W[3 * j] = a0 * d
        W[3 * j + 1] = a1 * d
        W[3 * j + 2] = a2 * d
        return
    q = lp[j + 1]
    b0 = W[3 * j + 3]
    b1 = W[3 * j + 4]
    b2 = W[3 * j + 5]
    c0 = c1 = c2 = 0.0
    r = 0
    if c == 2:
        for t in range(pe - p - 2):
            i = 3 * li[p + 2 + t]
            u = lx[p + 2 + t]
            v = lx[q + 1 + t]
            x0 = W[i]
            x1 = W[i + 1]
            x2 = W[i + 2]
            a0 -= u * x0
            a1 -= u * x1
            a2 -= u * x2
            b0 -= v * x0
            b1 -= v * x1
            b2 -= v * x2
    else:
        r = lp[j + 2]
        c0 = W[3 * j + 6]
        c1 = W[3 * j + 7]
        c2 = W[3 * j + 8]
        for t in range(pe - p - 3):
            i = 3 * li[p + 3 + t]
            u = lx[p + 3 + t]
            v = lx[q + 2 + t]
            w = lx[r + 1 + t]
            x0 = W[i]
            x1 = W[i + 1]
            x2 = W[i + 2]
            a0 -= u * x0
            a1 -= u * x1
            a2 -= u * x2
            b0 -= v * x0
            b1 -= v * x1
            b2 -= v * x2
            c0 -= w * x0
            c1 -= w * x1
            c2 -= w * x2
        d2 = 1.0 / lx[r]
        c0 *= d2
        c1 *= d2
        c2 *= d2
        l21 = lx[q + 1]
        b0 -= l21 * c0
        b1 -= l21 * c1
        b2 -= l21 * c2
        a0 -= lx[p + 2] * c0
        a1 -= lx[p + 2] * c1
        a2 -= lx[p + 2] * c2
        W[3 * j + 6] = c0
        W[3 * j + 7] = c1
        W[3 * j + 8] = c2
    d1 = 1.0 / lx[q]
    b0 *= d1
    b1 *= d1
    b2 *= d1
    l10 = lx[p + 1]
    d = 1.0 / lx[p]
    W[3 * j] = (a0 - l10 * b0) * d
    W[3 * j + 1] = (a1 - l10 * b1) * d
    W[3 * j + 2] = (a2 - l10 * b2) * d
    W[3 * j + 3] = b0
    W[3 * j + 4] = b1
    W[3 * j + 5] = b2


@numba.njit(cache=True, error_model="numpy")
def solve_soa(lp, li, lx, perm, chains, B, X, W):
    """X = A⁻¹·B for the three rows of ``B`` (3, n) at once (X may be B); A = Pᵀ·L·Lᵀ·P,
    L in CSC (``lp``, ``li``, ``lx``, the diagonal first in each column), ``perm[k]`` the
    point of row k of P·A·Pᵀ. ``chains`` (m, 2): L's columns in runs of 1–3 whose patterns
    nest (start, length; :func:`catwalk.cloth.solvers.implicit.factor.column_chains`), each
    run's rows below read once a sweep, as CHOLMOD's simplicial solve does; ``W`` (3n,)
    scratch: the permuted right-hand side, a point's three coordinates side by side."""
    n = perm.shape[0]
    for k in range(n):
        i = perm[k]
        W[3 * k] = B[0, i]
        W[3 * k + 1] = B[1, i]
        W[3 * k + 2] = B[2, i]
    m = chains.shape[0]
    for h in range(m):
        _forward(lp, li, lx, chains[h, 0], chains[h, 1], W)
    for h in range(m - 1, -1, -1):
        _backward(lp, li, lx, chains[h, 0], chains[h, 1], W)
    for k in range(n):
        i = perm[k]
        X[0, i] = W[3 * k]
        X[1, i] = W[3 * k + 1]
        X[2, i] = W[3 * k + 2]


@numba.njit(cache=True, error_model="numpy")
def csr_times(ptr, idx, val, X, out, scale):
    """out[:, i] = scale[i]·Σⱼ val·X[:, j] over row i of the CSR matrix."""
    n = ptr.shape[0] - 1
    for i in range(n):
        s0 = 0.0
        s1 = 0.0
        s2 = 0.0
        for p in range(ptr[i], ptr[i + 1]):
            j = idx[p]
            v = val[p]
            s0 += v * X[0, j]
            s1 += v * X[1, j]
            s2 += v * X[2, j]
        w = scale[i]
        out[0, i] = w * s0
        out[1, i] = w * s1
        out[2, i] = w * s2


@numba.njit(cache=True, error_model="numpy")
def bend_forces(X, bend, T, F):
    """F −= Q·X, Q = Δᵀ·diag(coef)·Δ (the quadratic bending; Δ symmetric, CSR): two sparse
    products through ``T`` (3, n)."""
    ptr, idx, val, coef = bend
    csr_times(ptr, idx, val, X, T, coef)
    n = ptr.shape[0] - 1
    for i in range(n):
        s0 = 0.0
        s1 = 0.0
        s2 = 0.0
        for p in range(ptr[i], ptr[i + 1]):
            j = idx[p]
            v = val[p]
            s0 += v * T[0, j]
            s1 += v * T[1, j]
            s2 += v * T[2, j]
        F[0, i] -= s0
        F[1, i] -= s1
        F[2, i] -= s2


@numba.njit(cache=True, error_model="numpy")
def residual(X, h, model, bend, work):
    """R = f(x, (x − xₙ)/h) − Q·x − M(x − y)/h² (zero at fixed points); returns |R|² summed
    over the free points (N²)."""
    mass, fixed, runs, n_runs_lim, rest, k, c, compress, gravity, air, seam_a, seam_b, \
        seam_k = model
    X0, Y, V, F, R = work[0], work[1], work[2], work[3], work[4]
    T = work[7]
    n = X.shape[1]
    inv_h = 1.0 / h
    for q in range(3):
        for i in range(n):
            V[q, i] = (X[q, i] - X0[q, i]) * inv_h
    accumulate_forces(X, V, mass, runs, n_runs_lim, rest, k, c, compress, gravity, air,
                      seam_a, seam_b, seam_k, F)
    if bend[0].shape[0] > 1:
        bend_forces(X, bend, T, F)
    inv_h2 = inv_h * inv_h
    norm = 0.0
    for q in range(3):
        for i in range(n):
            r = F[q, i] - mass[i] * (X[q, i] - Y[q, i]) * inv_h2
            r = 0.0 if fixed[i] else r
            R[q, i] = r
            norm += r * r
    return norm


@numba.njit(cache=True, error_model="numpy")
def project_planes(X, idx, planes, t, touched):
    """Each point ``idx[k]`` behind its plane ``planes[k]`` (n, c, w, μ: n·x ≥ c + (n·w)·t)
    goes back onto it; ``touched[k]`` set to 1 for those. Returns how many moved."""
    moved = 0
    for k in range(idx.shape[0]):
        i = idx[k]
        nx = planes[k, 0]
        ny = planes[k, 1]
        nz = planes[k, 2]
        d = nx * X[0, i] + ny * X[1, i] + nz * X[2, i] - planes[k, 3] - \
            (nx * planes[k, 4] + ny * planes[k, 5] + nz * planes[k, 6]) * t
        if d < 0.0:
            X[0, i] -= d * nx
            X[1, i] -= d * ny
            X[2, i] -= d * nz
            touched[k] = 1
            moved += 1
    return moved


@numba.njit(cache=True, error_model="numpy")
def iterate(X, h, model, bend, fac, it, work, plane_idx, planes, plane_t, touched, norms,
            lam, kappa, project):
    """The step's iterations from the guess ``X`` (3, n), in place: ``it.iterations`` times
    the residual (:func:`residual`), the solve D = A⁻¹·R, x ← x + D with Chebyshev's weight
    ω (from iteration ``cheby_start`` on, spectral radius estimate ``rho``, under-relaxation
    ``gamma``), then the contact planes: with ``project``, each point behind its plane is put
    back on it and its multiplier ``lam[i]`` (N, the plane's push, added to its residual
    force along the normal) follows Uzawa's update λ ← max(0, λ − κ·d) (d the distance
    before the projection, ``kappa`` N/m) — without the multipliers the solve, which does
    not know the contacts, sees the weight the planes carry as a net force every iteration
    and the projections stretch the cloth round them further each time. ``norms[j]``: |R|²
    at iteration j (the last entry after the last update)."""
    iterations, rho, gamma, cheby_start = it
    lp, li, lx, perm, chains = fac
    D, XPREV, W = work[5], work[6], work[8]
    n = X.shape[1]
    omega = 1.0
    for q in range(3):
        for i in range(n):
            XPREV[q, i] = X[q, i]
    R = work[4]
    for j in range(iterations):
        norms[j] = residual(X, h, model, bend, work)
        if project:
            add_pushes(R, plane_idx, planes, lam)
        solve_soa(lp, li, lx, perm, chains, work[4], D, W)
        if j < cheby_start:
            omega = 1.0
        elif j == cheby_start:
            omega = 2.0 / (2.0 - rho * rho)
        else:
            omega = 4.0 / (4.0 - rho * rho * omega)
        for q in range(3):
            for i in range(n):
                x = X[q, i]
                xn = omega * (gamma * D[q, i] + x - XPREV[q, i]) + XPREV[q, i]
                XPREV[q, i] = x
                X[q, i] = xn
        if project and plane_idx.shape[0]:
            uzawa(X, plane_idx, planes, plane_t, touched, lam, kappa)
    norms[iterations] = residual(X, h, model, bend, work)


@numba.njit(cache=True, error_model="numpy")
def friction(V, idx, planes, touched):
    """The points their plane stopped in the step (``touched``): velocity relative to the
    body without its part into the plane, the sliding slowed by Coulomb friction
    (:func:`catwalk.cloth.contact_planes.contact_velocity`, as the collider's response)."""
    for k in range(idx.shape[0]):
        if touched[k] == 0:
            continue
        i = idx[k]
        V[0, i], V[1, i], V[2, i] = contact_velocity(
            V[0, i], V[1, i], V[2, i], planes[k, 0], planes[k, 1], planes[k, 2],
            planes[k, 4], planes[k, 5], planes[k, 6], planes[k, 7])


@numba.njit(cache=True, error_model="numpy")
def add_pushes(R, idx, planes, lam):
    """R[:, i] += λᵢ·nᵢ for the points with a plane (their contact's push)."""
    for k in range(idx.shape[0]):
        i = idx[k]
        g = lam[i]
        if g != 0.0:
            R[0, i] += g * planes[k, 0]
            R[1, i] += g * planes[k, 1]
            R[2, i] += g * planes[k, 2]


@numba.njit(cache=True, error_model="numpy")
def uzawa(X, idx, planes, t, touched, lam, kappa):
    """The contacts after an update: λᵢ ← max(0, λᵢ − κ·dᵢ) (dᵢ the signed distance to the
    plane, negative behind it), and a point behind its plane back onto it (``touched``)."""
    for k in range(idx.shape[0]):
        i = idx[k]
        nx = planes[k, 0]
        ny = planes[k, 1]
        nz = planes[k, 2]
        d = nx * X[0, i] + ny * X[1, i] + nz * X[2, i] - planes[k, 3] - \
            (nx * planes[k, 4] + ny * planes[k, 5] + nz * planes[k, 6]) * t
        lam[i] = max(0.0, lam[i] - kappa * d)
        if d < 0.0:
            X[0, i] -= d * nx
            X[1, i] -= d * ny
            X[2, i] -= d * nz
            touched[k] = 1
