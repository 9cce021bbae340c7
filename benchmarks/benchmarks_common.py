"""Helpers shared by the benchmark scripts."""

from __future__ import annotations

import os
import statistics
import time


def pin_to_one_core() -> None:
    """Measure on one core, as the project's figures are stated."""
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})


def median_ms(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times)
