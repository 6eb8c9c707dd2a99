"""Steady running against integrating the equation of motion in time, same process, one core.

    python benches/python/bench_motion.py [--repeat 30] [--markdown]

Machines: a V12 four-stroke engine (±30° banks, engine cycles from mc.IndicatorDiagram.engine,
PCHIP tables of 1441 points) and a four-cylinder two-stroke compressor
(mc.IndicatorDiagram.compressor), both with gravity, rods with ΔI ≠ 0 and load="balance".

- ``mc.steady_state`` (everything it returns: the cycle's arrays at 361 points, δ, δ without
  gravity and δ of the machine coasting), repeated on one machine and as a first call (on a copy
  of the machine, whose native machine and cycle tables are made afresh), and
  ``mc.flywheel_inertia`` (δ = 0.01, with and without gravity), best of --repeat;
- the baseline: what one would do without the library —
  the equation of motion J φ̈ + ½J'φ̇² = M_gas − U' − M_load integrated in time with SciPy's
  solve_ivp (DOP853, rtol 1e-10, tightened tenfold until its δ agrees with the library's to
  1e-6) over one cycle, shooting on ω(0) with brentq until the cycle takes Φ/ω_m, then δ from
  the dense output.
  Torques from the same mc.Machine (the baseline is about the method, not the kernels).

Runs in a child process with RAYON_NUM_THREADS=1 and OPENBLAS_NUM_THREADS=1 (a few minutes:
the V12's baseline needs rtol 1e-13 to reach δ to 1e-6). Refuses a debug build of the extension.
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import sys
import time

from timing import best_time, child_rows


def machines():
    import numpy as np

    import multicrank as mc

    def cylinder(**changes):
        base = dict(
            crank_radius=0.06,
            rod_length=0.2,
            piston_mass=1.2,
            rod_mass=1.0,
            rod_cg=0.13,
            rod_inertia=0.004,
            bore=0.1,
            crank_mass=1.5,
            crank_cg_radius=0.03,
        )
        return mc.Cylinder(**{**base, **changes})

    single = mc.Machine([cylinder()], shaft_inertia=1.0)
    area = math.pi * 0.1**2 / 4

    def volume(theta):  # clearance for a compression ratio of 16, plus A·s(θ) from the machine
        return area * 0.12 / 15 + area * single.piston_travel(np.asarray(theta, dtype=float))[0]

    engine = mc.IndicatorDiagram.engine(volume, intake_pressure=1.2e5, heat_release=2500.0)
    banks = (math.pi / 2 - math.pi / 6, math.pi / 2 + math.pi / 6)
    v12 = mc.Machine(
        [
            cylinder(phase=float(alpha), inclination=banks[j % 2], pressure=engine)
            for j, alpha in enumerate(mc.crank_phases(12, strokes=4))
        ],
        shaft_inertia=2.0,
        strokes=4,
        name="V12 four-stroke",
    )
    compressor = mc.IndicatorDiagram.compressor(volume, suction_pressure=1e5, discharge_pressure=7e5)
    four = mc.Machine(
        [cylinder(phase=float(alpha), pressure=compressor) for alpha in mc.crank_phases(4)],
        shaft_inertia=0.5,
        name="4-cylinder compressor",
    )
    return [(v12, 1500.0), (four, 900.0)]


def shooting_baseline(machine, rpm: float, load: float, rtol: float):
    """δ by time integration and shooting (see the module's docstring)."""
    import numpy as np
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq, minimize_scalar

    cycle = machine.cycle
    omega_mean = rpm * math.pi / 30

    def rates(t, y):
        at = np.array([y[0]])
        J, slope = machine.reduced_inertia(at)
        torque = machine.gas_torque(at)[0] + machine.gravity_torque(at)[0] - 0.5 * slope[0] * y[1] ** 2 - load
        return [y[1], torque / J[0]]

    def turn(t, y):
        return y[0] - cycle

    turn.terminal, turn.direction = True, 1

    def run(omega0, dense=False):
        return solve_ivp(
            rates,
            (0.0, 3 * cycle / omega0),
            [0.0, omega0],
            method="DOP853",
            rtol=rtol,
            atol=[1e-2 * rtol * cycle, 1e-2 * rtol * omega0],
            events=turn,
            dense_output=dense,
        )

    def excess(omega0):
        return run(omega0).t_events[0][0] - cycle / omega_mean

    omega0 = brentq(excess, 0.9 * omega_mean, 1.1 * omega_mean, xtol=1e-13 * omega_mean, rtol=1e-13)
    final = run(omega0, dense=True)
    period = final.t_events[0][0]
    times = np.linspace(0.0, period, 20001)
    omega = final.sol(times)[1]
    extremes = []
    for sign in (1.0, -1.0):  # the best sample, polished on the dense output
        i = int(np.argmax(sign * omega))
        found = minimize_scalar(
            lambda t, sign=sign: -sign * final.sol(t)[1],
            bounds=(times[max(i - 1, 0)], times[min(i + 1, times.size - 1)]),
            method="bounded",
            options={"xatol": 1e-14 * period},
        )
        extremes.append(max(sign * omega[i], -found.fun))
    return (extremes[0] + extremes[1]) * period / cycle


def measure(repeat: int) -> list[dict]:
    import multicrank as mc

    if mc.build_profile != "release":
        sys.exit(f"refusing to benchmark a {mc.build_profile} build: pip install . (release) first")

    def first_call(machine, rpm):
        # A copy: a new machine, whose native machine (and its cycle's tables) is made afresh.
        return mc.steady_state(machine.replace(), rpm=rpm)

    rows = []
    for machine, rpm in machines():
        result = mc.steady_state(machine, rpm=rpm)
        # Short runs, many of them: these calls last milliseconds.
        short = functools.partial(best_time, min_seconds=0.01)
        fast = short(functools.partial(mc.steady_state, machine, rpm=rpm), repeat)
        cold = short(functools.partial(first_call, machine, rpm), repeat)
        flywheel = short(functools.partial(mc.flywheel_inertia, machine, delta=0.01, rpm=rpm), max(3, repeat // 2))
        # The baseline's tolerance is tightened until its δ is the library's to 1e-6 (tabulated
        # pressures put a kink into its right-hand side at every table node of every cylinder);
        # the time is that of the run that got there.
        runs = []
        for rtol in (1e-10, 1e-11, 1e-12, 1e-13):
            start = time.perf_counter()
            delta = shooting_baseline(machine, rpm, result.mean_load_torque, rtol)
            runs.append((time.perf_counter() - start, abs(delta - result.delta) / result.delta, rtol))
            if runs[-1][1] <= 1e-6:
                break
        rows.append(
            dict(
                machine=machine.name,
                cylinders=len(machine),
                rpm=rpm,
                delta=result.delta,
                first_ms=runs[0][0] * 1e3,
                first_error=runs[0][1],
                steady_ms=fast * 1e3,
                cold_ms=cold * 1e3,
                flywheel_ms=flywheel * 1e3,
                baseline_ms=runs[-1][0] * 1e3,
                baseline_error=runs[-1][1],
                baseline_rtol=runs[-1][2],
            )
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=30)
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(measure(args.repeat)))
        return
    rows = child_rows(__file__, "--repeat", str(args.repeat))
    header = (
        "| machine | k | rpm | δ | steady_state | first call | flywheel_inertia | solve_ivp, rtol 1e-10 "
        "(its δ off by) | ratio | solve_ivp, δ to 1e-6 (rtol) | ratio |"
    )
    print(header)
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['machine']} | {r['cylinders']} | {r['rpm']:g} | {r['delta']:.4e} | {r['steady_ms']:.2f} ms | "
            f"{r['cold_ms']:.2f} ms | {r['flywheel_ms']:.1f} ms | {r['first_ms']:.0f} ms ({r['first_error']:.1e}) | "
            f"{r['first_ms'] / r['steady_ms']:.0f}× | {r['baseline_ms']:.0f} ms ({r['baseline_rtol']:.0e}) | "
            f"{r['baseline_ms'] / r['steady_ms']:.0f}× |"
        )
    if not args.markdown:
        print("\none core (RAYON_NUM_THREADS=1); best of --repeat for multicrank, one run for the baseline")


if __name__ == "__main__":
    main()
