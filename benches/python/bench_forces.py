"""The forces on the frame and the bearings of a twelve-cylinder machine, one core, against
plain numpy in the same run.

    python benches/python/bench_forces.py [--repeat 7] [--markdown]

``genset-v12`` (60° V12, six throws placed along the shaft, seven main bearings):

- ``mc.shaking_forces(machine, rpm)`` through order 12, asked again (its series are kept by
  the machine after the first call; the issue's figure: ≤ 20 µs). Baseline: the same table
  from plain numpy — every body's first moment sampled at 512 angles of a revolution from its
  planar geometry (the piston on its axis, the rod's centre of gravity between its pins, web
  and counterweight), numpy's FFT, n²ω² times each order.
- ``mc.bearing_loads(machine, phi=720 angles, gravity=False)`` (one pass of the core; the
  issue's figure: ≤ 1 ms), and its ``summary`` with gravity (a second pass with g = 0, for
  what gravity adds, and the table).
  Baseline: plain numpy vectorised over the angles — each unit's five unknown pin and wall
  forces by ``numpy.linalg.solve`` on the stacked 5 × 5 Newton–Euler systems, accelerations
  from the geometry by spectral derivatives, the lever rule.

- ``mc.motion_sweep(inline-4, 50 000 designs, outputs=free_force_1/2, free_moment_1/2)`` in
  designs per second on all cores (the issue's figure: ≥ 10⁵ designs/s on 2 cores), and
  ``bearing_loads`` again on all cores (its units solved in parallel).

Each figure is the best of --repeat runs (benches/python/timing.py). Runs in child processes
with RAYON_NUM_THREADS=1 (the sweep: all cores). Refuses a debug build of the extension.
"""

from __future__ import annotations

import argparse
import json
import math
import os

from timing import best_time, child_rows

SAMPLES = 512


def first_moments(np, machine, phi):
    """Σ m·(y, x) and Σ z·m·(y, x) of every body, shape (4, phi.size)."""
    out = np.zeros((4, phi.size))
    for c in machine.cylinders:
        psi = phi + c.phase
        angle = psi + c.inclination
        pin = c.crank_radius * np.array([np.cos(angle), np.sin(angle)])
        axis = np.array([math.cos(c.inclination), math.sin(c.inclination)])[:, None]
        along = c.crank_radius * np.cos(psi) + np.sqrt(c.rod_length**2 - (c.crank_radius * np.sin(psi)) ** 2)
        piston = along * axis
        rod = piston + c.rod_cg / c.rod_length * (pin - piston)
        arm = (c.crank_mass * c.crank_cg_radius - c.counterweight_mass * c.counterweight_radius) / c.crank_radius
        total = c.piston_mass * piston + c.rod_mass * rod + arm * pin
        out[0] += total[1]
        out[1] += total[0]
        out[2] += c.axial_position * total[1]
        out[3] += c.axial_position * total[0]
    return out


def numpy_orders(np, machine, omega, max_order):
    phi = 2 * np.pi * np.arange(SAMPLES) / SAMPLES
    c = np.fft.rfft(first_moments(np, machine, phi), axis=-1) / SAMPLES
    n = np.arange(1, max_order + 1)
    force = 2 * omega**2 * n**2 * c[:, 1 : max_order + 1]
    return np.abs(force), np.angle(force)


def numpy_bearings(np, machine, phi, omega, gas):
    """The bearing loads by stacked Newton–Euler solves (g = 0), shape (2, bearings, n)."""
    turn = 2 * np.pi * np.arange(SAMPLES) / SAMPLES
    k = np.fft.fftfreq(SAMPLES, 1.0 / SAMPLES)
    waves = np.exp(1j * np.outer(k, phi))

    def second(samples):
        return np.real((np.fft.fft(samples, axis=-1) / SAMPLES * (1j * k) ** 2) @ waves) * omega**2

    bearings = np.asarray(machine.bearings)
    loads = np.zeros((2, bearings.size, phi.size))
    for j, c in enumerate(machine.cylinders):
        axis = np.array([math.cos(c.inclination), math.sin(c.inclination)])
        normal = np.array([-axis[1], axis[0]])

        def bodies(x, c=c, axis=axis):
            psi = x + c.phase
            pin = c.crank_radius * np.array([np.cos(psi + c.inclination), np.sin(psi + c.inclination)])
            along = c.crank_radius * np.cos(psi) + np.sqrt(c.rod_length**2 - (c.crank_radius * np.sin(psi)) ** 2)
            piston = along * axis[:, None]
            rod = piston + c.rod_cg / c.rod_length * (pin - piston)
            d = piston - pin
            angle = np.arctan2(axis[0] * d[1] - axis[1] * d[0], axis @ d)
            return pin, piston, rod, angle

        pin_s, piston_s, rod_s, angle_s = bodies(turn)
        pin, piston, rod, _ = bodies(phi)
        a_pin, a_piston, a_rod, alpha = second(pin_s), second(piston_s), second(rod_s), second(angle_s)
        count = phi.size
        A = np.zeros((count, 5, 5))
        rhs = np.zeros((count, 5))
        A[:, 0:2, 0:2] = np.eye(2)
        A[:, 0:2, 2] = normal
        rhs[:, 0:2] = (c.piston_mass * a_piston + gas[j] * axis[:, None]).T
        A[:, 2:4, 0:2] = -np.eye(2)
        A[:, 2:4, 3:5] = np.eye(2)
        rhs[:, 2:4] = (c.rod_mass * a_rod).T
        b_g, p_g = piston - rod, pin - rod
        A[:, 4, 0], A[:, 4, 1] = -b_g[1], b_g[0]
        A[:, 4, 3], A[:, 4, 4] = p_g[1], -p_g[0]
        rhs[:, 4] = -c.rod_inertia * alpha
        x = np.linalg.solve(A, rhs[..., None])[..., 0]
        arm = (c.crank_mass * c.crank_cg_radius - c.counterweight_mass * c.counterweight_radius) / c.crank_radius
        load = -x[:, 3:5].T - arm * a_pin
        after = int(np.searchsorted(bearings, c.axial_position, side="right"))
        a, b = bearings[after - 1], bearings[after]
        loads[:, after - 1] += (b - c.axial_position) / (b - a) * load
        loads[:, after] += (c.axial_position - a) / (b - a) * load
    return loads


def measure(repeat: int) -> list[dict]:
    import numpy as np

    import multicrank as mc

    if mc.build_profile != "release":
        raise SystemExit(f"bench_forces: refusing a {mc.build_profile} build; install the release wheel")
    machine = mc.presets.MACHINES["genset-v12"]
    rpm = machine.rpm
    omega = math.pi * rpm / 30
    mc.shaking_forces(machine, rpm)  # its series made, as after any first call
    found = mc.shaking_forces(machine, rpm).orders["force_vertical"].to_numpy()
    amplitude, _ = numpy_orders(np, machine, omega, 12)
    agreement = float(np.max(np.abs(found - amplitude[0])) / np.max(amplitude))
    phi = machine.cycle * np.arange(720) / 720
    gas = machine.piston_forces(phi)
    loads = mc.bearing_loads(machine, phi=phi, gravity=False)
    plain = numpy_bearings(np, machine, phi, omega, gas)
    bearing_agreement = float(np.max(np.abs(loads.vertical - plain[1])) / np.max(np.abs(plain)))
    rows = [
        {
            "question": "shaking_forces, orders 1-12 (asked again)",
            "seconds": best_time(lambda: mc.shaking_forces(machine, rpm), repeat),
            "baseline": best_time(lambda: numpy_orders(np, machine, omega, 12), repeat),
            "agreement": agreement,
        },
        {
            "question": "bearing_loads, 720 angles, gravity=False",
            "seconds": best_time(lambda: mc.bearing_loads(machine, phi=phi, gravity=False), repeat),
            "baseline": best_time(lambda: numpy_bearings(np, machine, phi, omega, gas), max(1, repeat // 3)),
            "agreement": bearing_agreement,
        },
        {
            "question": "bearing_loads(...).summary, 720 angles (its g = 0 pass too)",
            "seconds": best_time(lambda: mc.bearing_loads(machine, phi=phi).summary, repeat),
            "baseline": math.nan,
            "agreement": math.nan,
        },
    ]
    return rows


def sweep_rate(repeat: int) -> list[dict]:
    import numpy as np

    import multicrank as mc

    machine = mc.presets.MACHINES["inline-4"]
    grid = mc.MachineGrid(machine, rpm=np.linspace(1000.0, 6000.0, 200), counterweight_mass=np.linspace(0.5, 2.0, 250))
    outputs = ["free_force_1", "free_force_2", "free_moment_1", "free_moment_2"]
    seconds = best_time(lambda: mc.motion_sweep(machine, grid, outputs=outputs, progress=False), max(1, repeat // 3))
    v12 = mc.presets.MACHINES["genset-v12"]
    phi = v12.cycle * np.arange(720) / 720
    bearings = best_time(lambda: mc.bearing_loads(v12, phi=phi, gravity=False), repeat)
    return [{"designs": len(grid), "seconds": seconds, "bearings": bearings}]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--sweep-child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(measure(args.repeat) if not args.sweep_child else sweep_rate(args.repeat)))
        return
    rows = child_rows(__file__, "--repeat", str(args.repeat))
    cores = str(os.cpu_count())
    swept = child_rows(__file__, "--repeat", str(args.repeat), "--sweep-child", threads=cores)[0]
    print("| genset-v12 (12 cylinders) | multicrank | plain numpy | ratio | agree to |")
    print("|---|---|---|---|---|")
    for row in rows:
        baseline = row["baseline"]
        plain = "–" if math.isnan(baseline) else f"{baseline * 1e6:.0f} µs"
        ratio = "–" if math.isnan(baseline) else f"{baseline / row['seconds']:.0f}×"
        agree = "–" if math.isnan(row["agreement"]) else f"{row['agreement']:.0e}"
        print(f"| {row['question']} | {row['seconds'] * 1e6:.1f} µs | {plain} | {ratio} | {agree} |")
    rate = swept["designs"] / swept["seconds"]
    label = f"motion_sweep, 4 free outputs, {swept['designs']} designs, {cores} cores"
    print(f"| {label} | {rate:,.0f} designs/s | – | – | – |")
    label = f"bearing_loads, 720 angles, gravity=False, {cores} cores (the units in parallel)"
    print(f"| {label} | {swept['bearings'] * 1e6:.1f} µs | – | – | – |")
    if not args.markdown:
        print("\none core (RAYON_NUM_THREADS=1) but the sweep; best of --repeat, each run long enough to time")


if __name__ == "__main__":
    main()
