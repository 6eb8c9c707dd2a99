"""Words for numbers in what the package prints: "1 cylinder", "12 cylinders"; a column of
numbers in one notation.

Like :mod:`multicrank._validation` it imports nothing of the package, so any module (the
machine's repr, the motion's summary, the command line, the report) may use it."""

from __future__ import annotations

import math
from collections.abc import Iterable

__all__ = ["FIXED_RANGE", "column_text", "counted"]

#: The magnitudes a column writes without an exponent: every number in it that is not 0 lies
#: in [1e-4, 1e6) once rounded (the range in which ``%g`` writes 6 digits fixed); a column
#: with one number outside writes them all with an exponent.
FIXED_RANGE = (1e-4, 1e6)


def counted(number: int, noun: str, plural: str | None = None) -> str:
    """The number and its noun, plural unless the number is one.

    Parameters
    ----------
    number : int
        How many; printed with thousands separators.
    noun : str
        The singular ("cylinder").
    plural : str, optional
        The plural where it is not the noun with an "s" ("axes"); default ``noun + "s"``.

    Examples
    --------
    >>> counted(1, "cylinder"), counted(12, "cylinder"), counted(0, "unit"), counted(2, "axis", "axes")
    ('1 cylinder', '12 cylinders', '0 units', '2 axes')
    """
    return f"{number:,} {noun if number == 1 else (plural or noun + 's')}"


def column_text(values: Iterable[float], digits: int) -> list[str]:
    """A column of numbers as text, all in one notation, each to ``digits`` significant digits:
    fixed ("8726", "0.0925") where every number that is not 0 lies in :data:`FIXED_RANGE`,
    else all with an exponent ("8.726e+03", "1.139e+04"), so that a column never mixes the
    two; 0 is "0" and what is not finite is written as Python writes it ("nan", "inf").

    Parameters
    ----------
    values : iterable of float
        The column.
    digits : int
        Significant digits, ≥ 1.

    Examples
    --------
    >>> column_text([8726.0, 11390.0, 0.0], 4)
    ['8726', '11390', '0']
    >>> column_text([8726.0, 1.02e-6], 4)
    ['8.726e+03', '1.020e-06']
    >>> column_text([0.0925, 631.8, -0.15, float("nan")], 4)
    ['0.0925', '631.8', '-0.15', 'nan']
    """
    rounded = [float(f"{v:.{digits}g}") if math.isfinite(v) else float(v) for v in values]
    low, high = FIXED_RANGE
    fixed = all(v == 0 or not math.isfinite(v) or low <= abs(v) < high for v in rounded)
    texts = []
    for value in rounded:
        if value == 0 or not math.isfinite(value):
            texts.append("0" if value == 0 else f"{value}")
        elif fixed:  # as %g writes it: the zeros after the last significant digit dropped
            text = f"{value:.{max(digits - 1 - math.floor(math.log10(abs(value))), 0)}f}"
            texts.append(text.rstrip("0").rstrip(".") if "." in text else text)
        else:
            texts.append(f"{value:.{digits - 1}e}")
    return texts
