"""Loads and drives, and the "balance" rule."""

from __future__ import annotations

import math

import numpy as np
import pytest

import multicrank as mc
from multicrank.motion.loads import BALANCE, AppliedTorques, PowerLawLoad, as_torque


def test_power_law_load_is_the_law_with_the_sign_of_omega():
    load = PowerLawLoad(torque=120.0, rpm=50.0 * 30 / math.pi, exponent=2.0)  # ω_n = 50 rad/s
    omega = np.array([-100.0, -50.0, 0.0, 25.0, 50.0])
    np.testing.assert_allclose(load(0.0, omega), [-480.0, -120.0, 0.0, 30.0, 120.0], rtol=1e-15)
    assert load.coefficient == pytest.approx(120.0 / 2500.0, rel=1e-15)
    coulomb = PowerLawLoad(7.0, rpm=3.0, exponent=0)
    assert coulomb(np.zeros(2), np.array([2.0, -2.0])).tolist() == [7.0, -7.0]


def test_power_law_load_takes_its_nominal_speed_in_rpm():
    fan = PowerLawLoad(90.0, rpm=120.0)
    assert fan.rpm == 120.0 and fan.omega == pytest.approx(4 * math.pi, rel=1e-15)  # 2 rev/s
    assert fan == PowerLawLoad(90.0, rpm=120.0) and fan != PowerLawLoad(90.0, rpm=121.0)
    assert repr(fan) == "PowerLawLoad(torque=90.0, rpm=120.0, exponent=2.0)"
    for arguments, message in (({}, "neither"), ({"rpm": 0.0}, "rpm = 0.0")):
        with pytest.raises(mc.MechanismError, match=message):
            PowerLawLoad(1.0, **arguments)


def test_power_law_load_speed_in_rad_s_is_deprecated_but_still_the_same_load():
    """0.1's ``speed=`` [rad/s] (a name without its unit) still works for one release."""
    with pytest.warns(DeprecationWarning, match=r"PowerLawLoad\(speed=.* use rpm="):
        old = PowerLawLoad(90.0, 4 * math.pi)  # positional, as 0.1 took it: 4π rad/s = 120 rpm
    assert old.omega == 4 * math.pi and old.rpm == pytest.approx(120.0, rel=1e-15)
    np.testing.assert_allclose(old(0.0, [2 * math.pi]), [22.5], rtol=1e-15)  # half the speed, a quarter
    with pytest.warns(DeprecationWarning, match=r"PowerLawLoad.speed is deprecated.* PowerLawLoad.omega"):
        assert old.speed == 4 * math.pi
    with pytest.raises(mc.MechanismError, match="both"):
        PowerLawLoad(1.0, speed=1.0, rpm=10.0)


@pytest.mark.parametrize(("field", "value"), [("torque", -1.0), ("rpm", 0.0), ("rpm", math.nan), ("exponent", -0.5)])
def test_power_law_load_refuses_bad_numbers_naming_them(field, value):
    arguments = {"torque": 1.0, "rpm": 1.0, "exponent": 2.0, field: value}
    with pytest.raises(mc.MechanismError, match=field):
        PowerLawLoad(**arguments)


def test_as_torque_resolves_numbers_callables_and_balance():
    assert as_torque(None, "load") is None
    assert as_torque(BALANCE, "load", balance=True) == BALANCE
    constant = as_torque(3.5, "load")
    assert constant.kind == "constant" and not constant.depends_on_speed
    np.testing.assert_array_equal(constant(np.zeros((2, 3)), 1.0), np.full((2, 3), 3.5))
    function = as_torque(lambda phi, omega: np.sin(phi) * omega, "drive")
    np.testing.assert_allclose(function(np.array([0.5, 1.0]), 2.0), 2 * np.sin([0.5, 1.0]))


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("balance", "drive = 'balance' is not understood"),
        ("fast", "drive = 'fast'"),
        (math.inf, "drive = inf is out of range"),
        ([1.0, 2.0], "drive"),
    ],
)
def test_as_torque_refuses_what_it_cannot_use(value, message):
    with pytest.raises(mc.MechanismError, match=message):
        as_torque(value, "drive")


def test_a_callable_that_fails_or_returns_nan_is_named():
    with pytest.raises(mc.MechanismError, match="load failed: ZeroDivisionError"):
        as_torque(lambda phi, omega: 1 / 0, "load")(np.zeros(2), 1.0)
    with pytest.raises(mc.MechanismError, match="load returned a non-finite torque"):
        as_torque(lambda phi, omega: np.full_like(phi, np.nan), "load")(np.zeros(2), 1.0)


def _cylinder(**changes):
    base = dict(crank_radius=0.1, rod_length=0.35, piston_mass=2.0, rod_mass=1.0, rod_cg=0.25, bore=0.09)
    return mc.Cylinder(**{**base, **changes})


def test_balance_is_the_cycle_mean_of_gas_and_drive():
    # p = p0 (1 + cos θ) on a single cylinder: ∮ p A s'(φ) dφ checked with a dense trapezoid.
    cylinder = _cylinder(pressure=lambda theta: 2e5 * (1 + np.cos(theta)))
    machine = mc.Machine([cylinder, cylinder.replace(phase=1.3)], shaft_inertia=1.0, strokes=4)
    phi = np.linspace(0, 4 * math.pi, 400_001)
    dense = np.trapezoid(machine.gas_torque(phi), phi) / (4 * math.pi)
    drive = lambda phi, omega: 10.0 + 0 * phi + omega  # noqa: E731

    def balance(drive):
        return AppliedTorques.of(BALANCE, drive).balanced(machine, 5.0).load.value

    assert balance(None) == pytest.approx(dense, rel=1e-8, abs=1e-9)
    assert balance(drive) == pytest.approx(dense + 15.0, rel=1e-8)
