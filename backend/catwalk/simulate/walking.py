"""The walk (paper §6): the dressed garment follows the body through a motion.

The body is skinned for every frame up front (its velocities by central differences). The
cloth starts from the settled drape on the body's rest pose; the body then blends from its rest
pose into the motion's first pose over ``settings.blend_seconds`` (joint rotations nlerped,
translations lerped) so the first recorded frames do not jerk, and then plays the motion.
Per 30-fps frame the collider is updated once and resolved ``n`` times, ``n`` from the body's
fastest vertex (it moves at most ``settings.max_move`` between two resolves, clamped to
``min_collisions`` … ``max_collisions``; a frame whose cloth blows up is run again with twice
the resolves, up to 4 × ``max_collisions``); the cloth solver runs at its own stable step in
between, and after each resolve Provot's position correction
(:meth:`~catwalk.cloth.solvers.explicit.solver.Solver.after_collision`) lets the cloth round the
pushed points follow them. One more resolve at the frame's time ends every frame, so the recorded
positions are the body's (that correction may pull free points a little into the body: measured on
the small try-on test, a swinging hand left a skirt point 4.5 mm inside without it, 0 with it).
Recorded: the cloth on every motion frame, per pattern point (so each panel keeps its
UVs), and the costs and errors of every frame.
"""

from __future__ import annotations

import copy
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from catwalk.body.skinning import body_frames
from catwalk.body.types import Motion
from catwalk.cloth.solvers import ClothExplosionError
from catwalk.cloth.solvers.explicit.solver import Solver
from catwalk.collide import make_collider
from catwalk.collide.kernels.stats import STAT_NAMES
from catwalk.errors import Cancelled
from catwalk.geometry.surface import BodySurface, segments_crossing
from catwalk.simulate.dressing import Dressed
from catwalk.simulate.garment_cloth import seam_gaps
from catwalk.simulate.settings import PRESETS, Settings
from catwalk.simulate.stepping import (
    ORDER_TOLERANCE,
    advance,
    collide_and_floor,
    collisions_for,
    max_move,
    never,
    quiet,
)


def strain_of(model, x: np.ndarray) -> np.ndarray:
    """Strain (|x_b − x_a|/rest − 1) of every stretch/shear spring."""
    n = model.n_limited
    d = x[model.spring_b[:n]] - x[model.spring_a[:n]]
    return np.sqrt(np.sum(d * d, axis=1)) / model.spring_rest[:n] - 1.0


@dataclass
class Walked:
    times: np.ndarray            # (F,) seconds on the motion's clock
    positions: np.ndarray        # (F, P, 3) float32, per pattern point
    stats: dict = field(default_factory=dict)


def _quat_rest(skeleton) -> tuple[np.ndarray, np.ndarray]:
    from scipy.spatial.transform import (
        Rotation,  # deferred: scipy loads in ≈ 0.3 s; only this path needs it
    )  # deferred: scipy loads in ≈ 0.3 s; only this path needs it

    r = skeleton.rest_local
    return Rotation.from_matrix(r[:, :3, :3]).as_quat(), r[:, :3, 3].copy()


def blend_frame_count(settings: Settings, fps: float) -> int:
    """Frames of the blend from the rest pose into the walk (not recorded)."""
    return int(round(settings.blend_seconds * fps))


def blend_motion(body, motion: Motion, seconds: float) -> Motion:
    """Frames from the body's rest pose to the motion's first pose (exclusive) at its fps."""
    n = int(round(seconds * motion.fps))
    q0, t0 = _quat_rest(body.skeleton)
    q1, t1 = motion.rotations[0], motion.translations[0]
    q0 = np.where((np.sum(q0 * q1, axis=1) < 0)[:, None], -q0, q0)
    rots, trs = [], []
    for i in range(n):
        s = i / n
        s = s * s * (3 - 2 * s)   # ease in and out
        q = (1 - s) * q0 + s * q1
        rots.append(q / np.linalg.norm(q, axis=1, keepdims=True))
        trs.append((1 - s) * t0 + s * t1)
    if n == 0:
        return Motion(motion.fps, np.zeros((0,) + q1.shape), np.zeros((0,) + t1.shape), False)
    return Motion(motion.fps, np.array(rots), np.array(trs), loop=False)


def walk_body_frames(body, motion: Motion, settings: Settings, *,
                progress: Callable[[str, int, int], None] | None = None,
                cancel: Callable[[], bool] | None = None):
    """The body's vertices and velocities (F, V, 3) float32 at every frame the walk steps
    through: the rest pose the garment was dressed on, the blend into the motion, the motion;
    and how many frames come before the motion's first (``n_pre``: not recorded)."""
    progress = progress or quiet
    pre = blend_motion(body, motion, settings.blend_seconds)
    full = Motion(motion.fps, np.concatenate([pre.rotations, motion.rotations]),
                  np.concatenate([pre.translations, motion.translations]), loop=False)
    verts, vels = body_frames(body, full, cancel=cancel,
                              progress=progress)
    rest = body.vertices.astype(np.float32)
    verts = np.concatenate([rest[None], verts])
    vels = np.concatenate([np.zeros_like(rest)[None], vels])
    return verts, vels, len(pre.rotations) + 1


def walk(body, motion: Motion, dressed: Dressed, settings: Settings | None = None, *,
         progress: Callable[[str, int, int], None] | None = None,
         cancel: Callable[[], bool] | None = None, measure: bool = True) -> Walked:
    """Play ``motion`` on ``body`` with the ``dressed`` garment following (module docstring).
    ``measure``: also measure penetration with the independent check of
    :mod:`catwalk.geometry.surface` on every frame (costs ≈ 20 ms a frame)."""
    settings = (settings or PRESETS["balanced"]).check()
    progress = progress or quiet
    cancel = cancel or never
    t_body = time.perf_counter()
    verts, vels, n_pre = walk_body_frames(body, motion, settings, progress=progress, cancel=cancel)
    t_body = time.perf_counter() - t_body
    frame_dt = 1.0 / motion.fps
    model, state = dressed.model, dressed.state.copy()
    friction = dressed.cloth.fabric.friction if settings.friction is None else settings.friction
    collider = make_collider(settings.collider, body.faces, body.parts, friction=friction,
                             **settings.collider_options(walking=True))
    collider.update(verts[0].astype(np.float64), vels[0].astype(np.float64))
    solver = cloth_solver(dressed, settings)
    tally = _Tally(BodySurface(body.faces, len(body.vertices)) if measure else None,
                   solver.tau)
    nf = motion.frames
    out = np.empty((nf, len(dressed.rep), 3), dtype=np.float32)
    x0 = state.positions.copy()
    counts0 = collider.stats.copy()
    timings0 = copy.copy(collider.timings)
    for f in range(1, len(verts)):
        if cancel():
            raise Cancelled("try-on cancelled")
        if f == n_pre:   # the recorded frames' collider work from here
            counts0 = collider.stats.copy()
            timings0 = copy.copy(collider.timings)
        try:
            n_col, tc, tcl, clock = _step_frame(solver, model, state, collider, verts[f - 1],
                                                verts[f], vels[f], frame_dt, x0, settings, tally,
                                                cancel)
        except ClothExplosionError as exc:
            raise ClothExplosionError(f"walk frame {f - n_pre} (t = {(f - n_pre) * frame_dt:.3f} "
                                      f"s): {exc}") from None
        rec = f - n_pre
        if rec < 0:
            progress("blending", f, n_pre - 1)
            continue
        # shown: the cloth off the body's sharp vertices (the state is left as it is);
        # collider time
        t2 = time.perf_counter()
        xs = state.positions.copy()
        n_sharp = collider.push_off_sharp(xs, model.triangles)
        tally.t_col += tc + time.perf_counter() - t2
        tally.t_cloth += tcl
        tally.t_correction += clock.get("correction", 0.0)
        tally.ncols.append(n_col)
        out[rec] = xs[dressed.rep]
        tally.frame(model, state, xs, verts[f], vels[f], n_sharp)
        progress("walking", rec + 1, nf)
    steps_per_frame = int(np.ceil(frame_dt / solver.dt_max))
    stats = {
        "frames": int(nf), "fps": float(motion.fps), "blend_frames": int(n_pre - 1),
        "points": int(model.n_points), "springs": int(model.n_springs),
        "body_triangles": int(len(body.faces)), "collider": settings.collider,
        "cloth_steps_per_frame": steps_per_frame,
        **tally.stats(model, nf, t_body * 1e3 / len(verts)),
        # the collider's counters over the recorded frames (collide.kernels.stats.STAT_NAMES), and
        # its calls: each frame's responses and its closing one
        "collider_counts": dict(zip(STAT_NAMES, (collider.stats - counts0).tolist(),
                                    strict=True)),
        "collider_calls": int(sum(tally.ncols)) + int(nf),
    }
    stats["frame_ms"] = frame_costs(stats["ms_per_frame"], collider.timings, timings0,
                                    tally.t_correction * 1e3 / max(1, nf), nf)
    return Walked(np.arange(nf) / motion.fps, out, stats)


#: what a recorded frame's collider time is spent on, in the order a frame does it (the
#: collider's :class:`~catwalk.collide.collider.Timings`, CPU seconds of the walking thread)
FRAME_STAGES = (("normals", "normals"), ("refits", "refit"), ("maps", "maps"),
                ("image_look_ups", "image_queries"), ("object_passes", "object_queries"),
                ("sharp_push", "sharp"))


def frame_costs(ms: dict, timings, timings0, correction_ms: float, frames: int) -> dict:
    """ms per recorded frame of each stage (:data:`FRAME_STAGES`, Provot's position
    correction after each response, the cloth's steps) and ``other`` (the rest of the
    collider's and the cloth's time: the floor, the speed cap, the responses' bookkeeping)."""
    n = max(1, frames)
    out = {name: 1e3 * (getattr(timings, key) - getattr(timings0, key)) / n
           for name, key in FRAME_STAGES}
    out["position_correction"] = correction_ms
    out["cloth_steps"] = ms["cloth"]
    out["other"] = ms["collider"] + ms["cloth"] - sum(out.values())
    return {k: round(v, 2) for k, v in out.items()}


def cloth_solver(dressed: Dressed, settings: Settings) -> Solver:
    """The walk's cloth solver: the settings' integrator, strain limit and step, held points
    free in the limit, seam springs for any pair left open."""
    model = dressed.model
    m_med = float(np.median(dressed.cloth.model.mass))
    w = settings.sew_omega
    common = dict(held_fixed=False, sewing=len(model.seam_a) > 0, safety=settings.step_safety,
                  order_tolerance=ORDER_TOLERANCE, seam_stiffness=w * w * m_med,
                  seam_damping=2.0 * w * m_med)
    if settings.integrator == "implicit":
        from catwalk.cloth.solvers.implicit import ImplicitSolver

        return ImplicitSolver(model, settings.method, dt=settings.implicit_dt,
                              iterations=settings.implicit_iterations, **common)
    return Solver(model, settings.method, integrator=settings.integrator,
                  xpbd_dt=settings.xpbd_dt, xpbd_iterations=settings.xpbd_iterations, **common)


def _step_frame(solver, model, state, collider, v_prev, v_next, vel_next, frame_dt, x0,
                settings: Settings, tally, cancel) -> tuple[int, float, float, dict]:
    """One frame: the collider given the body's next pose, the cloth advanced over the frame
    with its resolves, then one resolve at the frame's time. Returns the resolves, the
    collider's seconds, the cloth's and the stepping's clock (:func:`advance`)."""
    n_col = collisions_for(max_move(v_next, v_prev), settings)
    clock = {}
    t0 = time.perf_counter()
    collider.update(v_next.astype(np.float64), vel_next.astype(np.float64), substeps=n_col)
    tc = time.perf_counter() - t0
    # the implicit walk: no response after the frame's last step — the frame's closing one
    # below is at the same pose (docs/cloth.md: one response a frame less, ≈ 1–1.7 ms)
    last = settings.integrator != "implicit"
    n_col = advance(solver, model, state, collider, frame_dt, n_col, x0,
                    settings.max_collisions * 4, clock, cancel, last_response=last) - (not last)
    # the relaxation may have pulled free points into the body: settle the frame's final
    # positions against the body as it is at the frame's time (the frame recorded: the
    # pushed points looked at again, each searched afresh)
    t2 = time.perf_counter()
    collide_and_floor(state, collider, x0, 1.0, final=True)
    tc += time.perf_counter() - t2 + clock.get("collider", 0.0)
    tally.slowed += clock.get("slowed", 0)
    return n_col, tc, clock.get("cloth", 0.0), clock


#: a spring longer than (1 + τ + this)·rest counts as over the limit (issue 21's bound on the
#: walk's maximum strain: τ + 2 %)
OVER_LIMIT = 0.02
#: at most this many of a frame's springs over the limit (the longest) are tested against the
#: body (each test visits every body triangle, box-culled: 38–64 µs on the 26,756-triangle
#: body, the paper scene at h 1 and 1.77 cm): a torn walk is not slowed down by its own check
MAX_CROSSING_TESTS = 256
#: m/s. A point moving slower than this relative to the body's surface where it is nearest is
#: at rest there: the share of such point-frames (``resting_share``) is what a skip letting
#: resting points sleep could save in a walk
REST_SPEED = 0.01


@dataclass
class _Tally:
    """What the walk keeps of its recorded frames: their costs and errors."""
    surface: BodySurface | None
    tau: float = 0.0
    t_col: float = 0.0
    t_cloth: float = 0.0
    t_correction: float = 0.0
    slowed: int = 0
    sharp: int = 0
    sharp_mm: float = 0.0
    seam_gap: float = 0.0
    ncols: list = field(default_factory=list)
    strains: list = field(default_factory=list)
    strains99: list = field(default_factory=list)
    kinetic: list = field(default_factory=list)
    pen_max: list = field(default_factory=list)
    pen_p99: list = field(default_factory=list)
    over: int = 0
    over_crossing: int = 0
    resting: int = 0
    point_frames: int = 0

    def frame(self, model, state, xs, body_vertices, body_velocities, n_sharp: int) -> None:
        """A recorded frame's errors: the simulated ``state``, the shown ``xs``; and how
        many points rest on the body (``body_velocities``: its vertices')."""
        if n_sharp:
            self.sharp += n_sharp
            self.sharp_mm = max(self.sharp_mm, max_move(xs, state.positions))
        # the cloth's own motion: kinetic energy relative to its centre of mass (the walk's
        # forward motion, the same in every frame, taken out)
        v = state.velocities - (model.mass @ state.velocities) / model.mass.sum()
        self.kinetic.append(0.5 * float(model.mass @ np.einsum("ij,ij->i", v, v)))
        e = strain_of(model, state.positions)
        self.strains.append(float(e.max()) if len(e) else 0.0)
        self.strains99.append(float(np.percentile(e, 99)) if len(e) else 0.0)
        if len(model.seam_a):
            self.seam_gap = max(self.seam_gap, float(seam_gaps(model, state.positions).max()))
        if self.surface is not None:   # of what is shown
            _, d, tri, bary = self.surface.closest(body_vertices, xs)
            pen = np.maximum(-d, 0.0)
            vb = np.einsum("pk,pkj->pj", bary, body_velocities[self.surface.faces[tri]])
            rel = np.linalg.norm(state.velocities - vb, axis=1)
            self.resting += int(np.count_nonzero(rel < REST_SPEED))
            self.point_frames += len(rel)
            self.pen_max.append(float(pen.max()))
            self.pen_p99.append(float(np.percentile(pen, 99)))
            # the springs over the limit, and of those the ones across a body part
            over = np.flatnonzero(e > self.tau + OVER_LIMIT)
            if len(over):
                self.over += len(over)
                if len(over) > MAX_CROSSING_TESTS:
                    over = over[np.argsort(e[over])[-MAX_CROSSING_TESTS:]]
                x = state.positions
                hits = segments_crossing(body_vertices, self.surface.faces,
                                         x[model.spring_a[over]], x[model.spring_b[over]])
                self.over_crossing += int(np.count_nonzero(hits))

    def stats(self, model, frames: int, body_ms: float) -> dict:
        """The walk's statistics of its costs and errors (docs/tryon.md, metrics.json)."""
        nrec = max(1, frames)
        ncols = self.ncols
        out = {
            "collisions_per_frame": {"min": int(min(ncols)), "max": int(max(ncols)),
                                     "mean": float(np.mean(ncols))} if ncols else None,
            "ms_per_frame": {"body": body_ms, "collider": self.t_col * 1e3 / nrec,
                             "cloth": self.t_cloth * 1e3 / nrec,
                             "total": (self.t_col + self.t_cloth) * 1e3 / nrec + body_ms},
            "max_strain": float(max(self.strains)) if self.strains else 0.0,
            "p99_strain": float(max(self.strains99)) if self.strains99 else 0.0,
            "max_seam_gap_mm": 1e3 * self.seam_gap, "open_seam_pairs": int(len(model.seam_a)),
            "exploded": False, "nan": False,   # either aborts the walk with ClothExplosionError
            "slowed_points": int(self.slowed), "sharp_pushes": int(self.sharp),
            "sharp_push_max_mm": 1e3 * self.sharp_mm,
            "internal_kinetic_j_per_frame": [round(k, 7) for k in self.kinetic],
        }
        if self.surface is not None and self.pen_max:
            out["max_penetration_mm"] = 1e3 * max(self.pen_max)
            out["p99_penetration_mm"] = 1e3 * float(np.percentile(self.pen_p99, 99))
            out["penetration_mm_per_frame"] = [round(1e3 * p, 2) for p in self.pen_max]
            out["springs_over_limit"] = self.over
            out["over_limit_crossing_body"] = self.over_crossing
            out["resting_share"] = round(self.resting / max(1, self.point_frames), 5)
        return out
