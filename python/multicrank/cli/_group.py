"""The ``multicrank`` command group: its error handling, which turns a user's mistake into one
line and exit status 2, and the ``--machine`` option that most commands share."""

from __future__ import annotations

from typing import TYPE_CHECKING

import click

from .._native import MechanismError, __version__
from .._optional import OptionalDependencyError
from ..presets import DEFAULT_MACHINE_NAME, MACHINES

if TYPE_CHECKING:
    from ..machine.machine import Machine

__all__ = ["MissingExtra", "UserError", "machine_option", "main"]


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


def _load_machine(ctx: click.Context, param: click.Parameter, spec: str) -> Machine:
    """--machine: a built-in machine's name or a TOML machine file, as a multicrank.Machine."""
    from ..presets import machine_by_name_or_file

    try:
        return machine_by_name_or_file(spec)
    except MechanismError as error:
        raise UserError(f"--machine: {error}") from None


# --engine is the option's name of 0.1, still accepted (a machine is what it always took).
machine_option = click.option(
    "--machine",
    "--engine",
    "machine",
    default=DEFAULT_MACHINE_NAME,
    show_default=True,
    callback=_load_machine,
    metavar="NAME|FILE",
    help=f"A built-in machine ({', '.join(MACHINES)}) or a TOML machine file (docs/machine-files.md); "
    "--engine is its former name.",
)
