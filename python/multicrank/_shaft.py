"""The shaft's speed in its two units, and the inertia torque of its variable reduced inertia.

The few formulas that the machine (:mod:`multicrank.machine`), its motion
(:mod:`multicrank.motion`), the CLI and the report all use, in one place. Like
:mod:`multicrank._validation` (where the speed conversions live, beside the check of a speed) it
imports nothing else of the package, so any module may use it.

The house convention for speeds: a name carries its unit — ``rpm…`` in revolutions per
minute [1/min], ``omega…`` in radians per second [rad/s]; ω = π n/30.
"""

from __future__ import annotations

import numpy as np

# The one conversion lives where a user's speed is checked (re-exported for the old imports).
from ._validation import omega_from_rpm, rpm_from_omega

__all__ = ["inertia_torque", "omega_from_rpm", "rpm_from_omega"]


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
