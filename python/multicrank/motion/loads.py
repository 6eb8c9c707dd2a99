"""Load and drive torques on the shaft: what :func:`~multicrank.steady_state`,
:func:`~multicrank.flywheel_inertia` and :func:`~multicrank.simulate` accept as ``load=``
and ``drive=``.

A **load** resists rotation (positive opposes it), a **drive** accelerates the shaft
(positive drives it forward). Either may be

- a number: a constant torque [N·m];
- a :class:`PowerLawLoad`: M = M_n·sign(ω)·|ω/ω_n|^e (e = 2: fan, pump, propeller;
  e = 1: viscous), its nominal speed given as ``rpm=`` [1/min];
- a vectorised callable ``f(phi, omega) -> N·m`` of the crank angle φ [rad] and the shaft
  speed ω [rad/s], returning an array that broadcasts to their common shape;
- for a load only, ``"balance"``: the constant load that takes, over one working cycle, the
  mean of the gas and drive torques (gravity's mean over a cycle is zero) — the machine then
  runs periodically at any mean speed asked for.

:class:`AppliedTorques` resolves the two of one call and is the one home of the "balance"
rule (:meth:`AppliedTorques.balanced`) and of the net applied torque M_drive − M_load.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np

from .._native import MechanismError
from .._validation import (
    MAGNITUDE_LIMIT,
    SPEED_LIMITS,
    as_omega,
    as_returned,
    as_scalar,
    one_of,
    refused,
    renamed,
    rpm_from_omega,
    warn_renamed,
)

__all__ = ["BALANCE", "AppliedTorques", "PowerLawLoad", "Torque", "as_torque"]

#: The load that balances the cycle-mean of the gas and drive torques.
BALANCE = "balance"


@dataclass(frozen=True, init=False)
class PowerLawLoad:
    r"""A torque that grows as a power of the speed, a load or a drive.

    .. math::

        M(\omega) = M_n \,\operatorname{sign}(\omega)\, \left|\frac{\omega}{\omega_n}\right|^e

    Parameters
    ----------
    torque : float
        M_n [N·m], the torque at the nominal speed; 0 ≤ M_n ≤ 1e30.
    speed : float, optional
        Deprecated since 0.2 (goes in 0.3): the nominal speed ω_n [rad/s]; give ``rpm``.
    exponent : float, default 2
        e ≥ 0 [dimensionless]: 2 for fans, centrifugal pumps and propellers (the square
        law), 1 for viscous friction, 0 for a constant (Coulomb) torque that changes sign
        with ω.
    rpm : float
        n_n [1/min], the nominal speed (keyword only), within the speeds the package takes
        (1e-6 … 1e8 rpm).

    Attributes
    ----------
    torque : float
        M_n [N·m].
    rpm : float
        n_n [1/min], the nominal speed.
    omega : float
        ω_n = π n_n/30 [rad/s], the nominal speed in rad/s.
    exponent : float
        e [dimensionless].

    See Also
    --------
    steady_state : A square law (e = 2) is solved there in closed form.

    Examples
    --------
    A fan that takes 90 N·m at 120 rpm:

    >>> import math
    >>> import multicrank as mc
    >>> fan = mc.PowerLawLoad(torque=90.0, rpm=120)
    >>> fan.omega == 120 * math.pi / 30  # rad/s
    True
    >>> fan(0.0, [0.0, 2 * math.pi, 4 * math.pi])  # N·m at ω = 0, 2π and 4π rad/s: 0, 60 and 120 rpm
    array([ 0. , 22.5, 90. ])
    """

    torque: float
    rpm: float
    exponent: float = 2.0
    # ω_n [rad/s]: exactly the ``speed`` given, where one was (the deprecated keyword).
    omega: float = field(init=False, repr=False, compare=False, default=math.nan)

    #: The name of 0.1 for :attr:`omega` [rad/s].
    speed: ClassVar[renamed] = renamed("omega")

    def __init__(self, torque: float, speed: float | None = None, exponent: float = 2.0, *, rpm: float | None = None):
        torque = as_scalar(torque, "torque")
        name, value = one_of(("rpm", rpm), ("speed", speed))
        exponent = as_scalar(exponent, "exponent")
        if not (math.isfinite(torque) and 0 <= torque <= MAGNITUDE_LIMIT):
            raise refused(
                "torque", f"torque = {torque} is out of range; allowed: 0 <= torque <= {MAGNITUDE_LIMIT:g} [N·m]"
            )
        if name == "rpm":
            nominal = as_scalar(value, "rpm")
            omega = as_omega(nominal, "rpm")
        else:
            omega = as_scalar(value, "speed")
            low, high = SPEED_LIMITS
            if not (math.isfinite(omega) and low <= omega <= high):
                # the speeds the package takes (a speed of 1e200 rad/s overflowed in the coefficient)
                raise refused(
                    "speed", f"speed = {omega} is out of range; allowed: {low:g} <= speed <= {high:g} [rad/s]"
                )
            nominal = rpm_from_omega(omega)
        if not (math.isfinite(exponent) and exponent >= 0):
            raise refused("exponent", f"exponent = {exponent} is out of range; allowed: exponent >= 0")
        object.__setattr__(self, "torque", torque)
        object.__setattr__(self, "rpm", nominal)
        object.__setattr__(self, "exponent", exponent)
        object.__setattr__(self, "omega", omega)
        if name == "speed":
            warn_renamed("PowerLawLoad(speed=ω [rad/s])", "rpm=n [1/min]")

    def __setstate__(self, state: dict[str, Any]) -> None:
        # A pickle of 0.1 holds the nominal speed as ``speed`` [rad/s].
        if "speed" in state:
            state = dict(state)
            state["omega"] = state.pop("speed")
            state["rpm"] = rpm_from_omega(state["omega"])
        self.__dict__.update(state)

    @property
    def coefficient(self) -> float:
        """c = M_n/ω_n^e [N·m·(s/rad)^e]: M = c·sign(ω)|ω|^e."""
        return self.torque / self.omega**self.exponent

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
        ratio = np.abs(speed) / self.omega
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
            values = self.value(angles, speed)
        except MechanismError:
            raise
        except Exception as error:
            raise refused(
                self.name,
                f"{self.name} failed: {type(error).__name__}: {error}; it must be a vectorised callable "
                f"f(phi [rad], omega [rad/s]) -> torque [N·m] returning an array that broadcasts to their shape",
            ) from error
        return as_returned(values, self.name, "torque", "N·m", shape, broadcast=True).copy()

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
        raise refused(
            name,
            f"{name} = {value!r} is not understood; allowed: {allowed}a number [N·m], a "
            f"multicrank.PowerLawLoad or a callable f(phi, omega) -> N·m",
        )
    if isinstance(value, PowerLawLoad):
        return Torque("power-law", value, name)
    if callable(value):
        return Torque("callable", value, name)
    number = as_scalar(value, name)
    if not (math.isfinite(number) and abs(number) <= MAGNITUDE_LIMIT):
        raise refused(
            name, f"{name} = {number} is out of range; allowed: a finite torque, |{name}| <= {MAGNITUDE_LIMIT:g} [N·m]"
        )
    return Torque("constant", number, name)


@dataclass(frozen=True)
class AppliedTorques:
    """The load and the drive of one call, resolved (:func:`as_torque`); the load may still be
    :data:`BALANCE` until :meth:`balanced` fixes it at a speed.

    Attributes
    ----------
    load : Torque, "balance" or None
        The resisting torque (None: no load).
    drive : Torque or None
        The driving torque beside the gas (None: no drive).
    """

    load: Torque | str | None
    drive: Torque | None

    @classmethod
    def of(cls, load: Any, drive: Any) -> AppliedTorques:
        """``load=`` and ``drive=`` as a user gives them, validated (only the load may be "balance")."""
        resolved_drive = as_torque(drive, "drive")
        assert not isinstance(resolved_drive, str)  # as_torque gives "balance" only where allowed
        return cls(as_torque(load, "load", balance=True), resolved_drive)

    @property
    def balance(self) -> bool:
        """Whether the load is "balance" (not yet fixed)."""
        return self.load == BALANCE

    def balanced(self, machine: Any, omega: float) -> AppliedTorques:
        """The same torques with a "balance" load fixed at ``omega`` [rad/s]: the constant
        (1/Φ)∫₀^Φ [M_gas(φ) + M_drive(φ, ω)] dφ over one working cycle, a drive's speed
        dependence frozen at ω (gravity's mean over a cycle is 0). The gas's mean is the core's
        (the indicated work per cycle over Φ, exact also for tabulated pressures), the drive's
        a Gauss–Legendre mean (:func:`~multicrank.motion._shooting.cycle_mean`)."""
        if not self.balance:
            return self
        from ..machine.native import motion_machine
        from ._shooting import cycle_mean

        load = motion_machine(machine).mean_gas_torque()
        if self.drive is not None:
            drive = self.drive
            load += cycle_mean(lambda phi: drive(phi, omega), machine.cycle)
        return replace(self, load=Torque("constant", float(load), "load"))

    def net(self, phi: Any, omega: Any) -> np.ndarray:
        """M_drive − M_load [N·m] at φ [rad] and ω [rad/s] (a "balance" load not yet fixed counts as none)."""
        value = np.zeros(np.broadcast_shapes(np.shape(phi), np.shape(omega)))
        if self.drive is not None:
            value = value + self.drive(phi, omega)
        if isinstance(self.load, Torque):
            value = value - self.load(phi, omega)
        return value
