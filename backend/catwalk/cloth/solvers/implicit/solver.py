"""The implicit solver: implicit Euler steps on a matrix factored once per garment, the paper's
ordered strain correction as the final clamp.

``ImplicitSolver(model, dt=1/90, iterations=10).step(model, state, collider, dt)`` has the
explicit :class:`~catwalk.cloth.solvers.explicit.solver.Solver`'s interface (it is one: the
substeps, the collider hook, the ordered pass's order, :meth:`after_collision` are the explicit
solver's); only what a (sub)step does differs. One step of h seconds:

1. y = xₙ + h·vₙ; the guess x = y;
2. ``iterations`` times (:func:`~catwalk.cloth.solvers.implicit.kernels.iterate`): the
   residual force r(x) (the springs with their damping at v = (x − xₙ)/h, gravity, air, the
   quadratic bending, the inertia), the global solve A⁻¹·r through the factor (the same for
   x, y, z), the update with Chebyshev's weight, the contact planes (``State.planes``, moving
   with the body) projected;
3. v = (x − xₙ)/h, Coulomb friction at the points their plane stopped;
4. the paper's ordered pass on those velocities from the tension centres outward, and the
   positions taken again as xₙ + h·v (:func:`catwalk.cloth.solvers.explicit.kernels.clamp_step`, as
   the XPBD integrator does): no stretch/shear spring ends the step over (1+τ)·rest where the pass
   can reach it.

A = M(1/h² + air/h) + Σ (k + c/h)·AₛᵀAₛ + Q (:mod:`.system`) is factored when the solver
first steps with a step h, and again only when h, the pinned points or the seams change
(``factorizations`` counts; a walk makes one).

``bending``: ``"quadratic"`` (the constant-Hessian energy of :mod:`.system`, rigidity
``bend_rigidity`` N·m, default the fabric's mean of warp and weft; the model's bend springs
are left out) or ``"springs"`` (the model's bend springs in the force loop and in A, as the
explicit solver has them).
"""

from __future__ import annotations

import math
import time

import numpy as np
import scipy.sparse as sp

from catwalk.cloth import bending, springs
from catwalk.cloth.model import ClothModel
from catwalk.cloth.solvers import ClothExplosionError
from catwalk.cloth.solvers.explicit import kernels as CK
from catwalk.cloth.solvers.explicit.solver import Solver
from catwalk.cloth.solvers.implicit import kernels as K
from catwalk.cloth.solvers.implicit import system
from catwalk.cloth.solvers.implicit.factor import ORDERS, Factor
from catwalk.cloth.state import State
from catwalk.errors import InputError

BENDING = ("quadratic", "springs")
#: how the contact planes enter a step: ``uzawa`` (projected every iteration, with Uzawa
#: multipliers carried from step to step), ``after`` (only after the iterations, by the
#: clamp, as the explicit step applies them)
CONTACTS = ("uzawa", "after")


class ImplicitSolver(Solver):
    """Implicit Euler on a prefactored matrix (module docstring). ``dt``: the step (s);
    ``iterations`` a step; ``rho`` Chebyshev's spectral radius estimate (0: no
    acceleration), ``gamma`` its under-relaxation, from iteration ``cheby_start`` on;
    ``bending`` and ``bend_rigidity`` (N·m, None: the fabric's); ``order`` the factor's
    fill-reducing order. The other keywords are the explicit solver's (the strain limit's
    ``method`` and its settings, ``sewing``, ``extra_air``, ``held_fixed``, …)."""

    def __init__(self, model: ClothModel, method: str = "ordered", *, dt: float = 1.0 / 90.0,
                 iterations: int = 10, rho: float = 0.95, gamma: float = 1.0,
                 cheby_start: int = 1, bending: str = "quadratic",
                 bend_rigidity: float | None = None, bend_in_matrix: bool = False,
                 order: str = "metis",
                 contacts: str = "uzawa", kappa: float = 1.0, passes: int = 6, **kw):
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and 0 < dt <= 0.1):
            raise InputError(f"implicit dt must be within (0, 0.1] s, got {dt!r}")
        if isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer)) or \
                not 1 <= iterations <= 1000:
            raise InputError(f"implicit iterations must be a whole number 1–1000, got "
                             f"{iterations!r}")
        if not (0.0 <= rho < 1.0) or not (0.0 < gamma <= 2.0) or cheby_start < 0:
            raise InputError("Chebyshev needs 0 ≤ rho < 1, 0 < gamma ≤ 2, cheby_start ≥ 0")
        if bending not in BENDING:
            raise InputError(f"bending must be one of {', '.join(BENDING)}, got {bending!r}")
        if bend_rigidity is not None and not (math.isfinite(bend_rigidity) and
                                              bend_rigidity >= 0):
            raise InputError(f"bend_rigidity must be ≥ 0 N·m, got {bend_rigidity!r}")
        if order not in ORDERS:
            raise InputError(f"order must be one of {', '.join(ORDERS)}, got {order!r}")
        self.implicit_dt = float(dt)
        self.iterations = int(iterations)
        self.rho, self.gamma, self.cheby_start = float(rho), float(gamma), int(cheby_start)
        self.bending = bending
        self.bend_rigidity = bend_rigidity
        self.bend_in_matrix = bool(bend_in_matrix)
        self.order = order
        if contacts not in CONTACTS:
            raise InputError(f"contacts must be one of {', '.join(CONTACTS)}, got {contacts!r}")
        self.contacts = contacts
        self.kappa = float(kappa)
        self.factorizations = 0
        self.factor_seconds = 0.0
        self.last_residuals = np.zeros(self.iterations + 1)
        super().__init__(model, method, passes=passes, **kw)
        self.integrator = "implicit"

    # --- per-model caches ---
    def _prepare(self, model: ClothModel) -> None:
        super()._prepare(model)
        self.dt_max = self.implicit_dt
        n = model.n_points
        if self.bending == "quadratic":
            b = bending.bending_rigidity(model) if self.bend_rigidity is None else \
                self.bend_rigidity
            lap, coef, q = bending.bending(model, b)
            self._bend = K.Bending(lap.indptr.astype(np.int64), lap.indices.astype(np.int64),
                                   lap.data.astype(np.float64), coef)
            # in A whole, or as its rows' absolute sums on the diagonal (a bound of Q that
            # keeps the factor as sparse as the springs' alone)
            self._bend_q = q if self.bend_in_matrix else \
                sp.diags(np.asarray(abs(q).sum(axis=1)).ravel()).tocsc()
            self._springs = np.arange(model.n_limited)
            self._runs_used = self._runs[:self._n_runs_lim]
        else:
            self._bend = K.Bending(np.zeros(1, np.int64), np.zeros(0, np.int64), np.zeros(0),
                                   np.zeros(0))
            self._bend_q = None
            self._springs = np.arange(model.n_springs)
            self._runs_used = self._runs
        self._factor = None
        self._factor_key = None
        self._iwork = K.Work(*(np.zeros((3, n)) for _ in range(8)), np.zeros(3 * n))
        self._touched = np.zeros(n, np.uint8)
        self._lam = np.zeros(n)
        self._lam_keep = np.zeros(n)

    def _factor_for(self, model: ClothModel, h: float, fixed: np.ndarray) -> Factor:
        """The factor of A for step ``h`` with the ``fixed`` points, made when the key
        changed (counted in ``factorizations``)."""
        key = (round(h, 15), fixed.tobytes(), self.sewing)
        if key != self._factor_key:
            t = time.perf_counter()
            a = system.system_matrix(model, h, self._springs, self._bend_q,
                                     model.fabric.air + self.extra_air, fixed)
            if self.sewing and len(self._seam_a):
                a = (a + system.laplacian(model.n_points, self._seam_a, self._seam_b,
                                          np.full(len(self._seam_a), self.seam_stiffness +
                                                  self.seam_damping / h))).tocsc()
            self._factor = Factor(a, self.order, self._factor)
            self._factor_key = key
            self.factorizations += 1
            self.factor_seconds += time.perf_counter() - t
        return self._factor

    # --- one (sub)step ---
    def _run(self, model, state, w_int, w_lim, h, nsteps):
        for _ in range(nsteps):
            self._implicit_step(model, state, w_int, w_lim, h)

    def _implicit_step(self, model, state: State, w_int, w_lim, h: float,
                       predicted: np.ndarray | None = None) -> None:
        """One step of ``h`` s (module docstring); ``predicted``: the inertial prediction
        xₙ + h·vₙ as a detection left it (pushed out of the body; its planes, set at the
        step's end, in the state), instead of xₙ + h·vₙ."""
        fixed = (w_int == 0.0)
        f = self._factor_for(model, h, fixed)
        X0, Y, V, F, R, D, XPREV, T, W = self._iwork
        springs.to_soa(state.positions, X0)
        if predicted is None:
            springs.to_soa(state.velocities, V)
            Y[:] = X0 + h * V
        else:
            springs.to_soa(predicted, Y)
        X = self._X = getattr(self, "_X", None)
        if X is None or X.shape != X0.shape:
            X = self._X = np.zeros_like(X0)
        X[:] = Y
        idx, rows, _ = self._planes(state)
        t_end = state.time + h - state.plane_time
        touched = self._touched[:len(idx)]
        touched[:] = 0
        project = self.contacts == "uzawa" and len(idx) > 0
        if project:
            K.project_planes(X, idx, rows, t_end, touched)
            # the multipliers of the points that still have a plane carry over
            self._lam_keep[:] = 0.0
            self._lam_keep[idx] = self._lam[idx]
            self._lam, self._lam_keep = self._lam_keep, self._lam
        kappa = self.kappa * float(model.mass.sum()) / (max(1, len(idx)) * h * h)
        mdl = K.ImplicitModel(model.mass, fixed.astype(np.uint8), self._runs_used,
                              self._n_runs_lim, model.spring_rest, model.spring_k,
                              model.spring_c, model.fabric.compression, self.gravity,
                              model.fabric.air + self.extra_air, self._seam_a, self._seam_b,
                              self.seam_stiffness)
        K.iterate(X, h, tuple(mdl), tuple(self._bend), (f.lp, f.li, f.lx, f.perm, f.chains),
                  (self.iterations, self.rho, self.gamma, self.cheby_start),
                  tuple(self._iwork), idx, rows, t_end, touched, self.last_residuals,
                  self._lam, kappa, project)
        V[:] = (X - X0) / h
        if project:
            K.friction(V, idx, rows, touched)
        if self.sewing and len(self._seam_a):
            CK.damp_seams(V, self._seam_a, self._seam_b, w_int, self.seam_damping, h)
        x_prev = state.positions.copy()
        springs.from_soa(V, state.velocities)
        self._clamp(model, state, x_prev, w_int, w_lim, h, (idx, rows, t_end))
        self._xprev = x_prev
        self._check_state(state, h)

    def _clamp(self, model, state, x_prev, w_int, w_lim, h, contact) -> None:
        """The paper's ordered pass on the step's velocities, positions xₙ + h·v, the planes
        (:func:`catwalk.cloth.solvers.explicit.kernels.clamp_step`; without the parents' reactions,
        as the
        XPBD integrator's clamp)."""
        groups = self._step_groups(model, state, w_int, w_lim, react=0.0)
        state.positions[:] = x_prev
        CK.clamp_step(state.positions, state.velocities, x_prev.copy(), h, groups[0],
                      *groups[2:4], contact, groups[5])

    def _check_state(self, state: State, h: float) -> None:
        v = state.velocities
        s2 = np.einsum("ij,ij->i", v, v)
        bad = ~np.isfinite(s2) | (s2 > self.max_speed ** 2)
        bad |= ~np.all(np.isfinite(state.positions), axis=1)
        if bad.any():
            i = int(np.argmax(bad))
            msg = (f"cloth simulation exploded: point {i} at t = {state.time + h:.6g} s "
                   f"(implicit step {h:.3g} s)")
            state.failed = msg
            raise ClothExplosionError(msg)
        state.time += h
        state.steps += 1
        self._last_h = h
