"""The synthetic indicator diagrams: the ideal reciprocating compressor and the single-zone
engine cycle with Wiebe heat release, in a cylinder volume V(θ) the caller supplies, and the
analysis of that volume they rest on (its dead centres, where it crosses a value).

They are :meth:`IndicatorDiagram.compressor <multicrank.IndicatorDiagram.compressor>` and
:meth:`IndicatorDiagram.engine <multicrank.IndicatorDiagram.engine>`: each function here takes
the class as its first argument, and the class makes them its classmethods. This module does no
kinematics (the volume is the caller's, :meth:`multicrank.Cylinder.chamber_volume` say), and
imports SciPy only when a cycle is built.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validation import as_count, as_flag, as_option, as_real_array, refused
from ._cycle import (
    FOUR_STROKE,
    INTERPOLATIONS,
    STANDARD_ATMOSPHERE,
    TWO_STROKE,
    as_cycle,
    as_finite,
    cycle_name,
    gauss,
)

if TYPE_CHECKING:
    from .diagram import IndicatorDiagram

__all__ = ["compressor", "engine"]


def _scipy_optimize() -> Any:
    import scipy.optimize  # type: ignore[import-untyped,unused-ignore]

    return scipy.optimize


# -- the cylinder volume ---------------------------------------------------------------------


class Volume:
    """The caller's V(θ) [m³], checked: positive, finite, of θ's shape, periodic over the cycle."""

    def __init__(self, volume: Any, cycle: float, samples: int) -> None:
        if not callable(volume):
            raise refused("volume", f"volume must be a callable θ [rad] -> V [m³], got {type(volume).__name__}")
        self._function: Callable[[np.ndarray], Any] = volume
        self.cycle = cycle
        self.grid = np.arange(samples) * (cycle / samples)
        self.values = self(self.grid)
        ends = self(np.array([0.0, cycle]))
        if abs(ends[1] - ends[0]) > 1e-9 * float(np.max(self.values)):
            raise refused(
                "volume",
                f"volume must be periodic over the cycle {cycle_name(cycle)}: "
                f"V(0) = {ends[0]:.10g} m³ but V({cycle:.10g}) = {ends[1]:.10g} m³",
            )

    def __call__(self, theta: np.ndarray) -> np.ndarray:
        result = as_real_array(self._function(theta), "volume(θ)")
        if result.shape != theta.shape:
            try:
                result = np.broadcast_to(result, theta.shape)
            except ValueError:
                raise refused(
                    "volume", f"volume(θ) must return an array of θ's shape {theta.shape}, got shape {result.shape}"
                ) from None
        bad = ~(np.isfinite(result) & (result > 0))
        if np.any(bad):
            where = np.flatnonzero(bad.ravel())[0]
            at, value = theta.ravel()[where], result.ravel()[where]
            raise refused("volume", f"volume(θ) must be finite and positive [m³]; volume({at:.10g}) = {value:.10g}")
        return result

    def wrapped(self, theta: np.ndarray) -> np.ndarray:
        """V at any θ, taken modulo the cycle (V is periodic)."""
        return self(np.mod(theta, self.cycle))

    def dead_centres(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The extrema of V in [0, Φ): their angles [rad], volumes [m³] and whether each is a minimum.

        Each sign change of the sampled ΔV brackets one extremum, polished by bounded Brent
        minimisation between the neighbouring samples (the volume there is exact to rounding
        even where the angle is not, V being flat at an extremum).
        """
        rise = np.sign(np.roll(self.values, -1) - self.values)  # rise[i]: from sample i to i + 1
        if not np.any(rise):
            raise refused("volume", "volume must vary over the cycle; it is constant (no stroke)")
        # A flat step keeps the direction before it.
        nonzero = np.flatnonzero(rise)
        fill = np.searchsorted(nonzero, np.arange(rise.size), side="right") - 1  # -1: wrap to the last
        rise = rise[nonzero[fill]]
        turns = np.flatnonzero(np.roll(rise, 1) != rise)  # the direction changes at sample i
        optimize = _scipy_optimize()
        step = self.cycle / self.grid.size
        angles, volumes, minima = [], [], []
        for i in turns:
            is_min = bool(rise[i] > 0)
            sign = 1.0 if is_min else -1.0
            best = optimize.minimize_scalar(
                lambda t, sign=sign: sign * float(self.wrapped(np.array([t]))[0]),
                bounds=(self.grid[i] - step, self.grid[i] + step),
                method="bounded",
                options={"xatol": 1e-12 * self.cycle},
            )
            angle, value = float(best.x), sign * float(best.fun)
            if sign * self.values[i] <= sign * value:  # the sample itself is as good
                angle, value = float(self.grid[i]), float(self.values[i])
            angles.append(angle % self.cycle)
            volumes.append(value)
            minima.append(is_min)
        order = np.argsort(angles)
        return np.asarray(angles)[order], np.asarray(volumes)[order], np.asarray(minima)[order]

    def crossing(self, target: float, start: float, stop: float) -> float:
        """The angle in [start, stop] where V (monotone there) equals target [m³]."""
        optimize = _scipy_optimize()
        return float(
            optimize.brentq(
                lambda t: float(self.wrapped(np.array([t]))[0]) - target,
                start,
                stop,
                xtol=1e-14 * self.cycle,
                rtol=4 * np.finfo(float).eps,
            )
        )


def _table_angles(cycle: float, points: int, events: list[float]) -> np.ndarray:
    """A uniform grid of ``points`` angles over [0, Φ] with the events (kinks) added as nodes.

    Grid nodes closer than a quarter step to an event give way to it, so no interval is tiny.
    """
    grid = np.linspace(0.0, cycle, points)
    step = cycle / (points - 1)
    inside = sorted(e for e in (float(e) % cycle for e in events) if 1e-9 * cycle < e < cycle * (1 - 1e-9))
    kept: list[float] = []
    for event in inside:
        if not kept or event - kept[-1] > 1e-9 * cycle:
            kept.append(event)
    chosen = np.asarray(kept)
    if chosen.size:
        nearest = np.min(np.abs(grid[1:-1, None] - chosen[None, :]), axis=1)
        interior = grid[1:-1][nearest > 0.25 * step]
        return np.concatenate(([0.0], np.sort(np.concatenate((interior, chosen))), [cycle]))
    return grid


# -- the cycles -------------------------------------------------------------------------------


def compressor(
    cls: type[IndicatorDiagram],
    volume: Callable[[np.ndarray], Any],
    *,
    suction_pressure: float,
    discharge_pressure: float,
    polytropic_exponent: float = 1.3,
    cycle: float = TWO_STROKE,
    points: int = 721,
    absolute: bool = True,
    reference_pressure: float = STANDARD_ATMOSPHERE,
    kind: str = "pchip",
) -> IndicatorDiagram:
    """The ideal reciprocating compressor's cycle in a cylinder of volume V(θ).

    Suction at constant p_s, polytropic compression p Vⁿ = const to p_d, discharge at
    constant p_d, polytropic re-expansion of the clearance gas to p_s (automatic valves,
    no pressure losses). The valve events follow from V alone: wherever V increases the
    cylinder re-expands from the smallest volume V_a at p_d, p = max(p_s, p_d (V_a/V)ⁿ),
    and wherever it decreases it compresses from the largest volume V_b at p_s,
    p = min(p_d, p_s (V_b/V)ⁿ). With this library's V (smallest at θ = 0, outer dead
    centre) the cycle runs: re-expansion from θ = 0, suction opening at V = V_a (p_d/p_s)^{1/n},
    suction to θ ≈ π, compression, discharge opening at V = V_b (p_s/p_d)^{1/n}, discharge
    to θ = 2π.

    Parameters
    ----------
    volume : callable
        The chamber volume V(θ) [m³], vectorised over θ [rad], periodic over the cycle:
        V_clearance + A·s(θ) for the head end; for the crank end of a double-acting
        cylinder pass that chamber's volume (it grows while the head end's shrinks).
    suction_pressure, discharge_pressure : float
        p_s < p_d [Pa], absolute unless ``absolute=False``.
    polytropic_exponent : float, default 1.3
        n > 0 [dimensionless] of compression and re-expansion (1: isothermal, the gas's
        κ: isentropic).
    cycle : float, default 2π
        The working cycle [rad]; with 4π the compressor's cycle appears once per revolution.
    points : int, default 721
        Table points uniformly over [0, Φ] (0.5° steps for 2π), plus the valve events.
    absolute : bool, default True
        Whether p_s and p_d are absolute; False: gauge, relative to ``reference_pressure``.
    reference_pressure : float, default 101325.0
        The crankcase pressure [Pa]: the diagram holds p_abs − reference_pressure.
    kind : str, default "pchip"
        The interpolation (the valve events are kinks, which PCHIP follows without overshoot).

    Returns
    -------
    IndicatorDiagram
        Gauge pressures [Pa]; its table holds the exact cycle at every node.

    Raises
    ------
    MechanismError
        For bad input, or when the clearance is so large that the re-expansion from the
        smallest volume never reaches p_s (the compressor would deliver nothing).
    """
    cycle = as_cycle(cycle)
    points = as_count(points, "points", minimum=8)
    absolute = as_flag(absolute, "absolute")
    reference = as_finite(reference_pressure, "reference_pressure")
    n = as_finite(polytropic_exponent, "polytropic_exponent", above=0.0)
    shift = 0.0 if absolute else reference
    p_s = as_finite(suction_pressure, "suction_pressure") + shift
    p_d = as_finite(discharge_pressure, "discharge_pressure") + shift
    if not p_s > 0:
        raise refused(
            "suction_pressure", f"suction_pressure = {suction_pressure} must be above vacuum (absolute {p_s} Pa > 0)"
        )
    if not p_d > p_s:
        raise refused(
            "discharge_pressure",
            f"discharge_pressure = {discharge_pressure} must exceed suction_pressure = {suction_pressure}",
        )
    kind = as_option(kind, "kind", INTERPOLATIONS)
    vol = Volume(volume, cycle, samples=max(points, 720))
    angles, volumes, minima = vol.dead_centres()
    try:
        ratio = (p_d / p_s) ** (1.0 / n)  # the polytropic volume ratio
    except OverflowError:  # beyond 1.8e308: no clearance volume re-expands so far
        ratio = math.inf
    ends = np.append(angles, angles[0] + cycle)
    events = []
    for j, start in enumerate(volumes):
        end = volumes[(j + 1) % volumes.size]
        if minima[j]:  # expanding: re-expansion until suction opens at V_a·ratio
            target = start * ratio
            if not target < end:
                raise refused(
                    "volume",
                    f"volume: the re-expansion of the clearance volume {start:.10g} m³ from discharge_pressure "
                    f"reaches suction_pressure only at {target:.10g} m³, beyond the largest volume {end:.10g} m³: "
                    f"the clearance is too large for this pressure ratio (the compressor delivers nothing)",
                )
        else:  # shrinking: compression until discharge opens at V_b/ratio
            target = start / ratio
            if not target > end:
                raise refused(
                    "volume",
                    f"volume: compression from the largest volume {start:.10g} m³ reaches discharge_pressure "
                    f"only at {target:.10g} m³, below the smallest volume {end:.10g} m³ (the compressor "
                    "delivers nothing)",
                )
        events.append(vol.crossing(target, ends[j], ends[j + 1]))
    theta = _table_angles(cycle, points, events)
    v = vol(theta)
    # Which stroke each node is on: the extremum at or before it (cyclically).
    segment = np.searchsorted(ends, np.where(theta >= angles[0], theta, theta + cycle), side="right") - 1
    segment = np.clip(segment, 0, volumes.size - 1)
    start = volumes[segment]
    expanding = minima[segment]
    with np.errstate(over="ignore"):
        p = np.where(
            expanding,
            np.maximum(p_s, p_d * (start / v) ** n),
            np.minimum(p_d, p_s * (start / v) ** n),
        )
    p = np.clip(p, p_s, p_d)
    return cls(theta, p - reference, cycle=cycle, kind=kind)


def engine(
    cls: type[IndicatorDiagram],
    volume: Callable[[np.ndarray], Any],
    *,
    intake_pressure: float,
    heat_release: float,
    cycle: float = FOUR_STROKE,
    start_of_combustion: float = -math.radians(10.0),
    combustion_duration: float = math.radians(60.0),
    compression_exponent: float = 1.35,
    expansion_exponent: float = 1.3,
    wiebe_a: float = 5.0,
    wiebe_m: float = 2.0,
    exhaust_opening: float = math.radians(40.0),
    intake_closing: float = 0.0,
    points: int = 1441,
    absolute: bool = True,
    reference_pressure: float = STANDARD_ATMOSPHERE,
    kind: str = "pchip",
) -> IndicatorDiagram:
    """A single-zone engine cycle in a cylinder of volume V(θ), two- or four-stroke.

    θ = 0 is the **firing** dead centre (outer dead centre, smallest volume): a unit fires
    when its cycle angle is 0, so the units' phases give the firing order. The cycle:

    - polytropic expansion (``expansion_exponent``) from θ = 0, with the rest of the heat
      release, to the exhaust opening ``exhaust_opening`` before the next (inner) dead
      centre θ_B ≈ π;
    - blowdown from there to θ_B: the pressure blends smoothly (a half-cosine weight, C¹)
      from the expansion curve into the gas-exchange pressure, which it reaches at θ_B;
    - gas exchange at constant ``intake_pressure``: four-stroke exhaust θ_B … 2π and intake
      2π … 3π; two-stroke scavenging around θ_B; until the intake closes ``intake_closing``
      after the last inner dead centre (θ ≈ 3π four-stroke, ≈ π two-stroke);
    - polytropic compression (``compression_exponent``) from there to the firing dead centre
      at θ = Φ ≡ 0, with the heat released before it.

    The heat release follows Wiebe: x_b = 1 − exp[−a((θ − θ₀)/Δθ)^{m+1}] for θ₀ ≤ θ ≤ θ₀ + Δθ,
    dQ/dθ = Q·dx_b/dθ (so Q·(1 − e^{−a}) is released in all: a = 6.9 for 99.9 %). With κ the
    exponent of the phase (compression before the firing dead centre, expansion after),
    the first law for the closed cylinder, dp/dθ = (κ−1)/V·dQ/dθ − κ p/V·dV/dθ, is exactly
    d(p V^κ)/dθ = (κ−1) V^{κ−1} dQ/dθ, so p V^κ is integrated in closed form as the
    quadrature of (κ−1) V^{κ−1} dQ/dθ (Gauss–Legendre on each table interval, no ODE
    solver): with Q = 0 every closed phase is an exact polytrope.

    Parameters
    ----------
    volume : callable
        The cylinder volume V(θ) [m³], vectorised over θ [rad], periodic over the cycle,
        smallest at θ = 0 (V_clearance + A·s(θ)); one minimum and one maximum per revolution.
    intake_pressure : float
        The gas-exchange pressure [Pa] (intake and exhaust alike), absolute unless
        ``absolute=False``; the compression starts from it at intake closing.
    heat_release : float
        Q ≥ 0 [J per cycle]: the heat the Wiebe function releases to the gas (fuel energy
        times combustion efficiency, less wall heat if wished); 0 gives the motored cycle.
    cycle : float, default 4π
        The working cycle [rad]: 2π two-stroke, 4π four-stroke.
    start_of_combustion : float, default −10° (as rad)
        θ₀ [rad] relative to the firing dead centre (negative: before it); after intake
        closing.
    combustion_duration : float, default 60° (as rad)
        Δθ > 0 [rad]; combustion ends (θ₀ + Δθ) at the latest at exhaust opening.
    compression_exponent, expansion_exponent : float, default 1.35 and 1.3
        The polytropic exponents κ > 1 [dimensionless] of compression and expansion.
    wiebe_a, wiebe_m : float, default 5.0 and 2.0
        Wiebe's efficiency parameter a > 0 and form factor m > −1 [dimensionless].
    exhaust_opening : float, default 40° (as rad)
        How far before the inner dead centre ending the expansion [rad] the exhaust opens
        (0 < … < that dead centre's angle).
    intake_closing : float, default 0
        How far after the last inner dead centre [rad] the intake closes and compression
        starts (≥ 0).
    points : int, default 1441
        Table points uniformly over [0, Φ] (0.5° steps for 4π), plus the events (start and
        end of combustion, exhaust opening, dead centres, intake closing).
    absolute : bool, default True
        Whether ``intake_pressure`` is absolute; False: gauge, relative to ``reference_pressure``.
    reference_pressure : float, default 101325.0
        The crankcase pressure [Pa]: the diagram holds p_abs − reference_pressure.
    kind : str, default "pchip"
        The interpolation.

    Returns
    -------
    IndicatorDiagram
        Gauge pressures [Pa]; continuous over the whole cycle.

    Raises
    ------
    MechanismError
        For bad input, naming the parameter; when combustion would start before intake
        closing or end after exhaust opening; when V is not smallest at θ = 0.
    """
    cycle = as_cycle(cycle)
    points = as_count(points, "points", minimum=8)
    absolute = as_flag(absolute, "absolute")
    reference = as_finite(reference_pressure, "reference_pressure")
    p_gas = as_finite(intake_pressure, "intake_pressure") + (0.0 if absolute else reference)
    if not p_gas > 0:
        raise refused(
            "intake_pressure", f"intake_pressure = {intake_pressure} must be above vacuum (absolute {p_gas} Pa > 0)"
        )
    heat = as_finite(heat_release, "heat_release", at_least=0.0)
    theta0 = as_finite(start_of_combustion, "start_of_combustion")
    duration = as_finite(combustion_duration, "combustion_duration", above=0.0)
    kappa_c = as_finite(compression_exponent, "compression_exponent", above=1.0)
    kappa_e = as_finite(expansion_exponent, "expansion_exponent", above=1.0)
    a = as_finite(wiebe_a, "wiebe_a", above=0.0)
    m = as_finite(wiebe_m, "wiebe_m", above=-1.0)
    opening = as_finite(exhaust_opening, "exhaust_opening", above=0.0)
    closing = as_finite(intake_closing, "intake_closing", at_least=0.0)
    kind = as_option(kind, "kind", INTERPOLATIONS)

    vol = Volume(volume, cycle, samples=max(points, 1440))
    angles, _, minima = vol.dead_centres()
    revolutions = round(cycle / TWO_STROKE)
    if angles.size != 2 * revolutions:
        raise refused(
            "volume",
            f"volume must have one minimum and one maximum per revolution; it has {int(np.sum(minima))} minima "
            f"and {int(np.sum(~minima))} maxima over the cycle {cycle_name(cycle)}",
        )
    first = np.flatnonzero(minima)
    off = np.min(np.abs(np.remainder(angles[first] + 0.5 * cycle, cycle) - 0.5 * cycle))
    if off > 1e-5 * cycle:
        raise refused(
            "volume",
            "volume must be smallest at θ = 0 (outer dead centre, the firing dead centre); "
            f"its minimum nearest θ = 0 is {off:.10g} rad away",
        )
    inner = angles[~minima]
    bdc_first, bdc_last = float(inner[0]), float(inner[-1])
    if not opening < bdc_first:
        raise refused(
            "exhaust_opening",
            f"exhaust_opening = {opening} is out of range; allowed: 0 < exhaust_opening < {bdc_first!r} "
            f"(the inner dead centre ending the expansion)",
        )
    if not bdc_last + closing < cycle:
        raise refused(
            "intake_closing",
            f"intake_closing = {closing} is out of range; allowed: 0 <= intake_closing < {cycle - bdc_last!r} "
            f"(before the firing dead centre)",
        )
    t_open = bdc_first - opening  # exhaust opens (t ≥ 0)
    t_close = bdc_last + closing - cycle  # intake closes (t < 0: before the firing dead centre)
    if not theta0 >= t_close:
        raise refused(
            "start_of_combustion",
            f"start_of_combustion = {theta0} is out of range; allowed: start_of_combustion >= {t_close!r} "
            f"(intake closing, relative to the firing dead centre)",
        )
    if not theta0 + duration <= t_open:
        raise refused(
            "combustion_duration",
            f"combustion_duration = {duration} is out of range: combustion would end at {theta0 + duration!r} "
            f"rad, after the exhaust opens at {t_open!r} rad; allowed: start_of_combustion + "
            f"combustion_duration <= {t_open!r}",
        )

    events = [t_open, bdc_first, bdc_last, bdc_last + closing, theta0, theta0 + duration]
    theta = _table_angles(cycle, points, events)
    # The closed part of the cycle in t = θ relative to the firing dead centre: [t_close, t_B].
    t = np.where(theta >= bdc_last + closing, theta - cycle, theta)
    closed = (t >= t_close) & (t <= bdc_first)
    p = np.full(theta.shape, p_gas)
    t_closed = t[closed]

    def heat_rate(x: np.ndarray) -> np.ndarray:
        """dQ/dθ [J/rad] of the Wiebe function at Gauss points x inside the combustion window."""
        u = (x - theta0) / duration
        return heat * a * (m + 1.0) / duration * u**m * np.exp(-a * u ** (m + 1.0))

    def release(lo: float, hi: np.ndarray, kappa: float) -> np.ndarray:
        """(κ−1)∫_lo^hi V^{κ−1} dQ/dθ dθ for each hi ≥ lo (cumulative along sorted hi)."""
        knots = np.unique(np.concatenate(([lo], hi)))
        left = np.clip(knots[:-1], theta0, theta0 + duration)
        right = np.clip(knots[1:], theta0, theta0 + duration)
        nodes, weights = gauss()
        half = 0.5 * (right - left)
        burning = half > 0  # the intervals inside the combustion window
        x = (0.5 * (left + right))[burning, None] + half[burning, None] * nodes[None, :]
        pieces = np.zeros(half.shape)
        pieces[burning] = half[burning] * ((vol.wrapped(x) ** (kappa - 1.0) * heat_rate(x)) @ weights)
        total = np.concatenate(([0.0], np.cumsum(pieces)))
        return (kappa - 1.0) * total[np.searchsorted(knots, hi)]

    v_close = float(vol.wrapped(np.array([t_close]))[0])
    v_tdc = float(vol(np.array([0.0]))[0])
    compressing = t_closed < 0
    before = t_closed[compressing]
    c_tdc = p_gas * v_close**kappa_c + release(t_close, np.array([0.0]), kappa_c)[0]
    p_tdc = c_tdc / v_tdc**kappa_c
    p_closed = np.empty_like(t_closed)
    p_closed[compressing] = (p_gas * v_close**kappa_c + release(t_close, before, kappa_c)) / vol.wrapped(
        before
    ) ** kappa_c
    after = t_closed[~compressing]
    p_closed[~compressing] = (p_tdc * v_tdc**kappa_e + release(0.0, after, kappa_e)) / vol.wrapped(after) ** kappa_e
    # Blowdown: blend into the gas-exchange pressure between exhaust opening and t_B.
    u = np.clip((t_closed - t_open) / opening, 0.0, 1.0)
    weight = 0.5 * (1.0 + np.cos(math.pi * u))
    p[closed] = p_gas + (p_closed - p_gas) * weight
    return cls(theta, p - reference, cycle=cycle, kind=kind)
