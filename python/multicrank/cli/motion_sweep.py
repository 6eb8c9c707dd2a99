"""``multicrank sweep motion``: the steady running of many variants of one machine
(:func:`multicrank.motion_sweep`), its axes from the options or a TOML ``--config`` file in
the gravity sweep's syntax, to Parquet or printed; every mistake one line naming it."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import click

from .._native import MechanismError
from .._text import counted
from .._validation import refused
from ..motion.columns import COLUMN_MEANINGS
from ._group import UserError, machine_option, note_renamed, options_named, renamed_option
from ._output import format_option
from .motion import DIGITS, parse_torque, readable
from .sweep import grid_axes, output_names, progress_option, read_config, resume_option

if TYPE_CHECKING:
    from ..machine.machine import Machine

__all__ = ["MOTION_AXES", "motion_sweep_command"]

#: The axes of a motion sweep, option name: what it is and its unit for --help: the design
#: columns of multicrank.motion.columns (light to import, unlike multicrank.motion.variants, to
#: keep ``multicrank --help`` quick).
MOTION_AXES: dict[str, str] = {name: f"{what} [{unit}]" for name, (what, unit) in COLUMN_MEANINGS.items()}
MOTION_AXES["rpm"] += " (default: the machine's own)"
_AXES = {name: (name, float) for name in MOTION_AXES}
_CONFIG_KEYS = ("axes", "outputs", "load", "delta_target", "delta")


def _axis_options(command: Any) -> Any:
    """One option per axis, in MOTION_AXES' order on --help."""
    for name, what in reversed(MOTION_AXES.items()):
        command = click.option(f"--{name.replace('_', '-')}", metavar="AXIS", help=f"{what[0].upper()}{what[1:]}.")(
            command
        )
    return command


def _config_load(table: dict[str, Any], path: str | None) -> str | None:
    """load in --config: a string as --load takes it."""
    load = table.get("load")
    if load is None:
        return None
    if not isinstance(load, str):
        raise refused("--config", f"--config {path}: load = {load!r}; it is a string as --load takes it")
    return load


def _load_rule(text: str, where: str) -> Any:
    """The load of --load (or load in --config, ``where``): balance or a power law. A constant
    torque is refused here, before any work: a sweep has no drive, so with gas alone against
    a constant load no machine runs steadily unless the load is the mean gas torque — which
    is what balance is."""
    rule = parse_torque(text, "load", balance=True)
    if isinstance(rule, float):
        raise refused(
            where,
            f"{where} = {text!r}: a constant torque is not a load a motion sweep takes (without a drive it "
            "runs steadily only if it equals the mean gas torque: that is balance); give balance or "
            "power:TORQUE:RPM[:EXPONENT]",
        )
    return rule


def _as_target(value: Any, name: str) -> float:
    """A target δ given as ``name`` (an option as typed, or a key of --config), checked by
    the library's rule for it (δ ≥ 1e-9) when it is read."""
    from ..motion.flywheel import _as_delta

    return _as_delta(value, name)


def _config_delta(ctx: click.Context, table: dict[str, Any], path: str | None) -> float | None:
    """delta_target in --config (or delta, its former name, with a note on stderr once the
    sweep has run): a number, the target δ."""
    key = "delta_target"
    if "delta" in table:
        if key in table:
            raise refused(
                "--config", f"--config {path}: delta_target and delta are one key (delta its former name): give it once"
            )
        key = "delta"
    delta = table.get(key)
    if delta is None:
        return None
    if isinstance(delta, bool) or not isinstance(delta, int | float):
        raise refused("--config", f"--config {path}: {key} = {delta!r}; it is a number (the target δ)")
    try:
        target = _as_target(float(delta), key)
    except MechanismError as error:
        raise refused("--config", f"--config {path}: {error}") from None
    if key == "delta":
        note_renamed(ctx, "note: delta in --config is now delta_target (the old name goes in 0.3)")
    return target


@click.command("motion", short_help="The steady running of variants of a machine: δ with and without gravity.")
@machine_option
@_axis_options
@click.option(
    "--config",
    type=click.Path(exists=True, dir_okay=False),
    help="TOML file with an [axes] table (the axes' names with underscores: lists, numbers or range "
    "strings) and optional outputs, load, delta_target; options given override it.",
)
@click.option(
    "--outputs",
    metavar="NAMES",
    help="Comma-separated outputs, of delta, delta_without_gravity, delta_coasting, gravity_effect, "
    "rpm_min, rpm_max, stalled, near_stall, flywheel_inertia, flywheel_inertia_without_gravity "
    "[default: the steady state's, and the flywheel's with --delta-target].",
)
@click.option(
    "--load",
    default=None,
    metavar="LOAD",
    help="balance (the constant that takes the mean gas torque, at each design's rpm) or "
    "power:TORQUE:RPM[:EXPONENT] (TORQUE [N·m] at RPM [1/min], growing as speed^EXPONENT, default 2; the "
    "speed follows from it; no --rpm axis) [default: balance].",
)
@renamed_option(
    "--delta-target",
    "--delta",
    "delta_target",
    check=_as_target,
    type=float,
    default=None,
    metavar="DELTA",
    help="Size the flywheel for this coefficient of speed fluctuation δ, e.g. 0.025 for 1/40 "
    "(adds the flywheel_inertia outputs). --delta is its former name.",
)
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    default=None,
    metavar="FILE",
    help="Write the result to this Parquet file, chunk by chunk [default: print it, as --format says; "
    "--format is for a printed result only].",
)
@format_option
@resume_option
@click.option(
    "--chunk-size",
    type=click.IntRange(min=1),
    default=None,
    help="Designs per chunk (and Parquet row group) [default: 256]; the results do not depend on it.",
)
@progress_option
@click.pass_context
def motion_sweep_command(
    ctx: click.Context,
    machine: Machine,
    config: str | None,
    outputs: str | None,
    load: str | None,
    delta_target: float | None,
    out: str | None,
    fmt: str,
    resume: bool,
    chunk_size: int | None,
    progress: bool,
    **axis_options: str | None,
) -> None:
    """The steady running of variants of one machine (--machine), one row per design.

    Each axis changes the machine: a range "start:stop:count" (count points, both ends
    included) or a comma-separated list; a single value is a constant. The cylinder fields
    are set on every cylinder. The grid is every combination of the axes, in the order of
    this help (the first varies slowest). Without --rpm each design runs at the machine's own
    speed.

    Outputs per design: δ with gravity, without (g = 0) and coasting (delta_coasting: gas and
    load removed, J(φ) and gravity together), gravity_effect = δ/δ without gravity − 1 (a
    fraction), the speed extremes [1/min], stalled, near_stall (δ > 0.5: the design nearly
    stops each cycle), and with --delta-target the flywheel [kg·m²] with and without gravity. A
    design that stalls is a row with stalled true and no δ. A printed --format json gives the
    target δ as delta_target (and as target_delta, its former name, deprecated: gone in 0.3).

    Ctrl-C stops the sweep with exit status 130; with --out the finished chunks are kept, and
    the same command with --resume continues from them.
    """
    import time

    from ..motion.loads import BALANCE
    from ..motion.sweep import RENAMED_OUTPUTS, motion_sweep
    from ..motion.variants import MachineGrid

    table = read_config(config, _CONFIG_KEYS, _AXES)
    sources: dict[str, str] = {}
    axes = grid_axes(axis_options, table.get("axes", {}), _AXES, sources)
    if not axes:
        raise refused("axes", "no axes: give at least one, e.g. --rpm 60:300:9, as an option or in [axes] of --config")
    load_text = load if load is not None else _config_load(table, config) or BALANCE
    load_rule = _load_rule(load_text, "--load" if load is not None else f"--config {config}: load")
    target = delta_target if delta_target is not None else _config_delta(ctx, table, config)
    chosen = output_names(outputs, "--outputs") if outputs else table.get("outputs")
    if chosen:  # the names of 0.1 still work, said on stderr
        for old in (name for name in chosen if name in RENAMED_OUTPUTS):
            note_renamed(ctx, f"note: the output {old} is now {RENAMED_OUTPUTS[old]} (the old name goes in 0.3)")
        chosen = [RENAMED_OUTPUTS.get(name, name) for name in chosen]
    if out is None:
        if resume:
            raise refused("--resume", "--resume needs --out, the Parquet file of the interrupted sweep")
    elif ctx.get_parameter_source("fmt") is click.core.ParameterSource.COMMANDLINE:
        raise refused("--format", "--format is for a printed result; with --out the result is written as Parquet")
    options = {**sources, "outputs": "--outputs", "delta_target": "--delta-target", "out": "--out"}
    started = time.perf_counter()
    try:
        with options_named(options):
            grid = MachineGrid(machine, **axes)
            result = motion_sweep(
                machine, grid, outputs=chosen, load=load_rule, delta_target=target, out=out, resume=resume,
                chunk_size=chunk_size, progress=progress,
            )  # fmt: skip
    except OSError as error:  # a full disk, a directory that went away: the kept parts stay
        raise UserError(f"--out {out}: {error.strerror or error}; finished chunks are kept for --resume") from None
    except KeyboardInterrupt:  # the group says it and exits with status 130
        kept = f"finished chunks are kept; rerun with --resume to continue into {out}" if out else "nothing was written"
        raise KeyboardInterrupt(kept) from None
    elapsed = time.perf_counter() - started
    rate = f"{len(grid) / elapsed:,.0f} designs/s" if elapsed > 0 else "instant"
    heading = f"{machine.name}: {counted(len(grid), 'design')} (load {load_text}) in {elapsed:.2f} s ({rate})"
    if out is not None:
        from .._optional import require

        frame = require("pyarrow.parquet", "parquet").read_table(result).to_pandas()
        click.echo(f"{heading} → {result}")
        numbers = frame.drop(columns=[*axes, "stalled", "near_stall"], errors="ignore")
        click.echo(readable(numbers.describe().T[["min", "mean", "max"]], DIGITS).to_string())
        note = _near_stall_note(frame)
        if note:
            click.echo(note)
        return
    units = {name: unit for name, unit in _UNITS.items() if name in result}
    meta = dict(machine=machine.name, load=load_text, delta_target=target, target_delta=target, units=units)
    summary = [heading, "gravity_effect = δ/δ without gravity − 1; δ = (ω_max − ω_min)/ω_mean (time mean)"]
    note = _near_stall_note(result)
    if note:
        summary.append(note)
        if fmt == "csv":
            click.echo(note, err=True)
    if target is not None:
        summary.append(f"flywheel_inertia: the shaft inertia [kg·m²] for δ = {target:.4g} (1/{1 / target:.4g})")
    from ._output import write_result

    write_result(readable(result, DIGITS) if fmt == "table" else result, fmt, None, summary=summary, json_meta=meta)


def _near_stall_note(frame: Any) -> str:
    """A note on the designs whose δ is above NEAR_STALL_DELTA, or "" where there are none."""
    if "near_stall" not in frame or not frame["near_stall"].any():
        return ""
    from ..motion.steady import NEAR_STALL_NOTE

    return f"note: {int(frame['near_stall'].sum()):,} of {len(frame):,} designs near_stall: {NEAR_STALL_NOTE}"


_UNITS = {
    "shaft_inertia": "kg·m²", "rpm": "1/min", "g": "m/s²", "rpm_min": "1/min", "rpm_max": "1/min",
    "flywheel_inertia": "kg·m²", "flywheel_inertia_without_gravity": "kg·m²",
}  # fmt: skip
