"""The periodic solution by its route, shared by :mod:`~multicrank.motion.steady` and
:mod:`~multicrank.motion.flywheel`: the inputs they share validated (load and drive, the mean
speed, the stall criterion), the route the load asks for chosen, and solved on the machine's
cycle tables by the numerics of :mod:`~multicrank.motion._solvers`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._native import MechanismError
from .._shaft import omega_from_rpm
from .._validation import as_scalar, as_speed
from ..machine.machine import Machine
from ._quadrature import CycleQuadrature
from ._solvers import Balance, CycleTables, Periodic, Shooting, SquareLaw, Stall, quasi_static_speed
from .loads import BALANCE, AppliedTorques, Torque, balance_torque

__all__ = [
    "DEFAULT_MIN_SPEED_RATIO",
    "METHODS",
    "SOLVED",
    "Rules",
    "as_min_speed_ratio",
    "balance_at",
    "cycle_tables",
    "mean_speed",
    "resolve_rules",
    "solve_periodic",
]

#: ω_min/ω_m below which a machine is said to stall.
DEFAULT_MIN_SPEED_RATIO = 1e-3
# The shooting's relative tolerance (solve_ivp's rtol and the root's): ω_m to ~1e-10.
_SHOOTING_RTOL = 1e-11


def as_min_speed_ratio(value: Any) -> float:
    ratio = as_scalar(value, "min_speed_ratio")
    # Below 1e-9 the crawl over a dead centre takes longer than any run (and 1/ratio² leaves
    # the range of a double on the way): such a machine has stalled by any measure.
    if not 1e-9 <= ratio < 1.0:
        raise MechanismError(f"min_speed_ratio = {ratio} is out of range; allowed: 1e-9 <= min_speed_ratio < 1")
    return ratio


def mean_rpm(value: Any, route: str, machine: Machine) -> float | None:
    """The mean speed n [1/min] asked for, ``rpm`` = ``value``, default the machine's own
    ``rpm`` (as :meth:`~multicrank.Machine.engine` takes it), checked; None where the load
    fixes the speed."""
    if route != BALANCE:
        if value is not None:
            raise MechanismError(
                f"rpm = {value!r} is not allowed with this load: a {route} load fixes the mean speed itself "
                "(it is a result); pass rpm only with load='balance'"
            )
        return None
    if value is None:
        if machine.rpm is None:
            raise MechanismError(
                f"rpm is required with load='balance': the mean speed [1/min] to run at (machine {machine.name!r} "
                "has no rpm of its own)"
            )
        value = machine.rpm
    return as_speed(value, "rpm")


def mean_speed(value: Any, route: str, machine: Machine) -> float | None:
    """ω_m [rad/s] of :func:`mean_rpm`; None where the load fixes the speed."""
    rpm = mean_rpm(value, route, machine)
    return None if rpm is None else omega_from_rpm(rpm)


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


def resolve_rules(load: Any, drive: Any) -> Rules:
    """``load=`` and ``drive=`` validated, and the route that solves them."""
    torques = AppliedTorques.of(load, drive)
    load_, drive_ = torques.load, torques.drive
    constant_drive = drive_ is None or drive_.kind == "constant"
    if torques.balance:
        return Rules(BALANCE, torques)
    assert not isinstance(load_, str)
    if isinstance(load_, Torque) and load_.kind == "power-law" and load_.value.exponent == 2 and constant_drive:
        if load_.value.coefficient == 0:
            raise MechanismError(
                "load = PowerLawLoad(torque=0, ...) takes no torque: nothing holds the speed; "
                "use load='balance' with rpm"
            )
        return Rules("square-law", torques)
    if (load_ is None or load_.kind == "constant") and constant_drive:
        raise MechanismError(
            f"load = {load!r} is a constant torque and so is the drive: the machine has no periodic steady state "
            "unless the load equals the cycle mean of gas and drive exactly — that is load='balance' (with rpm); "
            "or give a load that grows with speed (mc.PowerLawLoad, or a callable f(phi, omega))"
        )
    return Rules("general", torques)


def cycle_tables(machine: Machine, gravity: bool) -> CycleTables:
    """The machine over its cycle (g = 0 without gravity). Its panels are cut at the gassed
    units' dead centres only — the gas torque enters through its exact work
    (:class:`~multicrank._work.GasWork`), which takes the pressure tables' breakpoints — and
    are π/8 wide or, where the machine's J and U have harmonics too high for that (a large
    crank ratio, many cylinders), halved until their interpolants converge."""
    width = math.pi / 8
    work = None
    while True:
        rule = CycleQuadrature.of(machine, tables=False, max_width=width)
        cycle = CycleTables(machine, rule, gravity=gravity, work=work)
        if width < math.pi / 60 or cycle.resolved():
            return cycle
        width, work = width / 2, cycle.work


def rest_angle(cycle: CycleTables, drive: float) -> float:
    """Where a machine with no mean driving torque comes to rest [rad]: the sample where the
    work of gas, drive and gravity from φ = 0, W + M_drive·φ − (U − U(0)), is largest — the
    bottom of the well of their potential (for a machine without gas or drive, the lowest
    potential energy)."""
    rule = cycle.rule
    angles = np.concatenate([rule.phi.ravel(), rule.edges])
    work = np.concatenate([cycle.W.ravel(), cycle.W_edges]) + drive * angles
    work -= np.concatenate([cycle.U.ravel(), cycle.U_edges])
    return float(angles[int(np.argmax(work))] % rule.cycle)


def balance_at(cycle: CycleTables, rules: Rules, omega_mean: float) -> Balance:
    """The energy method for "balance": the drive at the nodes and the balancing load
    (:func:`~multicrank.motion.loads.balance_torque`), a drive's speed dependence frozen at ω_m."""
    drive = None if rules.drive is None else rules.drive(cycle.rule.phi, omega_mean)
    load = balance_torque(cycle.machine, rules.drive, omega_mean, cycle.rule, work=cycle.work)
    return Balance(cycle, drive, load)


def solve_periodic(cycle: CycleTables, rules: Rules, omega_mean: float | None, ratio: float) -> Periodic:
    """One periodic solution by the route of ``rules``; raises _solvers.Stall."""
    if rules.route == BALANCE:
        assert omega_mean is not None
        return balance_at(cycle, rules, omega_mean).solve(omega_mean, ratio)
    if rules.route == "square-law":
        assert isinstance(rules.load, Torque)
        # What a balancing load would take beside gas and drive (the drive is constant: any ω).
        mean = balance_torque(cycle.machine, rules.drive, 0.0, cycle.rule, work=cycle.work)
        if not mean > 0:
            # Nothing drives the machine on the cycle's mean (a design without gas, or a drive
            # that takes what the gas gives): a square-law load brings it to rest, a stall like
            # any other (a sweep's row, not an error in the input).
            raise Stall(
                rest_angle(cycle, rules.constant_drive),
                f"the cycle mean of gas and drive torque is {mean:.6g} N·m, not positive: nothing drives it "
                "against a square-law load, which brings it to rest",
            )
        return SquareLaw(cycle, rules.constant_drive, rules.load.value.coefficient).solve(ratio)
    applied = rules.torques.net
    guess = quasi_static_speed(cycle, applied, "load")
    # Runs stop where ω falls to half of min_speed_ratio times the speed the torques balance at.
    floor = 0.5 * float(np.min(cycle.J)) * (0.5 * ratio * guess) ** 2
    return Shooting(cycle, applied, _SHOOTING_RTOL, floor).solve(guess, ratio)
