"""Evaluation of U_w*(φ) and Q_u*(φ) over crank-angle grids and design arrays
(docs/theory.md, "Potential energy and generalised force").

All design keywords broadcast together, numpy-style, to a design shape D; the result has
shape D + phi.shape. The work runs in the Rust core with the GIL released, in parallel
above a size threshold (see :func:`set_parallel_threshold`); results do not depend on the
thread count.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._native import evaluate as _native_evaluate
from ._native import get_parallel_threshold as _native_get_parallel_threshold
from ._native import set_parallel_threshold as _native_set_parallel_threshold
from ._validation import (
    as_option,
    as_phases,
    as_threshold,
    as_work_size,
    broadcast_designs,
    broadcast_shape,
    check_size,
    design_keywords,
    finish,
)
from .grids import as_phi

__all__ = [
    "FORCE_METHODS",
    "force_derivative",
    "generalized_force",
    "get_parallel_threshold",
    "potential_energy",
    "set_parallel_threshold",
]

FORCE_METHODS = ("exact", "series", "paper")


def _evaluate(
    quantity: str,
    phi: Any,
    crank_ratio: Any,
    inclination: Any,
    u1: Any,
    u2: Any,
    phases: Any,
    parallel_threshold: Any = None,
) -> np.ndarray | np.float64:
    """`quantity` ("potential_energy", "generalized_force", "force_derivative" or, through
    the Fourier form, "series" / "paper") of the broadcast designs over all of φ."""
    phi_shape, angles = as_phi(phi)
    keywords = design_keywords(crank_ratio, inclination, u1, u2)
    designs, points = math.prod(broadcast_shape("design parameters", keywords)), math.prod(phi_shape)
    check_size("phi", f"{points} points for {designs} designs", designs * points)
    shape, design = broadcast_designs(**keywords)
    flat = _native_evaluate(quantity, angles, design, as_phases(phases), as_threshold(parallel_threshold))
    return finish(flat, shape + phi_shape)


def potential_energy(phi, *, crank_ratio, inclination, u1, u2, phases=None, parallel_threshold=None):
    """Dimensionless potential energy U_w*(φ) = U_w/(I_w ω²) of a k-crank machine (eq. 3, 12).

    .. math::

        U_w^*(\\varphi) = \\sum_j U_2[\\sin(\\psi_j+\\gamma) - \\sin\\gamma]
                         - U_1 \\frac{s(\\psi_j)}{r}\\sin\\gamma, \\qquad \\psi_j = \\varphi + \\alpha_j,

    with s(ψ)/r = (1 − cos ψ) + (1 − √(1 − λ² sin² ψ))/λ the piston's travel from outer dead
    centre. Each crank unit is measured from its own ψ_j = 0 position.

    Parameters
    ----------
    phi : array_like, crank angle φ [rad] from outer dead centre of crank 0; any shape.
        NaN or ±inf give NaN in that place. A :class:`UniformGrid` (see
        :func:`uniform_grid`) is evaluated by rotation, faster; each point's value then
        agrees with the same point given alone to ~1e-15 relative, not bit for bit.
    crank_ratio : λ = r/l, 0 ≤ λ < 1 (λ = 0 is the infinite-rod limit)
    inclination : γ [rad], cylinder axis to the horizontal; +π/2 upright, −π/2 inverted
    u1, u2 : dimensionless gravity moments (see :func:`dimensionless_moments`)
    phases : 1-D array_like of crank phases α_j [rad]; None means one crank at 0
        (see :func:`crank_phases`).
    parallel_threshold : int, optional
        The work size (output points × cranks) from which this call runs on all cores;
        None uses the global default (:func:`set_parallel_threshold`). Results are
        bit-identical either way.

    Returns
    -------
    ndarray of shape D + phi.shape (D: the broadcast shape of the design keywords), or a
    numpy float64 for all-scalar input.
    """
    return _evaluate("potential_energy", phi, crank_ratio, inclination, u1, u2, phases, parallel_threshold)


def generalized_force(phi, *, crank_ratio, inclination, u1, u2, phases=None, method="exact", parallel_threshold=None):
    """Generalised Lagrange force due to gravity, Q_u*(φ) = +dU_w*/dφ (eq. 13).

    .. math::

        Q_u^*(\\varphi) = \\sum_j U_2\\cos(\\psi_j+\\gamma)
            - U_1\\Big[\\sin\\psi_j
                + \\frac{\\lambda\\sin 2\\psi_j}{2\\sqrt{1-\\lambda^2\\sin^2\\psi_j}}\\Big]\\sin\\gamma.

    The gravity torque on the shaft is −Q_u*·I_w ω². Parameters and result shape as in
    :func:`potential_energy`.

    method : str
        ``"exact"``: the closed form, eq. (13), summed over the cranks. Its rounding is
        ~1e-15 of each crank's own terms (``|U1| + |U2|``), not of ``max|Q|``: where the crank sum
        cancels nearly all of Q (an in-line eleven four-stroke keeps only harmonic 22,
        ``max|Q|`` ~1e-17 per unit U1) it can exceed ``max|Q|`` by orders of magnitude; use
        ``"series"`` there.
        ``"series"``: the Fourier form (eq. 14–16) with exact Λ_n, keeping only the harmonics
        that survive the crank sum and cut where a rigorous bound on the rest is below
        ε·max|Q|/2 (agrees with "exact" to ~1e-15 relative to max|Q|). Evaluated by rotation
        recurrences, so its cost per point hardly depends on the number of cranks.
        ``"paper"``: eq. (16) as the paper computes it — Λ_n from the λ-series through λ¹¹,
        harmonics n ≤ 12 — to show the paper's truncation error.
    """
    method = as_option(method, "method", FORCE_METHODS)
    quantity = "generalized_force" if method == "exact" else method
    return _evaluate(quantity, phi, crank_ratio, inclination, u1, u2, phases, parallel_threshold)


def force_derivative(phi, *, crank_ratio, inclination, u1, u2, phases=None, parallel_threshold=None):
    """dQ_u*/dφ = d²U_w*/dφ², the closed form used for Newton steps on the extrema of U_w*.

    Parameters and result shape as in :func:`potential_energy`.
    """
    return _evaluate("force_derivative", phi, crank_ratio, inclination, u1, u2, phases, parallel_threshold)


def get_parallel_threshold() -> int:
    """The work size (output points × cranks) from which evaluation runs on all cores."""
    return _native_get_parallel_threshold()


def set_parallel_threshold(threshold: int) -> None:
    """Set the work size (output points × cranks) from which evaluation runs in parallel.

    0 means always parallel, a huge value always serial. Results are bit-identical either
    way. The number of threads is rayon's: set ``RAYON_NUM_THREADS`` before the first call.
    """
    _native_set_parallel_threshold(as_work_size(threshold, "threshold"))
