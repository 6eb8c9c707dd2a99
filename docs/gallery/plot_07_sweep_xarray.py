"""
A design sweep into xarray
==========================

``mc.design_grid`` spans a grid of designs — every combination of the values given for
the crank ratio λ, the inclination γ, the moments u1 and u2, the number of cranks and
the cycle — and ``mc.sweep`` reduces each design to a few numbers in parallel, in Rust,
without forming the Q_u*(φ) curves. ``mc.to_xarray`` turns the result into an
``xarray.Dataset`` with one dimension per axis of the grid, ready for selection and
plotting.
"""

# %%
# The grid
# --------
# The moments u1 and u2 are those of the slow compressor's crank unit at its speed (see
# the first example); λ runs from 0.1 to 0.45, γ from lying (0°) to upright (90°), k
# from 1 to 4, two- and four-stroke. Inclinations are in radians in the API.
import os
import textwrap

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import LogNorm

import multicrank as mc

# Short settings for the documentation's continuous-integration build.
FAST = os.environ.get("MULTICRANK_DOCS_FAST", "") not in ("", "0")

unit = mc.presets.MACHINES["slow-compressor"].design()
grid = mc.design_grid(
    crank_ratio=np.linspace(0.1, 0.45, 15 if FAST else 71),
    inclination=np.radians(np.linspace(0, 90, 10 if FAST else 46)),
    u1=unit["u1"],
    u2=unit["u2"],
    cranks=[1, 2, 3, 4],
    strokes=[2, 4],
)
print(f"{len(grid)} designs, the first of them:")
print(grid.head(3))

# %%
# The sweep
# ---------
# ``phi=360`` is the grid of one revolution on which the RMS and the largest magnitude
# of Q_u* are taken; the energy extrema (and δ_g = ``energy_range``) are exact, not
# sampled.
result = mc.sweep(grid, phi=360)
print(
    result[
        ["crank_ratio", "inclination", "cranks", "strokes", "energy_range", "force_rms"]
    ].head()
)

data = mc.to_xarray(result)
# Degrees read better on an axis; units and names label the plots.
data = data.assign_coords(inclination=np.degrees(data["inclination"]))
data["crank_ratio"].attrs.update(long_name="crank ratio λ", units="–")
data["inclination"].attrs.update(long_name="inclination γ", units="°")
data["energy_range"].attrs.update(long_name=r"$\delta_g$", units="–")
data["force_rms"].attrs.update(long_name=r"RMS of $Q_u^*$", units="–")
print(dict(data.sizes))
print(textwrap.fill("variables: " + ", ".join(data.data_vars), 80))

# %%
# δ_g over λ and γ
# ----------------
# One panel per number of cranks (two-stroke), on a logarithmic colour scale. White is
# δ_g = 0: a lying cylinder (γ = 0) lifts no piston, and from k = 2 on the cranks cancel
# the rotating unbalance.
norm = LogNorm(1e-10, 1e-2)
figure, axes = plt.subplots(1, 4, figsize=(9, 3.6), sharey=True, layout="constrained")
for ax, k in zip(axes, data["cranks"].values, strict=True):
    image = (
        data["energy_range"]
        .sel(strokes=2, cranks=k)
        .plot(
            x="crank_ratio",
            y="inclination",
            ax=ax,
            norm=norm,
            cmap="viridis",
            add_colorbar=False,
        )
    )
    ax.set_title(f"k = {k}")
    if k > 1:
        ax.set_ylabel("")
figure.colorbar(image, ax=axes, label=r"$\delta_g$ [–]", extend="min")
figure.suptitle(
    r"Gravity's $\delta_g$ of k slow-compressor units at 120 rpm, two-stroke"
)
plt.show()

# %%
# A single crank's δ_g hardly depends on λ: it is set by γ, from 2u2 lying to 2(u1 + u2)
# upright. The twin's grows with λ and with γ. Three cranks leave only the sixth
# harmonic and its multiples: δ_g falls by orders of magnitude, the more so the smaller
# λ.
#
# Slices
# ------
# Selecting by coordinate gives lines: δ_g of upright machines over λ, two- and
# four-stroke, one line per k, against the threshold 1/3000 below which gravity may be
# neglected.
upright = data["energy_range"].sel(inclination=90.0)
figure, axes = plt.subplots(1, 2, figsize=(8.5, 3.8), sharey=True, layout="constrained")
for ax, strokes in zip(axes, (2, 4), strict=True):
    upright.sel(strokes=strokes).plot.line(
        x="crank_ratio", hue="cranks", ax=ax, yscale="log", add_legend=strokes == 2
    )
    ax.axhline(1 / 3000, color="black", linestyle="--", linewidth=1)
    ax.set_title(f"upright (γ = 90°), {strokes}-stroke")
axes[0].set_ylabel(r"$\delta_g$ [–]")
axes[1].set_ylabel("")
axes[1].text(0.44, 1 / 3000 * 1.5, "1/3000", ha="right")
figure.suptitle(r"$\delta_g$ of upright machines against the threshold 1/3000")
plt.show()

# %%
# The four-stroke twin (both cranks together) doubles the single crank; the four-stroke
# four behaves as the two-stroke twin, doubled. The other outputs are there to slice the
# same way — for instance the RMS of Q_u* of upright machines at λ = 0.25:
print(
    data["force_rms"]
    .sel(inclination=90.0, crank_ratio=0.25, method="nearest")
    .to_pandas()
)
