"""One unit at the core's boundary, one rule for a speed: the Python API checks a user's speed
[1/min] by the core's limits on ω [rad/s] (read from the binding) and converts it once; what it
shows in 1/min is derived back from the ω the core gives. Oracles: ω = πn/30 written out here."""

from __future__ import annotations

import math

import pytest

import multicrank as mc
from multicrank import _native, _validation
from multicrank.machine.native import native_machine


def test_the_python_speed_limits_are_the_cores():
    # The core's rule, read from the binding: 1e-6 to 1e8 revolutions per minute in rad/s.
    assert _validation.SPEED_LIMITS == tuple(_native.SPEED_LIMITS)
    assert _native.SPEED_LIMITS == pytest.approx((math.pi / 30 * 1e-6, math.pi / 30 * 1e8), rel=1e-15)
    assert _validation.RPM_LIMITS == pytest.approx((1e-6, 1e8), rel=1e-15)
    # The message stays in the user's unit, its numbers from the core's limits.
    with pytest.raises(
        mc.MechanismError, match=r"rpm = 200000000.0 is out of range; allowed: 1e-06 <= rpm <= 1e\+08 \[1/min\]"
    ):
        _validation.as_rpm(2e8, "rpm")
    # Both ends are the core's: what Python takes, the core takes, and the next speed out is
    # refused by both.
    machine = mc.presets.DEFAULT_MACHINE
    native = native_machine(machine)
    for rpm in (1e-6, 1e8):
        omega = _validation.as_omega(rpm, "rpm")
        assert omega == pytest.approx(math.pi * rpm / 30, rel=1e-15)
        low, high = _native.SPEED_LIMITS
        assert low <= omega <= high
    for omega in (math.nextafter(_native.SPEED_LIMITS[0], 0), math.nextafter(_native.SPEED_LIMITS[1], math.inf)):
        with pytest.raises(mc.MechanismError, match="omega_mean"):
            native.steady_state(omega)
        with pytest.raises(mc.MechanismError, match=r"rpm = .* is out of range; allowed: 1e-06 <= rpm <= 1e\+08"):
            _validation.as_omega(30 * omega / math.pi, "rpm")


@pytest.mark.parametrize("rpm", [100.0, 120.0, 157.3])
def test_the_steady_state_runs_at_the_speed_asked(rpm):
    machine = mc.presets.DEFAULT_MACHINE
    state = mc.steady_state(machine, rpm=rpm)
    assert state.omega_mean == pytest.approx(math.pi * rpm / 30, rel=1e-14)  # t_Φ = Φ/ω_m to rounding
    assert state.rpm == pytest.approx(rpm, rel=1e-14)  # and back to 1/min
    assert state.rpm == pytest.approx(30 * state.omega_mean / math.pi, rel=1e-15)
    sized = mc.flywheel_inertia(machine, delta=1 / 50, rpm=rpm)
    assert sized.rpm == pytest.approx(rpm, rel=1e-15)


def test_every_speed_of_a_user_is_checked_by_the_one_rule():
    # A speed the core would refuse is refused where the user gives it, in 1/min, by name.
    machine = mc.presets.DEFAULT_MACHINE
    allowed = r"allowed: 1e-06 <= {0} <= 1e\+08 \[1/min\]"
    with pytest.raises(mc.MechanismError, match=r"balance_rpm = 200000000.0 .*" + allowed.format("balance_rpm")):
        mc.simulate(machine, [0.0, 0.1], rpm0=120, load="balance", drive=lambda phi, omega: 0 * phi, balance_rpm=2e8)
    with pytest.raises(mc.MechanismError, match=allowed.format("rpm")):
        mc.dimensionless_moments(
            crank_radius=0.1, rod_length=0.4, rod_cg=0.1, piston_mass=1.0, rod_mass=1.0, crank_mass=0.5,
            crank_cg_radius=0.05, counterweight_mass=0.5, counterweight_radius=0.05, shaft_inertia=1.0,
            rpm=[100.0, 1e-9], g=9.81,
        )  # fmt: skip
    with pytest.raises(mc.MechanismError, match=allowed.format("rpm")):
        machine.engine(rpm=1e9)


def test_every_question_of_a_machine_without_a_speed_is_refused_by_one_rule():
    """The speed asked, or the machine's own ``rpm``: one rule (_validation.running_omega), so a
    machine without one is refused alike by every question that defaults to its speed — by the
    parameter ``rpm``, as data, and in the same words."""
    from multicrank.report.settings import running_speed

    machine = mc.presets.MACHINES["slow-compressor"].replace(rpm=None, rpm_range=None)
    questions = {
        "shaking_forces": lambda: mc.shaking_forces(machine),
        "bearing_loads": lambda: mc.bearing_loads(machine),
        "steady_state": lambda: mc.steady_state(machine),
        "flywheel_inertia": lambda: mc.flywheel_inertia(machine, delta=0.01),
        "Machine.engine": lambda: machine.engine(),
        "to_opentorsion": lambda: mc.to_opentorsion(machine, max_order=2),
        "firing_orders": lambda: mc.firing_orders(machine),
        "optimize_counterweights": lambda: mc.optimize_counterweights(machine, maxiter=1, progress=False),
        "the report": lambda: running_speed(machine),
    }
    messages = {}
    for name, question in questions.items():
        with pytest.raises(mc.MechanismError) as caught:
            question()
        assert caught.value.parameter == "rpm", name
        messages[name] = str(caught.value)
    assert set(messages.values()) == {
        "rpm is required: machine 'slow-compressor' has no running speed (rpm) of its own"
    }, messages


def test_the_speed_asked_is_converted_once_and_given_back_as_asked():
    """running_omega: ω = πn/30 of the speed asked, or of the machine's own; running_rpm: that
    speed as given [1/min], checked by the same rule."""
    machine = mc.presets.MACHINES["slow-compressor"]
    assert _validation.running_omega(machine, None) == 120 * math.pi / 30
    assert _validation.running_omega(machine, 300) == 300 * math.pi / 30
    assert _validation.running_rpm(machine, None) == 120.0
    assert _validation.running_rpm(machine, 7) == 7
    with pytest.raises(mc.MechanismError, match=r"^--rpm = 0\.0 is out of range") as caught:
        _validation.running_rpm(machine, 0.0, "--rpm")
    assert caught.value.parameter == "--rpm"
