"""The report's gravity part: the paper's analysis reproduced, corrected and extended.

For the machine's crank unit (its first cylinder) on k = 1 … k_max in-line cranks:

- U_w*(φ) and Q_u*(φ), two- and four-stroke;
- the harmonic spectra of Q_u* per k;
- the paper's Table 1, the derived Table 2 and the double-acting tables up to n_max, next
  to the paper's printed Table 1;
- the error of the paper's truncated λ-series against the exact Λ_n, as a function of λ;
- the gravity-significance map: δ_g over k and λ, per preset machine over its speeds, and
  per preset layout;
- the conventions and the paper's errata;

as figures, tables and the HTML sections that follow the motion part.
"""

from __future__ import annotations

import html
import math
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from .._native import MechanismError
from .._text import counted
from ..gravity.evaluation import generalized_force, potential_energy
from ..gravity.extrema import speed_fluctuation
from ..gravity.harmonics import fourier_coefficients, harmonic_table, lambda_coefficients
from ..gravity.layouts import LAYOUTS
from ..gravity.mechanism import crank_phases
from ..machine.machine import Machine
from .plotting import plain_log_axis, pyplot
from .prose import significance_sentence
from .settings import ReportSettings, running_speed, speed_range

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "CONVENTIONS",
    "ERRATA",
    "PAPER_TABLE_1",
    "curves_figure",
    "gravity_html",
    "layouts_figure",
    "machines_figure",
    "paper_table_frame",
    "significance_map",
    "spectra_figure",
    "surviving_tables",
    "truncation_figure",
]

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
    bar = fig.colorbar(image, ax=axes, shrink=0.9)
    bar.set_label("log₁₀ δ_g  (δ_g = max U_w* − min U_w*)")
    fig.suptitle(
        f"Gravity's share of the speed fluctuation δ_g, {machine.name}'s unit at {running_speed(machine):g} rpm: "
        f"red, gravity matters; blue, negligible (δ_g < {settings.threshold:.2g})",
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
        f"threshold {settings.threshold:.2g}: below, gravity may be neglected",
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
def _significance_text(settings: ReportSettings) -> str:
    """The significance map's row at the machine's own λ, in words: for which k gravity is
    above the threshold (:func:`~multicrank.report.prose.significance_sentence`)."""
    unit = _unit_machine(settings.machine).design()
    ks = list(range(1, settings.k_max + 1))
    deltas = {
        strokes: [
            float(
                speed_fluctuation(
                    crank_ratio=unit["crank_ratio"],
                    inclination=unit["inclination"],
                    u1=unit["u1"],
                    u2=unit["u2"],
                    phases=crank_phases(k, strokes, "single"),
                )
            )
            for k in ks
        ]
        for strokes in (2, 4)
    }
    return significance_sentence(unit["crank_ratio"], deltas, settings.threshold, ks)


def _truncation_text(crank_ratio: float) -> str:
    """How far the paper's Λ_12 and Λ_2 are off at λ = 0.4 (dotted) and at the machine's λ."""
    parts = []
    for lam, where in ((0.4, "at λ = 0.4 (dotted)"), (crank_ratio, f"at this machine's λ = {crank_ratio:.3g}")):
        exact = lambda_coefficients(lam, 12)
        paper = lambda_coefficients(lam, 12, method="paper")
        error = [abs(float(paper[n] / exact[n]) - 1) for n in (2, 12)]
        parts.append(
            f"{where} its Λ<sub>12</sub> is {100 * error[1]:.2g} % off, its Λ<sub>2</sub> {100 * error[0]:.1e} %"
        )
    return "; ".join(parts) + "."


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


def gravity_html(
    settings: ReportSettings,
    figures: dict[str, str],
    tables: dict[str, pd.DataFrame],
    paper: pd.DataFrame,
    layouts: pd.DataFrame,
) -> str:
    """The report's gravity sections, after the motion part: the machine and the verdict,
    gravity significance, layouts, the curves, spectra and tables on k cranks, the paper's
    truncation error, the conventions and the errata. ``figures`` holds the embedded figures
    by name, ``tables`` the :func:`surviving_tables`, ``paper`` the :func:`paper_table_frame`
    and ``layouts`` the table of :func:`layouts_figure`."""
    machine = settings.machine
    rpm = running_speed(machine)
    sections: list[str] = []
    unit = _unit_machine(machine).design()
    delta = float(machine.engine(rpm).speed_fluctuation())
    verdict = "may be neglected" if delta < settings.threshold else "may NOT be neglected"
    first = machine.cylinders[0]
    inline = _is_inline(machine)
    acting = "double" if any(c.pressure_crank_end is not None for c in machine.cylinders) else "single"
    gammas = ", ".join(f"{g:g}°" for g in sorted({round(math.degrees(c.inclination), 9) for c in machine.cylinders}))
    machine_rows = "".join(
        f"<tr><th>{html.escape(k)}</th><td>{html.escape(str(v))}</td></tr>"
        for k, v in [
            ("cylinders", len(machine)),
            ("cycle", f"{machine.strokes}-stroke, {acting}-acting"),
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
            ("shaft inertia I_w", f"{machine.shaft_inertia:g} kg·m²"),
            ("speed", f"{rpm:g} rpm"),
            ("U1, U2 (first cylinder)", f"{unit['u1']:.6g}, {unit['u2']:.6g}"),
            ("δ_g at this speed (the whole machine)", f"{delta:.4g}"),
        ]
    )
    unit_note = (
        ""
        if inline
        else f"""<p class="note">{html.escape(machine.name)} is not a machine of identical cylinders on one bank
(the paper's machine): δ<sub>g</sub> above is the whole machine's, from its engine of
{counted(len(machine), "unit")}; the sections on k cranks below put its first cylinder, with its throw's crank
web and counterweight, on k in-line cranks.</p>"""
    )
    derived_12 = tables["table1_two_stroke_single"].loc[[n for n in paper.index if n <= settings.n_max]]
    matches = bool((derived_12 == paper.loc[derived_12.index]).all().all())
    sections.append(f"""
<h2>The machine</h2>
<p>{html.escape(machine.note)}</p>
<table>{machine_rows}</table>
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
neglected where δ<sub>g</sub> &lt; {settings.threshold:.2g}. Below: the machine's crank unit on k cranks over λ
(left two-stroke, right four-stroke), and every preset machine over its speed range (δ<sub>g</sub> ∝ 1/n²).
{_significance_text(settings)}</p>
<img src="{figures["gravity_significance_k_lambda"]}" alt="δ_g over k and λ">
<img src="{figures["gravity_significance_machines"]}" alt="δ_g per machine over its speed range">
<p class="note">Data: gravity_significance_k_lambda.csv, gravity_significance_machines.csv</p>
""")
    layout_records: Iterable[Any] = layouts.itertuples()  # the columns of layouts_figure's table
    layout_rows = "".join(
        f"<tr><td>{html.escape(r.layout)}</td><td style='text-align:left'>{html.escape(r.description)}</td>"
        f"<td>{r.cylinders}</td><td>{r.energy_range:.3g}</td>"
        + (
            f"<td>{r.leading_harmonic}</td><td>{r.leading_amplitude:.3g}</td></tr>"
            if r.leading_amplitude > 0
            else "<td>none</td><td>0 (cancels exactly)</td></tr>"
        )
        for r in layout_records
    )
    sections.append(f"""
<h2>Layouts: V, boxer, W, odd-fire</h2>
<p>The same cylinder ({html.escape(machine.name)}'s first, at {rpm:g} rpm) on every bank of every preset layout,
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
with the exact Λ<sub>n</sub>, up to n = {settings.n_max}: only the harmonics whose phase sum over the cranks
survives appear (Tables 1 and 2 below; n = 1 among them only where the cranks do not cancel it).</p>
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
{_truncation_text(first.crank_ratio)} Right: the error of the truncated f(ψ).</p>
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
    return "".join(sections)
