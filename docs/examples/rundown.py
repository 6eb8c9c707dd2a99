"""Run-down: a two-cylinder air compressor coasting to a stop after its motor is cut off.

Two single-acting cylinders on cranks 180° apart compress air from 1 to 8 bar (the
library's ideal compressor cycle, ``IndicatorDiagram.compressor``); bearing friction is a
constant torque plus a viscous part. With the motor off at 600 rpm, the gas work and the
friction take the flywheel's energy until the machine can no longer push a piston over its
compression: ``mc.simulate`` stops at that stall (ω = 0) and says when. Run it as

    python docs/examples/rundown.py [--png rundown.png]

It prints the stall time, the revolutions turned and the crank angle at which it stopped,
and with ``--png`` draws the speed and torques (needs matplotlib).
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import multicrank as mc

CYLINDER = mc.Cylinder(
    crank_radius=0.04,
    rod_length=0.16,
    piston_mass=0.9,
    rod_mass=0.6,
    rod_cg=0.11,
    crank_mass=1.5,
    crank_cg_radius=0.02,
    bore=0.07,
)
CLEARANCE = 8e-6  # m³
FRICTION = 1.5  # N·m, constant (Coulomb)
VISCOUS = 0.01  # N·m per rad/s


def compressor() -> mc.Machine:
    """Two cylinders 180° apart, each with the ideal compressor cycle in its own volume."""
    bare = mc.Machine([CYLINDER], shaft_inertia=1.2, strokes=2, name="two-cylinder compressor")

    def volume(theta: np.ndarray) -> np.ndarray:
        return CLEARANCE + CYLINDER.piston_area * bare.piston_travel(theta)[0]

    diagram = mc.IndicatorDiagram.compressor(volume, suction_pressure=1.0e5, discharge_pressure=8.0e5)
    cylinders = [CYLINDER.replace(pressure=diagram, phase=phase) for phase in (0.0, math.pi)]
    return bare.replace(cylinders=cylinders)


def friction(phi: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """The bearings' torque [N·m]: constant plus viscous (resisting, the machine turns forward)."""
    return FRICTION + VISCOUS * np.asarray(omega)


def main(argv: list[str] | None = None) -> mc.Transient:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rpm", type=float, default=600.0, help="speed when the motor is cut off (default 600)")
    parser.add_argument("--duration", type=float, default=30.0, help="longest simulated time [s] (default 30)")
    parser.add_argument("--rtol", type=float, default=1e-9, help="the integrator's tolerance (default 1e-9)")
    parser.add_argument("--png", help="save a figure of the run to this file")
    args = parser.parse_args(argv)

    machine = compressor()
    times = np.linspace(0.0, args.duration, int(args.duration * 1000) + 1)
    result = mc.simulate(machine, times, omega0=args.rpm * math.pi / 30, load=friction, rtol=args.rtol, atol=args.rtol)

    print(f"{machine.name}: motor off at {args.rpm:.0f} rpm")
    if result.stalled:
        angle = math.degrees(result.phi[-1] % machine.cycle)
        turns = (result.phi[-1] - result.phi[0]) / (2 * math.pi)
        print(f"stalled after {result.stall_time:.3f} s and {turns:.1f} revolutions, at crank angle {angle:.1f}°")
        work = result.work[-1]
        print(
            f"the gas and the friction took {-work:.1f} J, the kinetic energy at the start was "
            f"{result.kinetic_energy[0]:.1f} J"
        )
    else:
        print(f"still turning at {result.rpm[-1]:.0f} rpm after {result.time[-1]:.1f} s")
    print(f"energy check: drift {result.energy_drift:.1e} of the largest kinetic energy, {result.nfev} evaluations")
    if args.png:
        plot(result, args.png)
    return result


def plot(result: mc.Transient, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, (speed, torque) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    speed.plot(result.time, result.rpm)
    speed.set_ylabel("speed [1/min]")
    speed.set_title("Run-down of a compressor")
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
