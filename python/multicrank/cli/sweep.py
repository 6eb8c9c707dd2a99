"""``multicrank sweep``: a grid of designs into a Parquet file, its axes from the options or a
TOML ``--config`` file, every mistake in either one line naming it.

``sweep`` is a group: used plainly it is the gravity sweep of dimensionless designs (its options
are the group's, as before the group existed); ``sweep motion`` (:mod:`.motion_sweep`) sweeps
variants of a machine. The axis syntax and the checks of a ``--config`` file are here, for both."""

from __future__ import annotations

import math
from typing import Any

import click
import numpy as np

from .._files import read_toml
from .._native import SWEEP_OUTPUTS, MechanismError
from .._optional import require
from .._validation import refused
from ._group import UserError, options_named

__all__ = [
    "design_axes",
    "grid_axes",
    "output_names",
    "parse_axis",
    "progress_option",
    "read_config",
    "resume_option",
    "sweep_command",
]


def design_axes() -> dict[str, tuple[str, Any]]:
    """The gravity sweep's axes, option name: (grid column, kind): the columns of a
    :class:`~multicrank.DesignGrid`, as ``multicrank.sweeps.designs`` defines them. A design
    column is a real (the inclination given in degrees), an optional column of the kind of
    its default (``cranks`` 1, ``acting`` "single"). Read at run time: the designs module
    imports pandas, which would slow down ``multicrank --help``."""
    from ..sweeps.designs import KNOWN_COLUMNS, OPTIONAL_COLUMNS

    return {
        name: (name, "degrees" if name == "inclination" else type(OPTIONAL_COLUMNS.get(name, 0.0)))
        for name in KNOWN_COLUMNS
    }


def parse_axis(text: str, kind: Any, name: str = "axis") -> list[Any]:
    """An axis from the command line: "a:b:n" (n ≥ 1 points from a to b inclusive; for integer
    axes "a:b" is a..b inclusive, a ≤ b), or a comma-separated list; never empty. A mistake is
    a MechanismError naming the axis (one line from the CLI)."""
    text = str(text).strip()
    label = "an integer" if kind is int else "a number"
    try:
        if kind is str:
            values: list[Any] = [item.strip() for item in text.split(",") if item.strip()]
        elif ":" in text:
            parts = text.split(":")
            if kind is int and len(parts) == 2:
                start, stop = int(parts[0]), int(parts[1])
                if stop < start:
                    raise refused(name, f"{name} = {text!r}: an integer range start:stop needs start <= stop")
                values = list(range(start, stop + 1))
            elif len(parts) != 3:
                raise refused(name, f"{name} = {text!r}: a range is start:stop:count")
            else:
                first, last, count = float(parts[0]), float(parts[1]), int(parts[2])
                if count < 1 or not (math.isfinite(first) and math.isfinite(last)):
                    raise refused(name, f"{name} = {text!r}: a range start:stop:count needs finite ends and count >= 1")
                points = np.linspace(first, last, count).tolist()
                values = [round(v) for v in points] if kind is int else points
        else:
            convert = int if kind is int else float
            values = [convert(item) for item in text.split(",") if item.strip()]
    except MechanismError:  # a ValueError too: said above, as it is
        raise
    except ValueError:
        raise refused(
            name, f"{name} = {text!r} is not understood; give {label} list a,b,c or a range start:stop:count"
        ) from None
    if not values:
        raise refused(name, f"{name} = {text!r} gives no values")
    return values


def grid_axes(
    options: dict[str, Any],
    config: dict[str, Any],
    known: dict[str, tuple[str, Any]],
    sources: dict[str, str] | None = None,
) -> dict[str, Any]:
    """The grid's axes of ``known`` (option name: (grid column, kind)): each from its option
    or, where none is given, from [axes] of --config; inclinations from degrees to radians.
    ``sources``, where given, is filled with where each column came from (``--rpm``, ``[axes]
    rpm``), for the library's refusals to name it (:func:`~._group.options_named`)."""
    axes = {}
    for name, (column, kind) in known.items():
        value = options.get(name)
        where = f"--{name.replace('_', '-')}"
        if value is None:
            value, where = config.get(name), f"[axes] {name}"
        if value is None:
            continue
        if isinstance(value, list):
            values = [_config_value(item, kind, where) for item in value]
            if not values:
                raise refused(where, f"{where} is an empty list")
        elif isinstance(value, str):
            values = parse_axis(value, float if kind == "degrees" else kind, where)
        else:
            values = [_config_value(value, kind, where)]
        if kind == "degrees":
            values = np.radians(values).tolist()
        axes[column] = values if len(values) > 1 else values[0]
        if sources is not None:
            sources[column] = where
    return axes


def _config_value(value: Any, kind: Any, where: str) -> Any:
    """One value of an axis written as TOML (a number, or a string for acting), checked."""
    wanted = {int: "an integer", str: "a string"}.get(kind, "a number")
    if kind is str:
        ok = isinstance(value, str)
    elif kind is int:
        ok = isinstance(value, int) and not isinstance(value, bool)
    else:
        ok = isinstance(value, int | float) and not isinstance(value, bool)
    if not ok:
        raise refused(where, f"{where}: {value!r} is not {wanted}")
    return value


def read_config(path: str | None, keys: tuple[str, ...], axes: Any) -> dict[str, Any]:
    """The --config file as a checked table: only ``keys``, [axes] with names of ``axes``,
    outputs a list (or comma-separated string) of names. Every mistake is one line naming it."""
    if not path:
        return {}
    table = read_toml(path, "a sweep configuration", label=f"--config {path}")
    unknown = sorted(set(table) - set(keys))
    if unknown:
        raise refused("--config", f"--config {path}: unknown keys {unknown}; it takes {list(keys)}")
    known = table.get("axes", {})
    if not isinstance(known, dict):
        raise refused("--config", f"--config {path}: axes must be a table [axes], not {type(known).__name__}")
    unknown = sorted(set(known) - set(axes))
    if unknown:
        raise refused("--config", f"--config {path}: unknown axes {unknown}; the axes are {list(axes)}")
    outputs = table.get("outputs")
    if isinstance(outputs, str):
        table["outputs"] = output_names(outputs, f"--config {path}: outputs")
    elif outputs is not None:
        if not isinstance(outputs, list) or not outputs or not all(isinstance(name, str) for name in outputs):
            raise refused("--config", f"--config {path}: outputs = {outputs!r}; it is a list of output names")
    return table


def _sweep_config(path: str | None) -> dict[str, Any]:
    """The gravity sweep's --config: [axes], outputs, and phi a positive integer."""
    table = read_config(path, ("axes", "phi", "outputs"), design_axes())
    phi = table.get("phi")
    if phi is not None and (isinstance(phi, bool) or not isinstance(phi, int) or phi < 1):
        raise refused("--config", f"--config {path}: phi = {phi!r}; it is a positive integer (points per revolution)")
    return table


def output_names(text: str, where: str) -> list[str]:
    """The output names of a comma-separated list (--outputs, or outputs in --config)."""
    names = [name.strip() for name in text.split(",") if name.strip()]
    if not names:
        raise refused(where, f"{where} = {text!r} names no outputs")
    return names


# The options every sweep has.
resume_option = click.option("--resume", is_flag=True, help="Continue an interrupted sweep into the same --out.")
progress_option = click.option("--progress/--no-progress", default=True, show_default=True, help="Show a progress bar.")


@click.group(
    "sweep",
    invoke_without_command=True,
    subcommand_metavar="[motion [OPTIONS]]",
    short_help="Sweep a grid of designs (or of machines: sweep motion) into Parquet.",
)
@click.option("--crank-ratio", metavar="AXIS", help='λ = r/l axis, e.g. "0.2:0.45:26" or "0.25,0.3".')
@click.option("--inclination", metavar="AXIS", help='γ axis in DEGREES (90 = upright), e.g. "0:90:7".')
@click.option(
    "--u1", metavar="AXIS", help='U1 axis: the dimensionless reciprocating gravity moment, e.g. "0.001,0.01,0.1".'
)
@click.option("--u2", metavar="AXIS", help="U2 axis: the dimensionless rotating unbalance (may be negative).")
@click.option("--cranks", metavar="AXIS", help='k axis, e.g. "1:12" or "2,4,6".')
@click.option("--strokes", metavar="AXIS", help='"2", "4" or "2,4".')
@click.option("--acting", metavar="AXIS", help='"single", "double" or "single,double".')
@click.option(
    "--config",
    type=click.Path(exists=True, dir_okay=False),
    help="TOML file with an [axes] table (same names, lists or range strings) and optional phi, outputs.",
)
@click.option("--phi", type=click.IntRange(min=1), default=None, help="φ grid points per revolution [default: 720].")
@click.option(
    "--outputs",
    metavar="NAMES",
    help=f"Comma-separated outputs, of {', '.join(SWEEP_OUTPUTS)} [default: all].",
)
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    default="sweep.parquet",
    show_default=True,
    metavar="FILE",
    help="The Parquet file.",
)
@resume_option
@click.option(
    "--chunk-size",
    type=click.IntRange(min=1),
    default=65536,
    show_default=True,
    help="Designs per chunk (and Parquet row group); the results do not depend on it.",
)
@progress_option
@click.pass_context
def sweep_command(
    ctx: click.Context,
    config: str | None,
    phi: int | None,
    outputs: str | None,
    out: str,
    resume: bool,
    chunk_size: int,
    progress: bool,
    **axis_options: str | None,
) -> None:
    """Sweep a grid of designs and write the results to Parquet.

    Used as it is, the gravity sweep: dimensionless designs (λ, γ, U1, U2, cranks, strokes,
    acting), their U*, Q* and extrema, with the options below. With the command "motion"
    (multicrank sweep motion --help): the steady running of variants of a machine (speed,
    flywheel, masses, …), δ with and without gravity and the flywheel.

    Each axis is a range "start:stop:count" (count points, both ends included; integer axes
    also take "start:stop"), or a comma-separated list. Axes not given default to
    u2 = 0, cranks = 1, strokes = 2, acting = single; crank-ratio, inclination and u1 are
    required (on the command line or in --config).

    Ctrl-C stops the sweep with exit status 130; the finished chunks are kept next to --out,
    and the same command with --resume continues from them.
    """
    if ctx.invoked_subcommand is not None:
        given = [
            f"--{param.name.replace('_', '-')}"
            for param in ctx.command.params
            if param.name and ctx.get_parameter_source(param.name) is click.core.ParameterSource.COMMANDLINE
        ]
        if given:
            raise click.UsageError(
                f"{', '.join(given)}: given before '{ctx.invoked_subcommand}', an option of the gravity sweep; the "
                f"options of 'sweep {ctx.invoked_subcommand}' come after it (multicrank sweep "
                f"{ctx.invoked_subcommand} --help)"
            )
        return
    import time

    from ..sweeps.designs import DESIGN_COLUMNS, SWEEP_OUTPUTS, DesignGrid
    from ..sweeps.driver import sweep

    table = _sweep_config(config)
    sources: dict[str, str] = {}
    axes = grid_axes(axis_options, table.get("axes", {}), design_axes(), sources)
    axes.setdefault("u2", 0.0)
    missing = [name for name in DESIGN_COLUMNS if name not in axes]
    if missing:
        raise click.UsageError(f"missing axes: {', '.join(missing)} (give them as options or in --config)")
    phi = phi or int(table.get("phi", 720))
    chosen = output_names(outputs, "--outputs") if outputs else table.get("outputs", list(SWEEP_OUTPUTS))
    unknown = [name for name in chosen if name not in SWEEP_OUTPUTS]
    if unknown:
        raise refused("outputs", f"outputs: unknown {unknown}; the outputs are {list(SWEEP_OUTPUTS)}")
    started = time.perf_counter()
    try:
        with options_named({**sources, "outputs": "--outputs", "phi": "--phi", "out": "--out", "resume": "--resume"}):
            grid = DesignGrid(**axes)
            path = sweep(
                grid, phi=phi, outputs=chosen, out=out, resume=resume, progress=progress, chunk_size=chunk_size
            )
    except OSError as error:  # a full disk, a directory that went away: the kept parts stay
        raise UserError(f"--out {out}: {error.strerror or error}; finished chunks are kept for --resume") from None
    except KeyboardInterrupt:  # the group says it and exits with status 130
        raise KeyboardInterrupt(f"finished chunks are kept; rerun with --resume to continue into {out}") from None
    elapsed = time.perf_counter() - started
    pq = require("pyarrow.parquet", "parquet")
    result = pq.read_table(path, columns=list(chosen)).to_pandas()
    click.echo(
        f"{len(grid):,} designs × {phi} φ points in {elapsed:.2f} s ({len(grid) / elapsed:,.0f} designs/s) → {path}"
    )
    summary = result.describe().T[["min", "mean", "max"]]
    click.echo(summary.to_string(float_format=lambda v: f"{v:.6g}"))
