"""``multicrank report``: the HTML report of a machine (:func:`multicrank.report.write_report`)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import click

from .._native import MechanismError
from ._group import UserError, machine_option, renamed_option

if TYPE_CHECKING:
    from ..machine.machine import Machine

__all__ = ["report_command"]


def _finite_option(value: float | None, option: str) -> float | None:
    """click's FloatRange lets NaN through (every comparison with it is false)."""
    if value is not None and not math.isfinite(value):
        raise click.BadParameter(f"{value} is not a finite number", param_hint=option)
    return value


@click.command("report", short_help="Write the HTML report (PNG figures, CSV tables).")
@click.option(
    "--out",
    "out_dir",
    type=click.Path(file_okay=False),
    default="multicrank-report",
    show_default=True,
    metavar="DIR",
    help="The folder for index.html and its figures (PNG) and tables (CSV): a new or empty one, or a "
    "former report's, which is replaced whole once the new report is complete (until then, and after "
    "an interruption, it stays as it was).",
)
@machine_option
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
@renamed_option(
    "--delta-target",
    "--delta",
    "delta_target",
    type=click.FloatRange(min=0, max=1, min_open=True, max_open=True),
    default=None,
    help="Size the flywheel for this δ [default: the preset's class limit, else the machine's δ without gravity]. "
    "--delta is its former name.",
)
@click.option("--progress/--no-progress", default=True, show_default=True, help="Show a progress bar.")
def report_command(
    out_dir: str,
    machine: Machine,
    k_max: int,
    n_max: int,
    points: int,
    threshold: float | None,
    delta_target: float | None,
    progress: bool,
) -> None:
    """Write the report: first the machine's steady running with and without gravity (δ, the
    flywheel, ω(φ), the torques and their orders, δ over the speed range), then what to change
    (the best firing orders its crank allows and the counterweights that minimise δ), then
    the paper's analysis — curves, spectra, Tables 1–2, the truncation error, the gravity-significance map,
    conventions and errata — as index.html + PNG + CSV."""
    from ..report.html import replaceable_folder, write_report
    from ..report.settings import DEFAULT_THRESHOLD, ReportSettings

    settings = ReportSettings(
        machine=machine,
        k_max=k_max,
        n_max=n_max,
        points=points,
        threshold=threshold or DEFAULT_THRESHOLD,
        delta_target=delta_target,
    )
    try:
        replaceable_folder(out_dir, f"--out {out_dir}")  # refused in the option's words
        index = write_report(out_dir, settings, progress=progress)
    except OSError as error:
        raise UserError(f"--out {out_dir}: {error.strerror or error}") from None
    except MechanismError as error:
        raise UserError(str(error)) from None
    click.echo(f"report written: {index}")
