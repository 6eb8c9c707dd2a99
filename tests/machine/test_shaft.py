"""mc.Shaft's modes against independent solutions: the two-disc closed form, the three-disc
chain's characteristic polynomial (numpy's roots), numpy's general eigen solver on J⁻¹K for
random chains (hypothesis), mpmath's symmetric eigen solver at 40 digits for stiff and light
chains, and the uniform chain's closed form for a long one — none of them Holzer's recurrence
that the code bisects."""

from __future__ import annotations

import math
import pickle

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc

#: Two heavy discs joined through two light ones by a soft section between stiff ones (the
#: issue's chain): its first mode is 10¹³ times below the others in ω².
STIFF = mc.Shaft([1e4, 1e-4, 1e-4, 1e4], [1e9, 1e3, 1e9], cylinder_nodes=[0])


def mpmath_modes(inertia, stiffness):
    """The elastic modes at 40 digits: mpmath's eigen solver on the symmetric J^-1/2 K J^-1/2,
    built here from the numbers as given. Frequencies [Hz] (mpf, increasing) and the shapes
    (floats, nodes × modes) in Shaft.modes' convention (largest magnitude 1, positive at the
    first node that has it)."""
    with mpmath.workdps(40):
        n = len(inertia)
        J = [mpmath.mpf(float(v)) for v in inertia]
        k = [mpmath.mpf(float(v)) for v in stiffness]
        K = mpmath.zeros(n, n)
        for i, value in enumerate(k):
            K[i, i] += value
            K[i + 1, i + 1] += value
            K[i, i + 1] -= value
            K[i + 1, i] -= value
        scale = [1 / mpmath.sqrt(v) for v in J]
        A = mpmath.matrix(n, n)
        for i in range(n):
            for j in range(n):
                A[i, j] = scale[i] * K[i, j] * scale[j]
        values, vectors = mpmath.eigsy(A)
        order = sorted(range(n), key=lambda m: values[m])[1:]  # the rigid mode first
        frequencies = [mpmath.sqrt(values[m]) / (2 * mpmath.pi) for m in order]
        shapes = np.empty((n, n - 1))
        for column, m in enumerate(order):
            a = [vectors[j, m] * scale[j] for j in range(n)]
            size = max(abs(v) for v in a)
            first = next(j for j in range(n) if abs(a[j]) >= size * (1 - mpmath.mpf("1e-9")))
            shapes[:, column] = [float(v / (size * mpmath.sign(a[first]))) for v in a]
    return frequencies, shapes


def relative_errors(found, exact):
    with mpmath.workdps(40):
        return [float(abs(mpmath.mpf(float(f)) / e - 1)) for f, e in zip(found, exact, strict=True)]


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


def test_a_stiff_chain_keeps_every_digit_of_its_modes():
    """The issue's chain: a dense solver had its first mode 4.9e-4 off (0.071141 Hz)."""
    exact, shapes = mpmath_modes(STIFF.inertia, STIFF.stiffness)
    assert mpmath.nstr(exact[0], 12) == "0.0711761828097"
    modes = STIFF.modes()
    assert max(relative_errors(modes.natural_frequency, exact)) < 1e-14
    # The light nodes follow the heavy ones to 2e-6 in mode 1: each amplitude to its digits.
    np.testing.assert_allclose(modes.shapes[:, 0], shapes[:, 0], rtol=1e-12, atol=0)
    # Modes 2 and 3 lie 1e-6 apart (relative): their shapes are as sensitive, ε/1e-6.
    np.testing.assert_allclose(modes.shapes, shapes, rtol=0, atol=1e-9)
    first = STIFF.modes(count=1)
    assert first.natural_frequency.shape == (1,) and first.shapes.shape == (4, 1)
    np.testing.assert_array_equal(first.natural_frequency, modes.natural_frequency[:1])


@settings(max_examples=40, deadline=None)
@given(
    inertia=st.lists(st.floats(-4.0, 4.0), min_size=2, max_size=7).map(lambda e: [10.0**x for x in e]),
    data=st.data(),
)
def test_any_chain_stiff_or_light_has_mpmaths_modes(inertia, data):
    """Inertias over eight decades and stiffnesses over eight more: each mode's frequency to
    1e-10 (relative) of mpmath's at 40 digits, and its shape, the lowest ``count`` asked."""
    sections = len(inertia) - 1
    exponents = data.draw(st.lists(st.floats(2.0, 10.0), min_size=sections, max_size=sections))
    stiffness = [10.0**x for x in exponents]
    count = data.draw(st.integers(1, sections))
    shaft = mc.Shaft(inertia, stiffness, cylinder_nodes=[0])
    modes = shaft.modes(count)
    exact, shapes = mpmath_modes(inertia, stiffness)
    assert modes.natural_frequency.shape == (count,) and modes.shapes.shape == (len(inertia), count)
    assert max(relative_errors(modes.natural_frequency, exact[:count])) < 1e-10
    for m in range(count):
        # a shape is as well determined as its mode is apart from the others (relative gap)
        gaps = [abs(float(exact[m] / exact[other]) ** 2 - 1) for other in range(sections) if other != m]
        if not gaps or min(gaps) > 1e-4:
            np.testing.assert_allclose(modes.shapes[:, m], shapes[:, m], rtol=0, atol=1e-9)
    # J-orthogonal to the rigid-body mode: Σ J_i a_i = 0 (no net momentum)
    np.testing.assert_allclose(np.asarray(inertia) @ modes.shapes, 0.0, atol=1e-9 * np.sum(inertia))


@pytest.mark.parametrize("count", [None, 3])
def test_a_long_uniform_chain_has_the_closed_form_modes(count):
    """n equal discs J on n − 1 equal sections k: ω_m = 2 √(k/J) sin(mπ/2n) and the shape
    a_j ∝ cos(mπ(j + ½)/n). Its lowest ω² is 2e-6 of its highest, which a dense solver gets
    to ~1e-10 only."""
    n, J, k = 800, 0.02, 3e5
    shaft = mc.Shaft([J] * n, [k] * (n - 1), cylinder_nodes=[0])
    modes = shaft.modes(count)
    m = np.arange(1, (n - 1 if count is None else count) + 1)
    expected = 2 * np.sqrt(k / J) * np.sin(m * np.pi / (2 * n)) / (2 * math.pi)
    np.testing.assert_allclose(modes.natural_frequency, expected, rtol=1e-13)
    for column in (0, 1, 2):
        shape = np.cos(m[column] * np.pi * (np.arange(n) + 0.5) / n)
        shape /= np.abs(shape).max() * np.sign(shape[np.argmax(np.abs(shape) >= np.abs(shape).max() * (1 - 1e-9))])
        np.testing.assert_allclose(modes.shapes[:, column], shape, rtol=0, atol=1e-10)


def test_a_count_that_is_not_a_number_of_modes_is_refused_by_name():
    shaft = mc.Shaft([1.0, 2.0, 3.0], [1e4, 2e4], cylinder_nodes=[0])
    assert shaft.modes(2).natural_frequency.shape == (2,)
    for bad in (0, 3, -1, 1.5, True, "2", [1]):
        with pytest.raises(mc.MechanismError, match=r"^count"):
            shaft.modes(bad)


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
        (([1.0, 1.0], [1.0]), {"cylinder_nodes": [0], "node_damping": [1.0]}, "^node_damping must hold 2 values"),
        (([1.0, 1.0], [1.0]), {"cylinder_nodes": [0], "node_damping": [1.0, -0.5]}, "^node_damping"),
        (([1.0, 1.0], [1.0]), {"cylinder_nodes": [0], "node_damping": [np.nan, 0.0]}, "^node_damping"),
        (([1.0, 1.0], [1.0]), {"cylinder_nodes": [0], "node_damping": ["a", 0.0]}, "^node_damping"),
    ):
        with pytest.raises(mc.MechanismError, match=name):
            mc.Shaft(*args, **kwargs)


def test_a_shaft_keeps_its_numbers_and_pickles():
    shaft = mc.Shaft(
        [1.0, 2.0, 3.0], [1e4, 2e4], cylinder_nodes=[0, 0, 1], damping=[1.0, 2.0], node_damping=[0.0, 0.5, 4]
    )
    assert shaft.inertia == (1.0, 2.0, 3.0) and shaft.cylinder_nodes == (0, 0, 1)
    assert shaft.damping == (1.0, 2.0) and shaft.node_damping == (0.0, 0.5, 4.0)
    assert isinstance(shaft.node_damping[2], float)
    again = pickle.loads(pickle.dumps(shaft))
    assert again == shaft and again.node_damping == (0.0, 0.5, 4.0) and hash(again) == hash(shaft)
    np.testing.assert_array_equal(again.modes().natural_frequency, shaft.modes().natural_frequency)
    # Node damping is part of the shaft: another is another shaft; none is None (0 at every node).
    other = mc.Shaft(shaft.inertia, shaft.stiffness, cylinder_nodes=[0, 0, 1], damping=[1.0, 2.0])
    assert other != shaft and other.node_damping is None
    assert other != mc.Shaft(shaft.inertia, shaft.stiffness, cylinder_nodes=[0, 0, 1], damping=[1.0, 2.0],
                             node_damping=[0.0, 0.0, 0.0])  # fmt: skip


def test_a_shaft_pickled_before_node_damping_reads_none():
    shaft = mc.Shaft([1.0, 2.0], [1e4], cylinder_nodes=[0], damping=[0.5])
    state = dict(shaft.__dict__)
    del state["node_damping"]  # what a pickle of the release before holds
    # What unpickling does with it: a bare instance, its __dict__ updated with the state.
    restored = object.__new__(mc.Shaft)
    restored.__dict__.update(state)
    assert restored.node_damping is None and restored == shaft
    assert pickle.loads(pickle.dumps(restored)) == shaft


def test_modes_compare_by_identity_and_pickle():
    """ShaftModes holds arrays: == must not raise (an array's truth is ambiguous), and a
    pickled copy keeps every number."""
    modes = mc.Shaft(inertia=[1.0, 2.0, 3.0], stiffness=[1e5, 2e5], cylinder_nodes=[0]).modes()
    assert modes == modes
    assert not (modes == mc.Shaft(inertia=[1.0, 2.0, 3.0], stiffness=[1e5, 2e5], cylinder_nodes=[0]).modes())
    copy = pickle.loads(pickle.dumps(modes))
    assert np.array_equal(copy.natural_frequency, modes.natural_frequency)
    assert np.array_equal(copy.shapes, modes.shapes)
