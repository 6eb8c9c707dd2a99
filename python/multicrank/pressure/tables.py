"""Reading indicator-diagram tables: the angle and pressure columns of a CSV file.

pandas (``pd.read_csv``) splits the rows and ``pd.to_numeric`` reads the numbers; this module
decides what is a comment, a header and the delimiter, and words every fault with the file's
own line number and the column, as :meth:`multicrank.IndicatorDiagram.from_csv` documents.
pandas is imported when a table is read.
"""

from __future__ import annotations

import io
import math
from typing import Any

import numpy as np

from .._validation import refused

__all__ = ["read_columns"]

#: The columns a table gives, in the order they are checked on each line.
_KEYS = ("angle_column", "pressure_column")
#: The delimiters looked for on the first data line, in this order; else runs of white space.
_DELIMITERS = (",", ";", "\t")


def read_columns(
    name: str, delimiter: str | None, columns: dict[str, int | str], *, absolute: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """The angle and pressure columns of a CSV file, as written (no units applied).

    Parameters
    ----------
    name : str
        The file (UTF-8 text). Blank lines and lines starting with ``#`` are skipped; the
        first other line is a header when a column is given by name, or when its angle or
        pressure field is not a number.
    delimiter : str or None
        One character; white space or None: runs of white space. None also means: the first
        of ``,``, ``;`` and tab found on the first data line, if any.
    columns : dict
        ``angle_column`` and ``pressure_column``: a column counted from 0, or a header name.
    absolute : bool, default False
        Whether the pressures are absolute: then none may be negative (below vacuum).

    Returns
    -------
    angle, pressure : ndarray
        The two columns as float64, the angles strictly increasing, at least 4 rows.

    Raises
    ------
    MechanismError
        Naming the file, and the line and column where a field is missing, not a number, not
        finite, an angle that does not increase, or (``absolute``) a negative pressure.
    """
    lines = [
        (number, line.strip())
        for number, line in enumerate(_text(name).splitlines(), start=1)
        if line.strip() and not line.strip().startswith("#")
    ]
    if delimiter is None:
        separator = next((d for d in _DELIMITERS if lines and d in lines[0][1]), None)
    else:
        separator = None if delimiter.isspace() else delimiter
    index = {key: column for key, column in columns.items() if isinstance(column, int)}
    if lines:
        number, first = lines[0][0], _fields(name, lines[0][1], separator)
        named = len(index) < len(columns)
        if named or not _are_numbers([first[c] if c < len(first) else "" for c in index.values()]):
            for key, column in columns.items():  # the first line is a header
                if isinstance(column, str):
                    if column not in first:
                        raise refused(key, f"{name}, line {number}: {key} = {column!r} is not in the header {first}")
                    index[key] = first.index(column)
            lines = lines[1:]
    texts = _columns(name, lines, separator, index)
    values = {key: _to_numbers(text, len(lines)) for key, text in texts.items()}
    angles, pressures = values["angle_column"], values["pressure_column"]
    bad = np.flatnonzero(~(np.isfinite(angles) & np.isfinite(pressures)))
    falls = np.flatnonzero(~(np.diff(angles) > 0)) + 1
    # The first fault in the file's order, as a reader going line by line meets it.
    if bad.size and not (falls.size and falls[0] < bad[0]):
        _field_error(name, lines[bad[0]], separator, index, texts, values, int(bad[0]))
    if falls.size:
        row = falls[0]
        raise refused(
            "path",
            f"{name}, line {lines[row][0]}, column {index['angle_column']} (angle_column): the angle "
            f"{float(angles[row])!r} does not increase on line {lines[row - 1][0]}'s {float(angles[row - 1])!r}; the "
            "angles must increase strictly",
        )
    if angles.size < 4:
        raise refused("path", f"{name}: {angles.size} data row(s); an indicator diagram needs at least 4")
    below = np.flatnonzero(pressures < 0) if absolute else np.zeros(0, dtype=np.intp)
    if below.size:
        row = int(below[0])
        raise refused(
            "path",
            f"{name}, line {lines[row][0]}, column {index['pressure_column']} (pressure_column): "
            f"{texts['pressure_column'].iloc[row]!r} is a negative absolute pressure (below vacuum); with "
            "absolute=True every pressure must be >= 0 (gauge pressures are read with absolute=False)",
        )
    return angles, pressures


def _text(name: str) -> str:
    """The file's text, or a MechanismError that says why it cannot be had."""
    try:
        with open(name, encoding="utf-8", newline="") as handle:
            return handle.read()
    except FileNotFoundError:
        raise refused("path", f"path = {name!r}: no such file") from None
    except IsADirectoryError:
        raise refused("path", f"path = {name!r} is a directory, not a CSV file") from None
    except UnicodeDecodeError as error:
        raise refused(
            "path", f"path = {name!r} is not a UTF-8 text file: {error.reason} at byte {error.start}"
        ) from None
    except OSError as error:
        raise refused("path", f"path = {name!r} cannot be read: {error.strerror or error}") from None


def _read(name: str, text: str, separator: str | None, **options: Any) -> Any:
    """``pd.read_csv`` of some lines, every field a string (stripped of leading blanks)."""
    import pandas as pd

    try:
        return pd.read_csv(
            io.StringIO(text),
            sep=r"\s+" if separator is None else separator,
            header=None,
            dtype=str,
            keep_default_na=False,
            skipinitialspace=True,
            **options,
        )
    except pd.errors.ParserError as error:
        raise refused("path", f"{name}: not a table of (angle, pressure) rows: {error}") from None


def _fields(name: str, line: str, separator: str | None) -> list[str]:
    """The fields of one line."""
    return [field.strip() for field in _read(name, line, separator).iloc[0].tolist()]


def _are_numbers(fields: list[str]) -> bool:
    """Whether every field reads as a number, NaN and inf included (else a line is a header)."""
    try:
        for field in fields:
            float(field)
    except ValueError:
        return False
    return True


def _columns(name: str, lines: list[tuple[int, str]], separator: str | None, index: dict[str, int]) -> dict[str, Any]:
    """Each column's fields on the data lines (a pandas Series of strings), or None for a column
    beyond every line."""
    if not lines:
        return {key: None for key in index}
    # As many columns as the widest line could have (a quoted delimiter only overestimates):
    # read_csv takes the width from the first line, and would shift a longer line's fields.
    width = max(len(line.split()) if separator is None else line.count(separator) + 1 for _, line in lines)
    wanted = sorted({column for column in index.values() if column < width})
    frame = _read(name, "\n".join(line for _, line in lines), separator, names=range(width), usecols=wanted)
    return {key: frame[column].str.strip() if column < width else None for key, column in index.items()}


def _to_numbers(text: Any, rows: int) -> np.ndarray:
    """A column's fields as float64; NaN where a field is missing or no number."""
    import pandas as pd

    if text is None:
        return np.full(rows, np.nan)
    return np.asarray(pd.to_numeric(text, errors="coerce"), dtype=float)


def _field_error(
    name: str,
    line: tuple[int, str],
    separator: str | None,
    index: dict[str, int],
    texts: dict[str, Any],
    values: dict[str, np.ndarray],
    row: int,
) -> None:
    """Raise the MechanismError for the first bad field of a data line: missing, no number, not finite."""
    number, content = line
    for key in _KEYS:
        column, text = index[key], texts[key]
        if text is None or (text.iloc[row] == "" and len(_fields(name, content, separator)) <= column):
            count = len(_fields(name, content, separator))
            raise refused(key, f"{name}, line {number}: {count} column(s), but {key} = {column} (counted from 0)")
        if not np.isfinite(values[key][row]):
            field = text.iloc[row]
            what = "a finite number" if _are_numbers([field]) and not math.isfinite(float(field)) else "a number"
            raise refused("path", f"{name}, line {number}, column {column} ({key}): {field!r} is not {what}")
