"""The core's chain modes (``multicrank._native.chain_modes``, which Shaft.modes calls) against
the closed forms of short chains and the uniform chain's, and its refusals by name: the core's
own checks, which Shaft's validation otherwise stands in front of."""

from __future__ import annotations

import math

import numpy as np
import pytest

from multicrank import MechanismError, _native


def test_three_discs_on_two_sections_have_their_closed_form_modes():
    # det(K − ω²J) = −ω² (a ω⁴ − b ω² + c): the elastic ω² are the quadratic's roots
    inertia, stiffness = np.array([1.0, 3.0, 2.0]), np.array([5.0e4, 2.0e4])
    (j1, j2, j3), (k1, k2) = inertia, stiffness
    a, b, c = j1 * j2 * j3, k1 * j3 * (j1 + j2) + k2 * j1 * (j2 + j3), k1 * k2 * (j1 + j2 + j3)
    root = math.sqrt(b * b - 4 * a * c)
    expected = np.sqrt([2 * c / (b + root), (b + root) / (2 * a)])
    omega, shapes = _native.chain_modes(stiffness, inertia, 2)
    np.testing.assert_allclose(omega, expected, rtol=1e-15)
    assert shapes.shape == (3, 2) and shapes.flags.c_contiguous
    # each shape solves node 0's equation, k1 (a0 − a1) = ω² J1 a0, is J-orthogonal to the
    # rigid mode, and is largest (+1) at the first node that has it
    np.testing.assert_allclose(k1 * (shapes[0] - shapes[1]), omega**2 * j1 * shapes[0], rtol=1e-12)
    np.testing.assert_allclose(inertia @ shapes, 0.0, atol=1e-12)
    for column in shapes.T:
        first = np.argmax(np.abs(column) >= 1 - 1e-9)
        assert np.abs(column).max() == 1.0 and column[first] > 0


def test_the_lowest_modes_of_a_long_uniform_chain_are_its_closed_form_ones():
    n, j, k = 2000, 0.5, 4e6
    omega, shapes = _native.chain_modes(np.full(n - 1, k), np.full(n, j), 4)
    m = np.arange(1, 5)
    np.testing.assert_allclose(omega, 2 * math.sqrt(k / j) * np.sin(m * math.pi / (2 * n)), rtol=1e-13)
    # a_i ∝ cos(mπ(i + ½)/n), largest +1 at the first node that has it (to 1e-9): node 0,
    # except in mode 3, whose cosine is closer to ±1 at nodes 666 and 1333 than at the ends
    exact = np.cos(m * math.pi * (np.arange(n)[:, None] + 0.5) / n)
    size = np.abs(exact).max(axis=0)
    first = np.argmax(np.abs(exact) >= size * (1 - 1e-9), axis=0)
    np.testing.assert_array_equal(first, [0, 0, 666, 0])
    np.testing.assert_allclose(shapes, exact / (size * np.sign(exact[first, m - 1])), rtol=0, atol=1e-10)


@pytest.mark.parametrize(
    ("stiffness", "inertia", "count", "name"),
    [
        ([], [1.0], 1, "inertia"),
        ([1.0], [1.0, 0.0], 1, "inertia"),
        ([1.0], [1.0, np.nan], 1, "inertia"),
        ([1.0, 1.0], [1.0, 1.0], 1, "stiffness"),
        ([-1.0], [1.0, 1.0], 1, "stiffness"),
        ([np.inf], [1.0, 1.0], 1, "stiffness"),
        ([1.0], [1.0, 1.0], 0, "count"),
        ([1.0], [1.0, 1.0], 2, "count"),
    ],
)
def test_a_bad_chain_or_count_is_refused_by_name(stiffness, inertia, count, name):
    with pytest.raises(MechanismError, match=f"^{name}") as refused:
        _native.chain_modes(np.asarray(stiffness, dtype=float), np.asarray(inertia, dtype=float), count)
    assert refused.value.parameter == name
