"""The ``multicrank`` command group: its error handling, which turns a user's mistake into one
line and exit status 2, and the ``--engine`` option that most commands share."""

from __future__ import annotations

from typing import TYPE_CHECKING

import click

from .._native import MechanismError, __version__
from .._optional import OptionalDependencyError
from ..presets import DEFAULT_ENGINE_NAME, ENGINES

if TYPE_CHECKING:
    from ..machine.machine import Machine

__all__ = ["MissingExtra", "UserError", "engine_option", "main"]


class MissingExtra(click.ClickException):
    """An optional dependency is missing: one line on stderr, exit status 2 (as a usage error)."""

    exit_code = 2


class UserError(click.ClickException):
    """A mistake in what the user gave (a machine file, a machine without a speed): one line on
    stderr, exit status 2 (as a usage error)."""

    exit_code = 2


class _Commands(click.Group):
    """The group: the library's errors become one line, never a traceback."""

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


def _load_engine(ctx: click.Context, param: click.Parameter, spec: str) -> Machine:
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
