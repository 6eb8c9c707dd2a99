"""How the commands print a result: ``--format`` (a table to read, CSV or JSON for other
programs) to stdout or, with ``--out``, to a file written whole or not at all."""

from __future__ import annotations

import json
import math
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

import click
import numpy as np

from .._files import write_atomically
from ._group import UserError

if TYPE_CHECKING:
    import pandas as pd

__all__ = [
    "CSV_DIGITS",
    "FORMATS",
    "JSON_DIGITS",
    "format_option",
    "json_rows",
    "out_file",
    "out_option",
    "write_result",
    "writing",
]


def out_file(ctx: click.Context, param: click.Parameter, path: str | None) -> str | None:
    """The callback of an option naming a file to write (--out FILE, --cycle FILE): its
    folder must exist and be writable, checked before any work; else one line naming the
    option and the path (exit status 2)."""
    if path is None or ctx.resilient_parsing:
        return path
    option = max(param.opts, key=len)
    folder = os.path.dirname(path) or os.curdir
    if not os.path.isdir(folder):
        what = "is not a folder" if os.path.exists(folder) else "does not exist"
        raise UserError(f"{option} {path}: {folder} {what}")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise UserError(f"{option} {path}: the folder {folder} cannot be written")
    return path


@contextmanager
def writing(option: str, path: str | os.PathLike[str]) -> Iterator[None]:
    """A file written in the block that cannot be (a full disk, a folder gone or not writable)
    is one line naming the option and the path, never a traceback."""
    try:
        yield
    except OSError as error:
        raise UserError(f"{option} {os.fspath(path)}: {error.strerror or error}") from None


FORMATS = ("table", "csv", "json")

#: Significant digits of every number of a result's rows that ``--format csv`` and ``--format
#: json`` write (:func:`write_result`; the JSON's other fields are written whole).
CSV_DIGITS, JSON_DIGITS = 12, 15

format_option = click.option(
    "--format",
    "fmt",
    type=click.Choice(FORMATS),
    default="table",
    show_default=True,
    metavar="FORMAT",
    help="table (to read), csv or json (for other programs).",
)

#: ``--out FILE``: the command's table (or run) to FILE instead of stdout, its folder checked
#: before any work (:func:`out_file`).
out_option = click.option(
    "--out",
    "out_path",
    type=click.Path(dir_okay=False),
    callback=out_file,
    metavar="FILE",
    help="Write to FILE, not stdout.",
)


def write_result(
    frame: pd.DataFrame,
    fmt: str,
    out_path: str | os.PathLike[str] | None,
    *,
    summary: list[str],
    json_meta: dict[str, Any],
    footer: list[str] | None = None,
) -> None:
    """Write a result frame as csv/json (to --out or stdout; its numbers to :data:`CSV_DIGITS`
    and :data:`JSON_DIGITS` significant digits), or the summary, the table and the ``footer``
    lines below it."""
    if fmt == "csv":
        text = frame.to_csv(float_format=f"%.{CSV_DIGITS}g")
    elif fmt == "json":
        payload = dict(json_meta, rows=json_rows(frame))
        text = json.dumps(payload, indent=2) + "\n"
    else:
        text = "\n".join(summary) + "\n\n" + frame.to_string(float_format=lambda v: f"{v:.6g}") + "\n"
        if footer:
            text += "\n" + "\n".join(footer) + "\n"
    if out_path is None:
        sys.stdout.write(text)
    else:
        with writing("--out", out_path):
            write_atomically(out_path, text)
        click.echo(f"written: {out_path}", err=True)


def json_rows(frame: pd.DataFrame) -> list[dict[str, Any]]:
    """The frame's rows, its index first, as JSON records: every float — in a list too (the
    phases of a firing order) — to :data:`JSON_DIGITS` significant digits, NaN and ±inf as
    null, whatever its magnitude. pandas' ``to_json`` keeps decimal places instead
    (``double_precision``): 15 of them wrote 1.23456789e-12 as 0.000000000001235, four
    digits. What is no float (text, an integer, a flag, a missing value) is written as
    ``to_json`` writes it."""
    table = frame.reset_index()
    rows: list[dict[str, Any]] = json.loads(table.to_json(orient="records", double_precision=15))
    if rows:
        for key, (_, column) in zip(list(rows[0]), table.items(), strict=True):
            for row, value in zip(rows, column.tolist(), strict=True):
                row[key] = _rounded(value, row[key])
    return rows


def _rounded(value: Any, written: Any) -> Any:
    """``value`` (a float, or a list of them) to :data:`JSON_DIGITS` significant digits, NaN
    and ±inf as None; anything else as ``to_json`` wrote it (``written``)."""
    if isinstance(value, float):  # numpy's float64 is one
        if not math.isfinite(value):
            return None
        rounded = float(f"{value:.{JSON_DIGITS}g}")
        return rounded if math.isfinite(rounded) else value  # beyond 1.797693134862315e308: whole
    if isinstance(value, list | tuple | np.ndarray):
        if isinstance(written, list) and len(written) == len(value):
            return [_rounded(v, w) for v, w in zip(value, written, strict=True)]
    return written
