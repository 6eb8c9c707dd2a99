"""The numerics of steady (periodic) running (docs/theory.md, "Steady running"): the energy method, the closed
form of the square-law load, shooting, and the time quadrature they share.

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
from .._shaft import omega_from_rpm, rpm_from_omega
from ._quadrature import CycleQuadrature
from ._shooting import Stall
from ._work import GasWork
from .loads import balance_torque

__all__ = ["Balance", "CycleTables", "Extremes", "Periodic", "Shooting", "SquareLaw", "Stall", "running_speed"]

# A graded panel may sit this close to a near-zero of E, in units of the distance d of the
# zero from the real axis (E ≈ E_i + ½E''(φ − φ_i)² vanishes at φ_i ± i·d): then the nodes of
# a 12-point Gauss rule on it are good to ~1e-12 (Bernstein ellipse ρ ≥ 3).
_GRADE_REACH = 1.5
# Geometric grading towards such a zero: each panel this many times wider than the last.
_GRADE_RATIO = 4.0


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


# -- the time quadrature ---------------------------------------------------------------------------


@dataclass
class Mesh:
    """The rule on which t = ∫ √(J/2E) dφ is taken, with E's and J's values on it.

    ``energy`` is E at the nodes and edges (or, for "balance", E − s: the part that does not
    depend on the unknown s).
    """

    rule: CycleQuadrature
    energy: np.ndarray
    energy_edges: np.ndarray
    J: np.ndarray
    J_edges: np.ndarray


@dataclass
class Dips:
    """The local minima of E(φ) on the cycle, each located exactly (the root of E′ between
    the samples beside the lowest one, E evaluated there): where 1/√E is sharply peaked.

    ``angle`` [rad], ``value`` E there [J] and ``bend`` |E″| there [J/rad²], one entry per
    minimum."""

    angle: np.ndarray
    value: np.ndarray
    bend: np.ndarray

    def lifted(self, by: float) -> Dips:
        """The same minima of E + ``by``."""
        return Dips(self.angle, self.value + by, self.bend)

    @property
    def reach(self) -> np.ndarray:
        """d = √(2E/|E″|) [rad]: how far E's nearest complex zero is from the real axis."""
        with np.errstate(divide="ignore"):
            bend = np.where(self.bend > 0, self.bend, 1.0)
            return np.where(self.bend > 0, np.sqrt(2.0 * np.maximum(self.value, 0.0) / bend), np.inf)


def local_minima(
    rule: CycleQuadrature,
    energy: np.ndarray,
    energy_edges: np.ndarray,
    curvature: np.ndarray,
    slope: Callable[[float], float],
    value: Callable[[float], float],
) -> Dips:
    """Every local minimum of the samples of E (nodes and edges, in angle order) located
    exactly: the root of the exact slope E′ (``slope``, any angle) between the samples
    beside it, by Brent's method to rounding, and E there (``value``); the sample itself
    where that is no lower (a minimum at a kink of E′).

    Where the time mesh is graded (:func:`grading`) the centre must be the minimum itself
    and d its own: graded towards a sample 6e-3 rad off a minimum of d = 3e-4 rad, the time
    of a cycle near a stall was 0.5 % off."""
    optimize = scipy_optimize()
    cycle = rule.cycle
    # Samples in angle order: edge 0, the nodes of panel 0, edge 1, … (the last edge is edge 0).
    samples = np.concatenate([energy_edges[:-1, None], energy], axis=1).ravel()
    angles = np.concatenate([rule.edges[:-1, None], rule.phi], axis=1).ravel()
    bend = np.concatenate([curvature[:, :1], curvature], axis=1).ravel()
    left, right = np.roll(samples, 1), np.roll(samples, -1)
    minima = np.flatnonzero((samples < left) & (samples <= right))
    found_angle, found_value, found_bend = [], [], []
    for i in minima:
        angle, lowest = float(angles[i]), float(samples[i])
        before, after = float(angles[i - 1]), float(angles[(i + 1) % angles.size])
        before = before - cycle if before > angle else before
        after = after + cycle if after < angle else after
        low, high = slope(before), slope(after)
        if low < 0 < high:
            # (A slope that jumps through zero at a kink brackets no root: Brent's method then
            # ends beside the jump, which is the minimum too.)
            root = float(
                optimize.brentq(
                    slope, before, after, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=400, disp=False
                )
            )
            there = value(root)
            if there < lowest:
                angle, lowest = root % cycle, there
        found_angle.append(angle)
        found_value.append(lowest)
        # E'' from the neighbours too: a minimum on an edge has the curvature of both panels.
        found_bend.append(max(abs(bend[i]), abs(bend[i - 1]), abs(bend[(i + 1) % bend.size])))
    return Dips(np.array(found_angle), np.array(found_value), np.array(found_bend))


def grading(rule: CycleQuadrature, dips: Dips) -> np.ndarray:
    """Panel edges to add so that ∫ √(J/2E) dφ stays spectrally accurate where E nearly
    vanishes: geometric panels (ratio 4) centred on every local minimum of E (``dips``,
    located exactly) whose complex zeros come closer to the real axis than 1.5 half-widths
    of the widest panel. Empty when the base rule is good as it is (a machine running with a
    small fluctuation)."""
    half = float(np.max(rule.half))
    edges: list[np.ndarray] = []
    for angle, d in zip(dips.angle, dips.reach, strict=True):
        if not d < _GRADE_REACH * half:
            continue
        # The innermost panel [φ_i − w, φ_i + w] holds the zero at ≥ 1.5 half-widths… by
        # taking w = d/3, and the widths then grow ×4 out to the base panels.
        width = max(d / (2 * _GRADE_REACH), 1e-12 * rule.cycle)
        steps = width * _GRADE_RATIO ** np.arange(0, math.ceil(math.log(2 * half / width, _GRADE_RATIO)) + 1)
        edges.append(np.mod(np.concatenate([angle - steps, angle + steps]), rule.cycle))
    if not edges:
        return np.zeros(0)
    return np.concatenate(edges)


def graded_mesh(cycle: CycleTables, extra: np.ndarray, energy_at: Callable[[np.ndarray], np.ndarray]) -> Mesh:
    """The base rule with ``extra`` edges; E (from ``energy_at``, any angles) and J evaluated there."""
    rule = cycle.rule.refined(extra)
    everywhere = np.concatenate([rule.phi.ravel(), rule.edges])
    energy = energy_at(everywhere)
    J, _ = cycle.J_at(everywhere)
    n = rule.phi.size
    return Mesh(rule, energy[:n].reshape(rule.phi.shape), energy[n:], J[:n].reshape(rule.phi.shape), J[n:])


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


def _finish(
    method: str,
    cycle: CycleTables,
    mesh: Mesh,
    energy_at: Callable[[np.ndarray], np.ndarray],
    load_torque: float,
    ratio: float,
) -> Periodic:
    """t_Φ, ω_m and the extremes of ω from E on the mesh; StallError-to-be when ω_min < ratio·ω_m."""
    rule = mesh.rule
    omega = _omega(mesh.energy, mesh.J)
    omega_edges = _omega(mesh.energy_edges, mesh.J_edges)
    if not (np.all(mesh.energy > 0) and np.all(mesh.energy_edges > 0)):
        samples = np.concatenate([mesh.energy.ravel(), mesh.energy_edges])
        where = np.concatenate([rule.phi.ravel(), rule.edges])[int(np.argmin(samples))]
        raise Stall(float(where), "its kinetic energy would reach zero on the cycle")
    inverse = 1.0 / omega
    period = rule.integral(inverse)
    omega_mean = rule.cycle / period

    def time_at(phi: np.ndarray) -> np.ndarray:
        # t(φ) = ∫₀^φ dφ/ω, each panel's interpolant of 1/ω integrated exactly.
        return rule.antiderivative(inverse)[2](phi)

    def omega_at(phi: np.ndarray) -> np.ndarray:
        J, _ = cycle.J_at(phi)
        return _omega(energy_at(phi), J)

    extremes = _extremes(rule, omega, omega_edges, omega_at).around(omega_mean)
    solution = Periodic(method, omega_mean, period, extremes, energy_at, time_at, omega_at, load_torque)
    if extremes.omega_min < ratio * omega_mean:
        raise Stall(extremes.phi_min, "its speed minimum falls below min_speed_ratio·ω_m")
    return solution


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


# -- "balance": the energy method ----------------------------------------------------------------


class _SpeedExcess:
    """s ↦ (ω_m(s)/ω_m)² − 1 = (t/t_Φ(s))² − 1 for E = s + K̃ on a mesh, memoised (Brent's
    method evaluates the bracket's ends again)."""

    def __init__(self, mesh: Mesh, target: float) -> None:
        self.weights, self.half_J = mesh.rule.weights.ravel(), 0.5 * mesh.J.ravel()
        self.lifted, self.target = mesh.energy.ravel(), target
        self.known: dict[float, float] = {}

    def __call__(self, s: float) -> float:
        if s not in self.known:
            period = float(self.weights @ np.sqrt(self.half_J / (s + self.lifted)))
            self.known[s] = (self.target / period) ** 2 - 1.0
        return self.known[s]


class Balance:
    """E(φ) = E₀ + K(φ), K = ∫₀^φ (M_gas + M_drive − M_load) dφ − [U(φ) − U(0)], and the
    E₀ that gives a mean speed: written E = s + K̃ with K̃ = K − min K ≥ 0 and s > 0 the
    energy left at the worst angle.

    Parameters
    ----------
    cycle : CycleTables
        The machine over its cycle.
    drive : ndarray, optional
        M_drive at the rule's nodes [N·m] (a speed-dependent one frozen at a speed).
    load_torque : float
        The constant load [N·m] that makes the work over a cycle zero: the "balance" of gas
        and drive (:func:`~multicrank.motion.loads.balance_torque`), 0 with ``gas=False``.
    gas : bool
        False leaves the gas torque out (gravity and the variation of J alone).
    """

    def __init__(self, cycle: CycleTables, drive: np.ndarray | None, load_torque: float, *, gas: bool = True) -> None:
        self.cycle, self.gas, self.load_torque = cycle, gas, load_torque
        rule = cycle.rule
        K_edges = -cycle.U_edges - self.load_torque * rule.edges
        K = -cycle.U - self.load_torque * rule.phi
        torque = cycle.gravity - self.load_torque
        if gas:
            K, K_edges = K + cycle.W, K_edges + cycle.W_edges
            torque = torque + cycle.gas
        self.drive = self._drive_slope = None
        if drive is not None:
            at_nodes, at_edges, self.drive = rule.antiderivative(drive)
            self._drive_slope = self.drive.derivative()
            K, K_edges, torque = K + at_nodes, K_edges + at_edges, torque + drive
        # min K over the samples; the exact minimum (between them) only where it matters,
        # when E nearly vanishes there (see mesh).
        lowest = int(np.argmin(K))
        self.K_min = float(K.flat[lowest])
        self.lowest = float(rule.phi.flat[lowest])
        if float(np.min(K_edges)) < self.K_min:
            self.K_min = float(np.min(K_edges))
            self.lowest = float(rule.edges[int(np.argmin(K_edges))])
        self._exact: Dips | None = None
        self.K, self.K_edges = K - self.K_min, K_edges - self.K_min
        self.swing = max(float(np.max(self.K)), float(np.max(self.K_edges)))  # ≈ max K − min K
        # K'' = (M + gravity)' at the nodes: where E = s + K̃ nearly vanishes, how sharply.
        self.curvature = rule.slope(torque)
        self.sharpest = float(np.max(np.abs(self.curvature)))

    def K_at(self, phi: np.ndarray) -> np.ndarray:
        """K(φ) − min K [J] at any angles in [0, Φ]."""
        K = -self.cycle.U_at(phi) - self.load_torque * phi - self.K_min
        if self.gas:
            K = K + self.cycle.work(phi)
        if self.drive is not None:
            K = K + self.drive(phi)
        return K

    def K_slope(self, phi: float) -> float:
        """K′ = M_gas + M_drive − M_load − U′ [N·m] at one angle (the drive as interpolated)."""
        at = np.array([phi % self.cycle.rule.cycle])
        torque = -self.load_torque
        if self.cycle.gravity_on:
            torque += float(self.cycle.machine.gravity_torque(at)[0])
        if self.gas:
            torque += float(self.cycle.machine.gas_torque(at)[0])
        if self._drive_slope is not None:
            torque += float(self._drive_slope(at)[0])
        return torque

    def _dips(self) -> Dips:
        """The local minima of K̃ located exactly (once; they do not depend on s), and min K
        with them: K̃ ≥ 0 also on graded nodes near it."""
        if self._exact is None:
            dips = local_minima(
                self.cycle.rule,
                self.K,
                self.K_edges,
                self.curvature,
                self.K_slope,
                lambda phi: float(self.K_at(np.array([phi % self.cycle.rule.cycle]))[0]),
            )
            deepest = int(np.argmin(dips.value))
            dip = float(dips.value[deepest])
            if dip < 0:
                self.K_min += dip
                self.K, self.K_edges = self.K - dip, self.K_edges - dip
                self.lowest = float(dips.angle[deepest])
                dips = dips.lifted(-dip)
            self._exact = dips
        return self._exact

    def mesh(self, s: float) -> Mesh:
        """The time mesh fit for E = s + K̃ (E − s on it), graded towards E's exact minima."""
        cycle = self.cycle
        half = float(np.max(cycle.rule.half))
        # The nearest complex zero of E is at least √(2s/max|K''|) from the real axis.
        if 2.0 * s >= self.sharpest * (_GRADE_REACH * half) ** 2:
            return Mesh(cycle.rule, self.K, self.K_edges, cycle.J, cycle.J_edges)
        extra = grading(cycle.rule, self._dips().lifted(s))
        if extra.size == 0:
            return Mesh(cycle.rule, self.K, self.K_edges, cycle.J, cycle.J_edges)
        return graded_mesh(cycle, extra, self.K_at)

    def solve(self, omega_mean: float, ratio: float) -> Periodic:
        """The periodic solution of mean speed ``omega_mean`` [rad/s] (Stall when it needs
        ω_min < ratio·ω_m): s by Brent's method on (ω_m(s)/ω_m)² − 1, which is nearly linear
        in s (exactly so for a pure flywheel), on a mesh graded for that s."""
        optimize = scipy_optimize()
        cycle = self.cycle
        target = cycle.rule.cycle / omega_mean
        # At s_low the speed at the worst angle is at most ratio·ω_m (J there is at least the
        # least J): if the mean speed there is already above the one asked for, the solution
        # has a smaller s, and stalls. Only that: a solution above s_low is judged by its own
        # ω_min (_finish), so that a speed just above the lowest that runs does run.
        J_min = min(float(np.min(cycle.J)), float(np.min(cycle.J_edges)))
        s_low = 0.5 * J_min * (ratio * omega_mean) ** 2
        # At s_high, ω² = 2(s + K̃)/J ≥ ω_m² everywhere: the mean speed is at least ω_m.
        J_max = max(float(np.max(cycle.J)), float(np.max(cycle.J_edges)))
        s_high = 0.5 * J_max * omega_mean**2 * 1.01
        mesh = self.mesh(s_high)
        s = s_high
        for _ in range(16):
            excess = _SpeedExcess(mesh, target)
            if excess(s_low) > 0:
                finer = self.mesh(s_low)
                if finer.rule.phi.size > mesh.rule.phi.size:
                    mesh = finer  # decide on a mesh that resolves the peak at s_low
                    continue
                raise Stall(self.lowest, "the mean speed asked for is below the lowest that runs")
            high = s_high
            while excess(high) < 0:
                high *= 2.0
            s = optimize.brentq(excess, s_low, high, xtol=1e-300, rtol=1e-15)
            K_min = self.K_min
            finer = self.mesh(s)
            # Where the mesh located min K between the samples just now, K̃ moved under the s
            # found: solve again on the mesh as it is now.
            if finer.rule.phi.size <= mesh.rule.phi.size and self.K_min == K_min:
                break
            mesh = finer
        lifted = Mesh(mesh.rule, mesh.energy + s, mesh.energy_edges + s, mesh.J, mesh.J_edges)
        return _finish("energy", cycle, lifted, lambda phi: s + self.K_at(phi), self.load_torque, ratio)

    def with_inertia(self, inertia: float) -> Balance:
        """The same torques on a shaft of inertia I_w = ``inertia`` (K does not depend on it)."""
        other = copy.copy(self)
        other.cycle = self.cycle.with_inertia(inertia)
        return other

    def energy_swing(self, omega_mean: float) -> float:
        """max − min [J] of the textbook turning-moment diagram's energy at the constant speed
        ω_m = ``omega_mean`` [rad/s], ∫(M_gas + M_drive − M_load − U′ − ½J′ω_m²) dφ =
        K − ½ω_m²(J − J(0)): the ΔE of the textbook flywheel estimate, both extremes located
        on the panels and evaluated exactly. The inertia torque is part of it: without it the
        estimate does not tend to the exact flywheel as δ → 0."""
        cycle, rule = self.cycle, self.cycle.rule
        half_square = 0.5 * omega_mean**2
        diagram = self.K - half_square * (cycle.J - cycle.inertia)
        diagram_edges = self.K_edges - half_square * (cycle.J_edges - cycle.inertia)

        def value(phi: float) -> float:
            at = np.array([phi % rule.cycle])
            return float(self.K_at(at)[0] - half_square * (cycle.J_at(at)[0][0] - cycle.inertia))

        def slope(phi: float) -> float:
            return self.K_slope(phi) - half_square * float(cycle.J_at(np.array([phi % rule.cycle]))[1][0])

        # Every local extremum located exactly (the root of the exact slope beside the samples):
        # the largest and the smallest of them.
        flat = np.zeros(rule.phi.shape)
        lows = local_minima(rule, diagram, diagram_edges, flat, slope, value)
        highs = local_minima(rule, -diagram, -diagram_edges, flat, lambda phi: -slope(phi), lambda phi: -value(phi))
        return -float(np.min(highs.value)) - float(np.min(lows.value))

    def at_margin(self, s: float) -> Periodic:
        """The periodic solution with E = s + K̃ (its mean speed follows), no stall check."""
        mesh = self.mesh(s)
        mesh = Mesh(mesh.rule, mesh.energy + s, mesh.energy_edges + s, mesh.J, mesh.J_edges)
        return _finish("energy", self.cycle, mesh, lambda phi: s + self.K_at(phi), self.load_torque, 0.0)

    def lowest_running_speed(self, ratio: float, above: float) -> float:
        """The lowest mean speed [rad/s] whose solution keeps ω_min ≥ ratio·ω_m (StallError's
        min_rpm): the root in s of ω_min/ω_m = ratio, which grows with s, rounded up to the
        running side (within ~1e-11 of the threshold; :func:`running_speed` then makes sure).
        ``above`` is an s known to stall."""
        optimize = scipy_optimize()
        # min K located first: K̃, and with it the function whose root is taken, is then the
        # same at every s.
        self._dips()

        def shortfall(log_s: float) -> float:
            solution = self.at_margin(math.exp(log_s))
            return solution.extremes.omega_min / solution.omega_mean - ratio

        low = math.log(max(above, 1e-300))
        high = math.log(max(self.swing, above, 1e-300)) + 1.0
        while shortfall(high) < 0:
            high += 2.0
        while shortfall(low) > 0:
            low -= 2.0
        log_s = optimize.brentq(shortfall, low, high, xtol=1e-12)
        # Brent's answer may lie either side of the root: step up to the running side.
        step = 1e-12
        while log_s < high and shortfall(log_s) < 0:
            log_s, step = min(log_s + step, high), 2 * step
        return self.at_margin(math.exp(log_s)).omega_mean


def running_speed(omega: float, runs: Callable[[float], bool]) -> float:
    """``omega`` [rad/s], nudged up by a few ulps until the steady state asked for at its
    rpm runs (``runs``: whether it does at a speed in rad/s, solved afresh as steady_state
    solves it): the threshold's root, the round trip through rpm and the solve's own root in s
    each round by ~1e-15, so that StallError's min_rpm is a speed that runs."""
    step, asked = 4 * float(np.finfo(float).eps), omega
    for _ in range(64):
        if runs(omega_from_rpm(rpm_from_omega(asked))):
            break
        asked, step = omega * (1 + step), 2 * step
    return asked


# -- the square-law load: the closed form ---------------------------------------------------------


class SquareLaw:
    """The periodic solution under a load c·ω² (docs/theory.md, "Steady running"), with M(φ) the gas torque plus a
    constant drive: dE/dφ = M − U' − (2c/J)E is linear in E, so

        E(φ) = e^{−A(φ)} [E₀ + ∫₀^φ e^{A}(M − U') dφ],   A(φ) = ∫₀^φ 2c/J dφ,
        E₀ = ∫₀^Φ e^{A}(M − U') dφ / (e^{A(Φ)} − 1).

    Both running integrals are spectral on the rule's panels and exact polynomials between
    the nodes, so E is known everywhere; the mean speed is a result.
    """

    def __init__(self, cycle: CycleTables, drive: float, coefficient: float) -> None:
        rule = cycle.rule
        self.cycle, self.coefficient, self.drive_torque = cycle, coefficient, drive
        rate, rate_edges, self.rate = rule.antiderivative(2.0 * coefficient / cycle.J)
        total = float(rate_edges[-1])
        if not total < 700.0:
            raise MechanismError(
                f"load: the square-law load damps {total:.3g} e-folds of kinetic energy per cycle; the closed "
                "form overflows (the machine would barely turn): use a larger shaft_inertia or a smaller load"
            )
        # ∫₀^φ e^{A} M_gas dφ by parts, = e^{A}W − ∫₀^φ A' e^{A} W dφ: W, the gas work, is
        # exact and smooth (the kinks of tabulated pressures are in M_gas, not in W).
        grow = np.exp(rate)
        forcing = grow * (drive + cycle.gravity - 2.0 * coefficient / cycle.J * cycle.W)
        at_nodes, at_edges, self.forcing = rule.antiderivative(forcing)
        B_cycle = math.exp(total) * cycle.W_edges[-1] + float(at_edges[-1])
        self.E0 = B_cycle / math.expm1(total)
        # E = e^{−A}(E₀ + e^{A}W + ∫…) = W + e^{−A}(E₀ + ∫…)
        self.energy = cycle.W + np.exp(-rate) * (self.E0 + at_nodes)
        self.energy_edges = cycle.W_edges + np.exp(-rate_edges) * (self.E0 + at_edges)
        # E' = M − U' − (2c/J)E at the nodes; E'' from it shows where E nearly vanishes.
        torque = cycle.gas + drive + cycle.gravity
        self.curvature = rule.slope(torque - 2.0 * coefficient * self.energy / cycle.J)

    def energy_at(self, phi: np.ndarray) -> np.ndarray:
        return self.cycle.work(phi) + np.exp(-self.rate(phi)) * (self.E0 + self.forcing(phi))

    def energy_slope(self, phi: float) -> float:
        """E′ = M_gas + M_drive − U′ − (2c/J)E [N·m] at one angle, exactly."""
        at = np.array([phi % self.cycle.rule.cycle])
        machine = self.cycle.machine
        torque = float(machine.gas_torque(at)[0]) + self.drive_torque
        if self.cycle.gravity_on:
            torque += float(machine.gravity_torque(at)[0])
        J, _ = self.cycle.J_at(at)
        return torque - 2.0 * self.coefficient * float(self.energy_at(at)[0]) / float(J[0])

    def solve(self, ratio: float) -> Periodic:
        cycle = self.cycle
        rule = cycle.rule
        if not (np.all(self.energy > 0) and np.all(self.energy_edges > 0)):
            where = rule.extremum(self.energy, self.energy_edges, largest=False)
            raise Stall(where, "the kinetic energy of the periodic solution would be negative")
        dips = local_minima(
            rule,
            self.energy,
            self.energy_edges,
            self.curvature,
            self.energy_slope,
            lambda phi: float(self.energy_at(np.array([phi % rule.cycle]))[0]),
        )
        extra = grading(rule, dips)
        if extra.size:
            mesh = graded_mesh(cycle, extra, self.energy_at)
        else:
            mesh = Mesh(rule, self.energy, self.energy_edges, cycle.J, cycle.J_edges)
        load = rule.mean(2.0 * self.coefficient * self.energy / cycle.J)
        return _finish("closed form", cycle, mesh, self.energy_at, load, ratio)


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
