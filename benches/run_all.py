"""Regenerate BENCHMARKS.md: one command for every figure it holds.

    python benches/run_all.py [--criterion]

Runs benches/python/bench_kernels.py, bench_sweep.py, bench_machine.py, bench_motion.py,
bench_routes.py, bench_forces.py, bench_motion_sweep.py, bench_design_aid.py and
bench_torsion.py (release build of the installed package; each refuses a debug build) and,
with --criterion, the criterion benches of the Rust kernels, then writes BENCHMARKS.md at the
repository root.
OPENBLAS_NUM_THREADS=1 keeps numpy's BLAS threads from spinning on the cores being timed.
To compare two builds' criterion figures instead, see benches/compare_builds.py.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ENV = dict(os.environ, OPENBLAS_NUM_THREADS="1")


ROUTES_HEADING = "## The routes of one steady state: a drive, a callable pressure, against the plain route"
ROUTES_NOTE = (
    "`benches/python/bench_routes.py`: one core, the slow compressor at 120 rpm, `.delta` only. "
    "Each route is the Rust core's; a callable drive or pressure is sampled once (a new machine "
    "pays that and its cycle tables once)."
)
FORCES_HEADING = "## Forces on the frame and the bearings: a twelve-cylinder V, one core"
FORCES_NOTE = (
    "`benches/python/bench_forces.py`: genset-v12 (six throws along the shaft, seven main "
    "bearings). `shaking_forces` asked again (its series kept by the machine after the first "
    "call); `bearing_loads` at 720 angles, one pass, and its summary (a second pass with g = 0). Baselines: "
    "plain numpy — an FFT of the bodies' sampled first moments; stacked Newton–Euler solves per "
    "unit over the angles — whose results agree as the last column says."
)
MACHINE_HEADING = "## The machine's kernels: 10⁶ points, J and J′ together, U"
MACHINE_NOTE = (
    "Cylinders with λ = 0.3, rods with ΔI < 0, webs and counterweights, phases spread over the "
    "revolution, banks alternating ±45°. Baseline: one numpy expression per cylinder from planar "
    "geometry (one sin, one cos, one square root of ψ per cylinder), which also checks the values."
)
MOTION_HEADING = "## Motion: steady running against time integration, one core"
MOTION_NOTE = (
    "`steady_state`: everything it returns (arrays at 361 points, δ, δ without gravity, δ of the "
    "machine coasting), repeated calls on one machine (a table's indicator work is integrated on the "
    "first call and kept); `first call`: that work cleared before each call. `flywheel_inertia`: "
    "δ = 0.01, with and without gravity. Baseline (one run each): the equation of motion "
    "integrated in time with `solve_ivp` (DOP853) over one cycle, shooting on ω(0) with brentq "
    "until the cycle takes Φ/ω_m, δ from its dense output — at rtol 1e-10, and at the rtol "
    "(tightened tenfold) at which its δ agrees with the library's to 1e-6: the tables' kinks at "
    "every node of every cylinder hold DOP853 back."
)


def run(*command: str) -> str:
    return subprocess.run(command, cwd=ROOT, env=ENV, capture_output=True, text=True, check=True).stdout


def criterion_table() -> str:
    out = run("cargo", "bench", "-p", "multicrank-benches", "--bench", "kernels", "--", "--quick")
    rows = ["| kernel | throughput |", "|---|---|"]
    for name, value, unit in re.findall(
        r"^(\S+/\S+)\s*\n?\s*time:.*?\n\s*thrpt:\s*\[\S+ \S+ (\S+) (\S+)", out, re.M | re.S
    ):
        rows.append(f"| {name} | {value} {unit} |")
    return "\n".join(rows)


MOTION_SWEEP_HEADING = "## Motion at sweep scale: `mc.motion_sweep` against the per-machine path"
MOTION_SWEEP_NOTE = (
    "Outputs δ and δ without gravity (the flywheel row: I_w for δ = 0.01 with and without gravity), "
    "best of 3. Designs that differ only in shaft inertia and speed share their machine's cycle "
    "tables (speed × flywheel); a counterweight makes new ones, sharing the gas work of designs "
    "with the same rod length; a rod length and a crank radius make everything new. "
    "The per-machine path: `machine_variant` then the Python implementation of the steady state "
    "(or the flywheel), the library's only path before the core's motion, on 48 designs in the "
    "same child. A 10⁶-design sweep to Parquet: `python benches/python/bench_motion_sweep.py --million`."
)


DESIGN_AID_HEADING = "## The design aid: `mc.firing_orders` and `mc.optimize_counterweights`"
DESIGN_AID_NOTE = (
    "Wall times of the whole calls (defaults; counterweights: objective δ, seed 0), all cores. "
    "A firing order changes every cylinder's place in the cycle, so each candidate of the motion "
    "sweep is new gas and tables; the per-machine path builds each candidate with "
    "`Machine.replace` and solves it with `mc.steady_state`. The optimiser's per-machine figure is "
    "its number of steady states times the time of one `mc.steady_state` of a machine with other "
    "counterweights (40 timed)."
)

TORSION_HEADING = "## Every criterion and the torsional merit: `mc.firing_orders(shaft=...)`, `mc.torsional_merit`"
TORSION_NOTE = (
    "Wall times of the whole calls with a shaft, all cores: every candidate's δ class, free moments, "
    "bearing loads and torsional merit, and the Pareto marks. The per-machine path: "
    "`mc.steady_state`, `mc.shaking_forces`, `mc.bearing_loads` and `mc.torsional_merit` of each "
    "candidate machine, timed on 40 and scaled to the candidates made. `torsional_merit` of a "
    "14-node shaft: the first call makes each cylinder's orders (kept on the machine), later calls "
    "reuse them; the last column is a copy of the machine each time."
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--criterion", action="store_true", help="also run the criterion benches (a few minutes)")
    args = parser.parse_args()
    kernels = run(sys.executable, "benches/python/bench_kernels.py", "--markdown")
    sweeps = run(sys.executable, "benches/python/bench_sweep.py", "--markdown")
    machine = run(sys.executable, "benches/python/bench_machine.py", "--markdown")
    motion = run(sys.executable, "benches/python/bench_motion.py", "--markdown")
    routes = run(sys.executable, "benches/python/bench_routes.py", "--markdown")
    forces = run(sys.executable, "benches/python/bench_forces.py", "--markdown")
    motion_sweep = run(sys.executable, "benches/python/bench_motion_sweep.py", "--markdown")
    design_aid = run(sys.executable, "benches/python/bench_design_aid.py", "--markdown")
    torsion = run(sys.executable, "benches/python/bench_torsion.py", "--markdown")
    cpu = next(
        (
            line.split(":", 1)[1].strip()
            for line in Path("/proc/cpuinfo").read_text().splitlines()
            if line.startswith("model name")
        ),
        platform.processor(),
    )
    parts = [
        "# Benchmarks",
        "",
        f"Generated by `python benches/run_all.py{' --criterion' if args.criterion else ''}` on "
        f"{datetime.date.today()}: {os.cpu_count()} cores ({cpu}), Python {platform.python_version()}, "
        "release build. Ratios are against `multicrank.reference` (the plain-numpy "
        "baseline: a loop over cranks, each one vectorised numpy expression) timed in the same "
        "process; best of several repetitions. The machine is shared: expect ±10 %.",
        "",
        "## Kernels: 10⁶ points over one revolution, λ = 0.3, two-stroke phases",
        "",
        kernels.strip(),
        "",
        "φ: `points` is a plain array (every point's value from that point alone, bit for bit); "
        "`grid` is the same points as `mc.uniform_grid(10**6)`, whose sin/cos come by rotation from "
        "exact seeds. The baseline always gets the plain array. ns per (pt, crank) = ns/pt ÷ k, for "
        "the closed form. `lambda_coefficients` rows: ns per λ for Λ_0…Λ_24, λ spread over [0, 0.95].",
        "",
        "## Sweeps: 200 000 designs, mixed k = 1…12, two- and four-stroke, phi = 360",
        "",
        sweeps.strip(),
        "",
        MACHINE_HEADING,
        "",
        machine.strip(),
        "",
        MACHINE_NOTE,
        "",
        MOTION_HEADING,
        "",
        motion.strip(),
        "",
        MOTION_NOTE,
        "",
        ROUTES_HEADING,
        "",
        routes.strip(),
        "",
        ROUTES_NOTE,
        "",
        FORCES_HEADING,
        "",
        forces.strip(),
        "",
        FORCES_NOTE,
        "",
        MOTION_SWEEP_HEADING,
        "",
        motion_sweep.strip(),
        "",
        MOTION_SWEEP_NOTE,
        "",
        DESIGN_AID_HEADING,
        "",
        design_aid.strip(),
        "",
        DESIGN_AID_NOTE,
        "",
        TORSION_HEADING,
        "",
        torsion.strip(),
        "",
        TORSION_NOTE,
        "",
    ]
    if args.criterion:
        parts += ["## Criterion (Rust kernels alone, 10⁶ points)", "", criterion_table(), ""]
    (ROOT / "BENCHMARKS.md").write_text("\n".join(parts), encoding="utf-8")
    print((ROOT / "BENCHMARKS.md").read_text(encoding="utf-8"))


if __name__ == "__main__":
    main()
