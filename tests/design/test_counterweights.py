"""mc.optimize_counterweights: no worse than the best point of a dense grid evaluated by
mc.motion_sweep, its objective that of steady_state of the optimised machine, reproducible,
the machine as given never beaten by its own result, and bad input refused by name."""

from __future__ import annotations

import math

import numpy as np
import pytest

import multicrank as mc

COMPRESSOR = mc.presets.MACHINES["slow-compressor"]  # one throw
TWIN = mc.presets.MACHINES["marine-2t-twin"]  # two opposed throws
INLINE_4 = mc.presets.MACHINES["inline-4"]


def moment(machine: mc.Machine, j: int) -> float:
    c = machine.cylinders[j]
    return c.counterweight_mass * (c.counterweight_radius or c.crank_radius)


def test_one_throw_beats_a_dense_grid_and_is_its_machine():
    best = mc.optimize_counterweights(COMPRESSOR)
    assert best.throws == ((0,),)
    low, high = (
        0.0,
        2
        * (
            COMPRESSOR.cylinders[0].crank_mass * COMPRESSOR.cylinders[0].crank_cg_radius
            + (COMPRESSOR.cylinders[0].rod_mass + COMPRESSOR.cylinders[0].piston_mass)
            * COMPRESSOR.cylinders[0].crank_radius
        ),
    )
    radius = COMPRESSOR.cylinders[0].counterweight_radius
    grid = mc.MachineGrid(COMPRESSOR, **{"counterweight_mass[0]": np.linspace(low, high, 401) / radius})
    dense = mc.motion_sweep(COMPRESSOR, grid, outputs="delta")
    assert best.objective <= dense["delta"].min() * (1 + 1e-12)
    assert best.objective < best.objective_before
    # The objective is the optimised machine's steady state, and its counterweight is the moment.
    state = mc.steady_state(best.machine)
    assert best.objective == best.delta == state.delta
    assert best.objective_before == best.delta_before == mc.steady_state(COMPRESSOR).delta
    assert moment(best.machine, 0) == pytest.approx(best.counterweights[0], rel=1e-12)
    assert best.counterweights_before[0] == pytest.approx(moment(COMPRESSOR, 0), rel=1e-12)
    frame = best.to_frame()
    assert list(frame.columns) == ["throw", "cylinders", "angle_deg", "counterweight_before", "counterweight"]
    assert frame["angle_deg"].iloc[0] == pytest.approx(90.0)
    assert 0 < best.improvement < 1 and best.success and best.nfev > best.nit


def test_two_throws_beat_a_dense_grid():
    bounds = (0.0, 12.0)
    best = mc.optimize_counterweights(TWIN, bounds=bounds)
    assert best.throws == ((0,), (1,))
    radii = [c.counterweight_radius for c in TWIN.cylinders]
    axis = np.linspace(*bounds, 41)
    grid = mc.MachineGrid(TWIN, **{"counterweight_mass[0]": axis / radii[0], "counterweight_mass[1]": axis / radii[1]})
    dense = mc.motion_sweep(TWIN, grid, outputs="delta")
    assert best.objective <= dense["delta"].min() * (1 + 1e-12)
    assert best.objective <= best.objective_before
    assert best.objective == mc.steady_state(best.machine).delta


def test_the_gravity_effect_and_the_speed_range():
    effect = mc.optimize_counterweights(COMPRESSOR, objective="gravity_effect")
    assert effect.objective == abs(mc.steady_state(effect.machine).gravity_effect)
    assert effect.objective < 0.1 * effect.objective_before
    spread = mc.optimize_counterweights(COMPRESSOR, objective="delta_over_speed_range")
    speeds = np.linspace(*COMPRESSOR.rpm_range, 9)
    worst = max(mc.steady_state(spread.machine, rpm=n).delta for n in speeds)
    assert spread.objective == pytest.approx(worst, rel=1e-12)
    assert spread.objective_before == pytest.approx(max(mc.steady_state(COMPRESSOR, rpm=n).delta for n in speeds))
    assert spread.objective < spread.objective_before


def test_alike_counterweights_are_the_nearest_to_the_machine_as_given():
    # Only the resultant of the throws' moments acts: of the optimum's equals, the one least
    # changed from the machine as given. The in-line four's balanced counterweights are
    # already best for δ.
    best = mc.optimize_counterweights(INLINE_4, seed=3)
    assert best.objective <= best.objective_before
    np.testing.assert_allclose(best.counterweights, best.counterweights_before, rtol=1e-6)


def test_a_counterweight_at_radius_zero_has_no_moment_as_given():
    # Its mass sits on the axis: no first moment before; the optimum puts it at the crank radius.
    bare = TWIN.replace(
        cylinders=[c.replace(counterweight_mass=50.0, counterweight_radius=0.0) for c in TWIN.cylinders]
    )
    best = mc.optimize_counterweights(bare, bounds=(0.0, 12.0), maxiter=5)
    np.testing.assert_array_equal(best.counterweights_before, [0.0, 0.0])
    for j, moment_j in enumerate(best.counterweights):
        cylinder = best.machine.cylinders[j]
        assert cylinder.counterweight_radius == cylinder.crank_radius
        assert cylinder.counterweight_mass * cylinder.counterweight_radius == pytest.approx(moment_j, rel=1e-12)
    assert best.objective_before == mc.steady_state(bare).delta


def test_the_same_seed_gives_the_same_result():
    first = mc.optimize_counterweights(TWIN, seed=7, bounds=(0.0, 12.0))
    again = mc.optimize_counterweights(TWIN, seed=7, bounds=(0.0, 12.0))
    np.testing.assert_array_equal(first.counterweights, again.counterweights)
    assert first.objective == again.objective


def test_a_stalling_design_scores_infinity_not_nan():
    # At 20/min, counterweights above ~1500 kg·m make the compressor stall (rows of NaN δ).
    radius = COMPRESSOR.cylinders[0].counterweight_radius
    grid = mc.MachineGrid(COMPRESSOR, **{"counterweight_mass[0]": np.array([100.0, 1900.0]) / radius}, rpm=20.0)
    assert mc.motion_sweep(COMPRESSOR, grid, outputs="delta")["stalled"].tolist() == [False, True]
    best = mc.optimize_counterweights(COMPRESSOR, rpm=20.0, bounds=(0.0, 2000.0), maxiter=20)
    assert math.isfinite(best.objective)
    assert best.objective == mc.steady_state(best.machine, rpm=20.0).delta


@pytest.mark.parametrize(
    ("options", "match"),
    [
        ({"objective": "smoothness"}, "objective"),
        ({"bounds": (5.0, 1.0)}, "bounds"),
        ({"bounds": [(0.0, 1.0)] * 3}, "bounds"),
        ({"rpm": 0.0}, "rpm"),
        ({"seed": -1}, "seed"),
        ({"maxiter": 0}, "maxiter"),
    ],
)
def test_bad_input_is_named(options, match):
    with pytest.raises(mc.MechanismError, match=match):
        mc.optimize_counterweights(TWIN, **options)


def test_a_machine_without_speed_or_range_is_refused():
    with pytest.raises(mc.MechanismError, match="machine"):
        mc.optimize_counterweights("marine-2t-twin")
    bare = TWIN.replace(rpm=None, rpm_range=None)
    with pytest.raises(mc.MechanismError, match="rpm is required"):
        mc.optimize_counterweights(bare)
    with pytest.raises(mc.MechanismError, match="rpm_range"):
        mc.optimize_counterweights(bare, rpm=300.0, objective="delta_over_speed_range")
    massless = TWIN.replace(
        cylinders=[c.replace(crank_mass=0.0, rod_mass=0.0, piston_mass=0.0) for c in TWIN.cylinders]
    )
    with pytest.raises(mc.MechanismError, match="bounds is required"):
        mc.optimize_counterweights(massless)


def test_a_speed_at_which_no_counterweight_runs_is_a_stall_error_naming_rpm():
    """At 0.45/min the little one-cylinder machine stalls whatever its counterweight: SciPy's
    polish used to difference +∞ − +∞ (a RuntimeWarning, an error here) and could return NaN
    counterweights; now a StallError names the speed and the machine's own lowest speed."""
    sizes = {"crank_radius": 0.05, "rod_length": 0.2, "rod_cg": 0.05, "crank_cg_radius": 0.02}
    cylinder = mc.Cylinder(**sizes, piston_mass=1.0, rod_mass=1.0, crank_mass=1.0)
    machine = mc.Machine([cylinder], shaft_inertia=0.5, rpm=600.0)
    with pytest.raises(mc.StallError) as own:
        mc.steady_state(machine, rpm=0.45)
    with pytest.raises(mc.StallError, match=r"rpm = 0\.45") as caught:
        mc.optimize_counterweights(machine, rpm=0.45, maxiter=2)
    assert caught.value.min_rpm == own.value.min_rpm
    # The compressor at 4/min: also nothing within the default bounds runs.
    with pytest.raises(mc.StallError, match=r"rpm = 4\b"):
        mc.optimize_counterweights(COMPRESSOR, rpm=4.0, maxiter=5)


def test_counterweights_that_make_a_stalling_machine_run_are_found():
    """At 8/min the compressor as given stalls (it runs from 8.4/min), and a heavier
    counterweight makes it run: the result is that design, its δ that of steady_state, the
    machine as given scoring +∞ and its δ NaN."""
    with pytest.raises(mc.StallError):
        mc.steady_state(COMPRESSOR, rpm=8.0)
    best = mc.optimize_counterweights(COMPRESSOR, rpm=8.0, maxiter=30)
    assert math.isfinite(best.objective) and np.all(np.isfinite(best.counterweights))
    assert best.objective == mc.steady_state(best.machine, rpm=8.0).delta
    assert best.objective_before == math.inf and math.isnan(best.delta_before)
