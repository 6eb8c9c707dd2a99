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

import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .._broadcasting import as_angles
from .._native import MechanismError
from .._validation import as_count, as_flag, as_option, refused
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
from ._interpolant import _SPAN_TOLERANCE, _degrees, checked_table, interpolant
from .synthetic import Volume
from .synthetic import compressor as _compressor
from .synthetic import engine as _engine
from .tables import read_columns
from .units import ANGLE_UNITS, PLAUSIBLE_PRESSURES, PRESSURE_UNITS, PressureUnitWarning, check_pressure_unit

__all__ = [
    "ANGLE_UNITS",
    "EXAMPLE_COMPRESSOR_CSV",
    "INTERPOLATIONS",
    "PLAUSIBLE_PRESSURES",
    "PRESSURE_UNITS",
    "STANDARD_ATMOSPHERE",
    "IndicatorDiagram",
    "PressureUnitWarning",
    "check_pressure_unit",
]

#: A small **synthetic** example table (not measured), made by :meth:`IndicatorDiagram.compressor`;
#: its header says how. Read it with ``from_csv(EXAMPLE_COMPRESSOR_CSV, pressure_unit="bar", absolute=True)``.
EXAMPLE_COMPRESSOR_CSV = Path(__file__).resolve().parent.parent / "data" / "compressor_synthetic.csv"


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
        the torques' products would overflow). However small a pressure is, it is kept as
        given (``diagram.pressure``), never taken as 0: the motion is homogeneous in the
        masses, inertias and pressures, so a machine with all of them 10⁻¹⁰⁰ times smaller has
        the same δ.
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
        a, p = checked_table(angle, pressure, cycle, tolerance)
        self._angle, self._pressure, self._cycle, self._kind = a, p, cycle, kind
        self._poly = interpolant(a, p, cycle, kind)
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
            raise refused("angle_column", f"angle_column and pressure_column must differ, both are {angle_column!r}")
        if delimiter is not None and not (isinstance(delimiter, str) and len(delimiter) == 1):
            raise refused("delimiter", f"delimiter must be one character or None, got {delimiter!r}")
        try:
            name = os.fspath(path)
        except TypeError:
            raise refused("path", f"path must be a file path (str or os.PathLike), got {type(path).__name__}") from None
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
                raise refused(
                    "cycle",
                    f"{name}: cannot infer the cycle: the angles span {_degrees(span)} ({span:.10g} rad, angle_unit = "
                    f"{angle_unit!r}), neither 360° nor 720°; a table covers one cycle with its first point repeated "
                    f"at the end (or pass cycle=)",
                )
        try:
            diagram = cls(angles, pressures, cycle=cycle, kind=kind, closure_tolerance=closure_tolerance)
        except MechanismError as error:
            raise refused("path", f"{name}: {error}") from None
        # After the table's own checks: a table refused for a fault of its own says that alone.
        check_pressure_unit(pressures + (reference if absolute else 0.0), pressure_unit, name, stacklevel=2)
        return diagram

    # -- synthetic cycles: written, with their documentation, in multicrank.pressure.synthetic --

    compressor = classmethod(_compressor)
    engine = classmethod(_engine)
