"""The result of :func:`~multicrank.motion.steady.steady_state`: :class:`SteadyState`, a
machine's periodic steady running over one working cycle, and :class:`StallError`, the refusal
of a machine that would crawl over its dead point, with :data:`NEAR_STALL_DELTA` and its note.
How the steady state is solved is :mod:`~multicrank.motion.steady`'s (which re-exports every
name here).

Speeds follow the house convention: a name carries its unit, ``rpm…`` in 1/min
(:attr:`SteadyState.rpm`), ``omega…`` in rad/s (``omega``, ``omega_mean``, ``omega_max``,
``omega_min``); ω = πn/30.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from .._native import MechanismError
from .._text import counted
from .._validation import renamed, rpm_from_omega
from ..machine.machine import Machine
from ._deferred import Computed, CoreQuestion
from ._periodic import SOLVED
from ._result import MotionResult
from ._shooting import restored_error

__all__ = ["NEAR_STALL_DELTA", "NEAR_STALL_NOTE", "StallError", "SteadyState"]


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
    parameter : str, default "rpm"
        The parameter the refusal is about (the exception's ``parameter``): "rpm", the
        mean speed asked for, or "load" where the load fixes the speed itself.

    Attributes
    ----------
    angle : float
        The crank angle φ [rad] of the speed minimum (where it stops or crawls).
    min_rpm : float or None
        For ``load="balance"``: the lowest mean speed [1/min] that runs, i.e. whose speed
        minimum is ``min_speed_ratio`` times the mean speed. None for other loads, which fix
        the speed themselves.
    parameter : str
        "rpm" (the speed the machine does not run at) or "load" (a load under which it has
        no steady running at all), as every :class:`~multicrank.MechanismError` names its
        parameter.

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

    def __init__(self, message: str, *, angle: float, min_rpm: float | None = None, parameter: str = "rpm") -> None:
        super().__init__(message)
        self.parameter = parameter
        self.angle = float(angle)
        self.min_rpm = None if min_rpm is None else float(min_rpm)

    def __reduce__(self) -> tuple[Any, ...]:
        # An exception pickles as cls(*args), and angle is keyword-only: rebuild it without
        # __init__ and restore the attributes, so that the error crosses a pickle (a
        # multiprocessing worker's error sent back to its parent) whole.
        return (restored_error, (type(self), self.args, self.__dict__))


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
    status : int
        How the solve ended, SciPy's convention (``solve_ivp``'s ``status``): 0, converged —
        the only value a result has, since a machine that stalls raises :class:`StallError`
        instead (a stall is status 1 in the solver's own terms).
    message : str
        How the solve ended, in words (the solver's).
    nfev : int
        Evaluations of the function whose root the solver finds [count]: by the energy method
        ("balance") the mean speed as a function of the kinetic energy left at the worst
        angle, each a quadrature of the period over the cycle (a handful: Brent's method on a
        nearly linear function); 0 for the closed form (square law), which finds no root; by
        shooting the right-hand sides of every ``solve_ivp`` run of the search for E(0) (its
        bracket, Brent's method and the final run), the sum of their ``nfev``.
    nit : int
        Of the root finder's work, Brent's method's iterations [count] (the other evaluations
        bracket the root); 0 for the closed form.
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
    status: int
    message: str
    nfev: int
    nit: int
    #: What computes the rest on first use: its ``arrays()`` the arrays by name, its
    #: ``comparisons()`` the two comparison δ by name (each asked once, then kept): the
    #: question the core answered, or what shooting found with the solution. None in a pickle.
    _later: CoreQuestion | Computed | None = field(repr=False, compare=False)

    @classmethod
    def _of(cls, fields: dict[str, Any]) -> SteadyState:
        """A result of every field (name → value), checked by the solver that made them,
        without the frozen ``__init__`` (which sets each of the 18 fields through
        ``object.__setattr__``, and with its keywords took ~4 µs of a warm steady state's ~20)."""
        state = object.__new__(cls)
        state.__dict__.update(fields)
        return state

    # The arrays and the two comparison solves, computed when first read: δ alone costs one
    # solve (docs/theory.md, "Where it is computed, and when").
    @cached_property
    def _curves(self) -> dict[str, np.ndarray]:
        # φ, ω and t alone: reading them does not compute the torques (a pickle holds them all).
        if "_arrays" in self.__dict__:
            return self.__dict__["_arrays"]
        assert self._later is not None
        return self._later.curves()

    @cached_property
    def _arrays(self) -> dict[str, np.ndarray]:
        assert self._later is not None  # a pickle holds them
        return self._later.arrays(self._curves)

    @cached_property
    def _comparisons(self) -> dict[str, float]:
        assert self._later is not None  # a pickle holds them
        return self._later.comparisons()

    @property
    def phi(self) -> np.ndarray:
        """Crank angle φ [rad], uniform over the closed cycle."""
        return self._curves["phi"]

    @property
    def omega(self) -> np.ndarray:
        """Shaft speed ω(φ) [rad/s]."""
        return self._curves["omega"]

    @property
    def time(self) -> np.ndarray:
        """t(φ) [s] from φ = 0; ``time[-1]`` = t_Φ."""
        return self._curves["time"]

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
        # A pickle of 0.1 has no word on how the solve ended: it converged (or it would not
        # exist); its count is unknown (-1).
        for name, value in (
            ("status", 0),
            ("message", "converged (pickled by multicrank 0.1)"),
            ("nfev", -1),
            ("nit", -1),
        ):
            state.setdefault(name, value)
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
        "status": "",
        "message": "",
        "nfev": "count",
        "nit": "count",
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


#: Their old names: in a pickle of 0.1, and in the native extension's results (which still
#: say "delta_gravity_only" for δ of the machine coasting).
_RENAMED_COMPARISONS = {"delta_gravity_only": "delta_coasting"}
