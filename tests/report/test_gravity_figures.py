"""The gravity part's figures mark the threshold δ_g where a reader looks for it: the
significance map over k and λ on its colour bar, with its value, and the title and the
speed-range figure write it as 1/3000 (issue "Names and report")."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest

from multicrank.presets import MACHINES
from multicrank.report import DEFAULT_THRESHOLD, ReportSettings
from multicrank.report.gravity_figures import machines_figure, significance_map
from multicrank.report.plotting import threshold_text

matplotlib.use("Agg")


def test_the_threshold_is_written_as_a_fraction_where_it_is_one():
    assert threshold_text(DEFAULT_THRESHOLD) == "1/3000"
    assert threshold_text(1 / 300) == "1/300"
    assert threshold_text(4e-4) == "1/2500"
    assert threshold_text(3.7e-4) == "0.00037"
    assert threshold_text(2.0) == "2"


@pytest.mark.parametrize("threshold", [DEFAULT_THRESHOLD, 3.7e-4])
def test_the_significance_maps_colour_bar_marks_the_threshold(threshold):
    settings = ReportSettings(machine=MACHINES["slow-compressor"], k_max=4, threshold=threshold)
    fig, _ = significance_map(settings)
    fig.canvas.draw()
    bar = fig.axes[-1]
    marks = [line for line in bar.lines if np.allclose(line.get_ydata(), math.log10(threshold))]
    assert marks and marks[0].get_linewidth() >= 2
    (label,) = [text for text in bar.texts if threshold_text(threshold) in text.get_text()]
    assert label.xy[1] == pytest.approx(math.log10(threshold))
    # beside the bar, clear of the right-hand map
    right_map = fig.axes[1].get_window_extent()
    assert label.get_window_extent().x0 > right_map.x1
    assert threshold_text(threshold) in fig.get_suptitle()
    matplotlib.pyplot.close(fig)


def test_the_speed_range_figure_names_the_threshold():
    settings = ReportSettings(machines={name: MACHINES[name] for name in ("slow-compressor", "inline-4")})
    fig, _ = machines_figure(settings)
    assert any(text.get_text().startswith("threshold 1/3000: below") for text in fig.axes[0].texts)
    matplotlib.pyplot.close(fig)
