"""mc.Shaft's modes against independent solutions: the two-disc closed form, the three-disc
chain's characteristic polynomial (numpy's roots), and numpy's general eigen solver on J⁻¹K for
random chains (hypothesis) — not SciPy's symmetric solver that the code uses."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc


def test_two_discs_swing_against_each_other_at_the_closed_form_frequency():
    shaft = mc.Shaft([2.0, 0.5], [8.0e4], cylinder_nodes=[0])
    modes = shaft.modes()
    expected = math.sqrt(8.0e4 * (2.0 + 0.5) / (2.0 * 0.5)) / (2 * math.pi)
    assert modes.natural_frequency.shape == (1,)
    assert modes.natural_frequency[0] == pytest.approx(expected, rel=1e-12)
    # the amplitudes in inverse ratio to the inertias (the momentum stays zero), largest +1
    np.testing.assert_allclose(modes.shapes[:, 0], [-0.25, 1.0], rtol=1e-12)


def test_three_discs_match_the_characteristic_polynomial():
    J1, J2, J3, k1, k2 = 1.0, 3.0, 2.0, 5.0e4, 2.0e4
    # det(K − ω²J) = −ω² · (a ω⁴ − b ω² + c): the elastic ω² are the roots of the quadratic
    a = J1 * J2 * J3
    b = k1 * J3 * (J1 + J2) + k2 * J1 * (J2 + J3)
    c = k1 * k2 * (J1 + J2 + J3)
    expected = np.sqrt(np.sort(np.roots([a, -b, c]).real)) / (2 * math.pi)
    found = mc.Shaft([J1, J2, J3], [k1, k2], cylinder_nodes=[0, 1]).modes().natural_frequency
    np.testing.assert_allclose(found, expected, rtol=1e-12)


@settings(max_examples=40, deadline=None)
@given(
    inertia=st.lists(st.floats(0.1, 10.0), min_size=2, max_size=14),
    data=st.data(),
)
def test_any_chain_matches_a_general_eigen_solution(inertia, data):
    stiffness = data.draw(st.lists(st.floats(1e3, 1e6), min_size=len(inertia) - 1, max_size=len(inertia) - 1))
    shaft = mc.Shaft(inertia, stiffness, cylinder_nodes=[0])
    modes = shaft.modes()
    K = np.zeros((len(inertia), len(inertia)))
    for i, k in enumerate(stiffness):
        K[i : i + 2, i : i + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    values, vectors = np.linalg.eig(K / np.asarray(inertia)[:, None])
    order = np.argsort(values.real)[1:]  # the rigid-body mode first
    expected = np.sqrt(np.maximum(values.real[order], 0.0)) / (2 * math.pi)
    # numpy's general solver on J⁻¹K is good to ~1e-12 of the largest eigenvalue
    np.testing.assert_allclose(modes.natural_frequency, expected, rtol=1e-7, atol=1e-6 * expected.max())
    for m, column in enumerate(order):
        shape = modes.shapes[:, m]
        # the convention: largest magnitude 1, positive at the first node that has it
        assert np.abs(shape).max() == pytest.approx(1.0, rel=1e-12)
        assert shape[np.argmax(np.abs(shape) >= 1 - 1e-9)] > 0
        separated = len(expected) == 1 or np.min(np.abs(np.diff(expected))) > 1e-3 * expected.max()
        if separated:  # a repeated frequency has no one shape
            vector = vectors[:, column].real
            vector = vector / np.abs(vector).max()
            sign = 1.0 if np.dot(vector, shape) > 0 else -1.0
            np.testing.assert_allclose(shape, sign * vector, atol=1e-5)
    # J-orthogonal to the rigid-body mode: Σ J_i a_i = 0 (no net momentum)
    np.testing.assert_allclose(np.asarray(inertia) @ modes.shapes, 0.0, atol=1e-8 * np.sum(inertia))


def test_bad_shafts_are_refused_by_name():
    for args, kwargs, name in (
        (([1.0], []), {"cylinder_nodes": [0]}, "inertia"),
        (([1.0, -1.0], [1.0]), {"cylinder_nodes": [0]}, "inertia"),
        (([1.0, 1.0], [1.0, 2.0]), {"cylinder_nodes": [0]}, "stiffness"),
        (([1.0, 1.0], [0.0]), {"cylinder_nodes": [0]}, "stiffness"),
        (([1.0, 1.0], [1.0]), {"cylinder_nodes": [2]}, "cylinder_nodes"),
        (([1.0, 1.0], [1.0]), {"cylinder_nodes": [0.5]}, "cylinder_nodes"),
        (([1.0, 1.0], [1.0]), {"cylinder_nodes": []}, "cylinder_nodes"),
        (([1.0, 1.0], [1.0]), {"cylinder_nodes": [0], "damping": [-1.0]}, "damping"),
        (([1.0, np.nan], [1.0]), {"cylinder_nodes": [0]}, "inertia"),
    ):
        with pytest.raises(mc.MechanismError, match=name):
            mc.Shaft(*args, **kwargs)


def test_a_shaft_keeps_its_numbers_and_pickles():
    shaft = mc.Shaft([1.0, 2.0, 3.0], [1e4, 2e4], cylinder_nodes=[0, 0, 1], damping=[1.0, 2.0])
    assert shaft.inertia == (1.0, 2.0, 3.0) and shaft.cylinder_nodes == (0, 0, 1)
    assert shaft.damping == (1.0, 2.0)
    again = pickle.loads(pickle.dumps(shaft))
    assert again == shaft
    np.testing.assert_array_equal(again.modes().natural_frequency, shaft.modes().natural_frequency)
