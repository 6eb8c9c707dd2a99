"""
Firing orders by torsional merit, free moments and δ; a V's bank factor
=======================================================================

An engine designer chooses a firing order by more than the speed fluctuation δ: by the
free moments it leaves on the foundation and the torsional vibration it excites in the
shaft. ``mc.firing_orders`` weighs them all, and marks the firing orders that no other
beats on every criterion at once (the Pareto front). Here a six-cylinder marine
two-stroke, whose choice is the classic one between free moments and torsional
vibration; the truck six, whose cam can change only the half orders; and the V-bank
factor of two cylinders on a pin.
"""

# %%
# A marine six: free moments against torsional vibration
# --------------------------------------------------------
# Six cylinders of the built-in slow-speed diesel (960 mm bore, 90 rpm) on a two-stroke
# crank with throws 60° apart, 1.7 m from throw to throw. Which throw gets which angle
# is the firing order: 5! = 120 arrangements (turning the whole crank is the same
# engine, later). Its shaft: six throws with their running gear, the turning wheel, and
# the propeller with its entrained water on a long intermediate shaft; its first mode,
# at 2.3 Hz, meets the sixth order — the major one, all six cylinders in phase — just
# below the speed range (23 rpm), so that within it only minor orders resonate, and the
# firing order decides how much of them cancels.
import matplotlib.pyplot as plt
import numpy as np

import multicrank as mc

diesel = mc.presets.MACHINES["slow-diesel-12"]
six = mc.Machine.from_layout(
    "inline-6-2t",
    diesel.cylinders[0],
    shaft_inertia=6.0e5,  # kg·m²: shaft, turning wheel, propeller and entrained water
    strokes=2,
    rpm=90.0,
    rpm_range=(25.0, 100.0),
    cylinder_spacing=1.70,  # m
    name="marine six",
)
shaft = mc.Shaft(
    [1.2e5] * 6 + [1.5e5, 6.0e5],  # kg·m²: six throws, turning wheel, propeller
    [9.0e8] * 5
    + [7.0e8, 0.95e8],  # N·m/rad: the crank's journals, then the intermediate shaft
    cylinder_nodes=[0, 1, 2, 3, 4, 5],
)
print(f"natural frequencies: {np.round(shaft.modes().natural_frequency[:3], 2)} Hz")
table = mc.firing_orders(six, shaft=shaft)
print(f"{table.attrs['candidates']} arrangements, {table.attrs['distinct']} distinct, "
      f"{table['pareto'].sum()} on the Pareto front")  # fmt: skip
columns = [
    "firing",
    "delta",
    "free_moment_1",
    "free_moment_2",
    "torsional_major",
    "torsional_minor",
    "pareto",
]
print(table.loc[table["pareto"], columns].to_string(float_format="{:.4g}".format))

# %%
# δ is the same in every row: on a rigid shaft the order of the throws along it does not
# matter to the motion. What it changes is where the forces act along the shaft — the
# first- and second-order free moments — and how the cylinders' torques add up on the
# shaft's modes. The first order's moment vanishes in two arrangements only, and those
# excite the shaft's minor orders about twice to four times as much as the quietest one,
# which leaves some 15 MN·m of first-order moment for the foundation (or a balancer) to
# take. The major orders' part is the same in every row: no firing order changes it.
delta_spread = np.ptp(table["delta"]) / table["delta"].mean()
print(f"δ spread over the rows: {delta_spread:.1e}")
no_first = table[table["free_moment_1"] == 0]
minors = no_first["torsional_minor"]
majors = table["torsional_major"]
print(
    f"no first-order moment: {len(no_first)} rows, minor orders' modal excitation "
    f"{minors.min():.3g}–{minors.max():.3g}; "
    f"the least of all: {table['torsional_minor'].min():.3g}; "
    f"the major orders' in every row: {majors.min():.3g}–{majors.max():.3g}"
)
quietest = table.loc[table["torsional_minor"].idxmin()]
merit = mc.torsional_merit(quietest["machine"], shaft, rpm_range=six.rpm_range)
print(f"{quietest['firing']}: the resonances in the speed range")
print(merit.to_string(float_format="{:.4g}".format))

# %%
# The truck six: the cam changes only the half orders
# ---------------------------------------------------
# The built-in truck diesel carries its own shaft (``Machine.shaft``: damper, six
# throws, flywheel; first mode 167 Hz). Its four-stroke crank fixes each phase modulo
# 360°, so a firing order moves a cylinder's torque by a whole revolution: every whole
# order ν is untouched (e^{iν·2π} = 1), and only the half orders change. The major sixth
# order meets the first mode at 1670 rpm, in the speed range: ``torsional_major`` is
# the same in every row, and the half orders' ``torsional_minor`` and δ decide.
truck = mc.presets.MACHINES["inline-6"]
truck_table = mc.firing_orders(truck)
shown = ["firing", "delta", "max_bearing_load", "torsional_major", "torsional_minor"]
print(truck_table[[*shown, "pareto"]].to_string(float_format="{:.4g}".format))

# %%
# A V's bank factor
# -----------------
# Two cylinders on one crank pin, their banks Θ apart, fire Θ apart in crank angle: for
# order ν their vectors make the angle νΘ, and add to 2·abs(cos(νΘ/2)) times one
# cylinder's. ``mc.torsional_merit`` has no formula for it: the factor comes out of the
# phases. (A four-stroke pair may as well fire 360° + Θ apart, the cam's choice: then
# each odd half order's vectors turn by a further half turn, and its factor is
# 2·abs(sin(νΘ/2)).)
template = (
    mc.presets.MACHINES["inline-4"]
    .cylinders[0]
    .replace(pressure=None, axial_position=0.0)
)
banks = np.radians(np.linspace(30.0, 180.0, 61))
orders = (1.0, 1.5, 2.0, 3.0)
factor = {order: [] for order in orders}
for bank in banks:
    gammas = (np.pi / 2 + bank / 2, np.pi / 2 - bank / 2)
    vee = mc.Machine(
        # the pin at the first bank's angle: cylinder 1 at phase 0, cylinder 2 at Θ
        [template.replace(inclination=g, phase=gammas[0] - g) for g in gammas],
        shaft_inertia=0.2,
        strokes=4,
        rpm=3000.0,
    )
    pair = mc.torsional_merit(
        vee, mc.Shaft([0.02, 0.3], [3e5], cylinder_nodes=[0, 0]), modes=1, max_order=3
    )
    for order in orders:
        factor[order].append(
            float(pair.loc[pair["order"] == order, "vector_sum"].iloc[0])
        )

figure, (left, right) = plt.subplots(1, 2, figsize=(9.5, 4.4), layout="constrained")
other = table[~table["pareto"]]
front = table[table["pareto"]]
left.scatter(
    other["free_moment_1"] / 1e6,
    other["torsional_minor"],
    s=18,
    color="0.6",
    label="dominated",
)
left.scatter(
    front["free_moment_1"] / 1e6,
    front["torsional_minor"],
    s=30,
    color="C3",
    label="Pareto front",
)
left.scatter(
    table["free_moment_1"].iloc[0] / 1e6,
    table["torsional_minor"].iloc[0],
    s=120,
    facecolors="none",
    edgecolors="black",
    label="as the layout lists it",
)
left.set_xlabel("first-order free moment [MN·m]")
left.set_ylabel("minor orders' modal excitation [N·m/√(kg·m²)]")
left.set_title(f"marine six: {table.attrs['distinct']} firing orders, one δ")
left.legend(loc="upper right", fontsize=8)
left.grid(linewidth=0.4, alpha=0.5)
for order, color in zip(orders, ("C0", "C1", "C2", "C4"), strict=True):
    right.plot(
        np.degrees(banks),
        factor[order],
        color=color,
        lw=2.5,
        alpha=0.5,
        label=f"order {order:g}",
    )
    right.plot(
        np.degrees(banks),
        np.abs(2 * np.cos(order * banks / 2)),
        ":",
        color="black",
        lw=0.8,
    )
right.set_xlabel("bank angle Θ [°]")
right.set_ylabel("vector sum of the pair")
right.set_title("two cylinders on a pin: 2·abs(cos(νΘ/2)) (dotted)")
right.legend(loc="lower left", fontsize=8)
right.grid(linewidth=0.4, alpha=0.5)
plt.show()

# %%
# **Left**: every distinct firing order of the marine six, all with one δ. Moving down
# means less torsional vibration in the speed range (the largest modal excitation of the
# shaft's first two modes by a minor order resonating there: ``torsional_minor``; the
# major orders' part, ``torsional_major``, is the same in every row), moving left a
# smaller first-order moment on the foundation; the red ones are the Pareto front, where
# one is bought only with the other (with the second-order moment and the bearing loads
# weighed too: a red point that looks beaten here is better on one of those). **Right**:
# the pair's vector sum over the bank angle for four orders, on the dotted
# 2·abs(cos(νΘ/2)): a 90° V's pair cancels its second order, a 60° V's its third, and at
# 180° (one pin, opposed) the odd orders cancel and the even ones add. The forced
# response — how large the vibration is with the shaft's damping — is openTorsion's to
# compute: ``mc.to_opentorsion(six, shaft=shaft)`` hands it the shaft and every
# cylinder's orders.
