"""What the numbers mean: the extrema of U_w* and the speed fluctuation due to gravity
(docs/theory.md, "Speed fluctuation due to gravity")."""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from ._native import energy_extrema as _native_energy_extrema
from ._validation import as_phases, as_threshold, broadcast_designs, design_keywords, finish

__all__ = ["EnergyExtrema", "energy_extrema", "speed_fluctuation"]


class EnergyExtrema(NamedTuple):
    """min and max of U_w* over one revolution, the crank angles φ ∈ [0, 2π] where they
    occur, and δ_g = max − min (taken before the constant level is added, so a variation
    below one ulp of U_w* itself is kept)."""

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
    docs/theory.md, "Speed fluctuation due to gravity"): cells over which a bound on |Q''|
    proves Q clear of zero are dropped, cells over which Q' provably keeps its sign hold at
    most one root (bracketed by a sign change and polished by Newton steps), and any other
    cell is halved — three roots crowded close together are all found. Valid for every
    0 ≤ λ < 1 (as λ → 1 on the closed form, with bounded work). Each field has the
    broadcast design shape D.
    """
    shape, design = broadcast_designs(**design_keywords(crank_ratio, inclination, u1, u2))
    fields = _native_energy_extrema(design, as_phases(phases), as_threshold(parallel_threshold))
    return EnergyExtrema(**{name: finish(values, shape) for name, values in fields.items()})


def speed_fluctuation(
    *, crank_ratio: Any, inclination: Any, u1: Any, u2: Any, phases: Any = None, parallel_threshold: Any = None
):
    """δ_g = max U_w* − min U_w* over one revolution (docs/theory.md, "Speed fluctuation due to gravity").

    With constant reduced inertia I_w and gravity alone, ½I_w ω² + U is constant, so to
    first order the gravity contribution to the coefficient of speed fluctuation
    (ω_max − ω_min)/ω_mean is δ_g. Computed from the exact extrema (roots of Q_u*), so it is
    never below a sampled max − min. Returns shape D (a numpy float64 for scalar input).
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
