"""`mc.dimensionless_moments`: a worked SI example, the paper's erratum (eq. 5/6 swap the
rod's shares), broadcasting, defaults and input validation.

The engine (SI):
    r = 0.05 m, l = 0.2 m, z_k = 0.05 m (rod CG from the piston-pin axis),
    m_t = 1.2 kg, m_k = 0.9 kg, m_s = 2 kg at r_s = 0.03 m,
    counterweight m_p = 3 kg at r_p = 0.04 m, I_w = 0.5 kg m², n = 1500 rpm, g = 9.80665.

By hand (docs/theory.md, "Dimensionless moments": the corrected eq. 5–7):
    ω = π·1500/30 = 50π,   I_w ω² = 0.5·2500π² = 1250π²
    rod shares: piston (l − z_k)/l = 0.15/0.2 = 3/4,  crank pin z_k/l = 1/4
    U1 = r g [m_t + 3/4·m_k] / (1250π²) = 0.05·(1.2 + 0.675)·g/(1250π²)
       = 0.09375 g/(1250π²) = (3/40000)·g/π²                       ≈  7.4515e-5
    U2 = g [r_s m_s − r_p m_p + r·1/4·m_k] / (1250π²)
       = (0.06 − 0.12 + 0.01125)·g/(1250π²) = −0.04875 g/(1250π²)
       = −(39/1000000)·g/π²                                         ≈ −3.8750e-5  (< 0)
The paper's printed eq. 5/6 swap the shares (z_k/l to the piston, (l − z_k)/l to the pin):
    U1' = 0.05·(1.2 + 0.225)·g/(1250π²) = (57/1000000)·g/π²
    U2' = (0.06 − 0.12 + 0.03375)·g/(1250π²) = −(21/1000000)·g/π²
"""

from __future__ import annotations

import re
from fractions import Fraction as F

import mpmath
import numpy as np
import pytest

import multicrank as mc

G0 = "9.80665"

ENGINE = dict(
    crank_radius=0.05,
    rod_length=0.2,
    rod_cg=0.05,
    piston_mass=1.2,
    rod_mass=0.9,
    crank_mass=2.0,
    crank_cg_radius=0.03,
    counterweight_mass=3.0,
    counterweight_radius=0.04,
    shaft_inertia=0.5,
    rpm=1500.0,
    g=9.80665,
)

# the same numbers as exact decimals
D = {k: F(str(v)) for k, v in ENGINE.items()}


def exact_moments(p, *, paper=False, magnitude=False):
    """(U1, U2) as exact rationals c with U = c·g/π² (ω² = (π n/30)², so I ω² = I n²/900·π²).
    With magnitude=True, U2's coefficient is the sum of its terms' absolute values instead
    (the scale of a float64 evaluation's rounding, since U2 may cancel)."""
    r, l, zk = p["crank_radius"], p["rod_length"], p["rod_cg"]
    to_piston, to_pin = (l - zk) / l, zk / l
    if paper:
        to_piston, to_pin = to_pin, to_piston
    iw2_over_pi2 = p["shaft_inertia"] * p["rpm"] ** 2 / 900
    c1 = r * (p["piston_mass"] + to_piston * p["rod_mass"]) / iw2_over_pi2
    terms = (
        p["crank_cg_radius"] * p["crank_mass"],
        -p["counterweight_radius"] * p["counterweight_mass"],
        r * to_pin * p["rod_mass"],
    )
    c2 = (sum(abs(t) for t in terms) if magnitude else sum(terms)) / iw2_over_pi2
    return c1, c2


def assert_u2(got, p, g="1", label="u2"):
    """|u2 − exact| ≤ 1e-15·(Σ|terms of U2|): 1e-15 relative, measured against the terms
    (U2 = g[r_s m_s − r_p m_p + r z_k/l m_k]/(Iω²) cancels, e.g. 15-fold at z_k = l)."""
    _, c2 = exact_moments(p)
    _, c2abs = exact_moments(p, magnitude=True)
    want, scale = to_float(c2, g), abs(to_float(c2abs, g))
    got = float(got)
    assert abs(got - want) <= 1e-15 * scale, (
        f"{label}: {got!r} vs {want!r}, err {abs(got - want):.3e} > 1e-15 x {scale:.3e}"
    )


def to_float(c, g=G0):
    with mpmath.workdps(50):
        return float(mpmath.mpf(c.numerator) / c.denominator * mpmath.mpf(g) / mpmath.pi**2)


def assert_rel(got, want, rtol, label):
    got = float(got)
    assert abs(got - want) <= rtol * abs(want), (
        f"{label}: {got!r} vs {want!r}, rel err {abs(got - want) / abs(want):.3e} > {rtol:g}"
    )


def test_worked_example_matches_hand_computation():
    u1, u2 = mc.dimensionless_moments(**ENGINE)
    assert np.ndim(u1) == 0 and np.ndim(u2) == 0
    assert_rel(u1, to_float(F(3, 40000)), 1e-15, "u1")
    assert_rel(u2, to_float(F(-39, 1000000)), 1e-15, "u2")
    # the counterweight outweighs crank + rod's rotating share: u2 < 0
    assert float(u2) < 0 < float(u1)


def test_library_does_not_reproduce_the_papers_swapped_rod_shares():
    u1, u2 = mc.dimensionless_moments(**ENGINE)
    p1, p2 = (to_float(c) for c in exact_moments(D, paper=True))
    # the paper's eq. 5/6 give 5.7e-5 and -2.1e-5: ~24 % and ~46 % away
    assert abs(float(u1) - p1) > 0.2 * abs(p1)
    assert abs(float(u2) - p2) > 0.4 * abs(p2)
    # both differ by exactly (l − 2 z_k)/l · r m_k g / (I ω²) = 1/2·0.05·0.9·g/(1250π²)
    shift = to_float(F(1, 2) * F("0.05") * F("0.9") / 1250)
    assert_rel(float(u1) - p1, shift, 1e-12, "u1 - paper u1")
    assert_rel(p2 - float(u2), shift, 1e-12, "paper u2 - u2")


@pytest.mark.parametrize("r,l", [(0.05, 0.2), (0.09, 0.2), (0.031, 0.113)])
def test_paper_and_corrected_formulas_agree_when_rod_cg_is_mid_rod(r, l):
    params = dict(ENGINE, crank_radius=r, rod_length=l, rod_cg=l / 2)
    exact = {k: F(v) for k, v in params.items()}  # the binary values, exactly
    c1, c2 = exact_moments(exact)
    q1, q2 = exact_moments(exact, paper=True)
    g = F(params["g"])
    assert (c1, c2) == (q1, q2)
    u1, u2 = mc.dimensionless_moments(**params)
    assert_rel(u1, to_float(c1 * g, "1"), 1e-15, "u1")
    assert_u2(u2, exact, g=params["g"])


@pytest.mark.parametrize(
    "override",
    [
        dict(rod_cg=0.0),  # the whole rod translates with the piston
        dict(rod_cg=0.2),  # the whole rod rotates with the crank pin
        dict(rod_cg=0.17, counterweight_mass=0.0, crank_mass=0.0),
        dict(rpm=733.0, shaft_inertia=0.0123, g=9.81),
        dict(crank_radius=0.199999, rod_length=0.2, rod_cg=0.05),
    ],
)
def test_other_engines_match_exact_arithmetic(override):
    params = dict(ENGINE, **override)
    exact = {k: F(v) for k, v in params.items()}
    c1, _ = exact_moments(exact)
    g = F(params["g"])
    u1, u2 = mc.dimensionless_moments(**params)
    assert_rel(u1, to_float(c1 * g, "1"), 1e-15, "u1")
    assert_u2(u2, exact, g=params["g"])
    if override.get("rod_cg") == 0.0:
        # u2 has no rod term: g (r_s m_s − r_p m_p)/(I ω²)
        assert_rel(u2, to_float((F("0.06") - F("0.12")) / 1250), 1e-15, "u2")


def test_default_gravity_is_standard():
    params = dict(ENGINE)
    del params["g"]
    u1, u2 = mc.dimensionless_moments(**params)
    v1, v2 = mc.dimensionless_moments(**ENGINE)
    assert float(u1) == float(v1) and float(u2) == float(v2)
    assert_rel(u1, to_float(F(3, 40000)), 1e-15, "u1")


def test_optional_masses_default_to_zero():
    required = {
        k: ENGINE[k]
        for k in ("crank_radius", "rod_length", "rod_cg", "piston_mass", "rod_mass", "shaft_inertia", "rpm")
    }
    u1, u2 = mc.dimensionless_moments(**required)
    w1, w2 = mc.dimensionless_moments(
        **dict(required, crank_mass=0, crank_cg_radius=0, counterweight_mass=0, counterweight_radius=0)
    )
    assert float(u1) == float(w1) and float(u2) == float(w2)
    # u2 is the rod's rotating share only: r·(1/4)·m_k·g/(1250π²)
    assert_rel(u2, to_float(F("0.05") * F(1, 4) * F("0.9") / 1250), 1e-15, "u2")


def test_gravity_scales_linearly_and_may_be_zero_or_negative():
    u1, u2 = mc.dimensionless_moments(**ENGINE)
    z1, z2 = mc.dimensionless_moments(**dict(ENGINE, g=0.0))
    assert float(z1) == 0.0 and float(z2) == 0.0
    n1, n2 = mc.dimensionless_moments(**dict(ENGINE, g=-9.80665))
    assert float(n1) == -float(u1) and float(n2) == -float(u2)


def test_negative_u2_when_counterweight_outweighs():
    light = dict(ENGINE, counterweight_mass=0.5)  # 0.06 − 0.02 + 0.01125 > 0
    heavy = dict(ENGINE, counterweight_mass=10.0)
    assert float(mc.dimensionless_moments(**light)[1]) > 0
    assert float(mc.dimensionless_moments(**heavy)[1]) < 0
    # balanced exactly: r_s m_s + r z_k/l m_k = r_p m_p  → 0.06 + 0.01125 = 0.04 · 1.78125
    bal = mc.dimensionless_moments(**dict(ENGINE, counterweight_mass=1.78125))[1]
    assert abs(float(bal)) <= 4e-15 * abs(to_float(F(3, 40000)))


def test_rpm_array_broadcasts():
    rpm = np.array([[600.0, 1500.0, 3000.0], [1000.0, 2000.0, 6000.0]])
    u1, u2 = mc.dimensionless_moments(**dict(ENGINE, rpm=rpm))
    u1, u2 = np.asarray(u1), np.asarray(u2)
    assert u1.shape == u2.shape == (2, 3)
    assert u1.dtype == u2.dtype == np.float64
    for idx in np.ndindex(2, 3):
        p = dict(D, rpm=F(str(rpm[idx])))
        assert_rel(u1[idx], to_float(exact_moments(p)[0]), 1e-15, f"u1{idx}")
        assert_u2(u2[idx], p, G0, f"u2{idx}")
    # a list works like an array
    l1, l2 = mc.dimensionless_moments(**dict(ENGINE, rpm=rpm.tolist()))
    np.testing.assert_array_equal(np.asarray(l1), u1)
    np.testing.assert_array_equal(np.asarray(l2), u2)


def test_several_arrays_broadcast_together():
    rod_cg = np.array([[0.0], [0.05], [0.2]])  # (3, 1)
    rpm = np.array([500.0, 1500.0, 2500.0, 4000.0])  # (4,)
    u1, u2 = mc.dimensionless_moments(**dict(ENGINE, rod_cg=rod_cg, rpm=rpm))
    u1, u2 = np.asarray(u1), np.asarray(u2)
    assert u1.shape == u2.shape == (3, 4)
    for i in range(3):
        for j in range(4):
            p = dict(D, rod_cg=F(str(rod_cg[i, 0])), rpm=F(str(rpm[j])))
            assert_rel(u1[i, j], to_float(exact_moments(p)[0]), 1e-15, f"u1[{i},{j}]")
            assert_u2(u2[i, j], p, G0, f"u2[{i},{j}]")


def test_mechanism_error_is_a_value_error():
    assert issubclass(mc.MechanismError, ValueError)


NAN, INF = float("nan"), float("inf")

BAD = [
    ("crank_radius", 0.0, "crank_radius"),
    ("crank_radius", -0.05, "crank_radius"),
    ("crank_radius", NAN, "crank_radius"),
    ("crank_radius", INF, "crank_radius"),
    ("rod_length", 0.05, "rod_length"),  # = crank_radius
    ("rod_length", 0.03, "rod_length"),  # < crank_radius
    ("rod_length", -0.2, "rod_length"),
    ("rod_length", NAN, "rod_length"),
    ("rod_cg", -1e-9, "rod_cg"),
    ("rod_cg", 0.2000001, "rod_cg"),
    ("rod_cg", NAN, "rod_cg"),
    ("piston_mass", -1.2, "piston_mass"),
    ("piston_mass", NAN, "piston_mass"),
    ("piston_mass", INF, "piston_mass"),
    ("rod_mass", -0.1, "rod_mass"),
    ("rod_mass", NAN, "rod_mass"),
    ("crank_mass", -2.0, "crank_mass"),
    ("crank_mass", NAN, "crank_mass"),
    ("crank_cg_radius", -0.03, "crank_cg_radius"),
    ("crank_cg_radius", NAN, "crank_cg_radius"),
    ("counterweight_mass", -3.0, "counterweight_mass"),
    ("counterweight_mass", NAN, "counterweight_mass"),
    ("counterweight_radius", -0.04, "counterweight_radius"),
    ("counterweight_radius", NAN, "counterweight_radius"),
    ("shaft_inertia", 0.0, "shaft_inertia"),
    ("shaft_inertia", -0.5, "shaft_inertia"),
    ("shaft_inertia", NAN, "shaft_inertia"),
    ("shaft_inertia", INF, "shaft_inertia"),
    ("rpm", 0.0, "rpm"),
    ("rpm", -1500.0, "rpm"),
    ("rpm", NAN, "rpm"),
    ("rpm", INF, "rpm"),
    ("rpm", np.array([1500.0, 0.0]), "rpm"),
    ("rpm", np.array([1500.0, NAN]), "rpm"),
    ("piston_mass", np.array([[1.0], [-1.0]]), "piston_mass"),
    ("g", INF, "g"),
    ("g", -INF, "g"),
    ("g", NAN, "g"),
]


@pytest.mark.parametrize("name,value,needle", BAD, ids=[f"{n}={v!r}".replace(" ", "") for n, v, _ in BAD])
def test_invalid_inputs_raise_mechanism_error_naming_the_parameter(name, value, needle):
    with pytest.raises(mc.MechanismError) as info:
        mc.dimensionless_moments(**dict(ENGINE, **{name: value}))
    assert needle in str(info.value), f"message {str(info.value)!r} does not name {needle!r}"
    if needle == "g":
        # "g" is a letter of many words: ask for it as a word
        assert re.search(r"(?<![A-Za-z_])g(?![A-Za-z_])", str(info.value)), str(info.value)


def test_boundary_values_are_accepted():
    for override in (
        dict(rod_cg=0.0),
        dict(rod_cg=0.2),
        dict(piston_mass=0.0, rod_mass=0.0),
        dict(crank_cg_radius=0.0, counterweight_radius=0.0),
    ):
        u1, u2 = mc.dimensionless_moments(**dict(ENGINE, **override))
        assert np.isfinite(float(u1)) and np.isfinite(float(u2))
