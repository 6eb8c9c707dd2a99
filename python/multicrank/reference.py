"""The plain-numpy reference: obviously correct, never fast.

Same signatures as the public API. Each function is the paper's formula written the
obvious way — a Python loop over the k cranks, each crank one vectorised numpy expression
over all φ, accumulated into one output array (performance.md's baseline). It is the test
oracle for the Rust kernels and the baseline every benchmark ratio is quoted against.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._api import MechanismError, as_angles, as_option, as_phases, design_keywords, finish

__all__ = ["potential_energy", "generalized_force", "force_derivative"]


def _prepare(phi: Any, crank_ratio: Any, inclination: Any, u1: Any, u2: Any, phases: Any):
    angles = as_angles(phi)
    design = design_keywords(crank_ratio, inclination, u1, u2)
    try:
        shape = np.broadcast_shapes(*(v.shape for v in design.values()))
    except ValueError:
        raise MechanismError("design parameters do not broadcast together") from None
    # Design axes first, then φ's axes: result shape D + phi.shape.
    expand = (...,) + (np.newaxis,) * angles.ndim
    lam, gamma, u1_, u2_ = (np.broadcast_to(v, shape)[expand] for v in design.values())
    return angles, lam, gamma, u1_, u2_, as_phases(phases), shape + angles.shape


def potential_energy(phi, *, crank_ratio, inclination, u1, u2, phases=None):
    """U_w*(φ) = Σ_j U2[sin(ψ_j+γ) − sin γ] − U1 (s(ψ_j)/r) sin γ, ψ_j = φ + α_j (eq. 3, 12)."""
    phi, lam, gamma, u1, u2, alphas, shape = _prepare(phi, crank_ratio, inclination, u1, u2, phases)
    total = np.zeros(shape)
    for alpha in alphas:
        psi = phi + alpha
        sin2 = np.sin(psi) ** 2
        stroke = (1 - np.cos(psi)) + lam * sin2 / (1 + np.sqrt(1 - lam**2 * sin2))  # s/r, stable form
        total += u2 * (np.sin(psi + gamma) - np.sin(gamma)) - u1 * stroke * np.sin(gamma)
    return finish(total, shape)


def generalized_force(phi, *, crank_ratio, inclination, u1, u2, phases=None, method="exact"):
    """Q_u*(φ) = Σ_j U2 cos(ψ_j+γ) − U1 [sin ψ_j + λ sin 2ψ_j / (2√(1 − λ² sin² ψ_j))] sin γ (eq. 13)."""
    method = as_option(method, "method", ("exact", "series", "paper"))
    if method != "exact":
        raise NotImplementedError(f"method={method!r} arrives with the harmonics")
    phi, lam, gamma, u1, u2, alphas, shape = _prepare(phi, crank_ratio, inclination, u1, u2, phases)
    total = np.zeros(shape)
    for alpha in alphas:
        psi = phi + alpha
        root = np.sqrt(1 - lam**2 * np.sin(psi) ** 2)
        total += u2 * np.cos(psi + gamma) - u1 * (np.sin(psi) + lam * np.sin(2 * psi) / (2 * root)) * np.sin(gamma)
    return finish(total, shape)


def force_derivative(phi, *, crank_ratio, inclination, u1, u2, phases=None):
    """dQ_u*/dφ = Σ_j −U2 sin(ψ_j+γ) − U1 [cos ψ_j + λ (cos 2ψ_j + λ² sin⁴ψ_j)/(1 − λ² sin²ψ_j)^{3/2}] sin γ."""
    phi, lam, gamma, u1, u2, alphas, shape = _prepare(phi, crank_ratio, inclination, u1, u2, phases)
    total = np.zeros(shape)
    for alpha in alphas:
        psi = phi + alpha
        sin2 = np.sin(psi) ** 2
        curvature = lam * (np.cos(2 * psi) + lam**2 * sin2**2) / (1 - lam**2 * sin2) ** 1.5
        total += -u2 * np.sin(psi + gamma) - u1 * (np.cos(psi) + curvature) * np.sin(gamma)
    return finish(total, shape)
