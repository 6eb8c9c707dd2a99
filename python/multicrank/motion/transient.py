"""The machine in time: start-up, run-down, load steps (docs/theory.md, "Transients").

:func:`simulate` integrates the machine's equation of motion (docs/theory.md, "Transients")

    J(φ) φ̈ + ½ J'(φ) φ̇² = M_gas(φ) − U'(φ) + M_drive(φ, φ̇) − M_load(φ, φ̇)

in time with SciPy's ``solve_ivp``, together with the work W of the non-conservative
torques (gas, drive, load), so that ½ J ω² + U − W is a constant of every run: the
result's ``energy_drift`` is a built-in check of the whole chain (kinematics, torques,
integrator). J, J', U, the gravity and the gas torques come from the Rust core through
:class:`~multicrank.Machine`; here they are only put together. This module holds the API and
the result (:class:`Transient`); the right-hand side and SciPy's driver are in ``_integration``.

Speeds follow the house convention: a name carries its unit, ``omega…`` in rad/s
(the result's ``omega``) and ``rpm…`` in 1/min (``rpm0``, ``balance_rpm``, the result's
``rpm_history``).

SciPy is imported when a run starts, pandas and xarray when a result is converted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .._inertia_torque import inertia_torque
from .._validation import (
    RPM_LIMITS,
    SPEED_LIMITS,
    as_flag,
    as_instance,
    as_omega,
    as_real_array,
    as_scalar,
    omega_from_rpm,
    one_of,
    refused,
    renamed,
    rpm_from_omega,
    warn_renamed,
)
from ..machine.machine import Machine
from ._integration import METHODS, _integrate, _Model, _Solution, _tolerances
from ._result import MotionResult
from .loads import AppliedTorques

__all__ = ["METHODS", "Transient", "simulate"]

#: The per-sample arrays of a :class:`Transient`, in column order, with their units.
COLUMNS = {
    "phi": "rad",
    "omega": "rad/s",
    "acceleration": "rad/s²",
    "reduced_inertia": "kg·m²",
    "gas_torque": "N·m",
    "gravity_torque": "N·m",
    "inertia_torque": "N·m",
    "drive_torque": "N·m",
    "load_torque": "N·m",
    "kinetic_energy": "J",
    "potential_energy": "J",
    "work": "J",
}


@dataclass(frozen=True, eq=False)
class Transient(MotionResult):
    """The machine's state and torques at the sample times: the result of :func:`simulate`.

    Every array has one entry per sample: the times of ``t_eval`` up to the end of the run
    and, when the machine stalled, the stall itself as the last sample. The arrays are
    read-only; their names are those of :class:`SteadyState` and of the
    :class:`~multicrank.Machine` methods that give them. Speeds: ``omega`` in rad/s,
    :attr:`rpm_history` in 1/min (``rpm``, a number elsewhere, is the steady state's mean
    speed; ``Transient.rpm`` is the deprecated name of 0.1 of this array).

    Attributes
    ----------
    time : ndarray
        t [s].
    phi : ndarray
        φ [rad], the crank angle, unwrapped (cumulative: it grows by 2π per revolution).
    omega : ndarray
        ω = φ̇ [rad/s]; exactly 0 at a stall.
    acceleration : ndarray
        φ̈ [rad/s²] from the equation of motion.
    reduced_inertia : ndarray
        J(φ) [kg·m²].
    gas_torque, gravity_torque : ndarray
        M_gas(φ) and −U'(φ) [N·m] (the gravity torque is 0 for ``gravity=False``).
    inertia_torque : ndarray
        −½ J'(φ) ω² [N·m], the velocity term of the equation of motion, so that
        J·φ̈ = gas + gravity + inertia + drive − load at every sample.
    drive_torque, load_torque : ndarray
        M_drive and M_load [N·m] (zeros where none was given; the load positive resisting).
    kinetic_energy, potential_energy : ndarray
        ½ J ω² and U(φ) [J] (U = 0 for ``gravity=False``).
    work : ndarray
        W [J], the work of the gas, drive and load torques since the start,
        ∫ (M_gas + M_drive − M_load) ω dt, integrated with the motion.
    stalled : bool
        Whether ω reached 0 (the run stops there).
    stall_time : float or None
        The time of the stall [s], None if the machine did not stall.
    energy_drift : float
        The largest change of E = ½ J ω² + U − W over the run over the largest kinetic
        energy ½ J ω² of the run [dimensionless]: E is a constant of the exact motion, so
        this is the integration's relative error in energy (0 for a run that never moves).
    nfev : int
        The number of right-hand-side evaluations the integrator made.
    message : str
        The integrator's closing message.
    method : str
        The ``solve_ivp`` method that integrated it (:attr:`solved` in words).
    """

    time: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    acceleration: np.ndarray
    reduced_inertia: np.ndarray
    gas_torque: np.ndarray
    gravity_torque: np.ndarray
    inertia_torque: np.ndarray
    drive_torque: np.ndarray
    load_torque: np.ndarray
    kinetic_energy: np.ndarray
    potential_energy: np.ndarray
    work: np.ndarray
    stalled: bool
    stall_time: float | None
    energy_drift: float
    nfev: int
    message: str
    method: str = "DOP853"

    COLUMNS: ClassVar[dict[str, str]] = {"time": "s", **COLUMNS}
    NUMBERS: ClassVar[dict[str, str]] = {"stalled": "", "stall_time": "s", "energy_drift": ""}

    @property
    def solved(self) -> str:
        """What was solved and how, in words."""
        return f"time integration ({self.method})"

    @property
    def rpm_history(self) -> np.ndarray:
        """n = 30 ω/π [1/min], the speed at each sample in revolutions per minute."""
        return rpm_from_omega(self.omega)

    #: The name of 0.1 for :attr:`rpm_history` (an array, where ``rpm`` is a number elsewhere).
    rpm: ClassVar[renamed] = renamed("rpm_history")

    def __len__(self) -> int:
        return int(self.time.size)

    def __repr__(self) -> str:
        end = f"stalled at t = {self.stall_time:.6g} s" if self.stalled else f"to t = {self.time[-1]:.6g} s"
        return (
            f"Transient({len(self)} samples from t = {self.time[0]:.6g} s {end}, "
            f"ω {self.omega[0]:.6g} → {self.omega[-1]:.6g} rad/s, energy_drift = {self.energy_drift:.2g})"
        )


def simulate(
    machine: Machine,
    t_eval: Any,
    *,
    rpm0: float | None = None,
    phi0: float = 0.0,
    load: Any = None,
    drive: Any = None,
    gravity: bool = True,
    rtol: float = 1e-10,
    atol: float = 1e-10,
    method: str = "DOP853",
    max_step: float = math.inf,
    balance_speed: float | None = None,
    progress: bool = False,
    omega0: float | None = None,
    balance_rpm: float | None = None,
) -> Transient:
    """Integrate the machine's motion in time: start-up, run-down, a load step.

    Solves J(φ) φ̈ + ½ J'(φ) φ̇² = M_gas(φ) − U'(φ) + M_drive(φ, φ̇) − M_load(φ, φ̇) with
    ``scipy.integrate.solve_ivp`` for the state (φ, ω, W), W being the work of the gas,
    drive and load torques, dW/dt = (M_gas + M_drive − M_load)·ω.

    Parameters
    ----------
    machine : Machine
        The machine.
    t_eval : array_like, 1-D
        The sample times [s]: finite, strictly increasing, at least two, the first ≥ 0.
        **The run starts at t_eval[0]** (with φ = ``phi0``, n = ``rpm0``) and ends at
        t_eval[-1] or at a stall. To continue a run (a load step, say), start the next one
        at the last sample: ``simulate(machine, t_next, rpm0=r.rpm_history[-1],
        phi0=r.phi[-1], load=new_load)`` with ``t_next[0] = r.time[-1]``.
    rpm0 : float
        n₀, the speed at the start [1/min] (ω₀ = π n₀/30), finite and ≥ 0. Gas pressure given
        as a function of the cycle angle assumes the machine turns forward (docs/theory.md,
        "Transients"), so a negative start speed is refused; from n₀ = 0 a machine whose net
        torque at φ₀ is not positive stalls at once.
    phi0 : float
        φ at the start [rad], any finite real.
    load, drive : optional
        A number (constant torque, N·m), a :class:`~multicrank.PowerLawLoad`, or a
        vectorised callable ``f(phi, omega) -> N·m`` of the cumulative crank angle φ [rad]
        and the speed ω [rad/s] (reduce φ modulo ``machine.cycle`` where a torque depends on
        the place in the cycle); the load positive resisting rotation, the drive positive
        driving it. The load may also be ``"balance"``: the constant load equal to the cycle
        mean of the gas and drive torques, (1/Φ)∫₀^Φ (M_gas + M_drive) dφ, computed once, at
        the start, a speed-dependent drive being called with ω = ``balance_rpm`` there.
    gravity : bool
        False leaves gravity out (U ≡ 0), as if g were 0; J is the same either way.
    rtol, atol : float
        The integrator's relative and absolute tolerances: 2.2e-14 (100 machine epsilons)
        ≤ rtol < 1 and atol ≥ 1e-100, finite (atol applies to φ [rad], ω [rad/s] and W [J]
        alike).
    method : str
        The ``solve_ivp`` method: "DOP853" (default; 8th-order explicit Runge–Kutta), "RK45",
        "RK23", or an implicit one ("Radau", "BDF", "LSODA") for very stiff loads.
    max_step : float
        The largest time step [s], > 0 (default: no limit). Set it below the duration of
        the shortest feature of the torques (a combustion spike, a valve event) when the run
        starts with a step that could jump over it. At least 1e-8 of the run's duration (at
        most 10⁸ steps); a run is also refused beyond 10⁷ revolutions at ``rpm0``, so that
        no call runs for hours.
    balance_speed : float, optional
        Deprecated since 0.2 (goes in 0.3): ``balance_rpm`` in rad/s.
    progress : bool
        Show a tqdm progress bar of the simulated time, counted in the output times ``t``
        passed (it follows the integrator's farthest evaluation; the result does not depend
        on it).
    omega0 : float, optional
        Deprecated since 0.2 (goes in 0.3): ``rpm0`` in rad/s.
    balance_rpm : float, optional
        The speed [1/min] at which a speed-dependent drive is frozen for ``load="balance"``;
        default the start speed. Refused with any other load.

    Returns
    -------
    Transient
        Times, φ, ω, the torques and energies at the samples, ``stalled``, ``stall_time``
        and ``energy_drift``; ``to_pandas()`` and ``to_xarray()`` convert it.

    Raises
    ------
    MechanismError
        For bad input, naming the parameter; for an integrator that fails (its message).

    Notes
    -----
    **Stall.** A terminal event at ω = 0 (ω falling) ends the run: the last sample is the
    stall, at ``stall_time``, with ω = 0. The machine would then turn backwards or stay at
    rest, neither of which a pressure given per cycle angle describes.

    **Energy check.** E = ½ J(φ) ω² + U(φ) − W is constant along the exact motion for any
    torques, so ``energy_drift`` measures the integration's error; for a conservative run
    (no gas, drive or load) it is the drift of ½ J ω² + U itself. With the default
    tolerances it stays of the order of 1e-9 over tens of revolutions (docs/theory.md,
    "Transients", gives measured figures).

    **Kinks.** Tabulated pressures have kinks (valve events, breakpoints); the adaptive
    step follows them at the cost of more steps, so runs with such gas torques take longer
    at tight tolerances than smooth ones.

    Examples
    --------
    The slow compressor at 120 rpm with its motor switched off: the gas work brakes it
    until it stalls.

    >>> import numpy as np
    >>> import multicrank as mc
    >>> compressor = mc.presets.MACHINES["slow-compressor"]
    >>> times = np.linspace(0.0, 10.0, 201)  # s
    >>> run = mc.simulate(compressor, times, rpm0=120)
    >>> print(f"stalled: {run.stalled}, after {run.stall_time:.2f} s; "
    ...       f"energy check {run.energy_drift < 1e-8}")
    stalled: True, after 4.31 s; energy check True
    >>> run.to_pandas()[["omega", "gas_torque"]].head(3).round(2)
          omega  gas_torque
    time
    0.00  12.57        0.00
    0.05  12.62       58.75
    0.10  12.56     -878.40
    """
    machine = as_instance(machine, Machine, "machine")
    times = _as_times(t_eval)
    start_name, omega_start = _start_speed(rpm0, omega0)
    phi_start = _finite(phi0, "phi0")
    tolerances = _tolerances(rtol, atol)
    step_limit = as_scalar(max_step, "max_step")
    # The work is bounded up front (issue 13: fail fast, never hang): at most 10⁸ steps of
    # max_step, at most 10⁷ revolutions at the start speed, over the run.
    span = float(times[-1] - times[0])
    if not step_limit >= span * 1e-8 or not step_limit > 0:
        raise refused(
            "max_step",
            f"max_step = {step_limit} is out of range; allowed: max_step > 0 [s] and at least 1e-8 of the run "
            f"({span:g} s), i.e. at most 10⁸ steps",
        )
    revolutions = omega_start * span / (2 * math.pi)
    if revolutions > 1e7:
        raise refused(
            start_name,
            f"{start_name}: a start speed of {omega_start:g} rad/s over the run's {span:g} s is {revolutions:.3g} "
            "revolutions; at most 10⁷ in one run (shorten t_eval)",
        )
    if not isinstance(method, str) or method not in METHODS:
        raise refused("method", f"method = {method!r} is not allowed; allowed: {', '.join(map(repr, METHODS))}")
    gravity = as_flag(gravity, "gravity")
    progress = as_flag(progress, "progress")
    torques = AppliedTorques.of(load, drive)
    frozen = _balance_speed(balance_rpm, balance_speed, torques.balance)
    torques = torques.balanced(machine, omega_start if frozen is None else frozen)
    assert not isinstance(torques.load, str)

    model = _Model(machine, torques.drive, torques.load, gravity and machine.g != 0.0)
    solution = _integrate(model, times, phi_start, omega_start, tolerances, method, step_limit, progress)
    return _transient(model, solution, method)


# -- the result at the samples ---------------------------------------------------------------


def _transient(model: _Model, solution: _Solution, method: str) -> Transient:
    """The result: the torques and energies at the solution's samples, and the energy drift."""
    time, phi, omega, work = solution.time, solution.phi, solution.omega, solution.work
    inertia, slope = model.machine.reduced_inertia(phi)
    gas, drive, load = model.external(phi, omega)
    gravity = model.gravity_torque(phi)
    velocity_term = inertia_torque(slope, omega)
    kinetic = 0.5 * inertia * omega**2
    potential = model.potential_energy(phi)
    energy = kinetic + potential - work
    scale = float(np.max(kinetic))
    drift = float(np.max(np.abs(energy - energy[0]))) / scale if scale > 0 else 0.0
    arrays = {
        "time": time,
        "phi": phi,
        "omega": omega,
        "acceleration": (gas + gravity + velocity_term + drive - load) / inertia,
        "reduced_inertia": inertia,
        "gas_torque": gas,
        "gravity_torque": gravity,
        "inertia_torque": velocity_term,
        "drive_torque": drive,
        "load_torque": load,
        "kinetic_energy": kinetic,
        "potential_energy": potential,
        "work": work,
    }
    for array in arrays.values():
        array.setflags(write=False)
    return Transient(
        **arrays,
        stalled=solution.stalled,
        stall_time=solution.stall_time,
        energy_drift=drift,
        nfev=solution.nfev,
        message=solution.message,
        method=method,
    )


# -- validation -------------------------------------------------------------------------------


def _as_times(t_eval: Any) -> np.ndarray:
    times = as_real_array(t_eval, "t_eval")
    if times.ndim != 1:
        raise refused("t_eval", f"t_eval must be a 1-D array of times [s], got shape {times.shape}")
    if times.size < 2:
        raise refused("t_eval", f"t_eval must hold at least 2 times [s] (the start and an end), got {times.size}")
    if not np.all(np.isfinite(times)):
        bad = int(np.flatnonzero(~np.isfinite(times))[0])
        raise refused("t_eval", f"t_eval[{bad}] = {times[bad]} is not finite; t_eval must be finite times [s]")
    if times[0] < 0:
        raise refused(
            "t_eval", f"t_eval[0] = {times[0]} is out of range; allowed: t_eval[0] >= 0 [s] (the run starts there)"
        )
    steps = np.diff(times)
    if not np.all(steps > 0):
        i = int(np.flatnonzero(~(steps > 0))[0])
        raise refused(
            "t_eval",
            f"t_eval must increase strictly: t_eval[{i + 1}] = {times[i + 1]!r} follows t_eval[{i}] = {times[i]!r}",
        )
    return np.array(times, dtype=float)


def _finite(value: Any, name: str) -> float:
    x = as_scalar(value, name)
    if not math.isfinite(x):
        raise refused(name, f"{name} = {x} is out of range; allowed: a finite number")
    return x


def _start_speed(rpm0: Any, omega0: Any) -> tuple[str, float]:
    """(the name given, ω₀ [rad/s]) from ``rpm0`` [1/min] or its deprecated alias ``omega0``
    [rad/s] (exactly one), finite and ≥ 0."""
    name, value = one_of(("rpm0", rpm0), ("omega0", omega0))
    speed = _finite(value, name)
    unit = "rad/s" if name == "omega0" else "1/min"
    if speed < 0:
        raise refused(
            name,
            f"{name} = {speed} is out of range; allowed: {name} >= 0 [{unit}] (gas pressure per cycle angle "
            "assumes forward rotation)",
        )
    # From rest, or at a speed within the machines' limits (the core's SPEED_LIMITS, in rad/s):
    # a start speed of 1e-159 rad/s is no rest and no speed, and the integrator's step control
    # divides by it (hypothesis found the overflow).
    omega = speed if name == "omega0" else float(omega_from_rpm(speed))
    low, high = RPM_LIMITS if name == "rpm0" else SPEED_LIMITS
    if omega != 0 and not SPEED_LIMITS[0] <= omega <= SPEED_LIMITS[1]:
        raise refused(
            name,
            f"{name} = {speed} is out of range; allowed: {name} = 0 (from rest) or {low:g} <= {name} <= {high:g} "
            f"[{unit}]",
        )
    if name == "omega0":
        warn_renamed("simulate(omega0=ω [rad/s])", "rpm0=n [1/min]", stacklevel=4)
    return name, omega


def _balance_speed(balance_rpm: Any, balance_speed: Any, balance: bool) -> float | None:
    """The ω [rad/s] at which "balance" freezes a drive, from ``balance_rpm`` [1/min] or its old
    name ``balance_speed`` [rad/s]; None: the start speed."""
    if balance_rpm is None and balance_speed is None:
        return None
    name, value = one_of(("balance_rpm", balance_rpm), ("balance_speed", balance_speed))
    if not balance:
        raise refused(name, f"{name} applies to load='balance' only")
    speed = _finite(value, name)
    if name == "balance_speed":
        warn_renamed("simulate(balance_speed=ω [rad/s])", "balance_rpm=n [1/min]", stacklevel=4)
        return speed
    return as_omega(speed, name)  # a speed [1/min] by the core's rule, converted once
