"""The speed fluctuation and energy extrema of gravity (docs/theory.md, "Speed fluctuation
due to gravity"), and rounding that is not physics (issue 13, item 9).

Every expected value here is computed independently of the formulas under test:

- δ and the extrema against max − min of U on a dense grid of the plain-numpy reference
  (with the grid's own error bound), and against mpmath root finding on the closed forms of
  U and Q (40 digits; for regular sets that cancel all but a tiny harmonic, at the exact
  phases 2πj/k);
- closed-form cases: Q ≡ 0 (γ = 0, regular sets), the flat single crank δ = 2·u1;
- horizontal opposed layouts and inclinations typed in degrees: the terms that vanish at
  such angles are exactly zero, and the series agrees with the planar-geometry reference.

Tolerances are relative to the scales and helpers of tests/gravity/test_harmonics.py, where
they are explained; λ → 1 (0.9999 … 0.999999) is valid input and held to the same promises.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from mpmath import mp, mpf

import multicrank as mc
import multicrank.reference as ref
from tests.gravity.test_harmonics import (
    PI,
    RANDOM_PHASES,
    V8_CROSS_PLANE,
    energy_scale,
    machines,
    natural_scale,
    q_mp,
    regular_phases,
    regular_phases_mp,
    u_mp,
)

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
