"""The machine in steady running: its periodic motion, its speed fluctuation, its flywheel
(docs/theory.md, "Steady running").

A machine whose torques repeat every working cycle Φ (2π two-stroke, 4π four-stroke) runs,
once the start-up has died away, periodically: ω(φ + Φ) = ω(φ). :func:`steady_state` finds
that motion exactly (to the accuracy stated below) from Lagrange's equation

    J(φ) φ̈ + ½ J'(φ) φ̇² = M_gas(φ) − U'(φ) + M_drive − M_load,

with J the reduced moment of inertia, U the potential energy of gravity and the torques in
N·m, all from the Rust core (:class:`~multicrank.machine.Machine`); and
:func:`flywheel_inertia` the shaft inertia that keeps the fluctuation at a given δ.

Three routes, chosen by the load:

- ``load="balance"`` (the default): the constant load that takes the cycle mean of gas and
  drive. Every torque then depends on φ alone and the energy integral gives the motion in
  closed form, ω²(φ) = 2[E₀ + K(φ)]/J(φ), K = ∫₀^φ(M_gas + M_drive − M_load) dφ − ΔU; E₀ is
  the one number that gives the mean speed asked for (``rpm``).
- a :class:`~multicrank.loads.PowerLawLoad` of exponent 2 (fan, pump, propeller) with no drive
  or a constant one: the energy E = ½Jω² obeys a *linear* equation whose periodic solution is
  an explicit double integral. The load fixes the mean speed.
- any other load or drive: shooting for E(0) = E(Φ) with SciPy's ``solve_ivp``.

SciPy is imported when a steady state is computed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._native import MechanismError
from .._validation import as_count, as_scalar
from ..machine.machine import Machine, as_speed
from ._quadrature import CycleQuadrature
from ._solvers import Balance, Cycle, Periodic, Shooting, SquareLaw, Stall, quasi_static_speed, scipy_optimize
from .loads import BALANCE, PowerLawLoad, Torque, as_torque

__all__ = ["FlywheelInertia", "PowerLawLoad", "StallError", "SteadyState", "flywheel_inertia", "steady_state"]

#: ω_min/ω_m below which a machine is said to stall.
DEFAULT_MIN_SPEED_RATIO = 1e-3
# The shooting's relative tolerance (solve_ivp's rtol and the root's): ω_m to ~1e-10.
_SHOOTING_RTOL = 1e-11


class StallError(MechanismError):
    """The machine does not run steadily as asked: it would crawl over (or stop at) its dead
    point. A :class:`~multicrank.MechanismError` (and so a ``ValueError``).

    Raised by :func:`steady_state` and :func:`flywheel_inertia`; the message says where and,
    for ``load="balance"``, the lowest mean speed that runs.

    Parameters
    ----------
    message : str
        What happened, in words.
    angle : float
        The crank angle φ [rad] of the speed minimum.
    min_rpm : float, optional
        For ``load="balance"``: the lowest mean speed [1/min] that runs.

    Attributes
    ----------
    angle : float
        The crank angle φ [rad] of the speed minimum (where it stops or crawls).
    min_rpm : float or None
        For ``load="balance"``: the lowest mean speed [1/min] that runs, i.e. whose speed
        minimum is ``min_speed_ratio`` times the mean speed. None for other loads, which fix
        the speed themselves.

    Examples
    --------
    >>> import multicrank as mc
    >>> compressor = mc.presets.ENGINES["slow-compressor"]
    >>> try:
    ...     mc.steady_state(compressor, rpm=5)
    ... except mc.StallError as error:
    ...     print(f"stalls; runs from {error.min_rpm:.1f} rpm")
    stalls; runs from 8.4 rpm
    """

    def __init__(self, message: str, *, angle: float, min_rpm: float | None = None) -> None:
        super().__init__(message)
        self.angle = float(angle)
        self.min_rpm = None if min_rpm is None else float(min_rpm)


# -- inputs ------------------------------------------------------------------------------------


def _as_machine(machine: Any) -> Machine:
    if not isinstance(machine, Machine):
        raise MechanismError(f"machine must be a multicrank.Machine, got {type(machine).__name__}")
    return machine


def _as_flag(value: Any, name: str) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise MechanismError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def _as_ratio(value: Any) -> float:
    ratio = as_scalar(value, "min_speed_ratio")
    # Below 1e-9 the crawl over a dead centre takes longer than any run (and 1/ratio² leaves
    # the range of a double on the way): such a machine has stalled by any measure.
    if not 1e-9 <= ratio < 1.0:
        raise MechanismError(f"min_speed_ratio = {ratio} is out of range; allowed: 1e-9 <= min_speed_ratio < 1")
    return ratio


def _as_rpm(value: Any, route: str) -> float | None:
    if route != BALANCE:
        if value is not None:
            raise MechanismError(
                f"rpm = {value!r} is not allowed with this load: a {route} load fixes the mean speed itself "
                "(it is a result); pass rpm only with load='balance'"
            )
        return None
    if value is None:
        raise MechanismError("rpm is required with load='balance': the mean speed [1/min] to run at")
    return as_speed(value, "rpm")


#: Points of a result's arrays over the closed cycle: every degree of a two-stroke cycle,
#: every other degree of a four-stroke one (the arrays are for plots and tables; δ and the
#: extremes do not depend on them).
DEFAULT_POINTS = 361


def _as_points(value: Any) -> int:
    return DEFAULT_POINTS if value is None else as_count(value, "points", minimum=2)


@dataclass(frozen=True)
class _Rules:
    """The load and drive resolved, and which route solves them."""

    route: str  # "balance", "square-law" or "general"
    load: Torque | str | None
    drive: Torque | None

    @property
    def constant_drive(self) -> float:
        return 0.0 if self.drive is None else float(self.drive.value)


def _rules(load: Any, drive: Any) -> _Rules:
    load_ = as_torque(load, "load", balance=True)
    drive_ = as_torque(drive, "drive")
    assert not isinstance(drive_, str)  # "balance" is a load only
    constant_drive = drive_ is None or drive_.kind == "constant"
    if load_ == BALANCE:
        return _Rules(BALANCE, load_, drive_)
    assert not isinstance(load_, str)
    if isinstance(load_, Torque) and load_.kind == "power-law" and load_.value.exponent == 2 and constant_drive:
        if load_.value.coefficient == 0:
            raise MechanismError(
                "load = PowerLawLoad(torque=0, ...) takes no torque: nothing holds the speed; "
                "use load='balance' with rpm"
            )
        return _Rules("square-law", load_, drive_)
    if (load_ is None or load_.kind == "constant") and constant_drive:
        raise MechanismError(
            f"load = {load!r} is a constant torque and so is the drive: the machine has no periodic steady state "
            "unless the load equals the cycle mean of gas and drive exactly — that is load='balance' (with rpm); "
            "or give a load that grows with speed (mc.PowerLawLoad, or a callable f(phi, omega))"
        )
    return _Rules("general", load_, drive_)


def _cycle(machine: Machine, gravity: bool) -> Cycle:
    """The machine over its cycle (g = 0 without gravity). Its panels are cut at the gassed
    units' dead centres only — the gas torque enters through its exact work
    (:class:`~multicrank._work.GasWork`), which takes the pressure tables' breakpoints — and
    are π/8 wide or, where the machine's J and U have harmonics too high for that (a large
    crank ratio, many cylinders), halved until their interpolants converge."""
    width = math.pi / 8
    work = None
    while True:
        rule = CycleQuadrature.of(machine, tables=False, max_width=width)
        cycle = Cycle(machine, rule, gravity=gravity, work=work)
        if width < math.pi / 60 or cycle.resolved():
            return cycle
        width, work = width / 2, cycle.work


# -- the result ----------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class SteadyState:
    """A machine's periodic steady running over one closed cycle [0, Φ]: the result of
    :func:`steady_state`.

    The arrays have shape (points,), φ uniform from 0 to Φ inclusive, and are read-only.
    ``print(state)`` shows :meth:`summary`.

    Attributes
    ----------
    phi : ndarray
        Crank angle φ [rad].
    omega : ndarray
        Shaft speed ω(φ) [rad/s].
    time : ndarray
        t(φ) [s] from φ = 0; ``time[-1]`` = t_Φ, the time of one cycle.
    J, dJ_dphi : ndarray
        The reduced moment of inertia [kg·m²] and its slope [kg·m²/rad].
    torque_gas : ndarray
        M_gas [N·m].
    torque_gravity : ndarray
        −dU/dφ [N·m] (zero when solved without gravity).
    torque_inertia : ndarray
        −½ J'(φ) ω² [N·m] at the actual speed.
    torque_drive : ndarray
        M_drive [N·m] (with ``load="balance"`` at the mean speed, as solved).
    torque_load : ndarray
        M_load [N·m], positive resisting.
    acceleration : ndarray
        φ̈ [rad/s²] = (gas + gravity + inertia + drive − load)/J.
    omega_mean : float
        ω_m = Φ/t_Φ [rad/s], the time mean (:attr:`rpm` in 1/min).
    omega_max, omega_min : float
        The extreme speeds [rad/s], located exactly.
    phi_max, phi_min : float
        Where they occur [rad].
    period : float
        t_Φ [s], the time of one working cycle.
    cycle : float
        Φ [rad], 2π or 4π.
    load_torque : float
        The constant load "balance" found, or the load's cycle mean (1/Φ)∫M_load dφ [N·m].
    delta_without_gravity : float
        δ of the same machine and load rule with g = 0 (for "balance" at the same mean
        speed) [dimensionless]; NaN where that machine would stall.
    delta_gravity_only : float
        δ of the machine with gas, drive and load removed, at the same mean speed: gravity
        (and the variation of J) alone — the exact counterpart of δ_g (docs/theory.md)
        [dimensionless]; NaN where it would stall.
    method : str
        How it was solved: "energy", "closed form" or "shooting".
    load_rule : str
        The load as given, in words.
    gravity : bool
        Whether g was kept.
    min_speed_ratio : float
        As asked.
    machine : Machine
        As given.
    """

    machine: Machine
    method: str
    load_rule: str
    gravity: bool
    min_speed_ratio: float
    cycle: float
    phi: np.ndarray = field(repr=False)
    omega: np.ndarray = field(repr=False)
    time: np.ndarray = field(repr=False)
    J: np.ndarray = field(repr=False)
    dJ_dphi: np.ndarray = field(repr=False)
    torque_gas: np.ndarray = field(repr=False)
    torque_gravity: np.ndarray = field(repr=False)
    torque_inertia: np.ndarray = field(repr=False)
    torque_drive: np.ndarray = field(repr=False)
    torque_load: np.ndarray = field(repr=False)
    acceleration: np.ndarray = field(repr=False)
    omega_mean: float
    omega_max: float
    omega_min: float
    phi_max: float
    phi_min: float
    period: float
    load_torque: float
    delta_without_gravity: float
    delta_gravity_only: float

    @property
    def rpm(self) -> float:
        """The mean speed n = 30 ω_m/π [1/min]."""
        return 30.0 * self.omega_mean / math.pi

    @property
    def delta(self) -> float:
        """δ = (ω_max − ω_min)/ω_m, ω_m the time mean Φ/t_Φ."""
        return (self.omega_max - self.omega_min) / self.omega_mean

    @property
    def delta_midrange(self) -> float:
        """(ω_max − ω_min)/((ω_max + ω_min)/2): δ about the midrange, the textbook convention."""
        return 2.0 * (self.omega_max - self.omega_min) / (self.omega_max + self.omega_min)

    @property
    def gravity_effect(self) -> float:
        """δ − δ_without_gravity: what gravity adds to the fluctuation (may be negative)."""
        return self.delta - self.delta_without_gravity

    ARRAYS = (
        "phi",
        "time",
        "omega",
        "J",
        "dJ_dphi",
        "torque_gas",
        "torque_gravity",
        "torque_inertia",
        "torque_drive",
        "torque_load",
        "acceleration",
    )

    def to_pandas(self) -> Any:
        """The arrays as a table.

        Returns
        -------
        pandas.DataFrame
            Indexed by ``phi`` [rad], one column per array attribute (the attributes' names
            and units) and ``rpm``, the speed in 1/min.
        """
        import pandas as pd

        columns = {name: getattr(self, name) for name in self.ARRAYS if name != "phi"}
        columns["rpm"] = 30.0 * self.omega / math.pi
        return pd.DataFrame(columns, index=pd.Index(self.phi, name="phi"))

    def summary(self) -> str:
        """A few readable lines: speeds, δ in both conventions, and what gravity does.

        Returns
        -------
        str
            The lines, joined by newlines (also the ``repr`` of the result).
        """
        degrees = math.degrees
        lines = [
            f"steady state of {self.machine.name!r} ({self.machine.strokes}-stroke, {len(self.machine)} cylinders), "
            f"load {self.load_rule}, by {self.method}{'' if self.gravity else ', without gravity'}",
            f"  mean speed       {self.rpm:.6g} rpm (ω_m = {self.omega_mean:.8g} rad/s, t_Φ = {self.period:.6g} s)",
            f"  ω_max            {self.omega_max:.8g} rad/s at φ = {degrees(self.phi_max):.4f}°",
            f"  ω_min            {self.omega_min:.8g} rad/s at φ = {degrees(self.phi_min):.4f}°",
            f"  load torque      {self.load_torque:.6g} N·m",
            f"  δ (time mean)    {self.delta:.6e}   (about the midrange: {self.delta_midrange:.6e})",
            f"  δ without gravity {self.delta_without_gravity:.6e}   (gravity changes δ by {self.gravity_effect:+.3e})",
            f"  δ gravity alone  {self.delta_gravity_only:.6e}",
        ]
        return "\n".join(lines)

    def __repr__(self) -> str:
        return self.summary()


# -- the solvers ---------------------------------------------------------------------------------


def _applied(rules: _Rules) -> Any:
    """M_drive − M_load as one callable (φ, ω) [N·m] for the shooting."""
    drive, load = rules.drive, rules.load

    def torque(phi: np.ndarray, omega: Any) -> np.ndarray:
        value = np.zeros(np.broadcast_shapes(np.shape(phi), np.shape(omega)))
        if drive is not None:
            value = value + drive(phi, omega)
        if isinstance(load, Torque):
            value = value - load(phi, omega)
        return value

    return torque


def _drive_at_mean(cycle: Cycle, rules: _Rules, omega_mean: float) -> np.ndarray | None:
    """ "balance": the drive at the nodes, its speed dependence frozen at ω_m."""
    return None if rules.drive is None else rules.drive(cycle.rule.phi, omega_mean)


def _solve(cycle: Cycle, rules: _Rules, omega_mean: float | None, ratio: float) -> Periodic:
    """One periodic solution by the route of ``rules``; raises _steady.Stall."""
    if rules.route == BALANCE:
        assert omega_mean is not None
        return Balance(cycle, _drive_at_mean(cycle, rules, omega_mean)).solve(omega_mean, ratio)
    if rules.route == "square-law":
        assert isinstance(rules.load, Torque)
        mean = cycle.gas_mean + rules.constant_drive
        if not mean > 0:
            raise MechanismError(
                f"drive: the cycle mean of gas and drive torque is {mean:.6g} N·m, not positive: "
                "a square-law load cannot balance it at any positive speed"
            )
        return SquareLaw(cycle, rules.constant_drive, rules.load.value.coefficient).solve(ratio)
    applied = _applied(rules)
    guess = quasi_static_speed(cycle, applied, "load")
    # Runs stop where ω falls to half of min_speed_ratio times the speed the torques balance at.
    floor = 0.5 * float(np.min(cycle.J)) * (0.5 * ratio * guess) ** 2
    return Shooting(cycle, applied, _SHOOTING_RTOL, floor).solve(guess, ratio)


def _load_mean(cycle: Cycle, rules: _Rules, solution: Periodic) -> float:
    if rules.route == BALANCE or not isinstance(rules.load, Torque):
        return solution.load_torque if rules.route == BALANCE else 0.0
    phi = cycle.rule.phi
    return cycle.rule.mean(rules.load(phi, solution.omega_at(phi)))


def _stall_error(error: Stall, cycle: Cycle, rules: _Rules, omega_mean: float | None, ratio: float) -> StallError:
    error.angle %= cycle.rule.cycle
    if rules.route != BALANCE:
        return StallError(
            f"the machine stalls with this load: {error}, near φ = {math.degrees(error.angle):.4g}°; it has no "
            f"steady running (min_speed_ratio = {ratio:g})",
            angle=error.angle,
        )
    assert omega_mean is not None
    balance = Balance(cycle, _drive_at_mean(cycle, rules, omega_mean))
    lowest = balance.lowest_running_speed(ratio, above=1e-6 * balance.swing)
    min_rpm = 30.0 * lowest / math.pi
    return StallError(
        f"the machine stalls at rpm = {30.0 * omega_mean / math.pi:.6g}: {error}; it would crawl over its dead point "
        f"at φ = {math.degrees(error.angle):.4g}° (ω_min < min_speed_ratio·ω_m with min_speed_ratio = {ratio:g}); "
        f"the lowest mean speed that runs is min_rpm = {min_rpm:.6g}",
        angle=error.angle,
        min_rpm=min_rpm,
    )


def _delta_or_nan(cycle: Cycle, rules: _Rules, omega_mean: float | None, ratio: float) -> float:
    try:
        return _solve(cycle, rules, omega_mean, ratio).delta
    except Stall:
        return math.nan


def steady_state(
    machine: Machine,
    *,
    rpm: Any = None,
    load: Any = BALANCE,
    drive: Any = None,
    gravity: Any = True,
    min_speed_ratio: Any = DEFAULT_MIN_SPEED_RATIO,
    points: Any = None,
) -> SteadyState:
    """The machine's periodic steady running: ω(φ) over one working cycle, δ, and what gravity does.

    Parameters
    ----------
    machine : Machine
        The machine (its ``shaft_inertia``, cylinders, gas pressures, strokes and g).
    rpm : float, optional
        The mean speed n [1/min] (time mean, ω_m = πn/30); required with ``load="balance"``
        and refused with any other load, which fixes the speed itself.
    load : "balance", float, PowerLawLoad or callable, default "balance"
        The resisting torque [N·m] (positive opposes rotation). "balance": the constant that
        takes the cycle mean of gas and drive torque (for a four-stroke machine over 4π).
        A PowerLawLoad of exponent 2 with no drive or a constant drive is solved in closed
        form; any other speed-dependent load by shooting. A constant load (other than
        "balance") has no periodic solution and is refused.
    drive : float, PowerLawLoad or callable, optional
        A driving torque [N·m] (positive accelerates), beside the gas torque. With "balance" a
        callable f(φ, ω) is taken at ω = ω_m.
    gravity : bool, default True
        False solves the machine with g = 0.
    min_speed_ratio : float, default 1e-3
        The machine stalls when its speed minimum falls below this fraction of the mean
        speed [dimensionless]; 1e-9 ≤ min_speed_ratio < 1.
    points : int, default 361
        Points of the result's arrays, uniform over the closed cycle [0, Φ] (every degree of a
        two-stroke cycle, every other degree of a four-stroke one).

    Returns
    -------
    SteadyState
        ω(φ), the torques and δ over one working cycle, with δ without gravity and of
        gravity alone.

    Raises
    ------
    StallError
        When the machine would crawl over its dead point: ω_min < min_speed_ratio·ω_m, or no
        periodic solution with positive speed exists. Carries ``angle`` and, for "balance",
        ``min_rpm``.
    MechanismError
        For bad input, naming the parameter; for a load that cannot be balanced.

    Notes
    -----
    Accuracy (measured in tests/test_motion.py against independent time integrations): for
    smooth torques δ to 1e-7 relative and ω_m to 1e-9; with tabulated pressures (kinks
    between the nodes the integration cannot see) δ to 1e-3 and ω_m to 1e-7. The extremes are
    located on the quadrature panels' interpolants and evaluated exactly there.

    Examples
    --------
    The slow compressor at its speed, the motor taking the mean torque ("balance"):

    >>> import multicrank as mc
    >>> compressor = mc.presets.ENGINES["slow-compressor"]
    >>> state = mc.steady_state(compressor, rpm=120)
    >>> print(f"δ = {state.delta:.5f} with gravity, "
    ...       f"{state.delta_without_gravity:.5f} without")
    δ = 0.02953 with gravity, 0.02502 without
    >>> print(f"load {state.load_torque:.1f} N·m, ω from {state.omega_min:.3f} "
    ...       f"to {state.omega_max:.3f} rad/s")
    load -916.0 N·m, ω from 12.368 to 12.739 rad/s

    A motor of constant torque driving the compressor and a fan: the fan's square law fixes
    the speed (no ``rpm``), and the steady state comes in closed form.

    >>> import math
    >>> fan = mc.PowerLawLoad(torque=90.0, speed=120 * math.pi / 30)  # 90 N·m, 120 rpm
    >>> state = mc.steady_state(compressor, load=fan, drive=1000.0)
    >>> print(f"{state.rpm:.2f} rpm by {state.method}, δ = {state.delta:.5f}")
    115.90 rpm by closed form, δ = 0.03184
    """
    machine = _as_machine(machine)
    rules = _rules(load, drive)
    omega_mean = _as_rpm(rpm, rules.route)
    if omega_mean is not None:
        omega_mean *= math.pi / 30.0
    gravity = _as_flag(gravity, "gravity")
    ratio = _as_ratio(min_speed_ratio)
    count = _as_points(points)

    phi = np.linspace(0.0, machine.cycle, count)
    cycle = _cycle(machine, gravity)
    try:
        solution = _solve(cycle, rules, omega_mean, ratio)
    except Stall as error:
        raise _stall_error(error, cycle, rules, omega_mean, ratio) from None
    mean = solution.omega_mean
    if cycle.gravity_on:
        delta_without = _delta_or_nan(cycle.without_gravity(), rules, omega_mean, ratio)
    else:
        delta_without = solution.delta
    # Gravity alone: gas, drive and load gone; the conservative machine at the same mean speed.
    try:
        delta_alone = Balance(cycle, None, gas=False).solve(mean, ratio).delta
    except Stall:
        delta_alone = math.nan

    J, slope = cycle.J_at(phi)
    omega = np.sqrt(2.0 * np.maximum(solution.energy_at(phi), 0.0) / J)
    time = solution.time_at(phi)
    time[0], time[-1] = 0.0, solution.period
    gas = cycle.machine.gas_torque(phi)
    weight = cycle.machine.gravity_torque(phi) if cycle.gravity_on else np.zeros(count)
    inertia = -0.5 * slope * omega**2
    speed = np.full(count, mean) if rules.route == BALANCE else omega
    drive_ = rules.drive(phi, speed) if rules.drive is not None else np.zeros(count)
    if rules.route == BALANCE:
        load_ = np.full(count, solution.load_torque)
    else:
        load_ = rules.load(phi, omega) if isinstance(rules.load, Torque) else np.zeros(count)
    acceleration = (gas + weight + inertia + drive_ - load_) / J
    arrays = dict(
        phi=phi,
        omega=omega,
        time=time,
        J=J,
        dJ_dphi=slope,
        torque_gas=gas,
        torque_gravity=weight,
        torque_inertia=inertia,
        torque_drive=drive_,
        torque_load=load_,
        acceleration=acceleration,
    )
    for array in arrays.values():
        array.flags.writeable = False
    extremes = solution.extremes
    return SteadyState(
        machine=machine,
        method=solution.method,
        load_rule=_describe(load, rules),
        gravity=gravity,
        min_speed_ratio=ratio,
        cycle=machine.cycle,
        **arrays,
        omega_mean=mean,
        omega_max=extremes.omega_max,
        omega_min=extremes.omega_min,
        phi_max=extremes.phi_max,
        phi_min=extremes.phi_min,
        period=solution.period,
        load_torque=_load_mean(cycle, rules, solution),
        delta_without_gravity=delta_without,
        delta_gravity_only=delta_alone,
    )


def _describe(load: Any, rules: _Rules) -> str:
    if rules.route == BALANCE:
        return "'balance'"
    if isinstance(load, PowerLawLoad):
        return repr(load)
    return repr(load) if not callable(load) else getattr(load, "__name__", "callable")


# -- the flywheel ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class FlywheelInertia:
    """The shaft inertia that gives a machine a coefficient of speed fluctuation δ.

    The result of :func:`flywheel_inertia`; ``float(result)`` is ``shaft_inertia``.

    Attributes
    ----------
    shaft_inertia : float
        I_w [kg·m²] (everything turning rigidly with the shaft) giving the time-mean δ asked
        for, exactly (to the steady state's accuracy).
    shaft_inertia_without_gravity : float
        The same for the machine with g = 0 (equal to shaft_inertia when solved without
        gravity); NaN where only gravity makes the machine fluctuate that much.
    textbook : float
        The textbook estimate ΔE/(δ ω_m²) − mean(J − I_w) [kg·m²], ΔE = max − min of
        ∫(M_gas + M_drive − M_load − U') dφ with every torque at the constant speed ω_m and the
        load taken as the constant that balances the others over the cycle.
    textbook_error : float
        (textbook − shaft_inertia)/shaft_inertia.
    delta : float
        The δ asked for [dimensionless].
    rpm : float
        The mean speed [1/min] (for loads that fix the speed: the one reached with
        ``shaft_inertia``).
    energy_swing : float
        ΔE [J] of the textbook estimate.
    """

    shaft_inertia: float
    shaft_inertia_without_gravity: float
    textbook: float
    textbook_error: float
    delta: float
    rpm: float
    energy_swing: float

    def __float__(self) -> float:
        return self.shaft_inertia

    def __repr__(self) -> str:
        return (
            f"FlywheelInertia(shaft_inertia={self.shaft_inertia:.8g} kg·m² for δ = {self.delta:g} at "
            f"{self.rpm:.6g} rpm; without gravity {self.shaft_inertia_without_gravity:.8g} kg·m²; "
            f"textbook ΔE/(δω²) − mean(J − I_w) = {self.textbook:.8g} kg·m² ({self.textbook_error:+.2e})"
        )


def _as_delta(value: Any) -> float:
    delta = as_scalar(value, "delta")
    # Below 1e-9 a δ is within the rounding of the speeds it is found from (the steady state
    # is solved to ~1e-10 of ω): no flywheel can be sized for it.
    if not (math.isfinite(delta) and delta >= 1e-9):
        raise MechanismError(
            f"delta = {delta} is out of range; allowed: delta >= 1e-9 (the coefficient of speed fluctuation)"
        )
    return delta


def _inertia_for(
    cycle: Cycle, rules: _Rules, omega_mean: float | None, ratio: float, delta: float, start: float
) -> float:
    """The I_w [kg·m²] with δ(I_w) = delta: Brent's method on log I_w, δ falling as I_w grows.

    A machine that stalls counts as δ = ∞ (its fluctuation is above any target); a target that
    only a stalling machine would reach is unreachable."""
    optimize = scipy_optimize()
    balance = None
    if rules.route == BALANCE:
        assert omega_mean is not None
        balance = Balance(cycle, _drive_at_mean(cycle, rules, omega_mean))

    known: dict[float, float] = {}

    def excess(log_inertia: float) -> float:
        """log(δ(I_w)/delta), +inf where the machine stalls; each I_w solved once."""
        if log_inertia not in known:
            inertia = math.exp(log_inertia)
            try:
                if balance is not None:
                    assert omega_mean is not None
                    found = balance.with_inertia(inertia).solve(omega_mean, ratio).delta
                else:
                    found = _solve(cycle.with_inertia(inertia), rules, omega_mean, ratio).delta
                # a flywheel so heavy that δ rounds to 0 is beyond the target
                known[log_inertia] = math.log(found / delta) if found > 0 else -math.inf
            except Stall:
                known[log_inertia] = math.inf
        return known[log_inertia]

    # The bracket: from the estimate outwards, in steps that grow (the textbook estimate is
    # near for a machine of small δ, and ~10 % off for a compressor at δ ≈ 1/30: the first
    # steps cover both).
    origin = math.log(max(start, 1e-300))
    steps = [0.05, 0.2, 0.7, *([math.log(4.0)] * 100)]
    low = high = origin
    if excess(origin) > 0:
        for step in steps:
            low, high = high, high + step
            if excess(high) <= 0:
                break
            if high - origin > 150:
                raise MechanismError(f"delta = {delta} is not reached by any shaft_inertia (δ never falls that low)")
    else:
        for step in steps:
            high, low = low, low - step
            if excess(low) > 0:
                break
            # δ(I_w) levels off as I_w → 0 (the rods' and pistons' inertia remains): unreachable.
            if low < origin - 60 or abs(excess(low) - excess(high)) < 1e-9:
                raise MechanismError(
                    f"delta = {delta} is unreachable: even a massless shaft keeps δ below it (about "
                    f"{delta * math.exp(excess(low)):.4g}: the rods' and pistons' own inertia limits the fluctuation)"
                )
    # A stall on the low side is +inf: brentq needs finite values, so the low end is moved to
    # the lightest shaft that still runs (bisection); a target beyond it is unreachable.
    if math.isinf(excess(low)):
        running = high
        for _ in range(40):
            middle = 0.5 * (low + running)
            if math.isinf(excess(middle)):
                low = middle
            else:
                running = middle
        if excess(running) < 0:
            raise MechanismError(
                f"delta = {delta} is unreachable at this speed: the machine stalls (ω_min < min_speed_ratio·ω_m) "
                f"before its fluctuation grows that large; the largest δ that runs is about "
                f"{delta * math.exp(excess(running)):.4g}"
            )
        low = running
    log_inertia = optimize.brentq(excess, low, high, xtol=1e-12, rtol=1e-15)
    return math.exp(log_inertia)


def flywheel_inertia(
    machine: Machine,
    *,
    delta: Any,
    rpm: Any = None,
    load: Any = BALANCE,
    drive: Any = None,
    gravity: Any = True,
    min_speed_ratio: Any = DEFAULT_MIN_SPEED_RATIO,
) -> FlywheelInertia:
    """The shaft inertia I_w [kg·m²] that gives the machine a coefficient of speed fluctuation δ.

    δ is the time-mean one of :func:`steady_state`, (ω_max − ω_min)/ω_m, computed exactly for
    every trial I_w (the machine's own ``shaft_inertia`` is replaced); δ falls monotonically as
    I_w grows, and Brent's method on log I_w finds the I_w that gives ``delta``.

    Parameters
    ----------
    machine : Machine
        The machine; its own ``shaft_inertia`` is replaced by the trial values.
    delta : float
        The target δ [dimensionless], ≥ 1e-9.
    rpm : float, optional
        The mean speed [1/min]: required with ``load="balance"``, refused with other loads.
    load : "balance", float, PowerLawLoad or callable, default "balance"
        The resisting torque [N·m], as for :func:`steady_state`.
    drive : float, PowerLawLoad or callable, optional
        A driving torque [N·m], as for :func:`steady_state`.
    gravity : bool, default True
        False sizes the flywheel of the machine with g = 0.
    min_speed_ratio : float, default 1e-3
        The stall criterion [dimensionless], as for :func:`steady_state`.

    Returns
    -------
    FlywheelInertia
        ``shaft_inertia`` [kg·m²] (also ``float(result)``), ``shaft_inertia_without_gravity``,
        the textbook estimate ΔE/(δ ω_m²) − mean(J − I_w) and its relative error.

    Raises
    ------
    MechanismError
        For bad input, naming the parameter; ``delta`` unreachable (the machine would stall
        before its fluctuation grows that large, or the rods' own inertia keeps it below).

    Examples
    --------
    The slow compressor's flywheel for δ = 1/40 at 120 rpm, with gravity and without:

    >>> import multicrank as mc
    >>> compressor = mc.presets.ENGINES["slow-compressor"]
    >>> flywheel = mc.flywheel_inertia(compressor, delta=1 / 40, rpm=120)
    >>> print(f"I_w = {flywheel.shaft_inertia:.1f} kg·m² "
    ...       f"({flywheel.shaft_inertia_without_gravity:.1f} without gravity; "
    ...       f"textbook {flywheel.textbook:.1f})")
    I_w = 413.8 kg·m² (350.3 without gravity; textbook 450.5)
    """
    machine = _as_machine(machine)
    target = _as_delta(delta)
    rules = _rules(load, drive)
    omega_mean = _as_rpm(rpm, rules.route)
    if omega_mean is not None:
        omega_mean *= math.pi / 30.0
    gravity = _as_flag(gravity, "gravity")
    ratio = _as_ratio(min_speed_ratio)
    cycle = _cycle(machine, gravity)

    def estimate(cycle: Cycle, omega: float) -> tuple[float, float]:
        """(ΔE [J], the textbook I_w [kg·m²]) at the constant speed ω."""
        rule = cycle.rule
        applied = np.zeros(rule.phi.shape)
        if rules.drive is not None:
            applied = applied + rules.drive(rule.phi, omega)
        if isinstance(rules.load, Torque):
            applied = applied - rules.load(rule.phi, omega)
        swing = Balance(cycle, applied).energy_swing()
        return swing, swing / (target * omega**2) - cycle.mean_rest_inertia

    speed = omega_mean
    if speed is None:  # the load fixes the speed: near the machine's own, to start from
        try:
            speed = _solve(cycle, rules, None, ratio).omega_mean
        except Stall:
            speed = quasi_static_speed(cycle, _applied(rules), "load")
    swing, textbook = estimate(cycle, speed)
    start = textbook if textbook > 0 else swing / (target * speed**2)
    if not start > 0:
        start = max(cycle.mean_rest_inertia, machine.shaft_inertia)
    inertia = _inertia_for(cycle, rules, omega_mean, ratio, target, start)
    if omega_mean is None:  # the speed reached with that flywheel; the estimate there
        speed = _solve(cycle.with_inertia(inertia), rules, None, ratio).omega_mean
        swing, textbook = estimate(cycle, speed)
    if cycle.gravity_on:
        try:
            without = _inertia_for(cycle.without_gravity(), rules, omega_mean, ratio, target, inertia)
        except MechanismError:  # only with gravity does the machine fluctuate that much
            without = math.nan
    else:
        without = inertia
    return FlywheelInertia(
        shaft_inertia=inertia,
        shaft_inertia_without_gravity=without,
        textbook=textbook,
        textbook_error=(textbook - inertia) / inertia,
        delta=target,
        rpm=30.0 * speed / math.pi,
        energy_swing=swing,
    )
