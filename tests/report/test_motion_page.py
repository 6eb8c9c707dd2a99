"""The motion part's page and map as a reader meets them: the verdict beside the first table,
the torque orders without the rows that are 0, and the threshold δ_g on the "where gravity
matters" map as a labelled line (issue "Names and report")."""

from __future__ import annotations

import re

import matplotlib
import numpy as np
import pytest

import multicrank as mc
from multicrank.presets import MACHINES
from multicrank.report import DEFAULT_THRESHOLD, ReportSettings
from multicrank.report.motion import (
    LISTED_ORDERS,
    gravity_map_figure,
    motion_html,
    motion_results,
    threshold_curve,
)

matplotlib.use("Agg")

FIGURES = {name: "data:image/png;base64," for name in
           ("motion_speed", "motion_torques", "motion_speed_range", "motion_gravity_map", "motion_orders")}  # fmt: skip


def results(name: str, points: int = 5):
    settings = ReportSettings(machine=MACHINES[name], gravity_map_points=points)
    return settings, motion_results(settings)


def page(name: str) -> str:
    settings, found = results(name)
    return motion_html(found, settings.machine, FIGURES, settings.threshold)


@pytest.mark.parametrize("name", ["slow-compressor", "inline-6"])
def test_the_verdict_is_beside_the_first_table(name):
    """Right after the first table, before the flywheel's, with δ_g of the machine at its speed."""
    text = page(name)
    machine = MACHINES[name]
    delta_g = float(machine.engine(machine.rpm).speed_fluctuation())
    verdict = "may be neglected" if delta_g < DEFAULT_THRESHOLD else "may NOT be neglected"
    first_table = text.index("</table>")
    at = text.index("<b>Verdict:</b>")
    assert first_table < at < text.index("<h3>The flywheel</h3>")
    assert text[first_table:at].split() == ["</table>", "<p>"]  # nothing between them
    assert verdict in text[at : text.index("<h3>The flywheel</h3>")]
    assert f"δ<sub>g</sub> = {delta_g:.3g}" in text[at:]


def test_the_report_says_the_verdict_once_and_first(tmp_path):
    from multicrank.report import write_report

    compressor = MACHINES["slow-compressor"]
    settings = ReportSettings(machine=compressor, k_max=2, n_max=4, points=16, lambdas=4, gravity_map_points=3,
                              machines={compressor.name: compressor})  # fmt: skip
    written = write_report(tmp_path / "report", settings, progress=False).read_text(encoding="utf-8")
    assert written.count("<b>Verdict:</b>") == 1
    assert written.index("<b>Verdict:</b>") < written.index("<h3>The flywheel</h3>") < written.index("<h2>Forces")


def order_rows(text: str) -> list[list[float]]:
    table = text[text.index("<tr><th>order</th>") :]
    table = table[: table.index("</table>")]
    return [[float(cell) for cell in re.findall(r"<td>([^<]*)</td>", row)] for row in table.split("</tr>")[1:-1]]


@pytest.mark.parametrize("name", ["inline-6", "genset-v12", "slow-diesel-12", "inline-4", "slow-compressor"])
def test_the_orders_table_leaves_out_the_orders_that_are_0(name):
    """No row of zeros: the rows are the largest of torque_orders' orders that are not 0,
    at most LISTED_ORDERS, and the sentence says how many there are."""
    machine = MACHINES[name]
    orders = mc.torque_orders(machine, machine.rpm)
    amplitudes = orders[["gas_amplitude", "inertia_amplitude", "gravity_amplitude", "total_amplitude"]]
    nonzero = orders[(amplitudes > 1e-12 * float(amplitudes.to_numpy().max())).any(axis=1)]
    text = page(name)
    rows = order_rows(text)
    assert rows and all(any(value != 0 for value in row[1:]) for row in rows)
    expected = nonzero.sort_values("total_amplitude", ascending=False).head(LISTED_ORDERS)
    assert [row[0] for row in rows] == list(expected.index)
    if len(nonzero) <= LISTED_ORDERS:
        assert f"The {len(nonzero)} that are not 0, of the {len(orders)} orders" in text
    else:
        assert f"The {LISTED_ORDERS} largest" in text


def test_the_inline_six_lists_its_five_orders():
    """The textbook: an even-firing in-line six four-stroke has torque orders 3, 6, 9, … only
    (and the mean)."""
    assert sorted(row[0] for row in order_rows(page("inline-6"))) == [0.0, 3.0, 6.0, 9.0, 12.0]


def drawn(name: str):
    settings, found = results(name, points=7)
    fig, frame = gravity_map_figure(found, settings.machine, settings.threshold)
    fig.canvas.draw()
    return fig, frame


@pytest.mark.parametrize("name", ["slow-compressor", "marine-2t-twin", "inline-4"])
def test_the_threshold_is_a_labelled_line_on_the_map(name):
    """Where δ_g crosses the threshold on the map: a thick line along δ_g = 1/3000 — δ_g of the
    machine's variants there, computed afresh, is the threshold — and a label on the map
    that names it and points at it."""
    fig, _ = drawn(name)
    ax = fig.axes[0]
    (line,) = [line for line in ax.lines if line.get_linewidth() >= 2]
    speeds, inertias = line.get_data()
    assert len(speeds) >= 2
    machine = MACHINES[name]
    for rpm, inertia in zip(speeds[[0, len(speeds) // 2, -1]], inertias[[0, len(speeds) // 2, -1]], strict=True):
        variant = machine.replace(shaft_inertia=float(inertia))
        assert float(variant.engine(float(rpm)).speed_fluctuation()) == pytest.approx(DEFAULT_THRESHOLD, rel=1e-9)
    low, high = ax.get_ylim()
    assert low <= inertias.min() and inertias.max() <= high
    (label,) = [text for text in ax.texts if text.get_text() == "δ_g = 1/3000"]
    box = label.get_window_extent()
    frame_box = ax.get_window_extent()
    assert frame_box.x0 <= box.x0 and box.x1 <= frame_box.x1 and frame_box.y0 <= box.y0 and box.y1 <= frame_box.y1
    tip = ax.transData.transform(label.xy)
    assert np.min(np.hypot(*(ax.transData.transform(np.column_stack(line.get_data())) - tip).T)) < 1.0
    matplotlib.pyplot.close(fig)


def test_a_map_the_threshold_does_not_cross_says_on_which_side_it_lies():
    fig, frame = drawn("inline-6")
    assert frame["delta_g"].max() < DEFAULT_THRESHOLD
    ax = fig.axes[0]
    assert not [line for line in ax.lines if line.get_linewidth() >= 2]
    assert any(text.get_text().startswith("δ_g < 1/3000 everywhere on this map") for text in ax.texts)
    matplotlib.pyplot.close(fig)


def test_the_threshold_curve_is_delta_g_of_the_maps_rows():
    """threshold_curve's law δ_g = c/(I_w n²) holds on the map's own rows."""
    _, found = results("marine-2t-twin", points=4)
    frame = found.gravity_map
    speeds, inertias = threshold_curve(frame, DEFAULT_THRESHOLD)
    for _, row in frame.iterrows():
        at = np.interp(row["rpm"], speeds, inertias)
        assert row["delta_g"] * row["shaft_inertia"] == pytest.approx(DEFAULT_THRESHOLD * at, rel=1e-6)
