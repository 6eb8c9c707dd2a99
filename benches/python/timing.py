"""The one timing rule of the Python benches: best of several runs of enough calls each."""

from __future__ import annotations

import json
import os
import subprocess
import sys
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


def per_thread_count(script: str, points: int, repeat: int) -> dict[str, list]:
    """Run ``script --child --points P --repeat R`` once with one rayon thread and once with
    all cores (rayon fixes its pool at first use, so each count needs its own process), and
    return each child's JSON rows by thread count."""
    results = {}
    for threads in ("1", str(os.cpu_count())):
        child = subprocess.run(
            [sys.executable, script, "--child", "--points", str(points), "--repeat", str(repeat)],
            env=dict(os.environ, RAYON_NUM_THREADS=threads),
            capture_output=True,
            text=True,
            check=True,
        )
        results[threads] = json.loads(child.stdout)
    return results
