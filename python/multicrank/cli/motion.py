"""The motion commands: ``motion`` (the steady running with and without gravity, the
flywheel) and ``simulate`` (the motion in time), with the ``--load``/``--drive`` torques
they share."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import click
import numpy as np

from .._files import write_atomically
from .._native import MechanismError
from .._text import column_text, counted
from .._validation import omega_from_rpm, refused, rpm_from_omega, running_rpm
from ._group import UserError, machine_option, renamed_option
from ._output import format_option, out_file, out_option, write_result, writing

if TYPE_CHECKING:
    import pandas as pd

    from ..machine.machine import Machine

__all__ = ["DIGITS", "motion_command", "parse_torque", "readable", "simulate_command"]

#: Significant digits of the motion commands' tables to read (csv and json give 12 and 15).
DIGITS = 6


def readable(frame: pd.DataFrame, digits: int) -> pd.DataFrame:
    """The table to read: every float column as text to ``digits`` significant digits, in one
    notation per column (fixed, or all with an exponent: :func:`~multicrank._text.column_text`);
    the other columns and the index as they are."""
    from pandas.api.types import is_float_dtype

    shown = frame.copy()
    for name, column in frame.items():
        if is_float_dtype(column):
            shown[name] = column_text(column.tolist(), digits)
    return shown


def parse_torque(text: str, name: str, *, balance: bool) -> Any:
    """--load/--drive: "balance", a number [N·m], or power:TORQUE:RPM[:EXPONENT]."""
    from ..motion.loads import BALANCE, PowerLawLoad

    value = text.strip()
    if balance and value == BALANCE:
        return BALANCE
    if value.startswith("power:"):
        parts = value.split(":")[1:]
        if len(parts) not in (2, 3):
            raise refused(f"--{name}", f"--{name} = {text!r}: write power:TORQUE:RPM or power:TORQUE:RPM:EXPONENT")
        try:
            numbers = [float(p) for p in parts]
        except ValueError:
            raise refused(f"--{name}", f"--{name} = {text!r}: TORQUE, RPM and EXPONENT must be numbers") from None
        torque, rpm = numbers[0], numbers[1]
        if not (math.isfinite(rpm) and rpm > 0):
            raise refused(f"--{name}", f"--{name} = {text!r}: RPM must be > 0 [1/min]")
        return PowerLawLoad(torque, rpm=rpm, exponent=numbers[2]) if len(numbers) > 2 else PowerLawLoad(torque, rpm=rpm)
    try:
        number = float(value)
    except ValueError:
        allowed = "'balance', " if balance else ""
        raise refused(
            f"--{name}",
            f"--{name} = {text!r} is not understood; allowed: {allowed}a torque in N·m, or power:TORQUE:RPM[:EXPONENT]",
        ) from None
    if not math.isfinite(number):
        raise refused(f"--{name}", f"--{name} = {text!r} must be finite [N·m]")
    return number


drive_option = click.option(
    "--drive",
    default=None,
    metavar="DRIVE",
    help="A driving torque besides the gas: a constant [N·m] or power:TORQUE:RPM[:EXPONENT] [default: none].",
)


@click.command("simulate", short_help="The motion in time: start-up, run-down, stall.")
@machine_option
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
@drive_option
@click.option("--gas/--no-gas", default=True, show_default=True, help="With the cylinders' gas pressures.")
@click.option("--gravity/--no-gravity", default=True, show_default=True, help="With gravity (--no-gravity: g = 0).")
@format_option
@out_option
@click.option("--progress/--no-progress", default=True, show_default=True, help="Show a progress bar.")
def simulate_command(
    machine: Machine,
    rpm: float | None,
    duration: float | None,
    samples: int,
    load: str,
    drive: str | None,
    gas: bool,
    gravity: bool,
    fmt: str,
    out_path: str | None,
    progress: bool,
) -> None:
    """Integrate the machine's motion in time from a start speed (start-up, run-down, load step).

    The equation of motion J(φ)φ̈ + ½J'(φ)φ̇² = M_gas − dU/dφ + M_drive − M_load is integrated
    with SciPy's DOP853; the run stops early if the machine stalls. Prints (or writes) the
    time series: time [s], φ [rad, cumulative], ω [rad/s], rpm and the torques [N·m].
    """
    from ..motion.transient import simulate

    try:
        if not gas:
            machine = _without_gas(machine)
        start = _speed(machine, rpm, "--rpm")
        if duration is None:
            duration = 20 * machine.cycle / omega_from_rpm(start)
        if not (math.isfinite(duration) and duration > 0):
            raise refused("--duration", f"--duration = {duration} is out of range; allowed: > 0 [s]")
        t_eval = np.linspace(0.0, duration, samples)
        result = simulate(
            machine,
            t_eval,
            rpm0=start,
            load=parse_torque(load, "load", balance=True),
            drive=None if drive is None else parse_torque(drive, "drive", balance=False),
            gravity=gravity,
            progress=progress,
        )
    except MechanismError as error:
        raise UserError(str(error)) from None
    frame = result.to_pandas()
    frame.insert(2, "rpm", rpm_from_omega(frame["omega"]))
    end = f"stalled at t = {result.stall_time:.6g} s" if result.stalled else f"ran {duration:.6g} s"
    summary = [
        f"{machine.name}: from {start:g} rpm, load {load}, drive {drive or 'none'}, gas "
        f"{'on' if gas else 'off'}, gravity {'on' if gravity else 'off'}: {end}, last speed "
        f"{frame['rpm'].iloc[-1]:.6g} rpm",
        f"energy check (½Jω² + U − work, relative): {result.energy_drift:.2e}",
    ]
    shown = frame if fmt != "table" else readable(frame.iloc[:: max(1, len(frame) // 20)], DIGITS)
    meta = dict(
        machine=machine.name,
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
    write_result(shown, fmt, out_path, summary=summary, json_meta=meta)


def _speed(machine: Machine, rpm: float | None, option: str) -> float:
    """The speed [1/min] asked for with ``option``, or the machine's own; checked by the
    core's rule, a refusal naming ``option`` (:func:`~multicrank._validation.running_rpm`)."""
    return running_rpm(machine, rpm, option)


def _as_target(target: float, option: str) -> float:
    """The target δ of ``option`` (--delta-target, or --delta, its former name, as typed):
    1e-9 ≤ δ < 1, checked when the option is read."""
    if not (math.isfinite(target) and 1e-9 <= target < 1):
        raise UserError(f"{option} = {target} is out of range; allowed: 1e-9 <= δ < 1 (the target δ)")
    return target


def _without_gas(machine: Machine) -> Machine:
    """The machine with its gas pressures removed (a run-down, gravity and inertia alone)."""
    cylinders = [c.replace(pressure=None, pressure_crank_end=None) for c in machine.cylinders]
    return machine.replace(cylinders=cylinders, name=f"{machine.name} (no gas)")


@click.command("motion", short_help="Steady running: δ with and without gravity, flywheel.")
@machine_option
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
@drive_option
@renamed_option(
    "--delta-target",
    "--delta",
    "target",
    check=_as_target,
    type=float,
    default=None,
    metavar="DELTA",
    help="Size the flywheel for this coefficient of speed fluctuation δ, e.g. 0.025 for 1/40 "
    "[default: the preset's class limit; none for a machine file]. --delta is its former name.",
)
@click.option(
    "--cycle",
    "cycle_path",
    type=click.Path(dir_okay=False),
    callback=out_file,
    metavar="FILE",
    help="Write ω(φ) and the torques over one cycle, at the first speed that runs, to FILE (CSV).",
)
@format_option
@out_option
@click.option("--progress/--no-progress", default=True, show_default=True, help="Show a progress bar over the speeds.")
def motion_command(
    machine: Machine,
    speeds: tuple[float, ...],
    points: int,
    load: str,
    drive: str | None,
    target: float | None,
    cycle_path: str | None,
    fmt: str,
    out_path: str | None,
    progress: bool,
) -> None:
    """Steady running: the coefficient of speed fluctuation δ with and without gravity, and the flywheel.

    For each mean speed: the exact periodic steady state of J(φ)φ̈ + ½J'(φ)φ̇² = M_gas − dU/dφ +
    M_drive − M_load, its δ = (ω_max − ω_min)/ω_mean with gravity, without (g = 0) and coasting
    (gas, drive and load removed: J(φ) and gravity together), gravity_effect = δ/δ without
    gravity − 1 (a fraction), near_stall (δ > 0.5: the machine nearly stops each cycle), the
    load torque [N·m] and power [kW]; with a target δ, the shaft inertia [kg·m²] that gives it
    with and without gravity and the textbook estimate ΔE/(δω²).

    --format json gives the target δ as delta_target (and as target_delta, its former name,
    deprecated: gone in 0.3).
    """
    import pandas as pd
    from tqdm.auto import tqdm

    from ..motion.flywheel import flywheel_inertia
    from ..motion.steady import NEAR_STALL_DELTA, NEAR_STALL_NOTE, StallError, steady_state
    from ..presets import MACHINE_CLASSES, SPEED_FLUCTUATION

    load_rule = parse_torque(load, "load", balance=True)
    drive_rule = None if drive is None else parse_torque(drive, "drive", balance=False)
    balance = load_rule == "balance"
    if target is None and machine.name in MACHINE_CLASSES:
        target = SPEED_FLUCTUATION[MACHINE_CLASSES[machine.name]][1]
    wanted: list[float | None]
    if balance:
        wanted = [_speed(machine, rpm, "--rpm") for rpm in speeds] or list(_speed_set(machine, points))
    else:
        if speeds:
            raise refused("--rpm", f"--rpm: the load {load!r} fixes the speed; give --rpm only with --load balance")
        wanted = [None]
    rows = []
    first = None
    for rpm in tqdm(wanted, desc="motion", unit="speed", disable=not progress or len(wanted) < 2):
        row: dict[str, Any] = {"rpm": rpm}
        try:
            state = steady_state(machine, rpm=rpm, load=load_rule, drive=drive_rule)
        except StallError as error:
            row.update(stalled=True, near_stall=False, min_rpm=error.min_rpm)
            rows.append(row)
            continue
        first = first or state
        row.update(
            rpm=state.rpm if rpm is None else rpm,  # the speed asked for, or the one the load gives
            delta=state.delta,
            delta_without_gravity=state.delta_without_gravity,
            gravity_effect=state.gravity_effect,
            delta_coasting=state.delta_coasting,
            delta_midrange=state.delta_midrange,
            rpm_min=rpm_from_omega(state.omega_min),
            rpm_max=rpm_from_omega(state.omega_max),
            load_torque=state.mean_load_torque,
            power_kw=state.mean_load_torque * state.omega_mean / 1000,
            stalled=False,
            near_stall=state.near_stall,
        )
        if target is not None:
            sizing = flywheel_inertia(machine, delta=target, rpm=rpm, load=load_rule, drive=drive_rule)
            row.update(
                flywheel_inertia=sizing.shaft_inertia,
                flywheel_inertia_without_gravity=sizing.shaft_inertia_without_gravity,
                flywheel_inertia_textbook=sizing.textbook,
            )
        rows.append(row)
    frame = pd.DataFrame(rows).set_index("rpm")
    if cycle_path is not None:
        if first is None:
            raise refused("--cycle", "--cycle: the machine stalls at every speed asked for; nothing to write")
        cycle = first.to_pandas()
        cycle.insert(0, "phi_deg", np.degrees(cycle.index.to_numpy()))
        cycle["omega_without_gravity"] = steady_state(
            machine, rpm=first.rpm if balance else None, load=load_rule, drive=drive_rule, gravity=False
        ).omega
        with writing("--cycle", cycle_path):
            write_atomically(cycle_path, cycle.to_csv(float_format="%.12g"))
    units = dict(
        rpm="1/min", load_torque="N·m", power_kw="kW", flywheel_inertia="kg·m²",
        flywheel_inertia_without_gravity="kg·m²", flywheel_inertia_textbook="kg·m²", rpm_min="1/min",
        rpm_max="1/min",
    )  # fmt: skip
    summary = [
        f"{machine.name}: {counted(len(machine), 'cylinder')}, {machine.strokes}-stroke, shaft inertia "
        f"{machine.shaft_inertia:g} kg·m², load {load}, drive {drive or 'none'}",
        "δ = (ω_max − ω_min)/ω_mean (time mean); gravity_effect = δ/δ without gravity − 1 (a fraction); "
        "delta_coasting: δ with gas, drive and load removed (J(φ) and gravity)",
    ]
    near = frame.index[frame["near_stall"].astype(bool)]  # every row has it, False where stalled
    if len(near):
        speeds_text = ", ".join(f"{n:.6g}" for n in near)
        note = f"note: near_stall at {speeds_text} rpm: {NEAR_STALL_NOTE}"
        summary.append(note)
        if fmt == "csv":
            click.echo(note, err=True)
    if target is not None:
        summary.append(f"flywheel_inertia: the shaft inertia [kg·m²] for δ = {target:.4g} (1/{1 / target:.4g})")
    meta = dict(
        machine=machine.name, load=load, drive=drive, delta_target=target, target_delta=target,
        near_stall_delta=NEAR_STALL_DELTA, units=units,
    )  # fmt: skip
    write_result(readable(frame, DIGITS) if fmt == "table" else frame, fmt, out_path, summary=summary, json_meta=meta)


def _speed_set(machine: Machine, points: int) -> list[float | None]:
    """The machine's running speed and ``points`` speeds spread over its range."""
    speed = _speed(machine, None, "--rpm")
    if machine.rpm_range is None:
        return [speed]
    low, high = machine.rpm_range
    return sorted({speed, *np.linspace(low, high, points).tolist()})
