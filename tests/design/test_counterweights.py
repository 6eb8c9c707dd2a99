"""mc.optimize_counterweights: no worse than the best point of a dense grid evaluated by
mc.motion_sweep, its objective that of steady_state of the optimised machine, reproducible,
the machine as given never beaten by its own result, and bad input refused by name. The
frame's objectives and constraints: limits kept (checked by mc.bearing_loads and
mc.shaking_forces of the returned machine), the first-order free force of one slider-crank
against the textbook's closed form, every criterion before and after that of the machines,
and a limit nothing meets refused by name."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import multicrank as mc

COMPRESSOR = mc.presets.MACHINES["slow-compressor"]  # one throw
TWIN = mc.presets.MACHINES["marine-2t-twin"]  # two opposed throws
INLINE_4 = mc.presets.MACHINES["inline-4"]
BOXER = mc.presets.MACHINES["boxer-compressor"]  # two opposed throws, apart along the shaft


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
    assert list(frame.columns) == [
        "throw",
        "cylinders",
        "angle_deg",
        "counterweight_before",
        "counterweight",
        "at_bound",
    ]
    assert best.at_bound == (False,) and not frame["at_bound"].any()
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
    # To rounding: the sweep gives a design that differs from another only in counterweights
    # that one's J and panels with its own U (reweighted), not the same doubles.
    assert best.objective == pytest.approx(mc.steady_state(best.machine, rpm=20.0).delta, rel=1e-12)


@pytest.mark.parametrize(
    ("options", "match"),
    [
        ({"objective": "smoothness"}, "objective"),
        ({"bounds": (5.0, 1.0)}, "bounds"),
        ({"bounds": [(0.0, 1.0)] * 3}, "bounds"),
        ({"rpm": 0.0}, "rpm"),
        ({"seed": -1}, "seed"),
        ({"maxiter": 0}, "maxiter"),
        ({"objective": "bearing_loads"}, "objective"),
        ({"max_bearing_load": -1.0}, "max_bearing_load"),
        ({"max_bearing_load": math.nan}, "max_bearing_load"),
        ({"max_bearing_load": math.inf}, "max_bearing_load"),
        ({"max_bearing_load": "heavy"}, "max_bearing_load"),
        ({"max_bearing_load": [1e4, 2e4]}, "max_bearing_load"),
        ({"max_free_force": -0.5}, "max_free_force"),
        ({"max_free_force": math.nan}, "max_free_force"),
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
    assert best.objective == pytest.approx(mc.steady_state(best.machine, rpm=8.0).delta, rel=1e-12)  # (reweighted)
    assert best.objective_before == math.inf and math.isnan(best.delta_before)


# ------------------------------------------------------------ the frame's objectives and limits


def largest_bearing_load(machine: mc.Machine, rpm: float) -> float:
    return float(mc.bearing_loads(machine, rpm).magnitude.max())


def first_order(machine: mc.Machine, rpm: float, what: str = "force") -> float:
    """The largest magnitude over a revolution of the first-order free force [N] (or moment
    [N·m]): its forward and backward parts in phase."""
    orders = mc.shaking_forces(machine, rpm).orders
    return float(orders.loc[1, f"{what}_forward"] + orders.loc[1, f"{what}_backward"])


@pytest.fixture(scope="module")
def least_delta():
    """The compressor's counterweight of least δ: about seven times the one built, and
    heavier on its bearings."""
    return mc.optimize_counterweights(COMPRESSOR)


def test_a_bearing_load_limit_is_kept_and_costs_delta(least_delta):
    as_built = largest_bearing_load(COMPRESSOR, COMPRESSOR.rpm)
    heaviest = largest_bearing_load(least_delta.machine, least_delta.rpm)
    assert as_built < heaviest
    limit = 0.5 * (as_built + heaviest)
    kept = mc.optimize_counterweights(COMPRESSOR, max_bearing_load=limit, maxiter=40)
    load = largest_bearing_load(kept.machine, kept.rpm)
    assert load <= limit
    assert kept.max_bearing_load == pytest.approx(load, rel=1e-12)
    assert (kept.max_bearing_load_limit, kept.max_free_force_limit) == (limit, None)
    # A constraint can't help; this one binds (the least δ is outside it), and the optimum is
    # still better than as built.
    assert least_delta.delta <= kept.delta < kept.delta_before
    assert load > (1 - 1e-3) * limit
    # No design of a dense grid that keeps the limit runs smoother.
    radius = COMPRESSOR.cylinders[0].counterweight_radius
    grid = mc.MachineGrid(COMPRESSOR, **{"counterweight_mass[0]": np.linspace(0.0, 49.9, 400) / radius})
    dense = mc.motion_sweep(COMPRESSOR, grid, outputs=["delta", "max_bearing_load"])
    assert kept.delta <= dense.loc[dense["max_bearing_load"] <= limit, "delta"].min() * (1 + 1e-12)


def test_a_free_force_limit_is_kept(least_delta):
    assert least_delta.free_force_1 > 2000.0
    kept = mc.optimize_counterweights(COMPRESSOR, max_free_force=2000.0, maxiter=40)
    # The machine as built breaks the limit: the optimum keeps it.
    assert kept.free_force_1_before == pytest.approx(first_order(COMPRESSOR, COMPRESSOR.rpm), rel=1e-12)
    assert kept.free_force_1_before > 2000.0 >= first_order(kept.machine, kept.rpm)
    assert kept.free_force_1 == pytest.approx(first_order(kept.machine, kept.rpm), rel=1e-12)
    assert least_delta.delta <= kept.delta < kept.delta_before


def test_alike_counterweights_that_break_a_limit_are_not_returned():
    """The boxer's δ sees only the difference of its two opposed counterweights: of the least
    δ's designs, the one nearest the machine as given (no counterweights) loads the bearings
    with 16 kN; under a 12 kN limit the optimiser's own point, as smooth, is returned."""
    free = mc.optimize_counterweights(BOXER, maxiter=40, seed=1)
    assert largest_bearing_load(free.machine, free.rpm) > 12e3
    kept = mc.optimize_counterweights(BOXER, max_bearing_load=12e3, maxiter=40, seed=1)
    assert largest_bearing_load(kept.machine, kept.rpm) <= 12e3
    # the optimiser converges on δ's spread to 1e-7 of it (its tol): the free optimum is the
    # least δ to that
    assert free.delta <= kept.delta * (1 + 1e-7) and kept.delta <= free.delta * (1 + 1e-6)


def test_the_first_order_free_force_of_one_slider_crank_is_the_textbook_s():
    """The rotating masses (web, big-end share z_k/l of the rod, less the counterweight) turn
    forward; the reciprocating r·m_rec·ω² cos φ along the axis (m_rec: the piston and the
    pin-end share (l − z_k)/l of the rod) is half forward, half backward. Forward + backward
    is least where the forward part is zero, and then half the reciprocating first order."""
    c = COMPRESSOR.cylinders[0]
    r, l, z = c.crank_radius, c.rod_length, c.rod_cg
    rotating = c.crank_mass * c.crank_cg_radius + r * (z / l) * c.rod_mass  # [kg·m]
    reciprocating = c.piston_mass + (l - z) / l * c.rod_mass  # [kg]
    omega = COMPRESSOR.rpm * math.pi / 30
    best_moment = rotating + 0.5 * r * reciprocating
    least = 0.5 * r * omega**2 * reciprocating
    found = mc.optimize_counterweights(COMPRESSOR, objective="free_force_1", bounds=(0.0, 40.0), maxiter=30)
    assert found.counterweights[0] == pytest.approx(best_moment, rel=1e-6)
    assert found.objective == found.free_force_1 == pytest.approx(least, rel=1e-6)
    built = c.counterweight_mass * c.counterweight_radius
    assert found.free_force_1_before == pytest.approx((abs(best_moment - built) * omega**2 + least), rel=1e-9)
    assert found.objective_before == found.free_force_1_before
    assert found.free_force_1 == pytest.approx(first_order(found.machine, found.rpm), rel=1e-12)


def test_the_least_bearing_load_and_every_criterion_before_and_after():
    found = mc.optimize_counterweights(BOXER, objective="max_bearing_load", maxiter=30, seed=1)
    assert found.objective == found.max_bearing_load
    assert found.max_bearing_load == pytest.approx(largest_bearing_load(found.machine, found.rpm), rel=1e-12)
    assert found.max_bearing_load < found.max_bearing_load_before
    # No design of a dense grid (61 × 61 over the default bounds) loads the bearings less:
    # the optimiser's own point, not one moved along the designs of equal δ.
    radii = [c.counterweight_radius or c.crank_radius for c in BOXER.cylinders]
    high = 2 * sum(
        c.crank_mass * c.crank_cg_radius + (c.rod_mass + c.piston_mass) * c.crank_radius for c in BOXER.cylinders[:1]
    )
    axis = np.linspace(0.0, high, 61)
    columns = {f"counterweight_mass[{j}]": axis / radii[j] for j in range(2)}
    columns |= {f"counterweight_radius[{j}]": [radii[j]] for j in range(2)}
    dense = mc.motion_sweep(BOXER, mc.MachineGrid(BOXER, **columns), outputs="max_bearing_load")
    assert found.objective <= dense["max_bearing_load"].min() * (1 + 1e-9)
    # Every criterion, before and after, is that of the machine as given and of the optimum.
    table = found.criteria()
    assert table.index.tolist() == ["delta", "free_force_1", "free_moment_1", "max_bearing_load"]
    assert table.columns.tolist() == ["before", "after", "unit"]
    assert table["unit"].tolist() == ["", "N", "N·m", "N"]
    for column, machine in (("before", found.machine_before), ("after", found.machine)):
        expected = {
            "delta": mc.steady_state(machine, rpm=found.rpm).delta,
            "free_force_1": first_order(machine, found.rpm),
            "free_moment_1": first_order(machine, found.rpm, "moment"),
            "max_bearing_load": largest_bearing_load(machine, found.rpm),
        }
        for name, value in expected.items():
            assert table.loc[name, column] == pytest.approx(value, rel=1e-12, abs=1e-9), (column, name)
    assert found.machine_before is BOXER
    assert table.loc["max_bearing_load", "before"] == found.max_bearing_load_before == found.objective_before


def test_a_limit_on_the_speed_range_objective_holds_at_rpm():
    kept = mc.optimize_counterweights(BOXER, objective="delta_over_speed_range", max_free_force=500.0, maxiter=20)
    assert first_order(kept.machine, kept.rpm) <= 500.0
    speeds = np.linspace(*BOXER.rpm_range, 9)
    assert kept.objective == pytest.approx(max(mc.steady_state(kept.machine, rpm=n).delta for n in speeds), rel=1e-12)


def test_the_same_seed_gives_the_same_constrained_result():
    first = mc.optimize_counterweights(BOXER, objective="free_force_1", max_bearing_load=15e3, seed=5, maxiter=20)
    again = mc.optimize_counterweights(BOXER, objective="free_force_1", max_bearing_load=15e3, seed=5, maxiter=20)
    np.testing.assert_array_equal(first.counterweights, again.counterweights)
    assert first.criteria().equals(again.criteria())


def test_a_limit_nothing_meets_is_refused_by_name_with_the_least_found():
    with pytest.raises(mc.MechanismError, match=r"max_bearing_load <= 1000 N") as caught:
        mc.optimize_counterweights(COMPRESSOR, max_bearing_load=1000.0, maxiter=20)
    reached = float(
        re.search(
            r"lowest main-bearing load \(largest over the cycle\) of the \d+ designs tried is (\S+) N",
            str(caught.value),
        )[1]
    )
    # The least reached (to the message's 6 digits) is the least over the bounds: a dense grid's.
    radius = COMPRESSOR.cylinders[0].counterweight_radius
    grid = mc.MachineGrid(COMPRESSOR, **{"counterweight_mass[0]": np.linspace(0.0, 49.9, 400) / radius})
    least = mc.motion_sweep(COMPRESSOR, grid, outputs="max_bearing_load")["max_bearing_load"].min()
    assert reached == pytest.approx(least, rel=1e-4)
    # Two limits, each met alone, not together (no design of the grid meets both): both named.
    both = mc.motion_sweep(COMPRESSOR, grid, outputs=["max_bearing_load", "free_force_1"])
    assert (both["max_bearing_load"] <= 11100.0).any() and (both["free_force_1"] <= 1300.0).any()
    assert not ((both["max_bearing_load"] <= 11100.0) & (both["free_force_1"] <= 1300.0)).any()
    with pytest.raises(mc.MechanismError, match=r"max_bearing_load <= 11100 N and max_free_force <= 1300 N together"):
        mc.optimize_counterweights(COMPRESSOR, max_bearing_load=11100.0, max_free_force=1300.0, maxiter=20)


def placed(layout: str) -> mc.Machine:
    """The in-line four's cylinder on another four-stroke crank, throws 0.1 m apart."""
    return mc.Machine.from_layout(
        layout,
        INLINE_4.cylinders[0],
        shaft_inertia=INLINE_4.shaft_inertia,
        rpm=INLINE_4.rpm,
        strokes=4,
        cylinder_spacing=0.1,
    )


def test_a_limit_on_the_free_moment_keeps_the_frame_from_rocking():
    """The in-line three's least bearing load comes with counterweights unequal along the
    shaft, which rock the frame more than as built (its first-order couple grows); with
    max_free_moment at the couple as built the optimum keeps it, checked by mc.shaking_forces
    of the returned machine, and says what it keeps."""
    three = placed("inline-3-4t")
    free = mc.optimize_counterweights(three, objective="max_bearing_load", maxiter=40)
    as_built = first_order(three, free.rpm, "moment")
    assert free.free_moment_1_before == pytest.approx(as_built, rel=1e-12)
    assert free.free_moment_1 > as_built * (1 + 1e-3)  # the limit below bites
    kept = mc.optimize_counterweights(three, objective="max_bearing_load", max_free_moment=as_built, maxiter=40)
    assert first_order(kept.machine, kept.rpm, "moment") <= as_built * (1 + 1e-9)
    assert kept.free_moment_1 == pytest.approx(first_order(kept.machine, kept.rpm, "moment"), rel=1e-12)
    assert kept.max_free_moment_limit == as_built and kept.max_free_force_limit is None
    assert free.max_bearing_load <= kept.max_bearing_load < kept.max_bearing_load_before
    with pytest.raises(mc.MechanismError, match=r"max_free_moment = -1.0 is out of range.*N·m"):
        mc.optimize_counterweights(three, max_free_moment=-1.0)
    with pytest.raises(mc.MechanismError, match=r"max_free_moment <= 0\.001 N·m: the lowest first-order free moment"):
        mc.optimize_counterweights(three, max_free_moment=1e-3, maxiter=10)


def test_an_optimum_on_a_bound_of_the_search_says_so():
    """A 360° twin's least δ wants more counterweight than the default bounds allow (twice the
    throw's own first moment): both throws end on the upper bound, and the optimum, its
    table and its repr say so; bounds wide enough (its least δ is near 77 times the default
    bound) let it inside."""
    twin = placed("inline-2-4t")
    found = mc.optimize_counterweights(twin)
    high = 2 * sum(
        c.crank_mass * c.crank_cg_radius + (c.rod_mass + c.piston_mass) * c.crank_radius for c in twin.cylinders[:1]
    )
    np.testing.assert_allclose(found.counterweights, [high, high], rtol=1e-6)
    assert found.at_bound == (True, True)
    assert found.to_frame()["at_bound"].tolist() == [True, True]
    assert "throws 1, 2 at a bound of the search" in repr(found)
    wide = mc.optimize_counterweights(twin, bounds=(0.0, 200 * high))
    assert wide.at_bound == (False, False) and "bound" not in repr(wide)
    assert wide.delta < found.delta


def test_an_optimum_equals_its_pickle_and_not_another():
    import pickle

    found = mc.optimize_counterweights(COMPRESSOR, maxiter=20)
    again = pickle.loads(pickle.dumps(found))
    assert again == found and not (again != found)
    other = mc.optimize_counterweights(COMPRESSOR, maxiter=20, objective="free_force_1")
    assert other != found
    assert found != "an optimum"
