"""The flywheel for a coefficient of speed fluctuation (docs/theory.md, "Steady running"):
the shaft inertia I_w that gives a machine the δ asked for, found over exact steady states
(:mod:`~multicrank.motion.steady`), with the textbook estimate beside it.

Speeds follow the house convention: ``rpm`` in 1/min, ``omega…`` in rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from .._native import MechanismError
from .._validation import as_flag, as_instance, as_scalar, refused, rpm_from_omega
from ..machine.machine import Machine
from ..machine.native import motion_machine
from ._periodic import (
    DEFAULT_MIN_SPEED_RATIO,
    METHODS,
    SOLVED,
    as_min_speed_ratio,
    at_load,
    drive_table,
    mean_speed,
    resolve_rules,
)
from ._result import MotionResult
from ._shooting import flywheel_for
from .loads import BALANCE, Torque

__all__ = ["FlywheelInertia", "flywheel_inertia"]


@dataclass(frozen=True)
class FlywheelInertia(MotionResult):
    """The shaft inertia that gives a machine a coefficient of speed fluctuation δ.

    The result of :func:`flywheel_inertia`; ``float(result)`` is ``shaft_inertia``, and
    ``to_pandas()`` / ``to_xarray()`` give its numbers as one row.

    Attributes
    ----------
    shaft_inertia : float
        I_w [kg·m²] (everything turning rigidly with the shaft) giving the time-mean δ asked
        for, exactly (to the steady state's accuracy).
    shaft_inertia_without_gravity : float
        The same for the machine with g = 0 (equal to shaft_inertia when solved without
        gravity); NaN where only gravity makes the machine fluctuate that much.
    textbook : float
        The textbook estimate ΔE/(δ ω_m²) − mean(J − I_w) [kg·m²], ΔE = max − min of the
        turning-moment diagram's energy ∫(M_gas + M_drive − M_load − U′ − ½J′ω_m²) dφ with
        every torque at the constant speed ω_m (the inertia torque −½J′ω_m² of the rods and
        pistons included) and the load taken as the constant that balances the others over
        the cycle. Exact to first order: its relative error is O(δ).
    textbook_error : float
        (textbook − shaft_inertia)/shaft_inertia.
    delta : float
        The δ asked for [dimensionless].
    rpm : float
        The mean speed [1/min] (for loads that fix the speed: the one reached with
        ``shaft_inertia``).
    energy_swing : float
        ΔE [J] of the textbook estimate (inertia torque included).
    method : str
        How each trial steady state was solved: "energy", "closed form" or "shooting"
        (:attr:`solved` in words).
    """

    shaft_inertia: float
    shaft_inertia_without_gravity: float
    textbook: float
    textbook_error: float
    delta: float
    rpm: float
    energy_swing: float
    method: str = METHODS[BALANCE]

    NUMBERS: ClassVar[dict[str, str]] = {
        "shaft_inertia": "kg·m²",
        "shaft_inertia_without_gravity": "kg·m²",
        "textbook": "kg·m²",
        "textbook_error": "",
        "delta": "",
        "rpm": "1/min",
        "energy_swing": "J",
    }

    @property
    def solved(self) -> str:
        """What was solved and how, in words."""
        return f"flywheel (Brent's method on log I_w over steady states: {SOLVED[self.method]})"

    def __float__(self) -> float:
        return self.shaft_inertia

    def __repr__(self) -> str:
        return (
            f"FlywheelInertia(shaft_inertia={self.shaft_inertia:.8g} kg·m² for δ = {self.delta:g} at "
            f"{self.rpm:.6g} rpm; without gravity {self.shaft_inertia_without_gravity:.8g} kg·m²; "
            f"textbook ΔE/(δω²) − mean(J − I_w) = {self.textbook:.8g} kg·m² ({self.textbook_error:+.2e})"
        )


def _as_delta(value: Any, name: str = "delta") -> float:
    """A target δ [dimensionless], given as ``name`` (``delta_target`` in a motion sweep)."""
    delta = as_scalar(value, name)
    # Below 1e-9 a δ is within the rounding of the speeds it is found from (the steady state
    # is solved to ~1e-10 of ω): no flywheel can be sized for it.
    if not (math.isfinite(delta) and delta >= 1e-9):
        raise refused(
            name, f"{name} = {delta} is out of range; allowed: {name} >= 1e-9 (the coefficient of speed fluctuation)"
        )
    return delta


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
        The mean speed [1/min] with ``load="balance"``; default the machine's own ``rpm``
        (refused when it has none). Refused with other loads, which fix the speed. Under the
        machine's ``load_law`` the gauge pressures are the law's at this speed, as for
        :func:`steady_state`.
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
    >>> compressor = mc.presets.MACHINES["slow-compressor"]
    >>> flywheel = mc.flywheel_inertia(compressor, delta=1 / 40, rpm=120)
    >>> print(f"I_w = {flywheel.shaft_inertia:.1f} kg·m² "
    ...       f"({flywheel.shaft_inertia_without_gravity:.1f} without gravity; "
    ...       f"textbook {flywheel.textbook:.1f})")
    I_w = 413.8 kg·m² (350.3 without gravity; textbook 413.2)
    """
    machine = as_instance(machine, Machine, "machine")
    target = _as_delta(delta)
    rules = resolve_rules(load, drive)
    omega_mean = mean_speed(rpm, rules.route, machine)
    gravity = as_flag(gravity, "gravity")
    ratio = as_min_speed_ratio(min_speed_ratio)
    machine = at_load(machine, omega_mean)  # "balance" under a load law: the diagrams of its speed
    # The core's search on every route, its refusal of a target no shaft inertia gives saying
    # why and how close the machine comes: over shot steady states for a load or drive that
    # depends on the speed; over the core's own for "balance" beside any drive (a callable held
    # at ω_m and sampled, one that does not depend on φ leaving the motion as without it), or
    # the square law beside a constant drive (the mean speed reached a result).
    native = motion_machine(machine)
    try:
        if rules.route == "general":
            sized: Any = flywheel_for(machine, rules.torques.net, target, gravity, ratio)
        elif rules.route == BALANCE:
            assert omega_mean is not None
            table = drive_table(machine, rules, omega_mean)
            sized = native.flywheel_inertia(target, omega_mean, ratio, gravity=gravity, drive=table)
        else:
            assert isinstance(rules.load, Torque)
            coefficient = rules.load.value.coefficient
            sized = native.square_law_flywheel_inertia(
                coefficient, target, rules.constant_drive, ratio, gravity=gravity
            )
    except MechanismError as error:
        reach = getattr(error, "reach", None)
        if reach is None:
            raise
        raise unreachable(target, reach, error.closest) from None  # type: ignore[attr-defined]
    return _inertia(sized, target, rules.route)


def unreachable(delta: float, reach: str, closest: float) -> MechanismError:
    """The refusal of a target δ that no shaft inertia gives, worded from why (``reach``:
    "never_falls", "massless" or "stalls", as the core's error carries it) and ``closest``,
    the δ nearest to it that the machine reaches."""
    if reach == "massless":
        return refused(
            "delta",
            f"delta = {delta} is unreachable: even a massless shaft keeps δ below it (about "
            f"{closest:.4g}: the rods' and pistons' own inertia limits the fluctuation)",
        )
    if reach == "stalls":
        return refused(
            "delta",
            f"delta = {delta} is unreachable at this speed: the machine stalls (ω_min < min_speed_ratio·ω_m) "
            f"before its fluctuation grows that large; the largest δ that runs is about {closest:.4g}",
        )
    return refused("delta", f"delta = {delta} is not reached by any shaft_inertia (δ never falls that low)")


def _inertia(sized: Any, target: float, route: str) -> FlywheelInertia:
    """The result of a flywheel found by the core or by shooting (its numbers, the mean speed
    ``omega_mean`` [rad/s]), its ``rpm`` derived from that ω here."""
    return FlywheelInertia(
        shaft_inertia=sized.shaft_inertia,
        shaft_inertia_without_gravity=sized.shaft_inertia_without_gravity,
        textbook=sized.textbook,
        textbook_error=sized.textbook_error,
        delta=target,
        rpm=rpm_from_omega(sized.omega_mean),
        energy_swing=sized.energy_swing,
        method=METHODS[route],
    )
