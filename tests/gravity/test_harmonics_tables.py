"""The paper's power series and the surviving harmonics (docs/theory.md, "Fourier form and
Λ_n", "Which harmonics survive"; the paper's eq. (15) and Tables 1 and 2).

Every expected value here is computed independently of the formulas under test:

- the paper's rational coefficients against an exact expansion of f in λ (binomial series
  in exact rationals + Laurent polynomials in z = e^{iψ}; the same through sympy where it is
  installed), against the decimals printed in the paper (and its misprints), and against
  Python's big integers for every index the formula defines;
- surviving harmonics against numerical phase sums Σ_j e^{inα_j}, the paper's Table 1 as
  printed, Table 2 derived by hand, and the rule table of docs/theory.md written out here.

The independent helpers (phases, phase sums, Λ_n by mpmath quadrature) come from
tests/gravity/test_harmonics.py.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from mpmath import mpf

import multicrank as mc
from tests.gravity.test_harmonics import (
    KINDS,
    PI,
    assert_lambda_close,
    f_numpy,
    lambda_by_quadrature,
    numerical_survivors,
    regular_phases,
    working_digits,
)

# --------------------------------------------------------------------------------------
# 2. The paper's power series (eq. 15)
# --------------------------------------------------------------------------------------


def _laurent_mul(a: dict, b: dict) -> dict:
    out: dict = {}
    for ea, ca in a.items():
        for eb, cb in b.items():
            out[ea + eb] = out.get(ea + eb, 0) + ca * cb
    return out


def series_coefficients_exact(i_max: int, j_max: int) -> dict:
    """[λ^{2j+1}] of the sin(2iψ) coefficient of f, from first principles in exact rationals.

    (1 − x)^{−1/2} = Σ c_j x^j with c_0 = 1, c_{j+1} = c_j (j + ½)/(j + 1) (binomial series),
    so f = Σ_j λ^{2j+1} · ½ c_j sin 2ψ sin^{2j} ψ. With z = e^{iψ}, sin ψ = (z − 1/z)/(2i):
    sin 2ψ sin^{2j} ψ = P(z)/(2i)^{2j+1}, P = (z² − z⁻²)(z − z⁻¹)^{2j} with integer
    coefficients p_m; a real g = Σ c_m z^m has sine coefficient b_n = −2 Im c_n, which gives
    b_n = (−1)^j p_n / 4^j."""
    out = {}
    c = Fraction(1)
    for j in range(j_max + 1):
        poly = {2: 1, -2: -1}
        for _ in range(2 * j):
            poly = _laurent_mul(poly, {1: 1, -1: -1})
        for i in range(1, i_max + 1):
            out[i, j] = Fraction(1, 2) * c * (-1) ** j * Fraction(poly.get(2 * i, 0), 4**j)
        c = c * (j + Fraction(1, 2)) / (j + 1)
    return out


def test_paper_coefficients_match_exact_expansion():
    expected = series_coefficients_exact(6, 5)
    for (i, j), value in expected.items():
        got = mc.paper_coefficient(i, j)
        assert isinstance(got, Fraction)
        assert got == value, (i, j, got, value)


def test_paper_coefficients_match_sympy_expansion():
    """The same through sympy: series of f in λ, then (1/π)∫_0^{2π} … sin(2iψ) dψ exactly
    (as the constant term of the Laurent polynomial in z = e^{iψ}, times 2)."""
    sp = pytest.importorskip("sympy")
    lam, psi, z = sp.symbols("lambda psi z")
    f = lam / 2 * sp.sin(2 * psi) / sp.sqrt(1 - lam**2 * sp.sin(psi) ** 2)
    series = sp.expand(sp.series(f, lam, 0, 13).removeO())
    for j in range(6):
        coefficient = series.coeff(lam, 2 * j + 1)
        for i in range(1, 7):
            integrand = sp.expand_trig(coefficient * sp.sin(2 * i * psi))
            laurent = integrand.subs({sp.sin(psi): (z - 1 / z) / (2 * sp.I), sp.cos(psi): (z + 1 / z) / 2})
            shift = 2 * j + 2 * i + 4
            value = 2 * sp.Poly(sp.expand(laurent * z**shift), z).coeff_monomial(z**shift)
            value = sp.nsimplify(value)
            assert value.is_rational
            assert mc.paper_coefficient(i, j) == Fraction(int(sp.numer(value)), int(sp.denom(value))), (i, j)


# The paper's eq. (15) as printed (decimals), keyed (i, j) for [λ^{2j+1}] Λ_{2i}.
PRINTED = {
    (1, 0): 0.5, (1, 1): 0.125, (1, 2): 0.058594, (1, 3): 0.034180, (1, 4): 0.022432, (1, 5): 0.015862,
    (2, 1): -0.0625, (2, 2): -0.046875, (2, 3): -0.034180, (2, 4): -0.025635, (2, 5): -0.019827,
    (3, 2): 0.011719, (3, 3): 0.014648, (3, 4): 0.014420, (3, 5): 0.013218,
    (4, 3): -0.002441, (4, 4): -0.004272, (4, 5): -0.005287,
    (5, 4): 0.000534, (5, 5): 0.001202,
    (6, 5): -0.000120,
}  # fmt: skip


def test_paper_printed_coefficients_reproduced():
    for (i, j), printed in PRINTED.items():
        got = float(mc.paper_coefficient(i, j))
        if (i, j) == (1, 4):
            continue  # misprint, see below
        assert round(got, 6) == printed, (i, j, got, printed)
    # every coefficient the paper does not print (j < i − 1) is zero
    for i in range(1, 7):
        for j in range(6):
            if (i, j) not in PRINTED:
                assert mc.paper_coefficient(i, j) == 0, (i, j)


def test_paper_exact_rationals():
    assert [mc.paper_coefficient(1, j) for j in range(6)] == [
        Fraction(1, 2),
        Fraction(1, 8),
        Fraction(15, 256),
        Fraction(35, 1024),
        Fraction(735, 32768),
        Fraction(2079, 131072),
    ]
    assert mc.paper_coefficient(2, 0) == 0
    assert mc.paper_coefficient(2, 1) == Fraction(-1, 16)
    assert mc.paper_coefficient(6, 5) == Fraction(-63, 524288)
    assert mc.paper_coefficient(6, 4) == 0
    # beyond the paper's table the general term continues
    expected = series_coefficients_exact(8, 8)
    for (i, j), value in expected.items():
        assert mc.paper_coefficient(i, j) == value, (i, j)


def test_paper_misprint_lambda9_coefficient_of_lambda2():
    """Erratum 5: the λ⁹ coefficient of Λ_2 is 735/32768 = 0.0224304…, printed 0.022432."""
    got = mc.paper_coefficient(1, 4)
    assert got == Fraction(735, 32768)
    assert round(float(got), 6) == 0.022430
    assert abs(float(got) - PRINTED[1, 4]) > 1e-6  # we do NOT reproduce the misprint


def test_paper_misprint_first_term_of_lambda2():
    """Erratum 5: Λ_2's first term is 0.5·λ (the paper prints '0,5', without the λ)."""
    for method in ("exact", "paper"):
        small = mc.lambda_coefficients(1e-8, 2, method=method)[2]
        assert abs(small - 0.5e-8) <= 1e-15 * 0.5e-8
        assert mc.lambda_coefficients(0.0, 2, method=method)[2] == 0.0


@pytest.mark.parametrize("lam", [0.0, 0.01, 0.2, 0.4, 0.5, 0.8, 0.95])
def test_paper_lambda_coefficients_are_the_truncated_series(lam):
    got = mc.lambda_coefficients(lam, 24, method="paper")
    x = Fraction(lam)  # the binary value, exactly
    for n in range(2, 13, 2):
        i = n // 2
        exact_sum = sum((mc.paper_coefficient(i, j) * x ** (2 * j + 1) for j in range(6)), Fraction(0))
        assert abs(Fraction(got[n]) - exact_sum) <= Fraction(1, 10**15) * abs(exact_sum), n
    assert np.all(got[13:] == 0.0)


def test_paper_lambda_12_is_37_percent_off_at_lambda_04():
    exact = lambda_by_quadrature(0.4, 12, working_digits(0.4, 12))
    paper = mc.lambda_coefficients(0.4, 12, method="paper")[12]
    error = float(abs(mpf(paper) / exact - 1))
    assert 0.36 < error < 0.38
    # while the library's exact value has full accuracy
    assert_lambda_close(mc.lambda_coefficients(0.4, 12)[12], exact, 12, 0.4)


@pytest.mark.parametrize("lam", [0.1, 0.2, 0.3, 0.4, 0.5])
def test_paper_truncation_error_in_f(lam):
    """f from the paper's Λ_2 … Λ_12 errs by ≈ 0.037·λ¹³ (the λ¹³ term ½·C(12,6)/4⁶·
    sin 2ψ sin¹²ψ peaks at 0.0372), slightly more at larger λ."""
    psi = np.linspace(0, PI, 20001)
    paper = mc.lambda_coefficients(lam, 12, method="paper")
    truncated = sum(paper[n] * np.sin(n * psi) for n in range(2, 13, 2))
    error = np.max(np.abs(f_numpy(psi, lam) - truncated))
    ratio = error / (0.037 * lam**13)
    assert 0.9 < ratio < 2.0, ratio
    # the exact coefficients reproduce f (to rounding)
    exact = mc.lambda_coefficients(lam, 80)
    full = sum(exact[n] * np.sin(n * psi) for n in range(2, 81, 2))
    assert np.max(np.abs(f_numpy(psi, lam) - full)) <= 1e-15


def test_paper_coefficient_invalid_input():
    for args in [(0, 0), (-1, 2), (1, -1), (1.5, 2), ("1", 2)]:
        with pytest.raises(mc.MechanismError):
            mc.paper_coefficient(*args)


# --------------------------------------------------------------------------------------
# 3. Surviving harmonics ("Which harmonics survive", Tables 1 and 2)
# --------------------------------------------------------------------------------------

# The paper's Table 1 (two-stroke, single acting), as printed: n -> the k with W_n ≠ 0.
TABLE_1 = {
    1: [1],
    2: [1, 2],
    4: [1, 2, 4],
    6: [1, 2, 3, 6],
    8: [1, 2, 4, 8],
    10: [1, 2, 5, 10],
    12: [1, 2, 3, 4, 6, 12],
}

# Table 2 (four-stroke, single acting; not printed, derived by hand from α = 4π/k):
# n = 1 survives for k = 1, 2; even n for k | 2n.
TABLE_2 = {
    1: [1, 2],
    2: [1, 2, 4],
    4: [1, 2, 4, 8],
    6: [1, 2, 3, 4, 6, 12],
    8: [1, 2, 4, 8],
    10: [1, 2, 4, 5, 10],
    12: [1, 2, 3, 4, 6, 8, 12],
}


def test_table_1_as_printed():
    table = mc.harmonic_table()
    assert table.shape == (7, 12)
    assert table.index.name == "n" and table.columns.name == "k"
    assert list(table.index) == [1, 2, 4, 6, 8, 10, 12]
    assert list(table.columns) == list(range(1, 13))
    assert all(dtype == np.bool_ for dtype in table.dtypes)
    for n, ks in TABLE_1.items():
        assert [k for k in table.columns if table.loc[n, k]] == ks, n
    # the paper's conclusion: k = 7, 9, 11 have no entry up to n = 12
    for k in (7, 9, 11):
        assert not table[k].any()


def test_table_2_four_stroke():
    table = mc.harmonic_table(strokes=4)
    assert table.shape == (7, 12)
    assert list(table.index) == [1, 2, 4, 6, 8, 10, 12]
    for n, ks in TABLE_2.items():
        assert [k for k in table.columns if table.loc[n, k]] == ks, n
    for k in (7, 9, 11):
        assert not table[k].any()


@pytest.mark.parametrize("strokes,acting", KINDS)
def test_harmonic_table_matches_phase_sums(strokes, acting):
    table = mc.harmonic_table(strokes=strokes, acting=acting, k_max=9, n_max=20)
    assert table.shape == (11, 9)
    assert list(table.index) == [1, *list(range(2, 21, 2))]
    for k in range(1, 10):
        survivors = set(numerical_survivors(k, strokes, acting, 20))
        assert [bool(v) for v in table[k]] == [n in survivors for n in table.index], k


@pytest.mark.parametrize("strokes,acting", KINDS)
def test_surviving_harmonics_match_phase_sums(strokes, acting):
    for k in range(1, 13):
        got = mc.surviving_harmonics(k, strokes, acting, n_max=48)
        assert isinstance(got, list)
        assert got == numerical_survivors(k, strokes, acting, 48), (k, strokes, acting)
        assert got == sorted(got)


def rule_survives(n: int, k: int, strokes: int, acting: str) -> bool:
    """The table of docs/theory.md, "Which harmonics survive", verbatim."""
    if n == 1:
        return {(2, "single"): k == 1, (4, "single"): k in (1, 2), (4, "double"): k == 1, (2, "double"): True}[
            (strokes, acting)
        ]
    assert n % 2 == 0
    return {
        (2, "single"): n % k == 0,
        (4, "single"): (2 * n) % k == 0,
        (4, "double"): n % k == 0,
        (2, "double"): n % (2 * k) == 0,
    }[(strokes, acting)]


@pytest.mark.parametrize("strokes,acting", KINDS)
def test_surviving_harmonics_rule_table(strokes, acting):
    for k in range(1, 17):
        expected = [n for n in [1, *list(range(2, 61, 2))] if rule_survives(n, k, strokes, acting)]
        assert mc.surviving_harmonics(k, strokes, acting, n_max=60) == expected, k


def test_surviving_harmonics_examples():
    assert mc.surviving_harmonics(7) == [14]
    assert mc.surviving_harmonics(7, n_max=12) == []
    assert mc.surviving_harmonics(1, n_max=6) == [1, 2, 4, 6]
    assert mc.surviving_harmonics(1, n_max=0) == []
    assert mc.surviving_harmonics(1, n_max=1) == [1]
    assert mc.surviving_harmonics(2, 4, "single", n_max=4) == [1, 2, 4]
    assert mc.surviving_harmonics(3, 2, "double", n_max=24) == [1, 6, 12, 18, 24]
    assert mc.surviving_harmonics(6, 4, "single", n_max=12) == [6, 12]


U64 = 2**64 - 1


@settings(max_examples=200, deadline=None)
@given(
    cranks=st.one_of(st.integers(1, 100), st.integers(1, U64), st.sampled_from([10**18, 2**63, U64 - 1, U64])),
    kind=st.sampled_from(KINDS),
    n_max=st.integers(0, 400),
)
def test_surviving_harmonics_exact_for_any_crank_count(cranks, kind, n_max):
    """Issue 13, item 2: the rule in Python's unbounded integers, for counts whose products
    overflow 64 bits (surviving_harmonics(10**18) returned [20, 22, 24] instead of [])."""
    strokes, acting = kind
    expected = [n for n in [1, *range(2, n_max + 1, 2)] if n <= n_max and rule_survives(n, cranks, strokes, acting)]
    assert mc.surviving_harmonics(cranks, strokes, acting, n_max=n_max) == expected


@settings(max_examples=200, deadline=None)
@given(
    cranks=st.integers(2**20, U64),
    kind=st.sampled_from(KINDS),
    multiple=st.integers(0, 60),
    extra=st.integers(0, 2**20),
)
def test_surviving_harmonics_of_huge_n_max(cranks, kind, multiple, extra):
    """n_max up to 2⁶⁴ − 1 answers at once (no loop over n) and exactly: every survivor is a
    multiple of k/2 or k (the table), so checking those candidates by the rule is complete."""
    strokes, acting = kind
    n_max = min(multiple * cranks + extra, U64)
    unit = cranks // 2 if cranks % 2 == 0 else cranks
    candidates = [1, *range(unit, n_max + 1, unit)]
    expected = [
        n for n in candidates if n <= n_max and (n == 1 or n % 2 == 0) and rule_survives(n, cranks, strokes, acting)
    ]
    assert mc.surviving_harmonics(cranks, strokes, acting, n_max=n_max) == expected


def test_surviving_harmonics_issue_example():
    assert mc.surviving_harmonics(10**18) == []
    assert mc.surviving_harmonics(10**18, n_max=2 * 10**18) == [10**18, 2 * 10**18]
    assert mc.surviving_harmonics(U64, 2, "double", n_max=U64) == [1]


@settings(max_examples=300, deadline=None)
@given(i=st.integers(1, 2**32 - 1), j=st.integers(0, 20))
def test_paper_coefficients_exact_for_any_index(i, j):
    """Issue 13, item 2: every coefficient the paper's formula defines for j ≤ 20 is exact
    (it once raised ZeroDivisionError from j = 15), compared with Python's big integers."""
    if j < i - 1:
        expected = Fraction(0)
    else:
        expected = (-1) ** (i + 1) * Fraction(
            2 * i * math.comb(2 * j, j) * math.comb(2 * j + 2, j + 1 - i), (j + 1) * 4 ** (2 * j + 1)
        )
    assert mc.paper_coefficient(i, j) == expected


@pytest.mark.parametrize("j", [21, 22, 100, 2**31])
def test_paper_coefficient_beyond_j_20_is_refused_by_name(j):
    with pytest.raises(mc.MechanismError, match=f"j = {j}"):
        mc.paper_coefficient(1, j)


@pytest.mark.parametrize(
    "args",
    [
        dict(cranks=0),
        dict(cranks=2.5),
        dict(cranks=3, strokes=3),
        dict(cranks=3, acting="triple"),
        dict(cranks=3, n_max=-2),
    ],
)
def test_surviving_harmonics_invalid_input(args):
    with pytest.raises(mc.MechanismError):
        mc.surviving_harmonics(**args)


@pytest.mark.parametrize("strokes,acting", KINDS)
def test_crank_phases_are_the_regular_sets(strokes, acting):
    for k in range(1, 13):
        np.testing.assert_allclose(
            mc.crank_phases(k, strokes, acting), regular_phases(k, strokes, acting), rtol=1e-15, atol=0
        )
