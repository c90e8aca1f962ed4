"""Stepping the dressed cloth on the body: what dressing and walking both run.

:func:`advance` simulates an interval with ``n`` collider resolves evenly spread and the cloth
solver's own stable step between them; each resolve (:func:`resolve_contacts`) is a detection
— the body's collider, then the floor, each a contact source (:mod:`catwalk.simulate.contacts`)
— then Provot's position correction so the
cloth round the pushed points follows them, then a speed cap. :func:`collisions_for` picks
``n`` from how far things moved. A blown-up interval is run again from its start with twice the
resolves (up to a limit).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np

from catwalk.cloth.contact_planes import cap_speed
from catwalk.cloth.model import ClothModel
from catwalk.cloth.solvers import ClothExplosionError
from catwalk.cloth.solvers.explicit.solver import Solver
from catwalk.cloth.state import State
from catwalk.errors import Cancelled
from catwalk.simulate.contacts import Floor, body_contacts, contacts_of, keep
from catwalk.simulate.settings import Settings

ORDER_TOLERANCE = 0.05   # recompute the strain-limit order when 5 % of the contacts changed
# m/s. Cloth on a walking body moves at most a few m/s (a swinging hand ≈ 4); a point faster
# than this after a collision response is a local conflict (the body pushing cloth against
# its own springs) ringing at the springs' frequency; it is slowed down to this and counted
# (metrics: ``slowed_points``) instead of growing into a blow-up.
MAX_CLOTH_SPEED = 10.0


def never() -> bool:
    return False


def quiet(stage: str, i: int, total: int) -> None:
    pass


def collide_and_floor(state: State, collider, x0: np.ndarray, alpha: float | None,
                      final: bool = False) -> None:
    """One detection: the body's contacts (the collider at ``alpha``; ``final``: the frame
    kept), then the floor's; the state keeps the held points and their contact planes (the
    body's, the floor's for points on it that the body does not hold) until the next
    response."""
    body = body_contacts(collider, state, x0, alpha, final)
    keep(state, body, contacts_of(Floor(collider.thickness, collider.friction), state))


def resolve_contacts(solver: Solver, model: ClothModel, state: State, collider, x0: np.ndarray,
                     h: float, alpha: float | None = None, clock: dict | None = None) -> int:
    """One collision response: the body (the collider), the floor, then Provot's correction
    so the cloth round the pushed points follows them (over the ``h`` seconds since the last
    response), then no point faster than ``MAX_CLOTH_SPEED``. Returns how many points had to
    be slowed down (reported: a healthy run slows none). ``clock`` accumulates the seconds of
    Provot's correction (``"correction"``)."""
    collide_and_floor(state, collider, x0, alpha)
    t = time.perf_counter()
    solver.after_collision(model, state, h)
    if clock is not None:
        clock["correction"] = clock.get("correction", 0.0) + time.perf_counter() - t
    return int(cap_speed(state.velocities, MAX_CLOTH_SPEED))


def advance(solver: Solver, model: ClothModel, state: State, collider, duration: float,
            collisions: int, x0: np.ndarray, max_collisions: int | None = None,
            clock: dict | None = None, cancel: Callable[[], bool] | None = None,
            last_response: bool = True) -> int:
    """Simulate ``duration`` seconds with ``collisions`` collider resolves evenly spread (the
    k-th at ``alpha = k/collisions`` of the body's motion over the interval); the solver's own
    time step (below its stability bound) runs in between. ``last_response=False``: none
    after the interval's last stretch (the caller closes it with a response of its own at
    the same pose).

    If the cloth blows up (:class:`ClothExplosionError`), the interval is run again from its
    start with twice the resolves, up to ``max_collisions`` (default: no retry) — cloth that
    sank too far between two resolves is shoved out violently; closer resolves keep it out.
    Returns the number of resolves that succeeded. ``clock`` accumulates seconds spent in the
    cloth solver (``"cloth"``) and in collision response (``"collider"``: the collider, the
    floor, Provot's correction — that alone also as ``"correction"``), and the points slowed
    to ``MAX_CLOTH_SPEED`` (``"slowed"``).
    ``cancel()`` is asked before every resolve (:class:`Cancelled` when it says so)."""
    limit = collisions if max_collisions is None else max(collisions, max_collisions)
    start = state.copy()
    while True:
        try:
            h = duration / collisions
            for k in range(collisions):
                if cancel is not None and cancel():
                    raise Cancelled("try-on cancelled")
                x0[:] = state.positions
                t0 = time.perf_counter()
                solver.step(model, state, None, h)
                t1 = time.perf_counter()
                slowed = resolve_contacts(solver, model, state, collider, x0, h,
                                          alpha=(k + 1) / collisions, clock=clock) \
                    if last_response or k + 1 < collisions else 0
                if clock is not None:
                    clock["slowed"] = clock.get("slowed", 0) + slowed
                    clock["cloth"] = clock.get("cloth", 0.0) + t1 - t0
                    clock["collider"] = clock.get("collider", 0.0) + time.perf_counter() - t1
            return collisions
        except ClothExplosionError:
            if collisions >= limit:
                raise
            restore(state, start)
            collisions = min(2 * collisions, limit)


def restore(state: State, saved: State) -> None:
    state.positions[:] = saved.positions
    state.velocities[:] = saved.velocities
    state.held[:] = saved.held
    state.time, state.steps, state.failed = saved.time, saved.steps, None
    state.planes = None if saved.planes is None else saved.planes.copy()
    state.plane_time = saved.plane_time


def collisions_for(move: float, settings: Settings) -> int:
    """Collider resolves per 1/30 s for a cloth/body that moved ``move`` metres in it (the
    implicit integrator: its steps a frame, whatever the motion — its step, and so its
    factored matrix, stays the same —, a response after each but the last, which the frame's
    closing response follows)."""
    if settings.integrator == "implicit":
        return max(1, round(1.0 / (30.0 * settings.implicit_dt)))
    n = math.ceil(move / settings.max_move) if move > 0 else 1
    return int(min(max(n, settings.min_collisions), settings.max_collisions))


def max_move(a: np.ndarray, b: np.ndarray) -> float:
    d = a - b
    return float(np.sqrt(np.max(np.sum(d * d, axis=1)))) if len(d) else 0.0
