"""Uniform grids (mc.uniform_grid / mc.UniformGrid): the rotation kernels.

Checked: the grid's points are numpy's; evaluation on a grid agrees with evaluation at the
same points given as a plain array (which the oracle tests pin down) to a few ulps of the
terms' size, for every quantity and method, any start, step and length, many revolutions
and starts far out included (no drift along the grid or with the start: the values are
those at the doubles the grid exposes, issue 13 item 5); the point at index 0 is exact;
serial == parallel bit for bit; anything derived from a grid is a plain array; bad input
is a MechanismError.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc

EPS = np.finfo(np.float64).eps
HUGE_THRESHOLD = 2**62
QUANTITIES = ("potential_energy", "generalized_force", "force_derivative", "series")


def evaluate(quantity, phi, **design):
    if quantity == "series":
        return mc.generalized_force(phi, method="series", **design)
    return getattr(mc, quantity)(phi, **design)


def term_scale(crank_ratio, u1, u2, phases, **_) -> float:
    """The size of one crank's terms (and of their φ-derivative) times the number of cranks:
    balanced crank sets cancel to a far smaller sum, whose rounding is relative to this."""
    k = len(phases)
    return k * (2.0 * abs(u2) + 3.0 * abs(u1) * (1.0 + crank_ratio) / (1.0 - crank_ratio**2) ** 1.5)


def assert_close_to_points(quantity, grid, **design):
    """On the grid, the value is that at the grid's own points (the doubles numpy forms), to
    a few ulps of the terms' size wherever the grid starts: no allowance grows with φ. (The
    series at plain points raises e^{iφ} to the power p of its harmonics: p ulps there.)"""
    on_grid = evaluate(quantity, grid, **design)
    at_points = evaluate(quantity, np.asarray(grid), **design)
    assert type(on_grid) is np.ndarray and on_grid.shape == at_points.shape
    tolerance = 16 * EPS * term_scale(**design) * (24 if quantity == "series" else 1)
    np.testing.assert_allclose(on_grid, at_points, rtol=0, atol=tolerance)
    return on_grid


design_strategy = st.fixed_dictionaries(
    {
        "crank_ratio": st.floats(0.0, 0.95),
        "inclination": st.floats(-math.pi, math.pi),
        "u1": st.floats(-2.0, 2.0),
        "u2": st.floats(-2.0, 2.0),
        "phases": st.builds(
            mc.crank_phases, st.integers(1, 12), st.sampled_from([2, 4]), st.sampled_from(["single", "double"])
        ),
    }
)


@settings(max_examples=60, deadline=None)
@given(
    design=design_strategy,
    quantity=st.sampled_from(QUANTITIES),
    count=st.integers(1, 5000),
    start=st.floats(-50.0, 50.0),
    revolutions=st.floats(-8.0, 8.0),
    endpoint=st.booleans(),
)
def test_grid_agrees_with_the_same_points_as_an_array(design, quantity, count, start, revolutions, endpoint):
    grid = mc.uniform_grid(count, start, start + 2 * math.pi * revolutions, endpoint=endpoint)
    assert_close_to_points(quantity, grid, **design)


@pytest.mark.parametrize("quantity", QUANTITIES)
def test_no_drift_along_a_long_grid_of_many_revolutions(quantity):
    # 3·10⁶ points over 300 revolutions (φ up to ~1900 rad): the error at the far end is
    # that at the start, measured against 40-digit values at the grid's own points.
    design = dict(crank_ratio=0.4, inclination=1.2, u1=0.7, u2=0.2, phases=mc.crank_phases(3))
    grid = mc.uniform_grid(3_000_000, 0.0, 600 * math.pi)
    values = evaluate(quantity, grid, **design)
    picks = np.r_[0:20, len(grid) // 2 : len(grid) // 2 + 20, len(grid) - 20 : len(grid)]
    target = "force_derivative" if quantity == "force_derivative" else quantity
    expected = [mp_value(target, grid[i], **design) for i in picks]
    errors = np.abs(values[picks] - expected)
    assert errors.max() <= 16 * EPS * term_scale(**design)
    assert errors[-20:].max() <= max(4 * errors[:20].max(), 8 * EPS * term_scale(**design))


def mp_value(quantity, phi, *, crank_ratio, inclination, u1, u2, phases):
    """U, Q or dQ/dφ of the closed form at the double φ (exactly), in 40-digit mpmath."""
    from mpmath import mp, mpf

    with mp.workdps(40):
        lam, gamma, total = mpf(crank_ratio), mpf(inclination), mpf(0)
        for alpha in phases:
            psi = mpf(phi) + mpf(alpha)
            root = mp.sqrt(1 - lam**2 * mp.sin(psi) ** 2)
            if quantity == "potential_energy":
                travel = (1 - mp.cos(psi)) + lam * mp.sin(psi) ** 2 / (1 + root)
                term = u2 * (mp.sin(psi + gamma) - mp.sin(gamma)) - u1 * travel * mp.sin(gamma)
            elif quantity == "force_derivative":
                f1 = lam * (mp.cos(2 * psi) + lam**2 * mp.sin(psi) ** 4) / root**3
                term = -u2 * mp.sin(psi + gamma) - u1 * mp.sin(gamma) * (mp.cos(psi) + f1)
            else:
                f = lam * mp.sin(psi) * mp.cos(psi) / root
                term = u2 * mp.cos(psi + gamma) - u1 * mp.sin(gamma) * (mp.sin(psi) + f)
            total += term
        return float(total)


@pytest.mark.parametrize("quantity", QUANTITIES)
@pytest.mark.parametrize("start", [1e6, -3.3e9, 1e12, 1e15, -2.5e17])
def test_grids_far_out_are_exact_at_their_points(quantity, start):
    """Issue 13, item 5: uniform_grid(3000, 1e15, 1e15 + 30) erred by 1.1e-4 at its last
    point (the sincos of a double-double angle took its low part to first order, up to
    0.06 rad there), and values were those of the unrounded progression (6e-11 off the
    exposed points at start = 1e6). Now: a few ulps of the terms at every point, any start."""
    design = dict(crank_ratio=0.35, inclination=1.1, u1=0.9, u2=-0.4, phases=mc.crank_phases(4, 4))
    grid = mc.uniform_grid(3000, start, start + 30)
    values = evaluate(quantity, grid, **design)
    picks = [0, 1, 1500, 2998, 2999]
    target = "generalized_force" if quantity == "series" else quantity
    expected = [mp_value(target, grid[i], **design) for i in picks]
    assert np.abs(values[picks] - expected).max() <= 24 * EPS * term_scale(**design)
    assert_close_to_points(quantity, grid, **design)


@settings(max_examples=60, deadline=None)
@given(
    design=design_strategy,
    quantity=st.sampled_from(QUANTITIES),
    count=st.integers(1, 3000),
    exponent=st.floats(0.0, 18.0),
    sign=st.sampled_from([-1.0, 1.0]),
    span=st.floats(-200.0, 200.0),
)
def test_grids_anywhere_agree_with_their_points(design, quantity, count, exponent, sign, span):
    """Random grids starting anywhere up to ±10¹⁸ (where an ulp of φ is 128 rad)."""
    start = sign * 10.0**exponent
    assert_close_to_points(quantity, mc.uniform_grid(count, start, start + span), **design)


def test_index_zero_is_exact_and_single_crank_energy_is_zero_there():
    design = dict(crank_ratio=0.3, inclination=0.9, u1=0.8, u2=0.3)
    grid = mc.uniform_grid(1000)
    assert mc.potential_energy(grid, **design)[0] == 0.0
    for quantity in QUANTITIES:
        on_grid = evaluate(quantity, mc.uniform_grid(777, 1.25, 9.0), phases=mc.crank_phases(5), **design)
        alone = evaluate(quantity, np.array([1.25]), phases=mc.crank_phases(5), **design)
        if quantity != "series":  # the series' e^{ipφ} comes by rotation, not by powering
            assert on_grid[0] == alone[0]


@pytest.mark.parametrize("quantity", QUANTITIES)
def test_serial_and_parallel_are_bit_identical_on_grids(quantity):
    design = dict(crank_ratio=[[0.1], [0.5], [0.9]], inclination=1.0, u1=0.6, u2=[0.1, -0.4], phases=mc.crank_phases(6))
    grid = mc.uniform_grid(70_001, -3.0, 40.0)
    old = mc.get_parallel_threshold()
    try:
        mc.set_parallel_threshold(HUGE_THRESHOLD)
        serial = evaluate(quantity, grid, **design)
        mc.set_parallel_threshold(0)
        parallel = evaluate(quantity, grid, **design)
    finally:
        mc.set_parallel_threshold(old)
    assert serial.shape == (3, 2, 70_001)
    assert np.array_equal(serial, parallel)
    # and each design's row equals that design alone
    alone = evaluate(quantity, grid, crank_ratio=0.9, inclination=1.0, u1=0.6, u2=-0.4, phases=mc.crank_phases(6))
    assert np.array_equal(serial[2, 1], alone)


def test_engines_take_grids():
    engine = mc.layout_engine("v8-cross", crank_ratio=0.3, u1=0.5, u2=0.1)
    grid = mc.uniform_grid(4096)
    for method in ("exact", "series"):
        on_grid = engine.generalized_force(grid, method=method)
        at_points = engine.generalized_force(np.asarray(grid), method=method)
        np.testing.assert_allclose(on_grid, at_points, rtol=0, atol=1e-13)
    np.testing.assert_allclose(
        engine.potential_energy(grid), engine.potential_energy(np.asarray(grid)), rtol=0, atol=1e-13
    )


def test_points_are_numpys():
    grid = mc.uniform_grid(360)
    np.testing.assert_array_equal(grid, np.arange(360) * (2 * math.pi / 360))
    np.testing.assert_array_max_ulp(mc.uniform_grid(101, -1.0, 3.0, endpoint=True), np.linspace(-1.0, 3.0, 101), 2)
    np.testing.assert_array_max_ulp(mc.uniform_grid(100, 0.5, 7.0), np.linspace(0.5, 7.0, 100, endpoint=False), 2)
    assert mc.uniform_grid(1, 2.0, 5.0, endpoint=True).tolist() == [2.0]
    assert (grid.start, grid.step, len(grid)) == (0.0, 2 * math.pi / 360, 360)
    assert repr(grid).startswith("UniformGrid(count=360")


def test_anything_derived_from_a_grid_is_a_plain_array():
    grid = mc.uniform_grid(100)
    for derived in (
        grid[1:],
        grid[::2],
        grid * 2,
        2 * grid,
        np.sin(grid),
        grid.copy(),
        np.asarray(grid),
        grid + 0,
        grid.reshape(10, 10),
        np.array(grid),
        -grid,
    ):
        assert type(derived) is np.ndarray, type(derived)
    assert type(grid.sum()) is np.float64
    assert type(grid[3]) is np.float64
    assert (grid.shape, grid.dtype, grid.ndim, len(grid)) == ((100,), np.float64, 1, 100)
    assert list(grid)[:2] == [0.0, grid.step]
    with pytest.raises((ValueError, TypeError)):
        grid[0] = 1.0
    with pytest.raises(ValueError):
        np.asarray(grid)[0] = 1.0  # the points are read-only: the grid cannot be edited
    assert np.array(grid).flags.writeable
    # a slice evaluates as the points it holds, bit for bit
    design = dict(crank_ratio=0.3, inclination=1.0, u1=0.5, u2=0.2)
    assert np.array_equal(
        mc.generalized_force(grid[5:], **design), mc.generalized_force(np.asarray(grid)[5:], **design)
    )
    again = pickle.loads(pickle.dumps(grid))
    assert type(again) is mc.UniformGrid and np.array_equal(again, grid)
    assert again.step == grid.step


@pytest.mark.parametrize(
    "args, kwargs, names",
    [
        ((0,), {}, "count"),
        ((2.5,), {}, "count"),
        ((True,), {}, "count"),
        ((10, math.nan), {}, "start"),
        ((10, 0.0, math.inf), {}, "stop"),
        ((10, [0.0, 1.0]), {}, "start"),
        ((10, "0"), {}, "start"),
        ((10, 0.0, 1.0), {"endpoint": "yes"}, "endpoint"),
        ((10, -1e308, 1e308), {}, "stop - start"),
    ],
)
def test_bad_grids_raise_mechanism_error(args, kwargs, names):
    with pytest.raises(mc.MechanismError, match=names.split()[0]):
        mc.uniform_grid(*args, **kwargs)


def test_a_grid_costs_no_memory_until_its_points_are_asked_for():
    huge = mc.uniform_grid(10**10)  # 80 GB of points, were they formed
    assert len(huge) == 10**10 and huge.count == 10**10
    grid = mc.uniform_grid(5000)
    mc.generalized_force(grid, crank_ratio=0.3, inclination=1.0, u1=0.5, u2=0.2, phases=mc.crank_phases(4))
    assert grid._cache is None  # the kernels got (start, step, count) only
    assert grid.max() == grid.step * 4999 and grid._cache is not None
