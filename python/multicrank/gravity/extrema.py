"""What the numbers mean: the extrema of U_w* and the speed fluctuation due to gravity
(docs/theory.md, "Speed fluctuation due to gravity")."""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from .._broadcasting import as_phases, broadcast_designs, design_keywords, finish
from .._native import energy_extrema as _native_energy_extrema
from .._validation import as_threshold

__all__ = ["EnergyExtrema", "energy_extrema", "speed_fluctuation"]


class EnergyExtrema(NamedTuple):
    """The exact extrema of U_w* over one revolution: the result of :func:`energy_extrema`.

    A named tuple; every field has the broadcast design shape D (numpy float64 scalars for
    scalar input).

    Attributes
    ----------
    min, max : ndarray or numpy.float64
        The smallest and largest U_w* over a revolution [dimensionless].
    min_at, max_at : ndarray or numpy.float64
        The crank angles φ ∈ [0, 2π] [rad] where they occur.
    range : ndarray or numpy.float64
        δ_g = max − min [dimensionless], taken before the constant level is added, so that a
        variation below one ulp of U_w* itself is kept.
    """

    min: np.ndarray | np.float64
    min_at: np.ndarray | np.float64
    max: np.ndarray | np.float64
    max_at: np.ndarray | np.float64
    range: np.ndarray | np.float64


def energy_extrema(
    *, crank_ratio: Any, inclination: Any, u1: Any, u2: Any, phases: Any = None, parallel_threshold: Any = None
) -> EnergyExtrema:
    """The exact minimum and maximum of U_w*(φ) over one revolution.

    The extrema are roots of Q_u* = dU_w*/dφ, found by a search that cannot miss one (see
    docs/theory.md, "Speed fluctuation due to gravity"): cells over which a bound on
    :math:`|Q''|` proves Q clear of zero are dropped, cells over which Q′ provably keeps its sign
    hold at most one root (bracketed by a sign change and polished by Newton steps), and any
    other cell is halved — three roots crowded close together are all found. Valid for every
    0 ≤ λ < 1 (as λ → 1 on the closed form, with bounded work).

    Parameters
    ----------
    crank_ratio : array_like
        λ = r/l [dimensionless], 0 ≤ λ < 1.
    inclination : array_like
        γ [rad], the cylinder axis to the horizontal (+π/2 upright).
    u1, u2 : array_like
        The dimensionless gravity moments [dimensionless], see :func:`dimensionless_moments`.
    phases : array_like, optional
        The crank phases α_j [rad], 1-D; None means one crank at 0.
    parallel_threshold : int, optional
        The number of designs × cranks from which this call runs on all cores; None uses
        the global default (:func:`set_parallel_threshold`).

    Returns
    -------
    EnergyExtrema
        ``min``, ``min_at``, ``max``, ``max_at`` and ``range``, each of the broadcast design
        shape D.

    Examples
    --------
    An upright in-line twin (two-stroke, cranks 180° apart):

    >>> import numpy as np
    >>> import multicrank as mc
    >>> extrema = mc.energy_extrema(crank_ratio=0.25, inclination=np.pi / 2,
    ...                             u1=1e-3, u2=2e-4, phases=mc.crank_phases(2))
    >>> print(f"U_w* from {extrema.min:.6e} at {np.degrees(extrema.min_at):.1f}° "
    ...       f"to {extrema.max:.6e} at {np.degrees(extrema.max_at):.1f}°")
    U_w* from -2.654033e-03 at 90.0° to -2.400000e-03 at 0.0°
    """
    shape, design = broadcast_designs(**design_keywords(crank_ratio, inclination, u1, u2))
    fields = _native_energy_extrema(design, as_phases(phases), as_threshold(parallel_threshold))
    return EnergyExtrema(**{name: finish(values, shape) for name, values in fields.items()})


def speed_fluctuation(
    *, crank_ratio: Any, inclination: Any, u1: Any, u2: Any, phases: Any = None, parallel_threshold: Any = None
) -> Any:
    """δ_g = max U_w* − min U_w* over one revolution (docs/theory.md, "Speed fluctuation due to gravity").

    With constant reduced inertia I_w and gravity alone, ½I_w ω² + U is constant, so to
    first order the gravity contribution to the coefficient of speed fluctuation
    (ω_max − ω_min)/ω_mean is δ_g. Computed from the exact extrema (roots of Q_u*, see
    :func:`energy_extrema`), so it is never below a sampled max − min.

    Parameters
    ----------
    crank_ratio : array_like
        λ = r/l [dimensionless], 0 ≤ λ < 1.
    inclination : array_like
        γ [rad], the cylinder axis to the horizontal (+π/2 upright).
    u1, u2 : array_like
        The dimensionless gravity moments [dimensionless], see :func:`dimensionless_moments`.
    phases : array_like, optional
        The crank phases α_j [rad], 1-D; None means one crank at 0.
    parallel_threshold : int, optional
        The number of designs × cranks from which this call runs on all cores; None uses
        the global default (:func:`set_parallel_threshold`).

    Returns
    -------
    ndarray or numpy.float64
        δ_g [dimensionless] of the broadcast design shape D (a numpy float64 for scalar
        input).

    See Also
    --------
    steady_state : The exact δ of a physical machine, with gas and inertia torques.

    Examples
    --------
    δ_g of upright in-line two-stroke machines of k identical cranks:

    >>> import numpy as np
    >>> import multicrank as mc
    >>> design = dict(crank_ratio=0.25, inclination=np.pi / 2, u1=1e-3, u2=2e-4)
    >>> for k in (1, 2, 3, 4):
    ...     delta = mc.speed_fluctuation(**design, phases=mc.crank_phases(k))
    ...     print(f"k = {k}: δ_g = {delta:.4e}")
    k = 1: δ_g = 2.4000e-03
    k = 2: δ_g = 2.5403e-04
    k = 3: δ_g = 1.2397e-08
    k = 4: δ_g = 2.0491e-06
    """
    extrema = energy_extrema(
        crank_ratio=crank_ratio,
        inclination=inclination,
        u1=u1,
        u2=u2,
        phases=phases,
        parallel_threshold=parallel_threshold,
    )
    return extrema.range
