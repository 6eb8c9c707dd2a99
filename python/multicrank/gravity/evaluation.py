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

from .._broadcasting import as_phases, broadcast_designs, broadcast_shape, design_keywords, finish
from .._native import evaluate as _native_evaluate
from .._native import get_parallel_threshold as _native_get_parallel_threshold
from .._native import set_parallel_threshold as _native_set_parallel_threshold
from .._validation import as_option, as_threshold, as_work_size, check_size
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


def potential_energy(
    phi: Any,
    *,
    crank_ratio: Any,
    inclination: Any,
    u1: Any,
    u2: Any,
    phases: Any = None,
    parallel_threshold: Any = None,
) -> Any:
    r"""Dimensionless potential energy U_w*(φ) = U_w/(I_w ω²) of a k-crank machine.

    The paper's eq. (3) summed over the cranks, eq. (12):

    .. math::

        U_w^*(\varphi) = \sum_j U_2\,[\sin(\psi_j+\gamma) - \sin\gamma]
                         - U_1 \frac{s(\psi_j)}{r}\sin\gamma, \qquad \psi_j = \varphi + \alpha_j,

    with s(ψ)/r = (1 − cos ψ) + (1 − √(1 − λ² sin² ψ))/λ the piston's travel from outer dead
    centre. Each crank unit is measured from its own ψ_j = 0 position.

    Parameters
    ----------
    phi : array_like or UniformGrid
        Crank angle φ [rad] from the outer dead centre of crank 0; any shape. NaN or ±inf
        give NaN in that place. A :class:`UniformGrid` (see :func:`uniform_grid`) is
        evaluated by rotation, faster; each point's value then agrees with the same point
        given alone to ~1e-15 relative, not bit for bit.
    crank_ratio : array_like
        λ = r/l [dimensionless], 0 ≤ λ < 1 (λ = 0 is the infinite-rod limit).
    inclination : array_like
        γ [rad], the cylinder axis to the horizontal: +π/2 upright, −π/2 hanging, 0 and π
        lying.
    u1, u2 : array_like
        The dimensionless gravity moments U1 (reciprocating) and U2 (rotating unbalance)
        [dimensionless], see :func:`dimensionless_moments`.
    phases : array_like, optional
        The crank phases α_j [rad], 1-D (see :func:`crank_phases`); None means one crank at 0.
    parallel_threshold : int, optional
        The work size (output points × cranks) from which this call runs on all cores;
        None uses the global default (:func:`set_parallel_threshold`). Results are
        bit-identical either way.

    Returns
    -------
    ndarray or numpy.float64
        U_w* [dimensionless] of shape D + phi.shape, D being the broadcast shape of
        ``crank_ratio``, ``inclination``, ``u1`` and ``u2``; a numpy float64 for all-scalar
        input.

    Raises
    ------
    MechanismError
        For a parameter out of its range (naming it), design keywords that do not
        broadcast, or a result too large for memory.

    See Also
    --------
    generalized_force : Its derivative Q_u* = dU_w*/dφ.
    speed_fluctuation : max U_w* − min U_w* over a revolution, exactly.
    Engine.potential_energy : The same for cylinders of any layout.

    Examples
    --------
    One upright cylinder at outer dead centre, a quarter turn on, and inner dead centre:

    >>> import numpy as np
    >>> import multicrank as mc
    >>> phi = np.radians([0, 90, 180])
    >>> design = dict(crank_ratio=0.25, inclination=np.pi / 2, u1=1e-3, u2=2e-4)
    >>> mc.potential_energy(phi, **design).round(8)
    array([ 0.        , -0.00132702, -0.0024    ])

    Design keywords broadcast; the result has shape D + phi.shape:

    >>> lam = np.array([0.2, 0.3])[:, None]
    >>> gamma = np.radians([90, 60, 0])
    >>> U = mc.potential_energy(phi, crank_ratio=lam, inclination=gamma, u1=1e-3, u2=2e-4)
    >>> U.shape
    (2, 3, 3)
    """
    return _evaluate("potential_energy", phi, crank_ratio, inclination, u1, u2, phases, parallel_threshold)


def generalized_force(
    phi: Any,
    *,
    crank_ratio: Any,
    inclination: Any,
    u1: Any,
    u2: Any,
    phases: Any = None,
    method: str = "exact",
    parallel_threshold: Any = None,
) -> Any:
    r"""Generalised Lagrange force due to gravity, Q_u*(φ) = +dU_w*/dφ.

    The paper's eq. (13):

    .. math::

        Q_u^*(\varphi) = \sum_j U_2\cos(\psi_j+\gamma)
            - U_1\Big[\sin\psi_j
                + \frac{\lambda\sin 2\psi_j}{2\sqrt{1-\lambda^2\sin^2\psi_j}}\Big]\sin\gamma,
            \qquad \psi_j = \varphi + \alpha_j.

    The gravity torque on the shaft is −Q_u*·I_w ω² [N·m].

    Parameters
    ----------
    phi : array_like or UniformGrid
        Crank angle φ [rad] from the outer dead centre of crank 0; any shape. NaN or ±inf
        give NaN in that place. A :class:`UniformGrid` is evaluated by rotation, faster
        (see :func:`potential_energy`).
    crank_ratio : array_like
        λ = r/l [dimensionless], 0 ≤ λ < 1.
    inclination : array_like
        γ [rad], the cylinder axis to the horizontal (+π/2 upright).
    u1, u2 : array_like
        The dimensionless gravity moments [dimensionless], see :func:`dimensionless_moments`.
    phases : array_like, optional
        The crank phases α_j [rad], 1-D; None means one crank at 0.
    method : {"exact", "series", "paper"}, default "exact"
        ``"exact"``: the closed form above, eq. (13), summed over the cranks; its rounding
        is ~1e-15 of each crank's own terms (:math:`|U_1| + |U_2|`), not of
        :math:`\max|Q|`. Where the crank sum cancels nearly all of Q (an in-line eleven
        four-stroke keeps only harmonic 22, :math:`\max|Q|` ~1e-17 per unit U1) it can
        exceed :math:`\max|Q|` by orders of magnitude: use ``"series"`` there.
        ``"series"``: the Fourier form
        (eq. 14–16) with exact Λ_n, keeping only the harmonics that survive the crank sum
        and cut where a rigorous bound on the rest is below ε·max|Q|/2 (agrees with
        ``"exact"`` to ~1e-15 relative to max|Q|); evaluated by rotation recurrences, so its
        cost per point hardly depends on the number of cranks. ``"paper"``: eq. (16) as the
        paper computes it — Λ_n from the λ-series through λ¹¹, harmonics n ≤ 12 — to show the
        paper's truncation error.
    parallel_threshold : int, optional
        The work size (output points × cranks) from which this call runs on all cores;
        None uses the global default (:func:`set_parallel_threshold`).

    Returns
    -------
    ndarray or numpy.float64
        Q_u* [dimensionless, per radian] of shape D + phi.shape (D: the broadcast shape of
        the design keywords); a numpy float64 for all-scalar input.

    Raises
    ------
    MechanismError
        For a parameter out of its range or an unknown ``method``, naming it.

    See Also
    --------
    potential_energy : U_w*, of which this is the derivative.
    fourier_coefficients : The coefficients of the series form.
    force_derivative : dQ_u*/dφ.

    Examples
    --------
    >>> import numpy as np
    >>> import multicrank as mc
    >>> design = dict(crank_ratio=0.25, inclination=np.pi / 2, u1=1e-3, u2=2e-4)
    >>> phi = np.radians([45, 90, 135])
    >>> mc.generalized_force(phi, **design).round(8)
    array([-0.00097553, -0.0012    , -0.00072153])

    The series form agrees with the closed form to rounding:

    >>> phi = mc.uniform_grid(3600)
    >>> exact = mc.generalized_force(phi, **design)
    >>> series = mc.generalized_force(phi, **design, method="series")
    >>> bool(np.max(np.abs(series - exact)) < 1e-14 * np.max(np.abs(exact)))
    True
    """
    method = as_option(method, "method", FORCE_METHODS)
    quantity = "generalized_force" if method == "exact" else method
    return _evaluate(quantity, phi, crank_ratio, inclination, u1, u2, phases, parallel_threshold)


def force_derivative(
    phi: Any,
    *,
    crank_ratio: Any,
    inclination: Any,
    u1: Any,
    u2: Any,
    phases: Any = None,
    parallel_threshold: Any = None,
) -> Any:
    """dQ_u*/dφ = d²U_w*/dφ², the closed form used for Newton steps on the extrema of U_w*.

    Parameters
    ----------
    phi : array_like or UniformGrid
        Crank angle φ [rad] from the outer dead centre of crank 0; any shape.
    crank_ratio : array_like
        λ = r/l [dimensionless], 0 ≤ λ < 1.
    inclination : array_like
        γ [rad], the cylinder axis to the horizontal (+π/2 upright).
    u1, u2 : array_like
        The dimensionless gravity moments [dimensionless], see :func:`dimensionless_moments`.
    phases : array_like, optional
        The crank phases α_j [rad], 1-D; None means one crank at 0.
    parallel_threshold : int, optional
        The work size (output points × cranks) from which this call runs on all cores;
        None uses the global default (:func:`set_parallel_threshold`).

    Returns
    -------
    ndarray or numpy.float64
        dQ_u*/dφ [dimensionless, per rad²] of shape D + phi.shape, as in
        :func:`potential_energy`.
    """
    return _evaluate("force_derivative", phi, crank_ratio, inclination, u1, u2, phases, parallel_threshold)


def get_parallel_threshold() -> int:
    """The work size (output points × cranks) from which evaluation runs on all cores.

    Returns
    -------
    int
        The threshold set by :func:`set_parallel_threshold` (or the built-in default).
    """
    return _native_get_parallel_threshold()


def set_parallel_threshold(threshold: int) -> None:
    """Set the work size (output points × cranks) from which evaluation runs in parallel.

    Applies to every later call of the evaluation functions, :func:`energy_extrema` and
    :func:`speed_fluctuation` that does not pass its own ``parallel_threshold``.

    Parameters
    ----------
    threshold : int
        The work size, ≥ 0: 0 means always parallel, a huge value always serial. Results
        are bit-identical either way.

    Notes
    -----
    The number of threads is rayon's: set ``RAYON_NUM_THREADS`` before the first call. A
    process forked from one that has computed (multiprocessing's "fork") computes serially.

    Examples
    --------
    >>> import multicrank as mc
    >>> default = mc.get_parallel_threshold()
    >>> mc.set_parallel_threshold(0)  # always parallel
    >>> mc.get_parallel_threshold()
    0
    >>> mc.set_parallel_threshold(default)
    """
    _native_set_parallel_threshold(as_work_size(threshold, "threshold"))
