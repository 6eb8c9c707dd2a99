"""Where things are along a machine's shaft: its throws and the main bearings between them.

A cylinder's ``axial_position`` z [m] places it along the shaft; the cylinders at one axial
position are one **throw** (:func:`throws`), whose crank web and counterweight belong to it.
The main bearings are given (``Machine(main_bearings=...)``, checked by :func:`as_bearings`)
or interleave the throws (:func:`default_bearings`). :class:`~multicrank.Machine` exposes them
as ``throws``, ``throw_index`` and ``bearings``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .._validation import MAGNITUDE_LIMIT, as_real_array, refused

__all__ = ["SAME_POSITION", "as_bearings", "default_bearings", "throws"]

#: Axial positions closer than SAME_POSITION·max(1, |z|) [m] are one throw (and a throw that
#: close to a bearing is at it): a relative tolerance of rounding, not of manufacture.
SAME_POSITION = 1e-12


def _close(a: float, b: float) -> bool:
    """Whether two axial positions [m] are one, to :data:`SAME_POSITION`."""
    return abs(a - b) <= SAME_POSITION * max(1.0, abs(a), abs(b))


def throws(positions: Sequence[float]) -> tuple[tuple[float, ...], tuple[int, ...]]:
    """The throws of cylinders at ``positions`` [m]: the distinct positions, increasing, and
    the index of each cylinder's throw among them.

    Positions equal to within :data:`SAME_POSITION`·max(1, |z|) are one throw, at the
    smallest of them (a chain of such neighbours is one throw).
    """
    order = sorted(range(len(positions)), key=lambda j: positions[j])
    places: list[float] = []
    index = [0] * len(positions)
    for j in order:
        z = positions[j]
        if not places or not _close(z, places[-1]):
            places.append(z)
        index[j] = len(places) - 1
    return tuple(places), tuple(index)


def default_bearings(places: Sequence[float], crank_radius: float) -> tuple[float, ...]:
    """n + 1 main bearings [m] interleaving n throws at ``places`` (increasing).

    Between neighbouring throws, the midpoint; outside, as far from the end throw as the
    midpoint next to it: z₁ − d₁/2 and zₙ + dₙ/2 with d₁ = z₂ − z₁, dₙ = zₙ − zₙ₋₁. A lone
    throw gets z₁ ± ``crank_radius`` (the machine's largest): the lever rule splits its load
    in halves whatever the distance, so the distance only draws the bearings at a plausible
    place.
    """
    z = np.asarray(places, dtype=float)
    if z.size == 1:
        return (float(z[0] - crank_radius), float(z[0] + crank_radius))
    gaps = np.diff(z)
    middle = z[:-1] + gaps / 2
    return (float(z[0] - gaps[0] / 2), *(float(m) for m in middle), float(z[-1] + gaps[-1] / 2))


def as_bearings(value: Any, places: Sequence[float], members: Sequence[Sequence[int]]) -> tuple[float, ...]:
    """A machine's ``main_bearings`` [m], checked: at least two, finite, strictly increasing,
    and every throw (at ``places``, of the cylinders ``members``) strictly between two of them.

    Raises
    ------
    MechanismError
        Naming ``main_bearings``, the throw's position and what is wrong: fewer than two
        bearings, one not finite or beyond 10³⁰ m, not increasing, a throw overhung (before
        the first bearing or after the last) or exactly at a bearing.
    """
    allowed = "allowed: at least two finite axial positions [m], strictly increasing, every throw strictly between two"
    bearings = as_real_array(value, "main_bearings")
    if bearings.ndim != 1 or bearings.size < 2:
        raise refused(
            "main_bearings",
            f"main_bearings must be a sequence of at least two axial positions [m], got shape {bearings.shape}; "
            f"{allowed}",
        )
    for i, z in enumerate(bearings):
        if not (math.isfinite(z) and abs(z) <= MAGNITUDE_LIMIT):
            raise refused(
                "main_bearings", f"main_bearings[{i}] = {z:g} is out of range; {allowed}, |z| <= {MAGNITUDE_LIMIT:g}"
            )
    for i in range(1, bearings.size):
        if not bearings[i] > bearings[i - 1]:
            raise refused(
                "main_bearings",
                f"main_bearings[{i}] = {bearings[i]:g} m is not beyond main_bearings[{i - 1}] = "
                f"{bearings[i - 1]:g} m; {allowed}",
            )
    result = tuple(float(z) for z in bearings)
    for z, cylinders in zip(places, members, strict=True):
        which = ", ".join(f"cylinders[{j}]" for j in cylinders)
        where = f"the throw at z = {z:g} m ({which})"
        at = [i for i, b in enumerate(result) if _close(z, b)]
        if at:
            raise refused(
                "main_bearings",
                f"main_bearings[{at[0]}] = {result[at[0]]:g} m is at {where}: a throw lies between two "
                f"bearings, not on one; {allowed}",
            )
        if z < result[0]:
            raise refused(
                "main_bearings",
                f"main_bearings: {where} is overhung, before the first bearing at {result[0]:g} m; {allowed}",
            )
        if z > result[-1]:
            raise refused(
                "main_bearings",
                f"main_bearings: {where} is overhung, beyond the last bearing at {result[-1]:g} m; {allowed}",
            )
    return result
