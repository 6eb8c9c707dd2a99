"""The flywheel's one root search (the core's ``size_shaft_inertia``) over a δ(I_w) given from
Python, as the shooting route gives it for loads that are callables.

Oracles: δ(I_w) = a/(I_w + b), the usual flywheel's law, whose root a/δ − b, stall limit and
massless limit a/b are known in closed form; the steady state solved on the inertia found; and
the core's own flywheel, which searches over its own steady states.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import multicrank as mc
from multicrank._native import size_shaft_inertia
from tests.motion.test_steady import cylinder, smooth_pressure


def law(a: float, b: float, stall: float = 0.0):
    """δ(I_w) = a/(I_w + b), None (a stall) below I_w = ``stall``."""
    return lambda inertia: a / (inertia + b) if inertia >= stall else None


def test_the_search_over_python_steady_states_is_the_cores_own():
    # The same question as the core's flywheel under "balance", its δ(I_w) asked through the
    # Python API's steady state: the same root, which gives the δ asked for.
    machine, rpm, delta = mc.presets.MACHINES["inline-4"], 1500.0, 0.01
    core = mc.flywheel_inertia(machine, delta=delta, rpm=rpm)
    omega = rpm * math.pi / 30
    rest = core.energy_swing / (delta * omega**2) - core.textbook  # mean(J − I_w)
    asked = []

    def delta_at(inertia):
        asked.append(inertia)
        return mc.steady_state(machine.replace(shaft_inertia=inertia), rpm=rpm, points=2).delta

    found = size_shaft_inertia(delta_at, rest, delta, core.textbook)
    assert found == pytest.approx(core.shaft_inertia, rel=1e-11)
    check = mc.steady_state(machine.replace(shaft_inertia=found), rpm=rpm, points=2)
    assert check.delta == pytest.approx(delta, rel=1e-10)
    assert len(set(asked)) == len(asked)  # each inertia solved once


def test_the_root_and_the_stall_are_the_laws():
    a, b = 2.0, 0.3
    assert size_shaft_inertia(law(a, b), b, 0.01, 150.0) == pytest.approx(a / 0.01 - b, rel=1e-12)
    # A stall below I_w = 1 (None) counts as δ = ∞: a target under δ(1) is found, one above
    # it refused naming delta, with why and the largest δ that runs as data.
    assert size_shaft_inertia(law(a, b, stall=1.0), b, 1.0, 100.0) == pytest.approx(a - b, rel=1e-12)
    with pytest.raises(mc.MechanismError, match="unreachable") as raised:
        size_shaft_inertia(law(a, b, stall=1.0), b, 5.0, 100.0)
    error = raised.value
    assert (error.parameter, error.reach, error.delta) == ("delta", "stalls", 5.0)
    assert error.closest == pytest.approx(a / (1.0 + b), rel=1e-9)
    # δ of a massless shaft is a/b = 0.3: the rods' and pistons' inertia b keeps δ below 0.5.
    with pytest.raises(mc.MechanismError) as raised:
        size_shaft_inertia(law(0.3, 1.0), 1.0, 0.5, 2.0)
    assert (raised.value.reach, raised.value.closest) == ("massless", pytest.approx(0.3, rel=1e-8))


def test_what_the_callable_raises_reaches_the_caller_unchanged():
    class Failed(Exception):
        pass

    for failure in (Failed("shot"), mc.MechanismError("load: no periodic solution found")):
        calls = []

        def delta_at(inertia, failure=failure, calls=calls):
            calls.append(inertia)
            if len(calls) == 3:
                raise failure
            return 2.0 / (inertia + 0.3)

        with pytest.raises(type(failure)) as raised:
            size_shaft_inertia(delta_at, 0.3, 0.01, 150.0)
        assert raised.value is failure and len(calls) == 3


def test_a_delta_that_is_no_delta_and_bad_input_are_refused_naming_them():
    for answer in (math.nan, -1.0, math.inf):
        with pytest.raises(mc.MechanismError, match="delta_at") as raised:
            size_shaft_inertia(lambda inertia, answer=answer: answer, 0.3, 0.01, 1.0)
        assert raised.value.parameter == "delta_at"
    for rest, delta, start, parameter in [
        (0.3, 1e-10, 1.0, "delta"),
        (math.nan, 0.01, 1.0, "rest"),
        (0.3, 0.01, 0.0, "start"),
    ]:
        with pytest.raises(mc.MechanismError) as raised:
            size_shaft_inertia(law(2.0, 0.3), rest, delta, start)
        assert raised.value.parameter == parameter


def test_a_target_the_shot_machine_cannot_reach_is_worded_as_the_cores():
    # A load given as a callable takes the shooting route; its refusal reads as that of the
    # core's routes (test_steady's test_a_delta_the_machine_cannot_reach_is_refused_naming_delta).
    machine = mc.Machine(
        [cylinder(pressure=smooth_pressure), cylinder(phase=math.pi, inclination=0.3, pressure=smooth_pressure)],
        shaft_inertia=0.5,
    )
    law = mc.PowerLawLoad(torque=300.0, rpm=150.0 * 30 / math.pi)
    # δ of a (nearly) massless shaft, from the square law's closed form
    massless = mc.steady_state(machine.replace(shaft_inertia=1e-9), load=law, gravity=False).delta
    wording = rf"delta = 3.0 is unreachable: even a massless shaft keeps δ below it \(about {massless:.4g}: the rods'"
    with pytest.raises(mc.MechanismError, match=wording) as raised:
        mc.flywheel_inertia(
            machine, delta=3.0, load=lambda phi, omega: law.coefficient * omega * np.abs(omega), gravity=False
        )
    assert raised.value.parameter == "delta"
