"""`multicrank report`: the paper's analysis reproduced, corrected and extended.

Writes a directory with a self-contained ``index.html`` (figures embedded), the figures as
PNG and the tables as CSV:

- U_w*(φ) and Q_u*(φ) for k = 1 … k_max, two- and four-stroke, for the chosen engine;
- the harmonic spectra of Q_u* per k;
- the paper's Table 1, the derived Table 2 and the double-acting tables up to n_max, next
  to the paper's printed Table 1;
- the error of the paper's truncated λ-series against the exact Λ_n, as a function of λ;
- the gravity-significance map: δ_g over k and λ, and per preset machine over its speeds;
- the conventions and the paper's errata.
"""

from __future__ import annotations

import base64
import html
import io
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .._native import MechanismError
from .._optional import require
from ..gravity.evaluation import generalized_force, potential_energy
from ..gravity.extrema import speed_fluctuation
from ..gravity.harmonics import fourier_coefficients, harmonic_table, lambda_coefficients
from ..gravity.layouts import LAYOUTS
from ..gravity.mechanism import crank_phases
from ..machine.machine import Machine
from ..presets import DEFAULT_ENGINE_NAME, ENGINES

__all__ = ["DEFAULT_THRESHOLD", "PAPER_TABLE_1", "ReportSettings", "write_report"]

#: Table 1 as printed in the paper (two-stroke, single-acting): the k with non-zero W_n.
PAPER_TABLE_1 = {
    1: [1],
    2: [1, 2],
    4: [1, 2, 4],
    6: [1, 2, 3, 6],
    8: [1, 2, 4, 8],
    10: [1, 2, 5, 10],
    12: [1, 2, 3, 4, 6, 12],
}

#: δ_g below which gravity may be neglected in the speed fluctuation: a tenth of 1/300,
#: the tightest coefficient of speed fluctuation usually asked of machines (AC generators;
#: pumps and compressors allow 1/20–1/50, vehicle engines 1/100–1/200).
DEFAULT_THRESHOLD = 1.0 / 3000.0

ERRATA = [
    "λ is printed as l/r; it is r/l everywhere it is used.",
    "Eq. (3) prints l/λ; it is 1/λ (as in eq. 12).",
    "Eq. (5)/(6) swap the rod's shares: the printed U1 = M_t + (z_k/l)M_z and "
    "U2 = M_s − M_sp + ((1 − z_k)/l)M_z are wrong unless z_k = l/2. Correct: "
    "U1 = M_t + ((l − z_k)/l)M_z, U2 = M_s − M_sp + (z_k/l)M_z.",
    "ω_sr = π·n/30.",
    "Λ_2's first term is 0.5·λ (the λ is missing); its λ⁹ coefficient is 0.022430 (735/32768), not 0.022432.",
    "Eq. (20) and (22): the signs hold only with N and W evaluated at γ = 0 and γ = π/2.",
    "Eq. (16)–(18) cover single-acting machines only; “m” is a cap νp ≤ 12.",
    "γ, ξ and δ are one angle; φ and ψ one variable; “k-tego” in eq. (11) means j-th.",
]

CONVENTIONS = [
    "Angles in radians inside the library (degrees where a person types them, and in the figures).",
    "φ is the crank angle of crank 0 from outer dead centre; crank j is at ψ_j = φ + α_j.",
    "γ is the cylinder axis' inclination to the horizontal: +90° upright, −90° hanging, 0° and 180° lying.",
    "Energies are dimensionless, U* = U/(I_w ω²); each crank unit is measured from its own ψ = 0 position.",
    "Q_u* = +dU_w*/dφ (the term of Lagrange's equation); the gravity torque on the shaft is −Q_u*·I_w ω².",
    "δ_g = max U_w* − min U_w* over a revolution: to first order the gravity share of the "
    "coefficient of speed fluctuation (ω_max − ω_min)/ω_mean.",
]


@dataclass
class ReportSettings:
    """What the report is about: ``engine``, the machine (it needs a running speed, ``rpm``),
    and ``engines``, the machines of the speed-range figure (by default every preset)."""

    engine: Machine = field(default_factory=lambda: ENGINES[DEFAULT_ENGINE_NAME])
    k_max: int = 12
    n_max: int = 24
    points: int = 721
    threshold: float = DEFAULT_THRESHOLD
    lambdas: int = 60
    engines: dict = field(default_factory=lambda: dict(ENGINES))
    #: The δ to size the flywheel for (default: the preset's class limit, or the machine's own
    #: δ without gravity).
    delta: float | None = None


# ----------------------------------------------------------------------------- the machine
def _speed(machine: Machine) -> float:
    """The machine's running speed [rpm], which the report's gravity analysis needs."""
    if machine.rpm is None:
        raise MechanismError(
            f"machine {machine.name!r} has no running speed: the report judges gravity at the machine's rpm; "
            "give rpm (in a machine file: rpm = ...)"
        )
    return machine.rpm


def _speeds(machine: Machine) -> tuple[float, float]:
    """The machine's speed range [rpm]; its running speed ±50 % where it gives none."""
    if machine.rpm_range is not None:
        return machine.rpm_range
    rpm = _speed(machine)
    return 0.5 * rpm, 1.5 * rpm


def _unit_machine(machine: Machine) -> Machine:
    """The machine's first cylinder alone, with its throw's crank web and counterweight: the
    crank unit that the paper's sections (identical units on k in-line cranks) are about."""
    return Machine(
        [machine.cylinders[0]],
        shaft_inertia=machine.shaft_inertia,
        strokes=machine.strokes,
        g=machine.g,
        rpm=_speed(machine),
        name=machine.name,
    )


def _is_inline(machine: Machine) -> bool:
    """Whether the machine is the paper's: identical units differing only in phase."""
    try:
        machine.design(_speed(machine))
    except MechanismError:
        return False
    return True


# ----------------------------------------------------------------------------- figures
def _pyplot():
    matplotlib = require("matplotlib", "report")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"figure.dpi": 110, "axes.grid": True, "grid.alpha": 0.3, "font.size": 9})
    return plt


def _grid_shape(count: int) -> tuple[int, int]:
    cols = min(4, count)
    return math.ceil(count / cols), cols


def _small_multiples(plt, count: int, xlabel: str, ylabel: str, **options):
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


def _unit(engine: Machine, cranks: int, strokes: int) -> dict:
    """The machine's crank unit (its first cylinder) on a regular single-acting k-crank shaft of
    the given cycle (the machines of the paper's eq. 16 and Tables 1–2)."""
    return {**_unit_machine(engine).design(), "phases": crank_phases(cranks, strokes, "single")}


def curves_figure(settings: ReportSettings, strokes: int, quantity: str):
    plt = _pyplot()
    from matplotlib.ticker import ScalarFormatter

    phi_deg = np.linspace(0.0, 360.0, settings.points)
    phi = np.radians(phi_deg)
    # U_w* is drawn relative to its value at φ = 0: the offset grows with k and would hide
    # the variation, which is what matters. The CSV holds the values themselves.
    label = "U_w*(φ) − U_w*(0)" if quantity == "energy" else "Q_u*(φ)"
    fig, panels = _small_multiples(plt, settings.k_max, "φ [deg]", label, sharex=True)
    table = {"phi_deg": phi_deg}
    for k, ax in enumerate(panels, start=1):
        design = _unit(settings.engine, k, strokes)
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
    gamma = math.degrees(settings.engine.cylinders[0].inclination)
    fig.suptitle(
        f"{label} of {settings.engine.name}'s crank unit on k cranks, {strokes}-stroke, "
        f"single-acting, γ = {gamma:g}° (dimensionless, ÷ I_w ω²)",
        fontsize=10,
    )
    fig.tight_layout()
    return fig, pd.DataFrame(table)


def spectra_figure(settings: ReportSettings, strokes: int):
    plt = _pyplot()
    fig, panels = _small_multiples(plt, settings.k_max, "harmonic n", "|a_n + i b_n|", sharex=True, sharey=True)
    n = np.arange(settings.n_max + 1)
    records = []
    for k, ax in enumerate(panels, start=1):
        a, b = fourier_coefficients(**_unit(settings.engine, k, strokes), n_max=settings.n_max)
        amplitude = np.hypot(a, b)
        records += [{"k": k, "n": int(i), "amplitude": amplitude[i]} for i in n if amplitude[i] > 0]
        shown = amplitude > 0
        ax.bar(n[shown], amplitude[shown], color="C2", width=0.8)
        ax.set_yscale("log")
        ax.set_xticks(range(0, settings.n_max + 1, 6))
    fig.suptitle(
        f"Harmonic amplitudes of Q_u* (exact Λ_n), {settings.engine.name}'s unit on k cranks, "
        f"{strokes}-stroke, single-acting",
        fontsize=10,
    )
    fig.tight_layout()
    return fig, pd.DataFrame(records)


def truncation_figure(settings: ReportSettings):
    """The paper's λ¹¹ series against the exact Λ_n, and its effect on f(ψ)."""
    plt = _pyplot()
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


def significance_map(settings: ReportSettings):
    """δ_g over k and λ for the engine's unit (two- and four-stroke), at its speed."""
    plt = _pyplot()
    from matplotlib.colors import TwoSlopeNorm

    engine = settings.engine
    lam = np.linspace(0.1, 0.5, 41)
    ks = np.arange(1, settings.k_max + 1)
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.9), sharey=True)
    records = []
    unit = _unit_machine(engine).design()
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
    bar = fig.colorbar(image, ax=axes, shrink=0.9)
    bar.set_label("log₁₀ δ_g  (δ_g = max U_w* − min U_w*)")
    fig.suptitle(
        f"Gravity's share of the speed fluctuation δ_g, {engine.name}'s unit at {_speed(engine):g} rpm: "
        f"red, gravity matters; blue, negligible (δ_g < {settings.threshold:.2g})",
        fontsize=10,
    )
    return fig, pd.DataFrame(records)


def engines_figure(settings: ReportSettings):
    """δ_g of every preset machine over its speed range (δ_g ∝ 1/n²), from its whole engine."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9.5, 4.0))
    records = []
    for i, engine in enumerate(settings.engines.values()):
        low, high = _speeds(engine)
        rpm = np.geomspace(low, high, 40)
        delta = np.array([float(engine.engine(r).speed_fluctuation()) for r in rpm])
        ax.loglog(rpm, np.maximum(delta, 1e-18), color=f"C{i}", label=f"{engine.name} ({len(engine)} cyl.)")
        records += [
            {"engine": engine.name, "cylinders": len(engine), "rpm": r, "delta_g": d}
            for r, d in zip(rpm, delta, strict=True)
        ]
    ax.axhline(settings.threshold, color="black", ls="--", lw=1)
    ax.text(
        ax.get_xlim()[0] * 1.1,
        settings.threshold * 1.4,
        f"threshold {settings.threshold:.2g}: below, gravity may be neglected",
        fontsize=8,
    )
    ax.set_xlabel("speed n [rpm]")
    ax.set_ylabel("δ_g")
    ax.set_title("Gravity's share of the coefficient of speed fluctuation over each engine's speed range")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    return fig, pd.DataFrame(records)


def layouts_figure(settings: ReportSettings):
    """δ_g and the leading gravity harmonic of every preset layout with the machine's first
    cylinder on every bank (its crank web and counterweight once per throw), at its speed."""
    plt = _pyplot()
    from ..sweeps.driver import sweep

    engine = settings.engine
    rpm = _speed(engine)
    cylinder = engine.cylinders[0].replace(pressure=None, pressure_crank_end=None)  # gravity alone, any cycle
    chosen = [
        name
        for name in LAYOUTS
        if not name.startswith("inline-")
        or name
        in ("inline-1-2t", "inline-2-2t", "inline-3-4t", "inline-4-4t", "inline-6-4t", "inline-8-4t", "inline-12-2t")
    ]
    engines = [
        Machine.from_layout(name, cylinder, shaft_inertia=engine.shaft_inertia, g=engine.g)
        .engine(rpm)
        .replace(name=name)
        for name in chosen
    ]
    table = sweep(engines, outputs=["energy_range", "leading_harmonic", "leading_amplitude"])
    table.insert(1, "description", [LAYOUTS[name].note for name in chosen])
    fig, ax = plt.subplots(figsize=(9.5, 5.2))
    delta = table["energy_range"].to_numpy()
    # A layout whose gravity cancels exactly (horizontal boxers, the 180° V four-stroke) has
    # δ_g = 0, not a small number: it gets no bar and says so, at the axis's left edge.
    positive = delta[delta > 0]
    low = min(positive.min() if positive.size else settings.threshold, settings.threshold) / 30
    colours = ["C3" if d >= settings.threshold else "C0" for d in delta]
    ax.barh(table["engine"], np.where(delta > 0, delta - low, np.nan), left=low, color=colours)
    ax.set_xscale("log")
    ax.set_xlim(left=low)
    ax.axvline(settings.threshold, color="black", ls="--", lw=1)
    for y, (d, n) in enumerate(zip(delta, table["leading_harmonic"], strict=True)):
        label = f"n = {n}" if d > 0 else "δ_g = 0: gravity cancels exactly"
        ax.text(max(d, low) * 1.3, y, label, va="center", fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("δ_g (dashed: threshold; red above it)")
    ax.set_title(
        f"Layouts with {engine.name}'s cylinder (λ = {cylinder.crank_ratio:.3g}, {rpm:g} rpm): "
        "gravity's δ_g and leading harmonic n",
        fontsize=10,
    )
    fig.tight_layout()
    return fig, table


# ----------------------------------------------------------------------------- tables
def surviving_tables(settings: ReportSettings) -> dict[str, pd.DataFrame]:
    kinds = {
        "table1_two_stroke_single": (2, "single"),
        "table2_four_stroke_single": (4, "single"),
        "two_stroke_double": (2, "double"),
        "four_stroke_double": (4, "double"),
    }
    return {name: harmonic_table(s, a, k_max=settings.k_max, n_max=settings.n_max) for name, (s, a) in kinds.items()}


def paper_table_frame(k_max: int) -> pd.DataFrame:
    rows = sorted(PAPER_TABLE_1)
    frame = pd.DataFrame(False, index=pd.Index(rows, name="n"), columns=pd.Index(range(1, k_max + 1), name="k"))
    for n, ks in PAPER_TABLE_1.items():
        for k in ks:
            if k <= k_max:
                frame.loc[n, k] = True
    return frame


# ----------------------------------------------------------------------------- html
# ----------------------------------------------------------------------------- motion
@dataclass(frozen=True)
class MotionResults:
    """The machine's steady running, for the report's first section."""

    rpm: float
    target: float
    target_source: str
    state: Any  # SteadyState with gravity
    without: Any  # SteadyState with g = 0
    delta_g: float
    flywheel: Any  # FlywheelInertia for ``target``
    speeds: pd.DataFrame
    orders: pd.DataFrame


def motion_results(settings: ReportSettings, speeds: int = 9) -> MotionResults:
    """Steady state at the machine's speed with and without gravity, over its speed range,
    the flywheel for the class's δ (or ``settings.delta``) and the torque orders."""
    from ..motion.orders import torque_orders
    from ..motion.steady import StallError, flywheel_inertia, steady_state
    from ..presets import MACHINE_CLASSES, SPEED_FLUCTUATION

    machine = settings.engine
    rpm = _speed(machine)
    state = steady_state(machine, rpm=rpm)
    without = steady_state(machine, rpm=rpm, gravity=False)
    if settings.delta is not None:
        target, source = settings.delta, "asked for (--delta)"
    elif machine.name in MACHINE_CLASSES:
        kind = MACHINE_CLASSES[machine.name]
        target, source = SPEED_FLUCTUATION[kind][1], f"the {kind} class's limit"
    else:
        target, source = without.delta, "the machine's own δ without gravity (no class known)"
    flywheel = flywheel_inertia(machine, delta=target, rpm=rpm)
    low, high = _speeds(machine)
    rows: list[dict[str, Any]] = []
    for n in np.geomspace(low, high, speeds):
        try:
            s = steady_state(machine, rpm=float(n))
            rows.append(
                dict(
                    rpm=float(n),
                    delta=s.delta,
                    delta_without_gravity=s.delta_without_gravity,
                    delta_gravity_only=s.delta_gravity_only,
                    delta_g=float(machine.engine(float(n)).speed_fluctuation()),
                )
            )
        except StallError as error:
            rows.append(dict(rpm=float(n), stalled_below_rpm=error.min_rpm))
    return MotionResults(
        rpm=rpm,
        target=target,
        target_source=source,
        state=state,
        without=without,
        delta_g=float(machine.engine(rpm).speed_fluctuation()),
        flywheel=flywheel,
        speeds=pd.DataFrame(rows),
        orders=torque_orders(machine, rpm),
    )


def speed_figure(results: MotionResults):
    """ω(φ) with and without gravity at the machine's speed, in rpm over φ in degrees."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for state, label, style in ((results.state, "with gravity", "-"), (results.without, "without gravity", "--")):
        ax.plot(np.degrees(state.phi), state.omega * 30 / math.pi, style, label=f"{label} (δ = {state.delta:.4g})")
    ax.axhline(results.rpm, color="0.6", lw=0.8)
    ax.set_xlabel("crank angle φ [deg]")
    ax.set_ylabel("speed [rpm]")
    ax.set_xlim(0, np.degrees(results.state.cycle))
    ax.legend(loc="best", fontsize=8)
    ax.set_title(f"steady running at {results.rpm:g} rpm (mean)")
    table = pd.DataFrame(
        {
            "phi_deg": np.degrees(results.state.phi),
            "rpm_with_gravity": results.state.omega * 30 / math.pi,
            "rpm_without_gravity": results.without.omega * 30 / math.pi,
        }
    )
    return fig, table


def torque_figure(results: MotionResults):
    """The torque components over the cycle at the machine's speed [N·m]."""
    plt = _pyplot()
    state = results.state
    parts = {
        "gas": state.torque_gas,
        "gravity −dU/dφ": state.torque_gravity,
        "inertia −½J′ω²": state.torque_inertia,
        "−M_load (balance)": -state.torque_load,
    }
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for name, values in parts.items():
        ax.plot(np.degrees(state.phi), values, label=name, lw=1.2)
    ax.axhline(0, color="0.6", lw=0.8)
    ax.set_xlabel("crank angle φ [deg]")
    ax.set_ylabel("torque on the shaft [N·m]")
    ax.set_xlim(0, np.degrees(state.cycle))
    ax.legend(loc="best", fontsize=8, ncol=2)
    names = ("gas", "gravity", "inertia", "minus_load")
    table = pd.DataFrame({"phi_deg": np.degrees(state.phi), **dict(zip(names, parts.values(), strict=True))})
    return fig, table


def speed_range_figure(results: MotionResults):
    """δ over the speed range: with and without gravity, gravity alone and the paper's δ_g."""
    plt = _pyplot()
    frame = results.speeds.dropna(subset=["delta"]) if "delta" in results.speeds else results.speeds.iloc[:0]
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for column, label, style in (
        ("delta", "δ with gravity", "-o"),
        ("delta_without_gravity", "δ without gravity", "--s"),
        ("delta_gravity_only", "δ without gas and load (gravity and J(φ) alone)", ":^"),
        ("delta_g", "δ_g = max U* − min U* (first order)", "-."),
    ):
        if column in frame:
            ax.plot(frame["rpm"], frame[column], style, label=label, ms=4)
    ax.axhline(results.target, color="0.5", lw=0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("mean speed [rpm]")
    ax.set_ylabel("coefficient of speed fluctuation δ")
    ax.legend(loc="best", fontsize=8)
    return fig, results.speeds


def orders_figure(results: MotionResults):
    """Per-order amplitudes of the gas, inertia and gravity torques [N·m]."""
    plt = _pyplot()
    orders = results.orders
    fig, ax = plt.subplots(figsize=(8, 3.4))
    width = 0.25 if orders.index.size < 2 else 0.25 * float(np.min(np.diff(orders.index.to_numpy())))
    for i, name in enumerate(("gas", "inertia", "gravity")):
        ax.bar(orders.index.to_numpy() + (i - 1) * width, orders[f"{name}_amplitude"], width, label=name)
    ax.set_yscale("symlog", linthresh=1e-3 * max(float(orders["total_amplitude"].max()), 1e-12))
    ax.set_xlabel("order (harmonics per revolution)")
    ax.set_ylabel("amplitude [N·m]")
    ax.legend(fontsize=8)
    return fig, orders.reset_index()


def motion_html(results: MotionResults, machine: Machine, figures: dict[str, str]) -> str:
    """The report's first section: what gravity does to this machine's speed fluctuation."""
    state, without, flywheel = results.state, results.without, results.flywheel
    change = 100 * (state.delta / without.delta - 1)
    extra = 100 * (flywheel.shaft_inertia / flywheel.shaft_inertia_without_gravity - 1)
    rows = [
        ("mean speed", f"{results.rpm:g} rpm (ω<sub>m</sub> = {state.omega_mean:.6g} rad/s)"),
        ("δ with gravity", f"{state.delta:.5g} (1/{1 / state.delta:.4g})"),
        ("δ without gravity (g = 0)", f"{without.delta:.5g} (1/{1 / without.delta:.4g})"),
        ("gravity changes δ by", f"<b>{change:+.3g} %</b>"),
        ("δ without gas and load (gravity and J(φ) alone, exact)", f"{state.delta_gravity_only:.4g}"),
        ("δ<sub>g</sub> = max U* − min U* (the paper's first-order measure)", f"{results.delta_g:.4g}"),
        ("δ about the midrange (textbook convention)", f"{state.delta_midrange:.5g}"),
        ("speed swing", f"{state.omega_min * 30 / math.pi:.6g} … {state.omega_max * 30 / math.pi:.6g} rpm"),
        ("load torque (balance)", f"{state.load_torque:.6g} N·m ({state.load_torque * state.omega_mean / 1e3:.4g} kW)"),
        ("shaft inertia I<sub>w</sub> (as built)", f"{machine.shaft_inertia:.6g} kg·m²"),
    ]
    body = "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in rows)
    fly = [
        ("target δ", f"{results.target:.4g} (1/{1 / results.target:.4g}): {html.escape(results.target_source)}"),
        ("I<sub>w</sub> with gravity (exact)", f"{flywheel.shaft_inertia:.6g} kg·m²"),
        ("I<sub>w</sub> without gravity (exact)", f"{flywheel.shaft_inertia_without_gravity:.6g} kg·m²"),
        ("gravity asks for", f"<b>{extra:+.3g} %</b> flywheel inertia"),
        (
            "textbook ΔE/(δω²) − mean(J − I<sub>w</sub>)",
            f"{flywheel.textbook:.6g} kg·m² ({100 * flywheel.textbook_error:+.2g} % off the exact)",
        ),
    ]
    fly_body = "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in fly)
    top = results.orders.sort_values("total_amplitude", ascending=False).head(8)
    order_rows = "".join(
        f"<tr><td>{order:g}</td><td>{r.gas_amplitude:.4g}</td><td>{r.inertia_amplitude:.4g}</td>"
        f"<td>{r.gravity_amplitude:.4g}</td><td>{r.total_amplitude:.4g}</td></tr>"
        for order, r in zip(top.index, top.itertuples(), strict=True)
    )
    return f"""
<h2>What gravity does to this machine's running</h2>
<p>The exact periodic steady state of J(φ)φ̈ + ½J′(φ)φ̇² = M<sub>gas</sub> − dU/dφ − M<sub>load</sub>, with
the machine's variable reduced inertia J(φ), its gas pressure and the constant load that balances the cycle's
mean gas torque, at the same mean speed with and without gravity. δ = (ω<sub>max</sub> − ω<sub>min</sub>)/ω<sub>m</sub>
with ω<sub>m</sub> the time mean.</p>
<table>{body}</table>
<h3>The flywheel</h3>
<table>{fly_body}</table>
<img src="{figures["motion_speed"]}" alt="speed over the cycle with and without gravity">
<img src="{figures["motion_torques"]}" alt="torque components over the cycle">
<h3>Over the speed range</h3>
<p>Gravity's torque does not depend on the speed, the gas and inertia torques' effect on δ falls or grows with
it: gravity matters most at low speed. The grey line is the target δ.</p>
<img src="{figures["motion_speed_range"]}" alt="δ over the speed range">
<h3>Torque orders at {results.rpm:g} rpm</h3>
<p>Fourier amplitudes per order (harmonics per revolution; half orders in a four-stroke cycle) in N·m, for
torsional-vibration tools: gravity and inertia exact, gas from the cycle quadrature. The eight largest:</p>
<table><tr><th>order</th><th>gas</th><th>inertia</th><th>gravity</th><th>total</th></tr>{order_rows}</table>
<img src="{figures["motion_orders"]}" alt="torque orders">
<p class="note">Data: motion_speed.csv, motion_torques.csv, motion_speed_range.csv, motion_orders.csv</p>
"""


def _png(fig, path: Path) -> str:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", bbox_inches="tight")
    fig.clf()
    import matplotlib.pyplot as plt

    plt.close(fig)
    data = buffer.getvalue()
    path.write_bytes(data)
    return "data:image/png;base64," + base64.b64encode(data).decode()


def _bool_table(frame: pd.DataFrame, caption: str, highlight: pd.DataFrame | None = None) -> str:
    head = "".join(f"<th>{k}</th>" for k in frame.columns)
    body = []
    for n, row in frame.iterrows():
        cells = []
        for k, value in row.items():
            mark = "●" if value else ""
            extra = ""
            if (
                highlight is not None
                and n in highlight.index
                and k in highlight.columns
                and highlight.at[n, k] != value
            ):
                extra = ' class="diff"'
            cells.append(f"<td{extra}>{mark}</td>")
        body.append(f"<tr><th>W<sub>{n}</sub></th>{''.join(cells)}</tr>")
    return (
        f'<table class="bool"><caption>{html.escape(caption)}</caption>'
        f"<tr><th>n \\ k</th>{head}</tr>{''.join(body)}</table>"
    )


STYLE = """
body { font-family: system-ui, sans-serif; max-width: 1100px; margin: 2em auto; color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; } h2 { border-bottom: 1px solid #ccc; padding-bottom: .2em; margin-top: 2em; }
img { max-width: 100%; border: 1px solid #eee; }
table { border-collapse: collapse; margin: 1em 0; font-size: .9em; }
td, th { border: 1px solid #ccc; padding: .2em .5em; text-align: center; }
table.bool td { width: 1.6em; color: #1a5fb4; }
td.diff { background: #fdd; }
caption { caption-side: top; font-weight: bold; text-align: left; padding-bottom: .3em; }
.note { color: #555; font-size: .9em; }
.tables { display: flex; flex-wrap: wrap; gap: 2em; }
"""


def write_report(out: str | Path, settings: ReportSettings | None = None, progress: bool = True) -> Path:
    """Write the report into ``out`` (created if needed); returns the path of index.html."""
    from tqdm.auto import tqdm

    settings = settings or ReportSettings()
    # The user's mistakes first, then the missing extra, both before anything is written.
    rpm = _speed(settings.engine)
    for machine in settings.engines.values():
        _speeds(machine)
    require("matplotlib", "report")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    engine = settings.engine
    sections: list[str] = []
    steps = [
        "motion",
        "curves",
        "spectra",
        "tables",
        "truncation",
        "significance",
        "engines",
        "layouts",
    ]
    bar = tqdm(steps, desc="report", unit="part", disable=not progress)
    figures: dict[str, str] = {}

    def save(name: str, fig, table: pd.DataFrame | None):
        figures[name] = _png(fig, out / f"{name}.png")
        if table is not None:
            table.to_csv(out / f"{name}.csv", index=False)

    for step in bar:
        bar.set_postfix_str(step)
        if step == "motion":
            motion = motion_results(settings)
            save("motion_speed", *speed_figure(motion))
            save("motion_torques", *torque_figure(motion))
            save("motion_speed_range", *speed_range_figure(motion))
            save("motion_orders", *orders_figure(motion))
        elif step == "curves":
            for strokes in (2, 4):
                for quantity in ("energy", "force"):
                    save(f"{quantity}_{strokes}stroke", *curves_figure(settings, strokes, quantity))
        elif step == "spectra":
            for strokes in (2, 4):
                save(f"spectra_{strokes}stroke", *spectra_figure(settings, strokes))
        elif step == "tables":
            tables = surviving_tables(settings)
            for name, frame in tables.items():
                frame.astype(int).to_csv(out / f"{name}.csv")
            paper = paper_table_frame(settings.k_max)
            paper.astype(int).to_csv(out / "paper_table1_printed.csv")
        elif step == "truncation":
            save("paper_truncation_error", *truncation_figure(settings))
        elif step == "significance":
            save("gravity_significance_k_lambda", *significance_map(settings))
        elif step == "engines":
            save("gravity_significance_engines", *engines_figure(settings))
        elif step == "layouts":
            figure, layouts = layouts_figure(settings)
            save("layouts", figure, layouts)

    unit = _unit_machine(engine).design()
    delta = float(engine.engine(rpm).speed_fluctuation())
    verdict = "may be neglected" if delta < settings.threshold else "may NOT be neglected"
    first = engine.cylinders[0]
    inline = _is_inline(engine)
    acting = "double" if any(c.pressure_crank_end is not None for c in engine.cylinders) else "single"
    gammas = ", ".join(f"{g:g}°" for g in sorted({round(math.degrees(c.inclination), 9) for c in engine.cylinders}))
    engine_rows = "".join(
        f"<tr><th>{html.escape(k)}</th><td>{html.escape(str(v))}</td></tr>"
        for k, v in [
            ("cylinders", len(engine)),
            ("cycle", f"{engine.strokes}-stroke, {acting}-acting"),
            ("inclination γ", gammas),
            ("crank ratio λ = r/l", f"{first.crank_ratio:.4g}"),
            (
                "crank radius r / rod length l / rod CG z_k",
                f"{first.crank_radius:g} m / {first.rod_length:g} m / {first.rod_cg:g} m",
            ),
            ("bore", f"{first.bore:g} m"),
            (
                "piston / rod / crank / counterweight mass (first cylinder)",
                f"{first.piston_mass:g} / {first.rod_mass:g} / {first.crank_mass:g} / {first.counterweight_mass:g} kg",
            ),
            ("shaft inertia I_w", f"{engine.shaft_inertia:g} kg·m²"),
            ("speed", f"{rpm:g} rpm"),
            ("U1, U2 (first cylinder)", f"{unit['u1']:.6g}, {unit['u2']:.6g}"),
            ("δ_g at this speed (the whole machine)", f"{delta:.4g}"),
        ]
    )
    unit_note = (
        ""
        if inline
        else f"""<p class="note">{html.escape(engine.name)} is not a machine of identical cylinders on one bank
(the paper's machine): δ<sub>g</sub> above is the whole machine's, from its engine of {len(engine)} units; the
sections on k cranks below put its first cylinder, with its throw's crank web and counterweight, on k in-line
cranks.</p>"""
    )
    derived_12 = tables["table1_two_stroke_single"].loc[[n for n in paper.index if n <= settings.n_max]]
    matches = bool((derived_12 == paper.loc[derived_12.index]).all().all())
    sections.append(motion_html(motion, engine, figures))
    sections.append(f"""
<h2>The engine</h2>
<p>{html.escape(engine.note)}</p>
<table>{engine_rows}</table>
{unit_note}
<p><b>Verdict:</b> with δ<sub>g</sub> = {delta:.3g} against the threshold {settings.threshold:.2g},
gravity <b>{verdict}</b> in this machine's speed fluctuation at {rpm:g} rpm.
The threshold is a tenth of 1/300, the tightest coefficient of speed fluctuation usually asked of
machines (AC generators); pumps and compressors allow 1/20–1/50 and vehicle engines 1/100–1/200.</p>
""")
    sections.append(f"""
<h2>Gravity significance — when may gravity be neglected?</h2>
<p>δ<sub>g</sub> = max U<sub>w</sub>* − min U<sub>w</sub>* over a revolution, from the exact extrema (roots of
Q<sub>u</sub>*), is to first order gravity's share of the coefficient of speed fluctuation. Gravity may be
neglected where δ<sub>g</sub> &lt; {settings.threshold:.2g}. Below: the engine's crank unit on k cranks over λ
(left two-stroke, right four-stroke), and every preset machine over its speed range (δ<sub>g</sub> ∝ 1/n²).
Balanced crank sets (where only harmonics of order ≥ k survive) make gravity negligible by many orders of magnitude.</p>
<img src="{figures["gravity_significance_k_lambda"]}" alt="δ_g over k and λ">
<img src="{figures["gravity_significance_engines"]}" alt="δ_g per engine over its speed range">
<p class="note">Data: gravity_significance_k_lambda.csv, gravity_significance_engines.csv</p>
""")
    layout_rows = "".join(
        f"<tr><td>{html.escape(r.engine)}</td><td style='text-align:left'>{html.escape(r.description)}</td>"
        f"<td>{r.cylinders}</td><td>{r.energy_range:.3g}</td>"
        + (
            f"<td>{r.leading_harmonic}</td><td>{r.leading_amplitude:.3g}</td></tr>"
            if r.leading_amplitude > 0
            else "<td>none</td><td>0 (cancels exactly)</td></tr>"
        )
        for r in layouts.itertuples()
    )
    sections.append(f"""
<h2>Layouts: V, boxer, W, odd-fire</h2>
<p>The same cylinder ({html.escape(engine.name)}'s first, at {rpm:g} rpm) on every bank of every preset layout,
its crank web and counterweight once per throw (<code>Machine.from_layout</code>).
Cylinders sharing a crank pin have phases α = β − γ (pin angle β, bank γ); boxers have opposed cylinders on
throws 180° apart, unlike the 180° V whose opposed cylinders share a pin. Horizontal cylinders (boxers) feel only
their rotating parts. With unequal cylinders or phase errors cancelled harmonics return; see
<code>Engine.harmonic_sensitivity</code>.</p>
<img src="{figures["layouts"]}" alt="δ_g per layout">
<table><tr><th>layout</th><th>description</th><th>cylinders</th><th>δ<sub>g</sub></th><th>leading n</th>
<th>its amplitude</th></tr>
{layout_rows}</table>
<p class="note">Data: layouts.csv</p>
""")
    for strokes in (2, 4):
        sections.append(f"""
<h2>U<sub>w</sub>*(φ) and Q<sub>u</sub>*(φ), {strokes}-stroke, k = 1 … {settings.k_max}</h2>
<img src="{figures[f"energy_{strokes}stroke"]}" alt="U_w*, {strokes}-stroke">
<img src="{figures[f"force_{strokes}stroke"]}" alt="Q_u*, {strokes}-stroke">
<p class="note">Data: energy_{strokes}stroke.csv, force_{strokes}stroke.csv
(columns φ [deg], k1 … k{settings.k_max})</p>
""")
    sections.append(f"""
<h2>Harmonic spectra of Q<sub>u</sub>*</h2>
<p>Amplitudes √(a<sub>n</sub>² + b<sub>n</sub>²) of Q<sub>u</sub>* = Σ a<sub>n</sub> cos nφ + b<sub>n</sub> sin nφ
with the exact Λ<sub>n</sub>, up to n = {settings.n_max}: only n = 1 and the harmonics whose phase sum survives
appear.</p>
<img src="{figures["spectra_2stroke"]}" alt="spectra two-stroke">
<img src="{figures["spectra_4stroke"]}" alt="spectra four-stroke">
<p class="note">Data: spectra_2stroke.csv, spectra_4stroke.csv</p>
""")
    table_html = "".join(
        _bool_table(frame, caption)
        for frame, caption in [
            (tables["table1_two_stroke_single"], f"Table 1 (derived): two-stroke, single-acting, n ≤ {settings.n_max}"),
            (
                tables["table2_four_stroke_single"],
                "Table 2 (derived; not printed in the paper): four-stroke, single-acting",
            ),
            (tables["two_stroke_double"], "Two-stroke, double-acting"),
            (tables["four_stroke_double"], "Four-stroke, double-acting"),
        ]
    )
    verdict = (
        "agrees with the derived one in every cell" if matches else "DIFFERS from the derived one in the red cells"
    )
    printed = _bool_table(paper, "The paper's Table 1 as printed (n ≤ 12)", tables["table1_two_stroke_single"])
    sections.append(f"""
<h2>Which harmonics survive the sum over cranks (Tables 1 and 2)</h2>
<p>● marks a non-zero W<sub>n</sub> for a machine of k cranks (rows n = 1 and even n). Derived from the phase sums
S<sub>n</sub> = Σ<sub>j</sub> e<sup>inα<sub>j</sub></sup> in exact integer arithmetic, beyond the paper's cut at n = 12.
The paper's printed Table 1 {verdict}.</p>
<div class="tables">{printed}</div>
<div class="tables">{table_html}</div>
<p class="note">Data: table1_two_stroke_single.csv, table2_four_stroke_single.csv, two_stroke_double.csv,
four_stroke_double.csv, paper_table1_printed.csv (1 = survives)</p>
""")
    sections.append(f"""
<h2>The paper's truncated series against the exact form</h2>
<p>The paper expands Λ<sub>n</sub> in λ through λ¹¹ and keeps n ≤ 12. Left: the relative error of each Λ<sub>n</sub>;
at λ = 0.4 (dotted) its Λ<sub>12</sub> is tens of percent off. Right: the error of the truncated f(ψ).</p>
<img src="{figures["paper_truncation_error"]}" alt="paper truncation error">
<p class="note">Data: paper_truncation_error.csv</p>
""")
    sections.append(
        "<h2>Conventions</h2><ul>"
        + "".join(f"<li>{html.escape(c)}</li>" for c in CONVENTIONS)
        + "</ul>"
        + "<h2>Errata of the paper</h2><ol>"
        + "".join(f"<li>{html.escape(e)}</li>" for e in ERRATA)
        + "</ol>"
    )
    from .._native import __version__

    page = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>multicrank report — {html.escape(engine.name)}</title>
<style>{STYLE}</style></head><body>
<h1>Gravity in multi-crank mechanisms — report for <i>{html.escape(engine.name)}</i></h1>
<p>Generalised Lagrange forces due to potential energy after M. Stańczak, corrected and extended by
multicrank {html.escape(__version__)}: exact Λ<sub>n</sub>, every surviving harmonic, exact extrema.</p>
{"".join(sections)}
</body></html>
"""
    index = out / "index.html"
    index.write_text(page, encoding="utf-8")
    return index
