"""Loads, drives and the cycle quadrature that steady running and "balance" use."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import multicrank as mc
from multicrank.motion._quadrature import CycleQuadrature, PanelSeries, cycle_breaks
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


@given(
    cut=st.floats(0.1, 6.0),
    frequency=st.integers(0, 9),
    width=st.floats(0.05, math.pi / 8),
)
def test_running_integral_matches_the_antiderivative(cut, frequency, width):
    rule = CycleQuadrature(np.array([0.0, cut, 2 * math.pi]), max_width=width)
    values = np.cos(frequency * rule.phi) + rule.phi**3
    at_nodes, at_edges = rule.running(values)

    def antiderivative(x):
        return (np.sin(frequency * x) / frequency if frequency else x) + x**4 / 4

    np.testing.assert_allclose(at_nodes, antiderivative(rule.phi), rtol=1e-12, atol=1e-11)
    np.testing.assert_allclose(at_edges, antiderivative(rule.edges), rtol=1e-12, atol=1e-11)
    assert rule.integral(values) == pytest.approx(antiderivative(2 * math.pi), rel=1e-12)
    assert cut in rule.edges


def test_a_kink_on_a_panel_edge_is_integrated_exactly():
    # |φ − c| has a kink at c: split there, the panel rule is exact; not split, it is not.
    kink = 2.0
    exact = (kink**2 + (2 * math.pi - kink) ** 2) / 2
    split = CycleQuadrature(np.array([0.0, kink, 2 * math.pi]))
    whole = CycleQuadrature(np.array([0.0, 2 * math.pi]), max_width=2 * math.pi)
    assert split.integral(np.abs(split.phi - kink)) == pytest.approx(exact, rel=1e-14)
    assert abs(whole.integral(np.abs(whole.phi - kink)) - exact) > 1e-6


def _cylinder(**changes):
    base = dict(crank_radius=0.1, rod_length=0.35, piston_mass=2.0, rod_mass=1.0, rod_cg=0.25, bore=0.09)
    return mc.Cylinder(**{**base, **changes})


def test_breaks_are_the_gassed_units_dead_centres_and_table_angles():
    table = mc.IndicatorDiagram([0.0, 1.0, 3.0, 2 * math.pi], [1e5, 3e5, 2e5, 1e5], cycle=2 * math.pi, kind="linear")
    machine = mc.Machine(
        [_cylinder(phase=0.5, pressure=table), _cylinder(phase=1.0, bore=0.0), _cylinder(phase=2.5)],
        shaft_inertia=1.0,
    )
    # Dead centres at φ = kπ − α; table angles at φ = θ − α (mod Φ); the second unit has no
    # bore and the third no pressure, so neither adds a break.
    dead_centres = [math.pi - 0.5, 2 * math.pi - 0.5]
    table_angles = [1.0 - 0.5, 3.0 - 0.5]
    expected = np.sort([0.0, *dead_centres, *table_angles, 2 * math.pi])
    np.testing.assert_allclose(cycle_breaks(machine), expected, atol=1e-15)


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


@given(
    count=st.integers(64, 2000),
    seed=st.integers(0, 2**32 - 1),
    slivers=st.booleans(),
)
def test_panels_are_located_as_a_binary_search_would(count, seed, slivers):
    # Many panels (a pressure table's) are found through a bucket table; it must agree with
    # searchsorted everywhere, slivers of 1e-10 rad and points outside [0, Φ] included.
    rng = np.random.default_rng(seed)
    edges = np.sort(np.concatenate([[0.0, 4 * math.pi], rng.random(count) * 4 * math.pi]))
    if slivers:
        edges = np.sort(np.concatenate([edges, edges[3:8] + 1e-10]))
    edges = np.unique(edges)
    series = PanelSeries(edges, np.zeros((edges.size - 1, 2)))
    phi = np.concatenate([rng.random(500) * 4 * math.pi, edges, [-0.5, 4 * math.pi + 1.0]])
    index, _ = series.locate(phi)
    expected = np.clip(np.searchsorted(edges, phi, side="right") - 1, 0, edges.size - 2)
    np.testing.assert_array_equal(index, expected)


def test_panel_series_integrates_and_differentiates_exactly_between_the_nodes():
    rule = CycleQuadrature(np.array([0.0, 1.0, 2 * math.pi]))
    values = np.sin(3 * rule.phi) + 0.2 * np.cos(rule.phi)
    _, _, antiderivative = rule.antiderivative(values)
    phi = np.linspace(0, 2 * math.pi, 1001)
    exact = (1 - np.cos(3 * phi)) / 3 + 0.2 * np.sin(phi)
    np.testing.assert_allclose(antiderivative(phi), exact, atol=1e-13)
    slope = rule.interpolant(values).derivative()
    np.testing.assert_allclose(slope(phi), 3 * np.cos(3 * phi) - 0.2 * np.sin(phi), atol=1e-9)
    # and the extremum between the nodes, located on the interpolant
    edges = np.sin(3 * rule.edges) + 0.2 * np.cos(rule.edges)
    top = rule.extremum(values, edges, largest=True)
    assert 3 * math.cos(3 * top) - 0.2 * math.sin(top) == pytest.approx(0, abs=1e-8)
