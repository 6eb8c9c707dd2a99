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

import multicrank as mc
from multicrank.machine.native import motion_machine
from multicrank.motion._deferred import Computed, CoreQuestion
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
