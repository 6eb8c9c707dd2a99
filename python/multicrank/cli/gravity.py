"""The gravity commands: ``eval`` (U_w*(φ) and Q_u*(φ) of a machine) and ``tables`` (which
harmonics survive k cranks, the paper's Tables 1 and 2)."""

from __future__ import annotations

import json
import sys
from typing import TYPE_CHECKING, Any

import click
import numpy as np

from .._native import MechanismError
from .._text import counted
from .._validation import running_rpm
from ..gravity.evaluation import generalized_force, potential_energy
from ..gravity.mechanism import crank_phases
from ._group import UserError, machine_option
from ._output import format_option

if TYPE_CHECKING:
    from ..machine.machine import Machine

__all__ = ["eval_command", "tables_command"]


def _inline_variant(
    machine: Machine, cranks: int | None, strokes: str | None, acting: str | None, inclination: float | None
) -> Machine:
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
        machine = machine.replace(
            cylinders=[first.replace(phase=float(a)) for a in phases], strokes=cycle, main_bearings=None, shaft=None
        )
    if inclination is not None:
        gamma = float(np.radians(inclination))
        machine = machine.replace(cylinders=[c.replace(inclination=gamma) for c in machine.cylinders])
    return machine


@click.command("eval", short_help="U_w*(φ) and Q_u*(φ) of a machine on a coarse φ grid.")
@machine_option
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
def eval_command(
    machine: Machine,
    cranks: int | None,
    strokes: str | None,
    acting: str | None,
    inclination: float | None,
    rpm: float | None,
    points: int,
    fmt: str,
) -> None:
    """Print U_w*(φ) and Q_u*(φ) of a machine on a coarse φ grid (φ in degrees).

    --cranks, --strokes and --acting make a regular in-line machine of the machine's first
    cylinder (k cranks at the cycle's phases); --inclination tilts every cylinder.
    """
    try:
        evaluated = _inline_variant(machine, cranks, strokes, acting, inclination)
        speed = running_rpm(evaluated, rpm, "--rpm")
        try:
            design = evaluated.design(speed)  # the paper's machine: the in-line functions
        except MechanismError:
            design = None
        units = evaluated.engine(speed)
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
        acting = "double" if any(c.pressure_crank_end is not None for c in machine.cylinders) else "single"
    out = sys.stdout
    if fmt == "json":
        meta: dict[str, Any] = dict(
            name=evaluated.name, cylinders=len(evaluated), strokes=evaluated.strokes, acting=acting, rpm=speed
        )
        if design is not None:
            meta.update({k: v for k, v in design.items() if k != "phases"}, cranks=len(evaluated))
        else:
            meta.update({k: getattr(units, k).tolist() for k in ("crank_ratio", "inclination", "u1", "u2")})
        meta["phases_deg"] = np.degrees(units.phase).tolist()
        json.dump(
            {
                "machine": meta,
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
            f"{evaluated.name}: k = {len(evaluated)}, {evaluated.strokes}-stroke, {acting}-acting, "
            f"γ = {np.degrees(design['inclination']):g}°, λ = {design['crank_ratio']:.4g}, n = {speed:g} rpm\n"
            f"u1 = {design['u1']:.6g}, u2 = {design['u2']:.6g} (dimensionless, ÷ I_w ω²)\n\n"
        )
    else:
        out.write(
            f"{evaluated.name}: {counted(len(evaluated), 'cylinder')}, {evaluated.strokes}-stroke, {acting}-acting, "
            f"n = {speed:g} rpm (dimensionless, ÷ I_w ω²)\n\n"
        )
    out.write(f"{'φ [deg]':>9}  {'U_w*':>14}  {'Q_u*':>14}\n")
    for p, u, q in rows:
        out.write(f"{p:9.2f}  {u:14.6e}  {q:14.6e}\n")


@click.command("tables", short_help="Which harmonics survive k cranks (Tables 1 and 2).")
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
def tables_command(strokes: str, acting: str, k_max: int, n_max: int, fmt: str) -> None:
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
