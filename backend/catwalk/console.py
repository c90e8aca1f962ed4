"""What catwalk's commands write to a terminal while they work: the progress bar (the try-on's
and the benchmarks' walks; ``catwalk tryon``, ``catwalk demo``, ``catwalk bench paper``)."""

from __future__ import annotations

import sys
import time


class ProgressBar:
    """The try-on's overall progress on stderr: one line redrawn in place on a terminal, a line
    every 10 % (and at each new stage) when stderr is not a terminal (e.g. in CI logs).
    A progress callback (:mod:`catwalk.progress`): ``bar(stage, done, total)``."""

    def __init__(self, stream=None, quiet: bool = False):
        self.stream = stream or sys.stderr
        self.quiet = quiet
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.stage = None
        self.t0 = time.perf_counter()
        self.last_pct = -1

    def __call__(self, stage: str, done: float, total: float = 1.0) -> None:
        if self.quiet:
            return
        fraction = done / total if total else 1.0
        pct = int(100 * fraction)
        el = time.perf_counter() - self.t0
        eta = el / fraction * (1 - fraction) if fraction > 0 else 0.0
        if self.tty:
            bar = "#" * (pct // 4) + "-" * (25 - pct // 4)
            self.stream.write(f"\r[{bar}] {pct:3d} % {stage:10s} {el:5.1f} s, "
                              f"~{eta:4.0f} s left ")
        elif pct // 10 != self.last_pct // 10 or stage != self.stage:
            self.stream.write(f"{pct:3d} % {stage}, {el:.1f} s\n")
        self.stage, self.last_pct = stage, pct
        self.stream.flush()

    def done(self) -> None:
        if self.tty and self.stage is not None and not self.quiet:
            self.stream.write("\n")
            self.stream.flush()
