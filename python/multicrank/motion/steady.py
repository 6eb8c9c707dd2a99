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
- a :class:`~multicrank.loads.PowerLawLoad` of exponent 2 (fan, pump, propeller) with no drive
  or a constant one: the energy E = ½Jω² obeys a *linear* equation whose periodic solution is
  an explicit double integral. The load fixes the mean speed.
- any other load or drive: shooting for E(0) = E(Φ) with SciPy's ``solve_ivp``.

SciPy is imported when a steady state is computed.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from .._native import MechanismError
from .._shaft import inertia_torque, omega_from_rpm, rpm_from_omega
from .._text import counted
from .._validation import as_count, as_flag, as_instance, renamed
from ..machine.machine import Machine
from ..machine.native import motion_machine
from ._periodic import (
    DEFAULT_MIN_SPEED_RATIO,
    METHODS,
    SOLVED,
    Rules,
    as_min_speed_ratio,
    balance_at,
    cycle_tables,
    mean_rpm,
    resolve_rules,
    solve_periodic,
)
from ._result import MotionResult
from ._solvers import Balance, CycleTables, Periodic, Stall, restored_error, running_speed
from .loads import BALANCE, PowerLawLoad, Torque

__all__ = ["NEAR_STALL_DELTA", "PowerLawLoad", "StallError", "SteadyState", "steady_state"]

#: The coefficient of speed fluctuation δ above which a machine runs near a stall
#: [dimensionless]: its speed swings by more than half the mean speed every cycle — ten times
#: the roughest machine class (pumps and compressors, δ ≤ 1/20) — and as the mean speed falls
#: towards the lowest that runs (``StallError.min_rpm``) ω_min goes to 0 and δ grows to 2 or
#: more. :attr:`SteadyState.near_stall`, ``mc.motion_sweep``'s ``near_stall`` column, the
#: command line and the report say so wherever such a δ is shown.
NEAR_STALL_DELTA = 0.5
#: What a δ above :data:`NEAR_STALL_DELTA` means, in words (the summaries' note).
NEAR_STALL_NOTE = (
    f"δ > {NEAR_STALL_DELTA:g}: near a stall — the speed swings by more than half its mean every cycle "
    "(the roughest machine class allows 1/20); slower still it nearly stops each cycle, then stalls"
)


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
    >>> compressor = mc.presets.MACHINES["slow-compressor"]
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

    def __reduce__(self) -> tuple[Any, ...]:
        # An exception pickles as cls(*args), and angle is keyword-only: rebuild it without
        # __init__ and restore the attributes, so that the error crosses a pickle (a
        # multiprocessing worker's error sent back to its parent) whole.
        return (restored_error, (type(self), self.args, self.__dict__))


# -- inputs ------------------------------------------------------------------------------------


#: Points of a result's arrays over the closed cycle: every degree of a two-stroke cycle,
#: every other degree of a four-stroke one (the arrays are for plots and tables; δ and the
#: extremes do not depend on them).
DEFAULT_POINTS = 361


def _as_points(value: Any) -> int:
    return DEFAULT_POINTS if value is None else as_count(value, "points", minimum=2)


# -- the result ----------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class SteadyState(MotionResult):
    """A machine's periodic steady running over one closed cycle [0, Φ]: the result of
    :func:`steady_state`.

    The arrays have shape (points,), φ uniform from 0 to Φ inclusive, and are read-only; their
    names are those of :class:`Transient` and of the :class:`~multicrank.Machine` methods
    that give them. Speeds: ``omega…`` in rad/s, ``rpm…`` in 1/min. ``print(state)`` shows
    :meth:`summary`; ``to_pandas()`` and ``to_xarray()`` convert it.

    It computes what is read: the numbers (δ, the speeds, the period, the load) come with it;
    the arrays and ``delta_without_gravity`` and ``delta_coasting`` (two more solves) are
    computed when first read, then kept. A pickle holds them all.

    Attributes
    ----------
    phi : ndarray
        Crank angle φ [rad].
    omega : ndarray
        Shaft speed ω(φ) [rad/s].
    time : ndarray
        t(φ) [s] from φ = 0; ``time[-1]`` = t_Φ, the time of one cycle.
    reduced_inertia, reduced_inertia_slope : ndarray
        J(φ) [kg·m²] and J′(φ) [kg·m²/rad] (formerly ``J`` and ``dJ_dphi``).
    gas_torque : ndarray
        M_gas [N·m].
    gravity_torque : ndarray
        −dU/dφ [N·m] (zero when solved without gravity).
    inertia_torque : ndarray
        −½ J′(φ) ω² [N·m] at the actual speed.
    drive_torque : ndarray
        M_drive [N·m] (with ``load="balance"`` at the mean speed, as solved).
    load_torque : ndarray
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
    mean_load_torque : float
        The constant load "balance" found, or the load's cycle mean (1/Φ)∫M_load dφ [N·m].
    delta_without_gravity : float
        δ of the same machine and load rule with g = 0 (for "balance" at the same mean
        speed) [dimensionless]; NaN where that machine would stall.
    delta_coasting : float
        δ of the machine coasting: gas, drive and load removed, ½J(φ)ω² + U(φ) constant, at
        the same mean speed [dimensionless]; NaN where it would stall. Gravity and the
        variation of J(φ) together (with g = 0 it is J's alone, not 0), the exact
        counterpart of δ_g (docs/theory.md); formerly ``delta_gravity_only``. What gravity
        does to δ is :attr:`gravity_effect`.
    near_stall : bool
        δ > :data:`NEAR_STALL_DELTA` (0.5): the machine nearly stops each cycle.
    method : str
        How it was solved: "energy", "closed form" or "shooting" (:attr:`solved` in words).
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
    omega_mean: float
    omega_max: float
    omega_min: float
    phi_max: float
    phi_min: float
    period: float
    mean_load_torque: float
    #: What is computed on first use: ``later("arrays")`` the arrays by name,
    #: ``later("comparisons")`` the two comparison δ by name (each once, then kept).
    _later: Callable[[str], dict[str, Any]] = field(repr=False, compare=False)

    # The arrays and the two comparison solves, computed when first read: δ alone costs one
    # solve (docs/theory.md, "Where it is computed, and when").
    @cached_property
    def _arrays(self) -> dict[str, np.ndarray]:
        return self._later("arrays")

    @cached_property
    def _comparisons(self) -> dict[str, float]:
        return self._later("comparisons")

    @property
    def phi(self) -> np.ndarray:
        """Crank angle φ [rad], uniform over the closed cycle."""
        return self._arrays["phi"]

    @property
    def omega(self) -> np.ndarray:
        """Shaft speed ω(φ) [rad/s]."""
        return self._arrays["omega"]

    @property
    def time(self) -> np.ndarray:
        """t(φ) [s] from φ = 0; ``time[-1]`` = t_Φ."""
        return self._arrays["time"]

    @property
    def reduced_inertia(self) -> np.ndarray:
        """J(φ) [kg·m²]."""
        return self._arrays["reduced_inertia"]

    @property
    def reduced_inertia_slope(self) -> np.ndarray:
        """J′(φ) [kg·m²/rad]."""
        return self._arrays["reduced_inertia_slope"]

    @property
    def gas_torque(self) -> np.ndarray:
        """M_gas [N·m]."""
        return self._arrays["gas_torque"]

    @property
    def gravity_torque(self) -> np.ndarray:
        """−dU/dφ [N·m] (zero when solved without gravity)."""
        return self._arrays["gravity_torque"]

    @property
    def inertia_torque(self) -> np.ndarray:
        """−½ J′(φ) ω² [N·m] at the actual speed."""
        return self._arrays["inertia_torque"]

    @property
    def drive_torque(self) -> np.ndarray:
        """M_drive [N·m]."""
        return self._arrays["drive_torque"]

    @property
    def load_torque(self) -> np.ndarray:
        """M_load [N·m], positive resisting."""
        return self._arrays["load_torque"]

    @property
    def acceleration(self) -> np.ndarray:
        """φ̈ [rad/s²] = (gas + gravity + inertia + drive − load)/J."""
        return self._arrays["acceleration"]

    @property
    def delta_without_gravity(self) -> float:
        """δ of the same machine and load rule with g = 0 [dimensionless]; NaN where it stalls."""
        return self._comparisons["delta_without_gravity"]

    @property
    def delta_coasting(self) -> float:
        """δ of the machine coasting — gas, drive and load removed, ½J(φ)ω² + U(φ) constant —
        at the same mean speed [dimensionless]: gravity and the variation of J(φ) together
        (with g = 0, J's alone); NaN where it stalls. Formerly ``delta_gravity_only``."""
        return self._comparisons["delta_coasting"]

    @property
    def near_stall(self) -> bool:
        """δ > :data:`NEAR_STALL_DELTA` (0.5): the speed swings by more than half its mean
        every cycle — the machine runs near a stall (:meth:`summary` says so)."""
        return bool(self.delta > NEAR_STALL_DELTA)

    def __getstate__(self) -> dict[str, Any]:
        # A pickle holds every number and array, computed now, and no way to compute more.
        state = dict(self.__dict__, _arrays=self._arrays, _comparisons=self._comparisons)
        state["_later"] = None
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        compared = state.get("_comparisons")
        if isinstance(compared, dict) and "delta_gravity_only" in compared:  # a pickle of 0.1
            state["_comparisons"] = {_RENAMED_COMPARISONS.get(k, k): v for k, v in compared.items()}
        self.__dict__.update(state)

    COLUMNS: ClassVar[dict[str, str]] = {
        "phi": "rad",
        "time": "s",
        "omega": "rad/s",
        "rpm": "1/min",
        "reduced_inertia": "kg·m²",
        "reduced_inertia_slope": "kg·m²/rad",
        "gas_torque": "N·m",
        "gravity_torque": "N·m",
        "inertia_torque": "N·m",
        "drive_torque": "N·m",
        "load_torque": "N·m",
        "acceleration": "rad/s²",
    }
    NUMBERS: ClassVar[dict[str, str]] = {
        "omega_mean": "rad/s",
        "omega_max": "rad/s",
        "omega_min": "rad/s",
        "phi_max": "rad",
        "phi_min": "rad",
        "period": "s",
        "cycle": "rad",
        "mean_load_torque": "N·m",
        "delta": "",
        "delta_without_gravity": "",
        "delta_coasting": "",
        "near_stall": "",
        "gravity": "",
    }
    #: The array attributes, in column order (``rpm`` is ω in 1/min).
    ARRAYS: ClassVar[tuple[str, ...]] = tuple(COLUMNS)

    @property
    def solved(self) -> str:
        """What was solved and how, in words (from :attr:`method`)."""
        return SOLVED[self.method]

    @property
    def rpm(self) -> float:
        """The mean speed n = 30 ω_m/π [1/min]."""
        return float(rpm_from_omega(self.omega_mean))

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
        """δ/δ₀ − 1, δ₀ = ``delta_without_gravity``: the relative change gravity makes to the
        fluctuation [dimensionless] (may be negative), as ``mc.motion_sweep``'s column of the
        same name; NaN where the machine without gravity stalls, ∞ where it runs without
        any fluctuation (gravity is then all of δ)."""
        if self.delta_without_gravity == 0:
            return math.nan if self.delta == 0 else math.inf
        return self.delta / self.delta_without_gravity - 1.0

    # -- the names of 0.1, read with a DeprecationWarning -----------------------------------------
    J: ClassVar[renamed] = renamed("reduced_inertia")
    dJ_dphi: ClassVar[renamed] = renamed("reduced_inertia_slope")
    torque_gas: ClassVar[renamed] = renamed("gas_torque")
    torque_gravity: ClassVar[renamed] = renamed("gravity_torque")
    torque_inertia: ClassVar[renamed] = renamed("inertia_torque")
    torque_drive: ClassVar[renamed] = renamed("drive_torque")
    torque_load: ClassVar[renamed] = renamed("load_torque")
    #: It is not gravity's: δ of the machine coasting, J(φ)'s variation and gravity together.
    delta_gravity_only: ClassVar[renamed] = renamed("delta_coasting")

    def _column(self, name: str) -> Any:
        if name == "rpm":
            return rpm_from_omega(self.omega)
        return getattr(self, name)

    def summary(self) -> str:
        """A few readable lines: speeds, δ in both conventions, and what gravity does.

        Returns
        -------
        str
            The lines, joined by newlines (also the ``repr`` of the result).
        """
        degrees = math.degrees
        lines = [
            f"steady state of {self.machine.name!r} "
            f"({self.machine.strokes}-stroke, {counted(len(self.machine), 'cylinder')}), "
            f"load {self.load_rule}, by {self.method}{'' if self.gravity else ', without gravity'}",
            f"  mean speed       {self.rpm:.6g} rpm (ω_m = {self.omega_mean:.8g} rad/s, t_Φ = {self.period:.6g} s)",
            f"  ω_max            {self.omega_max:.8g} rad/s at φ = {degrees(self.phi_max):.4f}°",
            f"  ω_min            {self.omega_min:.8g} rad/s at φ = {degrees(self.phi_min):.4f}°",
            f"  load torque      {self.mean_load_torque:.6g} N·m",
            f"  δ (time mean)    {self.delta:.6e}   (about the midrange: {self.delta_midrange:.6e})",
            f"  δ without gravity {self.delta_without_gravity:.6e}   "
            f"(gravity changes δ by {100 * self.gravity_effect:+.3g} %)",
            f"  δ coasting       {self.delta_coasting:.6e}   (gas, drive and load removed: J(φ) and gravity)",
        ]
        if self.near_stall:
            lines.append(f"  note: {NEAR_STALL_NOTE}")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return self.summary()


# -- the solvers ---------------------------------------------------------------------------------


def _load_mean(cycle: CycleTables, rules: Rules, solution: Periodic) -> float:
    if rules.route == BALANCE or not isinstance(rules.load, Torque):
        return solution.load_torque if rules.route == BALANCE else 0.0
    phi = cycle.rule.phi
    return cycle.rule.mean(rules.load(phi, solution.omega_at(phi)))


def _stall_error(error: Stall, cycle: CycleTables, rules: Rules, omega_mean: float | None, ratio: float) -> StallError:
    error.angle %= cycle.rule.cycle
    if rules.route != BALANCE:
        return StallError(
            f"the machine stalls with this load: {error}, near φ = {math.degrees(error.angle):.4g}°; it has no "
            f"steady running (min_speed_ratio = {ratio:g})",
            angle=error.angle,
        )
    assert omega_mean is not None
    balance = balance_at(cycle, rules, omega_mean)
    lowest = balance.lowest_running_speed(ratio, above=1e-6 * balance.swing)

    def runs(omega: float) -> bool:
        try:
            solve_periodic(cycle, rules, omega, ratio)
        except Stall:
            return False
        return True

    min_rpm = rpm_from_omega(running_speed(lowest, runs))
    return StallError(
        f"the machine stalls at rpm = {rpm_from_omega(omega_mean):.6g}: {error}; it would crawl over its dead point "
        f"at φ = {math.degrees(error.angle):.4g}° (ω_min < min_speed_ratio·ω_m with min_speed_ratio = {ratio:g}); "
        f"the lowest mean speed that runs is min_rpm = {min_rpm:.6g}",
        angle=error.angle,
        min_rpm=min_rpm,
    )


def _delta_or_nan(cycle: CycleTables, rules: Rules, omega_mean: float | None, ratio: float) -> float:
    try:
        return solve_periodic(cycle, rules, omega_mean, ratio).delta
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
        machine coasting (gas, drive and load removed).

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
    rpm_value = mean_rpm(rpm, rules.route, machine)
    gravity = as_flag(gravity, "gravity")
    ratio = as_min_speed_ratio(min_speed_ratio)
    count = _as_points(points)

    solved = _native_solution(machine, rules, rpm_value, gravity, ratio, count)
    if solved is None:
        solved = _python_solution(machine, rules, rpm_value, gravity, ratio, count)
    numbers, later = solved
    return SteadyState(
        machine=machine,
        load_rule=_describe(load, rules),
        gravity=gravity,
        min_speed_ratio=ratio,
        cycle=machine.cycle,
        **numbers,
        _later=later,
    )


#: The numbers of a solution that :class:`SteadyState` holds from the start.
_NUMBERS = ("omega_mean", "omega_max", "omega_min", "phi_max", "phi_min", "period", "mean_load_torque")
#: Its comparison δ, computed when first read on the core's route.
_COMPARISONS = ("delta_without_gravity", "delta_coasting")
#: Their old names: in a pickle of 0.1, and in the native extension's results (which still
#: say "delta_gravity_only" for δ of the machine coasting).
_RENAMED_COMPARISONS = {"delta_gravity_only": "delta_coasting"}


def _native_comparisons(found: dict[str, Any]) -> dict[str, float]:
    """The comparison δ of a native result, by their names here."""
    named = {_RENAMED_COMPARISONS.get(key, key): value for key, value in found.items()}
    return {name: float(named[name]) for name in _COMPARISONS}


_Solved = tuple[dict[str, Any], Callable[[str], dict[str, Any]]]


def _arrays(
    machine: Machine,
    rules: Rules,
    gravity: bool,
    phi: np.ndarray,
    curves: dict[str, Any],
    omega_mean: float,
    period: float,
    mean_load: float,
) -> dict[str, np.ndarray]:
    """The arrays of :class:`SteadyState` (read-only) from ω and t at ``phi`` (``curves``),
    with J, J′, M_gas and the gravity torque from ``curves`` where the core gave them."""
    count = phi.size
    omega, time = curves["omega"], curves["time"]
    time[0], time[-1] = 0.0, period
    if "gas_torque" in curves:
        J, slope = curves["reduced_inertia"], curves["reduced_inertia_slope"]
        gas, weight = curves["gas_torque"], curves["gravity_torque"]
    else:
        J, slope = machine.reduced_inertia(phi)
        gas = machine.gas_torque(phi)
        weight = machine.gravity_torque(phi) if gravity and machine.g != 0 else np.zeros(count)
    inertia = inertia_torque(slope, omega)
    speed = np.full(count, omega_mean) if rules.route == BALANCE else omega
    drive_ = rules.drive(phi, speed) if rules.drive is not None else np.zeros(count)
    if rules.route == BALANCE:
        load_ = np.full(count, mean_load)
    else:
        load_ = rules.load(phi, omega) if isinstance(rules.load, Torque) else np.zeros(count)
    arrays = dict(
        phi=phi,
        omega=omega,
        time=time,
        reduced_inertia=J,
        reduced_inertia_slope=slope,
        gas_torque=gas,
        gravity_torque=weight,
        inertia_torque=inertia,
        drive_torque=drive_,
        load_torque=load_,
        acceleration=(gas + weight + inertia + drive_ - load_) / J,
    )
    for array in arrays.values():
        array.flags.writeable = False
    return arrays


def _native_solution(
    machine: Machine, rules: Rules, rpm: float | None, gravity: bool, ratio: float, points: int
) -> _Solved | None:
    """The steady state by the Rust core, where it solves it: the "balance" load beside no
    drive or one that does not depend on φ (one solve now; the arrays and the two comparison
    solves when first read), or a square law beside at most a constant drive (all at once);
    a pressure callable crosses sampled (:func:`~multicrank.machine.native.sampled`). None
    elsewhere (a callable drive under "balance", a load solved by shooting: the Python
    implementation's)."""
    balance = rules.plain_balance
    square_law = rules.route == "square-law"
    if not (balance or square_law):
        return None
    native = motion_machine(machine, gravity=gravity)
    # The square law's curves come with its solution; "balance" makes its angles only when
    # its arrays are read.
    square_law_phi = None if balance else np.linspace(0.0, machine.cycle, points)
    try:
        if balance:
            assert rpm is not None
            found = native.steady_state(rpm, ratio, None, False)
        else:
            assert isinstance(rules.load, Torque)
            found = native.square_law(rules.load.value.coefficient, rules.constant_drive, ratio, square_law_phi)
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
                ) from None
        raise _native_stall(angle, rpm, getattr(error, "min_rpm", None), ratio) from None
    numbers = {name: float(found[name]) for name in _NUMBERS}
    if balance and rules.drive is not None:  # the load takes the drive too (Rules.plain_balance)
        assert rpm is not None
        numbers["mean_load_torque"] += rules.drive_at(omega_from_rpm(rpm))
    mean, period, load = numbers["omega_mean"], numbers["period"], numbers["mean_load_torque"]

    def later(what: str) -> dict[str, Any]:
        if what == "comparisons":
            if not balance:  # the square law gave them with the rest
                return _native_comparisons(found)
            assert rpm is not None
            compared = native.comparisons(rpm, float(found["delta"]), mean, ratio)
            return dict(zip(_COMPARISONS, compared, strict=True))
        if balance:
            assert rpm is not None
            phi = np.linspace(0.0, machine.cycle, points)
            return _arrays(
                machine, rules, gravity, phi, native.steady_state(rpm, ratio, phi, False), mean, period, load
            )
        assert square_law_phi is not None
        return _arrays(machine, rules, gravity, square_law_phi, found, mean, period, load)

    return dict(numbers, method=METHODS[rules.route]), later


def _native_stall(angle: float, rpm: float | None, min_rpm: float | None, ratio: float) -> StallError:
    """The core's stall as :func:`_stall_error` words it."""
    if rpm is None or min_rpm is None:
        return StallError(
            f"the machine stalls with this load: its speed would fall below min_speed_ratio·ω_m near φ = "
            f"{math.degrees(angle):.4g}°; it has no steady running (min_speed_ratio = {ratio:g})",
            angle=angle,
        )
    return StallError(
        f"the machine stalls at rpm = {rpm:.6g}: it would crawl over its dead point at φ = {math.degrees(angle):.4g}° "
        f"(ω_min < min_speed_ratio·ω_m with min_speed_ratio = {ratio:g}); the lowest mean speed that runs is "
        f"min_rpm = {min_rpm:.6g}",
        angle=angle,
        min_rpm=min_rpm,
    )


def _python_solution(
    machine: Machine, rules: Rules, rpm: float | None, gravity: bool, ratio: float, points: int
) -> _Solved:
    """The steady state by the Python implementation (any load, drive and pressure), all at
    once."""
    phi = np.linspace(0.0, machine.cycle, points)
    omega_mean = None if rpm is None else omega_from_rpm(rpm)
    cycle = cycle_tables(machine, gravity)
    try:
        solution = solve_periodic(cycle, rules, omega_mean, ratio)
    except Stall as error:
        raise _stall_error(error, cycle, rules, omega_mean, ratio) from None
    mean = solution.omega_mean
    if cycle.gravity_on:
        delta_without = _delta_or_nan(cycle.without_gravity(), rules, omega_mean, ratio)
    else:
        delta_without = solution.delta
    # Coasting: gas, drive and load gone; the conservative machine (J(φ) and gravity) at the
    # same mean speed.
    try:
        delta_coasting = Balance(cycle, None, 0.0, gas=False).solve(mean, ratio).delta
    except Stall:
        delta_coasting = math.nan
    J, _ = cycle.J_at(phi)
    extremes = solution.extremes
    numbers = dict(
        omega_mean=mean,
        omega_max=extremes.omega_max,
        omega_min=extremes.omega_min,
        phi_max=extremes.phi_max,
        phi_min=extremes.phi_min,
        period=solution.period,
        mean_load_torque=_load_mean(cycle, rules, solution),
    )
    curves = dict(omega=np.sqrt(2.0 * np.maximum(solution.energy_at(phi), 0.0) / J), time=solution.time_at(phi))
    arrays = _arrays(machine, rules, gravity, phi, curves, mean, solution.period, numbers["mean_load_torque"])
    compared = dict(delta_without_gravity=delta_without, delta_coasting=delta_coasting)
    return dict(numbers, method=solution.method), lambda what: arrays if what == "arrays" else compared


def _describe(load: Any, rules: Rules) -> str:
    if rules.route == BALANCE:
        return "'balance'"
    if isinstance(load, PowerLawLoad):
        return repr(load)
    return repr(load) if not callable(load) else getattr(load, "__name__", "callable")
