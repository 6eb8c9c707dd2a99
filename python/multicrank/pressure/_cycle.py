"""The working cycle of an indicator diagram and the checks that the diagram
(:mod:`.diagram`), the synthetic cycles (:mod:`.synthetic`) and the table reader share."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._validation import as_scalar, refused

#: The interpolations an :class:`~multicrank.IndicatorDiagram` offers (its ``kind``).
INTERPOLATIONS = ("periodic-cubic", "pchip", "linear")
#: The default reference (crankcase) pressure [Pa].
STANDARD_ATMOSPHERE = 101325.0

TWO_STROKE = 2.0 * math.pi
FOUR_STROKE = 4.0 * math.pi
# Gauss–Legendre points per table interval for the integrals (work, heat release).
_GAUSS_POINTS = 10


def as_cycle(value: Any, name: str = "cycle") -> float:
    """The working cycle Φ [rad]: 2π or 4π (to 1e-9 relative), returned exact."""
    x = as_scalar(value, name)
    for cycle in (TWO_STROKE, FOUR_STROKE):
        if abs(x - cycle) <= 1e-9 * cycle:
            return cycle
    hint = ""
    if x in (2.0, 4.0):
        hint = f" (an angle in rad, not the number of strokes: cycle = {int(x)}*math.pi)"
    raise refused(name, f"{name} = {x!r} is not allowed; allowed: 2π (two-stroke) or 4π (four-stroke) [rad]{hint}")


def as_finite(value: Any, name: str, *, above: float | None = None, at_least: float | None = None) -> float:
    """One finite real number, > above or ≥ at_least where given."""
    x = as_scalar(value, name)
    if not math.isfinite(x):
        raise refused(name, f"{name} = {x} is out of range; allowed: a finite number")
    if above is not None and not x > above:
        raise refused(name, f"{name} = {x} is out of range; allowed: {name} > {above}")
    if at_least is not None and not x >= at_least:
        raise refused(name, f"{name} = {x} is out of range; allowed: {name} >= {at_least}")
    return x


def cycle_name(cycle: float) -> str:
    """ "2π (two-stroke)" or "4π (four-stroke)", for messages."""
    return "2π (two-stroke)" if cycle == TWO_STROKE else "4π (four-stroke)"


def gauss(points: int = _GAUSS_POINTS) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on [−1, 1]."""
    nodes, weights = np.polynomial.legendre.leggauss(points)
    return nodes, weights
