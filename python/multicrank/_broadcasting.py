"""The design parameters of the dimensionless gravity kernels and of the numpy reference:
each coerced and checked (:func:`as_design`, :func:`as_phases`, the four of
:func:`design_keywords`, the crank angles of :func:`as_angles`), broadcast together into the
flat contiguous columns the kernels take — their memory checked before they are formed
(:func:`broadcast_designs`) — and a flat result given back the designs' shape
(:func:`finish`). Built on `_validation`'s checks of one value.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._validation import as_real_array, check_size, contiguous, refused

__all__ = [
    "as_angles",
    "as_design",
    "as_phases",
    "broadcast_designs",
    "broadcast_shape",
    "design_keywords",
    "finish",
]


def as_angles(phi: Any, name: str = "phi") -> np.ndarray:
    """Crank angles of any shape as float64 (rad). NaN/inf are allowed (they give NaN)."""
    return as_real_array(phi, name)


def as_design(value: Any, name: str, *, low: float | None = None, high: float | None = None) -> np.ndarray:
    """A design parameter as float64; finite, and in [low, high) where those are given."""
    array = as_real_array(value, name)
    # NaN fails every comparison, so it lands outside [low, high) with the others and the
    # message gives the parameter's own range, not "any finite real".
    inside = np.isfinite(array)
    if low is not None:
        inside &= array >= low
    if high is not None:
        inside &= array < high
    if not np.all(inside):
        bad = array[~inside].flat[0]
        raise refused(name, f"{name} = {bad} is out of range; allowed: {_range_text(name, low, high)}")
    return array


def _range_text(name: str, low: float | None, high: float | None) -> str:
    if low is None and high is None:
        return "any finite real"
    if high is None:
        return f"{name} >= {low}, finite"
    if low is None:
        return f"{name} < {high}, finite"
    return f"{low} <= {name} < {high}"


def as_phases(phases: Any) -> np.ndarray:
    """The crank phases α_j (rad) as a non-empty finite 1-D float64 array; None → [0]."""
    if phases is None:
        return np.zeros(1)
    array = as_real_array(phases, "phases")
    if array.ndim != 1:
        raise refused("phases", f"phases must be a 1-D array of angles, got shape {array.shape}")
    if array.size == 0:
        raise refused("phases", "phases must not be empty")
    if not np.all(np.isfinite(array)):
        raise refused("phases", "phases must be finite angles in radians")
    return contiguous(array)


def broadcast_shape(what: str, columns: dict[str, np.ndarray]) -> tuple[int, ...]:
    """The shape the arrays broadcast to (nothing is materialised)."""
    try:
        return np.broadcast_shapes(*(a.shape for a in columns.values()))
    except ValueError:
        shapes = ", ".join(f"{k} {v.shape}" for k, v in columns.items())
        raise refused(what, f"{what} do not broadcast together: {shapes}") from None


def broadcast_designs(
    what: str = "design parameters", /, **columns: np.ndarray
) -> tuple[tuple[int, ...], dict[str, np.ndarray]]:
    """Broadcast arrays together: (their shape D, flat contiguous columns); the columns'
    size is checked against memory before they are formed."""
    shape = broadcast_shape(what, columns)
    check_size(what, f"shape {shape}", math.prod(shape) * len(columns))
    flat = {k: contiguous(np.broadcast_to(v, shape)).reshape(-1) for k, v in columns.items()}
    return shape, flat


def finish(flat: np.ndarray, shape: tuple[int, ...]) -> np.ndarray | np.float64:
    """Reshape a flat result; a 0-d result becomes a numpy float64 scalar."""
    result = flat.reshape(shape)
    return result[()] if result.ndim == 0 else result


def design_keywords(crank_ratio: Any, inclination: Any, u1: Any, u2: Any) -> dict[str, np.ndarray]:
    """The four design keywords of the evaluation functions, validated (0 ≤ λ < 1, all finite)."""
    return {
        "crank_ratio": as_design(crank_ratio, "crank_ratio", low=0.0, high=1.0),
        "inclination": as_design(inclination, "inclination"),
        "u1": as_design(u1, "u1"),
        "u2": as_design(u2, "u2"),
    }
