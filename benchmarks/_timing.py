"""Timing shared by the benchmarks: the best of a few runs, measured in the same process."""

from __future__ import annotations

import time
from collections.abc import Callable


def best_time(fn: Callable[[], object], budget: float = 0.5, max_repeats: int = 5) -> tuple[float, object]:
    """Smallest wall time of a few runs of ``fn`` and its result (stops once ``budget`` s are spent)."""
    times, out, spent = [], None, 0.0
    while len(times) < max_repeats and (not times or spent < budget):
        t0 = time.perf_counter()
        out = fn()
        dt = time.perf_counter() - t0
        times.append(dt)
        spent += dt
    return min(times), out
