"""
The torque orders of a V8
=========================

Torsional-vibration work starts from the shaft torques as Fourier series in the crank
angle, M(φ) = Σ_ν A_ν cos(νφ − θ_ν), where the order ν counts the periods per
revolution. ``mc.torque_orders`` gives the orders of the gas, inertia and gravity
torques of any machine. Here they are for a 90° V8 and for one of its cylinders alone:
the V8's crank and firing order cancel most of them.
"""

# %%
# The layouts
# -----------
# ``mc.LAYOUTS`` holds the crank and cylinder arrangements; two of them are V8s:
import textwrap

import matplotlib.pyplot as plt
import numpy as np

import multicrank as mc

for name, layout in mc.LAYOUTS.items():
    if name.startswith("v8"):
        print(f"{name}: {layout.note}")

# %%
# The machine
# -----------
# ``Machine.from_layout`` puts one cylinder template on every bank: here the cylinder of
# the built-in ``inline-4`` car engine (86 mm bore, 85 mm stroke, its full-load
# four-stroke gas cycle), on the cross-plane crank. The crank web and counterweight go
# once on each of the four throws, and the firing order is the evenest the crank allows:
# every 90° of crank angle.
cylinder = mc.presets.MACHINES["inline-4"].cylinders[0]
v8 = mc.Machine.from_layout("v8-cross", cylinder, shaft_inertia=0.25, rpm=3000)
single = mc.Machine(
    [cylinder], shaft_inertia=0.25, strokes=4, rpm=3000, name="one cylinder"
)
print(f"{v8.name}: {len(v8)} cylinders, {v8.strokes}-stroke")
phases = np.degrees(v8.engine().phase)  # α_j: cylinder j is at the cycle angle φ + α_j
print("phases α_j mod 720° (firing):", np.sort(phases % 720))
print("phases α_j mod 360° (crank): ", np.sort(phases % 360))

# %%
# The orders at 3000 rpm
# ----------------------
# A four-stroke cycle spans two revolutions, so the gas torque has half orders too. The
# inertia torque −½J′(φ)ω² is taken at the mean speed; it grows with ω², while the gas
# and gravity torques do not depend on the speed.
rpm = 3000
orders = {
    machine.name: mc.torque_orders(machine, rpm, max_order=12)
    for machine in (single, v8)
}
columns = ["gas_amplitude", "inertia_amplitude", "gravity_amplitude"]
print(
    orders["v8-cross"][columns]
    .loc[[0.0, 1.0, 2.0, 4.0, 8.0, 12.0]]
    .to_string(float_format="{:.3e}".format)
)

# %%
# What cancels
# ------------
# An order whose amplitude is below 10⁻¹² of the largest of its torque is rounding: it
# has cancelled. The bars show the rest on a logarithmic scale (each torque's order 0 —
# the mean, nonzero for the gas torque alone — is left out).
parts = {"gas": "C0", "inertia": "C1", "gravity": "C2"}
titles = {
    "one cylinder": "one of its cylinders alone",
    "v8-cross": "the 90° V8, cross-plane crank",
}
figure, axes = plt.subplots(
    2, 1, figsize=(8, 7), sharex=True, sharey=True, layout="constrained"
)
width = 0.15
for ax, (name, table) in zip(axes, orders.items(), strict=True):
    order = table.index.to_numpy()
    shown = order > 0
    whole = order == np.round(order)
    for offset, (part, colour) in zip((-width, 0.0, width), parts.items(), strict=True):
        amplitude = table[f"{part}_amplitude"].to_numpy()
        kept = shown & (amplitude > 1e-12 * amplitude[shown].max())
        # Half orders (gas only) sit on their own tick.
        ax.bar(
            np.where(whole, order + offset, order)[kept],
            amplitude[kept],
            width,
            color=colour,
            label=part,
        )
    ax.set_yscale("log")
    ax.set_ylabel("amplitude $A_ν$ [N·m]")
    ax.set_title(f"{titles[name]}: four-stroke, {rpm} rpm")
    ax.grid(axis="y", linewidth=0.4, alpha=0.5)
axes[0].legend(loc="upper right", ncols=3)
axes[1].set_xlabel("order ν [periods per revolution]")
axes[1].set_xticks(np.arange(0, 12.5, 1))
axes[1].set_xticks(np.arange(0.5, 12, 1), minor=True)
axes[1].set_ylim(1e-11, 2e3)
plt.show()

# %%
# Which survive, computed:
for name, table in orders.items():
    for part in parts:
        amplitude = table[f"{part}_amplitude"]
        moving = amplitude[amplitude.index > 0]  # order 0 is the mean
        surviving = moving[moving > 1e-12 * moving.max()].index
        listed = ", ".join(f"{v:g}" for v in surviving)
        print(textwrap.fill(f"{name}, {part}: {listed}", 80, subsequent_indent="    "))

# %%
# * **Gas torque**: one cylinder has every order, half and whole. The V8's cylinders are
#   spaced evenly over the 720° of the cycle, one every 90° (the phases mod 720° above),
#   so only the orders that are multiples of 4 survive: 4, 8, 12. The half orders and
#   the orders 1 to 3 cancel; order 0, the mean torque, adds up.
# * **Inertia torque**: one cylinder has whole orders only (J(φ) repeats every
#   revolution). Its torque depends only on the crank's angle to its own cylinder axis,
#   φ + α_j, and modulo 360° the V8's α_j fall on four angles 90° apart (twice each):
#   again only multiples of 4 survive.
# * **Gravity torque**: one upright cylinder has order 1 and the even orders (the
#   Fourier form of the theory). In the V8 they too cancel down to the orders 4, 8 and
#   12, which come to a few thousandths of a N·m: negligible beside the others, at any
#   speed, since the gravity torque does not depend on the speed.
#
# The shaft torques do not tell the two V8 cranks apart: the flat-plane crank gives the
# same amplitudes to rounding. What distinguishes them are the free forces and moments
# on the engine's mounts, which these torques do not include.
flat = mc.torque_orders(
    mc.Machine.from_layout("v8-flat", cylinder, shaft_inertia=0.25), rpm, max_order=12
)
cross = orders["v8-cross"]
difference = (flat[columns] - cross[columns]).abs().max() / cross[columns].max()
print("largest difference flat − cross, relative to the largest amplitude:")
print(difference.to_string(float_format="{:.1e}".format))
