"""How a steady state was solved, as SciPy's solvers say it (issue 27, item 5): ``status`` (0,
converged), ``message``, ``nfev``, the evaluations of the function whose root the solver
finds, and ``nit``, Brent's method's iterations among them. Oracles: SciPy's own counts (every
``solve_ivp`` run of the shooting and its ``brentq``'s iterations, counted by wrappers around
SciPy), and bisection's count for the energy method's root."""

from __future__ import annotations

import math
import pickle

import numpy as np
import scipy.integrate
import scipy.optimize

import multicrank as mc
from multicrank.presets import MACHINES

COMPRESSOR = MACHINES["slow-compressor"]


def test_the_energy_method_converges_in_fewer_evaluations_than_bisection():
    state = mc.steady_state(COMPRESSOR, rpm=120)
    assert (state.status, state.method) == (0, "energy")
    assert "runs" in state.message
    # Bisection from the bracket [s_low, s_high] (s_high/s_low ≥ 1/ratio² = 1e6) to rtol
    # 1e-15 would take log2(1e6/1e-15) ≈ 70 evaluations; Brent's method on the nearly linear
    # excess a handful.
    assert 0 < state.nfev < math.log2(1e6 / 1e-15) / 2
    # the rest of the evaluations bracket the root
    assert 0 < state.nit <= state.nfev


def test_the_closed_form_counts_no_evaluation():
    fan = mc.PowerLawLoad(torque=90.0, rpm=120)
    state = mc.steady_state(COMPRESSOR, load=fan, drive=1000.0)
    assert (state.status, state.nfev, state.nit, state.method) == (0, 0, 0, "closed form")
    assert "closed form" in state.message


def test_shooting_counts_every_right_hand_side_of_its_runs(monkeypatch):
    """nfev is the sum of solve_ivp's nfev over the runs of the search for E(0): SciPy's own
    count of every run, taken here by a wrapper (g = 0: no second search for δ₀)."""
    counted: list[int] = []
    original = scipy.integrate.solve_ivp

    def solve_ivp(*args, **kwargs):
        run = original(*args, **kwargs)
        counted.append(run.nfev)
        return run

    monkeypatch.setattr(scipy.integrate, "solve_ivp", solve_ivp)
    iterations: list[int] = []
    brentq = scipy.optimize.brentq

    def counted_brentq(*args, **kwargs):
        found = brentq(*args, **kwargs)
        if kwargs.get("full_output"):  # the search for E(0) (not that for the start speed)
            iterations.append(found[1].iterations)
        return found

    monkeypatch.setattr(scipy.optimize, "brentq", counted_brentq)
    law = mc.PowerLawLoad(torque=90.0, rpm=120)
    state = mc.steady_state(
        COMPRESSOR, load=lambda phi, omega: law.coefficient * omega * np.abs(omega), drive=1000.0, gravity=False
    )
    assert (state.status, state.method) == (0, "shooting")
    assert "Brent" in state.message
    assert len(counted) > 3
    assert state.nfev == sum(counted)
    assert len(iterations) == 1 and state.nit == iterations[0] > 0


def test_the_table_and_a_pickle_keep_them():
    state = mc.steady_state(COMPRESSOR, rpm=120, points=9)
    attrs = state.to_pandas().attrs
    told = (state.status, state.message, state.nfev, state.nit)
    assert tuple(attrs[key] for key in ("status", "message", "nfev", "nit")) == told
    again = pickle.loads(pickle.dumps(state))
    assert (again.status, again.message, again.nfev, again.nit) == told


def test_a_pickle_of_0_1_reads_them():
    """A steady state pickled before they existed converged (or it would not exist); its count
    is unknown (-1)."""
    state = mc.steady_state(COMPRESSOR, rpm=120, points=9)
    old = state.__getstate__()
    for key in ("status", "message", "nfev", "nit"):
        del old[key]
    restored = object.__new__(mc.SteadyState)
    restored.__setstate__(old)
    assert (restored.status, restored.nfev, restored.nit) == (0, -1, -1)
    assert "0.1" in restored.message


def test_every_route_gives_a_result_every_field():
    """A result is made from its fields without the dataclass's ``__init__`` (for speed): each
    route must still give every field, and the result equal one the ``__init__`` makes."""
    import dataclasses

    fan = mc.PowerLawLoad(torque=90.0, rpm=120)
    states = [
        mc.steady_state(COMPRESSOR, rpm=120),
        mc.steady_state(COMPRESSOR, load=fan, drive=1000.0),
        mc.steady_state(COMPRESSOR, load=fan, drive=lambda phi, omega: 1000.0 + 50.0 * np.sin(phi)),
    ]
    assert [s.method for s in states] == ["energy", "closed form", "shooting"]
    names = [f.name for f in dataclasses.fields(mc.SteadyState)]
    for state in states:
        assert set(names) <= set(vars(state)), state.method
        made = mc.SteadyState(**{name: getattr(state, name) for name in names})
        assert (made.delta, made.omega_mean, made.method) == (state.delta, state.omega_mean, state.method)
        assert made.delta_without_gravity == state.delta_without_gravity
