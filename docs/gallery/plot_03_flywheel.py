"""
Sizing a flywheel, with and without gravity
===========================================

How heavy a flywheel does the slow compressor need? ``mc.flywheel_inertia`` finds the
shaft inertia I_w [kg·m²] that gives a coefficient of speed fluctuation δ exactly: it
solves the periodic steady state for trial inertias and takes the root of δ(I_w) = δ.
Beside it, it gives the textbook estimate ΔE/(δ ω²), and the inertia the same machine
would need if gravity were left out.
"""

# %%
# The target δ of the machine's class
# -----------------------------------
# ``mc.presets.SPEED_FLUCTUATION`` holds the usual range of δ for each class of machine,
# ``mc.presets.MACHINE_CLASSES`` the class of each built-in machine. Compressors ask for
# δ between 1/50 and 1/20; take the middle of that range on a log scale, about 1/32.
import math
import os

import matplotlib.pyplot as plt
import numpy as np

import multicrank as mc

# Short settings for the documentation's continuous-integration build.
FAST = os.environ.get("MULTICRANK_DOCS_FAST", "") not in ("", "0")

compressor = mc.presets.MACHINES["slow-compressor"]
kind = mc.presets.MACHINE_CLASSES[compressor.name]
smoothest, roughest = mc.presets.SPEED_FLUCTUATION[kind]
target = math.sqrt(smoothest * roughest)
print(f"class {kind!r}: δ from 1/{1 / smoothest:.0f} to 1/{1 / roughest:.0f}")
print(f"target δ = 1/{1 / target:.1f}")

# %%
# The flywheel for that δ
# -----------------------
# With the default load ``"balance"`` the motor's torque is the constant that holds the
# mean speed (here 120 rpm). The result carries the exact inertia with gravity, the
# exact inertia without it, and the textbook estimate ΔE/(δ ω_m²) − mean(J − I_w), where
# ΔE is the largest swing of the work of all the torques at constant speed over a cycle,
# the inertia torque −½J′ω_m² of the rods and pistons among them.
flywheel = mc.flywheel_inertia(compressor, delta=target, rpm=120)
print(f"I_w = {flywheel.shaft_inertia:.1f} kg·m² with gravity")
print(f"I_w = {flywheel.shaft_inertia_without_gravity:.1f} kg·m² without gravity")
print(f"textbook estimate {flywheel.textbook:.1f} kg·m² (with gravity)")
extra = flywheel.shaft_inertia - flywheel.shaft_inertia_without_gravity
share = extra / flywheel.shaft_inertia_without_gravity
print(f"gravity asks for {extra:.0f} kg·m² more ({100 * share:.0f} %)")
print(f"ΔE = {flywheel.energy_swing:.0f} J")
print(f"the textbook estimate is off by {100 * flywheel.textbook_error:+.1f} %")
print(f"the machine as built has I_w = {compressor.shaft_inertia:g} kg·m²")

# %%
# The textbook estimate is a good start, but an estimate: it takes every torque at the
# constant mean speed, while the speed, and with it the inertia torque, varies over the
# cycle. It is right to first order, off by a fraction of the order of δ (the percentage
# printed above). Leaving gravity out errs by far more: it misses the energy that the
# falling and rising piston, rod and crank move each revolution.
#
# I_w over the target δ
# ---------------------
# The same for every δ of the class and a little beyond. Each point is one root-finding
# over exact steady states, a few milliseconds.
deltas = np.geomspace(1 / 60, 1 / 15, 8 if FAST else 30)
sized = [mc.flywheel_inertia(compressor, delta=d, rpm=120) for d in deltas]
exact = np.array([f.shaft_inertia for f in sized])
without = np.array([f.shaft_inertia_without_gravity for f in sized])
textbook = np.array([f.textbook for f in sized])
as_built = mc.steady_state(compressor, rpm=120)  # δ with the machine's own flywheel

figure, ax = plt.subplots(figsize=(8, 4.5), layout="constrained")
ax.axvspan(
    1 / smoothest,
    1 / roughest,
    color="0.9",
    label=f"the {kind} class: δ from 1/50 to 1/20",
)
ax.plot(1 / deltas, exact, "-o", markersize=3, label="exact, with gravity")
ax.plot(1 / deltas, without, "--", label="exact, without gravity")
ax.plot(
    1 / deltas,
    textbook,
    ":",
    color="black",
    label="textbook ΔE/(δω²) − mean(J − $I_w$), with gravity",
)
ax.plot(
    1 / flywheel.delta,
    flywheel.shaft_inertia,
    "*",
    markersize=12,
    color="C3",
    label=f"target δ = 1/{1 / target:.1f}",
)
ax.plot(
    1 / as_built.delta,
    compressor.shaft_inertia,
    "s",
    color="C2",
    label=f"as built: δ = 1/{1 / as_built.delta:.1f}",
)
ax.set_xlabel("1/δ [–]  (larger: smoother running)")
ax.set_ylabel("shaft inertia $I_w$ [kg·m²]")
ax.set_title("slow-compressor at 120 rpm: the flywheel that a δ needs")
ax.legend(loc="upper left")
plt.show()

# %%
# Over the whole class I_w grows in proportion to 1/δ, as the textbook rule says: the
# three lines are nearly straight and nearly through the origin. The machine as built
# (the square) lies on the exact line with gravity, as it must. The gap between the
# exact lines with and without gravity is the flywheel that gravity alone asks for; at
# this machine's speed it is too large to neglect (see the first example for where it is
# not). Faster machines need far less of it: δ_g falls with the square of the speed.
