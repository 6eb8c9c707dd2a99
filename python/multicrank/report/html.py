"""The report as a directory: ``index.html`` (its figures embedded, so that the page stands
alone), every figure as PNG and every table as CSV beside it, each file written whole or not
at all. The motion part (:mod:`.motion`) comes first, then the forces on the frame and the
bearings (:mod:`.forces`), then what to change (:mod:`.design`), then the gravity part
(:mod:`.gravity`)."""

from __future__ import annotations

import base64
import html
import io
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd

from .._files import TEMPORARY_SUFFIX, atomic_directory, write_atomically
from .._optional import require
from .._validation import refused
from .design import counterweight_forces_table, counterweight_table, design_html, design_results, firing_table
from .forces import bearing_polar_figure, bearing_summary_table, forces_html, forces_results, orders_table
from .gravity import (
    curves_figure,
    gravity_html,
    layouts_figure,
    machines_figure,
    paper_table_frame,
    significance_map,
    spectra_figure,
    surviving_tables,
    truncation_figure,
)
from .gravity_map import gravity_map_figure
from .motion import (
    motion_html,
    motion_results,
    orders_figure,
    speed_figure,
    speed_range_figure,
    torque_figure,
)
from .settings import ReportSettings, running_speed, speed_range
from .torsion import campbell_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["STYLE", "write_report"]


def _png(fig: Figure, path: Path) -> str:
    """Write ``fig`` to ``path`` as PNG and close it; returns the PNG as a data: URL to embed."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", bbox_inches="tight")
    fig.clf()
    import matplotlib.pyplot as plt

    plt.close(fig)
    data = buffer.getvalue()
    write_atomically(path, data)
    return "data:image/png;base64," + base64.b64encode(data).decode()


STYLE = """
body { font-family: system-ui, sans-serif; max-width: 1100px; margin: 2em auto; color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; } h2 { border-bottom: 1px solid #ccc; padding-bottom: .2em; margin-top: 2em; }
img { max-width: 100%; border: 1px solid #eee; }
table { border-collapse: collapse; margin: 1em 0; font-size: .9em; }
td, th { border: 1px solid #ccc; padding: .2em .5em; text-align: center; }
table.bool td { width: 1.6em; color: #1a5fb4; }
td.diff { background: #fdd; }
tr.own td { background: #e8f0fe; font-weight: bold; }
caption { caption-side: top; font-weight: bold; text-align: left; padding-bottom: .3em; }
.note { color: #555; font-size: .9em; }
.warning { background: #fff4e0; border-left: 4px solid #e66100; padding: .3em .6em; }
.tables { display: flex; flex-wrap: wrap; gap: 2em; }
"""


def write_report(out: str | Path, settings: ReportSettings | None = None, progress: bool = True) -> Path:
    """Write the report into the folder ``out``; returns the path of its index.html.

    The report is written into a new folder beside ``out`` and replaces ``out`` whole once
    it is complete: a report interrupted (an error, Ctrl-C) leaves ``out`` as it was, and a
    finished one leaves no file of the former report behind. The parent folders are created
    if needed.

    Parameters
    ----------
    out : str or pathlib.Path
        The report's folder: a new one, an empty one or a former report's.
    settings : ReportSettings, optional
        What the report is about [default: ``ReportSettings()``].
    progress : bool, default True
        Show a progress bar (tqdm) over the report's parts.

    Returns
    -------
    pathlib.Path
        ``out``/index.html.

    Raises
    ------
    MechanismError
        Before anything is written: for a machine without a running speed or speed range,
        and for an ``out`` that is not a folder this may replace (a file, the current folder
        or one holding it, a folder with other files than a report's).
    """
    settings = settings or ReportSettings()
    # The user's mistakes first, then the missing extra, both before anything is written.
    running_speed(settings.machine)
    for machine in settings.machines.values():
        speed_range(machine)
    target = replaceable_folder(out)
    require("matplotlib", "report")
    with atomic_directory(target) as folder:
        _write_files(folder, settings, progress)
    return target / "index.html"


# What a report's folder holds: index.html, PNG figures and CSV tables (any version's names).
_REPORT_SUFFIXES = (".html", ".png", ".csv")


def replaceable_folder(out: str | Path, where: str | None = None) -> Path:
    """``out`` as an absolute path, checked to be a folder the report may replace whole; a
    refusal starts with ``where`` (default ``out = '…'``; the command line names its option)."""
    target = Path(out).resolve()
    where = where or f"out = {str(out)!r}"
    if target == Path.cwd() or target in Path.cwd().parents:
        raise refused("out", f"{where} is the current folder or holds it; the report replaces its folder whole")
    if not target.exists():
        above = next(folder for folder in target.parents if folder.exists())  # "/" at least
        if not above.is_dir():
            raise refused("out", f"{where}: {above} is a file, not a folder")
        return target
    if not target.is_dir():
        raise refused("out", f"{where} is a file, not a folder")
    # A temporary file that a killed run of an earlier version left inside it is a report's too.
    entries = [e for e in target.iterdir() if not (e.name.startswith(".") and e.name.endswith(TEMPORARY_SUFFIX))]
    others = [e.name for e in entries if not (e.is_file() and e.suffix.lower() in _REPORT_SUFFIXES)]
    if others or (entries and not (target / "index.html").is_file()):
        shown = ", ".join(sorted(others)[:3]) or "no index.html"
        raise refused(
            "out",
            f"{where} holds other files than a report's ({shown}); the report replaces its folder whole: "
            "give a new or empty folder, or a former report's",
        )
    return target


def _write_files(out: Path, settings: ReportSettings, progress: bool) -> Path:
    """Write the report's files into the (empty) folder ``out``; returns its index.html."""
    from tqdm.auto import tqdm

    machine = settings.machine
    sections: list[str] = []
    steps = [
        "motion",
        "forces",
        "design",
        "curves",
        "spectra",
        "tables",
        "truncation",
        "significance",
        "machines",
        "layouts",
    ]
    bar = tqdm(steps, desc="report", unit="part", disable=not progress)
    figures: dict[str, str] = {}

    def save(name: str, fig: Figure, table: pd.DataFrame | None) -> None:
        figures[name] = _png(fig, out / f"{name}.png")
        if table is not None:
            write_atomically(out / f"{name}.csv", table.to_csv(index=False))

    for step in bar:
        bar.set_postfix_str(step)
        if step == "motion":
            motion = motion_results(settings)
            save("motion_speed", *speed_figure(motion))
            save("motion_torques", *torque_figure(motion))
            save("motion_speed_range", *speed_range_figure(motion))
            save("motion_gravity_map", *gravity_map_figure(motion, machine, settings.threshold))
            save("motion_orders", *orders_figure(motion))
        elif step == "forces":
            forces = forces_results(settings)
            write_atomically(out / "forces_orders.csv", orders_table(forces).to_csv(index=False))
            save("forces_bearing_loads", *bearing_polar_figure(forces))
            write_atomically(out / "forces_bearing_summary.csv", bearing_summary_table(forces).to_csv(index=False))
        elif step == "design":
            design = design_results(settings)
            write_atomically(out / "design_firing_orders.csv", firing_table(design).to_csv(index=False))
            write_atomically(out / "design_counterweights.csv", counterweight_table(design).to_csv(index=False))
            write_atomically(
                out / "design_counterweight_forces.csv", counterweight_forces_table(design).to_csv(index=False)
            )
            if design.resonances is not None:
                save("design_campbell", *campbell_figure(machine, design.rpm, design.resonances))
        elif step == "curves":
            for strokes in (2, 4):
                for quantity in ("energy", "force"):
                    save(f"{quantity}_{strokes}stroke", *curves_figure(settings, strokes, quantity))
        elif step == "spectra":
            for strokes in (2, 4):
                save(f"spectra_{strokes}stroke", *spectra_figure(settings, strokes))
        elif step == "tables":
            tables = surviving_tables(settings)
            for name, frame in tables.items():
                write_atomically(out / f"{name}.csv", frame.astype(int).to_csv())
            paper = paper_table_frame(settings.k_max)
            write_atomically(out / "paper_table1_printed.csv", paper.astype(int).to_csv())
        elif step == "truncation":
            save("paper_truncation_error", *truncation_figure(settings))
        elif step == "significance":
            save("gravity_significance_k_lambda", *significance_map(settings))
        elif step == "machines":
            save("gravity_significance_machines", *machines_figure(settings))
        elif step == "layouts":
            figure, layouts = layouts_figure(settings)
            save("layouts", figure, layouts)

    sections.append(motion_html(motion, machine, figures, settings.threshold))
    sections.append(forces_html(forces, figures))
    sections.append(design_html(design, figures))
    sections.append(gravity_html(settings, figures, tables, paper, layouts))
    from .._native import __version__

    page = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>multicrank report — {html.escape(machine.name)}</title>
<style>{STYLE}</style></head><body>
<h1>Gravity in multi-crank mechanisms — report for <i>{html.escape(machine.name)}</i></h1>
<p>Generalised Lagrange forces due to potential energy after M. Stańczak, corrected and extended by
multicrank {html.escape(__version__)}: exact Λ<sub>n</sub>, every surviving harmonic, exact extrema.</p>
{"".join(sections)}
</body></html>
"""
    index = out / "index.html"
    write_atomically(index, page)
    return index
