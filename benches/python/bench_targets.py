"""The steady state's speed targets, for two or more builds timed alternately in one run.

    python benches/python/bench_targets.py [--build DIR ...] [--rounds 3] [--markdown]

Each ``--build`` is a directory that holds a ``multicrank`` package with its release extension
built in place (``maturin develop --release --skip-install`` in a checkout puts it in
``python/``; for an old commit: ``git worktree add /tmp/old REV`` and build there); default
this checkout's ``python/``. Each round runs every build once, one after the other, in child
processes (``PYTHONPATH`` the build's directory), so that a shared host's changing load
disturbs both alike; each figure is a build's best over the rounds.

What is timed (the figures of issue 37's sixth item):

- one thread (``RAYON_NUM_THREADS=1``), per built-in machine: ``mc.steady_state(m).delta``
  warm; the first call on a machine (a fresh ``Machine.replace`` copy each time, its native
  machine and tables made in the call); ``.omega`` of ``mc.steady_state(m, points=1441)``;
  ``mc.bearing_loads(m)`` at its constant speed and with ``steady=True``;
- all cores: ``mc.motion_sweep`` of the "inline-4" preset along one axis of each kind, every
  design its own machine (but for speed × inertia, 64 × 64), δ with and without gravity, and
  two with ``max_bearing_load``, in designs per second (each sweep's best of three passes); and
  ``mc.firing_orders`` of "genset-v12" (every criterion; pandas imported, the machine's
  own native machine warm), wall time.

A report, never a test. Refuses a debug build.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

SERIAL = r"""
import json, sys, time
import multicrank as mc
if mc.build_profile != "release":
    sys.exit(f"refusing to time a {mc.build_profile} build")

def best(call, n, rounds=5):
    times = []
    for _ in range(rounds):
        start = time.perf_counter()
        for _ in range(n):
            call()
        times.append((time.perf_counter() - start) / n)
    return min(times)

rows = {}
for name, machine in mc.presets.MACHINES.items():
    if machine.rpm is None:
        continue
    mc.steady_state(machine).delta
    row = {"delta": best(lambda: mc.steady_state(machine).delta, 200)}
    firsts = []
    for _ in range(5):
        copies = [machine.replace(shaft_inertia=machine.shaft_inertia * (1 + 1e-9 * i)) for i in range(20)]
        start = time.perf_counter()
        for copy in copies:
            mc.steady_state(copy).delta
        firsts.append((time.perf_counter() - start) / len(copies))
    row["first"] = min(firsts)
    row["omega_1441"] = best(lambda: mc.steady_state(machine, points=1441).omega, 30)
    mc.bearing_loads(machine)
    row["bearing_loads"] = best(lambda: mc.bearing_loads(machine), 30)
    row["bearing_loads_steady"] = best(lambda: mc.bearing_loads(machine, steady=True), 10)
    rows[name] = row
print(json.dumps(rows))
"""

PARALLEL = r"""
import json, sys, time
import numpy as np
import pandas  # imported before the clock starts, as in a session
import multicrank as mc

def fastest(call, passes=3):
    # A sweep's best of a few passes: one pass of a few tens of ms is what a shared host's
    # load moves (rows that this round's work did not touch read 10-25 % apart).
    times = []
    for _ in range(passes):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return min(times)

machine = mc.presets.MACHINES["inline-4"]
cylinder = machine.cylinders[0]
n = 4096
rpm = np.linspace(1500, 6000, 64)
# Every design its own machine along each axis but the first (no two designs share tables).
axes = {
    "rpm x shaft_inertia (64 x 64)": dict(rpm=rpm, shaft_inertia=np.linspace(0.1, 0.5, 64)),
    "counterweight_mass": dict(counterweight_mass=np.linspace(0.5, 2.0, n)),
    "counterweight_radius": dict(counterweight_radius=cylinder.counterweight_radius * np.linspace(0.8, 1.2, n)),
    "bore": dict(bore=cylinder.bore * np.linspace(0.9, 1.1, n)),
    "pressure_scale": dict(pressure_scale=np.linspace(0.8, 1.2, n)),
    "rod_length": dict(rod_length=cylinder.rod_length * np.linspace(0.9, 1.1, 1024)),
    "crank_radius": dict(crank_radius=cylinder.crank_radius * np.linspace(0.95, 1.05, 1024)),
}
outputs = ["delta", "delta_without_gravity"]
rows = {}
for name, columns in axes.items():
    grid = mc.MachineGrid(machine, **columns)
    mc.motion_sweep(machine, grid.frame(0, 8), outputs=outputs)  # the base machine's tables made
    rows[name] = len(grid) / fastest(lambda: mc.motion_sweep(machine, grid, outputs=outputs))
for name, columns in {
    "max_bearing_load: counterweight_mass": dict(counterweight_mass=np.linspace(0.5, 2.0, n)),
    "max_bearing_load: rod_length": dict(rod_length=cylinder.rod_length * np.linspace(0.9, 1.1, 1024)),
}.items():
    grid = mc.MachineGrid(machine, **columns)
    mc.motion_sweep(machine, grid.frame(0, 8), outputs=["delta", "max_bearing_load"])
    rows[name] = len(grid) / fastest(lambda: mc.motion_sweep(machine, grid, outputs=["delta", "max_bearing_load"]))
v12 = mc.presets.MACHINES["genset-v12"]
mc.firing_orders(v12.replace(name="warm-up"))
times = []
for _ in range(2):
    start = time.perf_counter()
    mc.firing_orders(v12)
    times.append(time.perf_counter() - start)
rows["firing_orders genset-v12 [s]"] = min(times)
print(json.dumps(rows))
"""


def run(build: Path, code: str, threads: str | None) -> dict:
    env = dict(os.environ, PYTHONPATH=str(build), OPENBLAS_NUM_THREADS="1")
    if threads is None:
        env.pop("RAYON_NUM_THREADS", None)
    else:
        env["RAYON_NUM_THREADS"] = threads
    found = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    if found.returncode:
        sys.exit(f"{build}: {found.stderr.strip()}")
    return json.loads(found.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", action="append", type=Path, help="a directory holding a built multicrank")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args()
    builds = args.build or [ROOT / "python"]
    serial: list[dict] = [{} for _ in builds]
    parallel: list[dict] = [{} for _ in builds]
    for _ in range(args.rounds):
        for i, build in enumerate(builds):
            for machine, row in run(build, SERIAL, "1").items():
                kept = serial[i].setdefault(machine, row)
                for key, value in row.items():
                    kept[key] = min(kept[key], value)
            for key, value in run(build, PARALLEL, None).items():
                # designs/s: the best is the largest; the firing orders' seconds the smallest
                better = min if key.endswith("[s]") else max
                parallel[i][key] = better(parallel[i].get(key, value), value)
    names = [str(b) for b in builds]
    print("one thread [µs] (each build: " + ", ".join(names) + ")")
    header = ["machine", "delta", "first", "omega_1441", "bearing_loads", "bearing_loads_steady"]
    print(("| " + " | ".join(header) + " |") if args.markdown else "  ".join(header))
    for machine in serial[0]:
        cells = [machine]
        for key in header[1:]:
            cells.append(" / ".join(f"{s[machine][key] * 1e6:.0f}" for s in serial))
        print(("| " + " | ".join(cells) + " |") if args.markdown else "  ".join(cells))
    print("all cores")
    for key in parallel[0]:
        values = " / ".join(f"{p[key]:.3g}" for p in parallel)
        print(f"| {key} | {values} |" if args.markdown else f"{key}: {values}")


if __name__ == "__main__":
    main()
