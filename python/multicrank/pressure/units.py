"""The units an indicator diagram is given in, and the check that a table's pressures are
plausible in the unit named (:class:`PressureUnitWarning`)."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from .._text import column_text

__all__ = ["ANGLE_UNITS", "PLAUSIBLE_PRESSURES", "PRESSURE_UNITS", "PressureUnitWarning", "check_pressure_unit"]

#: Pressure units of :meth:`IndicatorDiagram.from_csv`: Pa per unit (psi: lbf/in², exact).
PRESSURE_UNITS = {"Pa": 1.0, "kPa": 1e3, "bar": 1e5, "MPa": 1e6, "psi": 0.45359237 * 9.80665 / 0.0254**2}
#: Angle units of :meth:`IndicatorDiagram.from_csv`: rad per unit.
ANGLE_UNITS = {"deg": math.pi / 180.0, "rad": 1.0}

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
    # The peak as the table writes it and, in another unit than bar, in bar too (in bar it
    # would be the same number twice), the two in one notation ("800000 Pa = 8 bar").
    if unit == "bar":
        largest = f"{column_text([written], 4)[0]} bar"
    else:
        as_written, in_bar = column_text([written, peak / 1e5], 4)
        largest = f"{as_written} {unit} = {in_bar} bar"
    warnings.warn(
        f"{where}: the largest pressure is {largest}, {side}{question} (pressure_unit = {unit!r})",
        PressureUnitWarning,
        stacklevel=stacklevel + 1,
    )
