"""Words for numbers in what the package prints: "1 cylinder", "12 cylinders".

Like :mod:`multicrank._validation` it imports nothing of the package, so any module (the
machine's repr, the motion's summary, the command line, the report) may use it."""

from __future__ import annotations

__all__ = ["counted"]


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
