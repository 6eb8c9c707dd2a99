"""The shaft's speed in its two units, and the inertia torque of its variable reduced inertia.

The few formulas that the machine (:mod:`multicrank.machine`), its motion
(:mod:`multicrank.motion`), the CLI and the report all use, in one place. Like
:mod:`multicrank._validation` it imports nothing of the package, so any module may use it.

The house convention for speeds: a name carries its unit — ``rpm…`` in revolutions per
minute [1/min], ``omega…`` in radians per second [rad/s]; ω = π n/30.
"""

from __future__ import annotations

import math
from typing import TypeVar

import numpy as np

__all__ = ["inertia_torque", "omega_from_rpm", "rpm_from_omega"]

#: A float, or an array of them (the conversions keep the type they are given).
Speed = TypeVar("Speed", float, np.ndarray)


def omega_from_rpm(rpm: Speed) -> Speed:
    """ω = π n/30 [rad/s] of a speed n [1/min] (a number or an array)."""
    return rpm * math.pi / 30.0  # one revolution (2π rad) per minute (60 s)


def rpm_from_omega(omega: Speed) -> Speed:
    """n = 30 ω/π [1/min] of a speed ω [rad/s] (a number or an array)."""
    return omega * 30.0 / math.pi


def inertia_torque(slope: np.ndarray, omega: np.ndarray | float) -> np.ndarray:
    """−½ J′(φ) ω² [N·m]: the torque of the variable reduced inertia on the shaft, the velocity
    term of J(φ)φ̈ + ½J′(φ)φ̇² = M moved to the right-hand side.

    Parameters
    ----------
    slope : ndarray
        J′(φ) [kg·m²/rad], from :meth:`~multicrank.Machine.reduced_inertia`.
    omega : ndarray or float
        ω [rad/s]; broadcasts against ``slope``.
    """
    return -0.5 * slope * np.square(omega)
