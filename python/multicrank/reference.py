"""The plain-numpy reference: obviously correct, never fast.

Same signatures as the public API. Each function is the paper's formula written the
obvious way — a Python loop over the k cranks, each crank one vectorised numpy expression
over all φ, accumulated into one output array (the baseline of BENCHMARKS.md). It is the test
oracle for the Rust kernels and the baseline every benchmark ratio is quoted against.
"""

from __future__ import annotations

from fractions import Fraction
from math import comb
from typing import Any

import numpy as np

from ._broadcasting import as_angles, as_design, as_phases, broadcast_designs, design_keywords, finish
from ._validation import as_count, as_option

__all__ = ["force_derivative", "generalized_force", "lambda_coefficients", "potential_energy"]


def _prepare(phi: Any, crank_ratio: Any, inclination: Any, u1: Any, u2: Any, phases: Any) -> tuple[Any, ...]:
    angles = as_angles(phi)
    shape, design = broadcast_designs(**design_keywords(crank_ratio, inclination, u1, u2))
    # Design axes first, then φ's axes: result shape D + phi.shape.
    expand = (...,) + (np.newaxis,) * angles.ndim
    lam, gamma, u1_, u2_ = (v.reshape(shape)[expand] for v in design.values())
    return angles, lam, gamma, u1_, u2_, as_phases(phases), shape + angles.shape


def _root(lam: np.ndarray, cos: np.ndarray) -> np.ndarray:
    """√(1 − λ² sin²ψ), formed as √((1 − λ)(1 + λ) + λ² cos²ψ): the same number, without
    the cancellation of 1 − λ² sin²ψ near ψ = π/2 as λ → 1 (at λ = 1 − 10⁻⁶ the first form
    keeps only ~6 of its digits there)."""
    return np.sqrt((1 - lam) * (1 + lam) + lam**2 * cos**2)


def potential_energy(
    phi: Any, *, crank_ratio: Any, inclination: Any, u1: Any, u2: Any, phases: Any = None
) -> np.ndarray | np.float64:
    """U_w*(φ) = Σ_j U2[sin(ψ_j+γ) − sin γ] − U1 (s(ψ_j)/r) sin γ, ψ_j = φ + α_j (eq. 3, 12)."""
    phi, lam, gamma, u1, u2, alphas, shape = _prepare(phi, crank_ratio, inclination, u1, u2, phases)
    total = np.zeros(shape)
    for alpha in alphas:
        psi = phi + alpha
        sin2, cos = np.sin(psi) ** 2, np.cos(psi)
        stroke = (1 - cos) + lam * sin2 / (1 + _root(lam, cos))  # s/r, stable form
        total += u2 * (np.sin(psi + gamma) - np.sin(gamma)) - u1 * stroke * np.sin(gamma)
    return finish(total, shape)


def generalized_force(
    phi: Any, *, crank_ratio: Any, inclination: Any, u1: Any, u2: Any, phases: Any = None, method: str = "exact"
) -> np.ndarray | np.float64:
    """Q_u*(φ) = Σ_j U2 cos(ψ_j+γ) − U1 [sin ψ_j + λ sin 2ψ_j / (2√(1 − λ² sin² ψ_j))] sin γ (eq. 13)."""
    method = as_option(method, "method", ("exact", "series", "paper"))
    phi, lam, gamma, u1, u2, alphas, shape = _prepare(phi, crank_ratio, inclination, u1, u2, phases)
    if method != "exact":
        return finish(_fourier_force(phi, lam, gamma, u1, u2, alphas, shape, method), shape)
    total = np.zeros(shape)
    for alpha in alphas:
        psi = phi + alpha
        sin, cos = np.sin(psi), np.cos(psi)
        total += u2 * np.cos(psi + gamma) - u1 * (sin + lam * sin * cos / _root(lam, cos)) * np.sin(gamma)
    return finish(total, shape)


def force_derivative(
    phi: Any, *, crank_ratio: Any, inclination: Any, u1: Any, u2: Any, phases: Any = None
) -> np.ndarray | np.float64:
    """dQ_u*/dφ = Σ_j −U2 sin(ψ_j+γ) − U1 [cos ψ_j + λ (cos 2ψ_j + λ² sin⁴ψ_j)/(1 − λ² sin²ψ_j)^{3/2}] sin γ."""
    phi, lam, gamma, u1, u2, alphas, shape = _prepare(phi, crank_ratio, inclination, u1, u2, phases)
    total = np.zeros(shape)
    for alpha in alphas:
        psi = phi + alpha
        sin2, cos = np.sin(psi) ** 2, np.cos(psi)
        root = _root(lam, cos)
        # cos 2ψ + λ² sin⁴ψ written as cos²ψ − sin²ψ·(1 − λ² sin²ψ), without cancellation
        curvature = lam * (cos**2 - sin2 * root**2) / root**3
        total += -u2 * np.sin(psi + gamma) - u1 * (np.cos(psi) + curvature) * np.sin(gamma)
    return finish(total, shape)


def _paper_coefficient(i: int, j: int) -> Fraction:
    """[λ^{2j+1}] Λ_{2i} = (−1)^{i+1}·(2i/(j+1))·C(2j, j)·C(2j+2, j+1−i)/4^{2j+1} (eq. 15)."""
    if j < i - 1:
        return Fraction(0)
    return (-1) ** (i + 1) * Fraction(2 * i * comb(2 * j, j) * comb(2 * j + 2, j + 1 - i), (j + 1) * 4 ** (2 * j + 1))


def _binomial_half(b: int) -> float:
    """C(1/2, b) exactly as a fraction, then rounded."""
    value = Fraction(1)
    for i in range(b):
        value *= Fraction(1, 2) - i
        value /= i + 1
    return float(value)


def lambda_coefficients(crank_ratio: Any, n_max: int, method: str = "exact") -> np.ndarray:
    """Λ_0 … Λ_{n_max} in plain floating point.

    "exact": Λ_{2m} = 2m Σ_{b≥0} C(½, b) C(½, b+m) t^{2m+4b−1}, t = λ/(1 + √(1 − λ²)),
    summed until the terms vanish (double precision throughout, so the relative error grows
    like n·ε). "paper": the λ-series through λ¹¹ with exact rational coefficients, n ≤ 12.
    """
    lam = as_design(crank_ratio, "crank_ratio", low=0.0, high=1.0)
    n_max = as_count(n_max, "n_max", minimum=0)
    method = as_option(method, "method", ("exact", "paper"))
    out = np.zeros((*lam.shape, n_max + 1))
    t = lam / (1 + np.sqrt(1 - lam**2))
    for n in range(2, n_max + 1, 2):
        m = n // 2
        if method == "paper":
            if n <= 12:
                out[..., n] = sum(float(_paper_coefficient(m, j)) * lam ** (2 * j + 1) for j in range(m - 1, 6))
            continue
        total = np.zeros(lam.shape)
        for b in range(0, 2000):
            term = _binomial_half(b) * _binomial_half(b + m) * t ** (2 * m + 4 * b - 1)
            total = total + term
            if np.all(np.abs(term) <= 1e-18 * np.abs(total)):
                break
        out[..., n] = 2 * m * total
    return out


def _fourier_force(
    phi: np.ndarray,
    lam: np.ndarray,
    gamma: np.ndarray,
    u1: np.ndarray,
    u2: np.ndarray,
    alphas: np.ndarray,
    shape: tuple[int, ...],
    method: str,
) -> np.ndarray:
    """Q_u* summed crank by crank from its Fourier form (eq. 14):
    Q = N cos ψ + W1 sin ψ + Σ_{n even} N1 Λ_n sin nψ with N = U2 cos γ, N1 = −U1 sin γ,
    W1 = N1 − U2 sin γ. "paper": Λ_n of the λ-series, n ≤ 12; "series": exact Λ_n up to
    the harmonic where t^{n−1} < 1e-18 (at most 400)."""
    if method == "paper":
        n_top = 12
    else:
        t = float(np.max(lam / (1 + np.sqrt(1 - lam**2)), initial=0.0))
        n_top = 2 if t == 0 else int(min(400, max(2, 2 * np.ceil((1 - 18 * np.log(10) / np.log(t)) / 2))))
    lambdas = lambda_coefficients(lam, n_top, method="exact" if method == "series" else "paper")
    big_n = u2 * np.cos(gamma)
    n1 = -u1 * np.sin(gamma)
    w1 = n1 - u2 * np.sin(gamma)
    total = np.zeros(shape)
    for alpha in alphas:
        psi = phi + alpha
        total += big_n * np.cos(psi) + w1 * np.sin(psi)
        for n in range(2, n_top + 1, 2):
            total += n1 * lambdas[..., n] * np.sin(n * psi)
    return total
