"""The rules of a periodic solution, shared by :mod:`~multicrank.motion.steady` and
:mod:`~multicrank.motion.flywheel`: the inputs they share validated (load and drive, the mean
speed, the stall criterion), the route the load asks for chosen ("balance" and the square law:
the Rust core; any other: shooting), and a callable drive under "balance" as the core takes it
(:func:`drive_table`), and the machine whose diagrams its load law gives at the mean speed
(:func:`at_load`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import as_scalar, refused, running_omega
from ..machine.machine import Machine, load_factor, rated_omega
from .loads import BALANCE, AppliedTorques, Torque

__all__ = [
    "DEFAULT_MIN_SPEED_RATIO",
    "METHODS",
    "SOLVED",
    "Rules",
    "as_min_speed_ratio",
    "at_load",
    "drive_table",
    "mean_speed",
    "resolve_rules",
]

#: ω_min/ω_m below which a machine is said to stall.
DEFAULT_MIN_SPEED_RATIO = 1e-3


def as_min_speed_ratio(value: Any) -> float:
    ratio = as_scalar(value, "min_speed_ratio")
    # Below 1e-9 the crawl over a dead centre takes longer than any run (and 1/ratio² leaves
    # the range of a double on the way): such a machine has stalled by any measure.
    if not 1e-9 <= ratio < 1.0:
        raise refused(
            "min_speed_ratio", f"min_speed_ratio = {ratio} is out of range; allowed: 1e-9 <= min_speed_ratio < 1"
        )
    return ratio


def mean_speed(value: Any, route: str, machine: Machine) -> float | None:
    """ω_m [rad/s] of the mean speed asked for, ``rpm`` = ``value`` [1/min], default the
    machine's own ``rpm`` (as :meth:`~multicrank.Machine.engine` takes it), checked and
    converted once (:func:`~multicrank._validation.as_omega`); None where the load fixes the
    speed."""
    if route != BALANCE:
        if value is not None:
            raise refused(
                "rpm",
                f"rpm = {value!r} is not allowed with this load: a {route} load fixes the mean speed itself "
                "(it is a result); pass rpm only with load='balance'",
            )
        return None
    return running_omega(machine, value)


#: How each route is solved (:attr:`SteadyState.method`), and what that is in words.
METHODS = {BALANCE: "energy", "square-law": "closed form", "general": "shooting"}
SOLVED = {
    "energy": "balance load (energy method)",
    "closed form": "square-law load (closed form)",
    "shooting": "periodic motion (shooting)",
}


@dataclass(frozen=True)
class Rules:
    """The load and drive resolved, and which route solves them."""

    route: str  # "balance", "square-law" or "general"
    torques: AppliedTorques

    @property
    def load(self) -> Torque | str | None:
        return self.torques.load

    @property
    def drive(self) -> Torque | None:
        return self.torques.drive

    @property
    def plain_balance(self) -> bool:
        """The "balance" load beside no drive or a drive that does not depend on φ (a
        constant, a :class:`~multicrank.PowerLawLoad` held at ω_m): the energy method the
        Rust core solves. Such a drive M_d adds M_d·φ to the work and as much to the balancing
        load, so K(φ), and with it the motion, is that of no drive; only the load grows by M_d."""
        return self.route == BALANCE and (self.drive is None or self.drive.kind != "callable")

    def drive_at(self, omega_mean: float) -> float:
        """The drive [N·m] of a :attr:`plain_balance` at the mean speed ω_m [rad/s] (0 without one)."""
        return 0.0 if self.drive is None else float(self.drive(0.0, omega_mean))

    @property
    def constant_drive(self) -> float:
        return 0.0 if self.drive is None else float(self.drive.value)


def drive_table(machine: Machine, rules: Rules, omega_mean: float) -> tuple[np.ndarray, np.ndarray] | None:
    """The drive of a "balance" load as the core takes it: a callable f(φ, ω) held at ω_m =
    ``omega_mean`` [rad/s] and sampled once over the working cycle
    (:func:`~multicrank.machine.native.sampled`, checked as a torque [N·m] named ``drive``);
    None for no drive or one that does not depend on φ (:attr:`Rules.plain_balance`: it only
    adds to the load)."""
    drive = rules.drive
    if rules.plain_balance or drive is None:
        return None
    from ..machine.native import sampled

    return sampled(lambda theta: drive(theta, omega_mean), machine.cycle, "drive", "torque", "N·m")


def at_load(machine: Machine, omega_mean: float | None) -> Machine:
    """The machine with the diagrams its :attr:`~multicrank.Machine.load_law` gives at the mean
    speed ω_m = ``omega_mean`` [rad/s]: every gauge pressure times the law's factor, as a
    motion sweep's ``pressure_scale`` scales them
    (:func:`~multicrank.motion.variants.scaled_pressure`; a diagram the cylinders share scaled
    once), and the law removed. ``machine`` itself without a law, at its rated speed, or where
    the load fixes the speed itself (``omega_mean`` None: the diagrams as given)."""
    factor = 1.0 if omega_mean is None else load_factor(omega_mean, rated_omega(machine))
    if factor == 1.0:
        return machine
    from .variants import scaled_pressure  # the sweep's machinery, imported when first needed

    scaled: dict[int, Any] = {}

    def scale(pressure: Any) -> Any:
        if id(pressure) not in scaled:
            scaled[id(pressure)] = scaled_pressure(pressure, factor)
        return scaled[id(pressure)]

    cylinders = [
        c.replace(pressure=scale(c.pressure), pressure_crank_end=scale(c.pressure_crank_end)) for c in machine.cylinders
    ]
    return machine.replace(cylinders=cylinders, load_law=None)


def resolve_rules(load: Any, drive: Any) -> Rules:
    """``load=`` and ``drive=`` validated, and the route that solves them."""
    if drive is None and isinstance(load, str) and load == BALANCE:
        return _BALANCE_ALONE  # the default, resolved once (a warm steady state is ~25 µs)
    torques = AppliedTorques.of(load, drive)
    load_, drive_ = torques.load, torques.drive
    constant_drive = drive_ is None or drive_.kind == "constant"
    if torques.balance:
        return Rules(BALANCE, torques)
    assert not isinstance(load_, str)
    if isinstance(load_, Torque) and load_.kind == "power-law" and load_.value.exponent == 2 and constant_drive:
        if load_.value.coefficient == 0:
            raise refused(
                "load",
                "load = PowerLawLoad(torque=0, ...) takes no torque: nothing holds the speed; "
                "use load='balance' with rpm",
            )
        return Rules("square-law", torques)
    if (load_ is None or load_.kind == "constant") and constant_drive:
        raise refused(
            "load",
            f"load = {load!r} is a constant torque and so is the drive: the machine has no periodic steady state "
            "unless the load equals the cycle mean of gas and drive exactly — that is load='balance' (with rpm); "
            "or give a load that grows with speed (mc.PowerLawLoad, or a callable f(phi, omega))",
        )
    return Rules("general", torques)


#: The rules of the default load ("balance", no drive), as :func:`resolve_rules` resolves them.
_BALANCE_ALONE = Rules(BALANCE, AppliedTorques.of(BALANCE, None))
