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

as figures (drawn in :mod:`.gravity_figures`), tables and the HTML sections that follow the
motion part.
"""

from __future__ import annotations

import html
import math
from collections.abc import Iterable
from typing import Any

import pandas as pd

from .._text import counted
from ..gravity.extrema import speed_fluctuation
from ..gravity.harmonics import harmonic_table, lambda_coefficients
from ..gravity.mechanism import crank_phases
from .gravity_figures import (
    _is_inline,
    _unit_machine,
    curves_figure,
    layouts_figure,
    machines_figure,
    significance_map,
    spectra_figure,
    truncation_figure,
)
from .prose import significance_sentence
from .settings import ReportSettings, running_speed

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
    """The report's gravity sections, after the motion part (which holds the verdict): the
    machine, gravity significance, layouts, the curves, spectra and tables on k cranks, the paper's
    truncation error, the conventions and the errata. ``figures`` holds the embedded figures
    by name, ``tables`` the :func:`surviving_tables`, ``paper`` the :func:`paper_table_frame`
    and ``layouts`` the table of :func:`layouts_figure`."""
    machine = settings.machine
    rpm = running_speed(machine)
    sections: list[str] = []
    unit = _unit_machine(machine).design()
    delta = float(machine.engine(rpm).speed_fluctuation())
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
