"""The one shape of a progress callback in catwalk: ``progress(stage, done, total)`` — the
work is in ``stage`` and ``done`` of its ``total`` units are done. The simulation's loops
report their own counts (``progress("walking", 12, 120)``); a try-on's overall progress is the
same call with the fraction of the whole (``progress("walking", 0.43, 1.0)``:
:class:`catwalk.simulate.progress.Progress` turns the first into the second); the body's
registration to a scan reports its stages (``progress("fit", 2, 5)``)."""

from __future__ import annotations

from collections.abc import Callable

#: ``progress(stage, done, total)``
ProgressFn = Callable[[str, float, float], None]


def quiet(stage: str, done: float, total: float) -> None:
    """A progress callback that reports nothing."""


def fraction(done: float, total: float) -> float:
    """``done / total`` (1 when there is nothing to do)."""
    return done / total if total else 1.0
