"""The numerics of steady (periodic) running that stay in Python (docs/theory.md, "Steady
running"): shooting for loads that depend on the speed, on the machine's cycle tables. The
energy method ("balance" beside any drive) and the closed form of the square-law load are the
Rust core's alone (:class:`~multicrank._native.MotionMachine`).

The public face is :mod:`multicrank.motion`; this module takes validated inputs and returns
plain numbers and callables. Every quantity of the machine (J, J', U, the gas and gravity
torques) comes from :class:`~multicrank.machine.Machine` — the Rust core; here are only the
integrals over the cycle and the root finds.

Notation: E(φ) = ½ J(φ) ω² [J] is the kinetic energy, K(φ) = ∫₀^φ (M − U') dφ the work of the
applied torques M and of gravity from φ = 0, and the time over the cycle is
t_Φ = ∫₀^Φ dφ/ω = ∫₀^Φ √(J/2E) dφ.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._native import MechanismError
from ._quadrature import CycleQuadrature
from ._shooting import Stall
from ._work import GasWork
from .loads import balance_torque

__all__ = ["CycleTables", "Extremes", "Periodic", "Shooting", "Stall"]


def scipy_optimize() -> Any:
    import scipy.optimize  # type: ignore[import-untyped,unused-ignore]

    return scipy.optimize


class CycleTables:
    """The machine's quantities over one working cycle (J, J′, U, the gas work W and the
    gravity torque), tabulated at the nodes and edges of a rule.

    J(φ) = I_w + (the machine's J − its own shaft_inertia), with I_w = ``inertia``, so that
    :meth:`with_inertia` (the flywheel search) changes I_w without a call to the core.

    Parameters
    ----------
    machine : Machine
        As solved (g = 0 for a run without gravity).
    rule : CycleQuadrature
        The panels: cut at the torques' kinks.
    work : GasWork, optional
        The machine's gas work, when already made (it depends on neither g nor I_w).
    """

    def __init__(
        self, machine: Any, rule: CycleQuadrature, *, gravity: bool = True, work: GasWork | None = None
    ) -> None:
        self.machine, self.rule = machine, rule
        self.gravity_on = gravity and machine.g != 0
        self.inertia = machine.shaft_inertia
        self.nodes = rule.phi.size
        everywhere = np.concatenate([rule.phi.ravel(), rule.edges])
        self.work = GasWork(machine) if work is None else work
        gas = self.work(everywhere)
        self.W, self.W_edges = gas[: self.nodes].reshape(rule.phi.shape), gas[self.nodes :]
        self._gas: np.ndarray | None = None
        rest, slope = machine.reduced_inertia(everywhere)
        self._rest = rest - machine.shaft_inertia  # J − I_w: the rods' and pistons' share
        self.dJ = slope[: self.nodes].reshape(rule.phi.shape)
        if self.gravity_on:
            energy = machine.potential_energy(np.concatenate([[0.0], everywhere]))
            self.U0 = float(energy[0])
            self._U = energy[1:] - self.U0
            self.gravity = machine.gravity_torque(rule.phi)
        else:
            self.U0, self._U = 0.0, np.zeros(everywhere.size)
            self.gravity = np.zeros(rule.phi.shape)

    @property
    def gas(self) -> np.ndarray:
        """M_gas at the nodes [N·m], the slope of the interpolant of W: an estimate, for the
        curvatures that decide where the time quadrature is graded (not for results)."""
        if self._gas is None:
            self._gas = self.rule.slope(self.W)
        return self._gas

    # -- at the rule's nodes (shape of rule.phi) and edges (P + 1) ----------------------------
    @property
    def J(self) -> np.ndarray:
        return self.inertia + self._rest[: self.nodes].reshape(self.rule.phi.shape)

    @property
    def J_edges(self) -> np.ndarray:
        return self.inertia + self._rest[self.nodes :]

    @property
    def U(self) -> np.ndarray:
        """U(φ) − U(0) [J] at the nodes."""
        return self._U[: self.nodes].reshape(self.rule.phi.shape)

    @property
    def U_edges(self) -> np.ndarray:
        return self._U[self.nodes :]

    @property
    def mean_rest_inertia(self) -> float:
        """(1/Φ)∫(J − I_w) dφ [kg·m²]: the rods' and pistons' mean share of J."""
        return self.rule.mean(self._rest[: self.nodes].reshape(self.rule.phi.shape))

    # -- anywhere ------------------------------------------------------------------------------
    def J_at(self, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(J, J') at any angles [rad]."""
        J, slope = self.machine.reduced_inertia(phi)
        return J - self.machine.shaft_inertia + self.inertia, slope

    def U_at(self, phi: np.ndarray) -> np.ndarray:
        """U(φ) − U(0) [J] at any angles."""
        if not self.gravity_on:
            return np.zeros(np.shape(phi))
        return self.machine.potential_energy(phi) - self.U0

    # -- variants ------------------------------------------------------------------------------
    def with_inertia(self, inertia: float) -> CycleTables:
        """The same machine with shaft inertia I_w = ``inertia`` (no call to the core)."""
        other = copy.copy(self)
        other.inertia = float(inertia)
        return other

    def without_gravity(self) -> CycleTables:
        """The same machine with g = 0 (the gas work is kept: it does not depend on g)."""
        if not self.gravity_on:
            return self
        other = copy.copy(self)
        other.gravity_on = False
        other.U0, other._U, other.gravity = 0.0, np.zeros(self._U.size), np.zeros(self.rule.phi.shape)
        return other

    def resolved(self) -> bool:
        """Whether the panels resolve J and U: the last two Legendre coefficients of every
        panel's interpolant (degree 11) below 1e-7 of the function's range, or of rounding.

        Where they are, the 12-point Gauss rule (exact to degree 23) integrates to ~1e-14, and the
        interpolants locate extrema to ~1e-7 rad, whose values are then taken exactly."""
        for values in (self._rest[: self.nodes], self._U[: self.nodes]):
            values = values.reshape(self.rule.phi.shape)
            spread = float(np.ptp(values))
            if spread == 0:
                continue
            tail = float(np.max(np.abs(self.rule.coefficients(values)[:, -2:])))
            if tail > max(1e-7 * spread, 1e-14 * float(np.max(np.abs(values)))):
                return False
        return True


# -- results -----------------------------------------------------------------------------------


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
    """A periodic solution: the functions E(φ) and t(φ) and the numbers that describe it."""

    method: str
    omega_mean: float
    period: float  # t_Φ [s]
    extremes: Extremes
    energy_at: Callable[[np.ndarray], np.ndarray]  # E(φ) [J] at any angles in [0, Φ]
    time_at: Callable[[np.ndarray], np.ndarray]  # t(φ) [s]
    omega_at: Callable[[np.ndarray], np.ndarray]  # ω(φ) [rad/s]
    load_torque: float  # the constant load of "balance", else the load's cycle mean [N·m]

    @property
    def delta(self) -> float:
        return (self.extremes.omega_max - self.extremes.omega_min) / self.omega_mean


def _omega(energy: np.ndarray, J: np.ndarray) -> np.ndarray:
    return np.sqrt(2.0 * np.maximum(energy, 0.0) / J)


def _extremes(
    rule: CycleQuadrature, omega: np.ndarray, omega_edges: np.ndarray, omega_at: Callable[[np.ndarray], np.ndarray]
) -> Extremes:
    """ω_max, ω_min located on the panels' interpolants, then evaluated exactly there."""
    where = np.array(
        [rule.extremum(omega, omega_edges, largest=True), rule.extremum(omega, omega_edges, largest=False)]
    )
    exact = omega_at(where)
    # The located angle is never taken when its exact value is worse than the best sample's.
    top, bottom = float(np.max(omega)), float(np.min(omega))
    top_at = float(rule.phi.flat[int(np.argmax(omega))])
    bottom_at = float(rule.phi.flat[int(np.argmin(omega))])
    omega_max, phi_max = (float(exact[0]), float(where[0])) if exact[0] >= top else (top, top_at)
    omega_min, phi_min = (float(exact[1]), float(where[1])) if exact[1] <= bottom else (bottom, bottom_at)
    return Extremes(omega_max, omega_min, phi_max % rule.cycle, phi_min % rule.cycle)


# -- any other load: shooting ----------------------------------------------------------------------


def mean_torque(cycle: CycleTables, applied: Callable[[np.ndarray, Any], np.ndarray], omega: float) -> float:
    """(1/Φ)∫(M_gas + M_drive − M_load) dφ [N·m] at a constant speed ω [rad/s]: what a
    "balance" load would take beside them."""
    return balance_torque(cycle.machine, applied, omega, cycle.rule, work=cycle.work)


def quasi_static_speed(cycle: CycleTables, applied: Callable[[np.ndarray, Any], np.ndarray], name: str) -> float:
    """The constant speed [rad/s] at which the torques balance over a cycle: the start of the
    shooting. MechanismError naming ``name`` when there is none (the load never takes what
    the gas and the drive give, or the drive's mean is not positive)."""
    optimize = scipy_optimize()
    low, high = 1e-6, 1.0
    if not mean_torque(cycle, applied, low) > 0:
        raise MechanismError(
            f"{name}: the mean torque of gas and drive does not exceed the load's even at rest "
            f"({mean_torque(cycle, applied, low):.6g} N·m): the machine cannot run forward"
        )
    while mean_torque(cycle, applied, high) > 0:
        high *= 4.0
        if high > 1e9:
            raise MechanismError(
                f"{name}: the load never balances the mean torque of gas and drive (up to 10⁹ rad/s): "
                "no periodic steady state; a constant load needs load='balance' and rpm"
            )
    return float(optimize.brentq(lambda w: mean_torque(cycle, applied, w), low, high, rtol=1e-12))


class Shooting:
    """The periodic solution under any load and drive: E(φ) integrated over the cycle with
    SciPy's ``solve_ivp`` (DOP853) in the angle domain and E(0) found so that E(Φ) = E(0).

    The equation of motion J φ̈ + ½ J' φ̇² = M − U' is, with E = ½ J ω² as the unknown and φ as
    the variable, dE/dφ = M(φ, ω) − U'(φ) (the same as dω/dφ = [M − U' − ½J'ω²]/(Jω), without
    its division by ω). The part of M that depends on φ alone (gas, gravity) is integrated
    once on the panels, K₀(φ) = ∫₀^φ M_gas dφ − ΔU; the ODE carries only Y = E − K₀ with
    dY/dφ = M_drive(φ, ω) − M_load(φ, ω), and the time t with dt/dφ = 1/ω.
    """

    def __init__(
        self, cycle: CycleTables, applied: Callable[[np.ndarray, np.ndarray], np.ndarray], rtol: float, floor: float
    ) -> None:
        self.cycle, self.applied, self.rtol = cycle, applied, rtol
        self.K_cycle = cycle.work.per_cycle  # K₀(Φ): U(Φ) = U(0)
        # A run whose E falls below this [J] has stalled: stopping it there spares solve_ivp the
        # crawl over the dead point (tiny steps), whose answer would be refused anyway.
        self.floor = floor

    def K0(self, phi: np.ndarray) -> np.ndarray:
        return self.cycle.work(phi) - self.cycle.U_at(phi)

    def _run(self, E0: float, dense: bool = False) -> Any:
        from scipy.integrate import solve_ivp  # type: ignore[import-untyped,unused-ignore]

        cycle = self.cycle
        floor = self.floor
        J0 = float(cycle.J_at(np.array([0.0]))[0][0])

        def rates(phi: float, y: np.ndarray) -> np.ndarray:
            at = np.array([phi])
            energy = float(self.K0(at)[0]) + y[0]
            J = float(cycle.J_at(at)[0][0])
            omega = math.sqrt(2.0 * max(energy, floor) / J)
            return np.array([float(self.applied(at, np.array([omega]))[0]), 1.0 / omega])

        def stopped(phi: float, y: np.ndarray) -> float:
            return float(self.K0(np.array([phi]))[0]) + y[0] - floor

        stopped.terminal = True  # type: ignore[attr-defined]
        stopped.direction = -1  # type: ignore[attr-defined]
        return solve_ivp(
            rates,
            (0.0, cycle.rule.cycle),
            [E0, 0.0],
            method="DOP853",
            rtol=self.rtol,
            # absolute tolerances a thousandth of the relative one on E and on t_Φ ≈ Φ/ω(0)
            atol=[self.rtol * 1e-3 * E0, self.rtol * 1e-3 * cycle.rule.cycle / math.sqrt(2.0 * E0 / J0)],
            events=stopped,
            dense_output=dense,
        )

    def residual(self, E0: float) -> float:
        """(E(Φ) − E(0))/E(0): positive when the cycle gains energy (E(0) too low)."""
        run = self._run(E0)
        if run.status == 1 or not run.success:  # stopped on the way: far too slow
            return 1.0
        return (self.K_cycle + float(run.y[0, -1]) - E0) / E0

    def solve(self, omega_guess: float, ratio: float) -> Periodic:
        optimize = scipy_optimize()
        cycle = self.cycle
        J0 = float(cycle.J_at(np.array([0.0]))[0][0])
        guess = 0.5 * J0 * omega_guess**2
        low, high = guess, guess
        if self.residual(guess) > 0:
            for _ in range(60):
                low, high = high, high * 1.5
                if self.residual(high) < 0:
                    break
            else:
                raise MechanismError("load: no periodic solution found (the machine keeps gaining energy)")
        else:
            for _ in range(60):
                high, low = low, low / 1.5
                if self.residual(low) > 0:
                    break
            else:
                raise MechanismError("load: no periodic solution found (the machine keeps losing energy)")
        E0 = optimize.brentq(self.residual, low, high, xtol=1e-300, rtol=max(self.rtol, 1e-15))
        run = self._run(E0, dense=True)
        if run.status == 1:
            raise Stall(float(run.t_events[0][0]), "it stops on the cycle: there is no periodic solution")
        if abs(self.K_cycle + float(run.y[0, -1]) - E0) > 1e-6 * E0:
            # Brent's method closed in on the jump between runs that stop and runs that lose
            # energy: no periodic solution with a positive speed.
            where = float(np.argmin(self.K0(cycle.rule.phi.ravel()) + run.sol(cycle.rule.phi.ravel())[0]))
            raise Stall(float(cycle.rule.phi.flat[int(where)]), "it stops on the cycle: there is no periodic solution")
        solution = run.sol
        period = float(run.y[1, -1])
        rule = cycle.rule
        omega_mean = rule.cycle / period

        def energy_at(phi: np.ndarray) -> np.ndarray:
            # The dense output takes a 1-D array of angles.
            return self.K0(phi) + solution(np.ravel(phi))[0].reshape(np.shape(phi))

        def time_at(phi: np.ndarray) -> np.ndarray:
            return solution(np.ravel(phi))[1].reshape(np.shape(phi))

        def omega_at(phi: np.ndarray) -> np.ndarray:
            J, _ = cycle.J_at(phi)
            return _omega(energy_at(phi), J)

        everywhere = np.concatenate([rule.phi.ravel(), rule.edges])
        omega = omega_at(everywhere)
        n = rule.phi.size
        extremes = _extremes(rule, omega[:n].reshape(rule.phi.shape), omega[n:], omega_at).around(omega_mean)
        # The load's own mean is the caller's to take: here drive and load are one torque.
        result = Periodic("shooting", omega_mean, period, extremes, energy_at, time_at, omega_at, math.nan)
        if extremes.omega_min < ratio * omega_mean:
            raise Stall(extremes.phi_min, "its speed minimum falls below min_speed_ratio·ω_m")
        return result
