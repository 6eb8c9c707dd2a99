"""
A compressor's run-down to a stall
==================================

A small two-cylinder air compressor loses its motor at 600 rpm. The gas work of every
compression and the bearings' friction take the energy of the flywheel until the machine
can no longer push a piston through its compression and stops short of the dead centre.
``mc.simulate`` ends the run at that stall (ω = 0) and says when and where it came.
"""

# %%
# The compressor
# --------------
# Two single-acting cylinders of 70 mm bore and 80 mm stroke on cranks 180° apart, each
# with the library's ideal compressor cycle (``Cylinder.compressor_diagram``: air from 1
# to 8 bar absolute, 8 cm³ of clearance), and a 1.2 kg·m² flywheel.
import math
import os

import matplotlib.pyplot as plt
import numpy as np

import multicrank as mc

# Short settings for the documentation's continuous-integration build.
FAST = os.environ.get("MULTICRANK_DOCS_FAST", "") not in ("", "0")

cylinder = mc.Cylinder(
    crank_radius=0.04,
    rod_length=0.16,
    piston_mass=0.9,
    rod_mass=0.6,
    rod_cg=0.11,
    crank_mass=1.5,
    crank_cg_radius=0.02,
    bore=0.07,
)
cylinder = cylinder.replace(
    pressure=cylinder.compressor_diagram(
        suction_pressure=1.0e5, discharge_pressure=8.0e5, clearance_volume=8e-6
    )
)
compressor = mc.Machine(
    [cylinder.replace(phase=phase) for phase in (0.0, math.pi)],
    shaft_inertia=1.2,
    strokes=2,
    name="two-cylinder compressor",
)
print(f"λ = {cylinder.crank_ratio:.2f}, I_w = {compressor.shaft_inertia} kg·m²")

# %%
# Friction
# --------
# The bearings resist with a constant torque of 1.5 N·m plus 0.01 N·m per rad/s. A load
# may be any vectorised function of the (cumulative) crank angle φ [rad] and the speed
# ω [rad/s] that returns N·m, positive resisting.


def friction(phi, omega):
    return 1.5 + 0.01 * np.asarray(omega)


# %%
# The run
# -------
# From 600 rpm, sampled every half millisecond for up to 30 s; the run stops earlier, at
# the stall. ``energy_drift`` compares the kinetic and potential energy with the work
# done on the shaft at every sample: a check of the whole computation.
rtol = 1e-7 if FAST else 1e-9
times = np.linspace(0.0, 30.0, 60001)
run = mc.simulate(compressor, times, rpm0=600, load=friction, rtol=rtol, atol=rtol)
print(f"{len(run)} samples, {run.rpm_history[0]:.0f} → {run.rpm_history[-1]:.0f} rpm")
turns = (run.phi[-1] - run.phi[0]) / (2 * math.pi)
stop = math.degrees(run.phi[-1] % compressor.cycle)
print(
    f"stalled: {run.stalled}, after {run.stall_time:.3f} s and {turns:.1f} revolutions"
)
print(f"stopped at φ = {stop:.1f}°")
print(
    f"the gas and the friction took {-run.work[-1]:.1f} J; "
    f"the kinetic energy at the start was {run.kinetic_energy[0]:.1f} J"
)
print(f"energy check: drift {run.energy_drift:.1e} of the largest kinetic energy")

# %%
# Speed and torques over time
# ---------------------------
# Each revolution carries two compressions (one per cylinder), and each slows the shaft
# sharply; between them the expanding clearance air gives a little back. As the speed
# falls, each compression takes a larger share of what is left, until one is not
# completed.
figure, (speed, torque) = plt.subplots(
    2, 1, figsize=(8, 6.5), sharex=True, layout="constrained"
)
speed.plot(run.time, run.rpm_history, linewidth=0.9)
speed.set_ylabel("speed n [rpm]")
speed.set_title(
    f"Run-down of a compressor from 600 rpm: stall after {run.stall_time:.2f} s"
)
for name, label in (
    ("gas_torque", "gas"),
    ("inertia_torque", "inertia"),
    ("gravity_torque", "gravity"),
    ("load_torque", "friction"),
):
    torque.plot(run.time, getattr(run, name), label=label, linewidth=0.7)
torque.set_xlabel("time t [s]")
torque.set_ylabel("torque [N·m]")
torque.legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), ncols=4, frameon=False)
plt.show()

# %%
# The stall
# ---------
# The last sample is the stall itself, with ω = 0 exactly. ``Machine.cycle_angles`` and
# ``Machine.piston_forces`` say where each cylinder is in its cycle (0° at its outer
# dead centre, where its volume is smallest) and how hard the air pushes on its piston
# (positive: toward the shaft):
angles = np.degrees(compressor.cycle_angles(run.phi[-1]))
forces = compressor.piston_forces(run.phi[-1])
for j, (angle, force) in enumerate(zip(angles, forces, strict=True), start=1):
    print(f"cylinder {j}: θ = {angle:5.1f}°, gas force on the piston {force:6.0f} N")
print(f"ω = {run.omega[-1]} rad/s, gas torque {run.gas_torque[-1]:.1f} N·m")

# %%
# The gas torque at the stall is negative: the machine stopped against the air it was
# compressing in one cylinder, short of that piston's outer dead centre.
