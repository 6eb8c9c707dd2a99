"""The phases of a four-stroke machine of a layout: which of the two phases each cylinder's
crank allows (β − γ or β − γ + 2π) it gets, chosen for the most even firing
(:meth:`~multicrank.Machine.from_layout` states the rule) or given by hand and checked.
Angles in degrees inside, where the layouts' angles are exact; phases out in radians.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._validation import as_real_array, refused

__all__ = ["MAX_FIRING_SEARCH", "chosen_firing", "even_firing"]

#: The most cylinders whose 2ⁿ firing choices :meth:`~multicrank.Machine.from_layout` tries (65536).
MAX_FIRING_SEARCH = 16


def even_firing(crank: np.ndarray, strokes: int) -> list[float]:
    """The phases [rad] of cylinders whose crank phases β − γ are ``crank`` [deg]: the most even
    firing over the cycle, by the rule of :meth:`~multicrank.Machine.from_layout` (done in degrees, where
    the layouts' angles are exact)."""
    if strokes == 2:
        return [math.radians(a) for a in np.mod(crank, 360.0)]
    count = crank.size
    if count > MAX_FIRING_SEARCH:
        raise refused(
            "firing",
            f"firing: the even-firing search covers up to {MAX_FIRING_SEARCH} cylinders of a four-stroke machine, "
            f"this layout has {count}; give firing= (the phases in rad) explicitly",
        )
    moved = (np.arange(2**count)[:, None] >> np.arange(count)[None, :]) & 1  # row i: which cylinders get +360°
    candidates = np.mod(crank[None, :] + 360.0 * moved, 720.0)
    ordered = np.sort(candidates, axis=1)
    gaps = np.diff(np.concatenate((ordered, ordered[:, :1] + 720.0), axis=1), axis=1)
    # Equal to rounding (the angles are exact or within ~1e-13° of it): compared at 1e-9°.
    largest = np.round(gaps.max(axis=1), 9)
    squares = np.round(np.sum(gaps**2, axis=1) / 720.0, 9)
    earliest = moved @ (2.0 ** np.arange(count - 1, -1, -1))  # moving a later cylinder is smaller
    best = np.lexsort((earliest, moved.sum(axis=1), squares, largest))[0]
    return [math.radians(a) for a in candidates[best]]


def chosen_firing(firing: Any, crank: np.ndarray, strokes: int) -> list[float]:
    """The given phases [rad], checked against the crank (β − γ [deg] plus whole turns)."""
    phases = as_real_array(firing, "firing")
    if phases.shape != crank.shape:
        raise refused(
            "firing",
            f"firing must hold one phase [rad] per cylinder ({crank.size}, in the layout's order), "
            f"got shape {phases.shape}",
        )
    turns = (phases - np.radians(crank)) / (2 * math.pi)
    whole = np.round(turns)
    for j, (turn, nearest) in enumerate(zip(turns, whole, strict=True)):
        if not (math.isfinite(turn) and abs(turn - nearest) <= 1e-9):
            raise refused(
                "firing",
                f"firing[{j}] = {phases[j]!r} rad is not a phase the crank allows: cylinder {j} is at "
                f"β − γ = {crank[j]:g}° plus whole turns (360°)",
            )
    cycle = 180.0 * strokes
    return [math.radians(a) for a in np.mod(crank + 360.0 * whole, cycle)]
