"""The report's "What to change" section: the machine's best firing orders and its counterweight
optimum, as the library computes them, on the page and as CSV, for the default machine (one
cylinder) and for a four-cylinder one."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import multicrank as mc
from multicrank.presets import DEFAULT_MACHINE_NAME, MACHINES
from multicrank.report.design import FIRING_ROWS, NEGLIGIBLE, DesignResults, firing_table
from multicrank.report.forces import number

SCRIPT = Path(sys.executable).with_name("multicrank")
#: The report's other parts on reduced settings: this file is about the design section.
SMALL = ["--k-max", "2", "--n-max", "4", "--points", "17", "--no-progress"]


def run_report(out: Path, *machine: str) -> Path:
    result = subprocess.run(
        [str(SCRIPT), "report", "--out", str(out), *machine, *SMALL], capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr
    return out


@pytest.fixture(scope="module")
def compressor(tmp_path_factory) -> Path:
    """The report of the default machine (no --machine: the slow compressor, one cylinder)."""
    return run_report(tmp_path_factory.mktemp("compressor"))


@pytest.fixture(scope="module")
def inline4(tmp_path_factory) -> Path:
    return run_report(tmp_path_factory.mktemp("inline4"), "--machine", "inline-4")


def read_csv(path: Path) -> pd.DataFrame:
    # Parsed by Python's float, exact on any pandas (before 3.0 its parser may be an ulp off).
    frame = pd.read_csv(path, dtype=str, keep_default_na=False)
    text = ("firing", "phases_deg", "fires_at_deg", "cylinders", "as_given", "stalled", "near_stall", "pareto", "major")
    text += ("in_range", "at_running_speed", "at_bound")
    numbers = [c for c in frame if c not in text]
    return frame.astype({c: float for c in numbers})


def section(out: Path) -> str:
    page = (out / "index.html").read_text(encoding="utf-8")
    assert page.index("What gravity does to this machine") < page.index("<h2>What to change</h2>")
    assert page.index("<h2>What to change</h2>") < page.index("<h2>The machine</h2>")
    return page[page.index("<h2>What to change</h2>") : page.index("<h2>The machine</h2>")]


def check_firing(out: Path, machine: mc.Machine) -> tuple[pd.DataFrame, pd.DataFrame, str]:
    """The firing-order CSV is the library's best rows, the machine's own marked; the page shows them."""
    expected = mc.firing_orders(machine)
    table = read_csv(out / "design_firing_orders.csv")
    assert list(table.columns) == [
        "rank",
        "firing",
        "as_given",
        "phases_deg",
        "fires_at_deg",
        "delta",
        "delta_without_gravity",
        "gravity_effect",
        "stalled",
        "near_stall",
        "largest_order",
        "largest_order_amplitude",
        "free_moment_1",
        "free_moment_2",
        "max_bearing_load",
        *(["torsional_major", "torsional_minor", "torsional_merit"] if machine.shaft is not None else []),
        "pareto",
    ]
    best = min(FIRING_ROWS, len(expected))
    assert table["rank"].tolist()[:best] == list(range(1, best + 1))
    rows = expected.iloc[table["rank"].astype(int) - 1]
    assert table["firing"].tolist() == rows["firing"].tolist()
    # every Pareto row is shown (these machines' fronts are short)
    assert set(table["rank"].astype(int) - 1) >= set(np.flatnonzero(expected["pareto"]))
    assert table["pareto"].tolist() == [str(p) for p in rows["pareto"]]
    numbers = ["delta", "delta_without_gravity", "gravity_effect", "largest_order", "largest_order_amplitude"]
    numbers += [
        c
        for c in (
            "free_moment_1",
            "free_moment_2",
            "max_bearing_load",
            "torsional_major",
            "torsional_minor",
            "torsional_merit",
        )
        if c in table
    ]
    for name in numbers:
        np.testing.assert_allclose(table[name], rows[name], rtol=1e-12, err_msg=name)
    phases = [np.radians([float(a) for a in text.split()]) for text in table["phases_deg"]]
    np.testing.assert_allclose(np.concatenate(phases), np.concatenate(rows["phases"].map(list).tolist()), atol=1e-12)
    own = table[table["as_given"] == "True"]
    assert len(own) == 1
    np.testing.assert_allclose(own["delta"], mc.steady_state(machine, rpm=machine.rpm).delta, rtol=1e-12)
    text = section(out)
    for r in table.itertuples():
        assert f"{r.delta:.5g}" in text and f"{r.delta_without_gravity:.5g}" in text
        assert f"<td>{number(r.max_bearing_load)}</td>" in text
    assert f"{own['firing'].iloc[0]} (as given)" in text
    return table, expected, text


def check_counterweights(out: Path, machine: mc.Machine) -> tuple[pd.DataFrame, object, str]:
    """The counterweight CSV is the optimum's table; the page has δ before and after, the
    improvement and whether it converged."""
    optimum = mc.optimize_counterweights(machine)
    table = read_csv(out / "design_counterweights.csv")
    expected = optimum.to_frame()
    assert list(table.columns) == [
        "throw",
        "cylinders",
        "angle_deg",
        "counterweight_before",
        "counterweight",
        "at_bound",
    ]
    assert table["cylinders"].tolist() == expected["cylinders"].astype(str).tolist()
    assert table["at_bound"].tolist() == [str(b) for b in optimum.at_bound]
    assert ("at a bound of the search" in section(out)) == any(optimum.at_bound)
    for name in ("throw", "angle_deg", "counterweight_before", "counterweight"):
        np.testing.assert_allclose(table[name], expected[name], rtol=1e-12, atol=1e-15, err_msg=name)
    np.testing.assert_allclose(table["counterweight_before"], optimum.counterweights_before, rtol=1e-12)
    np.testing.assert_allclose(table["counterweight"], optimum.counterweights, rtol=1e-12)
    text = section(out)
    assert f"{optimum.delta_before:.5g}" in text and f"{optimum.delta:.5g}" in text
    assert f"{100 * optimum.improvement:.3g} %" in text
    assert math.isclose(optimum.improvement, 1 - optimum.delta / optimum.delta_before, rel_tol=1e-9)
    for r in table.itertuples():
        assert f"{r.counterweight_before:.4g}" in text and f"{r.counterweight:.4g}" in text
    assert ("converged</th><td>yes" if optimum.success else "converged</th><td><b>no</b>") in text
    assert ("not worth changing for δ" in text) == (optimum.improvement < NEGLIGIBLE)
    return table, optimum, text


def test_design_section_of_the_default_machine(compressor):
    """One cylinder: one firing order, said so; one throw's counterweight."""
    machine = MACHINES[DEFAULT_MACHINE_NAME]
    assert len(machine) == 1
    table, expected, text = check_firing(compressor, machine)
    assert len(table) == 1 and table["as_given"].tolist() == ["True"] and expected.attrs["candidates"] == 1
    assert "A single cylinder has one firing order" in text
    weights, optimum, _ = check_counterweights(compressor, machine)
    assert len(weights) == 1 and weights["cylinders"].tolist() == ["1"]
    assert optimum.delta <= optimum.delta_before


def test_the_default_machine_s_shaft_gets_a_campbell_diagram(compressor):
    """The slow compressor carries a shaft: the section draws its Campbell diagram and lists the
    strongest resonances in the speed range, as mc.torsional_merit gives them."""
    machine = MACHINES[DEFAULT_MACHINE_NAME]
    assert machine.shaft is not None
    table = read_csv(compressor / "design_campbell.csv")
    expected = mc.torsional_merit(machine, modes=2, max_order=12)
    for column in (
        "mode",
        "order",
        "natural_frequency",
        "resonance_rpm",
        "vector_sum",
        "excitation",
        "modal_excitation",
    ):
        np.testing.assert_allclose(table[column], expected[column], rtol=1e-12, err_msg=column)
    low, high = machine.rpm_range
    inside = expected["resonance_rpm"].between(low, high)
    assert table["in_range"].tolist() == [str(v) for v in inside]
    assert (compressor / "design_campbell.png").stat().st_size > 10_000
    text = section(compressor)
    assert "<h3>Torsional vibration</h3>" in text and 'alt="Campbell diagram of the shaft"' in text
    strongest = expected[inside].sort_values("modal_excitation", ascending=False).iloc[0]
    assert f"<td>{strongest['resonance_rpm']:.4g}" in text
    # Its order 9 meets mode 1 at 119.8 1/min, the machine running at 120: pointed out.
    running = expected[expected["at_running_speed"]]
    assert [(int(m), float(o)) for m, o in zip(running["mode"], running["order"], strict=True)] == [(1, 9.0)]
    assert "A resonance at the running speed" in text and "mode 1, order 9 at 119.8 1/min" in text
    shown = text.count("(major)</td>")  # one cylinder: every order is major
    assert shown == min(8, int(inside.sum()))


def test_design_section_of_a_four_cylinder_machine(inline4):
    """inline-4: 8 phase assignments, all tried; the machine's own (1-3-4-2) is the best."""
    machine = MACHINES["inline-4"]
    table, expected, text = check_firing(inline4, machine)
    assert (expected.attrs["candidates"], expected.attrs["exhaustive"]) == (8, True)
    assert len(table) == 3 and table["as_given"].tolist() == ["True", "False", "False"]
    assert table["firing"].iloc[0] == "1-3-4-2"
    # By hand: 1-3-4-2 evenly, so cylinders 1, 2, 3, 4 fire at 0°, 540°, 180°, 360°.
    assert table["fires_at_deg"].iloc[0] == "0 540 180 360"
    assert "<th>fires at [°], cylinder 1, 2, …</th>" in text and "<td>0 540 180 360</td>" in text
    assert "The crank allows 8 phase assignments" in text and f"{expected.attrs['distinct']} of them distinct" in text
    assert "every one of them was solved" in text and "rank 1 (marked)" in text
    weights, optimum, _ = check_counterweights(inline4, machine)
    assert len(weights) == len(optimum.throws)
    assert optimum.delta <= optimum.delta_before


def test_the_machines_own_row_is_shown_below_the_best_where_it_ranks_lower():
    """The machine's own row (the library's ``as_given``) is shown below the best rows where
    it ranks lower."""
    six = MACHINES["inline-6"]
    worst = mc.firing_orders(six)["machine"].iloc[-1]
    six = mc.firing_orders(worst)
    last = int(np.flatnonzero(six["as_given"])[0])
    assert last >= FIRING_ROWS
    machine = six["machine"].iloc[last]
    shown = firing_table(DesignResults(machine=machine, rpm=machine.rpm, firing=six, own=last, optimum=None))
    # the best three, the rest of the Pareto front (up to ten rows in all), then the machine's own
    front = [int(i) for i in np.flatnonzero(six["pareto"]) if i >= FIRING_ROWS][: 10 - FIRING_ROWS]
    rows = [*range(FIRING_ROWS), *front, *([] if last in front else [last])]
    assert shown["rank"].tolist() == [i + 1 for i in rows]
    assert shown["as_given"].tolist() == [i == last for i in rows]
    assert shown["firing"].tolist() == six["firing"].iloc[rows].tolist()
    np.testing.assert_allclose(shown["delta"], six["delta"].iloc[rows], rtol=0)


def test_two_rows_of_one_name_differ_by_when_each_cylinder_fires():
    """A four-stroke twin of two unlike cylinders on throws 180° apart: cylinder 2 fires 180°
    or 540° after cylinder 1 (by hand), two motions both named "1-2"; the table tells them
    apart."""
    from multicrank.report.design import _firing_html

    template = MACHINES["inline-4"].cylinders[0]
    cylinders = [template.replace(phase=0.0), template.replace(phase=math.pi, bore=0.07)]
    machine = mc.Machine(cylinders, shaft_inertia=0.2, strokes=4, rpm=3000)
    firing = mc.firing_orders(machine)
    assert firing["firing"].tolist() == ["1-2", "1-2"]
    own = int(np.flatnonzero(firing["as_given"].to_numpy())[0])
    results = DesignResults(machine=machine, rpm=3000.0, firing=firing, own=own, optimum=None)
    table = firing_table(results)
    assert sorted(table["fires_at_deg"]) == ["0 180", "0 540"]
    assert table.loc[table["as_given"], "fires_at_deg"].tolist() == ["0 540"]  # α₂ = 180°: fires at −180° = 540°
    page = _firing_html(results)
    assert "<td>0 180</td>" in page and "<td>0 540</td>" in page
