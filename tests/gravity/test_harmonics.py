"""The harmonics of Q_u* (docs/theory.md, "Fourier form and Λ_n", "Which harmonics survive"),
and the independent helpers that tests/gravity/test_harmonics_tables.py (the paper's power
series, surviving harmonics) and tests/gravity/test_harmonics_fluctuation.py (the speed
fluctuation, rounding that is not physics) import from here.

Every expected value here is computed independently of the formulas under test:

- Λ_n against mpmath quadrature of its defining integral (1/π)∫ f(ψ) sin nψ dψ at the
  *binary* value of λ (plus a spectrally exact trapezoid sum and the elliptic-integral form
  of Λ_2);
- Fourier coefficients against an FFT of the closed-form Q;
- the special cases eq. (19)–(22) written out from "Which harmonics survive".

Tolerances are stated relative to a "natural scale": k·(|u1|·(1 + max f) + |u2|), an upper
bound of Σ_j |term_j| of Q (max f ≤ λ/(2√(1−λ²))). Where regular crank sets cancel all but
a tiny harmonic, the closed form (eq. 13) carries rounding noise ~1e-16 of that scale while
the Fourier form does not; those cases are compared with 50-digit mpmath instead.

λ → 1 (0.9999 … 1 − 1e-12) is valid input; the tests marked "near_one" hold Λ_n, the
series form and (in test_harmonics_fluctuation.py) the speed fluctuation to the same
promises there.
"""

from __future__ import annotations

import math

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
