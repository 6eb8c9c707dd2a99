"""
When may gravity be neglected?
==============================

Gravity's share of a machine's coefficient of speed fluctuation is, to first order,

.. math:: \\delta_g = \\max_\\varphi U_w^* - \\min_\\varphi U_w^*,

the range of the dimensionless potential energy U_w* = U/(I_w ω²) over one revolution
(``mc.speed_fluctuation``, from the exact extrema). Here it is mapped over the number of
cranks k = 1…12 and the crank ratio λ, for two- and four-stroke in-line machines, and
set against the threshold 1/3000 — a tenth of 1/300, the tightest coefficient of speed
fluctuation usually asked of a machine (generator sets) — below which gravity may be
neglected.
"""

# %%
# The crank unit
# --------------
# Every machine on the map is built of k copies of one crank unit: the cylinder of the
# built-in slow compressor (upright, 300 mm stroke, 85 kg piston, 60 kg rod), on that
# machine's shaft (I_w = 350 kg·m²) at its speed, 120 rpm. ``Machine.design`` gives the
# unit's dimensionless moments u1 (reciprocating masses) and u2 (rotating unbalance).
import math

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.colors import TwoSlopeNorm

import multicrank as mc

compressor = mc.presets.MACHINES["slow-compressor"]
unit = compressor.design()
print(
    f"λ = {unit['crank_ratio']:.3g}, γ = {math.degrees(unit['inclination']):.0f}°, "
    f"u1 = {unit['u1']:.4g}, u2 = {unit['u2']:.4g} at {compressor.rpm:g} rpm"
)

THRESHOLD = 1 / 3000

# %%
# δ_g over k and λ
# ----------------
# ``mc.crank_phases(k, strokes)`` gives the regular crank phases of an in-line machine
# (2π/k apart for a two-stroke, 4π/k for a four-stroke); ``mc.speed_fluctuation``
# broadcasts over an array of λ, so each row of the map is one call.
ratios = np.linspace(0.1, 0.5, 81)
cranks = np.arange(1, 13)
delta_g = {
    strokes: np.array(
        [
            mc.speed_fluctuation(
                crank_ratio=ratios,
                inclination=unit["inclination"],
                u1=unit["u1"],
                u2=unit["u2"],
                phases=mc.crank_phases(int(k), strokes),
            )
            for k in cranks
        ]
    )
    for strokes in (2, 4)
}

figure, axes = plt.subplots(1, 2, figsize=(8.5, 4.2), sharey=True, layout="constrained")
# Red where gravity matters, blue where it may be neglected, white at the threshold.
norm = TwoSlopeNorm(vmin=-16, vcenter=math.log10(THRESHOLD), vmax=-1)
for ax, (strokes, values) in zip(axes, delta_g.items(), strict=True):
    exponent = np.log10(np.maximum(values, 1e-16))
    image = ax.pcolormesh(
        ratios, cranks, exponent, norm=norm, cmap="RdBu_r", shading="nearest"
    )
    # Where a row crosses the threshold: a black bar at that λ.
    for k, row in zip(cranks, values, strict=True):
        for i in np.flatnonzero(np.diff(np.sign(row - THRESHOLD))):
            ax.plot(
                [np.mean(ratios[i : i + 2])] * 2,
                [k - 0.45, k + 0.45],
                color="black",
                linewidth=2,
            )
    ax.set_title(f"{strokes}-stroke")
    ax.set_xlabel("crank ratio λ = r/l [–]")
    ax.set_yticks(cranks)
axes[0].set_ylabel("cranks k")
bar = figure.colorbar(image, ax=axes, shrink=0.95)
bar.set_ticks(
    [-16, -12, -8, math.log10(THRESHOLD), -2],
    labels=["10⁻¹⁶", "10⁻¹²", "10⁻⁸", "1/3000", "10⁻²"],
)
bar.set_label(r"$\delta_g$ [–], log scale (10⁻¹⁶ and below alike)")
figure.suptitle(
    "Gravity's share of the speed fluctuation, k slow-compressor units at 120 rpm"
)
plt.show()

# %%
# What the map says
# -----------------
# Only three kinds of row are red:
#
# * **One crank** (k = 1): for an upright cylinder δ_g = 2(u1 + u2) whatever λ — between
#   the top and the bottom dead centre the piston falls a full stroke and the crank pin
#   a full diameter.
# * **The two-stroke twin** (cranks 180° apart) cancels the first harmonic of Q_u* but
#   keeps the second, whose coefficient Λ₂ ≈ λ/2 grows with the crank ratio: δ_g crosses
#   the threshold at a small λ.
# * **Cranks in phase**: the four-stroke twin has both cranks together (0° and 360°), so
#   its δ_g is twice the single crank's; the four-stroke four has the two-stroke twin's
#   crank (0°, 180°, 180°, 0°) and twice its δ_g.
#
# In every other row the crank sum leaves only harmonics of order 4 and up (listed
# below), whose coefficients Λ_n fall like λ^(n−1): δ_g lies orders of magnitude below
# the threshold over the whole range of λ, and grows steeply with it. Odd k are smoother
# than their even neighbours: Q_u* of one crank has only the first and even harmonics,
# so of the multiples of k only those of 2k survive.
#
# The numbers behind the rows, at the compressor's own λ = 0.25:
column = int(np.argmin(abs(ratios - unit["crank_ratio"])))
print(f"2(u1 + u2) = {2 * (unit['u1'] + unit['u2']):.3e}")
rows = (1, 2, 3, 4, 6, 8, 12)
table = pd.DataFrame(
    {
        "δ_g, 2-stroke": [delta_g[2][k - 1, column] for k in rows],
        "δ_g, 4-stroke": [delta_g[4][k - 1, column] for k in rows],
        "harmonics, 2-stroke": [mc.surviving_harmonics(k, strokes=2)[:3] for k in rows],
        "harmonics, 4-stroke": [mc.surviving_harmonics(k, strokes=4)[:3] for k in rows],
    },
    index=pd.Index(rows, name="k"),
)
print(table.to_string(float_format="{:.2e}".format))
# δ_g of the two-stroke twin rises with λ:
crossing = np.interp(THRESHOLD, delta_g[2][1], ratios)
print(f"the two-stroke twin reaches δ_g = 1/3000 at λ = {crossing:.3f}")

# %%
# The speed at which gravity stops mattering
# ------------------------------------------
# u1 and u2 scale with 1/(I_w ω²), so δ_g falls with the square of the speed: a machine
# whose δ_g is above the threshold at n reaches it at n·√(δ_g/threshold), and above that
# speed gravity may be neglected. At λ = 0.25, for the same shaft:
limit = {
    strokes: compressor.rpm * np.sqrt(values[:, column] / THRESHOLD)
    for strokes, values in delta_g.items()
}
speeds = pd.DataFrame(
    {f"{strokes}-stroke [rpm]": values for strokes, values in limit.items()},
    index=pd.Index(cranks, name="k"),
)
print(speeds.map(lambda n: f"{n:.0f}" if n >= 1 else "any").T.to_string())

figure, ax = plt.subplots(figsize=(8, 4), layout="constrained")
width = 0.4
for offset, (strokes, speeds) in zip(
    (-width / 2, width / 2), limit.items(), strict=True
):
    ax.bar(cranks + offset, speeds, width, label=f"{strokes}-stroke")
low, high = compressor.rpm_range
ax.axhspan(
    low,
    high,
    color="0.85",
    zorder=0,
    label=f"the compressor's speeds, {low:g}–{high:g} rpm",
)
ax.set_yscale("log")
ax.set_ylim(1, 1e4)
ax.set_xticks(cranks)
ax.set_xlabel("cranks k")
ax.set_ylabel(r"speed above which $\delta_g$ < 1/3000 [rpm]")
ax.set_title(
    "Gravity may be neglected above these speeds (no bar: below 1 rpm, at any speed)"
)
ax.legend(loc="upper right")
plt.show()

# %%
# The single crank, the twins and the four-stroke four would have to run faster than the
# speeds printed above before gravity could be left out: the single crank and the
# four-stroke twin faster than this compressor ever runs. Every other layout may leave
# it out above a few tens of rpm, most at any speed. A lighter or faster machine moves
# the whole map down with its smaller u1 and u2; the δ_g of any machine is one call
# away: ``machine.engine().speed_fluctuation()``.

# sphinx_gallery_thumbnail_number = 1
