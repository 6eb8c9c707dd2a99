"""
A compressor's speed over the cycle, with and without gravity
=============================================================

The built-in ``slow-compressor`` is a heavy, slow, upright, double-acting air compressor
driven at 120 rpm: the kind of machine where gravity is not negligible.
``mc.steady_state`` solves its periodic steady running exactly: the speed ω(φ) over one
cycle and the coefficient of speed fluctuation δ = (ω_max − ω_min)/ω_m. Solving it once
with gravity and once without (``gravity=False``) shows what the weight of the piston,
rod and crank does to the speed.
"""

# %%
# The machine and its steady state
# --------------------------------
# With the default load ``"balance"`` the motor supplies the constant torque that keeps
# the mean speed at the ``rpm`` asked for: the cycle mean of the gas torque (gravity's
# mean is zero). A compressor absorbs work, so that load comes out negative: the motor
# drives.
import math
import textwrap

import matplotlib.pyplot as plt
import numpy as np

import multicrank as mc

compressor = mc.presets.MACHINES["slow-compressor"]
print(textwrap.fill(compressor.note, 80))

with_gravity = mc.steady_state(compressor, rpm=120)
without_gravity = mc.steady_state(compressor, rpm=120, gravity=False)
print(with_gravity)

# %%
# The summary above already names δ without gravity (``delta_without_gravity``): it is
# the δ of the second solution, solved for the same load rule at the same mean speed.
for solved in (with_gravity, without_gravity):
    print(
        f"gravity={solved.gravity}: δ = {solved.delta:.5f} = 1/{1 / solved.delta:.1f}"
    )
change = with_gravity.gravity_effect  # δ/δ₀ − 1
print(f"gravity changes δ by {100 * change:+.1f} %")
print(
    f"the motor's torque: {-with_gravity.mean_load_torque:.0f} N·m, "
    f"{-with_gravity.mean_load_torque * with_gravity.omega_mean / 1e3:.1f} kW"
)

# %%
# ω(φ) over the cycle
# -------------------
# One revolution of this two-stroke machine, φ from the outer dead centre of the head
# end. The arrays of a :class:`~multicrank.SteadyState` are uniform in φ over the closed
# cycle; ``omega`` is in rad/s. Below the speed, the torques behind it, with gravity:
# the gas torque of both ends of the cylinder, the gravity torque −dU/dφ, the inertia
# torque −½J′(φ)ω² of the rod and piston, and the motor's constant torque (the negative
# of the load).
figure, (speed, torque) = plt.subplots(
    2, 1, figsize=(8, 6.5), sharex=True, layout="constrained"
)
for state, label, style in (
    (with_gravity, "with gravity", "-"),
    (without_gravity, "without gravity", "--"),
):
    speed.plot(
        np.degrees(state.phi),
        state.omega * 30 / math.pi,
        style,
        label=f"{label}: δ = {state.delta:.4f} = 1/{1 / state.delta:.1f}",
    )
speed.axhline(120, color="0.6", linewidth=0.8)
speed.set_ylabel("speed n [rpm]")
speed.set_title("slow-compressor at a mean 120 rpm: ω(φ) over one revolution")
speed.legend(loc="upper left")
state = with_gravity
for values, label in (
    (state.gas_torque, "gas"),
    (state.gravity_torque, "gravity"),
    (state.inertia_torque, "inertia"),
    (-state.load_torque, "motor"),
):
    torque.plot(np.degrees(state.phi), values / 1e3, label=label)
torque.axhline(0, color="0.6", linewidth=0.8)
torque.set_xlabel("crank angle φ [°]")
torque.set_ylabel("torque on the shaft [kN·m]")
torque.set_xticks(np.arange(0, 361, 45))
torque.legend(loc="lower left", ncols=4)
plt.show()

# %%
# What gravity does
# -----------------
# The gravity torque is small beside the gas torque, but it keeps one sign for half a
# revolution: it helps the shaft while the piston and rod go down (φ from 0° to 180°,
# the cylinder being upright) and brakes it while they are lifted. The energy it moves
# is the range of the potential energy U(φ), which is not small beside the swing of the
# kinetic energy:
phi = np.linspace(0, 2 * math.pi, 3601)
potential = compressor.potential_energy(phi)
kinetic = 0.5 * state.reduced_inertia * state.omega**2
print(
    f"largest |torque|: gravity {abs(state.gravity_torque).max():.0f} N·m, "
    f"gas {abs(state.gas_torque).max():.0f} N·m"
)
print(
    f"range of U(φ): {np.ptp(potential):.0f} J; swing of ½Jω²: {np.ptp(kinetic):.0f} J"
)
# δ of the machine coasting (no gas, no motor) is not gravity's share of δ: J(φ)'s
# variation shakes the coasting shaft too (what gravity does to δ is gravity_effect).
print(f"δ coasting (no gas, no motor; J(φ) and gravity): {state.delta_coasting:.5f}")
for solved in (with_gravity, without_gravity):
    slowest, fastest = math.degrees(solved.phi_min), math.degrees(solved.phi_max)
    print(
        f"gravity={solved.gravity}: slowest at {slowest:.0f}°, fastest {fastest:.0f}°"
    )

# %%
# Without gravity the two compression strokes (head end and crank end) leave two speed
# dips of nearly the same depth. Gravity lifts the first (where it helps) and deepens
# the second (where it brakes), so the slowest point moves to the second half-revolution
# and δ grows by the percentage printed above. A flywheel sized without gravity would
# leave this compressor short of the δ it was sized for; the next example sizes it both
# ways.
