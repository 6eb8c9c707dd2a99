"""The one timing rule of the Python benches: best of several runs of enough calls each."""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path
from typing import Any


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


def child_rows(script: str, *arguments: str, threads: str = "1") -> Any:
    """The JSON that ``script --child ARGUMENTS`` prints on its last line, run in a fresh
    interpreter with ``threads`` rayon threads (rayon fixes its pool at first use, so each
    count needs its own process) and one BLAS thread."""
    child = subprocess.run(
        [sys.executable, script, "--child", *arguments],
        env=dict(os.environ, RAYON_NUM_THREADS=threads, OPENBLAS_NUM_THREADS="1"),
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(child.stdout.strip().splitlines()[-1])


def per_thread_count(script: str, points: int, repeat: int) -> dict[str, list]:
    """Run ``script --child --points P --repeat R`` once with one rayon thread and once with
    all cores, and return each child's JSON rows by thread count."""
    arguments = ("--points", str(points), "--repeat", str(repeat))
    return {threads: child_rows(script, *arguments, threads=threads) for threads in ("1", str(os.cpu_count()))}


def cpu_name() -> str:
    """The processor's model name, as the benches' tables print it."""
    cpuinfo = Path("/proc/cpuinfo")
    lines = cpuinfo.read_text().splitlines() if cpuinfo.exists() else []
    found = (line.split(":", 1)[1].strip() for line in lines if line.startswith("model name"))
    return next(found, platform.processor() or platform.machine() or "?")
