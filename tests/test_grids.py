"""Uniform grids (mc.uniform_grid / mc.UniformGrid): the rotation kernels.

Checked: the grid's points are numpy's; evaluation on a grid agrees with evaluation at the
same points given as a plain array (which the oracle tests pin down) to a few ulps of the
terms' size, for every quantity and method, any start, step and length, many revolutions
included (no drift along the grid); the point at index 0 is exact; serial == parallel bit
for bit; anything derived from a grid is a plain array; bad input is a MechanismError.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc
import multicrank.reference as ref

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
    """On the grid, the value is that at the exact angle start + i·step; the plain array's
    point is that angle rounded (within ulp(φ)), so allow ulps of φ times the slope."""
    on_grid = evaluate(quantity, grid, **design)
    at_points = evaluate(quantity, np.asarray(grid), **design)
    assert type(on_grid) is np.ndarray and on_grid.shape == at_points.shape
    reach = 1.0 + float(np.max(np.abs(np.asarray(grid)))) * (24 if quantity == "series" else 1)
    tolerance = 16 * EPS * term_scale(**design) * reach
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
    # that at the start, measured against the reference at the exact angles.
    design = dict(crank_ratio=0.4, inclination=1.2, u1=0.7, u2=0.2, phases=mc.crank_phases(3))
    grid = mc.uniform_grid(3_000_000, 0.0, 600 * math.pi)
    values = evaluate(quantity, grid, **design)
    picks = np.r_[0:50, len(grid) // 2 : len(grid) // 2 + 50, len(grid) - 50 : len(grid)]
    # the exact angles i·step, reduced mod 2π before they reach the reference (libm sin)
    exact_angles = np.mod(np.float64(grid.step) * picks.astype(np.float64), 2 * math.pi)
    method = "series" if quantity == "series" else "exact"
    if quantity in ("series", "generalized_force"):
        expected = ref.generalized_force(exact_angles, method="exact", **design)
    elif quantity == "potential_energy":
        expected = ref.potential_energy(exact_angles, **design)
    else:
        expected = mc.force_derivative(exact_angles, **design)
    assert method  # both methods are held to the same tolerance
    # i·step itself is rounded before the mod (ulp(1900) ≈ 2e-13): allow that times the slope
    tolerance = 4e-13 * term_scale(**design)
    errors = np.abs(values[picks] - expected)
    assert errors.max() <= tolerance
    assert errors[-50:].max() <= max(8 * errors[:50].max(), 64 * EPS * term_scale(**design) * 1900)


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
