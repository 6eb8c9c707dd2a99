"""The report says what its numbers say (issue 26, item 7): every sentence of a trend or a
comparison is made from the data shown beside it, the map's colours cover its data without
painting a tiny change as saturated, labels read upright and log axes print plain numbers.

Oracles: mc.steady_state at the ends of the speed range, solved here, for the trend; the map's
own table (its CSV) for the colour limits; two machines whose trends go opposite ways (the
slow compressor, whose gravity effect grows with the speed, and the same machine without gas,
whose inertia torque alone grows as n², so that gravity's share falls)."""

from __future__ import annotations

import re

import matplotlib
import numpy as np
import pytest

import multicrank as mc
from multicrank.presets import MACHINES
from multicrank.report import ReportSettings
from multicrank.report.motion import gravity_map_figure, motion_html, motion_results, speed_range_figure
from multicrank.report.plotting import symmetric_limit

matplotlib.use("Agg")

FIGURES = {name: "" for name in ("motion_speed", "motion_torques", "motion_speed_range", "motion_gravity_map",
                                 "motion_orders")}  # fmt: skip


def without_gas(machine: mc.Machine) -> mc.Machine:
    cylinders = [c.replace(pressure=None, pressure_crank_end=None) for c in machine.cylinders]
    return machine.replace(cylinders=cylinders, name=f"{machine.name} without gas")


COMPRESSOR = MACHINES["slow-compressor"]
MACHINES_OF_OPPOSITE_TRENDS = [COMPRESSOR, without_gas(COMPRESSOR)]


@pytest.fixture(scope="module", params=MACHINES_OF_OPPOSITE_TRENDS, ids=lambda m: m.name)
def case(request):
    machine = request.param
    results = motion_results(ReportSettings(machine=machine, gravity_map_points=5), speeds=5)
    return machine, results, motion_html(results, machine, FIGURES, 1 / 3000)


def effect_at(machine: mc.Machine, rpm: float) -> float:
    """Gravity's effect on δ [%] by two steady states solved here."""
    with_gravity = mc.steady_state(machine, rpm=rpm)
    without = mc.steady_state(machine, rpm=rpm, gravity=False)
    return 100 * (with_gravity.delta / without.delta - 1)


def test_the_speed_trend_says_what_the_numbers_say(case):
    machine, _, page = case
    low, high = machine.rpm_range
    first, last = effect_at(machine, low), effect_at(machine, high)
    grows = abs(last) > abs(first)
    assert grows == (machine is COMPRESSOR)  # the two machines do go opposite ways
    word, where = ("grows", "high") if grows else ("falls", "low")
    assert f"Gravity's effect on δ {word} with the speed, from {first:+.3g} % at {low:.4g} rpm to {last:+.3g} %" in page
    assert f"it matters most at {where} speed" in page
    other = "low" if grows else "high"
    assert f"matters most at {other} speed" not in page


def test_the_map_caption_says_which_axis_moves_gravitys_effect(case):
    _, results, page = case
    effect = 100 * results.gravity_map.pivot(index="shaft_inertia", columns="rpm", values="gravity_effect").to_numpy()
    along_inertia = np.max(np.ptp(effect, axis=0))  # one speed, every flywheel
    along_speed = np.max(np.ptp(effect, axis=1))  # one flywheel, every speed
    assert f"at most {along_inertia:.3g} percentage points over the flywheels" in page
    assert f"up to {along_speed:.3g} over the speeds" in page
    if along_speed > 2 * along_inertia:
        assert "the speed decides it far more than the flywheel" in page
    assert "varies little along the inertia axis" not in page


def test_the_neglected_region_is_said_with_its_exact_effect(case):
    _, results, page = case
    frame = results.gravity_map
    below = frame[frame["delta_g"] < 1 / 3000]
    if len(below):
        values = 100 * below["gravity_effect"]
        assert f"({len(below)} of {len(frame)} variants), gravity changes δ by {values.min():+.3g}" in page


@pytest.mark.parametrize("name", ["slow-compressor", "inline-4"])
def test_the_map_colours_cover_the_data_and_tiny_changes_stay_pale(name):
    machine = MACHINES[name]
    results = motion_results(ReportSettings(machine=machine, gravity_map_points=5), speeds=2)
    fig, frame = gravity_map_figure(results, machine, 1 / 3000)
    largest = float(np.abs(100 * frame["gravity_effect"]).max())
    filled = next(c for c in fig.axes[0].collections if hasattr(c, "levels") and len(c.levels) > 10)
    limit = filled.norm.vmax
    assert filled.norm.vmin == -limit and limit >= largest
    assert min(filled.levels) <= -largest and max(filled.levels) >= largest  # every value has a colour
    bar = fig.axes[1]
    ticks = bar.get_yticks()
    # The scale is labelled to its ends.
    assert max(ticks) == pytest.approx(limit) and min(ticks) == pytest.approx(-limit)
    if largest < 0.5:  # the in-line four: a change below half a percent
        assert limit >= 1.0 and largest / limit < 0.5  # pale, not saturated
    for text in fig.axes[0].texts:  # the level labels
        assert -80 <= text.get_rotation() % 360 <= 100 or text.get_rotation() % 360 >= 280, text.get_text()
    matplotlib.pyplot.close(fig)


@pytest.mark.parametrize(("largest", "floor", "limit"), [(31.3, 1.0, 40.0), (0.02, 1.0, 1.0), (24.0, 1.0, 25.0),
                                                          (30.0, 1.0, 30.0), (0.0, 1.0, 1.0)])  # fmt: skip
def test_symmetric_limit(largest, floor, limit):
    assert symmetric_limit(largest, floor) == limit


def test_log_speed_axes_print_plain_numbers():
    results = motion_results(ReportSettings(machine=COMPRESSOR, gravity_map_points=2), speeds=3)
    for fig, axis in (
        (speed_range_figure(results)[0], "x"),
        (gravity_map_figure(results, COMPRESSOR, 1 / 3000)[0], "y"),
    ):
        fig.canvas.draw()
        ax = fig.axes[0]
        labels = [t.get_text() for t in (ax.get_xticklabels() if axis == "x" else ax.get_yticklabels())]
        shown = [t for t in labels if t]
        assert len(shown) >= 3, labels
        assert all(re.fullmatch(r"\d+(\.\d+)?", t) for t in shown), labels  # "60", not "6×10¹"
        matplotlib.pyplot.close(fig)
