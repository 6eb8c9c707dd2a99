"""The design aid against the per-machine path, same process.

    python benches/python/bench_design_aid.py [--markdown]

For built-in machines (and a 16-cylinder four-stroke V, the largest crank whose 2^15 phase
choices the firing search covers):

- ``mc.firing_orders`` (wall time, the whole call: candidates, telling alike motions apart,
  one motion sweep of the distinct ones, the torque orders); its motion sweep alone (the
  distinct candidates as ``"phase[j]"`` columns, δ with and without gravity), and the
  baseline for it: the same candidates each built with ``Machine.replace`` and solved by
  ``mc.steady_state`` one machine at a time;
- ``mc.optimize_counterweights`` (objective "delta", seed 0; wall time, steady states
  solved), and the baseline: the same number of steady states one machine at a time (timed
  on 40 machines with other counterweights and scaled).

With all cores (the core's rayon pool; two on this project's machines). Refuses a debug
build of the extension.
"""

from __future__ import annotations

import argparse
import os
import time

from timing import cpu_name

BASELINE_MACHINES = 40


def machines():
    import multicrank as mc

    chosen = {name: mc.presets.MACHINES[name] for name in ("slow-compressor", "inline-4", "inline-6", "genset-v12")}
    base = mc.presets.MACHINES["genset-v12"]
    eight = mc.Machine.from_layout("inline-8-4t", base.cylinders[0], shaft_inertia=50.0, strokes=4)
    banks = [c.replace(inclination=c.inclination - 1.0, phase=c.phase + 1.0) for c in eight.cylinders]
    chosen["v16 (hand-built)"] = mc.Machine(
        [*eight.cylinders, *banks], shaft_inertia=60.0, strokes=4, rpm=1500.0, name="v16"
    )
    return chosen


def per_machine(machines_to_solve, rpm) -> float:
    """Seconds to solve each machine by steady_state, one at a time, δ and δ₀ read."""
    import multicrank as mc

    start = time.perf_counter()
    for machine in machines_to_solve:
        state = mc.steady_state(machine, rpm=rpm)
        _ = state.delta, state.delta_without_gravity
    return time.perf_counter() - start


def measure(name, machine) -> dict:
    import numpy as np

    import multicrank as mc

    start = time.perf_counter()
    table = mc.firing_orders(machine)
    firing = time.perf_counter() - start
    import pandas as pd

    phases = np.array(table["phases"].tolist())
    designs = pd.DataFrame({f"phase[{j}]": phases[:, j] for j in range(len(machine))})
    start = time.perf_counter()
    mc.motion_sweep(machine, designs, outputs=["delta", "delta_without_gravity"])
    firing_sweep = time.perf_counter() - start
    build = time.perf_counter()
    candidates = [
        machine.replace(cylinders=[c.replace(phase=a) for c, a in zip(machine.cylinders, p, strict=True)])
        for p in table["phases"]
    ]
    build = time.perf_counter() - build
    firing_baseline = build + per_machine(candidates, machine.rpm)

    start = time.perf_counter()
    best = mc.optimize_counterweights(machine)
    optimum = time.perf_counter() - start
    rng = np.random.default_rng(0)
    sample = [
        machine.replace(cylinders=[c.replace(counterweight_mass=c.counterweight_mass * rng.uniform(0.5, 1.5))
                                   for c in machine.cylinders])
        for _ in range(BASELINE_MACHINES)
    ]  # fmt: skip
    start = time.perf_counter()
    for machine_ in sample:
        _ = mc.steady_state(machine_).delta
    per_design = (time.perf_counter() - start) / BASELINE_MACHINES
    return dict(
        name=name,
        cylinders=len(machine),
        candidates=table.attrs["candidates"],
        distinct=table.attrs["distinct"],
        firing=firing,
        firing_sweep=firing_sweep,
        firing_baseline=firing_baseline,
        optimum=optimum,
        nfev=best.nfev,
        optimum_baseline=per_design * best.nfev,
        improvement=best.improvement,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = parser.parse_args()

    import multicrank as mc

    if mc.build_profile != "release":
        raise SystemExit(f"bench_design_aid: refusing a {mc.build_profile} build; install the release wheel")
    rows = [measure(name, machine) for name, machine in machines().items()]
    if args.markdown:
        cpu = cpu_name()
        print(f"CPU: {cpu}, {os.cpu_count()} cores, all used")
        print()
        print(
            "| machine | cylinders | candidates → distinct | firing_orders (s) | its motion sweep (s) "
            "| per machine (s) | ratio | optimize_counterweights (s) | steady states | per machine (s) | ratio |"
        )
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for r in rows:
            print(
                f"| {r['name']} | {r['cylinders']} | {r['candidates']} → {r['distinct']} | {r['firing']:.2f} "
                f"| {r['firing_sweep']:.3f} | {r['firing_baseline']:.3f} "
                f"| {r['firing_baseline'] / r['firing_sweep']:.1f}× "
                f"| {r['optimum']:.2f} "
                f"| {r['nfev']} | {r['optimum_baseline']:.1f} | {r['optimum_baseline'] / r['optimum']:.1f}× |"
            )
    else:
        for r in rows:
            print(r)


if __name__ == "__main__":
    main()
