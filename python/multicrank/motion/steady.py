"""The machine in steady running: its periodic motion and its speed fluctuation
(docs/theory.md, "Steady running"); the flywheel for a given fluctuation is
:mod:`~multicrank.motion.flywheel`'s.

A machine whose torques repeat every working cycle Φ (2π two-stroke, 4π four-stroke) runs,
once the start-up has died away, periodically: ω(φ + Φ) = ω(φ). :func:`steady_state` finds
that motion exactly (to the accuracy stated below) from Lagrange's equation

    J(φ) φ̈ + ½ J'(φ) φ̇² = M_gas(φ) − U'(φ) + M_drive − M_load,

with J the reduced moment of inertia, U the potential energy of gravity and the torques in
N·m, all from the Rust core (:class:`~multicrank.machine.Machine`).

Speeds follow the house convention: a name carries its unit, ``rpm…`` in 1/min (the
argument ``rpm``, :attr:`SteadyState.rpm`), ``omega…`` in rad/s (``omega``, ``omega_mean``,
``omega_max``, ``omega_min``); ω = πn/30.

Three routes, chosen by the load:

- ``load="balance"`` (the default): the constant load that takes the cycle mean of gas and
  drive. Every torque then depends on φ alone and the energy integral gives the motion in
  closed form, ω²(φ) = 2[E₀ + K(φ)]/J(φ), K = ∫₀^φ(M_gas + M_drive − M_load) dφ − ΔU; E₀ is
  the one number that gives the mean speed asked for (``rpm``, default the machine's own).
  The Rust core solves it beside any drive: a callable f(φ, ω) is held at ω_m and crosses
  sampled once over the cycle; a drive that does not depend on φ only adds to the load.
- a :class:`~multicrank.loads.PowerLawLoad` of exponent 2 (fan, pump, propeller) with no drive
  or a constant one: the energy E = ½Jω² obeys a *linear* equation whose periodic solution is
  an explicit double integral (the Rust core's). The load fixes the mean speed.
- any other load or drive (one that depends on the speed): shooting for E(0) = E(Φ) with
  SciPy's ``solve_ivp``, in Python.

SciPy is imported when a steady state is computed.
"""

from __future__ import annotations

import math
from typing import Any

from .._native import MechanismError
from .._validation import as_count, as_flag, as_instance, rpm_from_omega
from ..machine.machine import Machine
from ..machine.native import motion_machine
from ._deferred import COMPARISONS, Computed, CoreQuestion, cycle_angles, steady_arrays, steady_curves
from ._periodic import (
    DEFAULT_MIN_SPEED_RATIO,
    METHODS,
    Rules,
    as_min_speed_ratio,
    at_load,
    drive_table,
    mean_speed,
    resolve_rules,
)
from ._shooting import ShaftCycle, Stall, cycle_mean, shoot
from .loads import BALANCE, PowerLawLoad, Torque

# The result and the stall, defined in steady_result and importable from here as before.
from .steady_result import NEAR_STALL_DELTA, NEAR_STALL_NOTE, StallError, SteadyState

__all__ = ["NEAR_STALL_DELTA", "NEAR_STALL_NOTE", "PowerLawLoad", "StallError", "SteadyState", "steady_state"]


# -- inputs ------------------------------------------------------------------------------------


#: Points of a result's arrays over the closed cycle: every degree of a two-stroke cycle,
#: every other degree of a four-stroke one (the arrays are for plots and tables; δ and the
#: extremes do not depend on them).
DEFAULT_POINTS = 361


def _as_points(value: Any) -> int:
    return DEFAULT_POINTS if value is None else as_count(value, "points", minimum=2)


# -- the solvers ---------------------------------------------------------------------------------


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
        The mean speed n [1/min] (time mean, ω_m = πn/30) with ``load="balance"``; default
        the machine's own ``rpm`` (refused when it has none). Refused with any other load,
        which fixes the speed itself.
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
        ω(φ), the torques and δ over one working cycle, with δ without gravity and of the
        machine coasting (gas, drive and load removed). Under the machine's ``load_law`` the
        "balance" load runs its gauge pressures times the law's factor at the mean speed
        (:meth:`Machine.load_factor`, (n/n_r)² for the propeller law), and the result's gas
        torque is theirs; ``machine`` is the one given.

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
    Accuracy (measured in tests/motion/test_steady.py against independent time integrations): for
    smooth torques δ to 1e-7 relative and ω_m to 1e-9; with tabulated pressures (kinks
    between the nodes the integration cannot see) δ to 1e-3 and ω_m to 1e-7. The extremes are
    located on the quadrature panels' interpolants and evaluated exactly there (by shooting:
    located on the integration's dense output and refined by SciPy's bounded Brent).

    Examples
    --------
    The slow compressor at its speed, the motor taking the mean torque ("balance"):

    >>> import multicrank as mc
    >>> compressor = mc.presets.MACHINES["slow-compressor"]
    >>> state = mc.steady_state(compressor, rpm=120)
    >>> print(f"δ = {state.delta:.5f} with gravity, "
    ...       f"{state.delta_without_gravity:.5f} without")
    δ = 0.02953 with gravity, 0.02502 without
    >>> print(f"load {state.mean_load_torque:.1f} N·m, ω from {state.omega_min:.3f} "
    ...       f"to {state.omega_max:.3f} rad/s")
    load -916.0 N·m, ω from 12.368 to 12.739 rad/s

    A motor of constant torque driving the compressor and a fan: the fan's square law fixes
    the speed (no ``rpm``), and the steady state comes in closed form.

    >>> fan = mc.PowerLawLoad(torque=90.0, rpm=120)  # 90 N·m at 120 rpm
    >>> state = mc.steady_state(compressor, load=fan, drive=1000.0)
    >>> print(f"{state.rpm:.2f} rpm by {state.method}, δ = {state.delta:.5f}")
    115.90 rpm by closed form, δ = 0.03184
    """
    machine = as_instance(machine, Machine, "machine")
    rules = resolve_rules(load, drive)
    omega = mean_speed(rpm, rules.route, machine)
    gravity = as_flag(gravity, "gravity")
    ratio = as_min_speed_ratio(min_speed_ratio)
    count = _as_points(points)
    return _solved(machine, rules, load, omega, gravity, ratio, count)


def balanced_state(machine: Machine, omega: float, *, gravity: bool = True, points: int) -> SteadyState:
    """:func:`steady_state` under the "balance" load at the mean speed ω [rad/s] (already
    checked: a caller's own speed, converted once where the user gave it), at the default
    ``min_speed_ratio``, with ``points`` points: what the frame's forces ask of the steady
    running (:func:`~multicrank.shaking_forces`, :func:`~multicrank.bearing_loads`)."""
    rules = resolve_rules(BALANCE, None)
    return _solved(machine, rules, BALANCE, omega, gravity, as_min_speed_ratio(DEFAULT_MIN_SPEED_RATIO), points)


def _solved(
    machine: Machine, rules: Rules, load: Any, omega: float | None, gravity: bool, ratio: float, count: int
) -> SteadyState:
    """The steady state of checked input (ω_m [rad/s], None where the load fixes it)."""
    # Under a load law, "balance" runs the diagrams of its mean speed; the other loads fix the
    # speed themselves, and take the diagrams as given.
    loaded = at_load(machine, omega)
    if rules.route == "general":
        numbers, later = _shooting_solution(loaded, rules, gravity, ratio, count)
    else:
        numbers, later = _native_solution(loaded, rules, omega, gravity, ratio, count)
    numbers.update(
        machine=machine,
        load_rule=_describe(load, rules),
        gravity=gravity,
        min_speed_ratio=ratio,
        cycle=machine.cycle,
        _later=later,
    )
    return SteadyState._of(numbers)


#: A route's answer: the numbers, and what computes the rest.
_Solved = tuple[dict[str, Any], CoreQuestion | Computed]


def _native_solution(
    machine: Machine, rules: Rules, omega: float | None, gravity: bool, ratio: float, points: int
) -> _Solved:
    """The steady state by the Rust core: the "balance" load beside any drive (one solve
    now; the arrays and the two comparison solves when first read), or a square law beside
    at most a constant drive (all at once). A pressure callable crosses sampled, and so does
    a callable drive under "balance", held at ω_m (:func:`~multicrank.motion._periodic.drive_table`);
    a drive that does not depend on φ only adds to the load (:attr:`Rules.plain_balance`)."""
    balance = rules.route == BALANCE
    square_law = not balance
    native = motion_machine(machine)
    table = drive_table(machine, rules, omega) if balance and omega is not None else None
    # The square law's curves come with its solution; "balance" makes its angles only when
    # its arrays are read.
    square_law_phi = None if balance else cycle_angles(machine.cycle, points)
    try:
        if balance:
            assert omega is not None
            found = native.steady_state(omega, ratio, None, False, gravity=gravity, drive=table)
        else:
            assert isinstance(rules.load, Torque)
            found = native.square_law(
                rules.load.value.coefficient, rules.constant_drive, ratio, square_law_phi, gravity=gravity
            )
    except MechanismError as error:
        angle = getattr(error, "angle", None)
        if angle is None:
            raise
        if square_law:
            # Nothing may drive the machine on the cycle's mean at all: the core's mean gas
            # torque says so (no solve).
            mean = native.mean_gas_torque() + rules.constant_drive
            if not mean > 0:
                raise StallError(
                    f"the machine stalls with this load: the cycle mean of gas and drive torque is {mean:.6g} "
                    "N·m, not positive: nothing drives it against a square-law load, which brings it to rest, "
                    f"near φ = {math.degrees(angle):.4g}°; it has no steady running (min_speed_ratio = {ratio:g})",
                    angle=angle,
                    parameter="load",
                ) from None
        raise _native_stall(angle, omega, getattr(error, "min_omega", None), ratio) from None
    numbers: dict[str, Any] = found.solution()
    if balance and rules.drive is not None and table is None:  # the load takes it (Rules.plain_balance)
        assert omega is not None
        numbers["mean_load_torque"] += rules.drive_at(omega)
    question = CoreQuestion(
        native=native,
        machine=machine,
        rules=rules,
        omega=omega if balance else None,
        gravity=gravity,
        ratio=ratio,
        points=points,
        table=table,
        found=found,
        phi=square_law_phi,
        omega_mean=numbers["omega_mean"],
        period=numbers["period"],
        mean_load=numbers["mean_load_torque"],
    )
    return dict(numbers, method=METHODS[rules.route]), question


def _native_stall(angle: float, omega: float | None, min_omega: float | None, ratio: float) -> StallError:
    """The core's stall (its typed attributes: the angle, the speed asked for and the lowest
    that runs, rad/s) in words, its speeds in 1/min (the one place they are derived)."""
    if omega is None or min_omega is None:
        return StallError(
            f"the machine stalls with this load: its speed would fall below min_speed_ratio·ω_m near φ = "
            f"{math.degrees(angle):.4g}°; it has no steady running (min_speed_ratio = {ratio:g})",
            angle=angle,
            parameter="load" if omega is None else "rpm",
        )
    rpm, min_rpm = rpm_from_omega(omega), rpm_from_omega(min_omega)
    return StallError(
        f"the machine stalls at rpm = {rpm:.6g}: it would crawl over its dead point at φ = {math.degrees(angle):.4g}° "
        f"(ω_min < min_speed_ratio·ω_m with min_speed_ratio = {ratio:g}); the lowest mean speed that runs is "
        f"min_rpm = {min_rpm:.6g}",
        angle=angle,
        min_rpm=min_rpm,
    )


def _shooting_solution(machine: Machine, rules: Rules, gravity: bool, ratio: float, points: int) -> _Solved:
    """The steady state under a load or drive that depends on the speed, by shooting
    (:mod:`~multicrank.motion._shooting`), all at once; δ of the machine coasting is the core's."""
    phi = cycle_angles(machine.cycle, points)
    shaft = ShaftCycle(machine, gravity)
    applied = rules.torques.net
    try:
        solution = shoot(shaft, applied, ratio)
    except Stall as error:
        angle = error.angle % machine.cycle
        raise StallError(
            f"the machine stalls with this load: {error}, near φ = {math.degrees(angle):.4g}°; it has no "
            f"steady running (min_speed_ratio = {ratio:g})",
            angle=angle,
            parameter="load",
        ) from None
    mean = solution.omega_mean
    delta_without = solution.delta
    if shaft.gravity:
        try:
            delta_without = shoot(shaft.without_gravity(), applied, ratio).delta
        except Stall:
            delta_without = math.nan
    # Coasting: gas, drive and load gone; the conservative machine (J(φ) and gravity) at the
    # same mean speed (the core's energy method).
    _, delta_coasting = motion_machine(machine).comparisons(mean, solution.delta, mean, ratio, gravity=gravity)
    load = rules.load
    mean_load = 0.0
    if isinstance(load, Torque):
        taken = load
        mean_load = cycle_mean(lambda at: taken(at, solution.omega_at(at)), machine.cycle)
    extremes = solution.extremes
    numbers = dict(
        omega_mean=mean,
        omega_max=extremes.omega_max,
        omega_min=extremes.omega_min,
        phi_max=extremes.phi_max,
        phi_min=extremes.phi_min,
        period=solution.period,
        mean_load_torque=mean_load,
        status=0,
        message=solution.message,
        nfev=solution.nfev,
        nit=solution.nit,
    )
    curves = steady_curves(phi, solution.omega_at(phi), solution.time_at(phi), solution.period)
    arrays = steady_arrays(machine, rules, gravity, curves, None, mean, mean_load)
    compared = dict(zip(COMPARISONS, (delta_without, delta_coasting), strict=True))
    return dict(numbers, method=solution.method), Computed(arrays, compared)


def _describe(load: Any, rules: Rules) -> str:
    if rules.route == BALANCE:
        return "'balance'"
    if isinstance(load, PowerLawLoad):
        return repr(load)
    return repr(load) if not callable(load) else getattr(load, "__name__", "callable")
