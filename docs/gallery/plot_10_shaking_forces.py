"""
An in-line three's rocking couple
=================================

The frame of a machine takes the reaction −Σ m·a of everything that moves in it.
``mc.shaking_forces`` gives it by order: the free forces [N] and, with the cylinders
placed along the shaft, the free moments [N·m]. An in-line three is the textbook case
of forces that cancel and moments that do not: three cranks 120° apart, one behind the
other, rock the engine end over end. A counterweight can take part of that couple, not
all of it.
"""

# %%
# The engine
# ----------
# The cylinder of the built-in ``inline-4`` car engine (86 mm bore, 85 mm stroke, a
# counterweight of 1.3 kg at 35 mm on each throw) on the in-line three's crank, the
# throws 94 mm apart along the shaft (``cylinder_spacing``), at 3000 rpm.
import math

import matplotlib.pyplot as plt
import numpy as np

import multicrank as mc

cylinder = mc.presets.MACHINES["inline-4"].cylinders[0]
three = mc.Machine.from_layout(
    "inline-3-4t",
    cylinder,
    shaft_inertia=0.2,
    rpm=3000,
    cylinder_spacing=0.094,
    name="in-line three",
)
one = mc.Machine([cylinder], shaft_inertia=0.2, strokes=4, rpm=3000, name="one")
print("throws along the shaft [m]:", three.throws)
print("crank pins [deg]:", np.degrees([c.phase for c in three.cylinders]) % 360)

# %%
# The orders
# ----------
# Each row is one order n (periods per revolution): the amplitude of its harmonic, and
# the parts of the force and of the moment that turn with the crank (forward) and
# against it (backward).
orders = mc.shaking_forces(three, max_order=6).orders
alone = mc.shaking_forces(one, max_order=6).orders
columns = ["force_vertical", "force_horizontal", "moment_pitch", "moment_yaw"]
print(orders[columns].to_string(float_format="{:.4g}".format))

# %%
# The three forces of the first order, and of the second, are equal and 120° apart:
# they add up to nothing, and so do those of the fourth and fifth. Only every third
# order survives, and it is small (the 6th, 1.6 N). But they act at z = 0, a and 2a,
# which leaves a couple of √3·a times one of them:
a = 0.094  # m
for n in (1, 2):
    couple = math.sqrt(3) * a * alone.loc[n, "force_vertical"]  # N·m
    print(
        f"order {n}: moment_pitch {orders.loc[n, 'moment_pitch']:.1f} N·m, "
        f"√3·a·F of one cylinder {couple:.1f}"
    )

# %%
# The curves over φ hold every order at once (``.curves()``, every degree of one
# revolution, from the closed-form kernels).
curves = mc.shaking_forces(three).curves()
print(curves.abs().max().to_string(float_format="{:.4g}".format))

# %%
# A balance counterweight
# -----------------------
# A counterweight turns with the crank. On each throw, one sized for the throw's
# rotating mass (web, the rod's big end) plus half its reciprocating mass (piston, the
# rest of the rod) leaves each throw's first order turning backward only, and so the
# couple. It adds 0.57 kg to each throw's 1.3 kg here.
c = cylinder
reciprocating = c.piston_mass + c.rod_mass * (1 - c.rod_cg / c.rod_length)  # kg
rotating = c.rod_mass * c.rod_cg / c.rod_length  # kg
first_moment = (
    c.crank_radius * (rotating + reciprocating / 2) + c.crank_mass * c.crank_cg_radius
)  # kg·m
heavier = c.replace(counterweight_mass=first_moment / c.counterweight_radius)
balanced = three.replace(
    cylinders=[
        x.replace(counterweight_mass=heavier.counterweight_mass)
        for x in three.cylinders
    ],
    name="balanced",
)
after = mc.shaking_forces(balanced, max_order=6).orders
after_curves = mc.shaking_forces(balanced).curves()
print(f"counterweight {c.counterweight_mass} → {heavier.counterweight_mass:.3f} kg")
parts = ["moment_pitch", "moment_yaw", "moment_forward", "moment_backward"]
print("as built:\n", orders.loc[[1, 2], parts].to_string(float_format="{:.4g}".format))
print("balanced:\n", after.loc[[1, 2], parts].to_string(float_format="{:.4g}".format))

# %%
# The figures
# -----------
# Above, the orders of the three as built: its forces beside one cylinder's (the three
# cancel them), its moments, and the moments over one revolution. Below, what the
# counterweight changes: the forward and backward parts of the moment by order, and the
# path of the moment vector (M_yaw, M_pitch) over one revolution.
shown = np.arange(1, 7)
width = 0.38
figure = plt.figure(figsize=(8.5, 7.5), layout="constrained")
top, bottom = figure.subfigures(2, 1, height_ratios=[1, 1.05])
forces_ax, moments_ax = top.subplots(1, 2)
forces_ax.bar(
    shown - width / 2,
    alone.loc[shown, "force_vertical"],
    width,
    color="0.7",
    label="one cylinder alone",
)
forces_ax.bar(
    shown + width / 2,
    orders.loc[shown, "force_vertical"],
    width,
    color="C0",
    label="the three",
)
for n in shown:
    forces_ax.annotate(
        f"{orders.loc[n, 'force_vertical']:.2g}",
        (n + width / 2, 0),
        xytext=(0, 3),
        textcoords="offset points",
        ha="center",
        fontsize=8,
        color="C0",
    )
forces_ax.set(title="vertical force by order", xlabel="order n", ylabel="amplitude [N]")
forces_ax.legend()
moments_ax.bar(
    shown - width / 2, orders.loc[shown, "moment_pitch"], width, label="pitch (Σ z·F_v)"
)
moments_ax.bar(
    shown + width / 2, orders.loc[shown, "moment_yaw"], width, label="yaw (Σ z·F_h)"
)
moments_ax.set(
    title="the three's moments by order", xlabel="order n", ylabel="amplitude [N·m]"
)
moments_ax.legend()
for ax in (forces_ax, moments_ax):
    ax.set_xticks(shown)
    ax.grid(axis="y", linewidth=0.4, alpha=0.5)
curve_ax = bottom.subplots()
degrees = np.degrees(curves.index.to_numpy())
curve_ax.plot(degrees, curves["moment_pitch"], label="pitch")
curve_ax.plot(degrees, curves["moment_yaw"], label="yaw")
curve_ax.set(
    title="the three's moments over one revolution, 3000 rpm "
    f"(its force: {curves['force_vertical'].abs().max():.2g} N at most)",
    xlabel="crank angle φ [deg]",
    ylabel="moment [N·m]",
    xlim=(0, 360),
    xticks=np.arange(0, 361, 60),
)
curve_ax.axhline(0, color="k", linewidth=0.5)
curve_ax.legend(loc="upper left")
curve_ax.grid(linewidth=0.4, alpha=0.5)
plt.show()

# %%
figure, (bars, path) = plt.subplots(1, 2, figsize=(9, 4.6), layout="constrained")
few = np.arange(1, 5)
step = 0.2
for offset, (table, label, hatch) in zip(
    (-step, step), ((orders, "as built", ""), (after, "balanced", "//")), strict=True
):
    for shift, part, colour in (
        (-step / 2, "forward", "C2"),
        (step / 2, "backward", "C3"),
    ):
        bars.bar(
            few + offset + shift,
            table.loc[few, f"moment_{part}"],
            step,
            color=colour,
            hatch=hatch,
            edgecolor="white" if not hatch else "k",
            linewidth=0.5,
            label=f"{part}, {label}",
        )
bars.annotate(  # the balanced forward first order
    "0", (1 + step / 2, 0), xytext=(0, 3), textcoords="offset points", ha="center"
)
bars.set(
    title="moment by order: forward and backward parts",
    xlabel="order n",
    ylabel="[N·m]",
    xticks=few,
)
bars.legend(fontsize=8)
bars.grid(axis="y", linewidth=0.4, alpha=0.5)
for table, label, style in (
    (curves, "as built", "-"),
    (after_curves, "balanced", "--"),
):
    path.plot(table["moment_yaw"], table["moment_pitch"], style, label=label)
reach = 1.1 * np.abs(curves[["moment_yaw", "moment_pitch"]].to_numpy()).max()
path.set(
    title="the moment vector over one revolution",
    xlabel="M_yaw [N·m]",
    ylabel="M_pitch [N·m]",
    aspect="equal",
    xlim=(-reach, reach),
    ylim=(-reach, reach),
)
path.axhline(0, color="k", linewidth=0.5)
path.axvline(0, color="k", linewidth=0.5)
path.legend(loc="upper right", fontsize=8)
plt.show()

# %%
# What the counterweight changes, and what it cannot
# --------------------------------------------------
# * **Forces**: none to change. The three's forces cancel up to the 6th order whatever
#   the counterweights, as long as every throw carries the same.
# * **The forward first order of the moment**: gone (323 N·m at 3000 rpm). The first
#   order is now a couple of constant size turning against the crank: its pitch and yaw
#   amplitudes are equal, and the largest first-order couple falls from forward +
#   backward, 530 N·m, to backward alone, 207 N·m.
# * **What it cannot**: the backward first order (207 N·m), and the whole second order
#   (64 N·m forward, 64 backward). A backward vector needs a balance shaft turning
#   against the crank at crank speed, the second order a pair at twice crank speed.
#   After the counterweight, the second order's couple (129 N·m at most) is more than
#   half the first order's.
#
# The price is in the yaw: the counterweights now overbalance each throw's rotating
# mass by half its reciprocating mass, and that surplus turns with the crank in the
# horizontal plane too: the first-order yaw moment grows from 116 to 207 N·m. A rocking
# mostly up and down becomes a smaller couple that swings round (the path on the right).
# Every amplitude grows with the square of the speed; ``steady=True`` adds what the
# speed fluctuation does (the how-to :doc:`/howto/shaking-forces`).
print(
    "largest first-order couple, as built and balanced [N·m]:",
    round(orders.loc[1, "moment_forward"] + orders.loc[1, "moment_backward"], 1),
    round(after.loc[1, "moment_forward"] + after.loc[1, "moment_backward"], 1),
)
