"""numba kernels of the implicit solver (:mod:`catwalk.cloth.solvers.implicit.solver`).

One implicit Euler step minimises g(x) = ½(x − y)ᵀM(x − y)/h² + E(x), y = xₙ + h·vₙ, by
iterations of ``x ← x + A⁻¹·r(x)``, r = −∇g the residual force (:func:`residual`: the springs'
forces — the explicit solver's force loop,
:func:`catwalk.cloth.solvers.explicit.kernels.accumulate_forces`, with the velocities (x − xₙ)/h,
so the damping along the springs is implicit too —, gravity, air drag, the quadratic bending −Q·x,
the inertia −M(x − y)/h²); A the constant matrix that
:class:`~catwalk.cloth.solvers.implicit.cholesky.Factor` holds factored. For a spring this is Liu
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
FactorArrays = namedtuple("FactorArrays", "lp li lx perm")
Iteration = namedtuple("Iteration", "iterations rho gamma cheby_start")
Work = namedtuple("Work", "X0 Y V F R D XPREV T W3")


@numba.njit(cache=True, error_model="numpy")
def solve_soa(lp, li, lx, perm, B, X, W3):
    """X = A⁻¹·B for the three rows of ``B`` (3, n) at once (X may be B); A = Pᵀ·L·Lᵀ·P,
    L in CSC (``lp``, ``li``, ``lx``, diagonal first in each column), ``perm[k]`` the point
    of row k of P·A·Pᵀ; ``W3`` (n, 3) scratch (the permuted right-hand side, the three
    coordinates of a point side by side)."""
    n = perm.shape[0]
    for k in range(n):
        i = perm[k]
        W3[k, 0] = B[0, i]
        W3[k, 1] = B[1, i]
        W3[k, 2] = B[2, i]
    for j in range(n):
        p0 = lp[j]
        d = 1.0 / lx[p0]
        y0 = W3[j, 0] * d
        y1 = W3[j, 1] * d
        y2 = W3[j, 2] * d
        W3[j, 0] = y0
        W3[j, 1] = y1
        W3[j, 2] = y2
        for p in range(p0 + 1, lp[j + 1]):
            i = li[p]
            v = lx[p]
            W3[i, 0] -= v * y0
            W3[i, 1] -= v * y1
            W3[i, 2] -= v * y2
    for j in range(n - 1, -1, -1):
        p0 = lp[j]
        s0 = W3[j, 0]
        s1 = W3[j, 1]
        s2 = W3[j, 2]
        for p in range(p0 + 1, lp[j + 1]):
            i = li[p]
            v = lx[p]
            s0 -= v * W3[i, 0]
            s1 -= v * W3[i, 1]
            s2 -= v * W3[i, 2]
        d = 1.0 / lx[p0]
        W3[j, 0] = s0 * d
        W3[j, 1] = s1 * d
        W3[j, 2] = s2 * d
    for k in range(n):
        i = perm[k]
        X[0, i] = W3[k, 0]
        X[1, i] = W3[k, 1]
        X[2, i] = W3[k, 2]


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
    lp, li, lx, perm = fac
    D, XPREV, W3 = work[5], work[6], work[8]
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
        solve_soa(lp, li, lx, perm, work[4], D, W3)
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
