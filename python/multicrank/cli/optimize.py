"""``multicrank optimize``: the design aid on the command line — ``optimize firing`` (the
firing orders a machine's crank allows, ranked by δ with gravity: :func:`multicrank.firing_orders`)
and ``optimize counterweights`` (the counterweight per throw that minimises an objective:
:func:`multicrank.optimize_counterweights`)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import click

from .._native import MechanismError
from .._text import counted
from .._validation import refused
from ..design.counterweights import OBJECTIVES, RENAMED_OBJECTIVES
from ..design.criteria import RANKINGS, SHAFT_CRITERIA, VOCABULARY
from ._group import UserError, machine_option, note_renamed, options_named
from ._output import format_option, out_option, write_result

if TYPE_CHECKING:
    import pandas as pd

    from ..machine.machine import Machine

__all__ = ["counterweights_command", "firing_command", "optimize_command"]

#: The constraints' options, by the library's parameter.
_LIMIT_OPTIONS = {
    "max_bearing_load": "--max-bearing-load",
    "max_free_force": "--max-free-force",
    "max_free_moment": "--max-free-moment",
}
#: Each command's options by the library's parameter, for its refusals (:func:`~._group.options_named`):
#: a constraint refused, or one that no counterweights keep, is named by the option the user typed.
FIRING_OPTIONS = {
    "rpm": "--rpm",
    "rank_by": "--rank-by",
    "max_order": "--max-order",
    "modes": "--modes",
    "max_candidates": "--max-candidates",
}
COUNTERWEIGHT_OPTIONS = {
    "rpm": "--rpm",
    "objective": "--objective",
    "bounds": "--bounds",
    **_LIMIT_OPTIONS,
    "seed": "--seed",
    "maxiter": "--maxiter",
}
#: The unit of each constraint.
_LIMIT_UNITS = {"max_bearing_load": "N", "max_free_force": "N", "max_free_moment": "N·m"}

_rpm_option = click.option(
    "--rpm",
    type=float,
    default=None,
    metavar="RPM",
    help="The mean speed [1/min] of the steady states (balance load) [default: the machine's own].",
)
_progress_option = click.option(
    "--progress/--no-progress", default=True, show_default=True, help="Show a progress bar."
)


# invoke_without_command: used alone the group prints its help itself, not through click's
# no_args_is_help (an error to make_context, which the docs' tests parse each command with).
@click.group(
    "optimize",
    invoke_without_command=True,
    subcommand_metavar="COMMAND [ARGS]...",
    short_help="Design aid: firing orders and counterweights, ranked by δ with gravity.",
)
@click.pass_context
def optimize_command(ctx: click.Context) -> None:
    """The design aid: what to change in a machine so that it runs smoother with gravity.

    "firing" ranks the firing orders the machine's crank allows by δ with gravity;
    "counterweights" finds the counterweight of each throw that minimises δ (or how much
    gravity changes it, or δ over the speed range). Each has --help.
    """
    if ctx.invoked_subcommand is None:
        click.echo(ctx.get_help())


def _write(
    frame: pd.DataFrame, fmt: str, out_path: str | None, *, summary: list[str], json_meta: dict[str, Any]
) -> None:
    """write_result, a file that cannot be written one line naming --out."""
    try:
        write_result(frame, fmt, out_path, summary=summary, json_meta=json_meta)
    except OSError as error:
        raise UserError(f"--out {out_path}: {error.strerror or error}") from None


_count = counted  # "1 cylinder", "12 cylinders"


def _degrees_text(phases: tuple[float, ...]) -> str:
    """Phases [rad] as degrees to a hundredth, for the printed table: "0 180 360 540"."""
    return " ".join(f"{round(math.degrees(a), 2) + 0.0:g}" for a in phases)


def _ranking(name: str) -> str:
    """A firing_orders ``rank_by`` for --help: its words and unit (the one vocabulary), and
    whether it needs a shaft."""
    return VOCABULARY[name].label + (" (needs a shaft)" if name in SHAFT_CRITERIA else "")


@click.command("firing", short_help="The firing orders the machine's crank allows, judged by every criterion.")
@machine_option
@_rpm_option
@click.option(
    "--shaft",
    "shaft_path",
    type=click.Path(dir_okay=False),
    default=None,
    metavar="FILE.toml",
    help="A TOML file with a [shaft] table (or a machine file with one): the shaft as a torsional chain, for "
    "the torsional merit [default: the machine file's own [shaft], if any].",
)
@click.option(
    "--rank-by",
    type=click.Choice(list(RANKINGS)),
    default="delta",
    show_default=True,
    help="The criterion the rows are sorted by (smallest first): "
    + "; ".join(f"{name}: {_ranking(name)}" for name in RANKINGS)
    + ".",
)
@click.option(
    "--max-order",
    type=click.IntRange(min=1),
    default=12,
    show_default=True,
    metavar="ORDER",
    help="The highest torque order ν (per revolution) for largest_order and the torsional criteria.",
)
@click.option(
    "--modes",
    type=click.IntRange(min=1),
    default=2,
    show_default=True,
    metavar="COUNT",
    help="With a shaft: how many of its elastic modes, from the lowest, the torsional criteria weigh.",
)
@click.option(
    "--max-candidates",
    type=click.IntRange(min=1),
    default=4096,  # multicrank.design.firing.DEFAULT_MAX_CANDIDATES
    show_default=True,
    metavar="COUNT",
    help="At most this many phase assignments are tried; the output says when the crank allows more.",
)
@format_option
@out_option
@_progress_option
@options_named(FIRING_OPTIONS)
def firing_command(
    machine: Machine,
    rpm: float | None,
    shaft_path: str | None,
    rank_by: str,
    max_order: int,
    modes: int,
    max_candidates: int,
    fmt: str,
    out_path: str | None,
    progress: bool,
) -> None:
    """The distinct firing orders the machine's crank allows, judged by every criterion.

    A four-stroke crank fixes each cylinder's phase only modulo 360° (the cam decides the
    revolution it fires on); a two-stroke one is its throws' angles, in any arrangement.
    Candidates that run alike (the same motion, shifted) are counted once, unless the frame or
    the shaft tells them apart. Each is solved at --rpm with the balance load: δ with and
    without gravity, gravity_effect = δ/δ without gravity − 1, stalled, near_stall (δ > 0.5:
    it nearly stops each cycle), and the torque order with the largest amplitude [N·m]; at
    --rpm held constant, the first- and second-order free moments [N·m] and the largest
    main-bearing load [N]; with a shaft (--shaft, or the machine file's [shaft]), of the
    resonances of its --modes lowest modes in the machine's speed range, torsional_major and
    torsional_minor [N·m/√(kg·m²)], the largest modal excitation (mass-normalised mode shape,
    comparable between modes) by a major order (every cylinder in phase: the same for every
    firing order) and by a minor one (which the firing order decides), and torsional_merit
    [N·m], the first mode's largest classical excitation. pareto marks the rows no other row
    beats on every criterion (torsional_merit is none); --rank-by sorts by one.

    firing lists the cylinders (numbered from 1) in the order they fire, "+" joining those
    that fire together; the phases α_j [deg] are in the machine's cylinder order (csv: one
    column phase_J_deg per cylinder; json: a list phases_deg). Whether every candidate was
    tried goes above the table (csv: to stderr; json: "exhaustive").
    """
    from ..design.firing import firing_orders
    from ..machine.shaft import Shaft

    if shaft_path is not None:
        try:
            machine = machine.replace(shaft=Shaft.from_toml(shaft_path))
        except MechanismError as error:
            raise UserError(f"--shaft {shaft_path}: {error}") from None
    if rank_by in SHAFT_CRITERIA and machine.shaft is None:
        raise UserError(
            f"--rank-by {rank_by} needs a shaft: give --shaft FILE.toml (machine {machine.name!r} has none)"
        )
    table = firing_orders(
        machine,
        rpm=rpm,
        rank_by=rank_by,
        max_order=max_order,
        modes=modes,
        max_candidates=max_candidates,
        progress=progress,
    )
    attrs = dict(table.attrs)
    frame = table.drop(columns=["machine", "phases"])
    frame.index = range(1, len(frame) + 1)
    frame.index.name = "rank"
    phases = table["phases"].tolist()
    if fmt == "csv":
        for j in range(len(machine)):
            frame.insert(1 + j, f"phase_{j + 1}_deg", [math.degrees(p[j]) for p in phases])
    elif fmt == "json":
        frame.insert(1, "phases_deg", [[math.degrees(a) for a in p] for p in phases])
    else:
        frame.insert(1, "phases_deg", [_degrees_text(p) for p in phases])
    allowed = f"the crank allows {_count(attrs['candidates'], 'phase assignment')}"
    if attrs["exhaustive"]:
        tried = f"exhaustive: {allowed}, all tried"
    else:
        tried = f"not exhaustive: {allowed}, only the first {max_candidates:,} tried (raise --max-candidates)"
    summary = [
        f"{machine.name}: {_count(len(machine), 'cylinder')}, {machine.strokes}-stroke, at {attrs['rpm']:g} rpm "
        f"(balance load): {_count(attrs['distinct'], 'distinct firing order')}, ranked by "
        f"{VOCABULARY[rank_by].label}; {int(table['pareto'].sum())} on the Pareto front",
        tried,
        "δ = (ω_max − ω_min)/ω_mean; gravity_effect = δ/δ without gravity − 1; phases_deg: α_j [deg] in the "
        f"machine's cylinder order; largest_order: the torque order ν ≤ {max_order} of the largest amplitude [N·m]",
        f"at {attrs['rpm']:g} rpm held constant: free_moment_1, free_moment_2 [N·m] (inertial), max_bearing_load [N] "
        "(gas, inertia and weights); pareto: no other row at least as good on every criterion and better on one",
    ]
    if attrs["speed_range"] is not None:
        low, high = attrs["speed_range"]
        summary.append(
            f"of the resonances of modes ≤ {modes} and orders ≤ {max_order} in {low:g}–{high:g} rpm "
            "(mc.torsional_merit): torsional_major, torsional_minor [N·m/√(kg·m²)] the largest modal excitation "
            "by a major (every cylinder in phase) and a minor order; torsional_merit [N·m] the first mode's "
            "largest excitation"
        )
    near = int(table["near_stall"].sum())
    if near:
        summary.append(f"note: {_count(near, 'firing order')} near_stall: {_near_stall_note()}")
    if fmt == "csv":
        click.echo(f"{machine.name}: {tried}", err=True)
        if near:
            click.echo(f"{machine.name}: {summary[-1]}", err=True)
    meta = dict(
        machine=machine.name,
        rpm=attrs["rpm"],
        candidates=attrs["candidates"],
        distinct=attrs["distinct"],
        exhaustive=attrs["exhaustive"],
        max_order=max_order,
        modes=modes,
        rank_by=rank_by,
        speed_range=attrs["speed_range"],
        units=dict(
            rpm="1/min",
            phases_deg="deg",
            largest_order="per revolution",
            largest_order_amplitude="N·m",
            free_moment_1="N·m",
            free_moment_2="N·m",
            max_bearing_load="N",
            torsional_major="N·m/√(kg·m²)",
            torsional_minor="N·m/√(kg·m²)",
            torsional_merit="N·m",
        ),
    )
    _write(frame, fmt, out_path, summary=summary, json_meta=meta)


def _bounds(value: tuple[float, float] | None) -> tuple[float, float] | None:
    """--bounds LOW HIGH: finite, 0 <= LOW < HIGH [kg·m]."""
    if value is None:
        return None
    low, high = value
    if not (math.isfinite(low) and math.isfinite(high) and 0 <= low < high):
        raise refused("--bounds", f"--bounds {low:g} {high:g} is out of range; allowed: finite 0 <= LOW < HIGH [kg·m]")
    return (low, high)


@click.command(
    "counterweights",
    short_help="The counterweight per throw that minimises δ, the bearing loads or the free force.",
)
@machine_option
@click.option(
    "--objective",
    type=click.Choice([*OBJECTIVES, *RENAMED_OBJECTIVES]),
    default="delta",
    show_default=True,
    help="What to minimise: "
    + "; ".join(f"{name}: {VOCABULARY[name].label}" for name in OBJECTIVES)
    + " (the last two at --rpm held constant; bearing_load and shaking_force, their names of 0.1, are "
    "deprecated).",
)
@click.option(
    "--bounds",
    nargs=2,
    type=float,
    default=None,
    metavar="LOW HIGH",
    help="The counterweight's first moment m·r [kg·m] allowed at every throw [default: 0 to twice the "
    "throw's own first moment of crank, rod and piston masses].",
)
@_rpm_option
@click.option(
    "--max-bearing-load",
    type=float,
    default=None,
    metavar="N",
    help="A constraint: the optimum's largest main-bearing load over the cycle at --rpm is at most N [newtons].",
)
@click.option(
    "--max-free-force",
    type=float,
    default=None,
    metavar="N",
    help="A constraint: the optimum's first-order free force at --rpm is at most N [newtons].",
)
@click.option(
    "--max-free-moment",
    type=float,
    default=None,
    metavar="NM",
    help="A constraint: the optimum's first-order free moment about the engine centre at --rpm is at most NM "
    "[N·m] (counterweights that differ along the shaft rock the frame).",
)
@click.option(
    "--seed", type=click.IntRange(min=0), default=0, show_default=True, metavar="SEED", help="The optimiser's seed."
)
@click.option(
    "--maxiter",
    type=click.IntRange(min=1),
    default=200,
    show_default=True,
    metavar="GENERATIONS",
    help="At most this many generations of the differential evolution.",
)
@format_option
@out_option
@_progress_option
@options_named(COUNTERWEIGHT_OPTIONS)
def counterweights_command(
    machine: Machine,
    objective: str,
    bounds: tuple[float, float] | None,
    rpm: float | None,
    max_bearing_load: float | None,
    max_free_force: float | None,
    max_free_moment: float | None,
    seed: int,
    maxiter: int,
    fmt: str,
    out_path: str | None,
    progress: bool,
) -> None:
    """The counterweight of each throw (its first moment m·r [kg·m], opposite the crank pin)
    that minimises an objective, by SciPy's differential evolution (each generation one motion
    sweep), polished — within --max-bearing-load, --max-free-force and --max-free-moment where
    given.

    Prints one row per throw: the cylinders on it, its angle [deg], the counterweight as
    given and the optimum [kg·m]; above the table the objective before and after, every
    criterion before and after (δ with gravity, the first-order free force and moment, the
    largest main-bearing load, the last three at --rpm held constant), the constraints and
    whether the optimiser converged (csv: to stderr; json: an object with these and the rows).
    A throw whose optimum lies on a bound of the search is marked "at a bound of the search":
    widen --bounds to see past it.
    """
    limits = _bounds(bounds)
    if objective in RENAMED_OBJECTIVES:  # a name of 0.1: the criterion it is, said once the command has run
        renamed = RENAMED_OBJECTIVES[objective]
        note_renamed(
            click.get_current_context(),
            f"note: --objective {objective} is now --objective {renamed} (the old name goes in 0.3)",
        )
        objective = renamed

    from ..design.counterweights import optimize_counterweights

    found = optimize_counterweights(
        machine,
        objective=objective,
        bounds=limits,
        rpm=rpm,
        max_bearing_load=max_bearing_load,
        max_free_force=max_free_force,
        max_free_moment=max_free_moment,
        seed=seed,
        maxiter=maxiter,
        progress=progress,
    )
    frame = found.to_frame().set_index("throw")
    converged = "converged" if found.success else "NOT converged"
    criteria = found.criteria()
    summary = [
        f"{machine.name}: the counterweight per throw [kg·m, opposite the crank pin] minimising "
        f"{found.objective_name} at {found.rpm:g} rpm",
        f"{found.objective_name}: {found.objective_before:.6g} as given → {found.objective:.6g} "
        f"({_percent(found.improvement)} lower)",
    ]
    summary += [
        f"{VOCABULARY[str(name)].label}: {row.before:.6g} as given → {row.after:.6g}"
        for name, row in criteria.iterrows()
    ]
    given = {name: getattr(found, f"{name}_limit") for name in _LIMIT_OPTIONS}
    kept = [
        f"{option} {given[name]:g} {_LIMIT_UNITS[name]}"
        for name, option in _LIMIT_OPTIONS.items()
        if given[name] is not None
    ]
    if kept:
        summary.append("kept: " + ", ".join(kept))
    if any(found.at_bound):
        throws = [str(t) for t, on in zip(frame.index, found.at_bound, strict=True) if on]
        summary.append(
            f"at a bound of the search: throw{'s' if len(throws) > 1 else ''} {', '.join(throws)} (the optimum would "
            "go further; widen --bounds, or take the bound as a limit of the design)"
        )
    summary.append(f"{converged}: {found.message} ({found.nit} generations, {found.nfev} evaluations, seed {seed})")
    from ..motion.steady import NEAR_STALL_DELTA

    if max(found.delta_before, found.delta) > NEAR_STALL_DELTA:
        summary.append(f"note: δ {found.delta_before:.4g} as given, {found.delta:.4g} optimum: {_near_stall_note()}")
    if fmt == "csv":
        for line in summary[1:]:
            click.echo(f"{machine.name}: {line}", err=True)
    meta = dict(
        machine=machine.name,
        objective_name=found.objective_name,
        objective_before=float(found.objective_before),
        objective=float(found.objective),
        improvement=float(found.improvement),
        **{key: float(getattr(found, key)) for name in criteria.index for key in (f"{name}_before", name)},
        max_bearing_load_limit=given["max_bearing_load"],
        max_free_force_limit=given["max_free_force"],
        max_free_moment_limit=given["max_free_moment"],
        at_bound=list(found.at_bound),
        rpm=float(found.rpm),
        success=bool(found.success),
        message=str(found.message),
        nit=int(found.nit),
        nfev=int(found.nfev),
        seed=seed,
        maxiter=maxiter,
        bounds=None if bounds is None else list(bounds),
        units=dict(
            angle_deg="deg",
            counterweight_before="kg·m",
            counterweight="kg·m",
            rpm="1/min",
            **{key: unit for name, unit in criteria["unit"].items() if unit for key in (f"{name}_before", name)},
            max_bearing_load_limit="N",
            max_free_force_limit="N",
            max_free_moment_limit="N·m",
        ),
    )
    _write(frame, fmt, out_path, summary=summary, json_meta=meta)


def _near_stall_note() -> str:
    from ..motion.steady import NEAR_STALL_NOTE

    return NEAR_STALL_NOTE


def _percent(fraction: float) -> str:
    return f"{100 * fraction:.3g} %" if math.isfinite(fraction) else "n/a"


optimize_command.add_command(firing_command)
optimize_command.add_command(counterweights_command)
