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

import math
import os
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .._native import MechanismError
from .._validation import MAGNITUDE_LIMIT, as_angles, as_count, as_flag, as_option, as_real_array
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
from .synthetic import Volume
from .synthetic import compressor as _compressor
from .synthetic import engine as _engine
from .tables import read_columns

__all__ = [
    "ANGLE_UNITS",
    "EXAMPLE_COMPRESSOR_CSV",
    "INTERPOLATIONS",
    "PLAUSIBLE_PRESSURES",
    "PRESSURE_FLOOR",
    "PRESSURE_UNITS",
    "STANDARD_ATMOSPHERE",
    "IndicatorDiagram",
    "PressureUnitWarning",
    "check_pressure_unit",
]

#: Pressure units of :meth:`IndicatorDiagram.from_csv`: Pa per unit (psi: lbf/in², exact).
PRESSURE_UNITS = {"Pa": 1.0, "kPa": 1e3, "bar": 1e5, "MPa": 1e6, "psi": 0.45359237 * 9.80665 / 0.0254**2}
#: Angle units of :meth:`IndicatorDiagram.from_csv`: rad per unit.
ANGLE_UNITS = {"deg": math.pi / 180.0, "rad": 1.0}
#: A small **synthetic** example table (not measured), made by :meth:`IndicatorDiagram.compressor`;
#: its header says how. Read it with ``from_csv(EXAMPLE_COMPRESSOR_CSV, pressure_unit="bar", absolute=True)``.
EXAMPLE_COMPRESSOR_CSV = Path(__file__).resolve().parent.parent / "data" / "compressor_synthetic.csv"

#: Pressures of smaller magnitude [Pa] are taken as exactly 0 by :class:`IndicatorDiagram`: a
#: gauge pressure of 1e-30 Pa is zero for any machine, and values down in the subnormal range
#: (below ~2.2e-308) would make the interpolation's slopes overflow (PCHIP divides by them).
PRESSURE_FLOOR = 1e-30

# A table must span one cycle to this fraction of the cycle (6e-6 rad for 2π): loose
# enough for angles printed with six digits, tight enough to catch a missing point.
_SPAN_TOLERANCE = 1e-6


#: The range [Pa] the largest pressure of a machine's gas lies in, 1 mbar … 5000 bar (the
#: highest, in hyper-compressors, are about 3500 bar; a fired engine's peak is 50 … 300 bar):
#: a table whose largest magnitude, in the unit it was given in, falls outside is most likely
#: in another unit, and :class:`PressureUnitWarning` says so.
PLAUSIBLE_PRESSURES = (1e2, 5e8)


class PressureUnitWarning(UserWarning):
    """Pressures given in a unit that makes them implausible for any machine — a peak of
    8·10⁵ bar, or of 3 Pa — most likely in another unit than the one named (Pa where bar is
    expected). The message names the file or key, the peak and the likely unit."""


def check_pressure_unit(pressures: Any, unit: str, where: str, *, stacklevel: int = 2) -> None:
    """Warn (:class:`PressureUnitWarning`) when the largest magnitude of ``pressures`` [Pa],
    given in ``unit`` (a key of :data:`PRESSURE_UNITS`), is outside :data:`PLAUSIBLE_PRESSURES`
    (all zero is no gas, and plausible). ``where``: the file or key, for the message;
    ``stacklevel``: as :func:`warnings.warn` takes it, seen from the caller (2: its caller's line)."""
    peak = float(np.max(np.abs(pressures), initial=0.0))
    low, high = PLAUSIBLE_PRESSURES
    if peak == 0.0 or low <= peak <= high:
        return
    written = peak / PRESSURE_UNITS[unit]  # the peak as the table has it
    # The unit that puts the peak nearest 10 bar, among those that make it plausible.
    fits = [u for u, factor in PRESSURE_UNITS.items() if u != unit and low <= written * factor <= high]
    likely = min(fits, key=lambda u: abs(math.log10(written * PRESSURE_UNITS[u] / 1e6)), default=None)
    side = (
        f"above {high / 1e5:g} bar, more than any machine's gas"
        if peak > high
        else (f"below {low / 1e2:g} mbar, less than any machine's gas")
    )
    question = f"; did you give {likely} where {unit} is expected?" if likely else ""
    warnings.warn(
        f"{where}: the largest pressure is {written:g} {unit} = {peak / 1e5:.4g} bar, {side}{question} "
        f"(pressure_unit = {unit!r})",
        PressureUnitWarning,
        stacklevel=stacklevel + 1,
    )


def _scipy_interpolate() -> Any:
    import scipy.interpolate  # type: ignore[import-untyped,unused-ignore]

    return scipy.interpolate


# -- messages ---------------------------------------------------------------------------------


def _degrees(angle: float) -> str:
    return f"{math.degrees(angle):.6g}°"


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
        crankcase side is 0). Finite, at most 1e30 Pa in magnitude (``MAGNITUDE_LIMIT``, where
        the torques' products would overflow). A magnitude below ``PRESSURE_FLOOR`` = 1e-30 Pa is taken
        as exactly 0 (physically it is; and a subnormal value such as 2.2e-309 would overflow
        the interpolation's slopes): ``diagram.pressure`` holds the table so flushed.
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
        cycle = as_cycle(cycle)
        kind = as_option(kind, "kind", INTERPOLATIONS)
        tolerance = as_finite(closure_tolerance, "closure_tolerance", at_least=0.0)
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
        huge = np.flatnonzero(np.abs(p) > MAGNITUDE_LIMIT)
        if huge.size:
            raise MechanismError(
                f"pressure[{huge[0]}] = {p[huge[0]]:g} is out of range; allowed: |pressure| <= {MAGNITUDE_LIMIT:g} [Pa]"
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
                f"but cycle = {cycle_name(cycle)} = {cycle:.10g} rad ({_degrees(cycle)}); the last angle must be the "
                f"first plus the cycle, the first point repeated at the end"
            )
        a = a.copy()
        a[-1] = a[0] + cycle
        if not a[-1] > a[-2]:
            raise MechanismError(
                f"angle must increase strictly: angle[{a.size - 2}] = {a[-2]:.10g} is at the cycle's end"
            )
        p = np.where(np.abs(p) < PRESSURE_FLOOR, 0.0, p)
        scale = float(np.max(np.abs(p)))
        mismatch = abs(float(p[-1] - p[0]))
        if mismatch > tolerance * scale:
            raise MechanismError(
                f"pressure does not close over the cycle: p = {p[0]:.10g} Pa at angle {a[0]:.10g} rad but "
                f"{p[-1]:.10g} Pa at angle {a[-1]:.10g} rad (one cycle later), a mismatch of {mismatch:.6g} Pa = "
                f"{mismatch / scale:.3g} of max|p|, above closure_tolerance = {tolerance}; the first and last "
                f"points are the same state of the cycle (raise closure_tolerance to accept the data as it is)"
            )
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
        return 2 if self._cycle == TWO_STROKE else 4

    @property
    def kind(self) -> str:
        """The interpolation: "periodic-cubic", "pchip" or "linear"."""
        return self._kind

    def __repr__(self) -> str:
        return (
            f"IndicatorDiagram({self._angle.size} points over {cycle_name(self._cycle)}, kind={self._kind!r}, "
            f"p from {float(np.min(self._pressure)):.6g} to {float(np.max(self._pressure)):.6g} Pa gauge)"
        )

    # -- a value: equal tables are equal diagrams -----------------------------------------------

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, IndicatorDiagram):
            return NotImplemented
        return (
            self._cycle == other._cycle
            and self._kind == other._kind
            and np.array_equal(self._angle, other._angle)
            and np.array_equal(self._pressure, other._pressure)
        )

    def __hash__(self) -> int:
        # + 0.0 makes −0.0 into 0.0, which == takes for equal (the table holds no NaN).
        return hash((self._cycle, self._kind, (self._angle + 0.0).tobytes(), (self._pressure + 0.0).tobytes()))

    def __getstate__(self) -> dict[str, Any]:
        # A pickle (and a copy) carries the table only; the interpolant is rebuilt from it, so
        # that a pickle does not hold SciPy's objects and their private module paths.
        return {"angle": self._angle, "pressure": self._pressure, "cycle": self._cycle, "kind": self._kind}

    def __setstate__(self, state: Any) -> None:
        if isinstance(state, tuple):  # multicrank 0.1's pickles: (None, the slots, "_poly" included)
            slots = state[1]
            state = {key: slots[f"_{key}"] for key in ("angle", "pressure", "cycle", "kind")}
        self.__init__(state["angle"], state["pressure"], cycle=state["cycle"], kind=state["kind"])  # type: ignore[misc]

    # -- a changed copy -----------------------------------------------------------------------

    def scaled(self, factor: Any) -> IndicatorDiagram:
        """The same diagram with every pressure multiplied by ``factor``.

        Parameters
        ----------
        factor : float
            The multiplier [dimensionless], finite: 1.2 for 20 % more load, 0 for no gas.

        Returns
        -------
        IndicatorDiagram
            The table's angles, its pressures times ``factor``, the same cycle and
            interpolation (``self`` itself for a factor of 1).

        Examples
        --------
        >>> import numpy as np
        >>> import multicrank as mc
        >>> diagram = mc.IndicatorDiagram(np.radians([0, 90, 180, 270, 360]),
        ...                               [30e5, 8e5, 0.0, 2e5, 30e5], cycle=2 * np.pi, kind="linear")
        >>> float(diagram.scaled(1.5)(np.radians(45)) / 1e5)  # bar
        28.5
        """
        value = as_finite(factor, "factor")
        if value == 1.0:
            return self
        return IndicatorDiagram(self._angle, self._pressure * value, cycle=self._cycle, kind=self._kind)

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
        shape = Volume(volume, self._cycle, samples=16)
        if self._derivative is None:
            self._derivative = self._poly.derivative()
        a = self._angle
        nodes, weights = gauss()
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
            True: the pressures are absolute (none below 0, vacuum), and ``reference_pressure``
            is subtracted to make them gauge. False: they are gauge already.
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
            file, line and column; with ``absolute=True`` also a negative pressure), an unknown
            unit, or a table that is no indicator diagram (the constructor's checks, prefixed
            with the file name).

        Warns
        -----
        multicrank.pressure.PressureUnitWarning
            When the table's largest pressure, in ``pressure_unit``, is outside
            :data:`~multicrank.pressure.PLAUSIBLE_PRESSURES` (1 mbar … 5000 bar): most likely the table is in
            another unit (Pa read as bar), and the warning names the likely one.

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
        absolute = as_flag(absolute, "absolute")
        reference = as_finite(reference_pressure, "reference_pressure")
        if cycle is not None:
            cycle = as_cycle(cycle)
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
        angles, pressures = read_columns(name, delimiter, columns, absolute=absolute)
        angles = angles * ANGLE_UNITS[angle_unit]
        pressures = pressures * PRESSURE_UNITS[pressure_unit]
        if absolute:
            pressures = pressures - reference
        if cycle is None:
            span = float(angles[-1] - angles[0])
            for candidate in (TWO_STROKE, FOUR_STROKE):
                if abs(span - candidate) <= _SPAN_TOLERANCE * candidate:
                    cycle = candidate
            if cycle is None:
                raise MechanismError(
                    f"{name}: cannot infer the cycle: the angles span {_degrees(span)} ({span:.10g} rad, angle_unit = "
                    f"{angle_unit!r}), neither 360° nor 720°; a table covers one cycle with its first point repeated "
                    f"at the end (or pass cycle=)"
                )
        try:
            diagram = cls(angles, pressures, cycle=cycle, kind=kind, closure_tolerance=closure_tolerance)
        except MechanismError as error:
            raise MechanismError(f"{name}: {error}") from None
        # After the table's own checks: a table refused for a fault of its own says that alone.
        check_pressure_unit(pressures + (reference if absolute else 0.0), pressure_unit, name, stacklevel=2)
        return diagram

    # -- synthetic cycles: written, with their documentation, in multicrank.pressure.synthetic --

    compressor = classmethod(_compressor)
    engine = classmethod(_engine)


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
