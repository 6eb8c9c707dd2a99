"""Shooting: the periodic steady state under a load or drive that depends on the speed, and the
flywheel for it (docs/theory.md, "Steady running"); the route that stays in Python, because the
core cannot call a Python load (the flywheel's root search over these steady states is the core's).

The equation of motion J φ̈ + ½ J′ φ̇² = M − U′ is, with the kinetic energy E = ½ J ω² as the
unknown and φ as the variable, dE/dφ = M(φ, ω) − U′(φ). Its part that depends on φ alone,
K₀(φ) = W(φ) − (U(φ) − U(0)) [J] (W the gas work from φ = 0), comes from the Rust core
(:meth:`~multicrank._native.NativeMachine.gas_and_gravity_work`, exact also for tabulated
pressures); SciPy's ``solve_ivp`` (DOP853) integrates only Y = E − K₀, with
dY/dφ = M_drive(φ, ω) − M_load(φ, ω), and the time t, with dt/dφ = 1/ω, over one cycle, and
Brent's method finds the E(0) with E(Φ) = E(0). J(φ) is the machine's
(:meth:`~multicrank.Machine.reduced_inertia`), with the trial shaft inertia I_w in place of the
machine's own during a flywheel search. Notation: Φ the working cycle [rad], ω_m = Φ/t_Φ the
time-mean speed [rad/s].
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np

from .._native import MechanismError, size_shaft_inertia
from .._validation import refused
from ..machine.machine import Machine
from ..machine.native import motion_machine, sampled

__all__ = ["Periodic", "ShaftCycle", "Stall", "cycle_mean", "flywheel_for", "shoot"]

#: The shooting's relative tolerance (solve_ivp's rtol and the root's): ω_m to ~1e-10.
SHOOTING_RTOL = 1e-11

#: The cycle means (:func:`cycle_mean`): Gauss–Legendre nodes per panel and the widest panel
#: [rad]. A smooth torque's mean is exact to rounding on such panels (12 nodes integrate a
#: polynomial of degree 23 exactly; sin kφ to ~1e-16 up to k ≈ 50).
MEAN_ORDER, MEAN_WIDTH = 12, math.pi / 16

#: Samples per radian on which the extremes of ω are bracketed before they are refined.
EXTREMES_PER_RADIAN = 160


def scipy_optimize() -> Any:
    import scipy.optimize  # type: ignore[import-untyped,unused-ignore]

    return scipy.optimize


def restored_error(cls: type[BaseException], args: tuple[Any, ...], state: dict[str, Any]) -> BaseException:
    """An exception of ``cls`` with ``args`` and the attributes ``state``, made without its
    ``__init__``: how an error whose ``__init__`` takes more than its message unpickles."""
    error = cls.__new__(cls, *args)
    error.__dict__.update(state)
    return error


class Stall(Exception):
    """Internal: the machine does not run at the state asked for (steady.py turns it into StallError)."""

    def __init__(self, angle: float, message: str) -> None:
        super().__init__(message)
        self.angle = angle

    def __reduce__(self) -> tuple[Any, ...]:
        # args holds the message only: rebuild without __init__ and restore the angle.
        return (restored_error, (type(self), self.args, self.__dict__))


# -- cycle means ---------------------------------------------------------------------------------


@cache
def _mean_rule(cycle: float) -> tuple[np.ndarray, np.ndarray]:
    """Nodes [rad] and weights [1] with ``weights @ f(nodes)`` ≈ (1/Φ)∫₀^Φ f dφ: numpy's
    Gauss–Legendre rule on equal panels at most :data:`MEAN_WIDTH` wide, cut at every multiple
    of π (dead centres of a unit of phase 0)."""
    x, w = np.polynomial.legendre.leggauss(MEAN_ORDER)
    panels = round(cycle / math.pi) * math.ceil(math.pi / MEAN_WIDTH - 1e-9)
    half = 0.5 * cycle / panels
    middles = (np.arange(panels) + 0.5) * 2 * half
    nodes = (middles[:, None] + half * x[None, :]).ravel()
    weights = np.tile(half * w, panels) / cycle
    return nodes, weights


def cycle_mean(function: Callable[[np.ndarray], np.ndarray], cycle: float) -> float:
    """(1/Φ)∫₀^Φ f dφ of a vectorised ``function`` of φ [rad], Φ = ``cycle``."""
    nodes, weights = _mean_rule(cycle)
    return float(weights @ np.asarray(function(nodes), dtype=float))


def mean_torque(shaft: ShaftCycle, applied: Callable[[np.ndarray, Any], np.ndarray], omega: float) -> float:
    """(1/Φ)∫(M_gas + M_drive − M_load) dφ [N·m] at a constant speed ω [rad/s] (``applied``:
    M_drive − M_load): what a "balance" load would take beside them. The gas's mean is the
    core's (the indicated work per cycle over Φ, exact)."""
    return shaft.native.mean_gas_torque() + cycle_mean(lambda phi: applied(phi, omega), shaft.cycle)


def quasi_static_speed(shaft: ShaftCycle, applied: Callable[[np.ndarray, Any], np.ndarray], name: str) -> float:
    """The constant speed [rad/s] at which the torques balance over a cycle: the start of the
    shooting. MechanismError naming ``name`` when there is none (the load never takes what
    the gas and the drive give, or the drive's mean is not positive)."""
    optimize = scipy_optimize()
    low, high = 1e-6, 1.0
    at_rest = mean_torque(shaft, applied, low)
    if not at_rest > 0:
        raise refused(
            name,
            f"{name}: the mean torque of gas and drive does not exceed the load's even at rest "
            f"({at_rest:.6g} N·m): the machine cannot run forward",
        )
    while mean_torque(shaft, applied, high) > 0:
        high *= 4.0
        if high > 1e9:
            raise refused(
                name,
                f"{name}: the load never balances the mean torque of gas and drive (up to 10⁹ rad/s): "
                "no periodic steady state; a constant load needs load='balance' and rpm",
            )
    return float(optimize.brentq(lambda w: mean_torque(shaft, applied, w), low, high, rtol=1e-12))


# -- the machine as the shooting takes it --------------------------------------------------------


class ShaftCycle:
    """The φ-only quantities of a machine over its cycle, from the core: K₀(φ) and J(φ) on a
    shaft of inertia I_w (default the machine's own ``shaft_inertia``).

    Parameters
    ----------
    machine : Machine
        The machine.
    gravity : bool
        False takes it with g = 0.
    """

    def __init__(self, machine: Machine, gravity: bool) -> None:
        self.machine, self.native = machine, motion_machine(machine)
        self.gravity = bool(gravity) and machine.g != 0
        self.cycle = machine.cycle
        self.inertia = machine.shaft_inertia
        # J − I_w on the mean rule's nodes: the rods' and pistons' share, for the least J.
        nodes, _ = _mean_rule(self.cycle)
        self._rest_min = float(np.min(machine.reduced_inertia(nodes)[0])) - machine.shaft_inertia
        self.per_cycle = float(self.K0(np.array([self.cycle]))[0])  # K₀(Φ) = W(Φ): U(Φ) = U(0)

    def K0(self, phi: Any) -> np.ndarray:
        """K₀(φ) = W(φ) − (U(φ) − U(0)) [J] at angles in [0, Φ] (a step's stage a rounding
        beyond Φ is taken at Φ)."""
        angles = np.asarray(phi, dtype=float)
        flat = np.ascontiguousarray(np.clip(angles.ravel(), 0.0, self.cycle))
        return np.asarray(self.native.gas_and_gravity_work(flat, gravity=self.gravity)).reshape(angles.shape)

    def J(self, phi: Any) -> np.ndarray:
        """J(φ) [kg·m²] with I_w = :attr:`inertia`, any angles."""
        return self.machine.reduced_inertia(phi)[0] - self.machine.shaft_inertia + self.inertia

    @property
    def J_min(self) -> float:
        """The least J over the cycle (on the mean rule's nodes) [kg·m²]."""
        return self._rest_min + self.inertia

    def with_inertia(self, inertia: float) -> ShaftCycle:
        """The same machine on a shaft of inertia I_w = ``inertia`` [kg·m²] (no call to the core)."""
        other = copy.copy(self)
        other.inertia = float(inertia)
        return other

    def without_gravity(self) -> ShaftCycle:
        """The same machine with g = 0."""
        if not self.gravity:
            return self
        other = copy.copy(self)
        other.gravity = False
        other.per_cycle = float(other.K0(np.array([self.cycle]))[0])
        return other


# -- the periodic solution -----------------------------------------------------------------------


@dataclass
class Extremes:
    omega_max: float
    omega_min: float
    phi_max: float
    phi_min: float

    def around(self, omega_mean: float) -> Extremes:
        """ω_min ≤ ω_m ≤ ω_max to the last ulp. The time mean Φ/∫dφ/ω lies between the
        extreme speeds, but where ω hardly varies (δ at rounding level: a pure flywheel) the
        three come from different sums and the mean may round an ulp outside: the nearer
        extreme then takes the mean's value (never the other way), and where ω is the same
        everywhere (ω_max = ω_min) both do, so that δ stays 0."""
        if self.omega_max == self.omega_min:
            return Extremes(omega_mean, omega_mean, self.phi_max, self.phi_min)
        return Extremes(max(self.omega_max, omega_mean), min(self.omega_min, omega_mean), self.phi_max, self.phi_min)


@dataclass
class Periodic:
    """A periodic solution: the functions E(φ), t(φ) and ω(φ) and the numbers that describe it."""

    omega_mean: float
    period: float  # t_Φ [s]
    extremes: Extremes
    energy_at: Callable[[np.ndarray], np.ndarray]  # E(φ) [J] at any angles in [0, Φ]
    time_at: Callable[[np.ndarray], np.ndarray]  # t(φ) [s]
    omega_at: Callable[[np.ndarray], np.ndarray]  # ω(φ) [rad/s]
    method: str = "shooting"
    nfev: int = 0  # the right-hand sides of every run of the search for E(0) (their nfev, summed)
    nit: int = 0  # of that search, Brent's method's iterations (the rest bracket the root)
    message: str = "E(0) = E(Φ) found by Brent's method over DOP853 runs; the machine runs"

    @property
    def delta(self) -> float:
        return (self.extremes.omega_max - self.extremes.omega_min) / self.omega_mean


def _extremes(omega_at: Callable[[np.ndarray], np.ndarray], cycle: float) -> Extremes:
    """ω_max and ω_min of the periodic ω(φ) and where they are.

    Why accurate: ω comes from the dense output, DOP853's own interpolant, as accurate as the
    integration (rtol 1e-11); the grid of :data:`EXTREMES_PER_RADIAN` samples only brackets
    each extremum, and SciPy's bounded Brent minimisation then locates it within ~1e-7 rad
    (its tolerance, √ε·|φ|), where a smooth extremum's value is off by ½|ω″|·(1e-7)², far below
    the integration's own error. At a kink of ω′ (a tabulated pressure's breakpoint) it ends
    on the kink itself. A refined value that is no better than the best sample is not taken."""
    optimize = scipy_optimize()
    count = math.ceil(EXTREMES_PER_RADIAN * cycle)
    grid = np.linspace(0.0, cycle, count + 1)[:-1]
    step = cycle / count
    omega = omega_at(grid)
    found = []
    for sign in (1.0, -1.0):  # the maximum, then the minimum
        best = int(np.argmax(sign * omega))
        value, angle = float(omega[best]), float(grid[best])

        def objective(phi: float, sign: float = sign) -> float:
            # ω is periodic: a bracket across φ = 0 is taken on the cycle's other end.
            return -sign * float(omega_at(np.array([phi % cycle]))[0])

        refined = optimize.minimize_scalar(
            objective, bounds=(angle - step, angle + step), method="bounded", options={"xatol": 1e-12 * cycle}
        )
        candidate = -sign * float(refined.fun)
        if sign * candidate > sign * value:
            value, angle = candidate, float(refined.x)
        found.append((value, angle % cycle))
    (omega_max, phi_max), (omega_min, phi_min) = found
    return Extremes(omega_max, omega_min, phi_max, phi_min)


class Shooting:
    """The periodic solution under any load and drive, ``applied`` = M_drive − M_load [N·m]
    (a vectorised f(φ, ω)): Y = E − K₀ integrated over the cycle with SciPy's ``solve_ivp``
    (DOP853) and E(0) found so that E(Φ) = E(0).

    ``floor`` [J]: a run whose E falls below it has stalled; stopping it there spares
    solve_ivp the crawl over the dead point (tiny steps), whose answer would be refused anyway.
    ``nfev``: the right-hand sides of every run so far (solve_ivp's ``nfev``, summed)."""

    def __init__(
        self, shaft: ShaftCycle, applied: Callable[[np.ndarray, np.ndarray], np.ndarray], rtol: float, floor: float
    ) -> None:
        self.shaft, self.applied, self.rtol, self.floor = shaft, applied, rtol, floor
        self.nfev = 0

    def _run(self, E0: float, dense: bool = False) -> Any:
        from scipy.integrate import solve_ivp  # type: ignore[import-untyped,unused-ignore]

        shaft, floor = self.shaft, self.floor
        J0 = float(shaft.J(np.array([0.0]))[0])

        def rates(phi: float, y: np.ndarray) -> np.ndarray:
            at = np.array([phi])
            energy = float(shaft.K0(at)[0]) + y[0]
            J = float(shaft.J(at)[0])
            omega = math.sqrt(2.0 * max(energy, floor) / J)
            return np.array([float(self.applied(at, np.array([omega]))[0]), 1.0 / omega])

        def stopped(phi: float, y: np.ndarray) -> float:
            return float(shaft.K0(np.array([phi]))[0]) + y[0] - floor

        stopped.terminal = True  # type: ignore[attr-defined]
        stopped.direction = -1  # type: ignore[attr-defined]
        run = solve_ivp(
            rates,
            (0.0, shaft.cycle),
            [E0, 0.0],
            method="DOP853",
            rtol=self.rtol,
            # absolute tolerances a thousandth of the relative one on E and on t_Φ ≈ Φ/ω(0)
            atol=[self.rtol * 1e-3 * E0, self.rtol * 1e-3 * shaft.cycle / math.sqrt(2.0 * E0 / J0)],
            events=stopped,
            dense_output=dense,
        )
        self.nfev += int(run.nfev)
        return run

    def residual(self, E0: float) -> float:
        """(E(Φ) − E(0))/E(0): positive when the cycle gains energy (E(0) too low)."""
        run = self._run(E0)
        if run.status == 1 or not run.success:  # stopped on the way: far too slow
            return 1.0
        return (self.shaft.per_cycle + float(run.y[0, -1]) - E0) / E0

    def solve(self, omega_guess: float, ratio: float) -> Periodic:
        """The periodic solution, from the speed ``omega_guess`` [rad/s]; Stall where it stops on
        the cycle or its ω_min falls below ``ratio``·ω_m."""
        optimize = scipy_optimize()
        shaft = self.shaft
        guess = 0.5 * float(shaft.J(np.array([0.0]))[0]) * omega_guess**2
        low, high = guess, guess
        if self.residual(guess) > 0:
            for _ in range(60):
                low, high = high, high * 1.5
                if self.residual(high) < 0:
                    break
            else:
                raise refused("load", "load: no periodic solution found (the machine keeps gaining energy)")
        else:
            for _ in range(60):
                high, low = low, low / 1.5
                if self.residual(low) > 0:
                    break
            else:
                raise refused("load", "load: no periodic solution found (the machine keeps losing energy)")
        E0, root = optimize.brentq(self.residual, low, high, xtol=1e-300, rtol=max(self.rtol, 1e-15), full_output=True)
        run = self._run(E0, dense=True)
        if run.status == 1:
            raise Stall(float(run.t_events[0][0]), "it stops on the cycle: there is no periodic solution")
        solution = run.sol

        def energy_at(phi: np.ndarray) -> np.ndarray:
            # The dense output takes a 1-D array of angles.
            return shaft.K0(phi) + solution(np.ravel(phi))[0].reshape(np.shape(phi))

        if abs(shaft.per_cycle + float(run.y[0, -1]) - E0) > 1e-6 * E0:
            # Brent's method closed in on the jump between runs that stop and runs that lose
            # energy: no periodic solution with a positive speed; it stops near its lowest E.
            grid = np.linspace(0.0, shaft.cycle, math.ceil(EXTREMES_PER_RADIAN * shaft.cycle) + 1)
            where = float(grid[int(np.argmin(energy_at(grid)))])
            raise Stall(where, "it stops on the cycle: there is no periodic solution")

        def time_at(phi: np.ndarray) -> np.ndarray:
            return solution(np.ravel(phi))[1].reshape(np.shape(phi))

        def omega_at(phi: np.ndarray) -> np.ndarray:
            return np.sqrt(2.0 * np.maximum(energy_at(phi), 0.0) / shaft.J(phi))

        period = float(run.y[1, -1])
        omega_mean = shaft.cycle / period
        extremes = _extremes(omega_at, shaft.cycle).around(omega_mean)
        counts = {"nfev": self.nfev, "nit": root.iterations}
        result = Periodic(omega_mean, period, extremes, energy_at, time_at, omega_at, **counts)
        if extremes.omega_min < ratio * omega_mean:
            raise Stall(extremes.phi_min, "its speed minimum falls below min_speed_ratio·ω_m")
        return result


def shoot(shaft: ShaftCycle, applied: Callable[[np.ndarray, Any], np.ndarray], ratio: float) -> Periodic:
    """The periodic solution under ``applied`` = M_drive − M_load [N·m] (f(φ, ω)), from the speed
    at which the torques balance; Stall where it stalls (``ratio``: min_speed_ratio)."""
    guess = quasi_static_speed(shaft, applied, "load")
    # Runs stop where ω falls to half of min_speed_ratio times the speed the torques balance at.
    floor = 0.5 * shaft.J_min * (0.5 * ratio * guess) ** 2
    return Shooting(shaft, applied, SHOOTING_RTOL, floor).solve(guess, ratio)


# -- the flywheel --------------------------------------------------------------------------------


@dataclass(frozen=True)
class Flywheel:
    """The numbers of a flywheel sized over shot steady states (FlywheelInertia's, ω_m in rad/s)."""

    shaft_inertia: float
    shaft_inertia_without_gravity: float
    textbook: float
    textbook_error: float
    omega_mean: float
    energy_swing: float


def flywheel_for(
    machine: Machine, applied: Callable[[np.ndarray, Any], np.ndarray], delta: float, gravity: bool, ratio: float
) -> Flywheel:
    """The shaft inertia [kg·m²] giving the shot steady state under ``applied`` = M_drive −
    M_load (f(φ, ω)) the coefficient of speed fluctuation ``delta``: the core's flywheel search
    (:func:`~multicrank._native.size_shaft_inertia`, every flywheel's) over :func:`shoot`, from
    the core's textbook estimate at the speed reached; with g = 0 beside it. A ``delta`` no shaft
    inertia gives is the core's MechanismError (its ``reach`` and ``closest`` set)."""
    shaft = ShaftCycle(machine, gravity)

    def estimate(omega: float) -> tuple[float, float, float]:
        """(ΔE [J], the textbook I_w, mean(J − I_w) [kg·m²]) at the constant speed ω [rad/s]: the
        core's, with the net applied torque at ω crossing as a table of φ."""
        table = sampled(lambda phi: applied(phi, omega), machine.cycle, "load", "torque", "N·m")
        swing, textbook = shaft.native.textbook_flywheel(delta, omega, drive=table, gravity=shaft.gravity)
        return swing, textbook, swing / (delta * omega**2) - textbook

    def delta_at(cycle: ShaftCycle) -> Callable[[float], float | None]:
        """δ of the shot steady state on a shaft of inertia I_w [kg·m²]; None where it stalls
        (to the search a δ above any target)."""

        def at(inertia: float) -> float | None:
            try:
                return shoot(cycle.with_inertia(inertia), applied, ratio).delta
            except Stall:
                return None

        return at

    try:  # the load fixes the speed: near the machine's own, to start from
        speed = shoot(shaft, applied, ratio).omega_mean
    except Stall:
        speed = quasi_static_speed(shaft, applied, "load")
    swing, textbook, rest = estimate(speed)
    start = textbook if textbook > 0 else swing / (delta * speed**2)
    if not start > 0:
        start = max(rest, machine.shaft_inertia)
    inertia = size_shaft_inertia(delta_at(shaft), rest, delta, start)
    # the speed reached with that flywheel; the estimate there
    speed = shoot(shaft.with_inertia(inertia), applied, ratio).omega_mean
    swing, textbook, _ = estimate(speed)
    if shaft.gravity:
        try:
            without = size_shaft_inertia(delta_at(shaft.without_gravity()), rest, delta, inertia)
        except MechanismError:  # only with gravity does the machine fluctuate that much
            without = math.nan
    else:
        without = inertia
    return Flywheel(inertia, without, textbook, (textbook - inertia) / inertia, speed, swing)
