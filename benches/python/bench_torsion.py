"""The design aid with every criterion, and the torsional merit, against the per-machine path,
same process.

    python benches/python/bench_torsion.py [--markdown]

- ``mc.firing_orders(machine, shaft=...)`` — δ, the free moments, the largest bearing load and
  the torsional merit of every candidate, the Pareto marks (wall time, the whole call) — for the
  generator set's V12 (2048 phase assignments) and a 16-cylinder V whose banks are 1 rad apart
  (an unequal crank: 32 768 assignments, the first 4096 tried — the default — and then all
  of them, once), best of three calls on a new machine each. The baseline: the same criteria
  one candidate machine at a time (``mc.steady_state``, ``mc.shaking_forces``,
  ``mc.bearing_loads``, ``mc.torsional_merit``), timed on 40 candidates and scaled to all.
- ``mc.torsional_merit`` of the twelve-cylinder two-stroke diesel on a 14-node shaft (twelve
  throws, a flywheel, the driven machine): the first call (each cylinder's orders made) and
  every later one (best of 200), against the same call on a copy of the machine each time (its
  orders made afresh).

- ``mc.Shaft.modes`` of long chains (1000 and 4000 nodes, random inertias and stiffnesses
  within a factor of 2): the lowest 5 modes and every one, wall time (best of three; every
  mode: once) and peak memory (tracemalloc, a call of its own), against the dense generalised
  eigen solver it replaced (``scipy.linalg.eigh(K, diag(J))``, 1000 nodes).

With all cores (the core's rayon pool; two on this project's machines). Refuses a debug
build of the extension.
"""

from __future__ import annotations

import argparse
import copy
import os
import time
import tracemalloc

from timing import cpu_name

SAMPLE = 40
FIRING_REPEATS = 3
REPEATS = 200


def v12():
    import multicrank as mc

    machine = mc.presets.MACHINES["genset-v12"]
    # six throws (cranks with their running gear), a flywheel, the generator's rotor
    shaft = mc.Shaft([2.5] * 6 + [40.0, 60.0], [8e6] * 5 + [6e6, 2e6], cylinder_nodes=list(machine.throw_index))
    return machine.replace(shaft=shaft)


def v16():
    import multicrank as mc

    base = mc.presets.MACHINES["genset-v12"]
    eight = mc.Machine.from_layout("inline-8-4t", base.cylinders[0], shaft_inertia=50.0, strokes=4,
                                   cylinder_spacing=0.24)  # fmt: skip
    banks = [c.replace(inclination=c.inclination - 1.0, phase=c.phase + 1.0) for c in eight.cylinders]
    cylinders = [*eight.cylinders, *banks]
    shaft = mc.Shaft([2.5] * 8 + [50.0, 80.0], [8e6] * 7 + [6e6, 2e6], cylinder_nodes=[*range(8), *range(8)])
    return mc.Machine(cylinders, shaft_inertia=60.0, strokes=4, rpm=1500.0, rpm_range=(1000.0, 1800.0),
                      name="v16 (banks 1 rad apart)", shaft=shaft)  # fmt: skip


def diesel_14():
    import multicrank as mc

    machine = mc.presets.MACHINES["slow-diesel-12"]
    nodes = list(range(len(machine.cylinders)))  # one throw a cylinder, from the front
    shaft = mc.Shaft([4.0e3] * 12 + [6.0e4, 9.0e4], [3.0e9] * 11 + [2.5e9, 1.5e9], cylinder_nodes=nodes)
    return machine.replace(shaft=shaft)


def per_candidate(machine, table, made: int) -> float:
    """Seconds for every criterion of every row's machine, one machine at a time: timed on
    SAMPLE rows (from the start of the table) and scaled to the candidates made."""
    import multicrank as mc

    rpm = table.attrs["rpm"]
    low, high = table.attrs["speed_range"]
    rows = table["machine"].iloc[:SAMPLE]
    start = time.perf_counter()
    for candidate in rows:
        state = mc.steady_state(candidate, rpm=rpm)
        _ = state.delta
        mc.shaking_forces(candidate, rpm)
        mc.bearing_loads(candidate, rpm).magnitude.max()
        mc.torsional_merit(candidate, modes=1, rpm_range=(low, high))
    return (time.perf_counter() - start) / len(rows) * made


def measure_firing(machine, max_candidates: int = 4096, repeats: int = FIRING_REPEATS) -> dict:
    """The best of ``repeats`` calls, each on a new machine equal to ``machine`` (nothing
    of an earlier call kept: its native machine and cylinders' orders are made afresh), the
    package's modules already imported (a small machine's call first)."""
    import multicrank as mc

    mc.firing_orders(mc.presets.MACHINES["inline-4"])
    times = []
    for _ in range(repeats):
        fresh = machine.replace(name=machine.name)
        start = time.perf_counter()
        table = mc.firing_orders(fresh, max_candidates=max_candidates)
        times.append(time.perf_counter() - start)
    made = min(table.attrs["candidates"], max_candidates)
    return dict(
        name=machine.name,
        cylinders=len(machine),
        candidates=table.attrs["candidates"],
        made=made,
        rows=len(table),
        pareto=int(table["pareto"].sum()),
        seconds=min(times),
        baseline=per_candidate(machine, table, made),
    )


def measure_merit() -> dict:
    import multicrank as mc

    machine = diesel_14()
    start = time.perf_counter()
    mc.torsional_merit(machine)
    first = time.perf_counter() - start
    later = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        mc.torsional_merit(machine)
        later.append(time.perf_counter() - start)
    afresh = []
    for _ in range(10):
        fresh = copy.copy(machine)  # its cached orders stay with the original
        fresh.__dict__.pop("_torsion_orders", None)
        fresh.__dict__.pop("_native", None)
        start = time.perf_counter()
        mc.torsional_merit(fresh)
        afresh.append(time.perf_counter() - start)
    return dict(nodes=len(machine.shaft.inertia), first=first, later=min(later), afresh=min(afresh))


def long_shaft(nodes: int):
    import numpy as np

    import multicrank as mc

    rng = np.random.default_rng(0)
    return mc.Shaft(rng.uniform(0.5, 2.0, nodes), rng.uniform(1e6, 2e6, nodes - 1), cylinder_nodes=[0])


def timed(call, repeats: int) -> tuple[float, float]:
    """(best wall time [s] of ``repeats`` calls, peak traced memory [MB] of one more)."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    tracemalloc.start()
    call()
    peak = tracemalloc.get_traced_memory()[1] / 1e6
    tracemalloc.stop()
    return min(times), peak


def measure_modes() -> list[dict]:
    import numpy as np
    from scipy.linalg import eigh

    rows = []
    for nodes in (1000, 4000):
        shaft = long_shaft(nodes)
        for count in (5, None):
            seconds, peak = timed(lambda shaft=shaft, count=count: shaft.modes(count), 3 if count else 1)
            rows.append(dict(how="Shaft.modes", nodes=nodes, modes=count or nodes - 1, seconds=seconds, peak=peak))
    shaft = long_shaft(1000)
    seconds, peak = timed(lambda: eigh(shaft.stiffness_matrix(), np.diag(shaft.inertia)), 1)
    rows.append(dict(how="dense eigh (before)", nodes=1000, modes=999, seconds=seconds, peak=peak))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--markdown", action="store_true", help="print Markdown tables")
    args = parser.parse_args()

    import multicrank as mc

    if mc.build_profile != "release":
        raise SystemExit(f"bench_torsion: refusing a {mc.build_profile} build; install the release wheel")
    rows = [measure_firing(v12()), measure_firing(v16()), measure_firing(v16(), max_candidates=32768, repeats=1)]
    merit = measure_merit()
    modes = measure_modes()
    if not args.markdown:
        for row in rows:
            print(row)
        print(merit)
        for row in modes:
            print(row)
        return
    cpu = cpu_name()
    print(f"CPU: {cpu}, {os.cpu_count()} cores, all used")
    print()
    print(
        "| machine | cylinders | assignments (tried) | rows | Pareto | firing_orders, every criterion (s) "
        "| per machine (s) | ratio |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(
            f"| {r['name']} | {r['cylinders']} | {r['candidates']} ({r['made']}) | {r['rows']} | {r['pareto']} "
            f"| {r['seconds']:.2f} | {r['baseline']:.1f} | {r['baseline'] / r['seconds']:.0f}× |"
        )
    print()
    print("| torsional_merit, slow-diesel-12 | shaft nodes | first call (ms) | later calls (ms) | orders afresh (ms) |")
    print("|---|---:|---:|---:|---:|")
    print(
        f"| modes 2, orders ≤ 12 | {merit['nodes']} | {1e3 * merit['first']:.2f} | {1e3 * merit['later']:.3f} "
        f"| {1e3 * merit['afresh']:.2f} |"
    )
    print()
    print("| long shafts | nodes | modes | wall time (s) | peak memory (MB) |")
    print("|---|---:|---:|---:|---:|")
    for r in modes:
        print(f"| {r['how']} | {r['nodes']} | {r['modes']} | {r['seconds']:.3f} | {r['peak']:.1f} |")


if __name__ == "__main__":
    main()
