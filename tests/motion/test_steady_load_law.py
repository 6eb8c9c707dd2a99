"""The propeller law in the steady running (Machine.load_law): mc.steady_state, mc.flywheel_inertia
and mc.motion_sweep with the "balance" load at a speed other than the rated one are those of the
same machine without a law whose diagrams were scaled by hand (the oracle of
tests/motion/test_orders_load_law.py); a load that fixes the speed itself takes the diagrams as
given."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import multicrank as mc
from tests.motion.test_orders_load_law import SHIP, TWIN, by_hand

PLAIN = TWIN.replace(load_law=None)


@pytest.mark.parametrize("machine", [TWIN, SHIP], ids=["twin", "slow-diesel-12"])
def test_a_steady_state_below_the_rated_speed_runs_the_load_of_its_speed(machine):
    rpm = 0.3 * machine.rpm
    state = mc.steady_state(machine, rpm=rpm)
    oracle = mc.steady_state(by_hand(machine, rpm), rpm=rpm)
    assert state.machine is machine
    for name in ("delta", "delta_without_gravity", "mean_load_torque", "omega_max", "omega_min"):
        assert getattr(state, name) == pytest.approx(getattr(oracle, name), rel=1e-9), name
    scale = np.abs(oracle.gas_torque).max()
    np.testing.assert_allclose(state.gas_torque, oracle.gas_torque, rtol=0, atol=1e-9 * scale)
    # 9 % of the rated mean load, not all of it.
    rated = mc.steady_state(machine)
    assert state.mean_load_torque == pytest.approx(0.09 * rated.mean_load_torque, rel=1e-9)


def test_at_the_rated_speed_and_without_a_law_the_diagrams_are_as_given():
    state = mc.steady_state(TWIN, rpm=TWIN.rpm)
    plain = mc.steady_state(PLAIN, rpm=TWIN.rpm)
    assert (state.delta, state.mean_load_torque) == (plain.delta, plain.mean_load_torque)
    slow = mc.steady_state(PLAIN, rpm=90.0)
    assert slow.mean_load_torque == pytest.approx(plain.mean_load_torque, rel=1e-12)


def test_the_flywheel_is_sized_for_the_load_of_its_speed():
    rpm = 200.0
    sized = mc.flywheel_inertia(TWIN, delta=1 / 40, rpm=rpm)
    oracle = mc.flywheel_inertia(by_hand(TWIN, rpm), delta=1 / 40, rpm=rpm)
    assert sized.shaft_inertia == pytest.approx(oracle.shaft_inertia, rel=1e-9)
    assert sized.shaft_inertia < mc.flywheel_inertia(PLAIN, delta=1 / 40, rpm=rpm).shaft_inertia


def test_every_row_of_a_speed_sweep_is_the_steady_state_of_its_load():
    grid = mc.MachineGrid(TWIN, rpm=[150.0, 300.0, 400.0], pressure_scale=[0.8, 1.0])
    result = mc.motion_sweep(TWIN, grid, outputs=["delta", "rpm_min", "flywheel_inertia"], delta_target=1 / 40)
    for _, row in result.iterrows():
        oracle = by_hand(TWIN, row["rpm"])
        oracle = oracle.replace(cylinders=[c.replace(pressure=c.pressure.scaled(row["pressure_scale"]))
                                           for c in oracle.cylinders])  # fmt: skip
        state = mc.steady_state(oracle, rpm=row["rpm"])
        assert row["delta"] == pytest.approx(state.delta, rel=1e-9)
        assert row["rpm_min"] == pytest.approx(state.omega_min * 30 / np.pi, rel=1e-12)
        sized = mc.flywheel_inertia(oracle, delta=1 / 40, rpm=row["rpm"]).shaft_inertia
        assert row["flywheel_inertia"] == pytest.approx(sized, rel=1e-9)


def test_a_load_that_fixes_the_speed_takes_the_diagrams_as_given():
    fan = mc.PowerLawLoad(torque=2500.0, rpm=250.0)
    state = mc.steady_state(TWIN, load=fan)
    plain = mc.steady_state(PLAIN, load=fan)
    assert (state.rpm, state.delta) == (plain.rpm, plain.delta)
    table = pd.DataFrame({"shaft_inertia": [240.0]})
    assert mc.motion_sweep(TWIN, table, outputs=["delta"], load=fan)["delta"].item() == pytest.approx(plain.delta)


@pytest.mark.parametrize("steady", [False, True])
def test_the_bearing_loads_below_the_rated_speed_carry_the_gas_of_its_load(steady):
    """bearing_loads at 30 % speed (constant, and in steady running) are those of the machine
    whose diagrams were scaled by hand; and a motion sweep's max_bearing_load over speeds is
    each row's."""
    rpm = 0.3 * TWIN.rpm
    got = mc.bearing_loads(TWIN, rpm, steady=steady)
    expected = mc.bearing_loads(by_hand(TWIN, rpm), rpm, steady=steady)
    scale = np.abs(expected.vertical).max()
    np.testing.assert_allclose(got.vertical, expected.vertical, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(got.horizontal, expected.horizontal, rtol=0, atol=1e-9 * scale)
    full = mc.bearing_loads(PLAIN, rpm, steady=steady)
    assert np.abs(full.vertical - got.vertical).max() > 1e-3 * scale  # the gas does differ
    speeds = [0.3 * TWIN.rpm, 0.7 * TWIN.rpm, TWIN.rpm]
    swept = mc.motion_sweep(TWIN, mc.MachineGrid(TWIN, rpm=speeds), outputs=["max_bearing_load"])
    for n, value in zip(speeds, swept["max_bearing_load"], strict=True):
        assert value == pytest.approx(mc.bearing_loads(by_hand(TWIN, n), n).magnitude.max(), rel=1e-9)
