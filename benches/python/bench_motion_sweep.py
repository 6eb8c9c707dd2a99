"""Motion at sweep scale against the per-machine path, same process.

    python benches/python/bench_motion_sweep.py [--markdown]
    python benches/python/bench_motion_sweep.py --million [--out DIR]

Machine: the "inline-4" preset (four cylinders, four-stroke, tabulated indicator diagrams,
gravity). Three sweeps of it with ``mc.motion_sweep``:

- speed × flywheel (``rpm`` × ``shaft_inertia``, 4096 designs), δ with and without gravity:
  the designs share their machine's cycle tables (the core tabulates them once per block);
- counterweight × rod length (1024 designs), the same outputs: every design its own tables,
  the designs of one rod length one gas work (G, and W on the panels);
- rod length × crank radius (1024 designs): every design its own tables and gas work;
- the flywheel for δ = 0.01 (with and without gravity) over rpm × rod length (256 designs);

each with one rayon thread and with all cores (a child process per thread count: rayon fixes
its pool at first use). The baseline, measured in the same child: one machine at a time — the
variant built with ``Machine.replace``, then its own steady state with its arrays (or its
flywheel), on the first 48 designs. (Before issue 27 the baseline was the Python
implementation of the steady state, which is gone: the core is the only solver.)

--million: one 10⁶-design speed × flywheel sweep streamed to Parquet with progress, reporting
the wall time and the peak resident memory (bounded: one chunk at a time).
Refuses a debug build of the extension.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

from timing import child_rows, cpu_name

BASELINE_DESIGNS = 48


def grids():
    import numpy as np

    import multicrank as mc

    machine = mc.presets.MACHINES["inline-4"]
    cylinder = machine.cylinders[0]
    return machine, {
        "speed × flywheel": (
            mc.MachineGrid(machine, rpm=np.linspace(1500, 6000, 64), shaft_inertia=np.linspace(0.1, 0.5, 64)),
            None,
        ),
        "counterweight × rod length": (
            mc.MachineGrid(
                machine,
                counterweight_mass=np.linspace(0.5, 2.0, 32),
                rod_length=cylinder.rod_length * np.linspace(0.9, 1.1, 32),
            ),
            None,
        ),
        "rod length × crank radius": (
            mc.MachineGrid(
                machine,
                rod_length=cylinder.rod_length * np.linspace(0.9, 1.1, 32),
                crank_radius=cylinder.crank_radius * np.linspace(0.95, 1.05, 32),
            ),
            None,
        ),
        "flywheel for δ = 0.01": (
            mc.MachineGrid(
                machine, rpm=np.linspace(1500, 6000, 16), rod_length=cylinder.rod_length * np.linspace(0.9, 1.1, 16)
            ),
            0.01,
        ),
    }


def baseline_rate(machine, frame, delta) -> float:
    """Designs/s of the per-machine path (replace, then the machine's own steady state with
    its arrays, or its flywheel)."""
    import multicrank as mc
    from multicrank.motion.variants import MACHINE_COLUMNS, machine_variant

    names = [c for c in frame.columns if c in MACHINE_COLUMNS]
    rows = frame.head(BASELINE_DESIGNS)
    start = time.perf_counter()
    for values in rows[names].itertuples(index=False, name=None):
        design = dict(zip(names, values, strict=True))
        variant = machine_variant(machine, design)
        rpm = design.get("rpm", machine.rpm)
        if delta is None:
            mc.steady_state(variant, rpm=rpm).omega  # noqa: B018 (the arrays, computed when read)
        else:
            mc.flywheel_inertia(variant, delta=delta, rpm=rpm)
    return len(rows) / (time.perf_counter() - start)


def child() -> list[dict]:
    import multicrank as mc

    machine, cases = grids()
    rows = []
    for name, (grid, delta) in cases.items():
        outputs = (
            ["flywheel_inertia", "flywheel_inertia_without_gravity"] if delta else ["delta", "delta_without_gravity"]
        )
        mc.motion_sweep(machine, grid.frame(0, 8), outputs=outputs, delta_target=delta)  # tables of the preset made
        best = float("inf")
        for _ in range(3):
            start = time.perf_counter()
            mc.motion_sweep(machine, grid, outputs=outputs, delta_target=delta)
            best = min(best, time.perf_counter() - start)
        rate = len(grid) / best
        base = baseline_rate(machine, grid.frame(0, BASELINE_DESIGNS), delta)
        rows.append(dict(sweep=name, designs=len(grid), rate=rate, baseline=base))
    return rows


def million(out: Path) -> None:
    import numpy as np

    import multicrank as mc

    machine = mc.presets.MACHINES["inline-4"]
    grid = mc.MachineGrid(machine, rpm=np.linspace(1500, 6000, 1000), shaft_inertia=np.linspace(0.1, 0.5, 1000))
    path = out / "million.parquet"
    start = time.perf_counter()
    mc.motion_sweep(
        machine, grid, outputs=["delta", "delta_without_gravity", "gravity_effect"], out=path, progress=True
    )
    wall = time.perf_counter() - start
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    import pyarrow.parquet as pq

    table = pq.read_table(path)
    print(
        f"{len(grid):,} designs in {wall:.1f} s ({len(grid) / wall:,.0f} designs/s) on {os.cpu_count()} cores; "
        f"peak resident memory {peak:.0f} MiB; {table.num_rows:,} rows, "
        f"{path.stat().st_size / 2**20:.1f} MiB of Parquet; "
        f"{int(np.isnan(table['delta'].to_numpy()).sum())} NaN δ"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--million", action="store_true")
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    import multicrank as mc

    if mc.build_profile == "debug":
        sys.exit("refusing a debug build of multicrank: build the release wheel first")
    if args.child:
        print(json.dumps(child()))
        return
    if args.million:
        if args.out is None:
            with tempfile.TemporaryDirectory() as directory:
                million(Path(directory))
        else:
            million(args.out)
        return
    results = {}
    for threads in ("1", str(os.cpu_count())):
        results[threads] = child_rows(__file__, threads=threads)
    cpu = cpu_name()
    print(f"CPU: {cpu}; inline-4 preset; baseline: replace + each machine's own steady state/flywheel, same child")
    head = "| sweep | designs | threads | designs/s | per-machine path (designs/s) | ratio |"
    print(head if args.markdown else head.replace("|", " "))
    if args.markdown:
        print("|---|---:|---:|---:|---:|---:|")
    for threads, rows in results.items():
        for row in rows:
            line = (
                f"| {row['sweep']} | {row['designs']} | {threads} | {row['rate']:,.0f} | "
                f"{row['baseline']:,.0f} | {row['rate'] / row['baseline']:.0f}× |"
            )
            print(line if args.markdown else line.replace("|", " "))


if __name__ == "__main__":
    main()
