"""Start-up: a single-cylinder four-stroke engine run up from 300 rpm against a propeller.

The engine's gas pressure is the library's synthetic single-zone cycle
(``IndicatorDiagram.engine``); the propeller is a square-law load sized to absorb the
engine's mean torque at 1500 rpm. ``mc.simulate`` integrates the motion in time until the
speed settles into its periodic steady state. Run it as

    python docs/examples/startup.py [--duration 4] [--png startup.png]

It prints the speed reached, its fluctuation over the last working cycle and the run's
energy check, and with ``--png`` draws the speed and torques (needs matplotlib).
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import multicrank as mc

CYLINDER = mc.Cylinder(
    crank_radius=0.045,
    rod_length=0.15,
    piston_mass=0.45,
    rod_mass=0.35,
    rod_cg=0.1,
    rod_inertia=0.0007,
    crank_mass=1.2,
    crank_cg_radius=0.02,
    counterweight_mass=1.0,
    counterweight_radius=0.04,
    bore=0.085,
)
CLEARANCE = 5.5e-5  # m³: compression ratio about 10


def engine() -> mc.Machine:
    """The engine with its gas pressure: V(θ) = V_c + A·s(θ) from the unit's own travel."""
    bare = mc.Machine([CYLINDER], shaft_inertia=0.12, strokes=4, name="single-cylinder engine")

    def volume(theta: np.ndarray) -> np.ndarray:
        return CLEARANCE + CYLINDER.piston_area * bare.piston_travel(theta)[0]

    diagram = mc.IndicatorDiagram.engine(volume, intake_pressure=0.95e5, heat_release=700.0)
    return bare.replace(cylinders=[CYLINDER.replace(pressure=diagram)])


def last_cycle(result: mc.Transient, cycle: float) -> tuple[float, float]:
    """(time-mean speed [rad/s], δ = (ω_max − ω_min)/ω_mean) over the last working cycle."""
    start = result.phi[-1] - cycle
    t_start = float(np.interp(start, result.phi, result.time))
    mean = cycle / (result.time[-1] - t_start)
    window = result.omega[result.phi >= start]
    return mean, (window.max() - window.min()) / mean


def main(argv: list[str] | None = None) -> mc.Transient:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=4.0, help="simulated time [s] (default 4)")
    parser.add_argument("--rtol", type=float, default=1e-8, help="the integrator's tolerance (default 1e-8)")
    parser.add_argument("--png", help="save a figure of the run to this file")
    args = parser.parse_args(argv)

    machine = engine()
    rated = 1500 * math.pi / 30  # rad/s
    mean_torque = mc.torque_orders(machine, 1500, max_order=1).loc[0.0, "gas_cos"]  # the cycle-mean gas torque
    propeller = mc.PowerLawLoad(torque=mean_torque, speed=rated, exponent=2)
    times = np.linspace(0.0, args.duration, int(args.duration * 2000) + 1)
    result = mc.simulate(machine, times, omega0=300 * math.pi / 30, load=propeller, rtol=args.rtol, atol=args.rtol)

    mean, delta = last_cycle(result, machine.cycle)
    print(f"{machine.name}: mean gas torque {mean_torque:.1f} N·m, propeller {propeller.torque:.1f} N·m at 1500 rpm")
    print(f"after {result.time[-1]:.2f} s: {mean * 30 / math.pi:.0f} rpm (last cycle), δ = {delta:.3f}")
    print(f"energy check: drift {result.energy_drift:.1e} of the largest kinetic energy, {result.nfev} evaluations")
    if args.png:
        plot(result, args.png, "Start-up against a propeller")
    return result


def plot(result: mc.Transient, path: str, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, (speed, torque) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    speed.plot(result.time, result.rpm)
    speed.set_ylabel("speed [1/min]")
    speed.set_title(title)
    for name in ("gas_torque", "inertia_torque", "gravity_torque", "load_torque"):
        torque.plot(result.time, getattr(result, name), label=name.replace("_", " "), linewidth=0.7)
    torque.set_xlabel("time [s]")
    torque.set_ylabel("torque [N·m]")
    torque.legend(loc="upper right")
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


if __name__ == "__main__":
    main()
