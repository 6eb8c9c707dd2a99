"""How the commands print a result: ``--format`` (a table to read, CSV or JSON for other
programs) to stdout or, with ``--out``, to a file written whole or not at all."""

from __future__ import annotations

import json
import sys
from typing import TYPE_CHECKING, Any

import click

from .._files import write_atomically

if TYPE_CHECKING:
    import os

    import pandas as pd

__all__ = ["FORMATS", "format_option", "write_result"]

FORMATS = ("table", "csv", "json")

format_option = click.option(
    "--format",
    "fmt",
    type=click.Choice(FORMATS),
    default="table",
    show_default=True,
    metavar="FORMAT",
    help="table (to read), csv or json (for other programs).",
)


def write_result(
    frame: pd.DataFrame,
    fmt: str,
    out_path: str | os.PathLike[str] | None,
    *,
    summary: list[str],
    json_meta: dict[str, Any],
) -> None:
    """Write a result frame as csv/json (to --out or stdout), or the summary and the table."""
    if fmt == "csv":
        text = frame.to_csv(float_format="%.12g")
    elif fmt == "json":
        payload = dict(json_meta, rows=json.loads(frame.reset_index().to_json(orient="records", double_precision=15)))
        text = json.dumps(payload, indent=2) + "\n"
    else:
        text = "\n".join(summary) + "\n\n" + frame.to_string(float_format=lambda v: f"{v:.6g}") + "\n"
    if out_path is None:
        sys.stdout.write(text)
    else:
        write_atomically(out_path, text)
        click.echo(f"written: {out_path}", err=True)
