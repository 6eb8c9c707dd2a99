"""Load and drive torques on the shaft: what :func:`~multicrank.steady_state`,
:func:`~multicrank.flywheel_inertia` and :func:`~multicrank.simulate` accept as ``load=``
and ``drive=``.

A **load** resists rotation (positive opposes it), a **drive** accelerates the shaft
(positive drives it forward). Either may be

- a number: a constant torque [N·m];
- a :class:`PowerLawLoad`: M = M_n·sign(ω)·|ω/ω_n|^e (e = 2: fan, pump, propeller;
  e = 1: viscous);
- a vectorised callable ``f(phi, omega) -> N·m`` of the crank angle φ [rad] and the shaft
  speed ω [rad/s], returning an array that broadcasts to their common shape;
- for a load only, ``"balance"``: the constant load that takes, over one working cycle, the
  mean of the gas and drive torques (gravity's mean over a cycle is zero) — the machine then
  runs periodically at any mean speed asked for.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._native import MechanismError
from .._validation import as_scalar

__all__ = ["BALANCE", "PowerLawLoad", "Torque", "as_torque", "balance_torque"]

#: The load that balances the cycle-mean of the gas and drive torques.
BALANCE = "balance"


@dataclass(frozen=True)
class PowerLawLoad:
    r"""A torque that grows as a power of the speed, a load or a drive.

    .. math::

        M(\omega) = M_n \,\operatorname{sign}(\omega)\, \left|\frac{\omega}{\omega_n}\right|^e

    Parameters
    ----------
    torque : float
        M_n [N·m], the torque at the nominal speed; finite, ≥ 0.
    speed : float
        ω_n [rad/s], the nominal speed, > 0 (``rpm * math.pi / 30`` from 1/min).
    exponent : float, default 2
        e ≥ 0 [dimensionless]: 2 for fans, centrifugal pumps and propellers (the square
        law), 1 for viscous friction, 0 for a constant (Coulomb) torque that changes sign
        with ω.

    See Also
    --------
    steady_state : A square law (e = 2) is solved there in closed form.

    Examples
    --------
    A fan that takes 90 N·m at 120 rpm:

    >>> import math
    >>> import multicrank as mc
    >>> fan = mc.PowerLawLoad(torque=90.0, speed=120 * math.pi / 30)
    >>> fan(0.0, [0.0, 2 * math.pi, 4 * math.pi])  # N·m at 0, 60 and 120 rpm
    array([ 0. , 22.5, 90. ])
    """

    torque: float
    speed: float
    exponent: float = 2.0

    def __post_init__(self) -> None:
        torque = as_scalar(self.torque, "torque")
        speed = as_scalar(self.speed, "speed")
        exponent = as_scalar(self.exponent, "exponent")
        if not (math.isfinite(torque) and torque >= 0):
            raise MechanismError(f"torque = {torque} is out of range; allowed: torque >= 0 [N·m]")
        if not (math.isfinite(speed) and speed > 0):
            raise MechanismError(f"speed = {speed} is out of range; allowed: speed > 0 [rad/s]")
        if not (math.isfinite(exponent) and exponent >= 0):
            raise MechanismError(f"exponent = {exponent} is out of range; allowed: exponent >= 0")
        object.__setattr__(self, "torque", torque)
        object.__setattr__(self, "speed", speed)
        object.__setattr__(self, "exponent", exponent)

    @property
    def coefficient(self) -> float:
        """c = M_n/ω_n^e [N·m·(s/rad)^e]: M = c·sign(ω)|ω|^e."""
        return self.torque / self.speed**self.exponent

    def __call__(self, phi: Any, omega: Any) -> np.ndarray:
        """The torque at a speed.

        Parameters
        ----------
        phi : array_like
            Crank angle φ [rad]; the torque does not depend on it, but its shape broadcasts.
        omega : array_like
            Shaft speed ω [rad/s].

        Returns
        -------
        ndarray
            M(ω) [N·m], the broadcast shape of ``phi`` and ``omega``.
        """
        speed = np.asarray(omega, dtype=float)
        ratio = np.abs(speed) / self.speed
        # 0**0 is 1 in numpy, but a torque that does not depend on the speed still changes
        # sign with it and is zero at rest: sign(0) = 0 takes care of that.
        values = self.torque * np.sign(speed) * ratio**self.exponent
        return np.broadcast_to(values, np.broadcast_shapes(np.shape(phi), speed.shape)).copy()


class Torque:
    """A load or drive resolved into one callable ``torque(phi, omega) -> ndarray`` [N·m].

    ``kind`` is "constant", "power-law" or "callable"; ``value`` the number, the
    :class:`PowerLawLoad` or the user's callable; ``name`` the parameter it came from (for
    error messages). The result always has the broadcast shape of ``phi`` and ``omega`` and
    is checked to be finite.
    """

    __slots__ = ("kind", "name", "value")

    def __init__(self, kind: str, value: Any, name: str) -> None:
        self.kind, self.value, self.name = kind, value, name

    @property
    def depends_on_speed(self) -> bool:
        """Whether the torque may change with ω (a callable is assumed to)."""
        return self.kind != "constant"

    def __call__(self, phi: Any, omega: Any) -> np.ndarray:
        angles = np.asarray(phi, dtype=float)
        speed = np.asarray(omega, dtype=float)
        shape = np.broadcast_shapes(angles.shape, speed.shape)
        if self.kind == "constant":
            return np.full(shape, float(self.value))
        if self.kind == "power-law":
            return np.asarray(self.value(angles, speed), dtype=float)
        try:
            values = np.asarray(self.value(angles, speed), dtype=float)
            values = np.broadcast_to(values, shape).copy()
        except MechanismError:
            raise
        except Exception as error:
            raise MechanismError(
                f"{self.name} failed: {type(error).__name__}: {error}; it must be a vectorised callable "
                f"f(phi [rad], omega [rad/s]) -> torque [N·m] returning an array that broadcasts to their shape"
            ) from error
        if not np.all(np.isfinite(values)):
            raise MechanismError(f"{self.name} returned a non-finite torque (NaN or inf) [N·m]")
        return values

    def __repr__(self) -> str:
        return f"Torque({self.name}: {self.kind} {self.value!r})"


def as_torque(value: Any, name: str, *, balance: bool = False) -> Torque | str | None:
    """``value`` of parameter ``name`` ("load" or "drive") as a :class:`Torque`, None (no
    torque) or :data:`BALANCE` (only where ``balance`` is allowed)."""
    if value is None:
        return None
    if isinstance(value, str):
        if balance and value == BALANCE:
            return BALANCE
        allowed = f"{BALANCE!r}, " if balance else ""
        raise MechanismError(
            f"{name} = {value!r} is not understood; allowed: {allowed}a number [N·m], a "
            f"multicrank.PowerLawLoad or a callable f(phi, omega) -> N·m"
        )
    if isinstance(value, PowerLawLoad):
        return Torque("power-law", value, name)
    if callable(value):
        return Torque("callable", value, name)
    number = as_scalar(value, name)
    if not math.isfinite(number):
        raise MechanismError(f"{name} = {number} is out of range; allowed: a finite torque [N·m]")
    return Torque("constant", number, name)


def balance_torque(machine: Any, drive: Torque | None, omega: float, quadrature: Any = None) -> float:
    """The "balance" load [N·m]: (1/Φ)∫₀^Φ [M_gas(φ) + M_drive(φ, ω)] dφ over one working cycle,
    a drive's speed dependence frozen at ``omega`` [rad/s]. Gravity's mean over a cycle is 0.

    The gas part is the indicated work per cycle over Φ, exact also for tabulated pressures
    (:class:`~multicrank._work.GasWork`); the drive's mean is taken on ``quadrature`` (default:
    the machine's cycle rule)."""
    from ._quadrature import CycleQuadrature
    from ._work import GasWork

    mean = GasWork(machine).per_cycle / machine.cycle
    if drive is not None:
        rule = CycleQuadrature.of(machine, tables=False) if quadrature is None else quadrature
        mean += rule.mean(drive(rule.phi, omega))
    return mean
