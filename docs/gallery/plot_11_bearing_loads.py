"""
The compressor's main bearings and its counterweight
====================================================

A counterweight chosen for the speed fluctuation δ alone is not the one an engine
designer would choose. ``mc.bearing_loads`` gives the force each main bearing receives
from the shaft over the cycle — the gas force carried through the rod, the piston and
the rod as rigid bodies, the web and the counterweight, the weights — and
``mc.motion_sweep`` gives δ, the free first-order force and the largest bearing load of
every counterweight at once.
"""

# %%
# The compressor as built
# -----------------------
# The built-in slow compressor: one horizontal double-acting cylinder, a crank web of 40
# kg at 80 mm and a counterweight of 30 kg at 120 mm opposite the pin, between two main
# bearings 0.3 m apart, at 120 rpm. Its bearings share the throw's load equally.
import matplotlib.pyplot as plt
import numpy as np

import multicrank as mc

compressor = mc.presets.MACHINES["slow-compressor"]
cylinder = compressor.cylinders[0]
built = mc.bearing_loads(compressor)
print(built.summary.round(1).to_string())

# %%
# Every counterweight at once
# ---------------------------
# The counterweight's mass from none to ten times the built one, at the same radius: δ
# of the steady state with gravity, the first-order free force (the largest over a
# cycle) and the largest main-bearing load, one row per design, from the Rust core.
masses = np.linspace(0.0, 300.0, 121)
swept = mc.motion_sweep(
    compressor,
    mc.MachineGrid(compressor, counterweight_mass=masses),
    outputs=["delta", "free_force_1", "max_bearing_load"],
)
as_built = swept.loc[int(np.argmin(np.abs(masses - cylinder.counterweight_mass)))]
best_delta = swept.loc[swept["delta"].idxmin()]
least_free = swept.loc[swept["free_force_1"].idxmin()]
for label, row in (
    ("as built", as_built),
    ("least free force", least_free),
    ("least δ", best_delta),
):
    mass, delta = row["counterweight_mass"], row["delta"]
    free, bearing = row["free_force_1"], row["max_bearing_load"]
    print(
        f"{label:>16}: {mass:5.1f} kg, δ = {delta:.4f}, "
        f"free first order {free:6.0f} N, largest bearing load {bearing:6.0f} N"
    )

# %%
# What δ's best counterweight does to the bearings
# ------------------------------------------------
# The polar diagram of a bearing's load: the tip of the force vector over the cycle, the
# shaft at the centre. The gas force through the rod dominates it at 120 rpm; the
# counterweight that minimises δ adds its centrifugal force, m_p·r_p·ω², turning with
# the crank all the way round.
heavy = compressor.replace(
    cylinders=[
        cylinder.replace(counterweight_mass=float(best_delta["counterweight_mass"]))
    ]
)
loaded = mc.bearing_loads(heavy)

fig = plt.figure(figsize=(9.5, 4.2), layout="constrained")
polar, trade = fig.subplots(1, 2, width_ratios=[1, 1.3])
reach = 1.15 * max(built.magnitude[0].max(), loaded.magnitude[0].max())
polar.plot(
    built.horizontal[0],
    built.vertical[0],
    label=f"as built, {cylinder.counterweight_mass:.0f} kg",
)
polar.plot(
    loaded.horizontal[0],
    loaded.vertical[0],
    label=f"least δ, {best_delta['counterweight_mass']:.0f} kg",
)
polar.plot([0], [0], marker="+", color="k")
polar.set(
    aspect="equal",
    xlim=(-reach, reach),
    ylim=(-reach, reach),
    xlabel="horizontal [kN]",
    ylabel="vertical [kN]",
    title="front main bearing, 120 rpm",
)
polar.xaxis.set_major_formatter(lambda x, _: f"{x / 1e3:g}")
polar.yaxis.set_major_formatter(lambda y, _: f"{y / 1e3:g}")
polar.legend(fontsize="small", loc="upper left")
polar.grid(alpha=0.3)

trade.plot(
    swept["counterweight_mass"],
    swept["max_bearing_load"] / 1e3,
    label="largest bearing load [kN]",
)
trade.plot(
    swept["counterweight_mass"],
    swept["free_force_1"] / 1e3,
    label="first-order free force [kN]",
)
trade.set(xlabel="counterweight mass [kg] (at 120 mm)", ylabel="[kN]")
delta_axis = trade.twinx()
delta_axis.plot(
    swept["counterweight_mass"], swept["delta"], color="C2", ls="--", label="δ (right)"
)
delta_axis.set_ylabel("δ")
for mass, style in (
    (cylinder.counterweight_mass, "-"),
    (least_free["counterweight_mass"], ":"),
    (best_delta["counterweight_mass"], "--"),
):
    trade.axvline(mass, color="0.6", lw=0.8, ls=style)
lines = trade.get_lines()[:2] + delta_axis.get_lines()[:1]
trade.legend(
    lines, [line.get_label() for line in lines], fontsize="small", loc="center right"
)
trade.grid(alpha=0.3)
trade.set_title(
    "every counterweight (grey: as built, least free force, least δ)", fontsize="medium"
)
plt.show()

# %%
# Reading it
# ----------
# The counterweight that makes δ least is about seven times the built one, which is what
# ``mc.optimize_counterweights`` recommends when δ is all it looks at. The free first-
# order force is least well before that, where the counterweight balances the rotating
# masses and half the reciprocating ones; past it the counterweight's own unbalance
# grows again. The largest bearing load grows with every kilogram. A counterweight is
# chosen by the free forces and the bearing loads first; δ is then the flywheel's to
# fix.
reduction = best_delta["delta"] / as_built["delta"] - 1
ratio = best_delta["counterweight_mass"] / cylinder.counterweight_mass
grow = best_delta["max_bearing_load"] / as_built["max_bearing_load"] - 1
print(f"least δ at {ratio:.1f} × the built counterweight: δ {reduction:+.1%}")
free = best_delta["free_force_1"]
print(f"its largest bearing load {grow:+.1%}, its free first-order force {free:.0f} N")
lightest, smallest = least_free["counterweight_mass"], least_free["free_force_1"]
print(f"least free force at {lightest:.0f} kg ({smallest:.0f} N)")
