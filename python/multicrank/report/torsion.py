"""The report's torsional part of "What to change", for a machine with a shaft
(``Machine.shaft``): a Campbell diagram — the shaft's natural frequencies against the firing
orders over the speeds — and the resonances in the machine's speed range with their
excitation (:func:`multicrank.torsional_merit`)."""

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
    resonance in it marked by a circle whose area grows with its excitation."""
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
            end = min(top_speed, top_frequency * 60 / order)
            ax.annotate(f"{order:g}", (end, order * end / 60), fontsize=7, xytext=(1, 1), textcoords="offset points",
                        color="tab:red" if major else "0.3")  # fmt: skip
    for mode, frequency in frequencies.items():
        ax.axhline(frequency, color="tab:blue", lw=1.2, ls="--", zorder=2)
        ax.annotate(f"mode {mode}: {frequency:.4g} Hz", (0.99 * top_speed, frequency), fontsize=8, xytext=(0, 3),
                    textcoords="offset points", color="tab:blue", ha="right")  # fmt: skip
    inside = merit[merit["in_range"]]
    if len(inside):
        largest = float(inside["excitation"].max()) or 1.0
        ax.scatter(
            inside["resonance_rpm"],
            inside["order"] * inside["resonance_rpm"] / 60,
            s=20 + 280 * inside["excitation"] / largest,
            facecolors="none",
            edgecolors="black",
            zorder=3,
            label="resonance in range (area ∝ excitation)",
        )
    ax.plot([], [], color="tab:red", lw=1.6, label="major order")
    ax.plot([], [], color="0.55", lw=0.7, label="minor order")
    ax.set_xlim(0, top_speed)
    ax.set_ylim(0, top_frequency)
    ax.set_xlabel("speed n [1/min]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(f"Campbell diagram: {machine.name}, orders up to {ORDERS} (rays labelled at whole orders)", fontsize=9)
    ax.legend(loc="upper left", fontsize=7)
    fig.tight_layout()
    return fig, merit


def torsion_html(machine: Machine, rpm: float, merit: pd.DataFrame, figures: dict[str, str]) -> str:
    """The torsional part of "What to change": the Campbell diagram and the strongest
    resonances in the speed range, largest excitation first."""
    from .forces import number

    low, high = speed_window(machine, rpm)
    ranked = merit[merit["in_range"]].sort_values("excitation", ascending=False, kind="stable")
    inside = ranked.head(RESONANCE_ROWS)
    if len(inside):
        records: Iterable[Any] = inside.itertuples()  # torsional_merit's columns
        body = "".join(
            f"<tr><td>{r.mode}</td><td>{r.order:g}{' (major)' if r.major else ''}</td>"
            f"<td>{r.resonance_rpm:.4g}</td><td>{r.vector_sum:.3g}</td><td>{number(r.excitation)}</td></tr>"
            for r in records
        )
        table = (
            "<table><tr><th>mode</th><th>order</th><th>resonance [1/min]</th><th>vector sum</th>"
            f"<th>excitation [N·m]</th></tr>{body}</table>"
        )
        if len(ranked) > len(inside):
            table += (
                f'<p class="note">The {len(inside)} strongest of {len(ranked)} resonances in the speed range; '
                "design_campbell.csv has every mode and order.</p>"
            )
    else:
        table = f"<p>No order up to {ORDERS} meets a mode of the shaft in the speed range.</p>"
    frequencies = ", ".join(f"{f:.4g} Hz" for f in merit.groupby("mode")["natural_frequency"].first())
    image = f'<img src="{figures["design_campbell"]}" alt="Campbell diagram of the shaft">'
    return f"""
<h3>Torsional vibration</h3>
<p>The shaft (<code>Machine.shaft</code>: {len(machine.shaft.inertia) if machine.shaft else 0} nodes) has its
first elastic modes at {frequencies}. An order ν meets a mode of frequency f at n = 60·f/ν: each circle in the
diagram is such a resonance within the speed range ({low:g}–{high:g} 1/min), larger the more the firing drives it
(the excitation |Σ a_j T_ν,j| of <code>mc.torsional_merit</code>: each cylinder's torque harmonic weighted by the
mode's swing at its throw). Major orders (every cylinder in phase) are red. This ranks; the size of the vibration
needs the damping: <code>mc.to_opentorsion</code> hands the model on.</p>
{image}
{table}"""
