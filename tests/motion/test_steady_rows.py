"""What every steady state and every motion-sweep row promises whatever the design: the speed
extremes bracket the mean to the last ulp, and a design that cannot run is a stalled row.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import multicrank as mc

PRESETS = list(mc.presets.MACHINES)


def assert_ordered(low, mean, high):
    assert low <= mean <= high, (low, mean, high)


# -- ω_min ≤ ω_mean ≤ ω_max ------------------------------------------------------------------------


def pure_flywheel(strokes: int = 2) -> mc.Machine:
    """No gas, no masses: ω is constant, and the three speeds come from three different sums."""
    unit = mc.Cylinder(crank_radius=0.05, rod_length=0.2, piston_mass=0.0, rod_mass=0.0, rod_cg=0.1)
    return mc.Machine([unit], shaft_inertia=1.0, strokes=strokes)


def check_state(state: mc.SteadyState) -> None:
    assert_ordered(state.omega_min, state.omega_mean, state.omega_max)
    rpm_min, rpm_max = state.omega_min * 30 / math.pi, state.omega_max * 30 / math.pi
    assert_ordered(rpm_min, state.rpm, rpm_max)
    assert state.delta >= 0 and state.delta_midrange >= 0


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rpm=st.floats(1.0, 1e5), inertia=st.floats(1e-3, 1e6), strokes=st.sampled_from([2, 4]))
def test_the_extremes_bracket_the_mean_of_a_machine_that_hardly_fluctuates(rpm, inertia, strokes):
    machine = pure_flywheel(strokes).replace(shaft_inertia=inertia)
    check_state(mc.steady_state(machine, rpm=rpm, points=2))
    # the Python implementation (a drive that gives nothing)
    check_state(mc.steady_state(machine, rpm=rpm, drive=lambda phi, omega: np.zeros(np.shape(phi)), points=2))
    # the square law's closed form
    law = mc.PowerLawLoad(torque=1e-6 * inertia, rpm=rpm)
    check_state(mc.steady_state(machine, load=law, drive=1e-6 * inertia, points=2))


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(name=st.sampled_from(PRESETS), factor=st.floats(0.3, 30.0), heavier=st.floats(1.0, 1e6))
def test_the_extremes_bracket_the_mean_on_every_preset(name, factor, heavier):
    machine = mc.presets.MACHINES[name]
    machine = machine.replace(shaft_inertia=heavier * machine.shaft_inertia)
    try:
        state = mc.steady_state(machine, rpm=factor * machine.rpm, points=2)
    except mc.StallError:
        return
    check_state(state)


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rpm=st.floats(1.0, 1e5), inertia=st.floats(1e-3, 1e6))
def test_motion_sweep_rows_keep_their_rpm_between_the_extremes(rpm, inertia):
    machine = pure_flywheel()
    table = pd.DataFrame({"rpm": [rpm, 2 * rpm], "shaft_inertia": [inertia, inertia]})
    rows = mc.motion_sweep(machine, table, outputs=["rpm_min", "rpm_max"])
    for _, row in rows.iterrows():
        assert_ordered(row["rpm_min"], row["rpm"], row["rpm_max"])
    # the Python implementation's rows (a callable pressure)
    gassed = machine.replace(cylinders=[machine.cylinders[0].replace(bore=0.05, pressure=lambda theta: 0.0 * theta)])
    rows = mc.motion_sweep(gassed, table, outputs=["rpm_min", "rpm_max"])
    for _, row in rows.iterrows():
        assert_ordered(row["rpm_min"], row["rpm"], row["rpm_max"])


# -- a design without gas under a square-law load --------------------------------------------------


def test_a_design_without_gas_is_a_stalled_row_under_a_square_law_load():
    engine = mc.presets.MACHINES["marine-2t-twin"]
    propeller = mc.PowerLawLoad(torque=2600.0, rpm=300)
    grid = mc.MachineGrid(engine, pressure_scale=[0.0, 1.0])
    rows = mc.motion_sweep(engine, grid, load=propeller)
    assert rows["stalled"].tolist() == [True, False]
    for name in ("delta", "delta_without_gravity", "gravity_effect", "rpm_min", "rpm_max"):
        assert math.isnan(rows[name].iloc[0]), name
        assert math.isfinite(rows[name].iloc[1]), name
    # the row with gas is the steady state of that design
    state = mc.steady_state(engine, load=propeller, points=2)
    assert rows["delta"].iloc[1] == pytest.approx(state.delta, rel=1e-12)


@pytest.mark.parametrize("route", ["core", "python"])
def test_a_square_law_load_with_nothing_driving_stalls_where_the_machine_comes_to_rest(route):
    # No gas, no drive: it settles where its potential energy is lowest (the heavy parts down).
    engine = mc.presets.MACHINES["marine-2t-twin"]
    bare = engine.replace(cylinders=[c.replace(pressure=None) for c in engine.cylinders])
    if route == "python":  # a callable pressure takes the Python implementation
        bare = engine.replace(cylinders=[c.replace(pressure=lambda theta: 0.0 * theta) for c in engine.cylinders])
    propeller = mc.PowerLawLoad(torque=2600.0, rpm=300)
    with pytest.raises(mc.StallError) as caught:
        mc.steady_state(bare, load=propeller)
    assert caught.value.min_rpm is None
    phi = np.linspace(0.0, bare.cycle, 100_001)
    lowest = phi[np.argmin(bare.potential_energy(phi))]
    assert abs(math.remainder(caught.value.angle - lowest, bare.cycle)) < 0.2
