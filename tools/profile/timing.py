"""What the profiling tools beside it share: the best of a few rounds of calls."""

import time

import numpy as np


def best_us(f, repeat: int) -> float:
    """The best of five rounds of ``repeat`` calls of ``f`` (after one to warm up), µs a
    call."""
    f()
    best = np.inf
    for _ in range(5):
        t = time.perf_counter()
        for _ in range(repeat):
            f()
        best = min(best, (time.perf_counter() - t) / repeat)
    return best * 1e6
