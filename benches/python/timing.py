"""The one timing rule of the Python benches: best of several runs of enough calls each."""

from __future__ import annotations

import time


def best_time(function, repeat: int, min_seconds: float = 0.02) -> float:
    """Seconds per call: the best of `repeat` runs, each of enough calls to last `min_seconds`
    (a single 1-ms call is at the mercy of the shared host's scheduler; of many short runs the
    best is the undisturbed one)."""
    start = time.perf_counter()
    function()
    calls = max(1, round(min_seconds / max(time.perf_counter() - start, 1e-9)))
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(calls):
            function()
        times.append((time.perf_counter() - start) / calls)
    return min(times)
