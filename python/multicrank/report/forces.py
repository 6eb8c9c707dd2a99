"""The report's "Forces on the frame and the bearings" part, after the motion part: at the
machine's running speed, the shaking forces and moments by order
(:func:`multicrank.shaking_forces`) and the loads on its main bearings
(:func:`multicrank.bearing_loads`), with and without gravity, as tables, a small multiple of
polar diagrams and its HTML section. Every sentence of the section is made from the numbers
shown beside it, so that a machine whose numbers differ reads differently."""

from __future__ import annotations

import html
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from ..machine.machine import Machine
from .plotting import pyplot
from .settings import ReportSettings, running_speed

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "MAX_ORDER",
    "ORDER_COLUMNS",
    "ForcesResults",
    "balancing_sentence",
    "bearing_polar_figure",
    "bearing_summary_table",
    "forces_html",
    "forces_results",
    "free_orders_sentence",
    "gravity_sentence",
    "largest_sentence",
    "most_loaded_sentence",
    "number",
    "orders_table",
]

#: The highest order (per revolution) the section lists.
MAX_ORDER = 8

#: The orders table's columns on the page, with their headings: the amplitude of each
#: component, the forward and backward parts (whose sum is the largest magnitude the order's
#: force or moment vector reaches over a cycle).
ORDER_COLUMNS: dict[str, str] = {
    "force_vertical": "F vertical [N]",
    "force_horizontal": "F horizontal [N]",
    "force_forward": "F forward [N]",
    "force_backward": "F backward [N]",
    "moment_pitch": "M pitch [N·m]",
    "moment_yaw": "M yaw [N·m]",
    "moment_forward": "M forward [N·m]",
    "moment_backward": "M backward [N·m]",
}

#: Panels per row of the polar diagrams.
POLAR_COLUMNS = 4
#: The space [in] above and below each polar panel: between the figure's title and the panels', and between rows.
POLAR_PAD = 0.1


@dataclass(frozen=True)
class ForcesResults:
    """What the section shows: the machine at ``rpm`` (constant speed), its ``shaking``
    forces (a ``ShakingForces`` to :data:`MAX_ORDER`) and its ``bearings`` loads (a
    ``BearingLoads`` with gravity, over one working cycle)."""

    machine: Machine
    rpm: float
    shaking: Any
    bearings: Any

    @property
    def orders(self) -> pd.DataFrame:
        """``ShakingForces.orders``: one row per order 1 … :data:`MAX_ORDER`."""
        frame: pd.DataFrame = self.shaking.orders
        return frame

    @property
    def summary(self) -> pd.DataFrame:
        """``BearingLoads.summary``: one row per main bearing."""
        frame: pd.DataFrame = self.bearings.summary
        return frame


def forces_results(settings: ReportSettings) -> ForcesResults:
    """The machine's shaking forces (orders 1 … :data:`MAX_ORDER`) and main-bearing loads at
    its running speed, held constant."""
    from ..forces.bearings import bearing_loads
    from ..forces.shaking import shaking_forces

    machine = settings.machine
    rpm = running_speed(machine)
    return ForcesResults(
        machine=machine,
        rpm=rpm,
        shaking=shaking_forces(machine, rpm, max_order=MAX_ORDER),
        bearings=bearing_loads(machine, rpm),
    )


def number(value: float) -> str:
    """A force or moment as the section prints it: 4 significant digits, without an exponent,
    thousands separated by commas ("884.3", "12,670", "18,140,000")."""
    if value == 0 or not math.isfinite(value):
        return f"{value:g}"
    if abs(value) < 1000:
        return f"{value:.4g}"
    digits = 3 - math.floor(math.log10(abs(value)))
    return f"{round(value, digits):,.0f}"


def _listed(items: Sequence[str]) -> str:
    """ "a", "a and b", "a, b and c"."""
    return items[0] if len(items) == 1 else f"{', '.join(items[:-1])} and {items[-1]}"


def _orders_text(orders: Sequence[float]) -> str:
    return ("order " if len(orders) == 1 else "orders ") + _listed([f"{n:g}" for n in orders])


def _free(orders: pd.DataFrame, kind: str) -> pd.Series:
    """The largest magnitude of each order's force (``kind`` = "force") or moment vector over
    a cycle, forward + backward, for the orders where it is not 0 (what the units' sum cancels
    is exactly 0)."""
    largest = orders[f"{kind}_forward"] + orders[f"{kind}_backward"]
    return largest[largest > 0]


def orders_table(results: ForcesResults) -> pd.DataFrame:
    """The orders table as CSV: ``order`` and every column of ``ShakingForces.orders`` (the
    amplitudes [N], [N·m] and phases [rad] of each component, the forward and backward parts)."""
    return results.orders.reset_index()


def bearing_summary_table(results: ForcesResults) -> pd.DataFrame:
    """The bearing summary as CSV: ``bearing`` (0 … from the front), ``position`` [m],
    ``max`` [N], ``phi_max_deg`` (the crank angle of the largest load [°]), ``mean`` [N],
    ``max_without_gravity`` [N] and ``gravity_adds`` [N] (the largest magnitude of what the
    weights add to the load vector), as ``BearingLoads.summary`` gives them."""
    summary = results.summary
    table = summary.drop(columns=["phi_max"]).reset_index()
    table.insert(3, "phi_max_deg", np.degrees(summary["phi_max"].to_numpy()))
    return table


def free_orders_sentence(orders: pd.DataFrame) -> str:
    """Which orders leave a free force and which a free moment (listed orders only)."""
    listed = f"up to {orders.index.max():g}"
    parts = []
    about = "about the engine centre"
    for kind, name, plural in (("force", "force", "forces"), ("moment", f"moment {about}", f"moments {about}")):
        free = _free(orders, kind)
        if free.empty:
            cancel = ": the cylinders' forces cancel" if kind == "force" else ""
            parts.append(f"no order {listed} leaves a free {name}{cancel}")
        else:
            balanced = [n for n in orders.index if n not in free.index]
            rest = f" (none at {_orders_text(balanced)})" if balanced else ""
            verb = "leaves a free " + name if len(free) == 1 else "leave free " + plural
            parts.append(f"{_orders_text(list(free.index))} {verb}{rest}")
    text = "; ".join(parts)
    return text[0].upper() + text[1:] + "."


def largest_sentence(orders: pd.DataFrame, kind: str) -> str:
    """The largest free force (``kind`` = "force") or moment: its order, the largest magnitude
    it reaches over a cycle (forward + backward) and its components' amplitudes; "" where
    there is none."""
    free = _free(orders, kind)
    if free.empty:
        return ""
    order = float(free.index[int(np.argmax(free.to_numpy()))])
    row = orders.loc[order].astype(float).to_dict()
    unit = "N" if kind == "force" else "N·m"
    first, second = ("vertical", "horizontal") if kind == "force" else ("pitch", "yaw")
    text = (
        f"The largest free {kind} is order {order:g}'s: it reaches {number(float(free.max()))} {unit} over a cycle "
        f"(forward {number(row[f'{kind}_forward'])} + backward {number(row[f'{kind}_backward'])} {unit}; "
        f"{first} amplitude {number(row[f'{kind}_{first}'])}, {second} {number(row[f'{kind}_{second}'])} {unit})."
    )
    if kind == "moment" and order in _free(orders, "force").index:
        text += (
            f" Order {order:g} also leaves a free force, so its moment depends on the point it is taken about "
            "(here the engine centre, midway between the outermost cylinders)."
        )
    return text


def balancing_sentence(orders: pd.DataFrame) -> str:
    """What counterweights could cancel (the forward first order) and what needs balance
    shafts (the backward first order, every higher order), with their sizes."""
    first = orders.loc[1.0].astype(float).to_dict()
    force, moment = float(first["force_forward"]), float(first["moment_forward"])
    if force == 0 and moment == 0:
        counterweights = (
            "Counterweights turn with the crank, so they can cancel only the forward first order: here there is none."
        )
    else:
        parts = [f"{number(force)} N of force"] if force else []
        parts += [f"{number(moment)} N·m of moment (counterweights differing along the shaft)"] if moment else []
        counterweights = (
            "Counterweights turn with the crank, so they can cancel only the forward first order: here "
            + " and ".join(parts)
            + "."
        )
    rest = []
    backward = (float(first["force_backward"]), float(first["moment_backward"]))
    if any(backward):
        sizes = [f"{number(backward[0])} N" if backward[0] else "", f"{number(backward[1])} N·m" if backward[1] else ""]
        rest.append(f"the backward first order ({', '.join(s for s in sizes if s)})")
    higher = orders.loc[orders.index > 1]
    force_free, moment_free = _free(higher, "force"), _free(higher, "moment")
    orders_free = sorted(set(force_free.index) | set(moment_free.index))
    if orders_free:
        biggest = [f"up to {number(force_free.max())} N" if not force_free.empty else ""]
        biggest += [f"up to {number(moment_free.max())} N·m" if not moment_free.empty else ""]
        rest.append(f"{_orders_text(orders_free)} ({', '.join(b for b in biggest if b)})")
    if not rest:
        return counterweights + " Nothing else is free up to this order: no balance shafts are needed."
    return (
        f"{counterweights} The rest — {_listed(rest)} — needs balance shafts turning at that order "
        "(with the crank for a forward part, against it for a backward part)."
    )


#: Bearings whose numbers differ by at most this fraction of the largest are alike (a
#: symmetric crank's mirrored bearings differ by rounding): a sentence names them all.
TIED = 1e-9


def _tied(values: np.ndarray) -> list[int]:
    """The positions of ``values`` within :data:`TIED` of their largest, in order."""
    top = float(np.max(values))
    return [int(i) for i in np.flatnonzero(values >= top - TIED * abs(top))]


def _bearings(summary: pd.DataFrame, which: Sequence[int]) -> str:
    """ "bearing 2", "bearings 0 and 1", "bearings 1, 2, 4 and 5": the bearings at positions ``which``."""
    names = [f"{summary.index[i]}" for i in which]
    return ("bearing " if len(names) == 1 else "bearings ") + _listed(names)


def most_loaded_sentence(summary: pd.DataFrame) -> str:
    """Which bearing takes the largest load, how much and at which crank angle; every bearing
    within :data:`TIED` of it where several take it alike (a symmetric crank's)."""
    largest, phi = summary["max"].to_numpy(dtype=float), np.degrees(summary["phi_max"].to_numpy(dtype=float))
    most = _tied(largest)
    load = number(largest[most[0]])
    if len(most) == 1:
        return f"The most loaded bearing is bearing {summary.index[most[0]]}: {load} N at φ = {phi[most[0]]:.0f}°."
    angles = [f"{angle}°" for angle in sorted({round(float(phi[i])) for i in most})]
    return f"The most loaded bearings, alike, are {_bearings(summary, most)}: {load} N each, at φ = {_listed(angles)}."


def gravity_sentence(summary: pd.DataFrame) -> str:
    """What the weights add to the bearing loads: the most in N (which bearings, as % of their
    largest load), the most relative to a bearing's own load where that is another bearing,
    and how the machine's largest load changes."""
    adds, largest = summary["gravity_adds"].to_numpy(dtype=float), summary["max"].to_numpy(dtype=float)
    if not (adds > 0).any():
        return "Gravity adds nothing to the bearing loads."
    most = _tied(adds)
    share = 100 * adds / largest
    if len(_tied(largest[most])) == len(most):  # one bearing, or alike ones of one load
        whose = "its" if len(most) == 1 else "their"
        of = f"{share[most[0]]:.3g} % of {whose} largest load, {number(largest[most[0]])} N"
        of += "." if len(most) == 1 else " each."
    else:
        shares = _listed([f"{share[i]:.3g}" for i in most])
        of = f"{shares} % of their largest loads, {_listed([number(largest[i]) for i in most])} N."
    text = (
        f"Gravity (the weights of the moving parts) adds at most {number(adds[most[0]])} N to a bearing's load, "
        f"at {_bearings(summary, most)}: {of}"
    )
    relative = [i for i in _tied(share) if i not in most]
    if relative and share[relative[0]] > share[most].max():
        alike = "" if len(relative) == 1 else " each"
        text += (
            f" Relative to its own load it adds most at {_bearings(summary, relative)}: "
            f"{number(adds[relative[0]])} N{alike}, {share[relative[0]]:.3g} % of {number(largest[relative[0]])} N."
        )
    with_gravity, without = float(summary["max"].max()), float(summary["max_without_gravity"].max())
    change = 100 * (with_gravity / without - 1) if without else math.inf
    text += (
        f" The largest load of any bearing is {number(with_gravity)} N with gravity and {number(without)} N "
        f"without ({change:+.3g} %)."
    )
    return text


def _scale(largest: float) -> tuple[float, str]:
    """The unit the polar diagrams' axes read in: N, kN or MN, so that tick labels stay short."""
    for factor, unit in ((1e6, "MN"), (1e3, "kN")):
        if largest >= 10 * factor:
            return factor, unit
    return 1.0, "N"


def bearing_polar_figure(results: ForcesResults) -> tuple[Figure, pd.DataFrame]:
    """One polar diagram per main bearing (``BearingLoads.polar``): the tip of the load vector
    over a working cycle with gravity, the same with g = 0 dashed, the largest load marked;
    each panel on its own scale. Returns the figure and the curves (one row per bearing and
    angle: ``bearing``, ``position`` [m], ``phi_deg``, ``horizontal``, ``vertical``,
    ``horizontal_without_gravity``, ``vertical_without_gravity`` [N])."""
    plt = pyplot()
    from matplotlib.lines import Line2D
    from matplotlib.ticker import FuncFormatter, MaxNLocator

    loads = results.bearings
    horizontal0, vertical0 = loads.without_gravity()
    count = len(loads.positions)
    columns = min(count, POLAR_COLUMNS)
    rows = math.ceil(count / columns)
    factor, unit = _scale(float(max(loads.magnitude.max(), np.hypot(horizontal0, vertical0).max())))
    side = {2: 3.6, 3: 3.2}.get(columns, 2.9)  # a panel's width [in]: larger where there are few
    fig, axes = plt.subplots(rows, columns, figsize=(side * columns + 0.4, (side + 0.1) * rows + 0.6), squeeze=False,
                             layout="constrained")  # fmt: skip
    ticks = FuncFormatter(lambda value, _: f"{value / factor:g}")
    for bearing, ax in enumerate(axes.flat):
        if bearing >= count:
            ax.set_axis_off()
            continue
        ax.plot(horizontal0[bearing], vertical0[bearing], "--", color="0.55", lw=0.9)
        loads.polar(bearing, ax=ax)
        largest = int(np.argmax(loads.magnitude[bearing]))
        for text in ax.texts:  # polar's note of the largest load, in the section's numbers
            text.set_text(
                f"max {number(loads.magnitude[bearing, largest])} N at φ = {np.degrees(loads.phi[largest]):.0f}°"
            )
        reach = 1.15 * float(
            max(loads.magnitude[bearing].max(), np.hypot(horizontal0[bearing], vertical0[bearing]).max())
        )
        reach = reach or 1.0
        ax.set(xlim=(-reach, reach), ylim=(-reach, reach))
        ax.set_title(f"bearing {bearing}, z = {loads.positions[bearing]:.3g} m", fontsize=9)
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(ticks)
            axis.set_major_locator(MaxNLocator(nbins=5, steps=[1, 2, 2.5, 5, 10], symmetric=True))
        ax.set_xlabel(f"horizontal [{unit}]" if bearing + columns >= count else "")
        ax.set_ylabel(f"vertical [{unit}]" if bearing % columns == 0 else "")
    handles = [
        Line2D([], [], color="C0", lw=1.2, label="with gravity"),
        Line2D([], [], color="0.55", ls="--", lw=0.9, label="without gravity (g = 0)"),
        Line2D([], [], color="C3", lw=1, label="largest load"),
    ]
    fig.legend(handles=handles, loc="outside lower center", ncol=3, fontsize=8, frameon=False)
    fig.suptitle(
        f"load each main bearing receives from the shaft over a working cycle, {results.rpm:g} rpm",
        fontsize=11,
    )
    # Room between the title and the panels' own titles, and between the rows of panels: the
    # constrained layout's default pad (3 pt) sets the title on the panels' titles.
    fig.get_layout_engine().set(h_pad=POLAR_PAD)
    phi = np.degrees(loads.phi)
    table = pd.DataFrame(
        {
            "bearing": np.repeat(np.arange(count), phi.size),
            "position": np.repeat(loads.positions, phi.size),
            "phi_deg": np.tile(phi, count),
            "horizontal": loads.horizontal.ravel(),
            "vertical": loads.vertical.ravel(),
            "horizontal_without_gravity": horizontal0.ravel(),
            "vertical_without_gravity": vertical0.ravel(),
        }
    )
    return fig, table


def _placement_note(machine: Machine) -> str:
    """A note where no cylinder is placed along the shaft: the moments are 0 by that."""
    if len(machine) > 1 and all(c.axial_position == 0 for c in machine.cylinders):
        return (
            '<p class="note">Every cylinder is at z = 0 (none is placed along the shaft), so the moments are 0 '
            "by that, not by balance, and the whole crank lies between two bearings; a machine file places the "
            "cylinders by <code>axial_position</code>, or by <code>cylinder_spacing</code> with a layout.</p>"
        )
    return ""


def forces_html(results: ForcesResults, figures: dict[str, str]) -> str:
    """The report's section "Forces on the frame and the bearings"."""
    orders, summary = results.orders, results.summary
    header = "".join(f"<th>{html.escape(name)}</th>" for name in ORDER_COLUMNS.values())
    body = "".join(
        f"<tr><td>{order:g}</td>" + "".join(f"<td>{number(row[name])}</td>" for name in ORDER_COLUMNS) + "</tr>"
        for order, row in orders.iterrows()
    )
    sentences = [free_orders_sentence(orders), *(largest_sentence(orders, kind) for kind in ("force", "moment"))]
    said = "\n".join(text for text in [*sentences, balancing_sentence(orders)] if text)
    share = 100 * summary["gravity_adds"].to_numpy(dtype=float) / summary["max"].to_numpy(dtype=float)
    bearing_rows = "".join(
        f"<tr><td>{bearing}</td><td>{r['position']:.4g}</td><td>{number(r['max'])}</td>"
        f"<td>{math.degrees(r['phi_max']):.0f}</td><td>{number(r['mean'])}</td>"
        f"<td>{number(r['max_without_gravity'])}</td><td>{number(r['gravity_adds'])}</td>"
        f"<td>{percent:.3g}</td></tr>"
        for (bearing, r), percent in zip(summary.iterrows(), share, strict=True)
    )
    cycle = "two revolutions (four-stroke)" if results.machine.strokes == 4 else "one revolution"
    return f"""
<h2>Forces on the frame and the bearings</h2>
<p>At {results.rpm:g} rpm held constant. The frame takes the inertial reaction −Σ m·a of every moving
part — pistons, rods, crank webs and counterweights — whatever the flywheel does
(<code>mc.shaking_forces</code>); the main bearings take that and the gas forces, the weights, and the rods'
inertia as rigid bodies, each throw shared between its two neighbouring bearings by the lever rule
(<code>mc.bearing_loads</code>).</p>
<h3>Shaking forces and moments by order</h3>
<p>The amplitude of each order (harmonics per revolution) of the force on the frame, vertical (upward) and
horizontal (toward a cylinder at γ = 0), and of the moments of those forces about the engine centre, midway
between the outermost cylinders (pitch: of the
vertical ones, yaw: of the horizontal ones); forward and backward are the parts that turn with the crank and
against it, their sum the largest the order reaches over a cycle.
{said}</p>
<table><tr><th>order</th>{header}</tr>{body}</table>
{_placement_note(results.machine)}
<h3>Main-bearing loads</h3>
<p>The force each main bearing receives from the shaft over {cycle}: the tip of the load vector with gravity,
the same with g = 0 dashed, the largest load marked. {most_loaded_sentence(summary)}
{gravity_sentence(summary)}</p>
<img src="{figures["forces_bearing_loads"]}" alt="polar diagrams of the main-bearing loads">
<table><tr><th>bearing</th><th>z [m]</th><th>largest load [N]</th><th>at φ [°]</th><th>mean [N]</th>
<th>largest without gravity [N]</th><th>gravity adds [N]</th><th>gravity adds [% of largest]</th></tr>
{bearing_rows}</table>
<p class="note">Data: forces_orders.csv, forces_bearing_loads.csv, forces_bearing_summary.csv</p>
"""
