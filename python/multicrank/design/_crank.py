"""What the design aid reads off a machine's crank: its throws."""

from __future__ import annotations

import math

import numpy as np

from ..machine.machine import Machine

__all__ = ["throws"]

#: Pins closer than this [rad] are one throw (the layouts' angles are exact to ~1e-13).
SAME_PIN = 1e-9


def throws(machine: Machine) -> tuple[tuple[tuple[int, ...], ...], np.ndarray]:
    """The cylinders (indices from 0) of each throw — those at one place along the shaft
    (``Machine.throw_index``) whose crank pins point the same way, pin = (α + γ) mod 2π, as a
    V's two banks on one pin — in order of their first cylinder, and each throw's pin angle
    [rad] in [0, 2π). An in-line four's cylinders 1 and 4 point alike but are two throws: a
    counterweight on each loads other bearings."""
    members: list[list[int]] = []
    angles: list[float] = []
    places: list[int] = []
    for j, (cylinder, place) in enumerate(zip(machine.cylinders, machine.throw_index, strict=True)):
        pin = (cylinder.phase + cylinder.inclination) % (2 * math.pi)
        for index, angle in enumerate(angles):
            if places[index] == place and abs(math.remainder(pin - angle, 2 * math.pi)) <= SAME_PIN:
                members[index].append(j)
                break
        else:
            angles.append(pin)
            places.append(place)
            members.append([j])
    return tuple(tuple(m) for m in members), np.array(angles)
