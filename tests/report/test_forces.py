"""The report's "Forces on the frame and the bearings" section and, in "What to change", what
the counterweight optimum does to the frame and the bearings (issue 28, item 5).

Oracles: textbook facts of the slider crank that share no formula with the library — a single
centred slider crank shakes its frame at order 1 and at even orders only; a counterweight
turning with the crank adds a purely forward first-order force ΔC·ω² opposite the pin, so the
optimum's first-order force is |F_forward − ΔC·ω²| + F_backward; the in-line four has no first
order and a second-order vertical force acting at the middle of its crank — and, for the numbers
shown, the library's own public results (mc.shaking_forces, mc.bearing_loads with and without
gravity, mc.optimize_counterweights), which the section must show unchanged."""

from __future__ import annotations

import math
import re
from pathlib import Path

import matplotlib
import numpy as np
import pandas as pd
import pytest

import multicrank as mc
from multicrank.presets import MACHINES
from multicrank.report import ReportSettings, write_report
from multicrank.report.design import UNCHANGED, counterweight_forces, counterweight_forces_sentence
from multicrank.report.forces import (
    MAX_ORDER,
    ORDER_COLUMNS,
    balancing_sentence,
    bearing_polar_figure,
    forces_html,
    forces_results,
    free_orders_sentence,
    gravity_sentence,
    most_loaded_sentence,
    number,
)

matplotlib.use("Agg")

COMPRESSOR = MACHINES["slow-compressor"]
FIGURES = {"forces_bearing_loads": "data:image/png;base64,"}


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    """A small report of the default machine (the slow compressor, one cylinder)."""
    out = tmp_path_factory.mktemp("forces") / "report"
    settings = ReportSettings(machine=COMPRESSOR, k_max=2, n_max=4, points=16, lambdas=4, gravity_map_points=3,
                              machines={COMPRESSOR.name: COMPRESSOR})  # fmt: skip
    write_report(out, settings, progress=False)
    return out


def page_of(out: Path) -> str:
    return (out / "index.html").read_text(encoding="utf-8")


def forces_section(page: str) -> str:
    start = page.index("<h2>Forces on the frame and the bearings</h2>")
    assert page.index("What gravity does to this machine") < start < page.index("<h2>What to change</h2>")
    return page[start : page.index("<h2>What to change</h2>")]


def text_of(html: str) -> str:
    """The words of an HTML fragment, tags removed and spaces collapsed."""
    return re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", html))


def read_csv(path: Path) -> pd.DataFrame:
    # Parsed by Python's float, exact on any pandas (before 3.0 its parser may be an ulp off).
    frame = pd.read_csv(path, dtype=str, keep_default_na=False)
    return frame.astype({c: float for c in frame if c != "design"})


def test_the_section_is_in_the_report_with_its_tables_and_figure(report):
    section = forces_section(page_of(report))
    assert section.count('<img src="data:image/png;base64,') == 1
    assert (report / "forces_bearing_loads.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for name in ("forces_orders", "forces_bearing_loads", "forces_bearing_summary", "design_counterweight_forces"):
        assert (report / f"{name}.csv").is_file(), name
    assert "<h3>Shaking forces and moments by order</h3>" in section and "<h3>Main-bearing loads</h3>" in section


def test_the_orders_are_the_librarys_and_a_centred_slider_crank_has_odd_orders_only_at_1(report):
    expected = mc.shaking_forces(COMPRESSOR, COMPRESSOR.rpm, max_order=MAX_ORDER).orders
    table = read_csv(report / "forces_orders.csv")
    assert table["order"].tolist() == list(range(1, MAX_ORDER + 1))
    for name in expected.columns:
        np.testing.assert_allclose(table[name], expected[name], rtol=1e-12, atol=1e-12, err_msg=name)
    section = forces_section(page_of(report))
    shown = section[section.index("<th>order</th>") : section.index("</table>")]
    rows = re.findall(r"<tr><td>(\d+)</td>((?:<td>[^<]*</td>)+)</tr>", shown)
    assert [int(order) for order, _ in rows] == list(range(1, MAX_ORDER + 1))
    for (order, cells), (_, row) in zip(rows, expected.iterrows(), strict=True):
        assert re.findall(r"<td>([^<]*)</td>", cells) == [number(row[name]) for name in ORDER_COLUMNS], order
    # The textbook: x(ψ) = r cos ψ + √(l² − r² sin² ψ) has only even harmonics past the first.
    said = text_of(section)
    assert "Orders 1, 2, 4, 6 and 8 leave free forces (none at orders 3, 5 and 7)" in said
    assert "no order up to 8 leaves a free moment about the engine centre" in said  # one cylinder: its centre
    first = expected.loc[1.0]
    largest = first["force_forward"] + first["force_backward"]
    assert largest == pytest.approx(first["force_vertical"], rel=1e-12)  # a vertical cylinder: along its axis
    assert (
        f"The largest free force is order 1's: it reaches {number(largest)} N over a cycle "
        f"(forward {number(first['force_forward'])} + backward {number(first['force_backward'])} N; "
        f"vertical amplitude {number(first['force_vertical'])}, horizontal {number(first['force_horizontal'])} N)."
    ) in said
    assert f"they can cancel only the forward first order: here {number(first['force_forward'])} N of force" in said
    second = expected.loc[2.0, "force_forward"] + expected.loc[2.0, "force_backward"]
    assert f"the backward first order ({number(first['force_backward'])} N) and orders 2, 4, 6 and 8 " in said
    assert f"(up to {number(second)} N)" in said


def test_the_bearing_summary_and_what_gravity_adds_are_the_librarys(report):
    loads = mc.bearing_loads(COMPRESSOR)
    without = mc.bearing_loads(COMPRESSOR, gravity=False)  # a pass of its own, g = 0
    largest = loads.magnitude.max(axis=1)
    adds = np.hypot(loads.horizontal - without.horizontal, loads.vertical - without.vertical).max(axis=1)
    table = read_csv(report / "forces_bearing_summary.csv")
    np.testing.assert_allclose(table["max"], largest, rtol=1e-12)
    np.testing.assert_allclose(table["max_without_gravity"], without.magnitude.max(axis=1), rtol=1e-12)
    np.testing.assert_allclose(table["gravity_adds"], adds, rtol=1e-9)
    np.testing.assert_allclose(table["phi_max_deg"], np.degrees(loads.phi[np.argmax(loads.magnitude, axis=1)]))
    np.testing.assert_allclose(table["position"], COMPRESSOR.bearings)
    said = text_of(forces_section(page_of(report)))
    most = int(np.argmax(adds))
    # one cylinder between two bearings: the two take the same load, to rounding, and are named both
    np.testing.assert_allclose(adds[0], adds[1], rtol=1e-9)
    assert (
        f"adds at most {number(adds[most])} N to a bearing's load, at bearings 0 and 1: "
        f"{100 * adds[most] / largest[most]:.3g} % of their largest load, {number(largest[most])} N each."
    ) in said
    change = 100 * (largest.max() / without.magnitude.max() - 1)
    assert (
        f"{number(largest.max())} N with gravity and {number(without.magnitude.max())} N without ({change:+.3g} %)"
        in said
    )
    curves = read_csv(report / "forces_bearing_loads.csv")
    assert len(curves) == loads.vertical.size
    np.testing.assert_allclose(curves["vertical"], loads.vertical.ravel(), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(curves["horizontal_without_gravity"], without.horizontal.ravel(), rtol=1e-12, atol=1e-9)


def test_the_counterweight_optimum_before_and_after(report):
    """The slow compressor's optimum for δ is a sevenfold counterweight: its first-order force
    is the textbook's |F_forward − ΔC·ω²| + F_backward, its largest bearing load its machine's
    own, and the page says plainly that it makes the bearing load larger."""
    optimum = mc.optimize_counterweights(COMPRESSOR)
    after = optimum.machine.cylinders[0]
    assert after.counterweight_mass * after.counterweight_radius == pytest.approx(optimum.counterweights[0])
    table = read_csv(report / "design_counterweight_forces.csv")
    first = mc.shaking_forces(COMPRESSOR, max_order=1).orders.loc[1.0]
    omega = COMPRESSOR.rpm * math.pi / 30
    added = (optimum.counterweights[0] - optimum.counterweights_before[0]) * omega**2
    textbook = abs(first["force_forward"] - added) + first["force_backward"]
    assert table["design"].tolist() == ["as given", "optimum", "bearings kept"]
    assert table["free_force_1"].tolist()[:2] == pytest.approx(
        [first["force_forward"] + first["force_backward"], textbook], rel=1e-9
    )
    # The third row: the least δ whose largest bearing load is no more than as built's.
    kept = mc.optimize_counterweights(COMPRESSOR, max_bearing_load=table["max_bearing_load"].iloc[0])
    machines = (optimum.machine_before, optimum.machine, kept.machine)
    for row, machine in zip(table.itertuples(), machines, strict=True):
        assert row.max_bearing_load == pytest.approx(mc.bearing_loads(machine).magnitude.max(), rel=1e-12)
        assert row.free_moment_1 == 0  # one cylinder: the engine centre is its own place
        assert row.delta == pytest.approx(mc.steady_state(machine).delta, rel=1e-9)
    assert table["max_bearing_load"].iloc[2] <= table["max_bearing_load"].iloc[0]
    before, now = table["max_bearing_load"].iloc[:2]
    assert now > before  # what the issue reports: only δ likes the overbalance
    design = page_of(report)[page_of(report).index("<h2>What to change</h2>") :]
    said = text_of(design)
    assert (
        f"The optimum for δ makes the largest main-bearing load over the cycle ({number(before)} → {number(now)} N, "
        f"{100 * (now / before - 1):+.3g} %) larger: δ does not see it"
    ) in said
    old, new = table["free_force_1"].iloc[:2]
    assert f"It makes the first-order free force ({number(old)} → {number(new)} N, " in said
    assert f"<td>{number(before)}</td><td>{number(now)}</td><td>{100 * (now / before - 1):+.3g} %</td>" in design
    assert "the counterweights as built are the best for δ that the bearings allow" in said


def test_a_machine_without_a_free_first_order_says_so():
    """The in-line four: no first order (the textbook), so nothing for counterweights; its second
    order acts at the middle of the crank, the engine centre, so it leaves no moment there
    (and the page does not say a moment depends on the point: there is none)."""
    four = MACHINES["inline-4"]
    results = forces_results(ReportSettings(machine=four))
    orders = results.orders
    said = text_of(forces_html(results, FIGURES))
    assert "they can cancel only the forward first order: here there is none." in said
    assert "Orders 2, 4, 6 and 8 leave free forces (none at orders 1, 3, 5 and 7)" in said
    assert orders.loc[2.0, "moment_pitch"] == 0 and orders.loc[2.0, "force_vertical"] > 0
    assert "also leaves a free force, so its moment depends on the point" not in said
    compressor = text_of(forces_html(forces_results(ReportSettings(machine=COMPRESSOR)), FIGURES))
    assert "here there is none" not in compressor


def test_a_balanced_machine_needs_no_balance_shafts_and_an_unplaced_one_is_said():
    """The twelve-cylinder two-stroke with its cylinders taken off their places along the
    shaft: every order up to 8 cancels; the moments are 0 only because every cylinder is at
    z = 0, which is said."""
    placed = MACHINES["slow-diesel-12"]
    diesel = placed.replace(cylinders=[c.replace(axial_position=0.0) for c in placed.cylinders])
    results = forces_results(ReportSettings(machine=diesel))
    said = text_of(forces_html(results, FIGURES))
    assert "No order up to 8 leaves a free force: the cylinders' forces cancel" in said
    assert "Nothing else is free up to this order: no balance shafts are needed." in said
    assert "Every cylinder is at z = 0 (none is placed along the shaft)" in said
    assert "Every cylinder is at z = 0" not in text_of(forces_html(forces_results(ReportSettings()), FIGURES))


def test_the_sentences_follow_the_numbers():
    """Sentences made from tables whose numbers go another way read another way."""
    orders = pd.DataFrame(0.0, index=pd.Index([1.0, 2.0, 3.0], name="order"), columns=list(ORDER_COLUMNS))
    orders.loc[1.0, ["moment_forward", "moment_backward"]] = [40.0, 10.0]
    assert free_orders_sentence(orders) == (
        "No order up to 3 leaves a free force: the cylinders' forces cancel; order 1 leaves a free moment about "
        "the engine centre (none at orders 2 and 3)."
    )
    assert "here 40 N·m of moment" in balancing_sentence(orders)
    assert "The rest — the backward first order (10 N·m) — needs balance shafts" in balancing_sentence(orders)
    summary = pd.DataFrame({"max": [1000.0, 100.0], "max_without_gravity": [990.0, 50.0], "gravity_adds": [20.0, 50.0]})
    sentence = gravity_sentence(summary)
    assert "adds at most 50 N to a bearing's load, at bearing 1: 50 % of its largest load, 100 N." in sentence
    assert "Relative to its own load" not in sentence  # the same bearing
    summary["gravity_adds"] = [60.0, 50.0]
    sentence = gravity_sentence(summary)
    assert (
        "at bearing 0: 6 % of its largest load, 1,000 N. Relative to its own load it adds most at bearing 1" in sentence
    )
    assert "1,000 N with gravity and 990 N without (+1.01 %)" in sentence


def test_the_optimum_sentence_says_what_changed():
    rows = {"free_force_1": [100.0, 100.0], "free_moment_1": [0.0, 0.0], "max_bearing_load": [500.0, 500.0]}
    same = pd.DataFrame({"design": ["as given", "optimum"], **rows, "bearing": [0, 0]})
    assert counterweight_forces_sentence(same) == (
        "The optimum leaves the first-order force and moment and the largest bearing load as they are."
    )
    worse = same.copy()
    worse.loc[1, ["free_moment_1", "max_bearing_load"]] = [30.0, 400.0]
    sentence = counterweight_forces_sentence(worse)
    assert sentence.startswith(
        "<b>The optimum for δ makes the first-order free moment about the engine centre (0 → 30 N·m) "
        "larger</b>: "
        "δ does not see it; check that the frame's mounts can take it"
    )
    assert sentence.endswith("It makes the largest main-bearing load over the cycle (500 → 400 N, -20 %) smaller.")
    tiny = same.copy()
    tiny.loc[1, "max_bearing_load"] = 500.0 * (1 + UNCHANGED / 2)
    assert "as they are" in counterweight_forces_sentence(tiny)


def test_one_polar_panel_per_bearing():
    six = MACHINES["inline-6"]
    results = forces_results(ReportSettings(machine=six))
    fig, table = bearing_polar_figure(results)
    shown = [ax for ax in fig.axes if ax.axison]
    assert len(shown) == len(six.bearings) == 7
    loads = mc.bearing_loads(six)
    for bearing, ax in enumerate(shown):
        assert ax.get_title().startswith(f"bearing {bearing}, z = ")
        curve = ax.lines[1]  # polar's curve, drawn over the dashed g = 0 one
        np.testing.assert_allclose(curve.get_ydata(), loads.vertical[bearing], rtol=1e-12, atol=1e-9)
        largest = loads.magnitude[bearing].max()
        assert any(f"max {number(largest)} N" in t.get_text() for t in ax.texts)
        low, high = ax.get_xlim()
        assert -low == high >= largest
    assert sorted(set(table["bearing"])) == list(range(7))
    matplotlib.pyplot.close(fig)


def test_counterweight_forces_of_an_unchanged_optimum():
    """The in-line four's optimum keeps its counterweights: before and after are alike."""
    four = MACHINES["inline-4"]
    optimum = mc.optimize_counterweights(four)
    np.testing.assert_array_equal(optimum.counterweights, optimum.counterweights_before)
    forces = counterweight_forces(optimum, four.rpm)
    assert forces["free_force_1"].tolist() == [0.0, 0.0]  # the textbook: no first order
    assert forces["max_bearing_load"].iloc[0] == forces["max_bearing_load"].iloc[1]
    assert "as they are" in counterweight_forces_sentence(forces)


def test_bearings_alike_are_all_named():
    """The most loaded bearing, and where gravity adds most: every bearing within 1e-9 of the
    largest is named, as a symmetric crank's mirrored bearings are alike to rounding."""
    summary = pd.DataFrame(
        {"max": [1000.0, 1000.0 * (1 + 1e-12), 400.0], "phi_max": np.radians([30.0, 210.0, 90.0]),
         "max_without_gravity": [990.0, 990.0, 300.0], "gravity_adds": [20.0, 20.0, 5.0]},
    )  # fmt: skip
    assert most_loaded_sentence(summary) == (
        "The most loaded bearings, alike, are bearings 0 and 1: 1,000 N each, at φ = 30° and 210°."
    )
    assert "adds at most 20 N to a bearing's load, at bearings 0 and 1: 2 % of their largest load, 1,000 N each." in (
        gravity_sentence(summary)
    )
    summary.loc[1, "max"] = 999.0  # 1e-3 apart: no longer alike
    assert most_loaded_sentence(summary) == "The most loaded bearing is bearing 0: 1,000 N at φ = 30°."
    summary.loc[[0, 1, 2], "max"] = [1000.0, 999.0, 1000.0 * (1 - 1e-10)]
    assert most_loaded_sentence(summary).startswith("The most loaded bearings, alike, are bearings 0 and 2: ")


@pytest.mark.parametrize(
    ("name", "named"), [("slow-compressor", "bearings 0 and 1"), ("inline-6", "bearings 1, 2, 4 and 5")]
)
def test_the_section_names_every_most_loaded_bearing(name, named):
    """The one-cylinder compressor's two bearings take the same load, as do the six's four
    bearings next to its middle pairs of throws: the section names them all, not bearing 0 alone."""
    machine = MACHINES[name]
    said = text_of(forces_html(forces_results(ReportSettings(machine=machine)), FIGURES))
    summary = mc.bearing_loads(machine).summary
    assert f"The most loaded bearings, alike, are {named}: {number(summary['max'].max())} N each" in said
    assert "The most loaded bearing is" not in said


@pytest.mark.parametrize("name", ["slow-compressor", "inline-6"])
def test_the_figures_title_stands_clear_of_the_panels_titles(name):
    """The bearing-load figure's title sits at least 8 pt above every panel's title (it sat on
    them: -2 pt for the compressor, 3 pt for the six)."""
    fig, _ = bearing_polar_figure(forces_results(ReportSettings(machine=MACHINES[name])))
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    title = fig.get_suptitle()
    assert title.startswith("load each main bearing receives")
    bottom = next(t for t in fig.texts if t.get_text() == title).get_window_extent(renderer).y0
    panels = [ax for ax in fig.axes if ax.axison]
    top_row = max(ax.get_position().y1 for ax in panels)
    for ax in panels:
        if ax.get_position().y1 == top_row:
            gap = (bottom - ax.title.get_window_extent(renderer).y1) * 72 / fig.dpi
            assert gap >= 8, (ax.get_title(), gap)
    matplotlib.pyplot.close(fig)
