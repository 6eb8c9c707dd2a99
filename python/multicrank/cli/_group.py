"""The ``multicrank`` command group: its error handling, which turns a user's mistake into one
line and exit status 2, and the ``--machine`` option that most commands share."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from .._native import MechanismError, __version__
from .._optional import OptionalDependencyError
from ..presets import DEFAULT_MACHINE_NAME, MACHINES

if TYPE_CHECKING:
    from ..machine.machine import Machine

__all__ = [
    "INTERRUPTED",
    "MissingExtra",
    "UserError",
    "machine_option",
    "main",
    "note_renamed",
    "options_named",
    "renamed_option",
]


class MissingExtra(click.ClickException):
    """An optional dependency is missing: one line on stderr, exit status 2 (as a usage error)."""

    exit_code = 2


class UserError(click.ClickException):
    """A mistake in what the user gave (a machine file, a machine without a speed): one line on
    stderr, exit status 2 (as a usage error)."""

    exit_code = 2


@contextmanager
def options_named(options: Mapping[str, str]) -> Iterator[None]:
    """The library's refusals inside, named by the option the user typed: ``options`` maps
    a parameter of the library (``"max_order"``) to the command's option (``"--max-order"``),
    and a :class:`MechanismError` whose ``parameter`` it maps is the one line ``--max-order:
    <message>`` (a :class:`UserError`); any other goes on as it is. The error's parameter
    decides, never its message. A ``with`` block, or a command's decorator (innermost, on the
    function click calls)."""
    try:
        yield
    except MechanismError as error:
        option = options.get(error.parameter) if error.parameter is not None else None
        if option is None:
            raise
        raise UserError(f"{option}: {error}") from None


#: The exit status of a command stopped by Ctrl-C: 128 + SIGINT, as a shell reports a
#: process that the signal ended.
INTERRUPTED = 130


#: Where the notes on former names wait (ctx.meta: shared by the contexts of one invocation).
_NOTES = "multicrank.notes"


def note_renamed(ctx: click.Context, text: str) -> None:
    """A note on stderr that a former name was used (``text``: "note: --delta is now
    --delta-target …"), said once the command has run: a command that fails on a mistake
    says only the mistake, its one line (a bad value given under a former name included)."""
    notes = ctx.meta.setdefault(_NOTES, [])
    if text not in notes:
        notes.append(text)


class _Commands(click.Group):
    """The group: the library's errors become one line, never a traceback; Ctrl-C, whenever it
    comes, one line and exit status 130; the notes on former names once the command has run."""

    def invoke(self, ctx: click.Context) -> object:
        result = self._invoke(ctx)
        for text in ctx.meta.pop(_NOTES, []):
            click.echo(text, err=True)
        return result

    def _invoke(self, ctx: click.Context) -> object:
        try:
            return super().invoke(ctx)
        except OptionalDependencyError as error:
            raise MissingExtra(str(error)) from None
        except MechanismError as error:
            # Every check of the library names what is wrong with the input: that line is
            # the message, never a traceback.
            raise UserError(str(error)) from None
        except KeyboardInterrupt as interruption:
            # One rule for every command and every moment (reading the machine, computing,
            # writing), not click's "Aborted!" and status 1. A command that keeps something
            # says what in the interruption's message (raise KeyboardInterrupt("...")).
            kept = str(interruption)
            click.echo(f"\ninterrupted{': ' + kept if kept else ''}", err=True)
            raise click.exceptions.Exit(INTERRUPTED) from None


@click.group(cls=_Commands, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="multicrank")
def main() -> None:
    """Gravity and motion of multi-crank piston machines: the potential energy U* and the
    generalised force Q_u* = dU*/dφ (dimensionless, U* = U/(I_w ω²)), the steady running
    with and without gravity, transients, design sweeps and the report.

    Angles are typed in degrees, speeds in 1/min, torques in N·m. Each command has --help.
    """


#: Where --engine's value waits for --machine's callback (ctx.meta: shared by the contexts of
#: one invocation).
_ENGINE = "multicrank.engine"


def _remember_engine(ctx: click.Context, param: click.Parameter, spec: str | None) -> None:
    """--engine (eager, so before --machine): its value, for --machine's callback to load."""
    if spec is not None:
        ctx.meta[_ENGINE] = spec


def _load_machine(ctx: click.Context, param: click.Parameter, spec: str) -> Machine:
    """--machine (or --engine): a built-in machine's name or a TOML machine file, as a
    multicrank.Machine; a mistake is one line naming the option the user typed."""
    from ..presets import machine_by_name_or_file

    option = "--machine"
    engine = ctx.meta.pop(_ENGINE, None)
    if engine is not None:
        if ctx.get_parameter_source("machine") is click.core.ParameterSource.COMMANDLINE:
            raise UserError("--machine and --engine are one option (--engine its former name): give it once")
        spec, option = engine, "--engine"
    if spec not in MACHINES and not os.path.exists(spec):
        if os.sep in spec or "/" in spec or Path(spec).suffix:  # meant as a file
            raise UserError(f"{option}: {spec}: no such file")
        raise UserError(f"{option}: {spec!r} is neither a built-in machine ({', '.join(MACHINES)}) nor a machine file")
    try:
        return machine_by_name_or_file(spec)
    except MechanismError as error:
        raise UserError(f"{option}: {error}") from None


class _MachineOption(click.Option):
    """--machine, whose help line also names --engine (an option of its own, hidden, so that a
    message can name the option the user typed)."""

    def get_help_record(self, ctx: click.Context) -> tuple[str, str] | None:
        record = super().get_help_record(ctx)
        return None if record is None else (record[0].replace("--machine", "--machine, --engine", 1), record[1])


_machine = click.option(
    "--machine",
    "machine",
    cls=_MachineOption,
    default=DEFAULT_MACHINE_NAME,
    show_default=True,
    callback=_load_machine,
    metavar="NAME|FILE",
    help=f"A built-in machine ({', '.join(MACHINES)}) or a TOML machine file (docs/machine-files.md); "
    "--engine is its former name.",
)
# --engine is the option's name of 0.1, still accepted (a machine is what it always took).
_engine = click.option(
    "--engine", metavar="NAME|FILE", hidden=True, is_eager=True, expose_value=False, callback=_remember_engine
)


def machine_option(command: Any) -> Any:
    """The --machine option (and its former name --engine) of a command: its argument
    ``machine``, a multicrank.Machine."""
    return _engine(_machine(command))


def renamed_option(
    name: str, former: str, parameter: str, *, check: Callable[[Any, str], Any] | None = None, **attrs: Any
) -> Any:
    """The option ``name`` of a command (its argument ``parameter``; ``attrs`` as
    click.option takes them) and its former name ``former``, an option of its own, hidden: its
    value goes to ``parameter`` with one line on stderr that names the new name, once the
    command has run (:func:`note_renamed`); both given is a mistake (exit status 2).
    ``check(value, option)``, where given, checks a value given under either name and returns
    it, raising :class:`UserError` or the library's error that names ``option``, the name the
    user typed: a bad value is that one line, before any work."""
    key = f"multicrank.renamed.{parameter}"

    def checked(value: Any, option: str) -> Any:
        if value is None or check is None:
            return value
        try:
            return check(value, option)
        except MechanismError as error:
            raise UserError(str(error)) from None

    def remember(ctx: click.Context, param: click.Parameter, value: Any) -> None:
        if value is not None:
            ctx.meta[key] = checked(value, former)
            note_renamed(ctx, f"note: {former} is now {name} (the old name goes in 0.3)")

    def take(ctx: click.Context, param: click.Parameter, value: Any) -> Any:
        if key not in ctx.meta:
            return checked(value, name)
        if ctx.get_parameter_source(parameter) is click.core.ParameterSource.COMMANDLINE:
            raise UserError(f"{name} and {former} are one option ({former} its former name): give it once")
        return ctx.meta.pop(key)

    old = {k: v for k, v in attrs.items() if k in ("type", "metavar")}
    new = click.option(name, parameter, callback=take, **attrs)
    hidden = click.option(former, hidden=True, is_eager=True, expose_value=False, callback=remember, **old)
    return lambda command: hidden(new(command))
