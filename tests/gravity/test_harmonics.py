"""The harmonics of Q_u* and the speed fluctuation (docs/theory.md, "Fourier form and Λ_n",
"Which harmonics survive", "Speed fluctuation due to gravity").

Every expected value here is computed independently of the formulas under test:

- Λ_n against mpmath quadrature of its defining integral (1/π)∫ f(ψ) sin nψ dψ at the
  *binary* value of λ (plus a spectrally exact trapezoid sum and the elliptic-integral form
  of Λ_2);
- the paper's rational coefficients against an exact expansion of f in λ (binomial series
  in exact rationals + Laurent polynomials in z = e^{iψ}; the same through sympy where it is
  installed) and against the decimals printed in the paper;
- surviving harmonics against numerical phase sums Σ_j e^{inα_j};
- Fourier coefficients against an FFT of the closed-form Q;
- the special cases eq. (19)–(22) written out from "Which harmonics survive";
- the speed fluctuation against a dense grid and against mpmath root finding on the
  closed forms of U and Q.

Tolerances are stated relative to a "natural scale": k·(|u1|·(1 + max f) + |u2|), an upper
bound of Σ_j |term_j| of Q (max f ≤ λ/(2√(1−λ²))). Where regular crank sets cancel all but
a tiny harmonic, the closed form (eq. 13) carries rounding noise ~1e-16 of that scale while
the Fourier form does not; those cases are compared with 50-digit mpmath instead.

λ → 1 (0.9999 … 1 − 1e-12) is valid input; the tests marked "near_one" hold Λ_n, the
series form and the speed fluctuation to the same promises there.
"""

from __future__ import annotations

import math
from fractions import Fraction

import mpmath
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from mpmath import mp, mpf

import multicrank as mc
import multicrank.reference as ref

PI = math.pi
KINDS = [(2, "single"), (4, "single"), (2, "double"), (4, "double")]


# --------------------------------------------------------------------------------------
# Independent helpers
# --------------------------------------------------------------------------------------


def regular_phases(k: int, strokes: int, acting: str) -> np.ndarray:
    """α_j = j·α, α = T/k (single) or T/(2k) (double), T = 2π or 4π (docs/theory.md, "Crank phases"),
    written out here."""
    period = 2 * PI if strokes == 2 else 4 * PI
    step = period / k if acting == "single" else period / (2 * k)
    return np.arange(k) * step


def regular_phases_mp(k: int, strokes: int, acting: str) -> list:
    """The same phases exactly (at the current mpmath precision)."""
    period = 2 * mp.pi if strokes == 2 else 4 * mp.pi
    step = period / k if acting == "single" else period / (2 * k)
    return [j * step for j in range(k)]


def phase_sum(n: int, alphas) -> complex:
    return complex(np.sum(np.exp(1j * n * np.asarray(alphas, dtype=float))))


def numerical_survivors(k: int, strokes: int, acting: str, n_max: int) -> list[int]:
    alphas = regular_phases(k, strokes, acting)
    candidates = [1, *list(range(2, n_max + 1, 2))]
    return [n for n in candidates if n <= n_max and abs(phase_sum(n, alphas)) > 1e-9]


def f_max(lam: float) -> float:
    """An upper bound of |f(ψ)| = |(λ/2) sin 2ψ / √(1 − λ² sin² ψ)|."""
    return lam / (2 * math.sqrt(1 - lam * lam))


def natural_scale(lam: float, u1: float, u2: float, k: int) -> float:
    """An upper bound of Σ_j |term_j| of Q (eq. 13)."""
    return k * (abs(u1) * (1 + f_max(lam)) + abs(u2))


def energy_scale(u1: float, u2: float, k: int) -> float:
    """An upper bound of |U_w*|: per unit |U2|·2 + |U1|·(s/r ≤ 2 + λ/(1+√(1−λ²)) < 3)."""
    return k * (2 * abs(u2) + 3 * abs(u1))


def f_numpy(psi, lam):
    return lam / 2 * np.sin(2 * psi) / np.sqrt(1 - lam**2 * np.sin(psi) ** 2)


def q_mp(phi, lam, gamma, u1, u2, alphas):
    """Eq. (13) in mpmath; all float arguments taken at their binary values."""
    L, G = mpf(lam), mpf(gamma)
    sin_g = mp.sin(G)
    total = mpf(0)
    for alpha in alphas:
        psi = mpf(phi) + alpha
        s = mp.sin(psi)
        total += (
            mpf(u2) * mp.cos(psi + G) - mpf(u1) * (s + L * mp.sin(2 * psi) / (2 * mp.sqrt(1 - L**2 * s**2))) * sin_g
        )
    return total


def u_mp(phi, lam, gamma, u1, u2, alphas):
    """U_w* ("Potential energy and generalised force") in mpmath: Σ_j U2[sin(ψ+γ) − sin γ] − U1 (s(ψ)/r) sin γ."""
    L, G = mpf(lam), mpf(gamma)
    sin_g = mp.sin(G)
    total = mpf(0)
    for alpha in alphas:
        psi = mpf(phi) + alpha
        s = mp.sin(psi)
        stroke = (1 - mp.cos(psi)) + L * s**2 / (1 + mp.sqrt(1 - L**2 * s**2))
        total += mpf(u2) * (mp.sin(psi + G) - sin_g) - mpf(u1) * stroke * sin_g
    return total


# --------------------------------------------------------------------------------------
# 1. Λ_n exact against quadrature
# --------------------------------------------------------------------------------------


def lambda_by_quadrature(lam: float, n: int, dps: int):
    """Λ_n = (1/π)∫_0^{2π} f(ψ) sin nψ dψ at the binary λ.

    For even n the integrand has period π and is symmetric about π/2 (f(π−ψ) = −f(ψ),
    sin n(π−ψ) = −sin nψ), so the integral is 4× the one over [0, π/2] — the quarter
    interval between the split points at multiples of π/2."""
    with mp.workdps(dps):
        L = mpf(lam)

        def integrand(p):
            return L / 2 * mp.sin(2 * p) / mp.sqrt(1 - L**2 * mp.sin(p) ** 2) * mp.sin(n * p)

        return 4 * mp.quad(integrand, [0, mp.pi / 2]) / mp.pi


def lambda_by_trapezoid(lam: float, n_max: int, dps: int, points: int = 512) -> list:
    """Λ_n by the trapezoid rule on [0, 2π): for a periodic analytic integrand its error is
    the aliased Λ_{M−n} ~ t^{M−n}, far below 1e-20 relative here."""
    with mp.workdps(dps):
        L = mpf(lam)
        out = [mpf(0)] * (n_max + 1)
        for m in range(points):
            p = 2 * mp.pi * m / points
            fv = L / 2 * mp.sin(2 * p) / mp.sqrt(1 - L**2 * mp.sin(p) ** 2)
            for n in range(2, n_max + 1, 2):
                out[n] += fv * mp.sin(n * p)
        return [2 * v / points for v in out]


def working_digits(lam: float, n: int) -> int:
    """Enough digits that the cancellation in the integral (Λ_n ~ t^{n−1}·λ⁰ against an
    integrand of size λ) leaves ≥ 30 correct digits."""
    t = lam / (1 + math.sqrt(1 - lam * lam))
    return 30 + max(0, math.ceil(-(n - 1) * math.log10(t)))


def assert_lambda_close(got: float, true, n: int, lam: float):
    if abs(true) < mpf("1e-300"):
        return  # underflows in double precision
    rel = abs((mpf(got) - true) / true)
    assert rel <= 1e-15 * n, f"Λ_{n}(λ={lam!r}) = {got!r}, true {mpmath.nstr(true, 20)}, rel err {mpmath.nstr(rel, 3)}"
    m = n // 2
    assert np.sign(got) == (-1) ** (m - 1)


@pytest.mark.parametrize("lam", [0.05, 0.3, 0.45, 0.7, 0.9, 0.95])
def test_lambda_exact_matches_quadrature(lam):
    got = mc.lambda_coefficients(lam, 40)
    assert got.shape == (41,)
    for n in range(2, 41, 2):
        assert_lambda_close(got[n], lambda_by_quadrature(lam, n, working_digits(lam, n)), n, lam)


def test_lambda_exact_tiny_lambda():
    """λ = 1e-6: Λ_40 ~ 1e-245, so the integral cancels ~240 digits; quadrature for a few n,
    the trapezoid sum for all even n ≤ 40."""
    lam = 1e-6
    got = mc.lambda_coefficients(lam, 40)
    trapezoid = lambda_by_trapezoid(lam, 40, working_digits(lam, 40))
    for n in range(2, 41, 2):
        assert_lambda_close(got[n], trapezoid[n], n, lam)
    for n in (2, 14, 40):
        assert_lambda_close(got[n], lambda_by_quadrature(lam, n, working_digits(lam, n)), n, lam)


def test_lambda_trapezoid_agrees_with_quadrature_at_large_lambda():
    """The trapezoid oracle itself, where aliasing would show first (λ = 0.95)."""
    lam = 0.95
    trapezoid = lambda_by_trapezoid(lam, 40, 40)
    got = mc.lambda_coefficients(lam, 40)
    for n in (2, 20, 40):
        quad = lambda_by_quadrature(lam, n, 40)
        assert abs(trapezoid[n] - quad) <= mpf("1e-30") * abs(quad)
    for n in range(2, 41, 2):
        assert_lambda_close(got[n], trapezoid[n], n, lam)


@pytest.mark.parametrize("lam", [0.99, 0.999, 0.9999999, 1 - 1e-12])
def test_lambda_exact_near_one(lam):
    """λ → 1 is inside the valid range (0 ≤ λ < 1). With λ taken at its binary value the
    computation needs only 1 − λ² = (1 − λ)(1 + λ) and t in extended precision, so the
    accuracy promise (≤ ~1e-15·n relative) still applies. The integrand's singularity sits
    ~√(2(1 − λ)) off the real axis at ψ = π/2, a split point, where tanh–sinh quadrature
    stays accurate (checked against ₂F₁ at 50 digits while writing this test)."""
    got = mc.lambda_coefficients(lam, 40)
    for n in range(2, 41, 2):
        assert_lambda_close(got[n], lambda_by_quadrature(lam, n, 40), n, lam)


def lambda_by_hypergeometric(lam: float, n: int):
    """Λ_n = 2m·C(½, m)·t^{2m−1}·₂F₁(−½, m − ½; m + 1; t⁴), m = n/2, at 40 digits (mpmath
    sums ₂F₁ near z = 1 by its own transformations)."""
    with mp.workdps(40):
        L, m = mpf(lam), n // 2
        t = L / (1 + mp.sqrt(1 - L**2))
        half = mpf(1) / 2
        return 2 * m * mp.binomial(half, m) * t ** (2 * m - 1) * mp.hyp2f1(-half, m - half, m + 1, t**4)


NEAR_ONE = [0.986, 0.99, 0.9999, 0.99999, 1 - 1e-8, 1 - 1e-12, 1 - 2**-52, 1 - 2**-53]


@pytest.mark.parametrize("lam", NEAR_ONE)
def test_lambda_exact_near_one_to_high_harmonics(lam):
    """Issue 13, item 4: Λ_n up to n = 4096 near λ = 1 — every regime of the ₂F₁ (the series
    about z = 1, Miller's recurrence, the power series) — is exact to the promise, and fast:
    at λ = 1 − 2⁻⁵³ a series once took 40 s (here the whole table is one call; the work per
    harmonic is bounded in the Rust tests)."""
    got = mc.lambda_coefficients(lam, 4096)
    for n in (2, 4, 6, 10, 20, 40, 98, 100, 102, 300, 1000, 2048, 3000, 4096):
        assert_lambda_close(got[n], lambda_by_hypergeometric(lam, n), n, lam)


@settings(max_examples=40, deadline=None)
@given(x=st.floats(0.0, 30.0), n=st.integers(1, 3000).map(lambda m: 2 * m))
def test_lambda_exact_anywhere_near_one(x, n):
    """λ = 1 − 10^−x/… spread from 0 to the last double below 1 (x = 30 clamps there)."""
    lam = min(1.0 - 10.0 ** (-x / 2) if x < 30 else 1.0, np.nextafter(1.0, 0.0))
    got = mc.lambda_coefficients(lam, n)
    assert_lambda_close(got[n], lambda_by_hypergeometric(lam, n), n, lam)


@pytest.mark.parametrize("lam", [1e-4, 0.1, 0.4, 0.8, 0.99])
def test_lambda_2_elliptic_form(lam):
    """Λ_2 = 8/(3πλ³)[(2 − λ²)E(λ) − 2(1 − λ²)K(λ)] (modulus λ; mpmath takes m = λ²)."""
    with mp.workdps(60):
        L = mpf(lam)
        m = L**2
        true = 8 / (3 * mp.pi * L**3) * ((2 - m) * mp.ellipe(m) - 2 * (1 - m) * mp.ellipk(m))
    got = mc.lambda_coefficients(lam, 2)[2]
    assert abs((mpf(got) - true) / true) <= 2e-15


@pytest.mark.parametrize("method", ["exact", "paper"])
def test_lambda_zero_entries_and_signs(method):
    lams = np.array([0.0, 1e-300, 1e-8, 0.2, 0.5, 0.9, 0.97])
    got = mc.lambda_coefficients(lams, 30, method=method)
    assert got.shape == (7, 31)
    assert got.dtype == np.float64
    assert np.all(got[:, 0] == 0.0)
    assert np.all(got[:, 1::2] == 0.0)
    assert np.all(got[0] == 0.0)  # λ = 0: f ≡ 0
    top = 30 if method == "exact" else 12
    for n in range(2, top + 1, 2):
        m = n // 2
        column = got[2:, n]
        nonzero = column[column != 0]
        assert np.all(np.sign(nonzero) == (-1) ** (m - 1)), (n, column)
    # nonzero where representable
    assert np.all(got[3:, 2] != 0) and np.all(got[4:, 12] != 0)
    if method == "paper":
        assert np.all(got[:, 13:] == 0.0)


def test_lambda_n_max_zero_and_broadcasting():
    assert mc.lambda_coefficients(0.3, 0).shape == (1,)
    assert mc.lambda_coefficients(0.3, 0)[0] == 0.0
    assert mc.lambda_coefficients([0.1, 0.2], 0).shape == (2, 1)
    assert mc.lambda_coefficients(0.3, 1).tolist() == [0.0, 0.0]
    lams = np.array([[0.1, 0.25, 0.5], [0.7, 0.0, 0.93]])
    for method in ("exact", "paper"):
        grid = mc.lambda_coefficients(lams, 16, method=method)
        assert grid.shape == (2, 3, 17)
        for idx in np.ndindex(lams.shape):
            np.testing.assert_array_equal(grid[idx], mc.lambda_coefficients(float(lams[idx]), 16, method=method))
    # non-contiguous, reversed, integer and list inputs
    base = np.linspace(0.0, 0.9, 10)
    np.testing.assert_array_equal(mc.lambda_coefficients(base[::-3], 8), mc.lambda_coefficients(base[::-3].copy(), 8))
    np.testing.assert_array_equal(mc.lambda_coefficients(0, 4), np.zeros(5))
    np.testing.assert_array_equal(mc.lambda_coefficients([0.3], 4)[0], mc.lambda_coefficients(0.3, 4))


@pytest.mark.parametrize("lam", [0.0, 1e-3, 0.2, 0.45, 0.8, 0.95])
def test_lambda_matches_reference(lam):
    got = mc.lambda_coefficients(lam, 60)
    slow = ref.lambda_coefficients(lam, 60)
    for n in range(2, 61, 2):
        if abs(slow[n]) > 1e-290:
            assert abs(got[n] - slow[n]) <= 4e-16 * n * abs(slow[n]), n
    np.testing.assert_allclose(
        mc.lambda_coefficients(lam, 20, method="paper"),
        ref.lambda_coefficients(lam, 20, method="paper"),
        rtol=1e-15,
        atol=0,
    )


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(crank_ratio=1.0, n_max=4),
        dict(crank_ratio=-0.1, n_max=4),
        dict(crank_ratio=float("nan"), n_max=4),
        dict(crank_ratio=0.3, n_max=-1),
        dict(crank_ratio=0.3, n_max=2.5),
        dict(crank_ratio=0.3, n_max=4, method="series"),
        dict(crank_ratio="0.3", n_max=4),
    ],
)
def test_lambda_invalid_input(kwargs):
    with pytest.raises(mc.MechanismError):
        mc.lambda_coefficients(**kwargs)


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


# --------------------------------------------------------------------------------------
# 4. Fourier coefficients against an FFT of the closed form
# --------------------------------------------------------------------------------------

V8_CROSS_PLANE = np.array([0.0, PI / 2, 3 * PI / 2, PI])
RANDOM_PHASES = np.random.default_rng(20240611).uniform(-PI, 3 * PI, size=5)

FOURIER_CASES = [
    (0.3, 1.0, 1.3, 0.7, None),
    (0.95, PI / 2, 1.0, -0.4, None),
    (0.45, -0.6, 2.0, 0.5, V8_CROSS_PLANE),
    (0.95, 2.5, 0.8, 1.1, V8_CROSS_PLANE),
    (0.7, 0.3, 1.5, -0.9, RANDOM_PHASES),
    (0.95, -2.0, 0.6, 0.6, RANDOM_PHASES),
    (0.3, 1.2, 1.0, 0.3, regular_phases(3, 2, "single")),
    (0.9, 1.2, 1.0, 0.3, regular_phases(5, 2, "double")),
    (0.6, -1.0, 1.0, 0.3, regular_phases(6, 4, "single")),
    (0.0, 0.7, 1.0, 0.3, regular_phases(2, 2, "single")),
]


@pytest.mark.parametrize("lam,gamma,u1,u2,phases", FOURIER_CASES)
def test_fourier_coefficients_match_fft(lam, gamma, u1, u2, phases):
    size = 4096
    phi = 2 * PI * np.arange(size) / size
    design = dict(crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=phases)
    q = mc.generalized_force(phi, **design)
    spectrum = np.fft.rfft(q)
    n_max = 200
    fa = 2 * spectrum.real[: n_max + 1] / size
    fb = -2 * spectrum.imag[: n_max + 1] / size
    fa[0] = spectrum.real[0] / size
    fb[0] = 0.0
    a, b = mc.fourier_coefficients(**design, n_max=n_max)
    assert a.shape == b.shape == (n_max + 1,)
    k = 1 if phases is None else len(phases)
    scale = natural_scale(lam, u1, u2, k)
    assert np.max(np.abs(a - fa)) <= 1e-13 * scale
    assert np.max(np.abs(b - fb)) <= 1e-13 * scale
    assert a[0] == 0.0 and b[0] == 0.0
    assert np.all(a[3::2] == 0.0) and np.all(b[3::2] == 0.0)
    # the coefficients carry the whole of Q
    rebuilt = sum(a[n] * np.cos(n * phi) + b[n] * np.sin(n * phi) for n in range(1, n_max + 1))
    assert np.max(np.abs(rebuilt - q)) <= 1e-13 * scale


def test_fourier_coefficients_first_harmonic_by_hand():
    """One crank: a_1 = N = U2 cos γ, b_1 = W1 = −(U1 + U2) sin γ, b_n = −U1 sin γ Λ_n."""
    lam, gamma, u1, u2 = 0.35, 0.8, 1.7, -0.6
    a, b = mc.fourier_coefficients(crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, n_max=12)
    assert a[1] == pytest.approx(u2 * math.cos(gamma), rel=1e-15)
    assert b[1] == pytest.approx(-(u1 + u2) * math.sin(gamma), rel=1e-15)
    lambdas = mc.lambda_coefficients(lam, 12)
    for n in range(2, 13, 2):
        assert a[n] == 0.0
        assert b[n] == pytest.approx(-u1 * math.sin(gamma) * lambdas[n], rel=1e-15)


def test_fourier_coefficients_broadcast():
    lam = np.array([[0.1], [0.4], [0.8]])
    u1 = np.array([1.0, 2.0])
    a, b = mc.fourier_coefficients(crank_ratio=lam, inclination=1.0, u1=u1, u2=0.2, phases=V8_CROSS_PLANE, n_max=10)
    assert a.shape == b.shape == (3, 2, 11)
    for i, j in np.ndindex(3, 2):
        sa, sb = mc.fourier_coefficients(
            crank_ratio=lam[i, 0], inclination=1.0, u1=u1[j], u2=0.2, phases=V8_CROSS_PLANE, n_max=10
        )
        np.testing.assert_array_equal(a[i, j], sa)
        np.testing.assert_array_equal(b[i, j], sb)
    a, b = mc.fourier_coefficients(crank_ratio=0.3, inclination=1.0, u1=1.0, u2=0.2)
    assert a.shape == b.shape == (25,)


# --------------------------------------------------------------------------------------
# 5. series / paper against exact
# --------------------------------------------------------------------------------------

nonzero_moment = st.one_of(st.just(0.0), st.floats(1e-3, 4.0), st.floats(-4.0, -1e-3))


@st.composite
def machines(draw):
    if draw(st.booleans()):
        k = draw(st.integers(1, 12))
        phases = regular_phases(k, draw(st.sampled_from([2, 4])), draw(st.sampled_from(["single", "double"])))
    else:
        phases = np.array(draw(st.lists(st.floats(-10.0, 10.0), min_size=1, max_size=12)))
    return dict(
        crank_ratio=draw(st.floats(0.0, 0.95)),
        inclination=draw(st.one_of(st.floats(-PI, PI), st.sampled_from([0.0, PI / 2, -PI / 2, PI]))),
        u1=draw(nonzero_moment),
        u2=draw(nonzero_moment),
        phases=phases,
    )


PHI_GRID = np.concatenate([np.linspace(0, 2 * PI, 181), [-5.0, -0.3, 7.5, 12.0]])


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(machine=machines())
def test_series_matches_exact(machine):
    exact = mc.generalized_force(PHI_GRID, **machine)
    series = mc.generalized_force(PHI_GRID, **machine, method="series")
    slow_series = ref.generalized_force(PHI_GRID, **machine, method="series")
    scale = natural_scale(machine["crank_ratio"], machine["u1"], machine["u2"], len(machine["phases"]))
    peak = np.max(np.abs(exact))
    tolerance = 4e-15 * peak + 1e-15 * scale
    assert np.max(np.abs(series - exact)) <= tolerance
    assert np.max(np.abs(series - slow_series)) <= tolerance


@pytest.mark.parametrize("k", [7, 9, 11, 12])
def test_series_in_cancelling_regular_sets(k):
    """Two-stroke single acting, λ = 0.3: the crank sum leaves only harmonics n = k·(even)
    (k = 7: max|Q| ~ 5e-11, k = 11: ~ 2e-17 of the single-crank terms). The series must
    carry that remnant to ~1e-14 relative; the truth is the closed form at 50 digits with
    the exact regular phases 2πj/k.

    (At the binary phases mpf(float α_j) the 50-digit closed form also contains a spurious
    first harmonic ~1e-16·k·(|u1| + |u2|) from the rounding of α_j; the library treats that
    phase sum as cancelled, so it is checked against the binary-phase truth only to that
    absolute level.)"""
    lam, gamma, u1, u2 = 0.3, 1.1, 1.3, 0.7
    phases = regular_phases(k, 2, "single")
    phi = np.linspace(0, 2 * PI, 97)
    design = dict(crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=phases)
    series = mc.generalized_force(phi, **design, method="series")
    with mp.workdps(50):
        exact_phases = regular_phases_mp(k, 2, "single")
        true = np.array([float(q_mp(p, lam, gamma, u1, u2, exact_phases)) for p in phi])
        binary = np.array([float(q_mp(p, lam, gamma, u1, u2, [mpf(a) for a in phases])) for p in phi])
    peak = np.max(np.abs(true))
    assert peak > 0
    assert np.max(np.abs(series - true)) <= 1e-14 * peak
    scale = natural_scale(lam, u1, u2, k)
    assert np.max(np.abs(series - binary)) <= 2e-15 * scale
    # the closed form (exact) is only good to its rounding noise here
    exact = mc.generalized_force(phi, **design)
    assert np.max(np.abs(exact - true)) <= 1e-15 * scale


@pytest.mark.parametrize("lam", [0.9999, 0.99999, 0.999999])
def test_series_near_lambda_one(lam):
    """λ → 1 (valid input): f develops a spike of width ~√(1 − λ²) at ψ = π/2 and its
    spectrum decays only like t^n, t → 1. Q itself is then ill-conditioned (internal
    rounding of 1 − λ² sin²ψ costs ~ε/(1 − λ) relative), so the bound here is
    10·ε/(1 − λ)·max|Q| against 30-digit mpmath — still far below any truncation error."""
    gamma, u1, u2 = 1.1, 1.3, 0.4
    phi = np.linspace(0, 2 * PI, 721)
    with mp.workdps(30):
        true = np.array([float(q_mp(p, lam, gamma, u1, u2, [mpf(0)])) for p in phi])
    peak = np.max(np.abs(true))
    tolerance = max(1e-14, 10 * np.finfo(float).eps / (1 - lam)) * peak
    design = dict(crank_ratio=lam, inclination=gamma, u1=u1, u2=u2)
    exact = mc.generalized_force(phi, **design)
    assert np.max(np.abs(exact - true)) <= tolerance
    series = mc.generalized_force(phi, **design, method="series")
    assert np.max(np.abs(series - true)) <= tolerance, np.max(np.abs(series - true)) / peak


@pytest.mark.parametrize("lam", [0.1, 0.3, 0.4, 0.5])
@pytest.mark.parametrize(
    "phases",
    [
        None,
        regular_phases(2, 2, "single"),
        regular_phases(4, 4, "single"),
        regular_phases(7, 2, "single"),
        RANDOM_PHASES,
    ],
    ids=["k1", "k2", "k4-four-stroke", "k7", "random"],
)
def test_paper_method_truncation(lam, phases):
    gamma, u1, u2 = 1.2, 1.5, 0.4
    phi = np.linspace(0, 2 * PI, 721)
    design = dict(crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=phases)
    k = 1 if phases is None else len(phases)
    scale = natural_scale(lam, u1, u2, k)
    exact = mc.generalized_force(phi, **design)
    paper = mc.generalized_force(phi, **design, method="paper")
    bound = 3 * 0.037 * lam**13 * k * abs(u1 * math.sin(gamma))
    difference = np.max(np.abs(paper - exact))
    assert difference <= bound + 1e-15 * scale
    if phases is None or k == 2:
        # even harmonics survive: the truncation shows, at the expected size
        assert difference >= 0.3 * 0.037 * lam**13 * k * abs(u1 * math.sin(gamma))
    slow = ref.generalized_force(phi, **design, method="paper")
    assert np.max(np.abs(paper - slow)) <= 1e-14 * scale


def test_paper_method_cuts_at_n_12():
    """k = 7 two-stroke: nothing survives up to n = 12, so the paper's Q is 0 ('negligible')."""
    phi = np.linspace(0, 2 * PI, 50)
    design = dict(crank_ratio=0.4, inclination=1.0, u1=1.0, u2=0.5, phases=regular_phases(7, 2, "single"))
    paper = mc.generalized_force(phi, **design, method="paper")
    assert np.max(np.abs(paper)) <= 1e-15 * natural_scale(0.4, 1.0, 0.5, 7)
    exact_remnant = mc.generalized_force(phi, **design, method="series")
    assert np.max(np.abs(exact_remnant)) > 1e-10  # the true Q is not zero


# --------------------------------------------------------------------------------------
# 6. Special cases, eq. (19)–(22)
# --------------------------------------------------------------------------------------

SPECIAL_PHASES = [None, regular_phases(3, 2, "single"), regular_phases(4, 4, "single"), V8_CROSS_PLANE, RANDOM_PHASES]


@pytest.mark.parametrize("phases", SPECIAL_PHASES, ids=["k1", "k3", "k4-four", "v8", "random"])
@pytest.mark.parametrize("gamma,sign", [(0.0, 1.0), (PI, -1.0)])
def test_horizontal_engines(phases, gamma, sign):
    """γ = 0: Q = N Σ cos(φ + α_j), N = U2; γ = π: N = U2 cos π = −U2 (eq. 19–20)."""
    lam, u1, u2 = 0.6, 1.4, 0.9
    alphas = np.zeros(1) if phases is None else phases
    phi = np.linspace(-PI, 3 * PI, 401)
    expected = sign * u2 * np.sum(np.cos(phi[:, None] + alphas[None, :]), axis=1)
    scale = natural_scale(lam, u1, u2, len(alphas))
    for method in ("exact", "series"):
        got = mc.generalized_force(phi, crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=phases, method=method)
        assert np.max(np.abs(got - expected)) <= 1e-15 * scale, method


@pytest.mark.parametrize("strokes", [2, 4])
@pytest.mark.parametrize("k", list(range(1, 13)))
@pytest.mark.parametrize("lam", [0.3, 0.9])
@pytest.mark.parametrize("gamma", [PI / 2, -PI / 2])
def test_vertical_engines(strokes, k, lam, gamma):
    """γ = ±π/2, single acting regular sets: Q = k Σ_ν W_{νp} sin(νpφ) (eq. 21–22), with
    W_1 = N1 + N2 = −(U1 + U2) sin γ where n = 1 survives and W_n = N1 Λ_n = −U1 sin γ Λ_n;
    at −π/2 every W is minus its value at +π/2."""
    u1, u2 = 1.25, -0.45
    alphas = regular_phases(k, strokes, "single")
    n_top = 240
    survivors = [n for n in [1, *list(range(2, n_top + 1, 2))] if abs(phase_sum(n, alphas)) > 1e-9]
    for n in survivors:
        assert abs(phase_sum(n, alphas) - k) < 1e-9  # a surviving sum is k (single acting)
    sign = 1.0 if gamma > 0 else -1.0
    lambdas = mc.lambda_coefficients(lam, n_top)
    phi = np.linspace(0, 2 * PI, 361)
    expected = np.zeros_like(phi)
    for n in survivors:
        w = sign * (-(u1 + u2)) if n == 1 else sign * (-u1) * lambdas[n]
        expected += k * w * np.sin(n * phi)
    got = mc.generalized_force(phi, crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=alphas)
    scale = natural_scale(lam, u1, u2, k)
    assert np.max(np.abs(got - expected)) <= 2e-15 * scale


# --------------------------------------------------------------------------------------
# 7. Speed fluctuation and energy extrema ("Speed fluctuation due to gravity")
# --------------------------------------------------------------------------------------

FLUCTUATION_CASES = [
    (0.3, 1.0, 1.0, 0.5, None),
    (0.9, PI / 2, 1.0, -0.3, regular_phases(3, 2, "single")),
    (0.95, -2.0, 2.0, 0.5, V8_CROSS_PLANE),
    (0.45, 0.4, 1.5, -1.0, RANDOM_PHASES),
    (0.3, 1.0, 1.0, 0.5, regular_phases(7, 2, "single")),
    (0.6, -PI / 2, 0.8, 0.2, regular_phases(4, 4, "single")),
    (0.25, 2.9, 0.0, 1.3, regular_phases(2, 2, "double")),
    (0.8, 0.05, 3.0, 0.0, regular_phases(5, 4, "double")),
]


def check_fluctuation_against_grid(design: dict, size: int):
    """δ against max − min of U on a uniform grid of `size` points (plain-numpy reference
    energies, also compared with the library's on the grid), and the extrema themselves."""
    step = 2 * PI / size
    phi = np.arange(size + 1) * step
    lam, u1, u2 = design["crank_ratio"], design["u1"], design["u2"]
    k = 1 if design["phases"] is None else len(design["phases"])
    scale = energy_scale(u1, u2, k)
    u = ref.potential_energy(phi, **design)
    q = ref.generalized_force(phi, **design)
    assert np.max(np.abs(mc.potential_energy(phi, **design) - u)) <= 1e-14 * scale
    brute = np.max(u) - np.min(u)
    # a grid point lies within step/2 of each extremum: U misses by ≤ max|Q'|·step²/8 each
    curvature = 1.01 * np.max(np.abs(np.diff(q))) / step
    delta = mc.speed_fluctuation(**design)
    assert isinstance(delta, np.float64)
    assert delta >= brute - 1e-14 * scale
    assert delta - brute <= curvature * step**2 / 4 + 1e-14 * scale
    extrema = mc.energy_extrema(**design)
    assert extrema.range == delta
    # δ is taken before the constant level is added, so it may be finer than max − min
    assert abs((extrema.max - extrema.min) - delta) <= 2e-15 * scale
    assert extrema.min <= np.min(u) + 1e-14 * scale
    assert extrema.max >= np.max(u) - 1e-14 * scale
    for value, at in ((extrema.min, extrema.min_at), (extrema.max, extrema.max_at)):
        assert 0.0 <= at <= 2 * PI
        assert abs(mc.potential_energy(at, **design) - value) <= 2e-15 * scale
        assert abs(ref.potential_energy(at, **design) - value) <= 4e-15 * scale
        # an interior extremum of a smooth U is a root of Q
        assert abs(mc.generalized_force(at, **design)) <= 1e-12 * natural_scale(lam, u1, u2, k)


@pytest.mark.parametrize("lam,gamma,u1,u2,phases", FLUCTUATION_CASES)
def test_speed_fluctuation_against_dense_grid(lam, gamma, u1, u2, phases):
    check_fluctuation_against_grid(dict(crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=phases), 200_000)


@pytest.mark.parametrize("lam", [0.9999, 0.99999, 0.999999])
@pytest.mark.parametrize("phases", [None, V8_CROSS_PLANE], ids=["k1", "v8"])
def test_speed_fluctuation_near_lambda_one(lam, phases):
    """λ → 1 (valid input): Q has sharp features near ψ = π/2, but U stays well-conditioned,
    so the exact extrema must still bound every grid value."""
    check_fluctuation_against_grid(dict(crank_ratio=lam, inclination=1.1, u1=1.3, u2=0.4, phases=phases), 200_000)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(machine=machines())
def test_speed_fluctuation_against_grid_random_designs(machine):
    check_fluctuation_against_grid(machine, 50_000)


def mp_extrema(lam, gamma, u1, u2, alphas, samples=360):
    """min and max of U over a revolution: sign changes of Q on a grid, each root polished by
    mpmath.findroot (bracketing solver) on the mpmath closed form."""
    with mp.workdps(40):
        grid = [2 * mp.pi * i / samples for i in range(samples + 1)]
        values = [q_mp(p, lam, gamma, u1, u2, alphas) for p in grid]
        points = [mpf(0)]
        for a, b, qa, qb in zip(grid, grid[1:], values, values[1:], strict=False):  # neighbours
            if qa == 0:
                points.append(a)
            elif qa * qb < 0:
                points.append(mp.findroot(lambda p: q_mp(p, lam, gamma, u1, u2, alphas), (a, b), solver="anderson"))
        energies = [u_mp(p, lam, gamma, u1, u2, alphas) for p in points]
        return min(energies), max(energies), len(points)


@pytest.mark.parametrize(
    "lam,gamma,u1,u2,phases",
    [(0.3, 1.0, 1.0, 0.5, None), (0.95, -2.0, 2.0, 0.5, V8_CROSS_PLANE), (0.45, 0.4, 1.5, -1.0, RANDOM_PHASES)],
    ids=["single", "v8", "random"],
)
def test_speed_fluctuation_against_mpmath_roots(lam, gamma, u1, u2, phases):
    alphas_float = np.zeros(1) if phases is None else phases
    lo, hi, count = mp_extrema(lam, gamma, u1, u2, [mpf(a) for a in alphas_float])
    assert count >= 2
    design = dict(crank_ratio=lam, inclination=gamma, u1=u1, u2=u2, phases=phases)
    scale = energy_scale(u1, u2, len(alphas_float))
    delta = mc.speed_fluctuation(**design)
    assert abs(delta - float(hi - lo)) <= 1e-14 * scale
    extrema = mc.energy_extrema(**design)
    assert abs(extrema.min - float(lo)) <= 1e-14 * scale
    assert abs(extrema.max - float(hi)) <= 1e-14 * scale


@pytest.mark.parametrize("k", [7, 9, 12])
def test_speed_fluctuation_of_cancelling_regular_sets(k):
    """Two-stroke single acting, λ = 0.3: U varies only by its surviving harmonic n = k or
    2k (δ ~ 5e-12, 2e-15, 5e-10 for k = 7, 9, 12, on a level |U| ~ 10). δ is to be exact
    relative to itself, against the 40-digit extrema at the exact regular phases 2πj/k."""
    design = dict(crank_ratio=0.3, inclination=1.0, u1=1.0, u2=0.5, phases=regular_phases(k, 2, "single"))
    delta = mc.speed_fluctuation(**design)
    with mp.workdps(40):
        lo, hi, count = mp_extrema(0.3, 1.0, 1.0, 0.5, regular_phases_mp(k, 2, "single"), samples=720)
    true = float(hi - lo)
    assert count >= 2 * k
    assert abs(delta - true) <= 1e-12 * true


@pytest.mark.parametrize("k", [2, 3, 4, 7, 12])
def test_speed_fluctuation_zero_when_q_vanishes(k):
    """γ = 0 with a regular set of k ≥ 2: Q = U2 Σ cos(φ + α_j) ≡ 0, U ≡ const."""
    phases = regular_phases(k, 2, "single")
    delta = mc.speed_fluctuation(crank_ratio=0.4, inclination=0.0, u1=1.2, u2=0.8, phases=phases)
    assert 0.0 <= delta <= 1e-15 * energy_scale(1.2, 0.8, k)
    for gamma in (0.0, 1.0, -2.5, PI / 2):
        zero = mc.speed_fluctuation(crank_ratio=0.4, inclination=gamma, u1=0.0, u2=0.0, phases=phases)
        assert zero == 0.0


@pytest.mark.parametrize("u1", [0.25, 1.0, 3.7])
def test_speed_fluctuation_flat_single_crank(u1):
    """λ = 0, k = 1, γ = π/2, u2 = 0: U = −u1(1 − cos φ), so δ = 2·u1 (min at π, max at 0)."""
    design = dict(crank_ratio=0.0, inclination=PI / 2, u1=u1, u2=0.0)
    delta = mc.speed_fluctuation(**design)
    assert abs(delta - 2 * u1) <= 1e-15 * u1
    extrema = mc.energy_extrema(**design)
    assert abs(extrema.min + 2 * u1) <= 1e-15 * u1
    assert abs(extrema.max) <= 1e-15 * u1
    assert abs(extrema.min_at - PI) <= 1e-7
    assert min(abs(extrema.max_at), abs(extrema.max_at - 2 * PI)) <= 1e-7


def test_speed_fluctuation_broadcasting():
    lam = np.array([[0.1], [0.3], [0.5]])
    u1 = np.array([1.0, 2.0, 0.5, 0.0])
    design = dict(crank_ratio=lam, inclination=1.0, u1=u1, u2=0.2, phases=V8_CROSS_PLANE)
    delta = mc.speed_fluctuation(**design)
    assert delta.shape == (3, 4)
    assert delta.dtype == np.float64
    extrema = mc.energy_extrema(**design)
    for field in extrema:
        assert field.shape == (3, 4)
    for i, j in np.ndindex(3, 4):
        single = mc.speed_fluctuation(crank_ratio=lam[i, 0], inclination=1.0, u1=u1[j], u2=0.2, phases=V8_CROSS_PLANE)
        assert abs(delta[i, j] - single) <= 1e-15 * energy_scale(u1[j], 0.2, 4)
    scalar = mc.speed_fluctuation(crank_ratio=0.3, inclination=1.0, u1=1.0, u2=0.5)
    assert isinstance(scalar, np.float64)
    assert np.ndim(scalar) == 0
    for field in mc.energy_extrema(crank_ratio=0.3, inclination=1.0, u1=1.0, u2=0.5):
        assert isinstance(field, np.float64)


def test_speed_fluctuation_invalid_input():
    with pytest.raises(mc.MechanismError):
        mc.speed_fluctuation(crank_ratio=1.0, inclination=1.0, u1=1.0, u2=0.5)
    with pytest.raises(mc.MechanismError):
        mc.speed_fluctuation(crank_ratio=0.3, inclination=float("nan"), u1=1.0, u2=0.5)
    with pytest.raises(mc.MechanismError):
        mc.speed_fluctuation(crank_ratio=0.3, inclination=1.0, u1=1.0, u2=0.5, phases=[])


# ----------------------------------------------------------- rounding is not physics (issue 13, item 9)
@pytest.mark.parametrize("layout", ["boxer-2", "boxer-4", "boxer-6", "v-180-4"])
def test_gravity_of_horizontal_opposed_layouts_cancels_exactly(layout):
    """sin(np.radians(180)) = 1.2e-16, not 0: it used to leave 'surviving' harmonics of
    1e-17 and a leading harmonic of that size. Horizontal cylinders have no reciprocating
    gravity term at all, and the opposed rotating terms cancel."""
    engine = mc.layout_engine(layout, crank_ratio=0.3, u1=1.0, u2=0.2)
    assert engine.surviving_harmonics(24) == []
    assert engine.leading_harmonic() == (0, 0.0)
    assert engine.speed_fluctuation() == 0.0
    a, b = engine.fourier_coefficients(24)
    assert not a.any() and not b.any()


@given(
    quarter=st.integers(-40, 40),
    crank_ratio=st.floats(0.0, 0.9),
    u1=st.floats(-2.0, 2.0),
    u2=st.floats(-2.0, 2.0),
)
def test_an_axis_inclination_typed_in_degrees_has_no_rounding_harmonics(quarter, crank_ratio, u1, u2):
    """γ = q·90° reaches the library as a rounded double; the terms that vanish at that
    angle (sin γ for horizontal, cos γ for vertical cylinders) are exactly zero."""
    gamma = np.radians(90.0 * quarter)
    a, b = mc.fourier_coefficients(crank_ratio=crank_ratio, inclination=gamma, u1=u1, u2=u2, n_max=12)
    if quarter % 2 == 0:  # horizontal: Q = U2 cos(ψ + γ) only, the first harmonic
        assert not a[2:].any() and not b[2:].any()
        assert b[1] == 0.0  # W1 = −(U1 + U2) sin γ = 0
    else:  # vertical: no N = U2 cos γ term
        assert a[1] == 0.0
    # and they agree with the planar-geometry reference to the terms' rounding
    reference = ref.generalized_force(
        np.linspace(0, 2 * np.pi, 13), crank_ratio=crank_ratio, inclination=gamma, u1=u1, u2=u2
    )
    series = mc.generalized_force(
        np.linspace(0, 2 * np.pi, 13), crank_ratio=crank_ratio, inclination=gamma, u1=u1, u2=u2, method="series"
    )
    np.testing.assert_allclose(series, reference, rtol=0, atol=1e-13 * (abs(u1) + abs(u2) + 1))
