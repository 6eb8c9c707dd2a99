"""The table of an :class:`~multicrank.IndicatorDiagram`: its checks, and its periodic
interpolant (SciPy, imported only when a diagram is built)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._validation import MAGNITUDE_LIMIT, as_real_array, refused
from ._cycle import cycle_name

# A table must span one cycle to this fraction of the cycle (6e-6 rad for 2π): loose
# enough for angles printed with six digits, tight enough to catch a missing point.
_SPAN_TOLERANCE = 1e-6


def _scipy_interpolate() -> Any:
    import scipy.interpolate  # type: ignore[import-untyped,unused-ignore]

    return scipy.interpolate


def _degrees(angle: float) -> str:
    return f"{math.degrees(angle):.6g}°"


def checked_table(angle: Any, pressure: Any, cycle: float, tolerance: float) -> tuple[np.ndarray, np.ndarray]:
    """The diagram's table (θ [rad], p [Pa]) checked, its end set to one cycle after its start
    and its last pressure set to its first; read-only. Every pressure is kept as given, however
    small: the motion is homogeneous in the masses, inertias and pressures, so a machine with
    all of them 10⁻¹⁰⁰ times smaller has the same δ. Raises :class:`MechanismError` naming the
    parameter (the constructor's checks)."""
    a = as_real_array(angle, "angle")
    p = as_real_array(pressure, "pressure")
    for array, name in ((a, "angle"), (p, "pressure")):
        if array.ndim != 1:
            raise refused(name, f"{name} must be a 1-D array, got shape {array.shape}")
    if a.size != p.size:
        raise refused("angle", f"angle and pressure must have the same length, got {a.size} and {p.size}")
    if a.size < 4:
        raise refused("angle", f"angle must hold at least 4 points (the first repeated at the end), got {a.size}")
    for array, name, unit in ((a, "angle", "rad"), (p, "pressure", "Pa")):
        bad = np.flatnonzero(~np.isfinite(array))
        if bad.size:
            raise refused(name, f"{name}[{bad[0]}] = {array[bad[0]]} is not finite; {name} must be finite [{unit}]")
    huge = np.flatnonzero(np.abs(p) > MAGNITUDE_LIMIT)
    if huge.size:
        raise refused(
            "pressure",
            f"pressure[{huge[0]}] = {p[huge[0]]:g} is out of range; allowed: |pressure| <= {MAGNITUDE_LIMIT:g} [Pa]",
        )
    steps = np.diff(a)
    bad = np.flatnonzero(~(steps > 0))
    if bad.size:
        i = bad[0]
        raise refused(
            "angle", f"angle must increase strictly: angle[{i + 1}] = {a[i + 1]:.10g} follows angle[{i}] = {a[i]:.10g}"
        )
    span = a[-1] - a[0]
    if abs(span - cycle) > _SPAN_TOLERANCE * cycle:
        raise refused(
            "angle",
            f"angle must cover exactly one cycle: it spans {span:.10g} rad ({_degrees(span)}) from {a[0]:.10g}, "
            f"but cycle = {cycle_name(cycle)} = {cycle:.10g} rad ({_degrees(cycle)}); the last angle must be the "
            f"first plus the cycle, the first point repeated at the end",
        )
    a = a.copy()
    a[-1] = a[0] + cycle
    if not a[-1] > a[-2]:
        raise refused(
            "angle", f"angle must increase strictly: angle[{a.size - 2}] = {a[-2]:.10g} is at the cycle's end"
        )
    p = p.copy()
    scale = float(np.max(np.abs(p)))
    mismatch = abs(float(p[-1] - p[0]))
    if mismatch > tolerance * scale:
        raise refused(
            "pressure",
            f"pressure does not close over the cycle: p = {p[0]:.10g} Pa at angle {a[0]:.10g} rad but "
            f"{p[-1]:.10g} Pa at angle {a[-1]:.10g} rad (one cycle later), a mismatch of {mismatch:.6g} Pa = "
            f"{mismatch / scale:.3g} of max|p|, above closure_tolerance = {tolerance}; the first and last "
            f"points are the same state of the cycle (raise closure_tolerance to accept the data as it is)",
        )
    p[-1] = p[0]
    a.flags.writeable = False
    p.flags.writeable = False
    return a, p


def interpolant(a: np.ndarray, p: np.ndarray, cycle: float, kind: str) -> Any:
    """A scipy PPoly over [a[0], a[0] + Φ], periodic in value (and slope, but for "linear").

    It is built on the table divided by a power of two that brings max|p| into [0.5, 1) —
    exact, and every interpolation here is homogeneous in p — and its coefficients multiplied
    back: a table of 10⁻⁹⁵ Pa, or one whose values are down among the subnormal doubles
    (2.2·10⁻³⁰⁹), is interpolated as a table of bar is, its values at the nodes exact (to a
    subnormal double's rounding, for a value below 2⁻¹⁰²² of the largest). On the table as
    given, PCHIP's harmonic mean of slopes that small overflowed.
    """
    largest = float(np.max(np.abs(p)))
    if largest == 0.0:
        return _interpolant(a, p, cycle, kind)
    exponent = math.frexp(largest)[1]
    poly = _interpolant(a, np.ldexp(p, -exponent), cycle, kind)
    coefficients = np.ldexp(poly.c, exponent)
    if not np.all(np.isfinite(coefficients)):
        raise refused(
            "angle",
            "angle: the table's points are too close together to interpolate its pressures (a slope between "
            "two of them overflows)",
        )
    return type(poly).construct_fast(coefficients, poly.x, poly.extrapolate)


def _interpolant(a: np.ndarray, p: np.ndarray, cycle: float, kind: str) -> Any:
    """:func:`interpolant` of a table as it is: max|p| is 0 or in [0.5, 1)."""
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
    # A slope of ~10⁻³⁰⁸ (two pressures that differ by a subnormal amount) overflows PCHIP's
    # harmonic mean w/m to ±inf, whose limit, a slope of 0 there, is the right one.
    with np.errstate(over="ignore"):
        full = interpolate.PchipInterpolator(extended_a, extended_p)
    return interpolate.PPoly(full.c[:, k : k + n - 1].copy(), a)
