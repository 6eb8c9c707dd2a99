"""The inertia torque of the shaft's variable reduced inertia.

The formula that the machine (:mod:`multicrank.machine`) and its motion
(:mod:`multicrank.motion`) use, in one place. Like :mod:`multicrank._validation` it imports
nothing of the package, so any module may use it. The speed's two units are converted by
:func:`multicrank._validation.omega_from_rpm` and :func:`~multicrank._validation.rpm_from_omega`
alone, where a user's speed is checked.

The house convention for speeds: a name carries its unit — ``rpm…`` in revolutions per
minute [1/min], ``omega…`` in radians per second [rad/s]; ω = π n/30.
"""

from __future__ import annotations

import numpy as np

__all__ = ["inertia_torque"]


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
