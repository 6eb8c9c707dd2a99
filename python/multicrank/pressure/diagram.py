"""Indicator diagrams: the gas pressure on a piston over one working cycle (docs/theory.md).

An :class:`IndicatorDiagram` is a table of cycle angle θ [rad] against **gauge** pressure
p [Pa], interpolated periodically over the working cycle Φ (2π for a two-stroke, 4π for a
four-stroke machine), and a vectorised callable ``diagram(theta) -> p`` for any θ. It is
made from arrays, from a CSV file (:meth:`IndicatorDiagram.from_csv`), or as a synthetic
cycle of an ideal reciprocating compressor (:meth:`IndicatorDiagram.compressor`) or a
single-zone engine (:meth:`IndicatorDiagram.engine`).

Conventions
-----------
- θ is the unit's cycle angle, θ = 0 at **outer dead centre**: the piston is farthest from
  the shaft and the cylinder volume is *smallest* there (top dead centre of an upright
  cylinder). The piston travel s(θ) grows from 0 at θ = 0 to the full stroke at θ ≈ π.
- Pressures are **gauge**: p = p_abs − p_ref, where p_ref (``reference_pressure``, 101325 Pa
  by default) is the pressure on the crankcase side of the piston, so that p·A is the net
  force pushing the piston toward the shaft. The thermodynamics of the synthetic cycles
  uses absolute pressures; only the result is gauge.
- The synthetic cycles take the cylinder volume as a vectorised callable θ [rad] → V [m³]
  supplied by the caller (V(θ) = V_clearance + A·s(θ)); this module does no kinematics.

SciPy (a dependency of the package) is imported only when a diagram is built.
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .._native import MechanismError
from .._validation import as_angles, as_count, as_option, as_real_array, as_scalar

__all__ = [
    "ANGLE_UNITS",
    "EXAMPLE_COMPRESSOR_CSV",
    "INTERPOLATIONS",
    "PRESSURE_UNITS",
    "STANDARD_ATMOSPHERE",
    "IndicatorDiagram",
]

#: The interpolations an :class:`IndicatorDiagram` offers (its ``kind``).
INTERPOLATIONS = ("periodic-cubic", "pchip", "linear")
#: Pressure units of :meth:`IndicatorDiagram.from_csv`: Pa per unit (psi: lbf/in², exact).
PRESSURE_UNITS = {"Pa": 1.0, "kPa": 1e3, "bar": 1e5, "MPa": 1e6, "psi": 0.45359237 * 9.80665 / 0.0254**2}
#: Angle units of :meth:`IndicatorDiagram.from_csv`: rad per unit.
ANGLE_UNITS = {"deg": math.pi / 180.0, "rad": 1.0}
#: The default reference (crankcase) pressure [Pa].
STANDARD_ATMOSPHERE = 101325.0
#: A small **synthetic** example table (not measured), made by :meth:`IndicatorDiagram.compressor`;
#: its header says how. Read it with ``from_csv(EXAMPLE_COMPRESSOR_CSV, pressure_unit="bar", absolute=True)``.
EXAMPLE_COMPRESSOR_CSV = Path(__file__).resolve().parent.parent / "data" / "compressor_synthetic.csv"

_TWO_STROKE = 2.0 * math.pi
_FOUR_STROKE = 4.0 * math.pi
# A table must span one cycle to this fraction of the cycle (6e-6 rad for 2π): loose
# enough for angles printed with six digits, tight enough to catch a missing point.
_SPAN_TOLERANCE = 1e-6
# Gauss–Legendre points per table interval for the integrals (work, heat release).
_GAUSS_POINTS = 10


def _scipy_interpolate() -> Any:
    import scipy.interpolate  # type: ignore[import-untyped,unused-ignore]

    return scipy.interpolate


def _scipy_optimize() -> Any:
    import scipy.optimize  # type: ignore[import-untyped,unused-ignore]

    return scipy.optimize


# -- validation -----------------------------------------------------------------------------


def _as_cycle(value: Any, name: str = "cycle") -> float:
    """The working cycle Φ [rad]: 2π or 4π (to 1e-9 relative), returned exact."""
    x = as_scalar(value, name)
    for cycle in (_TWO_STROKE, _FOUR_STROKE):
        if abs(x - cycle) <= 1e-9 * cycle:
            return cycle
    hint = ""
    if x in (2.0, 4.0):
        hint = f" (an angle in rad, not the number of strokes: cycle = {int(x)}*math.pi)"
    raise MechanismError(f"{name} = {x!r} is not allowed; allowed: 2π (two-stroke) or 4π (four-stroke) [rad]{hint}")


def _finite(value: Any, name: str, *, above: float | None = None, at_least: float | None = None) -> float:
    """One finite real number, > above or ≥ at_least where given."""
    x = as_scalar(value, name)
    if not math.isfinite(x):
        raise MechanismError(f"{name} = {x} is out of range; allowed: a finite number")
    if above is not None and not x > above:
        raise MechanismError(f"{name} = {x} is out of range; allowed: {name} > {above}")
    if at_least is not None and not x >= at_least:
        raise MechanismError(f"{name} = {x} is out of range; allowed: {name} >= {at_least}")
    return x


def _flag(value: Any, name: str) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise MechanismError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def _degrees(angle: float) -> str:
    return f"{math.degrees(angle):.6g}°"


def _cycle_name(cycle: float) -> str:
    return "2π (two-stroke)" if cycle == _TWO_STROKE else "4π (four-stroke)"


# -- the cylinder volume of the synthetic cycles ----------------------------------------------


class _Volume:
    """The caller's V(θ) [m³], checked: positive, finite, of θ's shape, periodic over the cycle."""

    def __init__(self, volume: Any, cycle: float, samples: int) -> None:
        if not callable(volume):
            raise MechanismError(f"volume must be a callable θ [rad] -> V [m³], got {type(volume).__name__}")
        self._function: Callable[[np.ndarray], Any] = volume
        self.cycle = cycle
        self.grid = np.arange(samples) * (cycle / samples)
        self.values = self(self.grid)
        ends = self(np.array([0.0, cycle]))
        if abs(ends[1] - ends[0]) > 1e-9 * float(np.max(self.values)):
            raise MechanismError(
                f"volume must be periodic over the cycle {_cycle_name(cycle)}: "
                f"V(0) = {ends[0]:.10g} m³ but V({cycle:.10g}) = {ends[1]:.10g} m³"
            )

    def __call__(self, theta: np.ndarray) -> np.ndarray:
        result = as_real_array(self._function(theta), "volume(θ)")
        if result.shape != theta.shape:
            try:
                result = np.broadcast_to(result, theta.shape)
            except ValueError:
                raise MechanismError(
                    f"volume(θ) must return an array of θ's shape {theta.shape}, got shape {result.shape}"
                ) from None
        bad = ~(np.isfinite(result) & (result > 0))
        if np.any(bad):
            where = np.flatnonzero(bad.ravel())[0]
            at, value = theta.ravel()[where], result.ravel()[where]
            raise MechanismError(f"volume(θ) must be finite and positive [m³]; volume({at:.10g}) = {value:.10g}")
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
            raise MechanismError("volume must vary over the cycle; it is constant (no stroke)")
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


def _gauss(points: int = _GAUSS_POINTS) -> tuple[np.ndarray, np.ndarray]:
    nodes, weights = np.polynomial.legendre.leggauss(points)
    return nodes, weights


# -- the diagram --------------------------------------------------------------------------------


class IndicatorDiagram:
    """The gauge pressure on a piston over one working cycle, interpolated periodically.

    Parameters
    ----------
    angle : array_like, shape (N,)
        Cycle angles θ [rad], strictly increasing, N ≥ 4, covering exactly one cycle: the last
        angle is the first plus ``cycle`` (to 1e-6 of the cycle; it is then set to exactly
        that), i.e. the first point is repeated at the end. The first angle may be any angle
        (0 is usual; −2π for a four-stroke table over [−360°, 360°] works as well): the
        diagram is periodic, and θ is taken modulo the cycle wherever it is evaluated.
        A table without its closing point (e.g. 0° … 355°) is refused: repeat the first point
        at angle + cycle.
    pressure : array_like, shape (N,)
        Gauge pressure p [Pa] at those angles (absolute minus the crankcase pressure; the
        crankcase side is 0). Finite.
    cycle : float
        The working cycle Φ [rad]: ``2*math.pi`` (two-stroke) or ``4*math.pi`` (four-stroke).
    kind : {"periodic-cubic", "pchip", "linear"}, default "periodic-cubic"
        The interpolation: a periodic cubic spline (C², smooth data), a monotone piecewise
        cubic Hermite interpolant (PCHIP, C¹, no overshoot: data with steps such as valve
        events) on the periodically extended table, or piecewise linear.
    closure_tolerance : float, default 1e-6
        The table must close [dimensionless]: the first and last pressures may differ by at
        most closure_tolerance · max|p|. The last pressure is then set to the first.

    Raises
    ------
    MechanismError
        For any bad input, naming the parameter (a NaN, a non-increasing or non-covering
        angle, a table that does not close, an unknown ``kind`` …).

    See Also
    --------
    Cylinder.compressor_diagram, Cylinder.engine_diagram : The synthetic cycles in a
        cylinder's own volume.

    Notes
    -----
    Calling the diagram, ``diagram(theta)``, gives p [Pa] for θ [rad] of any shape (the same
    shape; a numpy float64 for a scalar), θ taken modulo the cycle; NaN or ±inf give NaN.

    Examples
    --------
    A made-up two-stroke table in degrees and bar (gauge), the first point repeated at 360°:

    >>> import numpy as np
    >>> import multicrank as mc
    >>> degrees = [0, 90, 180, 270, 360]
    >>> bar = [30.0, 8.0, 0.0, 2.0, 30.0]
    >>> diagram = mc.IndicatorDiagram(np.radians(degrees), np.multiply(bar, 1e5),
    ...                               cycle=2 * np.pi, kind="linear")
    >>> diagram(np.radians([45, 405])) / 1e5  # bar; θ is taken modulo the cycle
    array([19., 19.])
    >>> print(f"mean {diagram.mean_pressure() / 1e5:.2f} bar")
    mean 10.00 bar
    """

    __slots__ = ("_angle", "_cycle", "_derivative", "_kind", "_poly", "_pressure")

    def __init__(
        self,
        angle: Any,
        pressure: Any,
        *,
        cycle: Any,
        kind: str = "periodic-cubic",
        closure_tolerance: Any = 1e-6,
    ) -> None:
        cycle = _as_cycle(cycle)
        kind = as_option(kind, "kind", INTERPOLATIONS)
        tolerance = _finite(closure_tolerance, "closure_tolerance", at_least=0.0)
        a = as_real_array(angle, "angle")
        p = as_real_array(pressure, "pressure")
        for array, name in ((a, "angle"), (p, "pressure")):
            if array.ndim != 1:
                raise MechanismError(f"{name} must be a 1-D array, got shape {array.shape}")
        if a.size != p.size:
            raise MechanismError(f"angle and pressure must have the same length, got {a.size} and {p.size}")
        if a.size < 4:
            raise MechanismError(f"angle must hold at least 4 points (the first repeated at the end), got {a.size}")
        for array, name, unit in ((a, "angle", "rad"), (p, "pressure", "Pa")):
            bad = np.flatnonzero(~np.isfinite(array))
            if bad.size:
                raise MechanismError(
                    f"{name}[{bad[0]}] = {array[bad[0]]} is not finite; {name} must be finite [{unit}]"
                )
        steps = np.diff(a)
        bad = np.flatnonzero(~(steps > 0))
        if bad.size:
            i = bad[0]
            raise MechanismError(
                f"angle must increase strictly: angle[{i + 1}] = {a[i + 1]:.10g} follows angle[{i}] = {a[i]:.10g}"
            )
        span = a[-1] - a[0]
        if abs(span - cycle) > _SPAN_TOLERANCE * cycle:
            raise MechanismError(
                f"angle must cover exactly one cycle: it spans {span:.10g} rad ({_degrees(span)}) from {a[0]:.10g}, "
                f"but cycle = {_cycle_name(cycle)} = {cycle:.10g} rad ({_degrees(cycle)}); the last angle must be the "
                f"first plus the cycle, the first point repeated at the end"
            )
        a = a.copy()
        a[-1] = a[0] + cycle
        if not a[-1] > a[-2]:
            raise MechanismError(
                f"angle must increase strictly: angle[{a.size - 2}] = {a[-2]:.10g} is at the cycle's end"
            )
        scale = float(np.max(np.abs(p)))
        mismatch = abs(float(p[-1] - p[0]))
        if mismatch > tolerance * scale:
            raise MechanismError(
                f"pressure does not close over the cycle: p = {p[0]:.10g} Pa at angle {a[0]:.10g} rad but "
                f"{p[-1]:.10g} Pa at angle {a[-1]:.10g} rad (one cycle later), a mismatch of {mismatch:.6g} Pa = "
                f"{mismatch / scale:.3g} of max|p|, above closure_tolerance = {tolerance}; the first and last "
                f"points are the same state of the cycle (raise closure_tolerance to accept the data as it is)"
            )
        p = p.copy()
        p[-1] = p[0]
        a.flags.writeable = False
        p.flags.writeable = False
        self._angle, self._pressure, self._cycle, self._kind = a, p, cycle, kind
        self._poly = _interpolant(a, p, cycle, kind)
        self._derivative: Any = None

    # -- what it is ---------------------------------------------------------------------------

    @property
    def angle(self) -> np.ndarray:
        """The table's cycle angles θ [rad] (read-only; the last is the first plus the cycle)."""
        return self._angle

    @property
    def pressure(self) -> np.ndarray:
        """The table's gauge pressures [Pa] (read-only; the last equals the first)."""
        return self._pressure

    @property
    def breakpoints(self) -> np.ndarray:
        """The table's angles [rad], where the interpolant may have kinks: split quadratures there."""
        return self._angle

    @property
    def cycle(self) -> float:
        """The working cycle Φ [rad]: 2π or 4π."""
        return self._cycle

    @property
    def strokes(self) -> int:
        """2 or 4: the strokes of the working cycle."""
        return 2 if self._cycle == _TWO_STROKE else 4

    @property
    def kind(self) -> str:
        """The interpolation: "periodic-cubic", "pchip" or "linear"."""
        return self._kind

    def __repr__(self) -> str:
        return (
            f"IndicatorDiagram({self._angle.size} points over {_cycle_name(self._cycle)}, kind={self._kind!r}, "
            f"p from {float(np.min(self._pressure)):.6g} to {float(np.max(self._pressure)):.6g} Pa gauge)"
        )

    # -- evaluation ---------------------------------------------------------------------------

    def _wrap(self, theta: Any) -> np.ndarray:
        t = as_angles(theta, "theta")
        with np.errstate(invalid="ignore"):
            return self._angle[0] + np.mod(t - self._angle[0], self._cycle)

    def __call__(self, theta: Any) -> np.ndarray | np.float64:
        """The gauge pressure at cycle angles θ, taken modulo the cycle.

        Parameters
        ----------
        theta : array_like
            Cycle angles θ [rad], any shape.

        Returns
        -------
        ndarray or numpy.float64
            p(θ) [Pa] gauge, the shape of ``theta`` (a numpy float64 for a scalar); NaN
            where θ is NaN or ±inf.
        """
        values = np.asarray(self._poly(self._wrap(theta)), dtype=np.float64)
        return values[()] if values.ndim == 0 else values

    def derivative(self, theta: Any) -> np.ndarray | np.float64:
        """The slope of the interpolant, dp/dθ, at cycle angles θ taken modulo the cycle.

        Parameters
        ----------
        theta : array_like
            Cycle angles θ [rad], any shape.

        Returns
        -------
        ndarray or numpy.float64
            dp/dθ [Pa/rad], the shape of ``theta``.
        """
        if self._derivative is None:
            self._derivative = self._poly.derivative()
        values = np.asarray(self._derivative(self._wrap(theta)), dtype=np.float64)
        return values[()] if values.ndim == 0 else values

    def mean_pressure(self) -> float:
        """The cycle mean of the gauge pressure, (1/Φ)∮p dθ, exact for the interpolant.

        This is the mean over the crank angle, not the mean effective pressure (work per
        displacement): for that, divide :meth:`indicated_work` by the swept volume.

        Returns
        -------
        float
            The mean [Pa] gauge.
        """
        start = float(self._angle[0])
        return float(self._poly.integrate(start, start + self._cycle)) / self._cycle

    def indicated_work(self, volume: Callable[[np.ndarray], Any]) -> float:
        """The work of the gas on the piston over one cycle, ∮p dV [J].

        Parameters
        ----------
        volume : callable
            The cylinder volume V(θ) [m³], vectorised over θ [rad], periodic over the cycle
            (it is called with θ taken modulo the cycle).

        Returns
        -------
        float
            ∮p dV [J]: positive for an engine, negative for a compressor (the work it takes).
            Gauge or absolute pressure give the same, ∮p_ref dV being 0.

        Notes
        -----
        Computed as −∮V dp (V and p periodic) with Gauss–Legendre quadrature on each interval
        of the table, where dp/dθ is the interpolant's exact piecewise polynomial: no
        derivative of V is needed, and the kinks at the breakpoints are honoured.
        """
        shape = _Volume(volume, self._cycle, samples=16)
        if self._derivative is None:
            self._derivative = self._poly.derivative()
        a = self._angle
        nodes, weights = _gauss()
        half = 0.5 * np.diff(a)
        t = (0.5 * (a[:-1] + a[1:]))[:, None] + half[:, None] * nodes[None, :]
        integrand = shape.wrapped(t) * self._derivative(t)
        return -float(np.sum(half * (integrand @ weights)))

    # -- from a file --------------------------------------------------------------------------

    @classmethod
    def from_csv(
        cls,
        path: str | os.PathLike[str],
        *,
        angle_unit: str = "deg",
        pressure_unit: str = "Pa",
        absolute: bool = False,
        reference_pressure: float = STANDARD_ATMOSPHERE,
        cycle: float | None = None,
        angle_column: int | str = 0,
        pressure_column: int | str = 1,
        delimiter: str | None = None,
        kind: str = "periodic-cubic",
        closure_tolerance: float = 1e-6,
    ) -> IndicatorDiagram:
        """An indicator diagram from a CSV file of (angle, pressure) rows.

        Parameters
        ----------
        path : str or os.PathLike
            The file (UTF-8 text). Blank lines and lines starting with ``#`` are skipped; the
            first other line may be a header (it is one when its angle or pressure field is not
            a number). Every further line holds at least the two columns, as numbers.
        angle_unit : {"deg", "rad"}, default "deg"
            The unit of the angle column.
        pressure_unit : {"Pa", "kPa", "bar", "MPa", "psi"}, default "Pa"
            The unit of the pressure column (psi = lbf/in² = 6894.757… Pa).
        absolute : bool, default False
            True: the pressures are absolute, and ``reference_pressure`` is subtracted to make
            them gauge. False: they are gauge already.
        reference_pressure : float, default 101325.0
            The crankcase (reference) pressure [Pa] for ``absolute=True``.
        cycle : float, optional
            The working cycle [rad], 2π or 4π; by default inferred from the angles' span.
        angle_column, pressure_column : int or str, default 0 and 1
            The columns, counted from 0, or their names in the header.
        delimiter : str, optional
            The field separator; by default the first of ``,``, ``;`` and tab found on the
            first data line, else runs of white space.
        kind : {"periodic-cubic", "pchip", "linear"}, default "periodic-cubic"
            The interpolation, as for :class:`IndicatorDiagram`.
        closure_tolerance : float, default 1e-6
            How far [relative to max|p|] the last pressure may be from the first, as for
            :class:`IndicatorDiagram`.

        Returns
        -------
        IndicatorDiagram
            Gauge pressures [Pa].

        Raises
        ------
        MechanismError
            For a missing, unreadable or non-text file, a directory, a bad field (naming the
            file, line and column), an unknown unit, or a table that is no indicator diagram
            (the constructor's checks, prefixed with the file name).

        Examples
        --------
        The package's synthetic example table (``EXAMPLE_COMPRESSOR_CSV``; angles in degrees,
        absolute pressures in bar):

        >>> import numpy as np
        >>> import multicrank as mc
        >>> from multicrank.pressure import EXAMPLE_COMPRESSOR_CSV
        >>> diagram = mc.IndicatorDiagram.from_csv(EXAMPLE_COMPRESSOR_CSV,
        ...                                        pressure_unit="bar", absolute=True)
        >>> diagram.angle.size, diagram.strokes, diagram.kind
        (75, 2, 'periodic-cubic')
        >>> (diagram(np.radians([0, 180])) / 1e5).round(5)  # bar gauge
        array([ 6.98675, -0.01325])
        """
        angle_unit = as_option(angle_unit, "angle_unit", tuple(ANGLE_UNITS))
        pressure_unit = as_option(pressure_unit, "pressure_unit", tuple(PRESSURE_UNITS))
        absolute = _flag(absolute, "absolute")
        reference = _finite(reference_pressure, "reference_pressure")
        if cycle is not None:
            cycle = _as_cycle(cycle)
        columns: dict[str, int | str] = {}
        for value, name in ((angle_column, "angle_column"), (pressure_column, "pressure_column")):
            columns[name] = value if isinstance(value, str) else as_count(value, name, minimum=0)
        if columns["angle_column"] == columns["pressure_column"]:
            raise MechanismError(f"angle_column and pressure_column must differ, both are {angle_column!r}")
        if delimiter is not None and not (isinstance(delimiter, str) and len(delimiter) == 1):
            raise MechanismError(f"delimiter must be one character or None, got {delimiter!r}")
        try:
            name = os.fspath(path)
        except TypeError:
            raise MechanismError(f"path must be a file path (str or os.PathLike), got {type(path).__name__}") from None
        angles, pressures = _read_table(name, delimiter, columns)
        angles = angles * ANGLE_UNITS[angle_unit]
        pressures = pressures * PRESSURE_UNITS[pressure_unit]
        if absolute:
            pressures = pressures - reference
        if cycle is None:
            span = float(angles[-1] - angles[0])
            for candidate in (_TWO_STROKE, _FOUR_STROKE):
                if abs(span - candidate) <= _SPAN_TOLERANCE * candidate:
                    cycle = candidate
            if cycle is None:
                raise MechanismError(
                    f"{name}: cannot infer the cycle: the angles span {_degrees(span)} ({span:.10g} rad, angle_unit = "
                    f"{angle_unit!r}), neither 360° nor 720°; a table covers one cycle with its first point repeated "
                    f"at the end (or pass cycle=)"
                )
        try:
            return cls(angles, pressures, cycle=cycle, kind=kind, closure_tolerance=closure_tolerance)
        except MechanismError as error:
            raise MechanismError(f"{name}: {error}") from None

    # -- synthetic cycles ---------------------------------------------------------------------

    @classmethod
    def compressor(
        cls,
        volume: Callable[[np.ndarray], Any],
        *,
        suction_pressure: float,
        discharge_pressure: float,
        polytropic_exponent: float = 1.3,
        cycle: float = _TWO_STROKE,
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
        cycle = _as_cycle(cycle)
        points = as_count(points, "points", minimum=8)
        absolute = _flag(absolute, "absolute")
        reference = _finite(reference_pressure, "reference_pressure")
        n = _finite(polytropic_exponent, "polytropic_exponent", above=0.0)
        shift = 0.0 if absolute else reference
        p_s = _finite(suction_pressure, "suction_pressure") + shift
        p_d = _finite(discharge_pressure, "discharge_pressure") + shift
        if not p_s > 0:
            raise MechanismError(f"suction_pressure = {suction_pressure} must be above vacuum (absolute {p_s} Pa > 0)")
        if not p_d > p_s:
            raise MechanismError(
                f"discharge_pressure = {discharge_pressure} must exceed suction_pressure = {suction_pressure}"
            )
        kind = as_option(kind, "kind", INTERPOLATIONS)
        vol = _Volume(volume, cycle, samples=max(points, 720))
        angles, volumes, minima = vol.dead_centres()
        ratio = (p_d / p_s) ** (1.0 / n)
        ends = np.append(angles, angles[0] + cycle)
        events = []
        for j, start in enumerate(volumes):
            end = volumes[(j + 1) % volumes.size]
            if minima[j]:  # expanding: re-expansion until suction opens at V_a·ratio
                target = start * ratio
                if not target < end:
                    raise MechanismError(
                        f"volume: the re-expansion of the clearance volume {start:.10g} m³ from discharge_pressure "
                        f"reaches suction_pressure only at {target:.10g} m³, beyond the largest volume {end:.10g} m³: "
                        f"the clearance is too large for this pressure ratio (the compressor delivers nothing)"
                    )
            else:  # shrinking: compression until discharge opens at V_b/ratio
                target = start / ratio
                if not target > end:
                    raise MechanismError(
                        f"volume: compression from the largest volume {start:.10g} m³ reaches discharge_pressure "
                        f"only at {target:.10g} m³, below the smallest volume {end:.10g} m³ (the compressor "
                        "delivers nothing)"
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

    @classmethod
    def engine(
        cls,
        volume: Callable[[np.ndarray], Any],
        *,
        intake_pressure: float,
        heat_release: float,
        cycle: float = _FOUR_STROKE,
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
        cycle = _as_cycle(cycle)
        points = as_count(points, "points", minimum=8)
        absolute = _flag(absolute, "absolute")
        reference = _finite(reference_pressure, "reference_pressure")
        p_gas = _finite(intake_pressure, "intake_pressure") + (0.0 if absolute else reference)
        if not p_gas > 0:
            raise MechanismError(f"intake_pressure = {intake_pressure} must be above vacuum (absolute {p_gas} Pa > 0)")
        heat = _finite(heat_release, "heat_release", at_least=0.0)
        theta0 = _finite(start_of_combustion, "start_of_combustion")
        duration = _finite(combustion_duration, "combustion_duration", above=0.0)
        kappa_c = _finite(compression_exponent, "compression_exponent", above=1.0)
        kappa_e = _finite(expansion_exponent, "expansion_exponent", above=1.0)
        a = _finite(wiebe_a, "wiebe_a", above=0.0)
        m = _finite(wiebe_m, "wiebe_m", above=-1.0)
        opening = _finite(exhaust_opening, "exhaust_opening", above=0.0)
        closing = _finite(intake_closing, "intake_closing", at_least=0.0)
        kind = as_option(kind, "kind", INTERPOLATIONS)

        vol = _Volume(volume, cycle, samples=max(points, 1440))
        angles, _, minima = vol.dead_centres()
        revolutions = round(cycle / _TWO_STROKE)
        if angles.size != 2 * revolutions:
            raise MechanismError(
                f"volume must have one minimum and one maximum per revolution; it has {int(np.sum(minima))} minima "
                f"and {int(np.sum(~minima))} maxima over the cycle {_cycle_name(cycle)}"
            )
        first = np.flatnonzero(minima)
        off = np.min(np.abs(np.remainder(angles[first] + 0.5 * cycle, cycle) - 0.5 * cycle))
        if off > 1e-5 * cycle:
            raise MechanismError(
                "volume must be smallest at θ = 0 (outer dead centre, the firing dead centre); "
                f"its minimum nearest θ = 0 is {off:.10g} rad away"
            )
        inner = angles[~minima]
        bdc_first, bdc_last = float(inner[0]), float(inner[-1])
        if not opening < bdc_first:
            raise MechanismError(
                f"exhaust_opening = {opening} is out of range; allowed: 0 < exhaust_opening < {bdc_first!r} "
                f"(the inner dead centre ending the expansion)"
            )
        if not bdc_last + closing < cycle:
            raise MechanismError(
                f"intake_closing = {closing} is out of range; allowed: 0 <= intake_closing < {cycle - bdc_last!r} "
                f"(before the firing dead centre)"
            )
        t_open = bdc_first - opening  # exhaust opens (t ≥ 0)
        t_close = bdc_last + closing - cycle  # intake closes (t < 0: before the firing dead centre)
        if not theta0 >= t_close:
            raise MechanismError(
                f"start_of_combustion = {theta0} is out of range; allowed: start_of_combustion >= {t_close!r} "
                f"(intake closing, relative to the firing dead centre)"
            )
        if not theta0 + duration <= t_open:
            raise MechanismError(
                f"combustion_duration = {duration} is out of range: combustion would end at {theta0 + duration!r} "
                f"rad, after the exhaust opens at {t_open!r} rad; allowed: start_of_combustion + "
                f"combustion_duration <= {t_open!r}"
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
            nodes, weights = _gauss()
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


def _interpolant(a: np.ndarray, p: np.ndarray, cycle: float, kind: str) -> Any:
    """A scipy PPoly over [a[0], a[0] + Φ], periodic in value (and slope, but for "linear")."""
    interpolate = _scipy_interpolate()
    if kind == "periodic-cubic":
        return interpolate.CubicSpline(a, p, bc_type="periodic")
    if kind == "linear":
        return interpolate.PPoly(np.vstack((np.diff(p) / np.diff(a), p[:-1])), a)
    # PCHIP on the table extended by a period's worth of neighbours on both sides, cut back
    # to the table: the slopes at its ends come from the same neighbours, so they agree.
    n = a.size
    k = min(3, n - 1)
    extended_a = np.concatenate((a[n - 1 - k : n - 1] - cycle, a, a[1 : 1 + k] + cycle))
    extended_p = np.concatenate((p[n - 1 - k : n - 1], p, p[1 : 1 + k]))
    full = interpolate.PchipInterpolator(extended_a, extended_p)
    return interpolate.PPoly(full.c[:, k : k + n - 1].copy(), a)


def _read_table(name: str, delimiter: str | None, columns: dict[str, int | str]) -> tuple[np.ndarray, np.ndarray]:
    """The angle and pressure columns of a CSV file, as written (no units applied)."""
    try:
        with open(name, encoding="utf-8", newline="") as handle:
            text = handle.read()
    except FileNotFoundError:
        raise MechanismError(f"path = {name!r}: no such file") from None
    except IsADirectoryError:
        raise MechanismError(f"path = {name!r} is a directory, not a CSV file") from None
    except UnicodeDecodeError as error:
        raise MechanismError(
            f"path = {name!r} is not a UTF-8 text file: {error.reason} at byte {error.start}"
        ) from None
    except OSError as error:
        raise MechanismError(f"path = {name!r} cannot be read: {error.strerror or error}") from None

    def split(line: str) -> list[str]:
        if separator is None:
            return line.split()
        return [field.strip() for field in next(csv.reader([line], delimiter=separator))]

    separator = delimiter if delimiter is not None and not delimiter.isspace() else None
    sniffed = delimiter is not None
    index: dict[str, int] = {}
    angles: list[float] = []
    pressures: list[float] = []
    lines: list[int] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        if not sniffed:
            separator = next((d for d in (",", ";", "\t") if d in line), None)
            sniffed = True
        fields = split(line)
        if not index:  # the first data line: header or data
            named = any(isinstance(column, str) for column in columns.values())
            if named or not _numbers(fields, columns):
                for key, column in columns.items():
                    if isinstance(column, str):
                        if column not in fields:
                            raise MechanismError(
                                f"{name}, line {number}: {key} = {column!r} is not in the header {fields}"
                            )
                        index[key] = fields.index(column)
                    else:
                        index[key] = column
                continue
            index = {key: int(column) for key, column in columns.items()}
        values = []
        for key in ("angle_column", "pressure_column"):
            column = index[key]
            if column >= len(fields):
                raise MechanismError(
                    f"{name}, line {number}: {len(fields)} column(s), but {key} = {column} (counted from 0)"
                )
            try:
                value = float(fields[column])
            except ValueError:
                raise MechanismError(
                    f"{name}, line {number}, column {column} ({key}): {fields[column]!r} is not a number"
                ) from None
            if not math.isfinite(value):
                raise MechanismError(
                    f"{name}, line {number}, column {column} ({key}): {fields[column]!r} is not a finite number"
                )
            values.append(value)
        if angles and not values[0] > angles[-1]:
            raise MechanismError(
                f"{name}, line {number}, column {index['angle_column']} (angle_column): the angle {values[0]!r} does "
                f"not increase on line {lines[-1]}'s {angles[-1]!r}; the angles must increase strictly"
            )
        angles.append(values[0])
        pressures.append(values[1])
        lines.append(number)
    if len(angles) < 4:
        raise MechanismError(f"{name}: {len(angles)} data row(s); an indicator diagram needs at least 4")
    return np.asarray(angles), np.asarray(pressures)


def _numbers(fields: list[str], columns: dict[str, int | str]) -> bool:
    """Whether the angle and pressure fields of a line are numbers (else it is a header)."""
    for value in columns.values():
        if isinstance(value, str) or value >= len(fields):
            return False
        try:
            float(fields[value])
        except ValueError:
            return False
    return True
