"""Dressing (paper §5–6): place the cut pieces round the body, sew them, weld, settle.

1. **Place**: :func:`catwalk.simulate.garment_cloth.garment_cloth` puts every piece round its
   body part from the body's landmarks, curved round the part, 3 cm off the skin; the collider
   pushes out whatever starts inside the body (three passes), velocities start at zero.
2. **Sew**: seam springs pull partner points together (k = ω²·m with m the median point mass,
   critically damped), gravity off and extra air drag, body friction off, and points touching the
   body are *not* fixed in the strain limit (:class:`~catwalk.cloth.solvers.explicit.solver.Solver`
   ``held_fixed=False``) so panels slide round the body instead of being pinned where they touch
   it. A seam spring pulls as if its gap were at most ``SEAM_REACH`` (1 cm, in
   :mod:`catwalk.cloth.solvers.explicit.kernels`), so far partners approach at a bounded speed.
   Sewing stops when every pair is within ``weld_gap``, when neither the widest nor the mean gap
   shrank by 2 % in ``sew_stall_seconds`` (0.3 s; not before 0.8 s), or after ``sew_seconds`` of
   simulated time.
3. **Weld**: pairs within ``weld_reach`` become one particle
   (:func:`~catwalk.simulate.garment_cloth.weld`); the others keep pulling while the garment
   settles and are welded as they close (to ``weld_gap``); once the garment is at rest, or
   the settling time is up, the pairs still within ``weld_reach`` are welded too and it
   settles again (at most ``FINAL_SETTLE_SECONDS`` more when the time was up). A seam still
   open by more than ``max_open_gap`` at the end fails the dressing with its name and gap.
   The weld moves partners up to ``weld_reach`` apart to one point: the collider pushes
   out what that put inside the body and the springs left over the limit are relieved in
   positions (as in 5., ``strain_after_push`` → ``strain_settle_start`` in the stats) before
   settling starts — the velocity pass would close them in one step, throwing the points at
   excess / dt (the bodice M blew up in its first 1/30 s of settling from 0.07, τ 0.05).
4. **Settle**: gravity and the fabric's friction, until the points' RMS speed (the kinetic
   energy) falls under ``settle_speed`` with every seam welded, or ``settle_seconds`` have
   passed (reported as not settled, with the speed reached). A settling that blows up even
   with each interval's own retries (:func:`~catwalk.simulate.stepping.advance`) is run again
   from the sewn state with twice the resolves a 1/30 s, up to ``max_collisions``
   (``settle_collisions``, ``settle_retries`` in the stats). Points held by the body stay
   tension centres of the ordered pass but are not fixed in it (``held_fixed=False``): with
   them fixed, cloth pinched between two held points (a waistband on the hips) cannot be
   corrected and its strain runs away (measured: 0.36 after 0.5 s on the pencil skirt,
   against 0.10 with them free).
5. **Strain relief**: a spring whose two ends the body holds (a neckline on the neck's base)
   can end over the limit; while the max strain is over τ + ``RELIEF_SLACK`` (0.1 %; at most
   ``STRAIN_RELIEF_ROUNDS`` times), Provot's position correction (``RELIEF_ITERATIONS``
   passes) runs with the held points free to move too, and the collider pushes them back out
   (the bodice S: max strain 0.158 → 0.055 in 10 rounds, τ 0.05; 4 fixed rounds of 4 passes
   left it at 0.074; nothing more than 0 mm inside the body). ``relief_rounds`` in the
   stats.

What is shown (``Dressed.display``, and each walk frame) is the simulated cloth with the
triangles that a sharp body vertex (a bust point) comes through pushed off it
(:meth:`~catwalk.collide.collider.Collider.push_off_sharp`); the simulation's own state is
left as it is (pushing it there, at every resolve or every frame, raised the walks' maximum
strain 2–3× and slowed points: the cloth sinks back onto the point between resolves).

Collisions are resolved ``n`` times per 1/30 s, ``n`` from how far the cloth moved in the
previous 1/30 s (at most ``max_move`` between two resolves). Everything reports progress as
``progress(stage, i, total)`` (stages ``placing``, ``sewing``, ``settling``, ``relief``) and
checks ``cancel()`` at every collider resolve, push-out round and relief round (a few ms apart;
:class:`~catwalk.errors.Cancelled` is raised).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from catwalk.cloth.model import ClothModel
from catwalk.cloth.solvers import ClothExplosionError
from catwalk.cloth.solvers.explicit.solver import Solver, max_strain
from catwalk.cloth.state import State
from catwalk.collide import make_collider
from catwalk.errors import Cancelled, InputError, SimulationError
from catwalk.simulate.contacts import Floor, body_contacts, contacts_of, keep
from catwalk.simulate.garment_cloth import GarmentCloth, garment_cloth, seam_gaps, weld
from catwalk.simulate.settings import PRESETS, Settings
from catwalk.simulate.stepping import (
    ORDER_TOLERANCE,
    advance,
    collide_and_floor,
    max_move,
    never,
    quiet,
)

CHUNK = 1.0 / 30.0
SETTLE_AIR = 10.0   # 1/s of extra air drag while the garment settles (terminal speed g/10)
MIN_SEW_SECONDS = 0.8   # sewing is not given up as stalled before this (gaps plateau a while)
FINAL_SETTLE_SECONDS = 0.5   # settling after the last pairs within reach are welded at rest
STRAIN_RELIEF_ROUNDS = 32    # at most; fewer once the max strain is within RELIEF_SLACK of τ
RELIEF_SLACK = 0.001   # (τ + 0.5 % left the dress M at 0.104, τ 0.10; this costs ≤ 0.2 s)
RELIEF_ITERATIONS = 16


class DressingError(SimulationError):
    """The garment could not be sewn or settled on this body."""


@dataclass
class Dressed:
    cloth: GarmentCloth           # the unwelded cloth: triangles, uv, panels per pattern point
    model: ClothModel             # the welded model that is simulated
    rep: np.ndarray               # (pattern points,) → particle of the welded model
    state: State                  # settled, on the body pose it was dressed on
    stats: dict = field(default_factory=dict)
    sewn: np.ndarray | None = None   # pattern points where sewing left them (before the weld)
    # the welded positions as shown (exported, rendered): ``state.positions`` with the cloth
    # triangles a sharp body vertex comes through pushed off it (collide/sharp.py)
    display: np.ndarray | None = None

    def pattern_positions(self, x: np.ndarray | None = None) -> np.ndarray:
        """Positions per pattern point (panels keep their own vertices along seams)."""
        return (self.state.positions if x is None else x)[self.rep]


def seam_names(garment) -> list[str]:
    """The garment's seams as the dressing names them (a seam without a name: ``seam k``)."""
    return [sm.name or f"seam {k}" for k, sm in enumerate(garment.seams)]

def push_out(solver: Solver, model: ClothModel, state: State, collider, x0: np.ndarray,
             rounds: int = 4, cancel: Callable[[], bool] | None = None) -> None:
    """Move cloth that starts inside the body out of it (the body at its current pose), and
    let the cloth around the pushed points follow (Provot's position correction with the
    pushed points held) so no spring starts far over its limit; velocities end at zero."""
    for r in range(rounds):
        if cancel is not None and cancel():
            raise Cancelled("try-on cancelled")
        x0[:] = state.positions
        body = body_contacts(collider, state, x0, 1.0)
        keep(state, body, contacts_of(Floor(collider.thickness, 0.0), state))
        # the first rounds relax every spring (points pushed to opposite sides of a thin limb
        # pull each other back); the last keeps the pushed points where the body put them
        if r < rounds - 1:
            state.held[:] = False
        solver.after_collision(model, state, CHUNK, iterations=30)
    state.velocities[:] = 0.0
    state.planes = None


def relieve_strain(solver: Solver, model: ClothModel, state: State, collider, x0: np.ndarray,
                   h: float, strain: float, progress, cancel) -> tuple[int, float]:
    """Strain relief (module docstring, 5.): while the max strain is over τ +
    ``RELIEF_SLACK``, at most ``STRAIN_RELIEF_ROUNDS`` times, Provot's position correction
    with the held points free to move, then the collider. Returns (rounds, max strain)."""
    rounds = 0
    while rounds < STRAIN_RELIEF_ROUNDS and strain > model.tau + RELIEF_SLACK:
        if cancel():
            raise Cancelled("try-on cancelled")
        solver.after_collision(model, state, h, move_held=True, iterations=RELIEF_ITERATIONS)
        collide_and_floor(state, collider, x0, 1.0)
        rounds += 1
        strain = max_strain(model, state.positions)
        progress("relief", rounds, STRAIN_RELIEF_ROUNDS)
    progress("relief", STRAIN_RELIEF_ROUNDS, STRAIN_RELIEF_ROUNDS)
    return rounds, strain


def _p99_move(a: np.ndarray, b: np.ndarray) -> float:
    d = a - b
    return float(np.sqrt(np.percentile(np.sum(d * d, axis=1), 99))) if len(d) else 0.0


def _rms_move(a: np.ndarray, b: np.ndarray) -> float:
    d = a - b
    return float(np.sqrt(np.mean(np.sum(d * d, axis=1)))) if len(d) else 0.0


def _weld_state(model: ClothModel, state: State, pairs: np.ndarray
                ) -> tuple[ClothModel, np.ndarray, State]:
    """Weld ``pairs`` of ``model``'s seam pairs; the new model, the point map and a state whose
    particles sit at the mass-weighted mean of their points, moving with their mean
    momentum."""
    welded, rep = weld(model, pairs)
    x = np.zeros((welded.n_points, 3))
    v = np.zeros((welded.n_points, 3))
    np.add.at(x, rep, state.positions * model.mass[:, None])
    np.add.at(v, rep, state.velocities * model.mass[:, None])
    st = State.from_model(welded, x / welded.mass[:, None])
    st.velocities[:] = v / welded.mass[:, None]
    st.held = np.zeros(welded.n_points, dtype=bool)
    np.logical_or.at(st.held, rep, state.held)
    st.time, st.steps = state.time, state.steps
    return welded, rep, st


def prev_of(prev: np.ndarray, rep: np.ndarray, model: ClothModel) -> np.ndarray:
    """Previous positions carried through a weld (first point of each particle)."""
    out = np.empty((model.n_points, 3))
    out[rep] = prev
    return out


def dress(body, garment, size: str | None = None, fabric=None,
          settings: Settings | None = None, *, vertices: np.ndarray | None = None,
          progress: Callable[[str, int, int], None] | None = None,
          cancel: Callable[[], bool] | None = None) -> Dressed:
    """Sew ``garment`` (a :class:`~catwalk.garment.model.Garment`) in ``size`` onto ``body``
    (a :class:`~catwalk.body.types.Body` with landmarks and parts) in its rest pose, or posed as
    ``vertices`` (landmarks are still taken from the rest pose). See the module docstring."""
    settings = (settings or PRESETS["balanced"]).check()
    if body.parts is None:
        raise InputError("the body has no per-vertex parts; make it with `catwalk body make`")
    run = _Dressing(body, garment, size, fabric, settings, vertices, progress or quiet,
                    cancel or never)
    run.sew()
    run.settle_retrying()
    run.finish()
    run.check_seams()
    return Dressed(run.gc, run.model, run.rep, run.state, run.stats(), run.sewn, run.display)


class _Dressing:
    """One dressing, its phases in the module docstring's order: placed (on construction),
    :meth:`sew`, :meth:`settle` (welding as seams close), :meth:`finish` (the last response,
    the strain relief, what is shown), :meth:`check_seams`; :meth:`stats` reports it."""

    def __init__(self, body, garment, size, fabric, settings: Settings, vertices, progress,
                 cancel):
        self.garment, self.settings = garment, settings
        self.progress, self.cancel = progress, cancel
        self.t_start = time.perf_counter()
        progress("placing", 0, 3)
        self.gc = gc = garment_cloth(garment, body, size, fabric, h=settings.h)
        self._check_cancel()
        progress("placing", 1, 3)
        self.pattern = model = gc.model
        if len(model.seam_a) == 0:
            raise DressingError(f"garment {garment.name!r} has no seams to sew")
        verts = np.ascontiguousarray(body.vertices if vertices is None else vertices,
                                     dtype=np.float64)
        self.friction = gc.fabric.friction if settings.friction is None else settings.friction
        self.collider = make_collider(settings.collider, body.faces, body.parts, friction=0.0,
                                      **settings.collider_options())
        self.collider.update(verts, np.zeros_like(verts))
        self.state = State.from_model(model)
        self.m_med = float(np.median(model.mass))
        w = settings.sew_omega
        self.solver = Solver(model, settings.method, gravity=(0.0, 0.0, 0.0), sewing=True,
                             safety=settings.step_safety, seam_stiffness=w * w * self.m_med,
                             seam_damping=2.0 * w * self.m_med, extra_air=2.0,
                             held_fixed=False, order_tolerance=ORDER_TOLERANCE)
        self.x0 = self.state.positions.copy()
        progress("placing", 2, 3)
        push_out(self.solver, model, self.state, self.collider, self.x0, cancel=cancel)
        progress("placing", 3, 3)
        self.clock = {}

    def _check_cancel(self) -> None:
        if self.cancel():
            raise Cancelled("try-on cancelled")

    def sew(self) -> None:
        """Seam springs pull the pieces together until every pair is within ``weld_gap``, the
        gaps stall, or ``sew_seconds`` are up."""
        st, model, settings = self.state, self.pattern, self.settings
        chunks = max(1, round(settings.sew_seconds / CHUNK))
        gaps = seam_gaps(model, st.positions)
        self.gap0 = float(gaps.max())
        history = [self.gap0]
        means = [float(gaps.mean())]
        self.sewn_chunks = 0
        for i in range(chunks):
            self._check_cancel()
            if (i + 1) * CHUNK <= settings.sew_free_seconds:
                self.solver.step(model, st, None, CHUNK)
            else:
                advance(self.solver, model, st, self.collider, CHUNK, settings.sew_collisions,
                        self.x0, settings.max_collisions * 4, self.clock, self.cancel)
            self.sewn_chunks = i + 1
            gaps = seam_gaps(model, st.positions)
            history.append(float(gaps.max()))
            self.progress("sewing", i + 1, chunks)
            if history[-1] < settings.weld_gap:
                break
            means.append(float(gaps.mean()))
            lag = round(settings.sew_stall_seconds / CHUNK)
            if (lag > 0 and len(history) > lag and (i + 1) * CHUNK >= MIN_SEW_SECONDS
                    and history[-1 - lag] - history[-1] < 0.02 * history[-1 - lag]
                    and means[-1 - lag] - means[-1] < 0.02 * means[-1 - lag]):
                break   # stalled: neither the widest nor the mean gap shrank by 2 % in 0.3 s
        self.t_sewn = time.perf_counter()
        self.sewn = st.positions.copy()
        self.gap_sewn = float(gaps.max())
        self.gaps = gaps

    def _settle_solver(self, m: ClothModel) -> Solver:
        w, s = self.settings.sew_omega, self.settings
        return Solver(m, s.method, extra_air=SETTLE_AIR, held_fixed=False,
                      safety=s.step_safety, order_tolerance=ORDER_TOLERANCE,
                      sewing=len(m.seam_a) > 0, seam_stiffness=w * w * self.m_med,
                      seam_damping=2.0 * w * self.m_med)

    def _weld(self, closed: np.ndarray) -> np.ndarray:
        """Weld the seam pairs ``closed``; a new solver and response start for the welded
        model. Returns the old particles' new ones."""
        self.model, rep2, self.state = _weld_state(self.model, self.state, closed)
        self.rep = rep2 if self.rep is None else rep2[self.rep]
        self.solver = self._settle_solver(self.model)
        self.x0 = self.state.positions.copy()
        return rep2

    def settle_retrying(self) -> None:
        """:meth:`settle` with the settings' resolves a 1/30 s; a settling that blows up even
        with each interval's own retries is run again from the sewn state with twice the
        resolves, up to ``max_collisions`` (``settle_retries`` in the stats: on one AMD EPYC
        the bodice S tore at the shoulder in its first 1/15 s of settling at 5 resolves and
        settles at 10)."""
        sewn, n = self.state.copy(), self.settings.settle_collisions
        self.settle_retries = 0
        while True:
            try:
                self.settle(n)
                return
            except ClothExplosionError:
                if n >= self.settings.max_collisions:
                    raise
            self.state, self.x0 = sewn.copy(), sewn.positions.copy()
            n = min(2 * n, self.settings.max_collisions)
            self.settle_retries += 1

    def settle(self, collisions: int) -> None:
        """Weld what closed; gravity and friction on, settle with ``collisions`` resolves a
        1/30 s until at rest (or the time is up), welding the pairs that close meanwhile
        (module docstring, 3.–4.)."""
        settings = self.settings
        self.settle_collisions = collisions
        self.model, self.rep = self.pattern, None
        self._weld(self.gaps <= settings.weld_reach)
        self.strain_weld = max_strain(self.model, self.state.positions)
        self.collider.friction = self.friction
        push_out(self.solver, self.model, self.state, self.collider, self.x0,
                 cancel=self.cancel)
        # what the weld and the push left over the limit is relieved in positions first: the
        # velocity pass would close it in one step, throwing the points at excess / dt (the
        # bodice M blew up in its first 1/30 s of settling so, from a strain of 0.07, τ 0.05)
        self.strain_pushed = max_strain(self.model, self.state.positions)
        _, self.strain_settle_start = relieve_strain(
            self.solver, self.model, self.state, self.collider, self.x0, CHUNK,
            self.strain_pushed, quiet, self.cancel)
        self.state.velocities[:] = 0.0
        self.prev = self.state.positions.copy()
        chunks = max(0, round(settings.settle_seconds / CHUNK))
        self.speed = float("inf")
        self.speeds = []
        limit = chunks
        i = 0
        while i < limit:
            self._check_cancel()
            self.prev[:] = self.state.positions
            advance(self.solver, self.model, self.state, self.collider, CHUNK, collisions,
                    self.x0, settings.max_collisions * 4, self.clock, self.cancel)
            # √(2·kinetic energy / mass)
            self.speed = _rms_move(self.state.positions, self.prev) / CHUNK
            self.speeds.append(round(self.speed, 4))
            i += 1
            self.progress("settling", i, limit)
            if len(self.model.seam_a):
                # pairs are welded as they close; once the garment is at rest (or the time is
                # up) the pairs still within reach are welded too, and it settles once more
                at_rest = self.speed < settings.settle_speed or i == limit
                gaps = seam_gaps(self.model, self.state.positions)
                closed = gaps <= (settings.weld_reach if at_rest else settings.weld_gap)
                if closed.any():
                    rep2 = self._weld(closed)
                    self.prev = prev_of(self.prev, rep2, self.model)
                    if i == limit == chunks:   # the time was up: once, a little more
                        limit += round(FINAL_SETTLE_SECONDS / CHUNK)
                    continue
            if self.speed < settings.settle_speed and not len(self.model.seam_a):
                break
        self.settled_chunks = i

    def finish(self) -> None:
        """The last response, the strain relief, and what is shown."""
        st, model, collider = self.state, self.model, self.collider
        # the last correction may have pulled free points a little into the body
        collide_and_floor(st, collider, self.x0, 1.0)
        # strain relief: springs the body holds at both ends (a neckline on the neck's base)
        # can be left over the limit, which the ordered pass cannot correct; let Provot's
        # correction move held points too, along the body, and push them back out, a few times
        self.strain_settled = max_strain(model, st.positions)
        self.relief_rounds, self.strain = relieve_strain(
            self.solver, model, st, collider, self.x0,
            CHUNK / self.settle_collisions, self.strain_settled, self.progress,
            self.cancel)
        st.velocities[:] = 0.0
        # what is shown: the body's sharp vertices (bust points) pushed out of the cloth
        # triangles they come through between three points that are all outside (the resolves
        # see points)
        self.display = st.positions.copy()
        self.sharp = collider.push_off_sharp(self.display, model.triangles)
        self.sharp_mm = 1e3 * max_move(self.display, st.positions)
        self.t_end = time.perf_counter()

    def check_seams(self) -> None:
        """Each seam's widest gap left (``open_gap``); a :class:`DressingError` naming the
        seams open by more than ``max_open_gap``."""
        names = seam_names(self.garment)
        self.open_gap = open_gap = {name: 0.0 for name in names}
        welded = self.model
        if len(welded.seam_a):
            left = seam_gaps(welded, self.state.positions)
            for sid in np.unique(welded.seam_id):
                open_gap[names[int(sid)]] = float(left[welded.seam_id == sid].max())
        self.worst = worst = max(open_gap, key=open_gap.get)
        limit = self.settings.max_open_gap
        if open_gap[worst] > limit:
            bad = ", ".join(f"{k!r} by {v * 100:.1f} cm" for k, v in
                            sorted(open_gap.items(), key=lambda kv: -kv[1]) if v > limit)
            raise DressingError(
                f"garment {self.garment.name!r} size {self.gc.size}: after "
                f"{self.sewn_chunks * CHUNK:.2f} s of sewing and "
                f"{self.settled_chunks * CHUNK:.2f} s of settling these seams are still open: "
                f"{bad} (limit {limit * 100:.1f} cm); check the placement hints and seam "
                "lengths, or whether the size fits this body")

    def stats(self) -> dict:
        welded, model, st, prev = self.model, self.pattern, self.state, self.prev
        return {
            "points": int(welded.n_points), "pattern_points": int(model.n_points),
            "springs": int(welded.n_springs), "seam_pairs": int(len(model.seam_a)),
            "open_seam_pairs": int(len(welded.seam_a)),
            "triangles": int(len(model.triangles)), "size": self.gc.size,
            "fabric": self.gc.fabric.id, "dt_max_s": float(self.solver.dt_max),
            "sewing_sim_s": self.sewn_chunks * CHUNK,
            "settle_sim_s": self.settled_chunks * CHUNK,
            "seam_gap_start_m": self.gap0, "seam_gap_sewn_m": self.gap_sewn,
            "seam_gap_m": self.open_gap[self.worst], "worst_seam": self.worst,
            "seam_gaps_m": self.open_gap,
            "strain_after_weld": float(self.strain_weld),
            # after the weld's push out of the body, and after its strain relief (settling
            # starts from there)
            "strain_after_push": float(self.strain_pushed),
            "strain_settle_start": float(self.strain_settle_start),
            "strain_before_relief": float(self.strain_settled),
            "relief_rounds": self.relief_rounds,
            "settle_collisions": int(self.settle_collisions),
            "settle_retries": int(self.settle_retries),
            "sharp_pushes": int(self.sharp), "sharp_push_max_mm": self.sharp_mm,
            "max_strain": float(self.strain),   # after the relief (the velocities zeroed since)
            "settle_speed_rms_m_s": float(self.speed),
            "settle_speed_p99_m_s": _p99_move(st.positions, prev) / CHUNK,
            "settle_speed_max_m_s": max_move(st.positions, prev) / CHUNK,
            "settled": bool(self.speed < self.settings.settle_speed),
            "settle_speeds_m_s": self.speeds,
            "slowed_points": int(self.clock.get("slowed", 0)),
            "sewing_s": self.t_sewn - self.t_start, "settling_s": self.t_end - self.t_sewn,
            "dressing_s": self.t_end - self.t_start,
        }
