"""The report's "What to change" part, between the motion part and the paper's analysis: for
the machine, the best firing orders its crank allows (:func:`multicrank.firing_orders`) next
to its own, and the counterweights that make δ with gravity smallest
(:func:`multicrank.optimize_counterweights`) against those it has, with what they do to the
first-order shaking force and moment and to the largest main-bearing load, as tables and
their HTML section."""

from __future__ import annotations

import html
import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from .._text import counted
from ..design.criteria import COUNTERWEIGHT_CRITERIA, VOCABULARY
from ..machine.machine import Machine
from .settings import ReportSettings, running_speed
from .torsion import resonances, torsion_html

__all__ = [
    "FIRING_ROWS",
    "NEGLIGIBLE",
    "PARETO_ROWS",
    "DesignResults",
    "counterweight_forces",
    "counterweight_forces_sentence",
    "counterweight_forces_table",
    "counterweight_table",
    "design_html",
    "design_results",
    "firing_table",
]

#: How many of the best firing orders the section lists (the machine's own is added below
#: them where it ranks lower).
FIRING_ROWS = 3

#: The most rows of the Pareto front the section lists besides the best by δ (a V12's front
#: may hold dozens; the CSV of :func:`~multicrank.firing_orders` has them all).
PARETO_ROWS = 10

#: An optimum that makes δ smaller by less than this fraction is not worth a change.
NEGLIGIBLE = 1e-3


@dataclass(frozen=True)
class DesignResults:
    """What the section shows: ``firing``, :func:`~multicrank.firing_orders`'s whole table
    for the machine; ``own``, the row of it that runs as the machine as given (its
    ``as_given``); ``optimum``, :func:`~multicrank.optimize_counterweights`'s
    result (a ``CounterweightOptimum``); ``forces``, :func:`counterweight_forces` of the
    optimum (None: made from ``optimum`` when asked); ``resonances``, for a machine with a
    shaft, its torsional resonances (:func:`~multicrank.report.torsion.resonances`);
    ``kept``, where the optimum for δ loads the bearings more than as built, the optimum for
    δ that keeps the largest bearing load no higher than as built (None otherwise)."""

    machine: Machine
    rpm: float
    firing: pd.DataFrame
    own: int | None
    optimum: Any
    forces: pd.DataFrame | None = None
    resonances: pd.DataFrame | None = None
    kept: Any = None


def design_results(settings: ReportSettings) -> DesignResults:
    """The machine's firing orders and its counterweight optimum at its running speed (the
    balance load, δ with gravity), each with the library's defaults."""
    from ..design.counterweights import optimize_counterweights
    from ..design.firing import firing_orders

    machine = settings.machine
    rpm = running_speed(machine)
    firing = firing_orders(machine, rpm=rpm)
    optimum = optimize_counterweights(machine, rpm=rpm)
    kept = None
    if optimum.max_bearing_load > optimum.max_bearing_load_before * (1 + UNCHANGED):
        kept = optimize_counterweights(machine, rpm=rpm, max_bearing_load=optimum.max_bearing_load_before)
    return DesignResults(
        machine=machine,
        rpm=rpm,
        firing=firing,
        own=next((int(row) for row in np.flatnonzero(firing["as_given"].to_numpy())), None),
        optimum=optimum,
        forces=counterweight_forces(optimum, rpm, kept),
        resonances=None if machine.shaft is None else resonances(machine, rpm),
        kept=kept,
    )


def counterweight_forces(optimum: Any, rpm: float, kept: Any = None) -> pd.DataFrame:
    """What a counterweight optimum does to the frame and the bearings at ``rpm`` [1/min]
    (constant speed): one row for the machine as given and one for the optimum's machine
    (``CounterweightOptimum.machine_before`` and ``.machine``) and, given ``kept`` (the
    optimum for δ under ``max_bearing_load``), one for its machine; with ``design`` ("as
    given", "optimum", "bearings kept"), the optimum's criteria (the design aid's one
    vocabulary): ``delta`` (δ with gravity at the optimum's speed), ``free_force_1`` [N] and
    ``free_moment_1`` [N·m] (the largest magnitude the first order's force and moment about
    the engine centre reach over a cycle), ``max_bearing_load`` [N] (the largest load of any
    main bearing over a working cycle, gravity included), and ``bearing``, the bearing that
    takes it (:func:`~multicrank.bearing_loads`)."""
    from ..forces.bearings import bearing_loads

    rows = []
    designs = [("as given", optimum, "_before"), ("optimum", optimum, "")]
    if kept is not None:
        designs.append(("bearings kept", kept, ""))
    for design, found, side in designs:
        machine = found.machine_before if side else found.machine
        largest = bearing_loads(machine, rpm).magnitude.max(axis=1)
        rows.append(
            {
                "design": design,
                **{name: float(getattr(found, name + side)) for name in COUNTERWEIGHT_CRITERIA},
                "bearing": int(np.argmax(largest)),
            }
        )
    return pd.DataFrame(rows)


def counterweight_forces_table(results: DesignResults) -> pd.DataFrame:
    """The section's before/after table of the counterweight optimum's forces
    (:func:`counterweight_forces`)."""
    return results.forces if results.forces is not None else counterweight_forces(results.optimum, results.rpm)


def firing_table(results: DesignResults) -> pd.DataFrame:
    """The section's firing-order table: the :data:`FIRING_ROWS` best of
    :func:`~multicrank.firing_orders` by δ, then the rest of its Pareto front (at most
    :data:`PARETO_ROWS` rows in all of it) and, where it is not among them, the machine's own;
    ``rank`` (1 = smallest δ with gravity), ``as_given`` (the machine's own phases), ``phases_deg``
    (α_j in degrees in the machine's cylinder order, space-separated), ``fires_at_deg`` (the
    crank angle φ at which each cylinder fires, (α_1 − α_j) mod the cycle in degrees from
    cylinder 1's firing, in cylinder order: two rows of one name, a twin's "1-2" 180° or
    540° apart, differ here) and the library's columns but ``phases`` and ``machine``."""
    firing = results.firing
    rows = list(range(min(FIRING_ROWS, len(firing))))
    front = [row for row in np.flatnonzero(firing["pareto"].to_numpy()) if row not in rows]
    rows += [int(row) for row in front[: max(PARETO_ROWS - len(rows), 0)]]
    if results.own is not None and results.own not in rows:
        rows.append(results.own)
    table = firing.iloc[rows].drop(columns=["phases", "machine"])
    table.insert(0, "rank", [row + 1 for row in rows])
    table.insert(
        3,
        "phases_deg",
        [" ".join(f"{math.degrees(a):.10g}" for a in firing["phases"].iloc[row]) for row in rows],
    )
    table.insert(4, "fires_at_deg", [_fires_at(firing["phases"].iloc[row], results.machine.cycle) for row in rows])
    return table.reset_index(drop=True)


def _fires_at(phases: Any, cycle: float) -> str:
    """Each cylinder's firing angle φ [°] after cylinder 1's, in cylinder order: cylinder j
    fires at φ = −α_j (mod the cycle), so (α_1 − α_j) mod the cycle; rounded to 1e-6°."""
    alpha = np.asarray(phases, dtype=float)
    degrees = np.round(np.degrees(np.mod(alpha[0] - alpha, cycle)), 6) % round(math.degrees(cycle))
    return " ".join(f"{d:g}" for d in degrees)


def counterweight_table(results: DesignResults) -> pd.DataFrame:
    """The section's counterweight table: one row per throw (``CounterweightOptimum.to_frame``):
    ``throw``, ``cylinders``, ``angle_deg``, ``counterweight_before`` and ``counterweight``
    [kg·m]."""
    frame: pd.DataFrame = results.optimum.to_frame()
    return frame


def _delta(value: float) -> str:
    return "stalls" if not math.isfinite(value) else f"{value:.5g}"


def _percent(value: float) -> str:
    return "—" if not math.isfinite(value) else f"{100 * value:+.3g} %"


def _near_stall_mark(delta: float) -> str:
    """A mark for a δ above NEAR_STALL_DELTA (:func:`_near_stall_legend` says what it means)."""
    from ..motion.steady import NEAR_STALL_DELTA

    return " †" if delta > NEAR_STALL_DELTA else ""


def _near_stall_legend(*deltas: float) -> str:
    """What the mark means, where one of ``deltas`` has it; else ""."""
    from ..motion.steady import NEAR_STALL_NOTE

    if not any(_near_stall_mark(d) for d in deltas):
        return ""
    return f'<p class="note">† {html.escape(NEAR_STALL_NOTE)}.</p>'


def _firing_html(results: DesignResults) -> str:
    firing, table = results.firing, firing_table(results)
    candidates, distinct = int(firing.attrs["candidates"]), int(firing.attrs["distinct"])
    cycle = "two-stroke: the throws' angles arranged over the throws" if results.machine.strokes == 2 else (
        "four-stroke: each cylinder's phase fixed by the crank modulo 360°, the cam choosing the revolution"
    )  # fmt: skip
    if candidates == 1:
        count = (
            "A single cylinder has one firing order: there is nothing to choose."
            if len(results.machine) == 1
            else f"The crank allows only one firing order ({html.escape(str(firing['firing'].iloc[0]))}): "
            "there is nothing to choose; another firing order needs another crank."
        )
    else:
        exhaustive = (
            "every one of them was solved"
            if firing.attrs["exhaustive"]
            else "<b>not all of them were tried</b> (the enumeration stopped at its limit, "
            "<code>max_candidates</code>): a better one may exist"
        )
        count = (
            f"The crank allows {candidates:,} phase assignments ({cycle}), {distinct} of them distinct "
            f"(running differently, not merely shifted or with alike cylinders swapped); {exhaustive}."
        )
    if results.own is None:
        own = " The machine's own phases are not among the candidates tried."
    elif candidates == 1:
        own = ""
    elif results.own < FIRING_ROWS:
        own = f" The machine as given is rank {results.own + 1} (marked)."
    else:
        own = f" The machine as given is rank {results.own + 1} of {distinct}, the last row."
    from .forces import number

    marked = ' class="own"'
    merit = "torsional_minor" in table.columns
    records: Iterable[Any] = table.itertuples()  # the columns of firing_table
    body = "".join(
        f"<tr{marked if r.as_given else ''}><td>{r.rank}</td><td>{html.escape(str(r.firing))}"
        f"{' (as given)' if r.as_given else ''}</td><td>{html.escape(str(r.fires_at_deg))}</td>"
        f"<td>{_delta(r.delta)}{_near_stall_mark(r.delta)}</td>"
        f"<td>{_delta(r.delta_without_gravity)}{_near_stall_mark(r.delta_without_gravity)}</td>"
        f"<td>{_percent(r.gravity_effect)}</td>"
        f"<td>{number(r.free_moment_1)}</td><td>{number(r.free_moment_2)}</td><td>{number(r.max_bearing_load)}</td>"
        + (f"<td>{number(r.torsional_major)}</td><td>{number(r.torsional_minor)}</td>" if merit else "")
        + f"<td>{'✓' if r.pareto else ''}</td></tr>"
        for r in records
    )
    criteria = "δ, the free moments, the largest bearing load" + (
        " and the torsional excitations by major and minor orders" if merit else ""
    )
    merit_header = "<th>torsional, major [N·m/√(kg·m²)]</th><th>torsional, minor [N·m/√(kg·m²)]</th>" if merit else ""
    merit_text = (
        "; with the machine's shaft, the largest modal excitation (comparable between modes) of its first modes by "
        "an order that resonates in the speed range (below), apart for the major orders, in which every cylinder "
        "fires in phase and which no firing order changes, and the minor ones, which the firing order decides"
        if merit
        else ""
    )
    return f"""
<h3>Firing order</h3>
<p>{count}{own} Each row is the exact steady state at {results.rpm:g} rpm with the balance load
(<code>mc.firing_orders</code>): the cylinders, numbered from 1 in the machine's order, in the order
they fire from cylinder 1 (the direction of rotation), "+" for those firing together; beside it the crank
angle at which each cylinder fires, in cylinder order, from cylinder 1's firing. Beside δ, what an engine designer
weighs too, each at {results.rpm:g} rpm held constant: the first- and second-order free moments on the frame (the
largest the order's moment vector reaches over a cycle, about the engine centre) and the largest main-bearing load
over the working cycle{merit_text}. A row marked Pareto is one no other row beats on every one of {criteria} at once:
the choice is among those. Firings that run alike on a rigid shaft (one δ) are separate rows where those differ.</p>
<table><tr><th>rank</th><th>firing</th><th>fires at [°], cylinder 1, 2, …</th><th>δ with gravity</th>
<th>δ without gravity</th><th>gravity changes δ by</th><th>free moment, 1st order [N·m]</th>
<th>free moment, 2nd order [N·m]</th><th>largest bearing load [N]</th>{merit_header}<th>Pareto</th></tr>{body}</table>
{_near_stall_legend(*table["delta"], *table["delta_without_gravity"])}"""


def _counterweight_html(results: DesignResults) -> str:
    optimum = results.optimum
    records: Iterable[Any] = counterweight_table(results).itertuples()  # CounterweightOptimum.to_frame's columns
    body = "".join(
        f"<tr><td>{r.throw}</td><td>{html.escape(str(r.cylinders))}</td><td>{r.angle_deg:g}°</td>"
        f"<td>{r.counterweight_before:.4g}</td><td>{r.counterweight:.4g}</td>"
        f"<td>{r.counterweight - r.counterweight_before:+.3g}</td>"
        f"<td>{'<b>at a bound of the search</b>' if r.at_bound else ''}</td></tr>"
        for r in records
    )
    work = f"{counted(optimum.nit, 'generation')}, {counted(optimum.nfev, 'evaluation')}"
    converged = (
        f"yes ({work})"
        if optimum.success
        else f"<b>no</b> ({html.escape(str(optimum.message))}; {work}): the optimum is the best point found, "
        "not a proven minimum"
    )
    objective = "δ with gravity" if optimum.objective_name == "delta" else html.escape(optimum.objective_name)
    summary = [
        ("δ with gravity, as given", f"{optimum.delta_before:.5g}{_near_stall_mark(optimum.delta_before)}"),
        ("δ with gravity, optimum counterweights", f"{optimum.delta:.5g}{_near_stall_mark(optimum.delta)}"),
        (f"{objective} smaller by", f"<b>{100 * optimum.improvement:.3g} %</b>"),
        ("converged", converged),
    ]
    if any(optimum.at_bound):
        summary.append(
            (
                "at a bound of the search",
                "<b>yes</b>: the optimiser would go further than the bounds allow, so the optimum is the bounds' as "
                "much as the machine's (widen <code>bounds</code>, or take them as a limit of the design)",
            )
        )
    verdict = (
        f" Here no counterweights within the bounds make δ smaller by {100 * NEGLIGIBLE:g} % or more: they are not "
        "worth changing for δ."
        if optimum.improvement < NEGLIGIBLE
        else ""
    )
    summary_body = "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in summary)
    return f"""
<h3>Counterweights</h3>
<p>The first moment m·r of each throw's counterweight (kg·m, opposite the crank pin) that makes δ with gravity
at {optimum.rpm:g} rpm smallest, the rest of the machine as given (<code>mc.optimize_counterweights</code>:
differential evolution over the library's default bounds, then polished). A counterweight also balances the
rotating masses: it changes the shaking forces and the bearing loads, which δ does not see (below).{verdict}</p>
<table><tr><th>throw</th><th>cylinders</th><th>pin angle</th><th>as given [kg·m]</th><th>optimum [kg·m]</th>
<th>change [kg·m]</th><th></th></tr>{body}</table>
<table>{summary_body}</table>
{_near_stall_legend(optimum.delta_before, optimum.delta)}
{_counterweight_forces_html(results)}"""


#: Relative changes below this are "unchanged" in the before/after of the counterweight optimum.
UNCHANGED = 1e-9

#: The before/after rows: the criteria of :func:`counterweight_forces` but δ, in the design
#: aid's words and units.
_FORCE_ROWS = {
    name: (VOCABULARY[name].words, VOCABULARY[name].unit) for name in COUNTERWEIGHT_CRITERIA if name != "delta"
}


def _change(before: float, after: float) -> str:
    """The change from ``before`` to ``after`` in %, or what it is where a % says nothing."""
    if abs(after - before) <= UNCHANGED * max(abs(before), abs(after)):
        return "unchanged"
    if before == 0:
        return "from none"
    return f"{100 * (after / before - 1):+.3g} %"


def counterweight_forces_sentence(forces: pd.DataFrame) -> str:
    """Whether the counterweight optimum makes the first-order force and moment and the
    largest bearing load worse, said plainly, from :func:`counterweight_forces`'s table."""
    from .forces import _listed, number

    before, after = forces.iloc[0], forces.iloc[1]
    worse: list[str] = []
    better: list[str] = []
    takers: list[str] = []
    for column, (name, unit) in _FORCE_ROWS.items():
        old, new = float(before[column]), float(after[column])
        change = _change(old, new)
        if change == "unchanged":
            continue
        said = f"the {name} ({number(old)} → {number(new)} {unit}" + (f", {change})" if old else ")")
        (worse if new > old else better).append(said)
        if new > old:
            takers.append("the bearings" if column == "max_bearing_load" else "the frame's mounts")
    if not worse and not better:
        return "The optimum leaves the first-order force and moment and the largest bearing load as they are."
    text = ""
    if worse:
        them = "it" if len(worse) == 1 else "them"
        text = (
            f"<b>The optimum for δ makes {_listed(worse)} larger</b>: δ does not see {them}; check that "
            f"{_listed(list(dict.fromkeys(takers)))} can take {them} before fitting these counterweights for δ."
        )
    if better:
        text += (" It makes " if worse else "The optimum makes ") + _listed(better) + " smaller."
    return text


def _counterweight_forces_html(results: DesignResults) -> str:
    """The first-order force and moment and the largest bearing load, as given and with the
    optimum counterweights (and with the optimum that keeps the bearing loads as built, where
    there is one), and the sentence on them."""
    from .forces import number

    forces = counterweight_forces_table(results)
    before, after = forces.iloc[0], forces.iloc[1]
    kept = forces.iloc[2] if len(forces) > 2 else None
    rows = {"delta": ("δ with gravity", "–"), **_FORCE_ROWS}

    def shown(column: str, value: float) -> str:
        return _delta(value) if column == "delta" else number(value)

    body = "".join(
        f"<tr><th>{name} [{unit}]</th><td>{shown(column, before[column])}</td><td>{shown(column, after[column])}</td>"
        f"<td>{_change(float(before[column]), float(after[column]))}</td>"
        + (
            ""
            if kept is None
            else f"<td>{shown(column, kept[column])}</td><td>{_change(float(before[column]), float(kept[column]))}</td>"
        )
        + "</tr>"
        for column, (name, unit) in rows.items()
    )
    header = "<th>as given</th><th>optimum for δ</th><th>change</th>"
    where = f"bearing {int(before['bearing'])} as given, bearing {int(after['bearing'])} with the optimum"
    trade = ""
    if kept is not None:
        header += "<th>optimum for δ, bearings as built</th><th>change</th>"
        where += f", bearing {int(kept['bearing'])} with the second"
        change = _change(float(before["delta"]), float(kept["delta"]))
        held = (
            f" Held to the bearing load as built ({number(before['max_bearing_load'])} N at most: "
            "<code>mc.optimize_counterweights(max_bearing_load=…)</code>, the last two columns)"
        )
        trade = (
            f"{held}, no counterweights make δ smaller than as built: the counterweights as built are the best for δ "
            "that the bearings allow."
            if change == "unchanged" or float(kept["delta"]) >= float(before["delta"])
            else f"{held}, the least δ is {_delta(kept['delta'])} ({change} against as built; the unconstrained "
            f"optimum reaches {_delta(after['delta'])})."
        )
    return f"""
<p>What the optimum counterweights do at {results.rpm:g} rpm (constant speed) to the frame and the bearings: the
largest magnitude the first order's shaking force and moment reach over a cycle (forward + backward,
<code>mc.shaking_forces</code>) and the largest load of any main bearing over a working cycle, gravity included
({where}; <code>mc.bearing_loads</code>). {counterweight_forces_sentence(forces)}{trade}</p>
<table><tr><th></th>{header}</tr>{body}</table>"""


def design_html(results: DesignResults, figures: dict[str, str]) -> str:
    """The report's "What to change" section: the firing orders, the torsional vibration
    (where the machine has a shaft; its Campbell diagram is ``figures["design_campbell"]``)
    and the counterweights."""
    torsion = (
        "" if results.resonances is None else torsion_html(results.machine, results.rpm, results.resonances, figures)
    )
    campbell = "" if results.resonances is None else ", design_campbell.csv"
    return f"""
<h2>What to change</h2>
<p>Two changes that keep the machine's cylinders and flywheel: another firing order (four-stroke: another
camshaft; two-stroke: the crank's throws rearranged) and other counterweights, each judged by δ with gravity at
the machine's speed and by what the frame, the bearings and the shaft feel.</p>
{_firing_html(results)}
{torsion}
{_counterweight_html(results)}
<p class="note">Data: design_firing_orders.csv, design_counterweights.csv, design_counterweight_forces.csv{campbell}</p>
"""
