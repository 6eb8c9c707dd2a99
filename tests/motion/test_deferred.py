"""A steady state carries no closure (issue 27, item 5): what it computes when first read is
asked of a typed object — the question the core answered (the native machine, the speed, the
ratio, gravity, the drive table, the route), or what shooting found — and a pickle holds the
answers, not the object."""

from __future__ import annotations

import dataclasses
import inspect
import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc
from multicrank.machine.native import motion_machine
from multicrank.motion._deferred import Computed, CoreQuestion, cycle_angles
from multicrank.presets import MACHINES

COMPRESSOR = MACHINES["slow-compressor"]
FAN = mc.PowerLawLoad(torque=90.0, rpm=120)


def _states() -> dict[str, mc.SteadyState]:
    return {
        "balance": mc.steady_state(COMPRESSOR, rpm=120, points=9, min_speed_ratio=0.01, gravity=False),
        "closed form": mc.steady_state(COMPRESSOR, load=FAN, drive=1000.0, points=9),
        "shooting": mc.steady_state(
            COMPRESSOR, load=lambda phi, omega: FAN.coefficient * omega * np.abs(omega), drive=1000.0, points=9
        ),
    }


def test_what_a_steady_state_computes_later_is_a_typed_question_not_a_closure():
    for route, state in _states().items():
        later = state._later
        assert not inspect.isfunction(later) and not inspect.ismethod(later), route
        assert dataclasses.is_dataclass(later), route
        assert isinstance(later, Computed if route == "shooting" else CoreQuestion), route


def test_the_question_is_the_one_asked():
    state = _states()["balance"]
    question = state._later
    assert isinstance(question, CoreQuestion)
    assert question.native is motion_machine(COMPRESSOR)  # the machine's own native machine
    assert question.omega == math.pi * 120 / 30  # ω = πn/30
    assert (question.ratio, question.gravity, question.points, question.table) == (0.01, False, 9, None)
    assert question.rules.route == "balance"
    # Asked, it answers: φ, ω and t alone at 9 angles over the cycle, ω(0) = ω(Φ); then the
    # arrays with them, the same ω.
    curves = question.curves()
    assert set(curves) == {"phi", "omega", "time"}
    np.testing.assert_array_equal(curves["phi"], np.linspace(0.0, COMPRESSOR.cycle, 9))
    assert curves["omega"][0] == curves["omega"][-1] and curves["time"][0] == 0.0
    arrays = question.arrays(curves)
    assert arrays["omega"] is curves["omega"] and {"gas_torque", "acceleration"} <= set(arrays)


def test_reading_omega_computes_no_torques():
    state = mc.steady_state(COMPRESSOR, rpm=120, points=9)
    state.omega, state.time  # noqa: B018 - reading them is the test
    assert "_curves" in state.__dict__ and "_arrays" not in state.__dict__
    J = state.reduced_inertia
    assert "_arrays" in state.__dict__ and J.shape == (9,)
    np.testing.assert_array_equal(state.omega, state._arrays["omega"])


def test_a_pickle_holds_the_answers_and_no_question():
    for route, state in _states().items():
        loaded = pickle.loads(pickle.dumps(state))
        assert loaded._later is None, route
        np.testing.assert_array_equal(loaded.omega, state.omega)
        assert loaded.delta_coasting == state.delta_coasting


@settings(max_examples=200, deadline=None)
@given(
    cycle=st.floats(1e-3, 1e3, allow_nan=False) | st.sampled_from([2 * math.pi, 4 * math.pi]),
    points=st.integers(2, 5000),
)
def test_the_curves_angles_are_linspaces_to_the_bit(cycle, points):
    assert cycle_angles(cycle, points).tobytes() == np.linspace(0.0, cycle, points).tobytes()


def test_curves_asked_of_the_kept_solve_are_those_the_solve_gives_with_its_angles():
    # One solve, its curves later at any angles: the doubles a solve with those angles gives
    # (the same root, mesh and K̃), on every preset that runs, and no second solve for .omega.
    for name, m in MACHINES.items():
        if m.rpm is None:
            continue
        native = motion_machine(m)
        omega = math.pi * m.rpm / 30
        phi = np.concatenate([np.linspace(0.0, m.cycle, 97), [m.cycle / 3, 0.0, m.cycle]])
        together = native.steady_state(omega, phi=phi, compare=False)
        solved = native.steady_state(omega, compare=False).solved
        assert solved is not None and together.omega is not None and together.time is not None
        later_omega, later_time = solved.curves(phi)
        assert later_omega.tobytes() == together.omega.tobytes(), name
        assert later_time.tobytes() == together.time.tobytes(), name
        state = mc.steady_state(m, points=97)
        assert state.omega.tobytes() == together.omega[:97].tobytes(), name
    with pytest.raises(mc.MechanismError) as error:
        solved.curves(np.array([0.0, -0.1]))
    assert error.value.parameter == "phi"
    assert mc.steady_state(COMPRESSOR, load=FAN, drive=1000.0, points=9)._later.found.solved is None
