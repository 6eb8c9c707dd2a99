"""Where things are along a machine's shaft: its throws and main bearings.

A cylinder's ``axial_position`` z [m] places it along the shaft; the cylinders at one axial
position (to 10⁻¹²·max(1, abs z) m) are one **throw**, whose crank web and counterweight
belong to it. The main bearings are given (``Machine(main_bearings=...)``) or interleave the
throws. The rules of both are the Rust core's (``core::BearingLayout``: one place, which the
bearing loads and the frame sweep use too); here a user's ``main_bearings`` is only made an
array (:func:`as_bearings`) and the core's answer a :class:`ShaftLayout`.
:class:`~multicrank.Machine` exposes it as ``throws``, ``throw_index`` and ``bearings``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple

from .._native import bearing_layout
from .._validation import as_real_array, refused

__all__ = ["ShaftLayout", "as_bearings", "layout_of"]


class ShaftLayout(NamedTuple):
    """A machine's throws [m, increasing], each cylinder's throw (its index among them) and
    its main bearings [m, increasing]."""

    throws: tuple[float, ...]
    throw_index: tuple[int, ...]
    bearings: tuple[float, ...]


def as_bearings(value: Any) -> tuple[float, ...]:
    """A user's ``main_bearings`` as a tuple of floats [m]: real numbers, one axis, at least
    two (the rest of the rules are the core's, :func:`layout_of`)."""
    bearings = as_real_array(value, "main_bearings")
    if bearings.ndim != 1 or bearings.size < 2:
        raise refused(
            "main_bearings",
            f"main_bearings must be a sequence of at least two axial positions [m], got shape {bearings.shape}; "
            "allowed: at least two finite axial positions [m], strictly increasing, every throw strictly between two",
        )
    return tuple(float(z) for z in bearings)


def layout_of(positions: Sequence[float], main_bearings: Sequence[float] | None, crank_radius: float) -> ShaftLayout:
    """The throws and bearings of cylinders at ``positions`` [m] with the bearings
    ``main_bearings`` (None: n + 1 interleaving the n throws, a lone throw's at ±
    ``crank_radius``), by the core's rules.

    Raises
    ------
    MechanismError
        Naming ``main_bearings``, the bearing and the throw: one not finite, not increasing,
        a throw overhung (before the first bearing or after the last) or exactly at a bearing.
    """
    given = None if main_bearings is None else list(main_bearings)
    throws, index, bearings = bearing_layout(list(positions), given, crank_radius)
    return ShaftLayout(tuple(throws), tuple(index), tuple(bearings))
