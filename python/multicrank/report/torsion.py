"""The report's torsional part of "What to change", for a machine with a shaft
(``Machine.shaft``): a Campbell diagram — the shaft's natural frequencies against the firing
orders over the speeds — and the resonances in the machine's speed range with their modal
excitation, comparable between modes (:func:`multicrank.torsional_merit`), those at the
running speed pointed out."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np
import pandas as pd

from ..machine.machine import Machine
from ..torsion.merit import speed_window, torsional_merit

__all__ = ["MODES", "ORDERS", "RESONANCE_ROWS", "campbell_figure", "resonances", "torsion_html"]

#: The elastic modes the diagram draws and the table lists.
MODES = 2
#: The highest order drawn and listed.
ORDERS = 12
#: The most resonances the section's table lists, the strongest first.
RESONANCE_ROWS = 8


def resonances(machine: Machine, rpm: float) -> pd.DataFrame:
    """:func:`~multicrank.torsional_merit` of the machine's shaft (modes 1…:data:`MODES` that
    it has, orders up to :data:`ORDERS`), every row, with ``in_range``: whether the resonance
    lies in the machine's speed range (ends included)."""
    assert machine.shaft is not None
    modes = min(MODES, len(machine.shaft.inertia) - 1)
    table = torsional_merit(machine, modes=modes, max_order=ORDERS)
    low, high = speed_window(machine, rpm)
    table["in_range"] = (table["resonance_rpm"] >= low) & (table["resonance_rpm"] <= high)
    return table


def campbell_figure(machine: Machine, rpm: float, merit: pd.DataFrame) -> tuple[Any, pd.DataFrame]:
    """The Campbell diagram: frequency [Hz] against speed [1/min], a ray f = ν·n/60 per order
    (major orders bold), a line per natural frequency, the speed range shaded and each
    resonance in it marked by a circle whose area grows with its modal excitation (comparable
    between modes), one at the running speed filled. Every label stays inside the axes."""
    from .plotting import pyplot

    plt = pyplot()
    low, high = speed_window(machine, rpm)
    top_speed = 1.25 * max(high, rpm)
    frequencies = merit.groupby("mode")["natural_frequency"].first()
    top_frequency = 1.25 * max(float(frequencies.max()), ORDERS * top_speed / 60 / 4)
    fig, ax = plt.subplots(figsize=(7.2, 4.6))
    ax.axvspan(low, high, color="tab:green", alpha=0.12, label="speed range")
    orders = np.unique(merit["order"])
    majors = set(merit.loc[merit["major"], "order"])
    for order in orders:
        major = order in majors
        ax.plot(
            [0, top_speed],
            [0, order * top_speed / 60],
            color="tab:red" if major else "0.55",
            lw=1.6 if major else 0.7,
            zorder=2,
        )
        if order == int(order):  # the half orders' rays unlabelled: the labels would crowd
            # At the ray's end on the frame, set inward from it so that it stays inside the axes.
            end = min(top_speed, top_frequency * 60 / order)
            on_top = end < top_speed
            ax.annotate(f"{order:g}", (end, order * end / 60), fontsize=7, textcoords="offset points",
                        xytext=(-2, -2), ha="right" if not on_top else "center", va="top",
                        color="tab:red" if major else "0.3", annotation_clip=True)  # fmt: skip
    for mode, frequency in frequencies.items():
        ax.axhline(frequency, color="tab:blue", lw=1.2, ls="--", zorder=2)
        ax.annotate(f"mode {mode}: {frequency:.4g} Hz", (0.99 * top_speed, frequency), fontsize=8, xytext=(0, 3),
                    textcoords="offset points", color="tab:blue", ha="right")  # fmt: skip
    inside = merit[merit["in_range"]]
    largest = float(inside["modal_excitation"].max()) if len(inside) else 1.0

    def circles(rows: pd.DataFrame, **style: Any) -> None:
        """A circle at each resonance of ``rows``, its area growing with the modal excitation."""
        if len(rows):
            speed = rows["resonance_rpm"]
            size = 20 + 280 * rows["modal_excitation"] / (largest or 1.0)
            ax.scatter(speed, rows["order"] * speed / 60, s=size, edgecolors="black", **style)

    circles(inside, facecolors="none", zorder=3, label="resonance in range (area ∝ modal excitation)")
    circles(inside[inside["at_running_speed"]], color="tab:orange", zorder=4, label="within ±5 % of the running speed")
    ax.axvline(rpm, color="tab:orange", lw=0.8, ls=":", zorder=1, label=f"running speed {rpm:g} 1/min")
    ax.plot([], [], color="tab:red", lw=1.6, label="major order")
    ax.plot([], [], color="0.55", lw=0.7, label="minor order")
    ax.set_xlim(0, top_speed)
    ax.set_ylim(0, top_frequency)
    ax.set_xlabel("speed n [1/min]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(f"Campbell diagram: {machine.name}, orders up to {ORDERS} (rays labelled at whole orders)", fontsize=9)
    ax.legend(loc="best", fontsize=7, framealpha=0.9)
    fig.tight_layout()
    return fig, merit


def torsion_html(machine: Machine, rpm: float, merit: pd.DataFrame, figures: dict[str, str]) -> str:
    """The torsional part of "What to change": the Campbell diagram and the strongest
    resonances in the speed range, largest modal excitation first, and those within ±5 % of
    the running speed named."""
    from .forces import number

    low, high = speed_window(machine, rpm)
    ranked = merit[merit["in_range"]].sort_values("modal_excitation", ascending=False, kind="stable")
    inside = ranked.head(RESONANCE_ROWS)
    if len(inside):
        records: Iterable[Any] = inside.itertuples()  # torsional_merit's columns
        body = "".join(
            f"<tr><td>{r.mode}</td><td>{r.order:g}{' (major)' if r.major else ''}</td>"
            f"<td>{r.resonance_rpm:.4g}{' <b>(at the running speed)</b>' if r.at_running_speed else ''}</td>"
            f"<td>{r.vector_sum:.3g}</td><td>{number(r.excitation)}</td><td>{number(r.modal_excitation)}</td></tr>"
            for r in records
        )
        table = (
            "<table><tr><th>mode</th><th>order</th><th>resonance [1/min]</th><th>vector sum</th>"
            f"<th>excitation [N·m]</th><th>modal excitation [N·m/√(kg·m²)]</th></tr>{body}</table>"
        )
        if len(ranked) > len(inside):
            table += (
                f'<p class="note">The {len(inside)} strongest of {len(ranked)} resonances in the speed range; '
                "design_campbell.csv has every mode and order.</p>"
            )
    else:
        table = f"<p>No order up to {ORDERS} meets a mode of the shaft in the speed range.</p>"
    running = merit[merit["at_running_speed"]]
    if len(running):
        named = "; ".join(
            f"mode {r.mode}, order {r.order:g} at {r.resonance_rpm:.4g} 1/min" for r in running.itertuples()
        )
        table += (
            f'<p class="warning"><b>A resonance at the running speed</b> ({rpm:g} 1/min, within ±5 %): {named}. '
            "The machine runs on it: move the mode (the shaft, a flywheel, a coupling), damp it, or show by a "
            "forced-response calculation that its stresses are within the limits.</p>"
        )
    frequencies = ", ".join(f"{f:.4g} Hz" for f in merit.groupby("mode")["natural_frequency"].first())
    image = f'<img src="{figures["design_campbell"]}" alt="Campbell diagram of the shaft">'
    return f"""
<h3>Torsional vibration</h3>
<p>The shaft (<code>Machine.shaft</code>: {len(machine.shaft.inertia) if machine.shaft else 0} nodes) has its
first elastic modes at {frequencies}. An order ν meets a mode of frequency f at n = 60·f/ν: each circle in the
diagram is such a resonance within the speed range ({low:g}–{high:g} 1/min), larger the more the firing drives it
(the modal excitation abs(Σ φ_j T_ν,j) of <code>mc.torsional_merit</code>: each cylinder's torque harmonic weighted
by the mass-normalised mode's swing at its throw, so that modes compare; the classical excitation with the
swings relative to the largest throw's is listed beside it). Major orders (every cylinder in phase) are red; the
dotted line is the running speed, and a filled circle a resonance within ±5 % of it. This ranks; the size of the
vibration needs the damping: <code>mc.to_opentorsion</code> hands the model on.</p>
{image}
{table}"""
