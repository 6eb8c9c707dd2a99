"""What the design aid reads off a machine's crank: its throws."""

from __future__ import annotations

import math

import numpy as np

from ..machine.machine import Machine

__all__ = ["throws"]

#: Pins closer than this [rad] are one throw (the layouts' angles are exact to ~1e-13).
SAME_PIN = 1e-9


def throws(machine: Machine) -> tuple[tuple[tuple[int, ...], ...], np.ndarray]:
    """The cylinders (indices from 0) of each throw — those whose crank pins point the same
    way, pin = (α + γ) mod 2π, as a V's two banks on one pin — in order of their first
    cylinder, and each throw's pin angle [rad] in [0, 2π)."""
    members: list[list[int]] = []
    angles: list[float] = []
    for j, cylinder in enumerate(machine.cylinders):
        pin = (cylinder.phase + cylinder.inclination) % (2 * math.pi)
        for index, angle in enumerate(angles):
            if abs(math.remainder(pin - angle, 2 * math.pi)) <= SAME_PIN:
                members[index].append(j)
                break
        else:
            angles.append(pin)
            members.append([j])
    return tuple(tuple(m) for m in members), np.array(angles)
