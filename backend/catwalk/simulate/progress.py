"""A try-on's progress: one overall fraction 0..1 and the stage's name, and its cancellation.

The stages and their weights are known before any work starts (:func:`tryon_plan`, from the
settings and the walk's length), so the fraction is meaningful from the first report: each
stage owns a slice of 0..1 in proportion to its expected cost, and a report ``(stage, i,
total)`` from the simulation lands at ``i/total`` of its slice. The fraction never goes back
(a stage that ends early — sewing that closed every seam — jumps to its slice's end) and
reaches 1 only when the caller says the work is done.

The simulation's own loops report ``progress(stage, i, total)`` and ask ``cancel()`` a few
milliseconds apart; :class:`Progress` is both, so a caller passes one object and gets the
overall fraction reported and a :class:`~catwalk.errors.Cancelled` raised in whatever stage
the work is in.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable

from catwalk.errors import Cancelled
from catwalk.progress import ProgressFn, fraction

# Expected cost of one unit of each stage, in "one sewing chunk" units (1/30 s of simulated
# sewing on the fast preset ≈ 14 ms on the reference machine; a walk frame ≈ 2.5 of them).
# Only the proportions matter: they make the fraction grow about evenly in time.
_UNIT = {"placing": 4.0, "sewing": 1.0, "settling": 0.7, "relief": 0.1, "gait": 1.0,
         "skinning": 0.02, "blending": 2.5, "walking": 2.5, "exporting": 0.06}


def tryon_plan(settings, frames: int, blend_frames: int, walk: bool = True,
               extra: list[tuple[str, float]] | None = None) -> list[tuple[str, float]]:
    """The stages of a try-on with ``settings`` and their weights. ``frames``: walk frames
    recorded, ``blend_frames``: frames blending from the rest pose into the walk; ``walk``:
    False for a dressing alone; ``extra``: the caller's own stages after these (e.g. the
    service's export, compression and preview: :func:`export_weight`), with weights in the
    same units."""
    chunk = 1.0 / 30.0
    walk_cost = max(1.0, settings.min_collisions / 10.0)
    plan = [("placing", _UNIT["placing"]),
            ("sewing", _UNIT["sewing"] * math.ceil(settings.sew_seconds / chunk)
             * settings.sew_collisions / 10.0),
            ("settling", _UNIT["settling"] * math.ceil(settings.settle_seconds / chunk)
             * settings.settle_collisions / 5.0),
            ("relief", _UNIT["relief"] * 32)]
    if walk:
        plan += [("gait", _UNIT["gait"]),
                 ("skinning", _UNIT["skinning"] * (frames + blend_frames + 1)),
                 ("blending", _UNIT["blending"] * walk_cost * max(blend_frames, 1)),
                 ("walking", _UNIT["walking"] * walk_cost * max(frames, 1))]
    return plan + list(extra or [])


def export_weight(frames: int) -> float:
    """The weight of writing a try-on of ``frames`` frames, in :func:`tryon_plan`'s units."""
    return _UNIT["exporting"] * max(frames, 1)


class Progress:
    """Progress and cancellation of one piece of work (module docstring).

    ``plan``: ``[(stage, weight), …]`` in order; ``report(stage, fraction, 1.0)`` (the one
    progress shape, :mod:`catwalk.progress`, over the whole work) is called on every change of
    stage and whenever the fraction grew by at least ``step`` (default 0.5 %);
    ``cancel()``: asked by :meth:`check` (and by every report from the simulation)."""

    def __init__(self, plan: list[tuple[str, float]], report: ProgressFn | None = None,
                 cancel: Callable[[], bool] | None = None, step: float = 0.005):
        if not plan:
            raise ValueError("a progress plan needs at least one stage")
        total = float(sum(max(w, 0.0) for _, w in plan)) or 1.0
        self._slices: dict[str, tuple[float, float]] = {}
        at = 0.0
        for name, w in plan:
            width = max(w, 0.0) / total
            self._slices[name] = (at, width)
            at += width
        self.stages = [name for name, _ in plan]
        self._report = report
        self._cancel = cancel
        self._step = step
        self._lock = threading.Lock()
        self.fraction = 0.0
        self.stage = plan[0][0]
        self._told = -1.0
        self._told_stage: str | None = None

    # -- what the simulation calls
    def __call__(self, stage: str, i: float, total: float) -> None:
        """A report from the work: ``i`` of ``total`` done in ``stage``. Asks ``cancel()``."""
        self.check()
        self.update(stage, fraction(i, total))

    def cancelled(self) -> bool:
        """The ``cancel()`` the simulation asks (False without a cancel check)."""
        return bool(self._cancel is not None and self._cancel())

    def check(self) -> None:
        """Raise :class:`~catwalk.errors.Cancelled` if the work should stop."""
        if self.cancelled():
            raise Cancelled("try-on cancelled")

    # -- what the caller calls
    def enter(self, stage: str) -> None:
        """The work is now in ``stage`` (at its start); asks ``cancel()``."""
        self(stage, 0, 1)

    def update(self, stage: str, done: float) -> None:
        """``done`` (0..1) of ``stage``; a stage not in the plan keeps the fraction where it is."""
        lo, width = self._slices.get(stage, (None, 0.0))
        with self._lock:
            if lo is not None:
                f = lo + width * min(max(done, 0.0), 1.0)
                self.fraction = max(self.fraction, min(f, 1.0 - 1e-9))
            self.stage = stage
            fraction = self.fraction
            tell = (stage != self._told_stage or fraction - self._told >= self._step)
            if tell:
                self._told, self._told_stage = fraction, stage
        if tell and self._report is not None:
            self._report(stage, fraction, 1.0)

    def done(self, stage: str = "done") -> None:
        """The work is complete: fraction 1."""
        with self._lock:
            self.fraction, self.stage = 1.0, stage
            self._told, self._told_stage = 1.0, stage
        if self._report is not None:
            self._report(stage, 1.0, 1.0)
