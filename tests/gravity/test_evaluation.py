"""Tests of the public Python API of multicrank against the numpy reference.

Covered: input validation (every bad input → MechanismError naming the parameter), accepted
input kinds (scalars, ints, lists, float16/32, n-D, non-contiguous, reversed, read-only,
empty, broadcasting designs) equal to `multicrank.reference`, layout-independence bit for
bit, NaN/inf in φ, crank phase sets. Serial == parallel, threads, fork and metadata are in
tests/gravity/test_evaluation_parallel.py, which imports the helpers below.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import multicrank as mc
import multicrank.reference as ref

# ---------------------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------------------

DESIGN = dict(crank_ratio=0.31, inclination=1.1, u1=0.62, u2=-0.27)
QUANTITIES = ("potential_energy", "generalized_force", "force_derivative")
HUGE_THRESHOLD = 2**62  # "always serial"

FAST = {name: getattr(mc, name) for name in QUANTITIES}
ORACLE = {name: getattr(ref, name) for name in QUANTITIES}


def _magnitude_scale(crank_ratio, inclination, u1, u2, phases) -> float:
    """A bound on the size of one crank's terms, times the number of cranks.

    The reference sums the cranks' terms in plain float64; for balanced multi-crank sets the
    sum cancels by orders of magnitude, so the reference's own rounding error is relative to
    the size of the terms, not of the (small) sum. The tolerance is taken relative to this.
    """
    lam = np.abs(np.asarray(crank_ratio, dtype=np.float64))
    a1 = np.abs(np.asarray(u1, dtype=np.float64))
    a2 = np.abs(np.asarray(u2, dtype=np.float64))
    k = 1 if phases is None else np.asarray(phases).size
    bound = k * (2.0 * a2 + 3.0 * a1 * (1.0 + lam) / (1.0 - lam**2) ** 1.5)
    return float(np.max(np.broadcast_to(bound, np.broadcast_shapes(lam.shape, a1.shape, a2.shape)), initial=0.0))


def assert_matches_reference(name, phi, *, phases=None, **design):
    """The fast result equals the reference to 1e-13 of max(|ref|, term size); same NaNs."""
    got = FAST[name](phi, phases=phases, **design)
    with np.errstate(invalid="ignore", over="ignore"):
        expected = ORACLE[name](phi, phases=phases, **design)
    assert np.shape(got) == np.shape(expected)
    assert np.asarray(got).dtype == np.float64
    assert type(got) is type(expected)
    got_a, exp_a = np.asarray(got), np.asarray(expected)
    assert np.array_equal(np.isnan(got_a), np.isnan(exp_a))
    finite = np.isfinite(exp_a)
    assert np.all(np.isfinite(got_a[finite]))
    scale = max(float(np.max(np.abs(exp_a[finite]), initial=0.0)), _magnitude_scale(phases=phases, **design))
    np.testing.assert_allclose(got_a[finite], exp_a[finite], rtol=0, atol=1e-13 * scale)
    return got


def assert_bits_equal(a, b):
    """Exactly the same float64 values (NaN where NaN), same shape and dtype."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    assert a.dtype == b.dtype == np.float64
    assert np.array_equal(a, b, equal_nan=True)


def assert_mechanism_error(call, *fragments, allowed=None):
    """`call()` raises MechanismError (a ValueError) whose message holds every fragment."""
    with pytest.raises(mc.MechanismError) as info:
        call()
    assert isinstance(info.value, ValueError)
    assert type(info.value) is mc.MechanismError
    message = str(info.value)
    for fragment in fragments:
        assert fragment in message, f"{fragment!r} not in message {message!r}"
    if allowed is not None:
        assert any(a in message for a in allowed), f"no allowed range {allowed!r} in {message!r}"
    return message


# ---------------------------------------------------------------------------------------
# 1. bad input → MechanismError that names the parameter
# ---------------------------------------------------------------------------------------

PHI = np.linspace(-4.0, 4.0, 17)

BAD_CRANK_RATIO = [
    -0.1,
    -1e-300,
    1.0,
    1,
    1.5,
    float("nan"),
    float("inf"),
    float("-inf"),
    np.array([0.1, 0.5, 1.0]),
    np.array([0.2, -0.1]),
    np.array([0.2, np.nan, 0.3]),
    np.array([[0.1], [np.inf]]),
    [0.1, 2.0],
]


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize("value", BAD_CRANK_RATIO, ids=repr)
def test_bad_crank_ratio(name, value):
    design = {**DESIGN, "crank_ratio": value}
    assert_mechanism_error(lambda: FAST[name](PHI, **design), "crank_ratio")


def test_crank_ratio_message_gives_range():
    for value in (-0.5, 1.0, 3.0):
        design = {**DESIGN, "crank_ratio": value}
        assert_mechanism_error(
            lambda design=design: mc.generalized_force(PHI, **design), "crank_ratio", allowed=("< 1", "<1")
        )


NON_FINITE = [
    float("nan"),
    float("inf"),
    float("-inf"),
    np.array([0.0, np.nan]),
    np.array([1.0, 2.0, np.inf]),
    np.array([[-np.inf], [0.5]]),
    [0.0, float("nan")],
]


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize("keyword", ["inclination", "u1", "u2"])
@pytest.mark.parametrize("value", NON_FINITE, ids=repr)
def test_non_finite_design_value(name, keyword, value):
    design = {**DESIGN, keyword: value}
    assert_mechanism_error(lambda: FAST[name](PHI, **design), keyword)


WRONG_TYPES = [
    "0.3",
    "abc",
    0.3 + 0.0j,
    1j,
    None,
    True,
    False,
    np.bool_(True),
    np.array([True, False]),
    np.array([0.1 + 0j]),
    [0.1, "a"],
    b"0.3",
    object(),
]


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize("keyword", ["crank_ratio", "inclination", "u1", "u2"])
@pytest.mark.parametrize("value", WRONG_TYPES, ids=repr)
def test_wrong_type_design_value(name, keyword, value):
    design = {**DESIGN, keyword: value}
    assert_mechanism_error(lambda: FAST[name](PHI, **design), keyword)


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize("value", [*WRONG_TYPES, [[0.0, 1.0], [2.0]]], ids=repr)
def test_wrong_type_phi(name, value):
    assert_mechanism_error(lambda: FAST[name](value, **DESIGN), "phi")


BAD_PHASES = [
    [],
    np.array([]),
    np.zeros((2, 2)),
    [[0.0, 1.0]],
    np.float64(0.0).reshape(()),  # 0-d is not 1-D
    [0.0, float("nan")],
    [float("inf")],
    np.array([0.0, -np.inf, 1.0]),
    "0.0",
    ["a", "b"],
    [0.0, 1j],
    [True, False],
]


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize("phases", BAD_PHASES, ids=repr)
def test_bad_phases(name, phases):
    assert_mechanism_error(lambda: FAST[name](PHI, phases=phases, **DESIGN), "phases")


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize(
    "shapes",
    [
        {"crank_ratio": (3,), "inclination": (4,)},
        {"u1": (2, 3), "u2": (3, 2)},
        {"crank_ratio": (5, 1), "inclination": (1, 4), "u1": (3,)},
    ],
    ids=str,
)
def test_design_arrays_that_do_not_broadcast(name, shapes):
    design = dict(DESIGN)
    for keyword, shape in shapes.items():
        design[keyword] = np.full(shape, DESIGN[keyword])
    message = assert_mechanism_error(lambda: FAST[name](PHI, **design))
    for shape in shapes.values():
        assert str(shape) in message, f"shape {shape} not in {message!r}"


@pytest.mark.parametrize("cranks", [0, -1, 2.5, 2.0, "3", True, False, None, np.float64(3.0), 3 + 0j])
def test_bad_cranks(cranks):
    assert_mechanism_error(lambda: mc.crank_phases(cranks), "cranks")


def test_bad_cranks_message_gives_range():
    assert_mechanism_error(lambda: mc.crank_phases(0), "cranks", allowed=(">= 1", "≥ 1", ">=1"))


@pytest.mark.parametrize("strokes", [3, 1, 0, -2, 6, "2", 2.0, 4.0, True, None])
def test_bad_strokes(strokes):
    assert_mechanism_error(lambda: mc.crank_phases(3, strokes), "strokes")


def test_bad_strokes_message_gives_range():
    message = assert_mechanism_error(lambda: mc.crank_phases(3, 3), "strokes")
    assert "2" in message.replace("strokes = 3", "") and "4" in message


@pytest.mark.parametrize("acting", ["triple", "Single", "", 1, None, b"single", True])
def test_bad_acting(acting):
    message = assert_mechanism_error(lambda: mc.crank_phases(3, 2, acting), "acting")
    assert "single" in message and "double" in message


@pytest.mark.parametrize("method", ["foo", "EXACT", "", 3, None, True])
def test_bad_method(method):
    message = assert_mechanism_error(lambda: mc.generalized_force(PHI, method=method, **DESIGN), "method")
    assert "exact" in message


@pytest.mark.parametrize("method", ["foo", 3])
def test_bad_method_reference(method):
    assert_mechanism_error(lambda: ref.generalized_force(PHI, method=method, **DESIGN), "method")


def test_missing_design_keyword_is_type_error():
    # Missing required keywords are a programming error of the ordinary Python kind.
    with pytest.raises(TypeError):
        mc.generalized_force(PHI, crank_ratio=0.3, inclination=1.0, u1=0.5)  # type: ignore[call-arg]


def test_error_does_not_poison_later_calls():
    with pytest.raises(mc.MechanismError):
        mc.generalized_force(PHI, **{**DESIGN, "crank_ratio": 1.0})
    assert_matches_reference("generalized_force", PHI, **DESIGN)


# ---------------------------------------------------------------------------------------
# 2. accepted inputs: equal to the reference; bit-identical across layouts
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize("phi", [0.0, 0.5, -2.75, 7, 0, -3, np.float64(1.25), np.float32(0.5), np.int64(2)], ids=repr)
def test_scalar_phi_gives_numpy_float64(name, phi):
    result = assert_matches_reference(name, phi, **DESIGN)
    assert type(result) is np.float64
    assert np.ndim(result) == 0
    assert_bits_equal(result, FAST[name](np.array(float(phi)), **DESIGN))


@pytest.mark.parametrize("name", QUANTITIES)
def test_zero_d_array_gives_numpy_float64(name):
    result = FAST[name](np.array(0.7), **{k: np.array(v) for k, v in DESIGN.items()})
    assert type(result) is np.float64
    assert_bits_equal(result, FAST[name](0.7, **DESIGN))


@pytest.mark.parametrize("name", QUANTITIES)
def test_integer_designs_and_phi(name):
    design = dict(crank_ratio=0, inclination=1, u1=2, u2=-1)
    result = assert_matches_reference(name, [0, 1, 2, 3], **design)
    float_design = {k: float(v) for k, v in design.items()}
    assert_bits_equal(result, FAST[name](np.array([0.0, 1.0, 2.0, 3.0]), **float_design))
    for dtype in (np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint32, np.uint64):
        assert_bits_equal(FAST[name](np.arange(4, dtype=dtype), **design), result)


@pytest.mark.parametrize("name", QUANTITIES)
def test_lists_and_tuples(name):
    phi = [0.0, 0.25, -1.5, 3.0, 6.5]
    design = dict(crank_ratio=[0.1, 0.4], inclination=[[0.3], [1.5], [-2.0]], u1=(0.8,), u2=[-0.2, 0.6])
    result = assert_matches_reference(name, phi, phases=[0.0, 2.0, 4.0], **design)
    assert result.shape == (3, 2, 5)
    as_arrays = {k: np.asarray(v, dtype=np.float64) for k, v in design.items()}
    assert_bits_equal(result, FAST[name](np.asarray(phi), phases=np.array([0.0, 2.0, 4.0]), **as_arrays))
    assert_bits_equal(result, FAST[name](tuple(phi), phases=(0.0, 2.0, 4.0), **design))


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize("dtype", [np.float16, np.float32, np.float64, np.longdouble])
def test_float_dtypes(name, dtype):
    phi = np.linspace(-6.0, 6.0, 101).astype(dtype)
    design = {k: np.asarray(v, dtype=dtype) for k, v in DESIGN.items()}
    result = assert_matches_reference(name, phi, **design)
    assert result.dtype == np.float64
    as64 = {k: v.astype(np.float64) for k, v in design.items()}
    assert_bits_equal(result, FAST[name](phi.astype(np.float64), **as64))


@pytest.mark.parametrize("name", QUANTITIES)
def test_nd_phi(name):
    phi = np.random.default_rng(1).uniform(-7, 7, size=(3, 4, 5))
    result = assert_matches_reference(name, phi, phases=mc.crank_phases(3), **DESIGN)
    assert result.shape == (3, 4, 5)
    assert result.flags.c_contiguous
    assert_bits_equal(result.reshape(-1), FAST[name](phi.reshape(-1), phases=mc.crank_phases(3), **DESIGN))


def _packed_field(values):
    records = np.zeros(values.size, dtype=np.dtype([("tag", "u1"), ("x", "f8")], align=False))
    records["x"] = values
    return records["x"]  # strided and misaligned


def _layouts():
    base = np.random.default_rng(2).uniform(-9, 9, size=600)
    two_d = base[:480].reshape(24, 20)
    readonly = base.copy()
    readonly.setflags(write=False)
    readonly_2d = two_d.copy()
    readonly_2d.setflags(write=False)
    return {
        "step3": base[::3],
        "reversed": base[::-1],
        "reversed_step": base[-2::-7],
        "transposed": two_d.T,
        "fortran": np.asfortranarray(two_d),
        "column": two_d[:, 3],
        "neg_2d": two_d[::-2, ::-3],
        "readonly": readonly,
        "readonly_T": readonly_2d.T,
        "readonly_reversed": readonly[::-1],
        "broadcast_view": np.broadcast_to(base[:7], (5, 7)),
        "packed_record_field": _packed_field(base[:40]),
    }


LAYOUTS = _layouts()


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize("layout", sorted(LAYOUTS))
def test_non_contiguous_and_readonly_phi(name, layout):
    phi = LAYOUTS[layout]
    result = assert_matches_reference(name, phi, phases=mc.crank_phases(4, 4), **DESIGN)
    assert result.shape == phi.shape
    contiguous = np.array(phi, order="C", copy=True)
    assert_bits_equal(result, FAST[name](contiguous, phases=mc.crank_phases(4, 4), **DESIGN))
    # the input was not written to
    assert np.array_equal(phi, contiguous)


def _unaligned(values):
    """A C-contiguous but misaligned float64 array holding `values` (float64 offset by 1 byte)."""
    values = np.asarray(values, dtype=np.float64)
    raw = np.zeros(values.nbytes + 1, dtype=np.uint8)
    array = raw[1:].view(np.float64).reshape(values.shape)
    assert not array.flags.aligned and array.flags.c_contiguous
    array[...] = values
    return array


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize("where", ["phi", "crank_ratio", "inclination", "u1", "u2", "phases"])
def test_unaligned_arrays(name, where):
    phi = np.linspace(-3, 3, 64)
    design = dict(crank_ratio=[0.1, 0.3, 0.5], inclination=[1.1, -0.2, 0.4], u1=[0.6, 0.7, 0.8], u2=[-0.3, 0.2, 0.0])
    phases = mc.crank_phases(3, 4)
    aligned = FAST[name](phi, phases=phases, **design)
    if where == "phi":
        phi = _unaligned(phi)
    elif where == "phases":
        phases = _unaligned(phases)
    else:
        design[where] = _unaligned(design[where])
    result = assert_matches_reference(name, phi, phases=phases, **design)
    assert_bits_equal(result, aligned)


@pytest.mark.parametrize("name", QUANTITIES)
def test_big_endian_arrays(name):
    phi = np.linspace(-3, 3, 40)
    design = {k: np.asarray([v, v / 2], dtype=">f8") for k, v in DESIGN.items()}
    result = assert_matches_reference(name, phi.astype(">f8"), phases=mc.crank_phases(2).astype(">f8"), **design)
    native = {k: v.astype(np.float64) for k, v in design.items()}
    assert_bits_equal(result, FAST[name](phi, phases=mc.crank_phases(2), **native))


@pytest.mark.parametrize("name", QUANTITIES)
def test_non_contiguous_and_readonly_designs_and_phases(name):
    rng = np.random.default_rng(3)
    cr = rng.uniform(0.0, 0.9, size=(6, 8))[::2, ::-3]  # (3, 3) strided
    inc = rng.uniform(-3, 3, size=9)[::-3]  # (3,)
    u1 = np.asfortranarray(rng.uniform(0, 2, size=(3, 3)))
    u2 = rng.uniform(-1, 1, size=3)
    u2.setflags(write=False)
    phases = mc.crank_phases(6, 2)[::-2]
    phi = np.linspace(-5, 5, 31)[::-1]
    result = assert_matches_reference(name, phi, crank_ratio=cr, inclination=inc, u1=u1, u2=u2, phases=phases)
    assert result.shape == (3, 3, 31)
    contiguous = FAST[name](
        phi.copy(),
        crank_ratio=cr.copy(),
        inclination=inc.copy(),
        u1=np.ascontiguousarray(u1),
        u2=u2.copy(),
        phases=phases.copy(),
    )
    assert_bits_equal(result, contiguous)


@pytest.mark.parametrize("name", QUANTITIES)
def test_empty_phi(name):
    empty = np.array([], dtype=np.float64)
    result = assert_matches_reference(name, empty, **DESIGN)
    assert result.shape == (0,) and result.dtype == np.float64
    result = assert_matches_reference(name, [], **DESIGN)
    assert result.shape == (0,)
    design = dict(crank_ratio=np.full((3, 1), 0.2), inclination=np.linspace(0, 3, 4), u1=0.5, u2=0.1)
    result = assert_matches_reference(name, empty, **design)
    assert result.shape == (3, 4, 0) and result.dtype == np.float64
    result = FAST[name](np.zeros((2, 0, 3)), **design)
    assert result.shape == (3, 4, 2, 0, 3)


@pytest.mark.parametrize("name", QUANTITIES)
def test_empty_design(name):
    result = FAST[name](PHI, **{**DESIGN, "crank_ratio": np.zeros((0, 2))})
    assert result.shape == (0, 2, *PHI.shape) and result.dtype == np.float64


@pytest.mark.parametrize("name", QUANTITIES)
def test_broadcasting_designs(name):
    crank_ratio = np.array([[0.0], [0.25], [0.6]])  # (3, 1)
    inclination = np.array([-np.pi / 2, 0.0, 0.7, np.pi / 2])  # (4,)
    u1 = 0.8
    u2 = np.array([-0.3, 0.1, 0.4, -1.2])  # (4,)
    phi = np.linspace(-3.5, 3.5, 10).reshape(5, 2)
    phases = mc.crank_phases(3)
    result = assert_matches_reference(
        name, phi, crank_ratio=crank_ratio, inclination=inclination, u1=u1, u2=u2, phases=phases
    )
    assert result.shape == (3, 4, *phi.shape)
    assert result.dtype == np.float64
    # every design's slice is bit-identical to evaluating that design alone
    for i in range(3):
        for j in range(4):
            alone = FAST[name](
                phi,
                crank_ratio=float(crank_ratio[i, 0]),
                inclination=float(inclination[j]),
                u1=u1,
                u2=float(u2[j]),
                phases=phases,
            )
            assert_bits_equal(result[i, j], alone)


@pytest.mark.parametrize("name", QUANTITIES)
def test_design_array_with_scalar_phi(name):
    result = assert_matches_reference(name, 1.3, **{**DESIGN, "crank_ratio": [0.1, 0.2, 0.3]})
    assert isinstance(result, np.ndarray) and result.shape == (3,)


@pytest.mark.parametrize("name", QUANTITIES)
def test_physical_corner_designs(name):
    # λ = 0 (infinite rod), λ just below 1, γ at the special angles, u2 < 0, zero moments
    phi = np.linspace(-2 * np.pi, 2 * np.pi, 73)
    crank_ratio = np.array([0.0, 0.2, 0.45, 0.9, np.nextafter(0.99, 0)])[:, None, None]
    inclination = np.array([0.0, np.pi, np.pi / 2, -np.pi / 2, 0.3])[:, None]
    u2 = np.array([-2.0, 0.0, 0.5])
    result = assert_matches_reference(name, phi, crank_ratio=crank_ratio, inclination=inclination, u1=1.5, u2=u2)
    assert result.shape == (5, 5, 3, 73)
    zero = FAST[name](phi, crank_ratio=0.3, inclination=0.4, u1=0.0, u2=0.0)
    assert np.all(zero == 0.0)


# hypothesis: random shapes and dtypes

PHI_DTYPES = st.sampled_from([np.float16, np.float32, np.float64, np.int8, np.int32, np.int64, np.uint16])


@st.composite
def phi_arrays(draw):
    dtype = np.dtype(draw(PHI_DTYPES))
    shape = draw(hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=6))
    if dtype.kind == "f":
        elements = st.floats(-60, 60, width=8 * dtype.itemsize if dtype.itemsize > 2 else 16)
    else:
        info = np.iinfo(dtype)
        elements = st.integers(max(info.min, -60), min(info.max, 60))
    return draw(hnp.arrays(dtype, shape, elements=elements))


@settings(max_examples=60, deadline=None)
@given(
    name=st.sampled_from(QUANTITIES),
    phi=phi_arrays(),
    shapes=hnp.mutually_broadcastable_shapes(num_shapes=4, max_dims=3, max_side=3),
    seed=st.integers(0, 2**32 - 1),
    n_cranks=st.integers(1, 7),
)
def test_random_shapes_and_dtypes_match_reference(name, phi, shapes, seed, n_cranks):
    rng = np.random.default_rng(seed)
    s_cr, s_inc, s_u1, s_u2 = shapes.input_shapes
    design = dict(
        crank_ratio=rng.uniform(0.0, 0.95, size=s_cr),
        inclination=rng.uniform(-4.0, 4.0, size=s_inc),
        u1=rng.uniform(-3.0, 3.0, size=s_u1),
        u2=rng.uniform(-3.0, 3.0, size=s_u2),
    )
    phases = rng.uniform(-7.0, 7.0, size=n_cranks)
    result = assert_matches_reference(name, phi, phases=phases, **design)
    assert np.shape(result) == shapes.result_shape + phi.shape
    assert np.asarray(result).dtype == np.float64
    if np.ndim(result) == 0:
        assert type(result) is np.float64
    assert_bits_equal(result, FAST[name](phi.astype(np.float64), phases=phases, **design))


@settings(max_examples=60, deadline=None)
@given(
    name=st.sampled_from(QUANTITIES),
    shape=hnp.array_shapes(min_dims=1, max_dims=3, min_side=1, max_side=9),
    data=st.data(),
    seed=st.integers(0, 2**32 - 1),
)
def test_random_views_are_bit_identical_to_contiguous_copies(name, shape, data, seed):
    rng = np.random.default_rng(seed)
    base = rng.uniform(-20.0, 20.0, size=shape)
    index = tuple(
        slice(
            data.draw(st.sampled_from([None, 0, 1, -1])),
            None,
            data.draw(st.sampled_from([1, 2, 3, -1, -2])),
        )
        for _ in shape
    )
    view = base[index]
    if data.draw(st.booleans()):
        view = view.T
    if data.draw(st.booleans()):
        view.setflags(write=False)
    design = dict(crank_ratio=rng.uniform(0, 0.9, size=(2, 1)), inclination=rng.uniform(-3, 3, size=3), u1=0.7, u2=-0.4)
    phases = mc.crank_phases(int(rng.integers(1, 6)), 4)
    result = FAST[name](view, phases=phases, **design)
    assert result.shape == (2, 3, *view.shape)
    assert_bits_equal(result, FAST[name](np.array(view, order="C"), phases=phases, **design))


# ---------------------------------------------------------------------------------------
# 3. NaN / ±inf in φ
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize("threshold", [0, HUGE_THRESHOLD], ids=["parallel", "serial"])
def test_non_finite_phi_gives_nan_exactly_there(name, threshold, restore_threshold):
    mc.set_parallel_threshold(threshold)
    phi = np.linspace(-5, 5, 3000)
    bad = np.zeros(phi.shape, dtype=bool)
    for position, value in [(0, np.nan), (17, np.inf), (18, -np.inf), (255, np.nan), (256, np.inf), (2999, -np.inf)]:
        phi[position] = value
        bad[position] = True
    design = dict(crank_ratio=[0.0, 0.3, 0.8], inclination=[[0.4], [-1.2]], u1=0.9, u2=-0.5)
    result = assert_matches_reference(name, phi, phases=mc.crank_phases(4), **design)
    assert result.shape == (2, 3, 3000)
    assert np.array_equal(np.isnan(result), np.broadcast_to(bad, result.shape))
    assert np.all(np.isfinite(result[..., ~bad]))


@pytest.mark.parametrize("name", QUANTITIES)
@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf, float("nan")])
def test_non_finite_scalar_phi(name, value):
    result = FAST[name](value, **DESIGN)
    assert type(result) is np.float64 and np.isnan(result)
    result = FAST[name](np.array([value], dtype=np.float32), **DESIGN)
    assert np.isnan(result[0])


# ---------------------------------------------------------------------------------------
# 4. phases and crank_phases
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", QUANTITIES)
def test_phases_none_is_one_crank_at_zero(name):
    phi = np.linspace(-4, 4, 50)
    default = FAST[name](phi, **DESIGN)
    assert_bits_equal(default, FAST[name](phi, phases=None, **DESIGN))
    assert_bits_equal(default, FAST[name](phi, phases=[0.0], **DESIGN))
    assert_bits_equal(default, FAST[name](phi, phases=np.zeros(1), **DESIGN))
    assert_bits_equal(default, FAST[name](phi, phases=[0], **DESIGN))
    assert_bits_equal(default, FAST[name](phi, phases=mc.crank_phases(1), **DESIGN))


def test_crank_phases_values():
    two_pi = 2 * np.pi
    cases = [
        ((1,), [0.0]),
        ((3,), [0.0, two_pi / 3, 2 * two_pi / 3]),
        ((3, 2, "single"), [0.0, two_pi / 3, 2 * two_pi / 3]),
        ((2, 2, "double"), [0.0, np.pi / 2]),
        ((6, 4, "single"), [j * 4 * np.pi / 6 for j in range(6)]),
        ((4, 4, "double"), [0.0, np.pi / 2, np.pi, 3 * np.pi / 2]),
        ((4, 2, "single"), [0.0, np.pi / 2, np.pi, 3 * np.pi / 2]),
        ((1, 4, "double"), [0.0]),
    ]
    for args, expected in cases:
        phases = mc.crank_phases(*args)
        assert isinstance(phases, np.ndarray)
        assert phases.dtype == np.float64 and phases.shape == (args[0],)
        np.testing.assert_allclose(phases, expected, rtol=0, atol=1e-14)
        assert phases[0] == 0.0


def test_crank_phases_keywords_and_numpy_integers():
    assert_bits_equal(mc.crank_phases(np.int64(4)), mc.crank_phases(4))
    assert_bits_equal(mc.crank_phases(np.int32(5), np.int64(4), "double"), mc.crank_phases(5, 4, "double"))
    assert_bits_equal(mc.crank_phases(cranks=3, strokes=4, acting="single"), mc.crank_phases(3, 4))


@pytest.mark.parametrize("k", [2, 3, 4, 5, 6, 8, 12])
def test_crank_phases_feed_the_evaluation(k):
    phi = np.linspace(0, 2 * np.pi, 91)
    for strokes in (2, 4):
        for acting in ("single", "double"):
            assert_matches_reference("generalized_force", phi, phases=mc.crank_phases(k, strokes, acting), **DESIGN)
