"""The gallery's examples (docs/gallery/plot_*.py) run with their short settings
(MULTICRANK_DOCS_FAST=1, as the documentation build in CI runs them), draw their figures,
and compute what their text says."""

from __future__ import annotations

import functools
import math
import runpy
from pathlib import Path

import numpy as np
import pytest

import multicrank as mc

GALLERY = Path(__file__).resolve().parents[2] / "docs" / "gallery"
SCRIPTS = sorted(path.name for path in GALLERY.glob("plot_*.py"))


@functools.cache
def _run(name: str) -> tuple[dict, list[tuple[int, int]]]:
    """The script's namespace after a run, and (width, height) in pixels of each figure it drew."""
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    drawn: list[tuple[int, int]] = []

    def show() -> None:  # as sphinx-gallery does: keep the figures, show nothing
        for number in plt.get_fignums():
            figure = plt.figure(number)
            figure.canvas.draw()
            drawn.append(figure.canvas.get_width_height())
            plt.close(figure)

    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("MULTICRANK_DOCS_FAST", "1")
        patch.setattr(plt, "show", show)
        try:
            namespace = runpy.run_path(str(GALLERY / name), run_name="__gallery__")
        finally:
            plt.close("all")
    return namespace, drawn


def run(name: str) -> dict:
    if name in ("plot_07_sweep_xarray.py", "plot_08_where_gravity_matters.py"):
        pytest.importorskip("xarray")
    return _run(name)[0]


def test_the_gallery_has_its_examples():
    assert len(SCRIPTS) == 12
    for name in SCRIPTS:
        text = (GALLERY / name).read_text(encoding="utf-8")
        assert text.startswith('"""\n'), f"{name}: the module docstring (title and summary) comes first"
        assert "# %%" in text, f"{name}: cells"


@pytest.mark.parametrize("name", SCRIPTS)
def test_every_example_runs_and_draws(name):
    run(name)
    figures = _run(name)[1]
    assert figures, f"{name} drew no figure"
    for width, height in figures:  # readable at the page's width, not a poster
        assert 600 <= width <= 1000 and height <= 800


def test_gravity_significance_red_rows():
    space = run("plot_01_gravity_significance.py")
    above = {
        (strokes, int(k))
        for strokes, values in space["delta_g"].items()
        for k, row in zip(space["cranks"], values, strict=True)
        if row.max() >= space["THRESHOLD"]
    }
    assert above == {(2, 1), (4, 1), (2, 2), (4, 2), (4, 4)}  # the rows the text names
    unit = space["unit"]
    assert np.allclose(space["delta_g"][2][0], 2 * (unit["u1"] + unit["u2"]), rtol=1e-12)
    assert 0.1 < space["crossing"] < 0.15


def test_compressor_gravity_raises_delta():
    space = run("plot_02_compressor_speed.py")
    with_gravity, without = space["with_gravity"], space["without_gravity"]
    assert with_gravity.delta > without.delta
    assert math.isclose(with_gravity.delta_without_gravity, without.delta, rel_tol=1e-9)
    assert with_gravity.mean_load_torque < 0  # the motor drives the compressor
    assert math.pi < with_gravity.phi_min < 2 * math.pi and without.phi_min < math.pi  # the dip that moves


def test_flywheel_with_and_without_gravity():
    space = run("plot_03_flywheel.py")
    flywheel = space["flywheel"]
    assert flywheel.shaft_inertia > flywheel.shaft_inertia_without_gravity
    # "right to first order, off by a fraction of the order of δ … leaving gravity out errs by far more"
    assert abs(flywheel.textbook_error) < flywheel.delta
    assert abs(flywheel.textbook_error) < 0.1 * (1 - flywheel.shaft_inertia_without_gravity / flywheel.shaft_inertia)
    assert np.all(np.diff(space["exact"]) < 0)  # less inertia for a larger δ
    assert 1 / 50 <= space["as_built"].delta <= 1 / 20


def test_startup_reaches_the_steady_state():
    space = run("plot_04_startup.py")
    result, steady = space["run"], space["steady"]
    assert not result.stalled
    assert result.rpm_history[-1] > 2 * result.rpm_history[0]  # from 300 rpm, on its way to 1500
    assert result.energy_drift < 1e-5
    assert math.isclose(space["last_mean"] * 30 / math.pi, steady.rpm, rel_tol=0.01)
    assert math.isclose(space["last_delta"], steady.delta, rel_tol=0.05)


def test_rundown_stalls_on_a_compression():
    space = run("plot_05_rundown.py")
    result = space["run"]
    assert result.stalled and result.omega[-1] == 0.0
    assert math.isclose(result.time[-1], result.stall_time)
    assert result.gas_torque[-1] < 0  # it stopped against the gas
    assert result.energy_drift < 1e-6
    assert max(space["forces"]) > 1e3  # one piston held by compressed air [N]


def test_v8_keeps_orders_4_8_12():
    space = run("plot_06_v8_orders.py")
    table = space["orders"]["v8-cross"]
    for part in ("gas", "inertia", "gravity"):
        amplitude = table[f"{part}_amplitude"]
        moving = amplitude[amplitude.index > 0]
        assert list(moving[moving > 1e-12 * moving.max()].index) == [4.0, 8.0, 12.0]
    assert (space["difference"] < 1e-12).all()  # flat-plane and cross-plane alike


def test_sweep_to_xarray_matches_speed_fluctuation():
    import multicrank as mc

    space = run("plot_07_sweep_xarray.py")
    data, unit = space["data"], space["unit"]
    cell = data["energy_range"].sel(cranks=2, strokes=2, inclination=90.0).isel(crank_ratio=-1)
    expected = mc.speed_fluctuation(
        crank_ratio=float(cell["crank_ratio"]),
        inclination=math.pi / 2,
        u1=unit["u1"],
        u2=unit["u2"],
        phases=mc.crank_phases(2, 2),
    )
    assert math.isclose(float(cell), float(expected), rel_tol=1e-12)


def test_where_gravity_matters_says_what_the_map_shows():
    import multicrank as mc

    space = run("plot_08_where_gravity_matters.py")
    effect, low, high = space["effect"], space["low"], space["high"]  # per cent
    assert not space["result"]["stalled"].any()
    assert float(effect.min()) > 0  # "red, never blue"
    built_for = effect.sel(rpm=slice(low, high))
    assert 15 <= float(built_for.min()) and float(built_for.max()) <= 33  # "15 to 31 %"
    # "under 5 % only at about 650 rpm", for every flywheel (the contours are vertical there)
    speeds = effect["rpm"].values
    for row in effect.values:
        first_below = speeds[np.argmax(row < 5.0)]
        assert row[-1] < 5.0 and 550 < first_below < 800
        assert np.all(row[speeds >= first_below] < 5.0)
    assert 200 < space["peak"] < 330  # "peaks near 270 rpm"
    as_built = space["as_built"]
    assert round(1 / as_built.delta) == 34 and math.isclose(as_built.gravity_effect, 0.18, abs_tol=0.005)
    row = space["result"].query("shaft_inertia == shaft_inertia.max()")  # a row is its steady state
    machine = space["compressor"].replace(shaft_inertia=2000.0)
    state = mc.steady_state(machine, rpm=row["rpm"].iloc[3])
    assert math.isclose(row["gravity_effect"].iloc[3], state.gravity_effect, rel_tol=1e-12)
    # the flywheel for 1/40: more with gravity everywhere; 15 % at 120 rpm, almost a quarter
    # too small near 300 rpm without it; it stops falling above about 450 rpm
    sized, extra = space["sized"], space["extra"]
    assert (extra > 0).all()
    at_120 = mc.flywheel_inertia(space["compressor"], delta=1 / 40, rpm=120)
    assert 0.14 < 1 - at_120.shaft_inertia_without_gravity / at_120.shaft_inertia < 0.16
    assert 0.22 < 1 - 1 / (1 + extra.max()) < 0.25
    assert 230 < sized["rpm"][extra.idxmax()] < 330
    assert 350 < space["cheapest"] < 600
    tail = sized["flywheel_inertia"][sized["rpm"] > 600]
    assert tail.between(35, 50).all()  # "levels off near 45 kg·m²"


def test_design_aid_says_what_its_figure_shows():
    import multicrank as mc

    space = run("plot_09_design_aid.py")
    table, best = space["table"], space["best"]
    # the six's even firing, as built, first; the worst eleven times rougher
    # (every one of the 32 apart: on the shaft with its damper and flywheel each drives the
    # half orders otherwise)
    assert table["firing"].iloc[0] == "1-5-3-6-2-4" and table.attrs["distinct"] == 32
    # "1-5-4-6-2-3, 1-2-3-6-5-4 and 1-2-4-6-5-3, the same motion on a rigid shaft ... load the
    # main bearings 9 % more"
    alike = ["1-5-4-6-2-3", "1-2-3-6-5-4", "1-2-4-6-5-3"]
    assert table["firing"].iloc[1:4].tolist() == alike and (table["delta"].iloc[1:4] == table["delta"].iloc[0]).all()
    assert all("+" in f for f in table["firing"].iloc[4:])
    more = table["max_bearing_load"].iloc[1:4] / table["max_bearing_load"].iloc[0] - 1
    assert ((0.085 < more) & (more < 0.095)).all()
    assert math.isclose(space["as_built"].delta, table["delta"].iloc[0], rel_tol=1e-9)
    assert 10 < space["gain"][0] < 12
    assert (table["gravity_effect"].abs() < 1e-7).all()  # "the same to 10⁻⁷"
    # the counterweight: flat without gravity; the optimum within 2 % of the first-order
    # balance, 14 % off δ, and the low point of the sweep with gravity
    swept = space["swept"]
    assert np.ptp(swept["delta_without_gravity"]) < 1e-9 * swept["delta_without_gravity"].max()
    assert abs(best.counterweights[0] / space["first_order"] - 1) < 0.02
    assert 0.14 < best.improvement < 0.15
    assert best.delta <= swept["delta"].min() * (1 + 1e-9)
    assert 0.18 < swept["delta"].max() / swept["delta"].min() - 1 < 0.22  # "by a fifth"
    state = mc.steady_state(best.machine)
    assert math.isclose(state.delta, best.delta, rel_tol=1e-9)


def test_inline_three_rocks_and_a_counterweight_takes_the_forward_part():
    space = run("plot_10_shaking_forces.py")
    orders, after, alone = space["orders"], space["after"], space["alone"]
    forces = ["force_vertical", "force_horizontal"]
    # "they add up to nothing ... only every third order survives ... (the 6th, 1.6 N)"
    assert (orders.loc[[1, 2, 4, 5], forces] == 0).all().all()
    assert (after.loc[[1, 2, 4, 5], forces] == 0).all().all()
    assert round(orders.loc[6, "force_vertical"], 1) == 1.6
    # "a couple of √3·a times one of them", of the first and the second order
    for n in (1, 2):
        expected = math.sqrt(3) * 0.094 * alone.loc[n, "force_vertical"]
        assert math.isclose(orders.loc[n, "moment_pitch"], expected, rel_tol=1e-12)
    # the numbers of the text (3000 rpm)
    assert round(orders.loc[1, "moment_forward"]) == 323
    assert round(orders.loc[1, "moment_backward"]) == 207
    assert round(orders.loc[1, "moment_pitch"]) == 530 and round(orders.loc[1, "moment_yaw"]) == 116
    assert round(orders.loc[2, "moment_forward"]) == 64 == round(orders.loc[2, "moment_backward"])
    assert round(space["heavier"].counterweight_mass - space["cylinder"].counterweight_mass, 2) == 0.57
    # the counterweight: the forward first order gone, pitch and yaw equal; the backward
    # first order and the second order untouched; the yaw grows to 207 N·m
    assert after.loc[1, "moment_forward"] <= 1e-12 * orders.loc[1, "moment_forward"]
    assert math.isclose(after.loc[1, "moment_pitch"], after.loc[1, "moment_yaw"], rel_tol=1e-9)
    assert math.isclose(after.loc[1, "moment_backward"], orders.loc[1, "moment_backward"], rel_tol=1e-12)
    assert (after.loc[2] - orders.loc[2]).abs().max() <= 1e-9 * orders.loc[2, "moment_pitch"]
    assert round(after.loc[1, "moment_yaw"]) == 207
    # "the second order's couple (129 N·m at most) is more than half the first order's"
    assert round(after.loc[2, "moment_pitch"]) == 129
    assert after.loc[2, "moment_pitch"] > after.loc[1, "moment_pitch"] / 2
    # the curves: the largest pitching moment over a revolution (every order at once)
    assert round(space["curves"]["moment_pitch"].abs().max()) == 578


def test_the_compressors_least_delta_counterweight_loads_its_bearings():
    space = run("plot_11_bearing_loads.py")
    built, least_free, best = space["as_built"], space["least_free"], space["best_delta"]
    swept = space["swept"]
    # "about seven times the built one, which is what mc.optimize_counterweights recommends"
    assert 6.5 < space["ratio"] < 7.0
    optimum = mc.optimize_counterweights(space["compressor"], seed=1)
    moment = optimum.counterweights[0] / space["cylinder"].counterweight_radius
    assert abs(moment - best["counterweight_mass"]) <= 2.5  # within the grid's step
    # "the free first-order force is least well before that"
    assert least_free["counterweight_mass"] < 0.75 * best["counterweight_mass"]
    # "the largest bearing load grows with every kilogram"
    assert (np.diff(swept["max_bearing_load"]) > 0).all()
    assert best["max_bearing_load"] > built["max_bearing_load"]
    # the rows are mc.bearing_loads' and mc.shaking_forces' of the machine as built
    summary = mc.bearing_loads(space["compressor"]).summary
    assert math.isclose(built["max_bearing_load"], summary["max"].max(), rel_tol=1e-9)
    first = mc.shaking_forces(space["compressor"]).orders.loc[1]
    free = first["force_forward"] + first["force_backward"]
    assert math.isclose(built["free_force_1"], free, rel_tol=1e-9)


def test_the_marine_six_trades_free_moments_for_torsional_merit():
    space = run("plot_12_torsional_merit.py")
    table, shaft = space["table"], space["shaft"]
    # "5! = 120 arrangements", 60 distinct (mirror images apart: their vector sums differ), one δ
    assert table.attrs["candidates"] == 120 and table.attrs["distinct"] == 60
    assert space["delta_spread"] < 1e-12
    # "first mode, at 2.3 Hz, meets the sixth order ... just below the speed range (23 rpm)"
    first = shaft.modes().natural_frequency[0]
    assert 2.3 < first < 2.4 and 22.5 < 60 * first / 6 < 25.0
    # "vanishes in two arrangements only, and those excite the shaft's minor orders about
    # twice to four times as much as the quietest one, which leaves some 15 MN·m"; "the major
    # orders' part is the same in every row"
    zero = table[table["free_moment_1"] == 0]
    assert len(zero) == 2
    quietest = table["torsional_minor"].min()
    assert 1.5 < zero["torsional_minor"].min() / quietest and zero["torsional_minor"].max() / quietest < 4
    assert 12e6 < table.loc[table["torsional_minor"].idxmin(), "free_moment_1"] < 18e6
    assert np.ptp(table["torsional_major"]) <= 1e-9 * table["torsional_major"].max()
    # the truck six: whole orders untouched, one major part for every row, the minor ones apart
    truck = space["truck_table"]
    assert np.ptp(truck["torsional_major"]) <= 1e-9 * truck["torsional_major"].max()
    assert np.ptp(truck["torsional_minor"]) > 0
    # the bank factor follows |2 cos(νΘ/2)| for every order drawn
    for order, values in space["factor"].items():
        np.testing.assert_allclose(values, np.abs(2 * np.cos(order * space["banks"] / 2)), atol=1e-9)
