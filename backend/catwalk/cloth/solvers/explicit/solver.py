"""The explicit solver of the paper (§2–3): eq. 2 forces, eq. 3 semi-implicit Euler, eq. 4 time
step, and the strain limit (the paper's ordered velocity pass, or a baseline).

``Solver(model, method="ordered").step(model, state, collider, dt)`` advances ``state`` by
``dt`` seconds. One step is:

1. forces: springs (eq. 2) with damping along each spring, gravity, air drag, seam springs
   while sewing;
2. v ← v + dt·f/m for every point that is not pinned (eq. 3);
3. strain limit on velocities (``ordered``: the paper; ``vassilev``: Vassilev et al. 2001,
   unordered) so that no stretch/shear spring ends the step longer than (1+τ)·rest;
4. x ← x + dt·v (eq. 3); the contact planes a collision response left in the state
   (``State.planes``) keep the points the body holds on its side, with friction, until the
   next response (the explicit integrator only); then ``provot``: Provot 1995's iterated,
   unordered position correction;
5. the collider, if any: ``collider.resolve(positions, velocities, previous_positions)`` fixes
   positions/velocities in place and returns the points held by the body (a bool mask, an
   index array or None); they become high-tension centres of the next steps' ordered pass.

**Time step.** Eq. 4 gives the natural period T₀ = π·√(m/K). For semi-implicit Euler with spring
damping, a point is stable when dt²·ω² + 2·dt·γ < 4; with the per-point (Gershgorin) bounds
ω² ≤ 2K/m and γ ≤ 2C/m + air (K, C: the sums of spring constants and damping coefficients at the
point) this gives ``dt_stable`` (= √2/π·T₀ ≈ 0.45·T₀ without damping). The solver's
``dt_max = safety × dt_stable`` (``safety`` = 0.9 by default). A larger ``dt`` passed to
:meth:`Solver.step` is split into equal substeps below ``dt_max``, never run as is (unless
``allow_unstable=True``, for tests).

**Failure.** Non-finite values or a speed above ``max_speed`` raise :class:`ClothExplosionError`
(a :class:`~catwalk.errors.SimulationError`) naming the step and point; the state is marked
``failed`` and refused afterwards.

``Solver(model, method, integrator="xpbd")`` swaps steps 1–4 for XPBD, an alternative kept for
comparison (``catwalk bench cloth --integrators xpbd``, the walk's ``integrator`` setting; see
docs/cloth.md): with ``method="ordered"`` each XPBD step (its sweeps without the limit) ends
with the paper's ordered pass on the step's velocities and the contact planes, as step 3–4
above; with the other methods the limit is a hard constraint inside the sweeps.
"""

from __future__ import annotations

import math

import numpy as np

from catwalk.cloth import bending as bending_law
from catwalk.cloth import contact_planes, springs, strain_limit
from catwalk.cloth.model import ClothModel
from catwalk.cloth.solvers import STATUS_NONFINITE, STATUS_OK, ClothExplosionError, StepInfo
from catwalk.cloth.solvers.explicit import kernels as K
from catwalk.cloth.solvers.xpbd import kernels as xpbd_kernels
from catwalk.cloth.state import PLANE_COLUMNS, State
from catwalk.cloth.strain_limit import ProcessingOrder
from catwalk.errors import InputError

METHODS = {"none": strain_limit.METHOD_NONE, "ordered": strain_limit.METHOD_ORDERED,
           "vassilev": strain_limit.METHOD_VASSILEV, "provot": strain_limit.METHOD_PROVOT}
#: ``paper``: the explicit integrator with the paper's bend springs (the seed's reference
#: scheme, ``catwalk bench paper``'s reference walk)
#: the most steps between two evaluations of the quadratic bending (:meth:`Solver._bend_interval`)
MAX_BEND_EVERY = 4
INTEGRATORS = ("explicit", "paper", "xpbd")
#: the explicit integrator's bending: the quadratic law of :mod:`catwalk.cloth.bending` (the
#: default), or the paper's bend springs (Provot's [i]–[i+2]; the seed's reference scheme)
BENDING_LAWS = ("quadratic", "springs")
GRAVITY = (0.0, -9.81, 0.0)


_NO_PLANE_IDX = np.zeros(0, dtype=np.int64)
_NO_PLANES = np.zeros((0, PLANE_COLUMNS))


def _held_mask(held, n: int) -> np.ndarray:
    if held is None:
        return np.zeros(n, dtype=bool)
    h = np.asarray(held)
    if h.dtype == bool:
        if h.shape != (n,):
            raise InputError(f"collider returned a held mask of shape {h.shape}, need ({n},)")
        return h
    mask = np.zeros(n, dtype=bool)
    if h.size:
        idx = h.astype(np.int64).ravel()
        if idx.min() < 0 or idx.max() >= n:
            raise InputError("collider returned held indices out of range")
        mask[idx] = True
    return mask


def energy(model: ClothModel, state: State, gravity=GRAVITY, bending: str = "quadratic") -> dict:
    """Kinetic, spring, bending and gravitational energy (J) of a state: with the
    ``quadratic`` law (:mod:`catwalk.cloth.bending`) the bend springs are not the model's, with
    ``springs`` they are (in ``spring``, and ``bending`` is 0)."""
    v = state.velocities
    x = state.positions
    ke = 0.5 * float(np.sum(model.mass * np.sum(v * v, axis=1)))
    n = model.n_limited if bending == "quadratic" else model.n_springs
    se = float(springs.spring_energy(x, model.spring_a[:n], model.spring_b[:n],
                                     model.spring_rest[:n], model.spring_k[:n],
                                     model.n_limited, model.fabric.compression))
    be = bending_law.bending_energy(bending_law.bending_matrix(model), x) \
        if bending == "quadratic" else 0.0
    ge = -float(np.sum(model.mass * (x @ np.asarray(gravity, dtype=np.float64))))
    return {"kinetic": ke, "spring": se, "bending": be, "gravity": ge,
            "total": ke + se + be + ge}


def max_strain(model: ClothModel, positions: np.ndarray) -> float:
    """Largest strain (|x_b − x_a|/rest − 1) over the stretch and shear springs."""
    return float(springs.max_strain(positions, model.spring_a, model.spring_b, model.spring_rest,
                                    model.n_limited))


class Solver:
    """Explicit mass-spring solver (see the module docstring).

    ``method``: ``ordered`` (the paper), ``vassilev``, ``provot`` or ``none``.
    ``sweeps``: local repetitions per point in the ordered pass (the pass itself runs once per
    step; ``passes`` > 1 repeats it, for experiments). ``react``: the share of each correction's
    opposite impulse given to the parent after the position update (1 keeps momentum; 0 is pure
    follow-the-leader, which is unstable). ``share``: also share what a point's parents could
    not agree on with them. ``provot_iterations``: passes of Provot's correction per step.
    ``sewing``: apply seam forces (``seam_stiffness`` N/m per point pair, ``seam_damping``
    N·s/m, the damping taken implicitly so that it does not bound the step) and count seam
    points as high-tension centres. ``extra_air`` (1/s) adds air drag,
    e.g. to settle a drape faster. ``held_fixed``: points held by the body are immovable in the
    strain limit (the paper); False lets them be corrected like free points, so that cloth
    pulled round the body while sewing can slide instead of being pinned where it touches.
    ``order_tolerance``: recompute the ordered pass's processing order only when more than this
    share of the points changed between centre and not since it was last computed (0, the
    paper: whenever the set changes; a walking body's contacts change at every collision
    response, and the breadth-first order costs about as much as a step).

    ``bending``: ``quadratic`` (the default: the bending energy of :mod:`catwalk.cloth.bending`,
    its force −Q·x each step, the model's bend springs left out) or ``springs`` (the paper's
    bend springs, the seed's reference scheme — ``integrator="paper"`` is the explicit
    integrator with them; the XPBD integrator always takes the springs).

    ``integrator``: ``explicit`` (the paper: eq. 2–3 and the chosen strain-limit pass) or
    ``xpbd`` (:func:`catwalk.cloth.solvers.xpbd.kernels.run_steps_xpbd`: the springs as compliant
    constraints, ``xpbd_iterations`` Gauss–Seidel sweeps per step of ``xpbd_dt`` seconds,
    unconditionally stable; the strain limit becomes a hard constraint in the same sweeps, or is
    left out with ``method="none"``). With ``xpbd``, ``dt_max`` is ``xpbd_dt`` (``dt_stable``
    stays the explicit scheme's bound, for comparison).
    """

    def __init__(self, model: ClothModel, method: str = "ordered", *, gravity=GRAVITY,
                 safety: float = 0.9, sweeps: int = 2, react: float = 1.0,
                 share: bool = False, passes: int = 1, provot_iterations: int = 8,
                 sewing: bool = False, seam_stiffness: float = 50.0, seam_damping: float = 0.05,
                 extra_air: float = 0.0, tau: float | None = None, max_speed: float = 100.0,
                 allow_unstable: bool = False, held_fixed: bool = True,
                 integrator: str = "explicit", xpbd_dt: float = 1e-3,
                 xpbd_iterations: int = 8, order_tolerance: float = 0.0,
                 bending: str = "quadratic", bend_every: int | str = 1):
        if integrator not in INTEGRATORS:
            raise InputError(f"unknown integrator {integrator!r} "
                               f"(choose from {', '.join(INTEGRATORS)})")
        if integrator == "xpbd" and not (math.isfinite(xpbd_dt) and xpbd_dt > 0
                                         and int(xpbd_iterations) >= 1):
            raise InputError("xpbd needs xpbd_dt > 0 s and xpbd_iterations ≥ 1")
        if integrator == "paper":
            integrator, bending = "explicit", "springs"
        if bending not in BENDING_LAWS:
            raise InputError(f"unknown bending law {bending!r} "
                             f"(choose from {', '.join(BENDING_LAWS)})")
        # (the implicit solver, a subclass, has a ``bending`` attribute of its own)
        self.bend_law = "springs" if integrator == "xpbd" else bending
        self._bend_cache = None
        self._bend_still = None
        if bend_every != "auto" and (isinstance(bend_every, bool) or
                                     not isinstance(bend_every, int) or bend_every < 1):
            raise InputError(f"bend_every must be a whole number ≥ 1 or 'auto', "
                             f"got {bend_every!r}")
        self.bend_every = bend_every
        self._bend_every_auto = None
        self.integrator = integrator
        self.xpbd_dt = float(xpbd_dt)
        self.xpbd_iterations = int(xpbd_iterations)
        if method not in METHODS:
            raise InputError(f"unknown strain-limit method {method!r} "
                               f"(choose from {', '.join(METHODS)})")
        if not (0.0 < safety <= 1.0):
            raise InputError(f"safety factor must be in (0, 1], got {safety}")
        self.method = method
        self.gravity = np.asarray(gravity, dtype=np.float64).reshape(3)
        self.safety = float(safety)
        self.sweeps = int(sweeps)
        self.provot_iterations = int(provot_iterations)
        self.sewing = bool(sewing)
        self.seam_stiffness = float(seam_stiffness)
        self.seam_damping = float(seam_damping)
        self.extra_air = float(extra_air)
        self.tau = float(model.tau if tau is None else tau)
        self.max_speed = float(max_speed)
        self.allow_unstable = bool(allow_unstable)
        self.held_fixed = bool(held_fixed)
        self.order_tolerance = float(order_tolerance)
        self._order_centres = None
        self.order_rebuilds = 0
        self._last_h = None
        self.share = bool(share)
        self.passes = int(passes)
        self.react = float(react)
        self._model_id = None
        self._prepare(model)

    # --- per-model caches ---
    def _prepare(self, model: ClothModel) -> None:
        self._bend_every_auto = None   # (the bending's interval follows the model and step)
        self._bend_held = np.zeros((3, model.n_points))
        n = model.n_points
        self._model_id = id(model)
        self._model = model
        self._inv_mass = 1.0 / model.mass
        # (3, n) work arrays of the kernels (structure of arrays, see
        # cloth/solvers/explicit/kernels.py)
        self._work = {name: np.zeros((3, n)) for name in ("X", "V", "XP", "XPREV", "F", "R")}
        self._dirty = np.zeros(n, dtype=np.uint8)
        self._xprev = np.zeros((n, 3))
        self._bad = np.zeros(2, dtype=np.int64)
        self._plane_idx = np.zeros(n, dtype=np.int64)   # the points with a plane (_planes)
        self._plane_rows = np.zeros((n, PLANE_COLUMNS))
        # springs in runs of consecutive end points (the vectorised force loop)
        self._runs, self._n_runs_lim = springs.model_runs(model.spring_a, model.spring_b,
                                                          model.n_limited)
        self._bend_pairs = self._bending_pairs(model, self._bend_still)
        self._centres = None
        self._order_centres = None
        self._order = ProcessingOrder(np.arange(n, dtype=np.int32),
                                      np.zeros(n + 1, dtype=np.int32),
                                      np.zeros(0, dtype=np.int32), np.zeros(0, dtype=np.int32),
                                      np.zeros(n, dtype=np.int64), np.zeros(0, dtype=np.uint8))
        self._order_lim = np.zeros(0)
        self._order_lim2 = np.zeros(0)
        self._order_pt_cross = np.zeros(n, dtype=np.uint8)
        empty = np.zeros(0, dtype=np.int32)
        self._seam_a = model.seam_a if self.sewing else empty
        self._seam_b = model.seam_b if self.sewing else empty
        self._seam_pts = np.zeros(n, dtype=bool)
        if self.sewing:
            self._seam_pts[model.seam_a] = True
            self._seam_pts[model.seam_b] = True
        self.dt_stable, self.t0_eq4 = self._stability(model)
        self.dt_max = self.safety * self.dt_stable
        if self.integrator == "xpbd":
            self.dt_max = self.xpbd_dt
            self._p = np.zeros((n, 3))
            self._lam = np.zeros(model.n_springs)
            self._lam_seam = np.zeros(len(self._seam_a))

    def _bending_pairs(self, model: ClothModel, still=None):
        """The quadratic bending's Q as (pairs' runs, their k, their damping c, Gershgorin's
        row bounds of Q and of C), made once per model, fabric and set of pinned points
        (``still``: a triangle whose corners are all pinned does not bend,
        :func:`catwalk.cloth.bending.bending_matrix`; ``_prepare`` runs again when the sewing
        is switched); none with the bend springs."""
        n = model.n_points
        if self.bend_law != "quadratic":
            return (np.zeros((0, 4), np.int64), np.zeros(0), np.zeros(0), np.zeros(n),
                    np.zeros(n))
        if still is not None and (len(still) != n or not still.any()):
            still = None
        key = (id(model), id(model.fabric), n, None if still is None else still.tobytes())
        if self._bend_cache is None or self._bend_cache[0] != key:
            q = bending_law.bending_matrix(model, still=still)
            a, b, k, runs = bending_law.bending_pairs(q)
            c = bending_law.pair_damping(a, b, k, model.mass, model.fabric.damping)
            c_row = np.bincount(a, weights=c, minlength=n) + np.bincount(b, weights=c,
                                                                         minlength=n)
            self._bend_cache = (key, (runs, k, c, bending_law.row_bound(q), c_row))
        return self._bend_cache[1]

    def _bend_interval(self, model: ClothModel) -> int:
        """Steps between two evaluations of the bending force: ``bend_every`` (1 by default),
        or with ``"auto"`` as many as keep them within half the bending's stable step (each
        point's ω_b² ≤ Gershgorin's row bound / m), at most :data:`MAX_BEND_EVERY`: the bending
        is slow against the stretch and shear springs that set the step (docs/cloth.md, "The
        time step"), so its force may be evaluated every few steps and held in between; not by
        default (docs/experiments.md)."""
        if self.bend_every != "auto":
            return self.bend_every
        if self._bend_every_auto is None:
            bound = self._bend_pairs[3]
            if not len(bound):
                self._bend_every_auto = 1
            else:
                w = float(np.sqrt(np.max(bound / model.mass)))
                dt_b = 2.0 / w if w > 0 else math.inf
                self._bend_every_auto = int(max(1, min(MAX_BEND_EVERY,
                                                       0.5 * dt_b // self.dt_max)))
        return self._bend_every_auto

    def _stability(self, model: ClothModel) -> tuple[float, float]:
        n = model.n_points
        ksum = np.zeros(n)
        csum = np.zeros(n)
        m_spr = model.n_limited if self.bend_law == "quadratic" else model.n_springs
        for ends in (model.spring_a[:m_spr], model.spring_b[:m_spr]):
            np.add.at(ksum, ends, model.spring_k[:m_spr])
            np.add.at(csum, ends, model.spring_c[:m_spr])
        ksum += 0.5 * self._bend_pairs[3]
        csum += self._bend_pairs[4]
        if self.sewing and len(model.seam_a):
            # (the seams' damping is implicit, kernels.damp_seams: no bound)
            for ends in (model.seam_a, model.seam_b):
                np.add.at(ksum, ends, self.seam_stiffness)
        m = model.mass
        a = 2.0 * ksum / m
        b = 2.0 * (2.0 * csum / m + model.fabric.air + self.extra_air)
        with np.errstate(divide="ignore", invalid="ignore"):
            dt = np.where(a > 0, (-b + np.sqrt(b * b + 16.0 * a)) / (2.0 * a),
                          np.where(b > 0, 2.0 / np.maximum(b, 1e-300), np.inf))
            t0 = np.where(ksum > 0, np.pi * np.sqrt(m / np.maximum(ksum, 1e-300)), np.inf)
        return float(dt.min()), float(t0.min())

    def _pin_bending(self, model: ClothModel, pinned: np.ndarray) -> None:
        """The bending and the stable step again for another set of pinned points."""
        self._bend_still = pinned.copy()
        self._bend_pairs = self._bending_pairs(model, self._bend_still)
        self.dt_stable, self.t0_eq4 = self._stability(model)
        if self.integrator == "explicit":
            self.dt_max = self.safety * self.dt_stable

    def set_sewing(self, on: bool, model: ClothModel | None = None) -> None:
        """Switch seam forces (and seam points as tension centres) on or off."""
        self.sewing = bool(on)
        self._prepare(model if model is not None else self._model)

    def _update_order(self, state: State) -> bool:
        """Refresh the limit weights and (ordered) the processing order when the pinned/held
        points changed; True if the order was recomputed."""
        centres = state.pinned | state.held
        if self.sewing:
            centres = centres | self._seam_pts
        if self._centres is not None and np.array_equal(centres, self._centres):
            return False
        self._w_int = np.where(state.pinned, 0.0, self._inv_mass)
        self._w_lim = (np.where(state.held, 0.0, self._w_int) if self.held_fixed
                       else self._w_int)
        if self.method != "ordered":
            self._centres = centres.copy()
            return False
        if (self.order_tolerance > 0 and self._order_centres is not None
                and np.count_nonzero(centres != self._order_centres)
                <= self.order_tolerance * len(centres)):
            self._centres = centres.copy()
            return False   # close enough to the centres the order was computed from
        self._centres = centres.copy()
        self._order_centres = centres.copy()
        m = self._model
        self._order = ProcessingOrder(*strain_limit.tension_order(
            m.n_points, m.adj_ptr, m.adj_spring, m.adj_other, centres.astype(np.uint8),
            state.positions))
        ptr, spr, cross = self._order.ptr, self._order.springs, self._order.cross
        self._order_lim = (1.0 + self.tau) * m.spring_rest[spr]
        # (1 − 1e-12)·lim²: a squared length at most this is surely ≤ lim after the square root
        self._order_lim2 = self._order_lim * self._order_lim * (1.0 - 1e-12)
        k_of = np.repeat(np.arange(m.n_points), np.diff(ptr))  # entry → its point's rank
        self._order_pt_cross = (np.bincount(k_of, weights=cross, minlength=m.n_points)
                                > 0).astype(np.uint8)
        self.order_rebuilds += 1
        return True

    def processing_order(self, state: State):
        """The ordered pass's :class:`~catwalk.cloth.strain_limit.ProcessingOrder` for
        ``state``."""
        self._update_order(state)
        return self._order

    # --- stepping ---
    def step(self, model: ClothModel, state: State, collider=None,
             dt: float | None = None) -> StepInfo:
        """Advance ``state`` by ``dt`` (default ``dt_max``) seconds (see the module docstring)."""
        if id(model) != self._model_id:
            self._prepare(model)
        if state.failed:
            raise ClothExplosionError(f"this cloth state failed earlier ({state.failed}); "
                                      "start from a good state")
        n = model.n_points
        if state.positions.shape != (n, 3) or state.velocities.shape != (n, 3):
            raise InputError(f"state does not match the model ({n} points)")
        if self.bend_law == "quadratic" and not np.array_equal(
                state.pinned, self._bend_still if self._bend_still is not None else False):
            self._pin_bending(model, state.pinned)
        if dt is None:
            dt = self.dt_max
        if not (math.isfinite(dt) and dt > 0):
            raise InputError(f"time step must be a positive number of seconds, got {dt!r}")
        nsub = 1 if self.allow_unstable else max(1, math.ceil(dt / self.dt_max - 1e-9))
        h = dt / nsub
        rebuilt = self._update_order(state)
        if collider is None:
            self._run(model, state, self._w_int, self._w_lim, h, nsub)
        else:
            for _ in range(nsub):
                self._run(model, state, self._w_int, self._w_lim, h, 1)
                held = collider.resolve(state.positions, state.velocities, self._xprev)
                state.held = _held_mask(held, n)
                rebuilt |= self._update_order(state)
        return StepInfo(nsub, h, int(state.held.sum()), rebuilt)

    def _run(self, model, state, w_int, w_lim, h, nsteps):
        if self.integrator == "xpbd" and self.method == "ordered":
            for _ in range(nsteps):
                self._check(state, self._xpbd(model, state, w_int, w_lim, h, 1, False), h, 1)
                self._ordered_clamp(model, state, w_int, w_lim, h)
            return
        if self.integrator == "xpbd":
            status = self._xpbd(model, state, w_int, w_lim, h, nsteps, self.method != "none")
        else:
            status = self._run_explicit(model, state, w_int, w_lim, h, nsteps)
        self._check(state, status, h, nsteps)

    def _xpbd(self, model, state, w_int, w_lim, h, nsteps, limit: bool) -> int:
        """XPBD steps (``limit``: the strain limit as hard constraints in the same sweeps)."""
        X = xpbd_kernels
        work = X.XpbdWork(self._p, self._lam)
        springs = X.XpbdModel(model.mass, w_int, w_lim, model.spring_a, model.spring_b,
                              model.spring_rest, model.spring_k, model.spring_c,
                              model.n_limited, model.fabric.compression, self.gravity,
                              model.fabric.air + self.extra_air)
        seams = X.XpbdSeams(self._seam_a, self._seam_b, self.seam_stiffness, self.seam_damping,
                            self._lam_seam)
        steps = X.XpbdSteps(h, nsteps, self.xpbd_iterations, limit, self.tau, self.max_speed)
        return X.run_steps_xpbd(state.positions, state.velocities, self._xprev, tuple(work),
                                tuple(springs), tuple(seams), tuple(steps), self._bad)

    def _ordered_clamp(self, model, state, w_int, w_lim, h) -> None:
        """The paper's ordered pass as the final clamp of an XPBD step
        (:func:`~catwalk.cloth.solvers.explicit.kernels.clamp_step`: the end of an explicit step on
        the XPBD step's velocities (p − x)/h, from the tension centres outward, then the contact
        planes). Without the parents' reaction impulses (``react``): the explicit step's next
        pass takes them back, an XPBD step does not (with them the bench cloth ends 1 ms steps
        of 8 sweeps at strain 0.175, without them at τ = 0.100: docs/cloth.md)."""
        groups = self._step_groups(model, state, w_int, w_lim, react=0.0)
        K.clamp_step(state.positions, state.velocities, self._xprev, h, groups[0],
                     *groups[2:6])

    def _run_explicit(self, model, state, w_int, w_lim, h, nsteps):
        return K.run_steps(state.positions, state.velocities, self._xprev, h, nsteps,
                           *self._step_groups(model, state, w_int, w_lim, self.react),
                           self._bad)

    def _step_groups(self, model, state, w_int, w_lim, react: float) -> tuple:
        """The step kernels' inputs, grouped
        (:data:`~catwalk.cloth.solvers.explicit.kernels.StepModel`, ``StepSeams``, ``StepLimit``,
        ``StepOrder``, the planes, ``StepWork``, ``StepBend``) as plain
        tuples: numba types a named tuple several µs slower a call. With the quadratic law
        the force loop takes the stretch and shear springs' runs only."""
        o = self._order
        w = self._work
        runs = self._runs if self.bend_law == "springs" else self._runs[:self._n_runs_lim]
        step_model = K.StepModel(model.mass, w_int, w_lim, model.spring_a, model.spring_b,
                                 model.spring_rest, model.spring_k, model.spring_c,
                                 model.n_limited, runs, self._n_runs_lim,
                                 model.fabric.compression, self.gravity,
                                 model.fabric.air + self.extra_air)
        seams = K.StepSeams(self._seam_a, self._seam_b, self.seam_stiffness, self.seam_damping)
        limit = K.StepLimit(METHODS[self.method], self.tau, self.sweeps, react, self.share,
                            self.passes, self.provot_iterations, self.max_speed)
        order = K.StepOrder(o.points, o.ptr, o.others, o.cross, self._order_lim, self._order_lim2,
                            self._order_pt_cross, model.adj_ptr, model.adj_other)
        work = K.StepWork(w["X"], w["V"], w["XP"], w["XPREV"], w["F"], w["R"], self._dirty)
        every = self._bend_interval(model)
        bend = K.StepBend(*self._bend_pairs[:3], every, state.steps % every, self._bend_held)
        return (tuple(step_model), tuple(seams), tuple(limit), tuple(order),
                tuple(self._planes(state)), tuple(work), tuple(bend))

    def _planes(self, state):
        """The state's contact planes as (point indices, (m, 8) planes, time since set)."""
        p = state.planes
        if p is None or p.shape != (state.positions.shape[0], PLANE_COLUMNS):
            return _NO_PLANE_IDX, _NO_PLANES, 0.0
        # (the state has the model's points, step() checks: the buffers are the model's)
        m = contact_planes.planes_set(p, self._plane_idx, self._plane_rows)
        return self._plane_idx[:m], self._plane_rows[:m], state.time - state.plane_time

    def _check(self, state, status, h, nsteps):
        if status != STATUS_OK:
            step = int(self._bad[0])
            t = state.time + (step + 1) * h
            what = "non-finite values" if status == STATUS_NONFINITE else \
                f"a speed above {self.max_speed:g} m/s"
            msg = (f"cloth simulation exploded: {what} at point {int(self._bad[1])}, "
                   f"t = {t:.6g} s (dt = {h:.3g} s, dt_max = {self.dt_max:.3g} s)")
            state.failed = msg
            raise ClothExplosionError(msg)
        state.time += h * nsteps
        state.steps += nsteps
        self._last_h = h

    def after_collision(self, model: ClothModel, state: State, dt: float,
                        iterations: int = 4, move_held: bool = False) -> None:
        """Provot's position correction after a collision response: stretch/shear springs the
        collider left longer than (1+τ)·rest (it pushed one end out and not the other) are
        shortened, points held by the body staying put, and the velocities take the change
        over ``dt`` (the time since the previous collision response). Without it a stiff
        fabric turns a few millimetres of push into tens of m/s of spring oscillation.
        ``move_held``: points held by the body are corrected too (only pinned points stay put;
        the caller pushes them back out of the body)."""
        w = np.where((state.held & (not move_held)) | state.pinned, 0.0, self._inv_mass)
        # the kernel works on (3, n) arrays; the transposed views are changed in place
        strain_limit.limit_provot_positions(state.positions.T, state.velocities.T, w,
                                            model.spring_a, model.spring_b, model.spring_rest,
                                            model.n_limited, self.tau, float(dt),
                                            int(iterations))

    def last_speed(self, state: State) -> float:
        """The largest speed over the last (sub)step from positions, |x − x_prev| / dt: with the
        ordered pass the velocity array also carries the parents' reaction impulses, which the
        next step's pass takes back, so this is the speed to judge settling by."""
        if self._last_h is None:
            return 0.0
        d = state.positions - self._xprev
        return float(np.sqrt(np.max(np.sum(d * d, axis=1)))) / self._last_h

    def run(self, model: ClothModel, state: State, duration: float, collider=None,
            dt: float | None = None, callback=None) -> int:
        """Simulate ``duration`` seconds in steps of ``dt`` (default ``dt_max``); returns the
        number of steps. ``callback(state)`` after each step may return True to stop."""
        dt = self.dt_max if dt is None else dt
        steps = max(1, round(duration / dt))
        if collider is None and callback is None:
            self.step(model, state, None, dt * steps)
            return steps
        for i in range(steps):
            self.step(model, state, collider, dt)
            if callback is not None and callback(state):
                return i + 1
        return steps
