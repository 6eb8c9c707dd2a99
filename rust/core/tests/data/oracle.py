"""An independent reference for the steady running of a multi-crank machine.

It shares no code and no formula with multicrank (neither its Rust core nor its Python
package): only a machine's *parameters* are read (masses, lengths, inertias, phases,
inclinations, bores and each indicator diagram's table of angles, pressures and interpolation
kind), and everything is computed from them here, by other means than the library's:

* **Kinematics by planar geometry.** Each slider-crank unit is placed in the plane: the crank
  pin at r·(cos(ψ+γ), sin(ψ+γ)) with ψ = φ + α, the piston pin on the cylinder axis at the
  distance r·cos ψ + √(l² − r² sin² ψ) from the shaft (the triangle shaft–crank pin–piston pin),
  the rod's centre of gravity on the segment between them at z_k from the piston pin, crank web
  and counterweight on the crank line. Velocities are exact derivatives taken by the
  **complex step** (d/dφ f = Im f(φ + ih)/h, no difference quotient, no rounding loss), the
  rod's angular speed from the cross product of the rod vector and its derivative. The library
  writes s(ψ), s'(ψ), β' in closed form and reduces the rod to two masses; none of that here.
* **Reduced inertia** J(φ) = I_w + Σ [m_t |v_piston|² + m_k |v_rod cg|² + I_k ω_rod²]/φ̇²
  (the rigid rod, not two masses), **gravity** from U = g Σ m·height (its torque −dU/dφ by the
  complex step), the **gas torque** by virtual work, F·ds/dφ with s the piston's travel from
  its outer dead centre and F = p·A − p_crank end·(A − πd²/4).
* **Pressures interpolated independently** with SciPy from each diagram's own table and kind:
  ``CubicSpline(bc_type="periodic")`` for "periodic-cubic", ``make_interp_spline(k=1)`` for
  "linear", and for "pchip" ``PchipInterpolator`` on the table laid out over three cycles (its
  slopes at the table's ends then come from the neighbours a cycle away).
* **The periodic steady state** of d(½Jω²)/dφ = M(φ) − dU/dφ (load "balance": the cycle mean
  of the gas torque is the load): the energy E(φ) = s + K(φ) − min K with K the work of gas and
  load minus U; s > 0 is the one number that makes the cycle's time ∫dφ/ω = Φ/ω_m, found by
  ``scipy.optimize.brentq`` in log s. The quadratures are Gauss–Legendre
  (``scipy.special.roots_legendre``) on the panels between the kinks of every pressure table
  (each table breakpoint seen from the shaft angle), the work at a point by a second
  Gauss–Legendre rule from its panel's start, and the time integral **adaptive** (a panel is
  halved until the rule on it and on its halves agree to 1e-14), which near stall follows the
  narrow dip of ω. The speed extremes are the samples' best, refined by
  ``scipy.optimize.minimize_scalar`` (bounded Brent) on the exact ω(φ).
* **The square-law load** c·ω² (beside a constant drive): the linear equation
  dE/dφ = M − U' − (2c/J)E solved panel by panel by its propagator, E(b) = a·E(a) + b', and the
  periodic E(0) from the cycle's product of them.
* **The flywheel** for a target δ by ``scipy.optimize.brentq`` on log I_w of δ(I_w) − δ, and
  the lowest running speed (ω_min/ω_m = 1e-3) by ``brentq`` on log s.

Accuracy: every panel's rules are exact to rounding for the tables' piecewise cubics times
smooth geometry on panels a few milliradians wide (checked by running everything with two rule
orders: make_motion_fixtures.py records the two runs' agreement in the fixtures); ω_m, t_Φ,
the load and ω(φ) are good to ~1e-13 relative, the extremes to ~1e-14, δ (a difference of
nearly equal speeds) to ~1e-13/δ, and near stall ω_min to ~1e-9 (it rests on s ≪ E, where
K − min K loses digits).

Used by make_motion_fixtures.py (the Rust core's fixtures) and tests/machine/test_native.py.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy import interpolate, optimize, special

#: The complex step [rad]: f'(φ) = Im f(φ + ih)/h to rounding.
STEP = 1e-30
#: Gauss–Legendre points per panel (the accuracy check runs with GL_CHECK).
GL_POINTS = 12
GL_CHECK = 20
#: Points of the rule for ∫2c/J inside a panel (the square law): J is analytic and varies by
#: ~1e-2 over a panel, so 8 points are exact to rounding.
SMOOTH_POINTS = 8
#: The adaptive time quadrature accepts a panel where its rule and its halves' agree to this.
ADAPTIVE_RTOL = 1e-14


@dataclass(frozen=True)
class Table:
    """An indicator diagram's table: cycle angles [rad] (first repeated one cycle on), gauge
    pressures [Pa] and the interpolation kind ("periodic-cubic", "pchip" or "linear")."""

    angle: np.ndarray
    pressure: np.ndarray
    kind: str
    cycle: float
    poly: interpolate.PPoly = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        a = np.asarray(self.angle, dtype=float)
        p = np.asarray(self.pressure, dtype=float)
        object.__setattr__(self, "angle", a)
        object.__setattr__(self, "pressure", p)
        if self.kind == "periodic-cubic":
            poly = interpolate.CubicSpline(a, p, bc_type="periodic")
        elif self.kind == "linear":
            poly = interpolate.PPoly.from_spline(interpolate.make_interp_spline(a, p, k=1))
            poly = interpolate.PPoly(poly.c[:, 1:-1] if poly.c.shape[1] > a.size - 1 else poly.c, a)
        elif self.kind == "pchip":
            n = a.size - 1
            wide_a = np.concatenate((a[:-1] - self.cycle, a[:-1], a[:-1] + self.cycle, [a[-1] + self.cycle]))
            wide_p = np.concatenate((p[:-1], p[:-1], p[:-1], [p[-1]]))
            wide = interpolate.PchipInterpolator(wide_a, wide_p)
            poly = interpolate.PPoly(np.array(wide.c[:, n : 2 * n]), a)
        else:
            raise ValueError(f"unknown kind {self.kind!r}")
        object.__setattr__(self, "poly", poly)

    def __call__(self, theta: np.ndarray) -> np.ndarray:
        a0 = self.angle[0]
        return self.poly(a0 + np.mod(theta - a0, self.cycle))


@dataclass(frozen=True)
class Unit:
    """One slider-crank unit's parameters (SI, angles in rad), as the machine declares them."""

    crank_radius: float
    rod_length: float
    piston_mass: float
    rod_mass: float
    rod_cg: float
    rod_inertia: float
    crank_mass: float
    crank_cg_radius: float
    counterweight_mass: float
    counterweight_radius: float
    phase: float
    inclination: float
    bore: float = 0.0
    piston_rod_diameter: float = 0.0
    head: Table | None = None
    crank_end: Table | None = None

    def points(self, phi):
        """Plane coordinates (x, y) of the piston pin, the rod's centre of gravity and the
        crank pin at shaft angle φ (real or complex), and the piston pin's distance from the
        shaft along the cylinder axis."""
        r, rod, z = self.crank_radius, self.rod_length, self.rod_cg
        psi = phi + self.phase
        along, across = r * np.cos(psi), r * np.sin(psi)  # the crank pin in the axis' frame
        distance = along + np.sqrt(rod * rod - across * across)  # the piston pin on the axis
        c, s = math.cos(self.inclination), math.sin(self.inclination)
        pin = (along * c - across * s, along * s + across * c)
        piston = (distance * c, distance * s)
        cg = tuple(p + z / rod * (q - p) for p, q in zip(piston, pin, strict=True))
        return piston, cg, pin, distance

    def heights(self, phi):
        """Σ m·height of the unit's moving parts [kg·m] (crank web and counterweight by their
        first moments), at φ real or complex."""
        piston, cg, _, _ = self.points(phi)
        crank_line = np.sin(phi + self.phase + self.inclination)
        first = self.crank_mass * self.crank_cg_radius - self.counterweight_mass * self.counterweight_radius
        return self.piston_mass * piston[1] + self.rod_mass * cg[1] + first * crank_line


def _times_at(edges: np.ndarray, pieces: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """t(φ) at `angles`, each an edge of the panels whose times are `pieces`."""
    ends = np.concatenate(([0.0], np.cumsum(pieces)))
    i = np.clip(np.searchsorted(edges, angles), 1, edges.size - 1)
    i -= np.abs(edges[i - 1] - angles) < np.abs(edges[i] - angles)
    if np.any(np.abs(edges[i] - angles) > 1e-12 * edges[-1]):
        raise ValueError("an angle asked for is not an edge of the panels (pass it to Cycle)")
    return ends[i]


def _step(phi):
    return np.asarray(phi, dtype=float) + 1j * STEP


def _derivative(values) -> np.ndarray:
    return np.imag(values) / STEP


class Machine:
    """A machine: its units, shaft inertia I_w [kg·m²], strokes (2 or 4) and g [m/s²]."""

    def __init__(self, units: Sequence[Unit], shaft_inertia: float, strokes: int, g: float) -> None:
        self.units = list(units)
        self.shaft_inertia = float(shaft_inertia)
        self.cycle = math.pi * strokes
        self.g = float(g)

    def engine_inertia(self, phi) -> np.ndarray:
        """J(φ) − I_w [kg·m²]: Σ m v² + I_k ω_rod² per unit shaft speed²."""
        z = _step(phi)
        total = np.zeros(np.shape(phi))
        for u in self.units:
            piston, cg, pin, _ = u.points(z)
            speed2 = lambda p: _derivative(p[0]) ** 2 + _derivative(p[1]) ** 2  # noqa: E731
            rod = (np.real(pin[0] - piston[0]), np.real(pin[1] - piston[1]))
            rate = (_derivative(pin[0] - piston[0]), _derivative(pin[1] - piston[1]))
            turning = (rod[0] * rate[1] - rod[1] * rate[0]) / (rod[0] ** 2 + rod[1] ** 2)
            total += u.piston_mass * speed2(piston) + u.rod_mass * speed2(cg) + u.rod_inertia * turning**2
        return total

    def potential(self, phi) -> np.ndarray:
        """U(φ) = g Σ m·height [J] (any zero)."""
        return self.g * sum(np.real(u.heights(np.asarray(phi, dtype=float) + 0j)) for u in self.units)

    def gravity_torque(self, phi) -> np.ndarray:
        """−dU/dφ [N·m]."""
        z = _step(phi)
        return -self.g * sum(_derivative(u.heights(z)) for u in self.units)

    def gas_torque(self, phi) -> np.ndarray:
        """Σ F·ds/dφ [N·m], s the travel from outer dead centre (toward the shaft)."""
        phi = np.asarray(phi, dtype=float)
        total = np.zeros(phi.shape)
        for u in self.units:
            if u.head is None and u.crank_end is None:
                continue
            travel_rate = -_derivative(u.points(_step(phi))[3])
            theta = phi + u.phase
            area = math.pi * u.bore**2 / 4
            force = np.zeros(phi.shape)
            if u.head is not None:
                force += u.head(theta) * area
            if u.crank_end is not None:
                force -= u.crank_end(theta) * (area - math.pi * u.piston_rod_diameter**2 / 4)
            total += force * travel_rate
        return total

    def kinks(self) -> np.ndarray:
        """Shaft angles in [0, Φ) where a pressure table has a breakpoint."""
        found = [np.zeros(1)]
        for u in self.units:
            for table in (u.head, u.crank_end):
                if table is not None:
                    found.append(np.mod(table.angle - u.phase, self.cycle))
        return np.concatenate(found)


class Cycle:
    """The angle-domain tables of a machine over one cycle: panels between every kink and
    every angle asked for, Gauss–Legendre rules on them, the work W(φ) = ∫₀^φ (M_gas + M_d)
    of gas and drive, U(φ) − U(0) and J(φ) − I_w at any angle.

    ``drive``: None, or a driving torque M_d(φ) [N·m] as a SciPy ``PPoly`` over [0, Φ] (its
    breakpoints are kinks: the rule integrates it on panels between them, by Gauss–Legendre
    like the gas — not by its antiderivative)."""

    def __init__(self, machine: Machine, angles=(), points: int | None = None, drive=None) -> None:
        self.machine = machine
        self.drive = drive
        points = GL_POINTS if points is None else points
        cycle = machine.cycle
        kinks = machine.kinks() if drive is None else np.concatenate((machine.kinks(), drive.x))
        edges = np.unique(np.concatenate((kinks, np.asarray(angles, float), [0.0, cycle])))
        edges = edges[(edges >= 0) & (edges <= cycle)]
        keep = np.concatenate(([True], np.diff(edges) > 1e-12 * cycle))
        edges = edges[keep]
        edges[-1] = cycle
        self.edges = edges
        self.x, self.w = special.roots_legendre(points)
        lo, hi = edges[:-1], edges[1:]
        work = self._rule(self.driving_torque, lo, hi)
        self.work_start = np.concatenate(([0.0], np.cumsum(work)))
        self.u0 = float(machine.potential(0.0))

    @property
    def cycle(self) -> float:
        return self.machine.cycle

    def _rule(self, f, lo, hi) -> np.ndarray:
        """∫_lo^hi f by the Gauss–Legendre rule, per pair (lo, hi)."""
        half = (hi - lo) / 2
        nodes = (lo + hi)[..., None] / 2 + half[..., None] * self.x
        return half * (f(nodes.ravel()).reshape(nodes.shape) @ self.w)

    def driving_torque(self, phi) -> np.ndarray:
        """M_gas + M_d [N·m] at φ in [0, Φ]."""
        torque = self.machine.gas_torque(phi)
        return torque if self.drive is None else torque + self.drive(phi)

    def panel(self, phi) -> np.ndarray:
        return np.clip(np.searchsorted(self.edges, phi, side="right") - 1, 0, self.edges.size - 2)

    def work(self, phi) -> np.ndarray:
        """W(φ) = ∫₀^φ (M_gas + M_d) dφ [J] at φ in [0, Φ]."""
        phi = np.asarray(phi, dtype=float)
        i = self.panel(phi)
        start = self.edges[i]
        return self.work_start[i] + self._rule(self.driving_torque, start, phi)

    @property
    def mean_gas_torque(self) -> float:
        """(1/Φ)∫(M_gas + M_d) dφ [N·m]: the "balance" load."""
        return float(self.work_start[-1] / self.cycle)

    def values(self, phi, *, gas: bool, gravity: bool, load: float):
        """(K, J − I_w) at φ: K = gas work − load·φ − (U − U(0)) (each part as asked)."""
        phi = np.asarray(phi, dtype=float)
        k = -load * phi
        if gas:
            k = k + self.work(phi)
        if gravity:
            k = k - (self.machine.potential(phi) - self.u0)
        return k, self.machine.engine_inertia(phi)


@dataclass
class Steady:
    """A periodic steady state: the cycle's results and ω(φ), t(φ) at the angles asked."""

    omega_mean: float
    period: float
    mean_load_torque: float
    omega_max: float
    omega_min: float
    phi_max: float
    phi_min: float
    energy_offset: float
    omega: np.ndarray
    time: np.ndarray

    @property
    def delta(self) -> float:
        return (self.omega_max - self.omega_min) / self.omega_mean

    @property
    def delta_midrange(self) -> float:
        return 2 * (self.omega_max - self.omega_min) / (self.omega_max + self.omega_min)


def refine_extreme(nodes, values, f, *, lowest: bool, cycle: float):
    """The extreme of f (periodic over `cycle`) near the best of its samples at sorted
    `nodes`, by bounded Brent between that sample's neighbours (across the cycle's end)."""
    i = int(np.argmin(values) if lowest else np.argmax(values))
    a = nodes[i - 1] if i > 0 else nodes[-1] - cycle
    b = nodes[i + 1] if i + 1 < nodes.size else nodes[0] + cycle
    sign = 1.0 if lowest else -1.0

    def value(p: float) -> float:
        return float(f(np.array([p % cycle]))[0])

    found = optimize.minimize_scalar(
        lambda p: sign * value(p), bounds=(a, b), method="bounded", options={"xatol": 1e-13}
    )
    best = value(found.x)
    if sign * best <= sign * values[i]:
        return best, float(found.x % cycle)
    return float(values[i]), float(nodes[i])


class Stall(Exception):
    """No steady running: ω reaches 0, or ω_min < ratio·ω_m."""

    def __init__(self, angle: float) -> None:
        super().__init__(f"stalls near φ = {angle}")
        self.angle = angle


class Balance:
    """The load "balance" on one Cycle, with gas and gravity each on or off (gas off: no
    load either)."""

    def __init__(self, cycle: Cycle, *, gas: bool = True, gravity: bool = True, angles=()) -> None:
        self.cycle = cycle
        self.gas, self.gravity = gas, gravity and cycle.machine.g != 0.0
        self.load = cycle.mean_gas_torque if gas else 0.0
        self.angles = np.asarray(angles, dtype=float)
        edges = cycle.edges
        lo, hi = edges[:-1], edges[1:]
        self.base = self._intervals(lo, hi)
        # K's minimum over the cycle, refined on the exact K.
        nodes, k = self.base["phi"].ravel(), self.base["k"].ravel()
        order = np.argsort(nodes)
        nodes, k = nodes[order], k[order]
        self.k_noise = 1e-15 * float(np.max(np.abs(k)) + np.max(np.abs(self.base["j"])))
        self.k_min, self.k_min_at = refine_extreme(
            nodes, k, lambda p: self._values(p)[0], lowest=True, cycle=cycle.cycle
        )

    def _values(self, phi):
        return self.cycle.values(phi, gas=self.gas, gravity=self.gravity, load=self.load)

    def _intervals(self, lo, hi) -> dict:
        """Nodes of the rule on [lo, hi] and on its halves, with K and J − I_w there."""
        x = self.cycle.x
        mid = (lo + hi) / 2
        whole = mid[:, None] + ((hi - lo) / 2)[:, None] * x
        left = ((lo + mid) / 2)[:, None] + ((mid - lo) / 2)[:, None] * x
        right = ((mid + hi) / 2)[:, None] + ((hi - mid) / 2)[:, None] * x
        phi = np.hstack((whole, left, right))
        k, j = self._values(phi.ravel())
        return {"lo": lo, "hi": hi, "phi": phi, "k": k.reshape(phi.shape), "j": j.reshape(phi.shape)}

    def _time(self, s: float, inertia: float, parts: dict, *, per_panel: bool = False):
        """∫dφ/ω over the intervals of `parts` (adaptive), E = s + K − min K."""
        n = self.cycle.x.size
        w = self.cycle.w
        total = np.zeros(parts["lo"].size)
        todo = parts
        owner = np.arange(parts["lo"].size)
        budget = None  # the error allowed per radian: ADAPTIVE_RTOL of the first estimate
        for _ in range(80):
            energy = s + todo["k"] - self.k_min
            if np.any(energy <= 0):
                raise Stall(float(todo["phi"].ravel()[np.argmin(energy.ravel())]))
            f = np.sqrt((inertia + todo["j"]) / (2 * energy))
            lo, hi = todo["lo"], todo["hi"]
            whole = (hi - lo) / 2 * (f[:, :n] @ w)
            halves = (hi - lo) / 4 * (f[:, n : 2 * n] @ w + f[:, 2 * n :] @ w)
            if budget is None:
                budget = ADAPTIVE_RTOL * math.fsum(halves) / math.fsum(hi - lo)
            # K's rounding (~1e-15 of its scale) is noise in E where E is small (near stall):
            # differences at that level are the rounding's, not the rule's.
            noise = (hi - lo) * np.mean(f * self.k_noise / energy, axis=1)
            allowed = np.maximum(ADAPTIVE_RTOL * np.abs(halves), budget * (hi - lo))
            done = np.abs(whole - halves) <= np.maximum(allowed, 10 * noise)
            done |= hi - lo < 1e-12
            if todo["lo"].size > 10**6:
                raise RuntimeError("the time quadrature does not settle")
            np.add.at(total, owner[done], halves[done])
            if done.all():
                break
            lo, hi, owner = lo[~done], hi[~done], owner[~done]
            mid = (lo + hi) / 2
            todo = self._intervals(np.concatenate((lo, mid)), np.concatenate((mid, hi)))
            owner = np.concatenate((owner, owner))
        else:
            raise RuntimeError("the time quadrature does not settle")
        return total if per_panel else float(math.fsum(total))

    def _omega(self, s: float, inertia: float, phi) -> np.ndarray:
        k, j = self._values(phi)
        return np.sqrt(2 * (s + k - self.k_min) / (inertia + j))

    def _solution(self, s: float, inertia: float, *, with_curves: bool = True) -> Steady:
        pieces = self._time(s, inertia, self.base, per_panel=True)
        period = float(math.fsum(pieces))
        omega_mean = self.cycle.cycle / period
        nodes, k, j = (self.base[key].ravel() for key in ("phi", "k", "j"))
        order = np.argsort(nodes)
        nodes, k, j = nodes[order], k[order], j[order]
        sampled = np.sqrt(2 * (s + k - self.k_min) / (inertia + j))
        f = lambda p: self._omega(s, inertia, p)  # noqa: E731
        omega_max, phi_max = refine_extreme(nodes, sampled, f, lowest=False, cycle=self.cycle.cycle)
        omega_min, phi_min = refine_extreme(nodes, sampled, f, lowest=True, cycle=self.cycle.cycle)
        omega = time = np.empty(0)
        if with_curves and self.angles.size:
            omega = f(self.angles)
            time = _times_at(self.cycle.edges, pieces, self.angles)
        return Steady(
            omega_mean=omega_mean,
            period=period,
            mean_load_torque=self.load,
            omega_max=omega_max,
            omega_min=omega_min,
            phi_max=phi_max,
            phi_min=phi_min,
            energy_offset=s,
            omega=omega,
            time=time,
        )

    def solve(self, omega_mean: float, inertia: float | None = None, ratio: float = 1e-3) -> Steady:
        """The steady state at mean speed ω_m [rad/s] with shaft inertia I_w [kg·m²];
        Stall where ω_min < ratio·ω_m."""
        inertia = self.cycle.machine.shaft_inertia if inertia is None else inertia
        target = self.cycle.cycle / omega_mean

        def excess(log_s: float) -> float:
            try:
                return math.log(self._time(math.exp(log_s), inertia, self.base) / target)
            except Stall:
                return math.inf

        j_max = float(np.max(self.base["j"])) + inertia
        high = math.log(2 * j_max * omega_mean**2 + 1e-300)
        low = high - 30.0  # ω_min/ω_m ~ e^-15 there: a stall by any ratio asked
        if excess(low) < 0:
            raise Stall(self.k_min_at)
        log_s = optimize.brentq(excess, low, high, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=300)
        found = self._solution(math.exp(log_s), inertia)
        if found.omega_min < ratio * found.omega_mean:
            raise Stall(found.phi_min)
        return found

    def min_rpm(self, inertia: float | None = None, ratio: float = 1e-3) -> float:
        """The lowest mean speed [1/min] whose ω_min/ω_m reaches `ratio`."""
        inertia = self.cycle.machine.shaft_inertia if inertia is None else inertia

        def shortfall(log_s: float) -> float:
            found = self._solution(math.exp(log_s), inertia, with_curves=False)
            return found.omega_min / found.omega_mean - ratio

        j_max = float(np.max(self.base["j"])) + inertia
        high = math.log(j_max)
        while shortfall(high) < 0:
            high += 2.0
        low = high - 4.0
        while shortfall(low) > 0:
            low -= 4.0
        log_s = optimize.brentq(shortfall, low, high, xtol=1e-14, rtol=4 * np.finfo(float).eps)
        return self._solution(math.exp(log_s), inertia, with_curves=False).omega_mean * 30 / math.pi

    def energy_swing(self, omega_mean: float) -> float:
        """ΔE [J]: the swing of K(φ) − ½ω_m²(J(φ) − J(0)) (gas, load, gravity and the inertia
        torque −½J'ω_m² at the mean speed)."""
        j0 = float(self.cycle.machine.engine_inertia(np.zeros(1))[0])

        def diagram(p):
            k, j = self._values(p)
            return k - 0.5 * omega_mean**2 * (j - j0)

        nodes, k, j = (self.base[key].ravel() for key in ("phi", "k", "j"))
        order = np.argsort(nodes)
        sampled = (k - 0.5 * omega_mean**2 * (j - j0))[order]
        top, _ = refine_extreme(nodes[order], sampled, diagram, lowest=False, cycle=self.cycle.cycle)
        bottom, _ = refine_extreme(nodes[order], sampled, diagram, lowest=True, cycle=self.cycle.cycle)
        return top - bottom

    def mean_engine_inertia(self) -> float:
        """(1/Φ)∫(J − I_w) dφ [kg·m²]."""
        c = self.cycle
        return float(np.sum(c._rule(c.machine.engine_inertia, c.edges[:-1], c.edges[1:])) / c.cycle)

    def flywheel(self, delta: float, omega_mean: float) -> float:
        """The I_w [kg·m²] giving δ at ω_m, by brentq on log I_w."""

        def excess(log_i: float) -> float:
            return math.log(self.solve(omega_mean, math.exp(log_i)).delta / delta)

        guess = max(self.energy_swing(omega_mean) / (delta * omega_mean**2), 1e-6)
        low, high = math.log(guess) - 1.0, math.log(guess) + 1.0
        while excess(low) < 0:
            low -= 1.0
        while excess(high) > 0:
            high += 1.0
        return math.exp(optimize.brentq(excess, low, high, xtol=1e-14, rtol=4 * np.finfo(float).eps))


class SquareLaw:
    """A square-law load c·ω² [N·m] beside a constant drive [N·m]: the periodic solution of
    the linear dE/dφ = M_gas + drive − U' − (2c/J)E, panel by panel by its propagator."""

    def __init__(self, cycle: Cycle, coefficient: float, drive: float, *, gravity: bool = True, angles=()) -> None:
        self.cycle, self.c, self.drive = cycle, coefficient, drive
        self.gravity = gravity and cycle.machine.g != 0.0
        self.angles = np.asarray(angles, dtype=float)
        edges = cycle.edges
        lo, hi = edges[:-1], edges[1:]
        # Over each panel: E(b) = e^{−A}(E(a) + ∫ e^{A(y)} h(y) dy), A(y) = ∫_a^y 2c/J.
        growth, source = self._propagate(lo, hi)
        # E at the panels' starts: E_{i+1} = g_i E_i + q_i, periodic: E_0 = E_P.
        p = lo.size
        gain, shift = 1.0, 0.0
        for i in range(p):
            gain, shift = growth[i] * gain, growth[i] * shift + source[i]
        start = np.empty(p + 1)
        start[0] = shift / (1 - gain)
        for i in range(p):
            start[i + 1] = growth[i] * start[i] + source[i]
        self.start = start

    def _h(self, y):
        h = self.cycle.machine.gas_torque(y) + self.drive
        if self.gravity:
            h = h + self.cycle.machine.gravity_torque(y)
        return h

    def _q(self, y):
        return 2 * self.c / (self.cycle.machine.shaft_inertia + self.cycle.machine.engine_inertia(y))

    def _propagate(self, lo, hi):
        """(e^{−A(hi)}, e^{−A(hi)}∫_lo^hi e^{A}h) per interval, A from lo."""
        if lo.size > 4096:
            parts = [self._propagate(lo[i : i + 4096], hi[i : i + 4096]) for i in range(0, lo.size, 4096)]
            return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])
        x, w = self.cycle.x, self.cycle.w
        sx, sw = special.roots_legendre(SMOOTH_POINTS)
        half = (hi - lo) / 2
        y = (lo + hi)[:, None] / 2 + half[:, None] * x  # outer nodes
        # A(y) = ∫_lo^y q: inner nodes on [lo, y].
        inner_half = (y - lo[:, None]) / 2
        inner = (y + lo[:, None])[..., None] / 2 + inner_half[..., None] * sx
        a_y = inner_half * (self._q(inner.ravel()).reshape(inner.shape) @ sw)
        ends = (lo + hi)[:, None] / 2 + half[:, None] * sx
        a_end = half * (self._q(ends.ravel()).reshape(ends.shape) @ sw)
        integral = half * ((np.exp(a_y) * self._h(y.ravel()).reshape(y.shape)) @ w)
        decay = np.exp(-a_end)
        return decay, decay * integral

    def energy(self, phi) -> np.ndarray:
        phi = np.asarray(phi, dtype=float)
        i = self.cycle.panel(phi)
        growth, source = self._propagate(self.cycle.edges[i], phi)
        return growth * self.start[i] + source

    def solve(self, ratio: float = 1e-3) -> Steady:
        c = self.cycle
        lo, hi = c.edges[:-1], c.edges[1:]
        x = c.x
        nodes = ((lo + hi)[:, None] / 2 + ((hi - lo) / 2)[:, None] * x).ravel()
        energy = self.energy(nodes)
        if np.any(energy <= 0):
            raise Stall(float(nodes[np.argmin(energy)]))
        inertia = c.machine.shaft_inertia + c.machine.engine_inertia(nodes)
        f = np.sqrt(inertia / (2 * energy)).reshape(lo.size, x.size)
        pieces = (hi - lo) / 2 * (f @ c.w)
        period = float(math.fsum(pieces))
        load = (2 * self.c * energy / inertia).reshape(lo.size, x.size)
        mean_load = float(math.fsum((hi - lo) / 2 * (load @ c.w))) / c.cycle

        def omega(p):
            return np.sqrt(2 * self.energy(p) / (c.machine.shaft_inertia + c.machine.engine_inertia(p)))

        sampled = np.sqrt(2 * energy / inertia)
        order = np.argsort(nodes)
        omega_max, phi_max = refine_extreme(nodes[order], sampled[order], omega, lowest=False, cycle=c.cycle)
        omega_min, phi_min = refine_extreme(nodes[order], sampled[order], omega, lowest=True, cycle=c.cycle)
        omega_mean = c.cycle / period
        if omega_min < ratio * omega_mean:
            raise Stall(phi_min)
        times = omega_at = np.empty(0)
        if self.angles.size:
            omega_at = omega(self.angles)
            times = _times_at(c.edges, pieces, self.angles)
        return Steady(
            omega_mean=omega_mean,
            period=period,
            mean_load_torque=mean_load,
            omega_max=omega_max,
            omega_min=omega_min,
            phi_max=phi_max,
            phi_min=phi_min,
            energy_offset=float(self.start[0]),
            omega=omega_at,
            time=times,
        )


# -- machines from their parameters -------------------------------------------------------------

UNIT_FIELDS = (
    "crank_radius",
    "rod_length",
    "piston_mass",
    "rod_mass",
    "rod_cg",
    "rod_inertia",
    "crank_mass",
    "crank_cg_radius",
    "counterweight_mass",
    "counterweight_radius",
    "phase",
    "inclination",
    "bore",
    "piston_rod_diameter",
)


def table_of(diagram) -> Table | None:
    """A Table from an object with ``angle``, ``pressure``, ``kind`` and ``cycle`` (a
    multicrank IndicatorDiagram's parameters; nothing of its interpolant is used)."""
    if diagram is None:
        return None
    return Table(np.array(diagram.angle), np.array(diagram.pressure), diagram.kind, float(diagram.cycle))


def machine_of(machine) -> Machine:
    """An oracle Machine from a multicrank Machine's parameters (duck-typed: its cylinders'
    fields, shaft_inertia, strokes and g)."""
    units = [
        Unit(
            **{name: float(getattr(c, name)) for name in UNIT_FIELDS},
            head=table_of(c.pressure),
            crank_end=table_of(c.pressure_crank_end),
        )
        for c in machine.cylinders
    ]
    return Machine(units, machine.shaft_inertia, machine.strokes, machine.g)
