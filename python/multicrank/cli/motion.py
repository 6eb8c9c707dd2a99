"""The `multicrank` command line."""

from __future__ import annotations

import json
import math
import sys

import click
import numpy as np

from .._native import SWEEP_OUTPUTS, MechanismError, __version__
from .._optional import OptionalDependencyError, require
from ..gravity.evaluation import generalized_force, potential_energy
from ..gravity.mechanism import crank_phases
from ..presets import DEFAULT_ENGINE_NAME, ENGINES

FORMATS = ("table", "csv", "json")


class MissingExtra(click.ClickException):
    """An optional dependency is missing: one line on stderr, exit status 2 (as a usage error)."""

    exit_code = 2


class UserError(click.ClickException):
    """A mistake in what the user gave (a machine file, a machine without a speed): one line on
    stderr, exit status 2 (as a usage error)."""

    exit_code = 2


class _Commands(click.Group):
    def invoke(self, ctx: click.Context) -> object:
        try:
            return super().invoke(ctx)
        except OptionalDependencyError as error:
            raise MissingExtra(str(error)) from None
        except MechanismError as error:
            # Every check of the library names what is wrong with the input: that line is
            # the message, never a traceback.
            raise UserError(str(error)) from None


@click.group(cls=_Commands, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="multicrank")
def main() -> None:
    """Gravity and motion of multi-crank piston machines: the potential energy U* and the
    generalised force Q_u* = dU*/dφ (dimensionless, U* = U/(I_w ω²)), the steady running
    with and without gravity, transients, design sweeps and the report.

    Angles are typed in degrees, speeds in 1/min, torques in N·m. Each command has --help.
    """


def _load_engine(ctx, param, spec: str):
    """--engine: a built-in machine's name or a TOML machine file, as a multicrank.Machine."""
    from ..presets import engine_by_name_or_file

    try:
        return engine_by_name_or_file(spec)
    except MechanismError as error:
        raise UserError(f"--engine: {error}") from None


engine_option = click.option(
    "--engine",
    "engine",
    default=DEFAULT_ENGINE_NAME,
    show_default=True,
    callback=_load_engine,
    metavar="NAME|FILE",
    help=f"A built-in machine ({', '.join(ENGINES)}) or a TOML machine file (docs/machine-files.md).",
)

format_option = click.option(
    "--format",
    "fmt",
    type=click.Choice(FORMATS),
    default="table",
    show_default=True,
    metavar="FORMAT",
    help="table (to read), csv or json (for other programs).",
)


def _inline_variant(machine, cranks, strokes, acting, inclination):
    """The machine with the eval command's overrides: --cranks, --strokes and --acting make a
    regular in-line machine of its first cylinder; --inclination tilts every cylinder."""
    if cranks is not None or strokes is not None or acting is not None:
        first = machine.cylinders[0]
        cycle = machine.strokes if strokes is None else int(strokes)
        if acting is None:
            acting = "double" if first.pressure_crank_end is not None else "single"
        # Gravity alone: the gas pressures (whose cycle --strokes may change) stay behind.
        first = first.replace(pressure=None, pressure_crank_end=None)
        phases = crank_phases(len(machine) if cranks is None else cranks, cycle, acting)
        machine = machine.replace(cylinders=[first.replace(phase=float(a)) for a in phases], strokes=cycle)
    if inclination is not None:
        gamma = float(np.radians(inclination))
        machine = machine.replace(cylinders=[c.replace(inclination=gamma) for c in machine.cylinders])
    return machine


@main.command("eval", short_help="U_w*(φ) and Q_u*(φ) of a machine on a coarse φ grid.")
@engine_option
@click.option("--cranks", type=click.IntRange(min=1), help="Override the number of cranks k.")
@click.option("--strokes", type=click.Choice(["2", "4"]), help="Override the working cycle: two- or four-stroke.")
@click.option("--acting", type=click.Choice(["single", "double"]), help="Override: single- or double-acting cylinders.")
@click.option(
    "--inclination",
    type=float,
    metavar="DEG",
    help="Override the cylinder inclination γ, in DEGREES (90 = upright, 0 = lying).",
)
@click.option(
    "--rpm",
    type=click.FloatRange(min=0, min_open=True),
    help="Override the mean speed [1/min] (default: the machine's own).",
)
@click.option(
    "--points",
    type=click.IntRange(min=1, max=10_000_000),
    default=24,
    show_default=True,
    help="φ grid points over one revolution (a printed table: at most 10⁷).",
)
@format_option
def eval_command(engine, cranks, strokes, acting, inclination, rpm, points, fmt) -> None:
    """Print U_w*(φ) and Q_u*(φ) of a machine on a coarse φ grid (φ in degrees).

    --cranks, --strokes and --acting make a regular in-line machine of the machine's first
    cylinder (k cranks at the cycle's phases); --inclination tilts every cylinder.
    """
    try:
        machine = _inline_variant(engine, cranks, strokes, acting, inclination)
        speed = machine.rpm if rpm is None else rpm
        if speed is None:
            raise MechanismError(f"machine {machine.name!r} has no running speed: give --rpm")
        try:
            design = machine.design(speed)  # the paper's machine: the in-line functions
        except MechanismError:
            design = None
        units = machine.engine(speed)
    except MechanismError as error:
        raise UserError(str(error)) from None
    phi_deg = np.arange(points) * (360.0 / points)
    phi = np.radians(phi_deg)
    if design is not None:
        energy = potential_energy(phi, **design)
        force = generalized_force(phi, **design)
    else:
        energy = units.potential_energy(phi)
        force = units.generalized_force(phi)
    rows = list(zip(phi_deg.tolist(), energy.tolist(), force.tolist(), strict=True))
    if acting is None:  # as the machine given is (the overrides leave its pressures behind)
        acting = "double" if any(c.pressure_crank_end is not None for c in engine.cylinders) else "single"
    out = sys.stdout
    if fmt == "json":
        meta: dict = dict(
            engine=machine.name, cylinders=len(machine), strokes=machine.strokes, acting=acting, rpm=speed
        )
        if design is not None:
            meta.update({k: v for k, v in design.items() if k != "phases"}, cranks=len(machine))
        else:
            meta.update({k: getattr(units, k).tolist() for k in ("crank_ratio", "inclination", "u1", "u2")})
        meta["phases_deg"] = np.degrees(units.phase).tolist()
        json.dump(
            {
                "engine": meta,
                "phi_deg": phi_deg.tolist(),
                "potential_energy": energy.tolist(),
                "generalized_force": force.tolist(),
            },
            out,
            indent=2,
        )
        out.write("\n")
        return
    if fmt == "csv":
        out.write("phi_deg,potential_energy,generalized_force\n")
        for p, u, q in rows:
            out.write(f"{p:.10g},{u:.17g},{q:.17g}\n")
        return
    if design is not None:
        out.write(
            f"{machine.name}: k = {len(machine)}, {machine.strokes}-stroke, {acting}-acting, "
            f"γ = {np.degrees(design['inclination']):g}°, λ = {design['crank_ratio']:.4g}, n = {speed:g} rpm\n"
            f"u1 = {design['u1']:.6g}, u2 = {design['u2']:.6g} (dimensionless, ÷ I_w ω²)\n\n"
        )
    else:
        out.write(
            f"{machine.name}: {len(machine)} cylinders, {machine.strokes}-stroke, {acting}-acting, "
            f"n = {speed:g} rpm (dimensionless, ÷ I_w ω²)\n\n"
        )
    out.write(f"{'φ [deg]':>9}  {'U_w*':>14}  {'Q_u*':>14}\n")
    for p, u, q in rows:
        out.write(f"{p:9.2f}  {u:14.6e}  {q:14.6e}\n")


# ----------------------------------------------------------------------------- sweep
_AXES = {
    # option name: (grid column, kind)
    "crank_ratio": ("crank_ratio", float),
    "inclination": ("inclination", "degrees"),
    "u1": ("u1", float),
    "u2": ("u2", float),
    "cranks": ("cranks", int),
    "strokes": ("strokes", int),
    "acting": ("acting", str),
}


def parse_axis(text: str, kind, name: str = "axis") -> list:
    """An axis from the command line: "a:b:n" (n ≥ 1 points from a to b inclusive; for integer
    axes "a:b" is a..b inclusive, a ≤ b), or a comma-separated list; never empty. A mistake is
    a MechanismError naming the axis (one line from the CLI)."""
    text = str(text).strip()
    label = "an integer" if kind is int else "a number"
    try:
        if kind is str:
            values: list = [item.strip() for item in text.split(",") if item.strip()]
        elif ":" in text:
            parts = text.split(":")
            if kind is int and len(parts) == 2:
                start, stop = int(parts[0]), int(parts[1])
                if stop < start:
                    raise MechanismError(f"{name} = {text!r}: an integer range start:stop needs start <= stop")
                values = list(range(start, stop + 1))
            elif len(parts) != 3:
                raise MechanismError(f"{name} = {text!r}: a range is start:stop:count")
            else:
                first, last, count = float(parts[0]), float(parts[1]), int(parts[2])
                if count < 1 or not (math.isfinite(first) and math.isfinite(last)):
                    raise MechanismError(
                        f"{name} = {text!r}: a range start:stop:count needs finite ends and count >= 1"
                    )
                points = np.linspace(first, last, count).tolist()
                values = [round(v) for v in points] if kind is int else points
        else:
            convert = int if kind is int else float
            values = [convert(item) for item in text.split(",") if item.strip()]
    except MechanismError:  # a ValueError too: said above, as it is
        raise
    except ValueError:
        raise MechanismError(
            f"{name} = {text!r} is not understood; give {label} list a,b,c or a range start:stop:count"
        ) from None
    if not values:
        raise MechanismError(f"{name} = {text!r} gives no values")
    return values


def _grid_axes(options: dict, config: dict) -> dict:
    axes = {}
    for name, (column, kind) in _AXES.items():
        value = options.get(name)
        where = f"--{name.replace('_', '-')}"
        if value is None:
            value, where = config.get(name), f"[axes] {name}"
        if value is None:
            continue
        if isinstance(value, list):
            values = [_config_value(item, kind, where) for item in value]
            if not values:
                raise MechanismError(f"{where} is an empty list")
        elif isinstance(value, str):
            values = parse_axis(value, float if kind == "degrees" else kind, where)
        else:
            values = [_config_value(value, kind, where)]
        if kind == "degrees":
            values = np.radians(values).tolist()
        axes[column] = values if len(values) > 1 else values[0]
    return axes


def _config_value(value, kind, where: str):
    """One value of an axis written as TOML (a number, or a string for acting), checked."""
    wanted = {int: "an integer", str: "a string"}.get(kind, "a number")
    if kind is str:
        ok = isinstance(value, str)
    elif kind is int:
        ok = isinstance(value, int) and not isinstance(value, bool)
    else:
        ok = isinstance(value, int | float) and not isinstance(value, bool)
    if not ok:
        raise MechanismError(f"{where}: {value!r} is not {wanted}")
    return value


_CONFIG_KEYS = ("axes", "phi", "outputs")


def _sweep_config(path: str | None) -> dict:
    """The --config file as a checked table: [axes] with known names, phi a positive integer,
    outputs a list (or comma-separated string) of names. Every mistake is one line naming it."""
    if not path:
        return {}
    import tomllib

    try:
        with open(path, "rb") as handle:
            table = tomllib.load(handle)
    except tomllib.TOMLDecodeError as error:
        raise MechanismError(f"--config {path}: not a valid TOML file: {error}") from None
    except UnicodeDecodeError as error:
        raise MechanismError(f"--config {path}: not a UTF-8 text file: {error.reason}") from None
    except OSError as error:
        raise MechanismError(f"--config {path}: cannot be read: {error.strerror or error}") from None
    unknown = sorted(set(table) - set(_CONFIG_KEYS))
    if unknown:
        raise MechanismError(f"--config {path}: unknown keys {unknown}; it takes {list(_CONFIG_KEYS)}")
    axes = table.get("axes", {})
    if not isinstance(axes, dict):
        raise MechanismError(f"--config {path}: axes must be a table [axes], not {type(axes).__name__}")
    unknown = sorted(set(axes) - set(_AXES))
    if unknown:
        raise MechanismError(f"--config {path}: unknown axes {unknown}; the axes are {list(_AXES)}")
    phi = table.get("phi")
    if phi is not None and (isinstance(phi, bool) or not isinstance(phi, int) or phi < 1):
        raise MechanismError(f"--config {path}: phi = {phi!r}; it is a positive integer (points per revolution)")
    outputs = table.get("outputs")
    if isinstance(outputs, str):
        table["outputs"] = _output_names(outputs, f"--config {path}: outputs")
    elif outputs is not None:
        if not isinstance(outputs, list) or not outputs or not all(isinstance(name, str) for name in outputs):
            raise MechanismError(f"--config {path}: outputs = {outputs!r}; it is a list of output names")
    return table


def _output_names(text: str, where: str) -> list[str]:
    names = [name.strip() for name in text.split(",") if name.strip()]
    if not names:
        raise MechanismError(f"{where} = {text!r} names no outputs")
    return names


@main.command("sweep", short_help="Sweep a grid of designs into a Parquet file.")
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
@click.option("--resume", is_flag=True, help="Continue an interrupted sweep into the same --out.")
@click.option(
    "--chunk-size",
    type=click.IntRange(min=1),
    default=65536,
    show_default=True,
    help="Designs per chunk (and Parquet row group); the results do not depend on it.",
)
@click.option("--progress/--no-progress", default=True, show_default=True, help="Show a progress bar.")
def sweep_command(config, phi, outputs, out, resume, chunk_size, progress, **axis_options) -> None:
    """Sweep a grid of designs and write the results to Parquet.

    Each axis is a range "start:stop:count" (count points, both ends included; integer axes
    also take "start:stop"), or a comma-separated list. Axes not given default to
    u2 = 0, cranks = 1, strokes = 2, acting = single; crank-ratio, inclination and u1 are
    required (on the command line or in --config).

    Ctrl-C stops the sweep with exit status 130; the finished chunks are kept next to --out,
    and the same command with --resume continues from them.
    """
    import time

    from ..sweeps.designs import SWEEP_OUTPUTS, DesignGrid
    from ..sweeps.driver import sweep

    table = _sweep_config(config)
    axes = _grid_axes(axis_options, table.get("axes", {}))
    axes.setdefault("u2", 0.0)
    missing = [name for name in ("crank_ratio", "inclination", "u1") if name not in axes]
    if missing:
        raise click.UsageError(f"missing axes: {', '.join(missing)} (give them as options or in --config)")
    phi = phi or int(table.get("phi", 720))
    chosen = _output_names(outputs, "--outputs") if outputs else table.get("outputs", list(SWEEP_OUTPUTS))
    unknown = [name for name in chosen if name not in SWEEP_OUTPUTS]
    if unknown:
        raise MechanismError(f"outputs: unknown {unknown}; the outputs are {list(SWEEP_OUTPUTS)}")
    grid = DesignGrid(**axes)
    started = time.perf_counter()
    try:
        path = sweep(grid, phi=phi, outputs=chosen, out=out, resume=resume, progress=progress, chunk_size=chunk_size)
    except MechanismError as error:
        raise click.UsageError(str(error)) from None
    except OSError as error:  # a full disk, a directory that went away: the kept parts stay
        raise UserError(f"--out {out}: {error.strerror or error}; finished chunks are kept for --resume") from None
    except KeyboardInterrupt:
        click.echo(f"\ninterrupted: finished chunks are kept; rerun with --resume to continue into {out}", err=True)
        sys.exit(130)
    elapsed = time.perf_counter() - started
    pq = require("pyarrow.parquet", "parquet")
    result = pq.read_table(path, columns=list(chosen)).to_pandas()
    click.echo(
        f"{len(grid):,} designs × {phi} φ points in {elapsed:.2f} s ({len(grid) / elapsed:,.0f} designs/s) → {path}"
    )
    summary = result.describe().T[["min", "mean", "max"]]
    click.echo(summary.to_string(float_format=lambda v: f"{v:.6g}"))


# ----------------------------------------------------------------------------- tables
@main.command("tables", short_help="Which harmonics survive k cranks (Tables 1 and 2).")
@click.option(
    "--strokes",
    type=click.Choice(["2", "4"]),
    default="2",
    show_default=True,
    help="The working cycle: two- or four-stroke.",
)
@click.option(
    "--acting",
    type=click.Choice(["single", "double"]),
    default="single",
    show_default=True,
    help="Single- or double-acting cylinders.",
)
@click.option("--k-max", type=click.IntRange(min=1), default=12, show_default=True, help="Largest number of cranks.")
@click.option("--n-max", type=click.IntRange(min=1), default=24, show_default=True, help="Highest harmonic.")
@format_option
def tables_command(strokes, acting, k_max, n_max, fmt) -> None:
    """Which harmonics W_n of Q_u* survive the sum over k cranks (the paper's Tables 1 and 2).

    Two-stroke single-acting is the paper's Table 1, four-stroke single-acting its Table 2.
    """
    from ..gravity.harmonics import harmonic_table

    table = harmonic_table(int(strokes), acting, k_max=k_max, n_max=n_max)
    if fmt == "csv":
        sys.stdout.write(table.astype(int).to_csv())
    elif fmt == "json":
        json.dump(
            {str(n): [int(k) for k in table.columns if table.loc[n, k]] for n in table.index}, sys.stdout, indent=2
        )
        sys.stdout.write("\n")
    else:
        sys.stdout.write(f"W_n that survive: {strokes}-stroke, {acting}-acting (● = non-zero)\n\n")
        corner = "n \\ k"
        sys.stdout.write(f"{corner:>6} " + " ".join(f"{k:>3}" for k in table.columns) + "\n")
        for n, row in table.iterrows():
            sys.stdout.write(f"{'W_' + str(n):>6} " + " ".join(f"{'●' if v else '·':>3}" for v in row) + "\n")


# ----------------------------------------------------------------------------- motion
def parse_torque(text: str, name: str, *, balance: bool) -> object:
    """--load/--drive: "balance", a number [N·m], or power:TORQUE:RPM[:EXPONENT]."""
    from ..motion.loads import BALANCE, PowerLawLoad

    value = text.strip()
    if balance and value == BALANCE:
        return BALANCE
    if value.startswith("power:"):
        parts = value.split(":")[1:]
        if len(parts) not in (2, 3):
            raise MechanismError(f"--{name} = {text!r}: write power:TORQUE:RPM or power:TORQUE:RPM:EXPONENT")
        try:
            numbers = [float(p) for p in parts]
        except ValueError:
            raise MechanismError(f"--{name} = {text!r}: TORQUE, RPM and EXPONENT must be numbers") from None
        torque, rpm = numbers[0], numbers[1]
        if not (math.isfinite(rpm) and rpm > 0):
            raise MechanismError(f"--{name} = {text!r}: RPM must be > 0 [1/min]")
        return PowerLawLoad(torque, rpm * math.pi / 30, *numbers[2:])
    try:
        number = float(value)
    except ValueError:
        allowed = "'balance', " if balance else ""
        raise MechanismError(
            f"--{name} = {text!r} is not understood; allowed: {allowed}a torque in N·m, or power:TORQUE:RPM[:EXPONENT]"
        ) from None
    if not math.isfinite(number):
        raise MechanismError(f"--{name} = {text!r} must be finite [N·m]")
    return number


def _table_or_file(frame, fmt: str, out_path, *, summary: list[str], json_meta: dict) -> None:
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
        _write_atomically(out_path, text)
        click.echo(f"written: {out_path}", err=True)


def _write_atomically(path, text: str) -> None:
    """All of ``text`` in ``path`` or, on any failure, nothing new there."""
    import os
    import tempfile
    from pathlib import Path

    target = Path(path)
    handle, temporary = tempfile.mkstemp(dir=target.parent if str(target.parent) else ".", prefix=f".{target.name}.")
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as stream:
            stream.write(text)
        os.replace(temporary, target)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


@main.command("simulate", short_help="The motion in time: start-up, run-down, stall.")
@engine_option
@click.option(
    "--rpm",
    type=float,
    metavar="RPM",
    help="The speed at the start [1/min] (default: the machine's running speed).",
)
@click.option(
    "--duration",
    type=float,
    default=None,
    metavar="SECONDS",
    help="Seconds to simulate [default: 20 working cycles at the start speed].",
)
@click.option(
    "--samples",
    type=click.IntRange(min=2, max=10_000_000),
    default=2001,
    show_default=True,
    help="Samples of the result, evenly spaced in time from 0 to --duration.",
)
@click.option(
    "--load",
    default="balance",
    show_default=True,
    metavar="LOAD",
    help="balance (the constant that takes the mean of gas and drive), a constant torque [N·m], or "
    "power:TORQUE:RPM[:EXPONENT] (TORQUE [N·m] at RPM [1/min], growing as speed^EXPONENT, default 2: "
    "a fan or propeller).",
)
@click.option(
    "--drive",
    default=None,
    metavar="DRIVE",
    help="A driving torque besides the gas: a constant [N·m] or power:TORQUE:RPM[:EXPONENT] [default: none].",
)
@click.option("--gas/--no-gas", default=True, show_default=True, help="With the cylinders' gas pressures.")
@click.option("--gravity/--no-gravity", default=True, show_default=True, help="With gravity (--no-gravity: g = 0).")
@format_option
@click.option(
    "--out",
    "out_path",
    type=click.Path(dir_okay=False, writable=True),
    metavar="FILE",
    help="Write to FILE, not stdout.",
)
@click.option("--progress/--no-progress", default=True, show_default=True, help="Show a progress bar.")
def simulate_command(engine, rpm, duration, samples, load, drive, gas, gravity, fmt, out_path, progress) -> None:
    """Integrate the machine's motion in time from a start speed (start-up, run-down, load step).

    The equation of motion J(φ)φ̈ + ½J'(φ)φ̇² = M_gas − dU/dφ + M_drive − M_load is integrated
    with SciPy's DOP853; the run stops early if the machine stalls. Prints (or writes) the
    time series: time [s], φ [rad, cumulative], ω [rad/s], rpm and the torques [N·m].
    """
    from ..motion.transient import simulate

    try:
        machine = engine if gas else _without_gas(engine)
        start = _speed(machine, rpm, "--rpm")
        omega0 = start * math.pi / 30
        if duration is None:
            duration = 20 * machine.cycle / omega0 if omega0 > 0 else 1.0
        if not (math.isfinite(duration) and duration > 0):
            raise MechanismError(f"--duration = {duration} is out of range; allowed: > 0 [s]")
        t_eval = np.linspace(0.0, duration, samples)
        result = simulate(
            machine,
            t_eval,
            omega0=omega0,
            load=parse_torque(load, "load", balance=True),
            drive=None if drive is None else parse_torque(drive, "drive", balance=False),
            gravity=gravity,
            progress=progress,
        )
    except MechanismError as error:
        raise UserError(str(error)) from None
    frame = result.to_pandas()
    frame.insert(2, "rpm", frame["omega"] * 30 / math.pi)
    end = f"stalled at t = {result.stall_time:.6g} s" if result.stalled else f"ran {duration:.6g} s"
    summary = [
        f"{machine.name}: from {start:g} rpm, load {load}, drive {drive or 'none'}, gas "
        f"{'on' if gas else 'off'}, gravity {'on' if gravity else 'off'}: {end}, last speed "
        f"{frame['rpm'].iloc[-1]:.6g} rpm",
        f"energy check (½Jω² + U − work, relative): {result.energy_drift:.2e}",
    ]
    shown = frame if fmt != "table" else frame.iloc[:: max(1, len(frame) // 20)]
    meta = dict(
        engine=machine.name,
        start_rpm=start,
        load=load,
        drive=drive,
        gas=gas,
        gravity=gravity,
        stalled=result.stalled,
        stall_time=result.stall_time,
        energy_drift=result.energy_drift,
        units=frame.attrs.get("units", {}),
    )
    _table_or_file(shown, fmt, out_path, summary=summary, json_meta=meta)


def _finite_option(value, option: str):
    """click's FloatRange lets NaN through (every comparison with it is false)."""
    if value is not None and not math.isfinite(value):
        raise click.BadParameter(f"{value} is not a finite number", param_hint=option)
    return value


def _speed(machine, rpm, option: str) -> float:
    """The speed [1/min] asked for, or the machine's own; checked."""
    speed = machine.rpm if rpm is None else rpm
    if speed is None:
        raise MechanismError(f"machine {machine.name!r} has no running speed: give {option}")
    if not (math.isfinite(speed) and speed > 0):
        raise MechanismError(f"{option} = {speed} is out of range; allowed: > 0 [1/min]")
    return float(speed)


def _without_gas(machine):
    """The machine with its gas pressures removed (a run-down, gravity and inertia alone)."""
    cylinders = [c.replace(pressure=None, pressure_crank_end=None) for c in machine.cylinders]
    return machine.replace(cylinders=cylinders, name=f"{machine.name} (no gas)")


@main.command("motion", short_help="Steady running: δ with and without gravity, flywheel.")
@engine_option
@click.option(
    "--rpm",
    "speeds",
    type=float,
    multiple=True,
    metavar="RPM",
    help="Mean speed(s) [1/min], repeatable [default: the machine's speed and --points speeds over its range].",
)
@click.option(
    "--points",
    type=click.IntRange(min=1, max=1000),
    default=5,
    show_default=True,
    help="Speeds over the machine's speed range, besides its running speed (when no --rpm is given).",
)
@click.option(
    "--load",
    default="balance",
    show_default=True,
    metavar="LOAD",
    help="balance (the constant that takes the mean of gas and drive, at each --rpm), or "
    "power:TORQUE:RPM[:EXPONENT] (TORQUE [N·m] at RPM [1/min], growing as speed^EXPONENT, default 2; "
    "the speed follows from it).",
)
@click.option(
    "--drive",
    default=None,
    metavar="DRIVE",
    help="A driving torque besides the gas: a constant [N·m] or power:TORQUE:RPM[:EXPONENT] [default: none].",
)
@click.option(
    "--delta",
    "target",
    type=float,
    default=None,
    metavar="DELTA",
    help="Size the flywheel for this coefficient of speed fluctuation δ, e.g. 0.025 for 1/40 "
    "[default: the preset's class limit; none for a machine file].",
)
@click.option(
    "--cycle",
    "cycle_path",
    type=click.Path(dir_okay=False),
    metavar="FILE",
    help="Write ω(φ) and the torques over one cycle, at the first speed that runs, to FILE (CSV).",
)
@format_option
@click.option(
    "--out", "out_path", type=click.Path(dir_okay=False), metavar="FILE", help="Write the table to FILE, not stdout."
)
@click.option("--progress/--no-progress", default=True, show_default=True, help="Show a progress bar over the speeds.")
def motion_command(engine, speeds, points, load, drive, target, cycle_path, fmt, out_path, progress) -> None:
    """Steady running: the coefficient of speed fluctuation δ with and without gravity, and the flywheel.

    For each mean speed: the exact periodic steady state of J(φ)φ̈ + ½J'(φ)φ̇² = M_gas − dU/dφ +
    M_drive − M_load, its δ = (ω_max − ω_min)/ω_mean with gravity, without (g = 0) and of gravity
    alone, the load torque [N·m] and power [kW]; with a target δ, the shaft inertia [kg·m²] that
    gives it with and without gravity and the textbook estimate ΔE/(δω²).
    """
    import pandas as pd
    from tqdm.auto import tqdm

    from ..motion.steady import StallError, flywheel_inertia, steady_state
    from ..presets import MACHINE_CLASSES, SPEED_FLUCTUATION

    machine = engine
    load_rule = parse_torque(load, "load", balance=True)
    drive_rule = None if drive is None else parse_torque(drive, "drive", balance=False)
    balance = load_rule == "balance"
    if target is None and machine.name in MACHINE_CLASSES:
        target = SPEED_FLUCTUATION[MACHINE_CLASSES[machine.name]][1]
    if target is not None and not (math.isfinite(target) and 1e-9 <= target < 1):
        raise MechanismError(f"--delta = {target} is out of range; allowed: 1e-9 <= delta < 1")
    wanted: list[float | None]
    if balance:
        wanted = [_speed(machine, rpm, "--rpm") for rpm in speeds] or list(_speed_set(machine, points))
    else:
        if speeds:
            raise MechanismError(f"--rpm: the load {load!r} fixes the speed; give --rpm only with --load balance")
        wanted = [None]
    rows = []
    first = None
    for rpm in tqdm(wanted, desc="motion", unit="speed", disable=not progress or len(wanted) < 2):
        row: dict = {"rpm": rpm}
        try:
            state = steady_state(machine, rpm=rpm, load=load_rule, drive=drive_rule)
        except StallError as error:
            row.update(stalled=True, min_rpm=error.min_rpm)
            rows.append(row)
            continue
        first = first or state
        row.update(
            rpm=state.rpm if rpm is None else rpm,  # the speed asked for, or the one the load gives
            delta=state.delta,
            delta_without_gravity=state.delta_without_gravity,
            gravity_change_percent=100 * state.gravity_effect / state.delta_without_gravity,
            delta_gravity_only=state.delta_gravity_only,
            delta_midrange=state.delta_midrange,
            rpm_min=state.omega_min * 30 / math.pi,
            rpm_max=state.omega_max * 30 / math.pi,
            load_torque=state.load_torque,
            power_kw=state.load_torque * state.omega_mean / 1000,
            stalled=False,
        )
        if target is not None:
            sizing = flywheel_inertia(machine, delta=target, rpm=rpm, load=load_rule, drive=drive_rule)
            row.update(
                flywheel=sizing.shaft_inertia,
                flywheel_without_gravity=sizing.shaft_inertia_without_gravity,
                flywheel_textbook=sizing.textbook,
            )
        rows.append(row)
    frame = pd.DataFrame(rows).set_index("rpm")
    if cycle_path is not None:
        if first is None:
            raise MechanismError("--cycle: the machine stalls at every speed asked for; nothing to write")
        cycle = first.to_pandas()
        cycle.insert(0, "phi_deg", np.degrees(cycle.index.to_numpy()))
        cycle["omega_without_gravity"] = steady_state(
            machine, rpm=first.rpm if balance else None, load=load_rule, drive=drive_rule, gravity=False
        ).omega
        _write_atomically(cycle_path, cycle.to_csv(float_format="%.12g"))
    units = dict(
        rpm="1/min", load_torque="N·m", power_kw="kW", flywheel="kg·m²", flywheel_without_gravity="kg·m²",
        flywheel_textbook="kg·m²", rpm_min="1/min", rpm_max="1/min",
    )  # fmt: skip
    summary = [
        f"{machine.name}: {len(machine)} cylinders, {machine.strokes}-stroke, shaft inertia "
        f"{machine.shaft_inertia:g} kg·m², load {load}, drive {drive or 'none'}",
        "δ = (ω_max − ω_min)/ω_mean (time mean); gravity_change_percent = (δ − δ without gravity)/δ without gravity",
    ]
    if target is not None:
        summary.append(f"flywheel: the shaft inertia [kg·m²] for δ = {target:.4g} (1/{1 / target:.4g})")
    meta = dict(engine=machine.name, load=load, drive=drive, target_delta=target, units=units)
    _table_or_file(frame, fmt, out_path, summary=summary, json_meta=meta)


def _speed_set(machine, points: int) -> list[float | None]:
    """The machine's running speed and ``points`` speeds spread over its range."""
    speed = _speed(machine, None, "--rpm")
    if machine.rpm_range is None:
        return [speed]
    low, high = machine.rpm_range
    return sorted({speed, *np.linspace(low, high, points).tolist()})


# ----------------------------------------------------------------------------- report
@main.command("report", short_help="Write the HTML report (PNG figures, CSV tables).")
@click.option(
    "--out",
    "out_dir",
    type=click.Path(file_okay=False),
    default="multicrank-report",
    show_default=True,
    metavar="DIR",
    help="The folder for index.html and its figures (PNG) and tables (CSV).",
)
@engine_option
@click.option(
    "--k-max",
    type=click.IntRange(min=1, max=24),
    default=12,
    show_default=True,
    help="Largest number of cranks in the paper's analysis.",
)
@click.option(
    "--n-max",
    type=click.IntRange(min=2),
    default=24,
    show_default=True,
    help="Highest harmonic in the spectra and tables.",
)
@click.option("--points", type=click.IntRange(min=8), default=721, show_default=True, help="φ points per curve.")
@click.option(
    "--threshold",
    type=click.FloatRange(min=0, min_open=True),
    callback=lambda ctx, param, value: _finite_option(value, "--threshold"),
    default=None,
    help="δ_g below which gravity may be neglected [default: 1/3000].",
)
@click.option(
    "--delta",
    type=click.FloatRange(min=0, max=1, min_open=True, max_open=True),
    default=None,
    help="Size the flywheel for this δ [default: the preset's class limit, else the machine's δ without gravity].",
)
@click.option("--progress/--no-progress", default=True, show_default=True, help="Show a progress bar.")
def report_command(out_dir, engine, k_max, n_max, points, threshold, delta, progress) -> None:
    """Write the report: first the machine's steady running with and without gravity (δ, the
    flywheel, ω(φ), the torques and their orders, δ over the speed range), then the paper's
    analysis — curves, spectra, Tables 1–2, the truncation error, the gravity-significance map,
    conventions and errata — as index.html + PNG + CSV."""
    from ..report.document import DEFAULT_THRESHOLD, ReportSettings, write_report

    settings = ReportSettings(
        engine=engine,
        k_max=k_max,
        n_max=n_max,
        points=points,
        threshold=threshold or DEFAULT_THRESHOLD,
        delta=delta,
    )
    try:
        index = write_report(out_dir, settings, progress=progress)
    except OSError as error:
        raise UserError(f"--out {out_dir}: {error.strerror or error}") from None
    except MechanismError as error:
        raise UserError(str(error)) from None
    click.echo(f"report written: {index}")


if __name__ == "__main__":
    main()
