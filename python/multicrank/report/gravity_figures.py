"""The report's gravity figures (:mod:`.gravity` has the tables and the HTML): for the machine's
crank unit (its first cylinder) on k = 1 … k_max in-line cranks, U_w*(φ) and Q_u*(φ), the
harmonic spectra of Q_u*, the error of the paper's truncated λ-series, and the
gravity-significance map: δ_g over k and λ, per preset machine over its speeds, and per preset
layout. Each returns the figure and the table of its data.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from .._native import MechanismError
from ..gravity.evaluation import generalized_force, potential_energy
from ..gravity.extrema import speed_fluctuation
from ..gravity.harmonics import fourier_coefficients, lambda_coefficients
from ..gravity.layouts import LAYOUTS
from ..gravity.mechanism import crank_phases
from ..machine.machine import Machine
from .plotting import plain_log_axis, pyplot, threshold_text
from .settings import ReportSettings, running_speed, speed_range

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "curves_figure",
    "layouts_figure",
    "machines_figure",
    "significance_map",
    "spectra_figure",
    "truncation_figure",
]


# ----------------------------------------------------------------------------- the crank unit
def _unit_machine(machine: Machine) -> Machine:
    """The machine's first cylinder alone, with its throw's crank web and counterweight: the
    crank unit that the paper's sections (identical units on k in-line cranks) are about."""
    return Machine(
        [machine.cylinders[0]],
        shaft_inertia=machine.shaft_inertia,
        strokes=machine.strokes,
        g=machine.g,
        rpm=running_speed(machine),
        name=machine.name,
    )


def _is_inline(machine: Machine) -> bool:
    """Whether the machine is the paper's: identical units differing only in phase."""
    try:
        machine.design(running_speed(machine))
    except MechanismError:
        return False
    return True


# ----------------------------------------------------------------------------- figures
def _grid_shape(count: int) -> tuple[int, int]:
    cols = min(4, count)
    return math.ceil(count / cols), cols


def _small_multiples(plt: Any, count: int, xlabel: str, ylabel: str, **options: Any) -> tuple[Figure, list[Axes]]:
    """A grid of panels, one per k = 1 … count, labelled inside (leaving room for the y
    offset text); returns the figure and the panels in use."""
    rows, cols = _grid_shape(count)
    fig, axes = plt.subplots(rows, cols, figsize=(3.0 * cols, 2.1 * rows), squeeze=False, **options)
    for ax in axes.flat[count:]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel(xlabel)
    for ax in axes[:, 0]:
        ax.set_ylabel(ylabel)
    for k, ax in enumerate(axes.flat[:count], start=1):
        ax.text(
            0.97,
            0.92,
            f"k = {k}",
            transform=ax.transAxes,
            ha="right",
            va="top",
            fontsize=9,
            bbox=dict(facecolor="white", edgecolor="none", alpha=0.8),
        )
    return fig, list(axes.flat[:count])


def _unit(machine: Machine, cranks: int, strokes: int) -> dict[str, Any]:
    """The machine's crank unit (its first cylinder) on a regular single-acting k-crank shaft of
    the given cycle (the machines of the paper's eq. 16 and Tables 1–2)."""
    return {**_unit_machine(machine).design(), "phases": crank_phases(cranks, strokes, "single")}


def curves_figure(settings: ReportSettings, strokes: int, quantity: str) -> tuple[Figure, pd.DataFrame]:
    plt = pyplot()
    from matplotlib.ticker import ScalarFormatter

    phi_deg = np.linspace(0.0, 360.0, settings.points)
    phi = np.radians(phi_deg)
    # U_w* is drawn relative to its value at φ = 0: the offset grows with k and would hide
    # the variation, which is what matters. The CSV holds the values themselves.
    label = "U_w*(φ) − U_w*(0)" if quantity == "energy" else "Q_u*(φ)"
    fig, panels = _small_multiples(plt, settings.k_max, "φ [deg]", label, sharex=True)
    table = {"phi_deg": phi_deg}
    for k, ax in enumerate(panels, start=1):
        design = _unit(settings.machine, k, strokes)
        values = potential_energy(phi, **design) if quantity == "energy" else generalized_force(phi, **design)
        table[f"k{k}"] = values
        shown = values - values[0] if quantity == "energy" else values
        rounding = 64 * np.finfo(float).eps * k * (abs(design["u1"]) + abs(design["u2"]))
        if np.ptp(shown) < rounding:
            # Cancelled to below the closed form's rounding: say so rather than plot noise.
            ax.axhline(0.0, color="grey", lw=1.0)
            delta = float(speed_fluctuation(**design))
            ax.text(
                0.5,
                0.4,
                f"constant to rounding\nδ_g = {delta:.2g} (exact)",
                transform=ax.transAxes,
                ha="center",
                fontsize=8,
                color="grey",
            )
        else:
            ax.plot(phi_deg, shown, color="C0" if quantity == "energy" else "C3", lw=1.2)
        ax.set_xticks([0, 90, 180, 270, 360])
        formatter = ScalarFormatter(useMathText=True)
        formatter.set_powerlimits((-2, 3))
        ax.yaxis.set_major_formatter(formatter)
    gamma = math.degrees(settings.machine.cylinders[0].inclination)
    fig.suptitle(
        f"{label} of {settings.machine.name}'s crank unit on k cranks, {strokes}-stroke, "
        f"single-acting, γ = {gamma:g}° (dimensionless, ÷ I_w ω²)",
        fontsize=10,
    )
    fig.tight_layout()
    return fig, pd.DataFrame(table)


def spectra_figure(settings: ReportSettings, strokes: int) -> tuple[Figure, pd.DataFrame]:
    plt = pyplot()
    fig, panels = _small_multiples(plt, settings.k_max, "harmonic n", "|a_n + i b_n|", sharex=True, sharey=True)
    n = np.arange(settings.n_max + 1)
    records = []
    for k, ax in enumerate(panels, start=1):
        a, b = fourier_coefficients(**_unit(settings.machine, k, strokes), n_max=settings.n_max)
        amplitude = np.hypot(a, b)
        records += [{"k": k, "n": int(i), "amplitude": amplitude[i]} for i in n if amplitude[i] > 0]
        shown = amplitude > 0
        ax.bar(n[shown], amplitude[shown], color="C2", width=0.8)
        ax.set_yscale("log")
        ax.set_xticks(range(0, settings.n_max + 1, 6))
    fig.suptitle(
        f"Harmonic amplitudes of Q_u* (exact Λ_n), {settings.machine.name}'s unit on k cranks, "
        f"{strokes}-stroke, single-acting",
        fontsize=10,
    )
    fig.tight_layout()
    return fig, pd.DataFrame(records)


def truncation_figure(settings: ReportSettings) -> tuple[Figure, pd.DataFrame]:
    """The paper's λ¹¹ series against the exact Λ_n, and its effect on f(ψ)."""
    plt = pyplot()
    lam = np.linspace(0.01, 0.95, settings.lambdas)
    exact = lambda_coefficients(lam, 12)
    paper = lambda_coefficients(lam, 12, method="paper")
    psi = np.linspace(0, np.pi, 2001)
    s = np.sin(psi)
    f_exact = (lam[:, None] / 2) * np.sin(2 * psi) / np.sqrt(1 - (lam[:, None] * s) ** 2)
    f_paper = sum(paper[:, n, None] * np.sin(n * psi) for n in range(2, 13, 2))
    f_error = np.max(np.abs(f_paper - f_exact), axis=1)
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.8))
    table = {"crank_ratio": lam, "f_max_abs_error": f_error}
    for n in range(2, 13, 2):
        relative = np.abs(paper[:, n] - exact[:, n]) / np.abs(exact[:, n])
        table[f"Lambda{n}_relative_error"] = relative
        left.semilogy(lam, relative, label=f"Λ_{n}")
    left.axvline(0.4, color="grey", lw=0.8, ls=":")
    left.set_xlabel("crank ratio λ")
    left.set_ylabel("|Λ_n(paper) − Λ_n| / |Λ_n|")
    left.set_title("Relative error of the paper's Λ_n (λ-series through λ¹¹)")
    left.legend(ncol=2, fontsize=8)
    right.semilogy(lam, f_error, color="C3", label="max_ψ |f_paper − f|")
    right.semilogy(lam, 0.037 * lam**13, color="grey", ls="--", label="0.037·λ¹³")
    right.set_xlabel("crank ratio λ")
    right.set_ylabel("max over ψ")
    right.set_title("Truncation error of f(ψ) = Σ Λ_n sin nψ (n ≤ 12)")
    right.legend(fontsize=8)
    fig.tight_layout()
    return fig, pd.DataFrame(table)


def significance_map(settings: ReportSettings) -> tuple[Figure, pd.DataFrame]:
    """δ_g over k and λ for the machine's unit (two- and four-stroke), at its speed."""
    plt = pyplot()
    from matplotlib.colors import TwoSlopeNorm

    machine = settings.machine
    lam = np.linspace(0.1, 0.5, 41)
    ks = np.arange(1, settings.k_max + 1)
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.9), sharey=True)
    records = []
    unit = _unit_machine(machine).design()
    # Red: gravity matters (δ_g above the threshold); blue: negligible. White at the threshold.
    center = math.log10(settings.threshold)
    norm = TwoSlopeNorm(vcenter=center, vmin=min(-14.0, center - 1), vmax=max(0.0, center + 1))
    for ax, strokes in zip(axes, (2, 4), strict=True):
        delta = np.empty((len(ks), len(lam)))
        for i, k in enumerate(ks):
            delta[i] = speed_fluctuation(
                crank_ratio=lam,
                inclination=unit["inclination"],
                u1=unit["u1"],
                u2=unit["u2"],
                phases=crank_phases(int(k), strokes, "single"),
            )
            records += [
                {"strokes": strokes, "k": int(k), "crank_ratio": ratio, "delta_g": d}
                for ratio, d in zip(lam, delta[i], strict=True)
            ]
        exponent = np.log10(np.maximum(delta, 1e-16))
        image = ax.pcolormesh(lam, ks, exponent, norm=norm, shading="nearest", cmap="RdBu_r")
        ax.set_title(f"{strokes}-stroke, single-acting")
        ax.set_xlabel("crank ratio λ")
        ax.set_yticks(ks)
    axes[0].set_ylabel("cranks k")
    bar = fig.colorbar(image, ax=axes, shrink=0.9, pad=0.1)  # room for the threshold's label
    bar.set_label("log₁₀ δ_g  (δ_g = max U_w* − min U_w*)")
    # The threshold, where the colours turn from blue to red: a line across the colour bar
    # and its value beside it, pointing at it.
    bar.ax.axhline(center, color="black", lw=2)
    bar.ax.annotate(
        f"threshold\n{threshold_text(settings.threshold)}",
        (0.0, center),
        xycoords=("axes fraction", "data"),
        xytext=(-8, 0),
        textcoords="offset points",
        ha="right",
        va="center",
        fontsize=8,
        arrowprops=dict(arrowstyle="->", color="black"),
    )
    fig.suptitle(
        f"Gravity's share of the speed fluctuation δ_g, {machine.name}'s unit at {running_speed(machine):g} rpm: "
        f"red, gravity matters; blue, negligible (δ_g < {threshold_text(settings.threshold)})",
        fontsize=10,
    )
    return fig, pd.DataFrame(records)


def machines_figure(settings: ReportSettings) -> tuple[Figure, pd.DataFrame]:
    """δ_g of every preset machine over its speed range (δ_g ∝ 1/n²), from its engine (all its cylinders)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9.5, 4.0))
    records = []
    for i, machine in enumerate(settings.machines.values()):
        low, high = speed_range(machine)
        rpm = np.geomspace(low, high, 40)
        delta = np.array([float(machine.engine(r).speed_fluctuation()) for r in rpm])
        label = f"{machine.name} ({len(machine)} cyl.)"
        if np.all(delta == 0):
            # Gravity cancels exactly (horizontal opposed cylinders): no line at a made-up floor.
            ax.plot([], [], color=f"C{i}", label=f"{label}: δ_g = 0, cancels exactly")
        else:
            ax.loglog(rpm, np.where(delta > 0, delta, np.nan), color=f"C{i}", label=label)
        records += [
            {"machine": machine.name, "cylinders": len(machine), "rpm": r, "delta_g": d}
            for r, d in zip(rpm, delta, strict=True)
        ]
    ax.axhline(settings.threshold, color="black", ls="--", lw=1)
    ax.text(
        ax.get_xlim()[0] * 1.1,
        settings.threshold * 1.4,
        f"threshold {threshold_text(settings.threshold)}: below, gravity may be neglected",
        fontsize=8,
    )
    ax.set_xscale("log")
    ax.set_yscale("log")
    plain_log_axis(ax.xaxis)
    ax.set_xlabel("speed n [rpm]")
    ax.set_ylabel("δ_g")
    ax.set_title("Gravity's share of the coefficient of speed fluctuation over each machine's speed range")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    return fig, pd.DataFrame(records)


def layouts_figure(settings: ReportSettings) -> tuple[Figure, pd.DataFrame]:
    """δ_g and the leading gravity harmonic of every preset layout with the machine's first
    cylinder on every bank (its crank web and counterweight once per throw), at its speed."""
    plt = pyplot()
    from ..sweeps.driver import sweep

    machine = settings.machine
    rpm = running_speed(machine)
    cylinder = machine.cylinders[0].replace(pressure=None, pressure_crank_end=None)  # gravity alone, any cycle
    chosen = [
        name
        for name in LAYOUTS
        if not name.startswith("inline-")
        or name
        in ("inline-1-2t", "inline-2-2t", "inline-3-4t", "inline-4-4t", "inline-6-4t", "inline-8-4t", "inline-12-2t")
    ]
    engines = [
        Machine.from_layout(name, cylinder, shaft_inertia=machine.shaft_inertia, g=machine.g)
        .engine(rpm)
        .replace(name=name)
        for name in chosen
    ]
    # The sweep names each engine in its "engine" column: here, by the layout it is.
    table = sweep(engines, outputs=["energy_range", "leading_harmonic", "leading_amplitude"])
    table = table.rename(columns={"engine": "layout"})
    table.insert(1, "description", [LAYOUTS[name].note for name in chosen])
    fig, ax = plt.subplots(figsize=(9.5, 5.2))
    delta = table["energy_range"].to_numpy()
    # A layout whose gravity cancels exactly (horizontal boxers, the 180° V four-stroke) has
    # δ_g = 0, not a small number: it gets no bar and says so, at the axis's left edge.
    positive = delta[delta > 0]
    low = min(positive.min() if positive.size else settings.threshold, settings.threshold) / 30
    colours = ["C3" if d >= settings.threshold else "C0" for d in delta]
    ax.barh(table["layout"], np.where(delta > 0, delta - low, np.nan), left=low, color=colours)
    ax.set_xscale("log")
    ax.set_xlim(left=low)
    ax.axvline(settings.threshold, color="black", ls="--", lw=1)
    for y, (d, n) in enumerate(zip(delta, table["leading_harmonic"], strict=True)):
        label = f"n = {n}" if d > 0 else "δ_g = 0: gravity cancels exactly"
        ax.text(max(d, low) * 1.3, y, label, va="center", fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("δ_g (dashed: threshold; red above it)")
    ax.set_title(
        f"Layouts with {machine.name}'s cylinder (λ = {cylinder.crank_ratio:.3g}, {rpm:g} rpm): "
        "gravity's δ_g and leading harmonic n",
        fontsize=10,
    )
    fig.tight_layout()
    return fig, table
