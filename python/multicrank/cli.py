"""The `multicrank` command line."""

from __future__ import annotations

import json
import sys

import click
import numpy as np

from . import __version__
from .evaluation import generalized_force, potential_energy
from .presets import DEFAULT_ENGINE, ENGINES

FORMATS = ("table", "csv", "json")


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="multicrank")
def main() -> None:
    """Gravitational potential energy U* and generalised force Q_u* = dU*/dφ of
    multi-crank piston mechanisms (dimensionless: U* = U/(I_w ω²))."""


@main.command("eval")
@click.option(
    "--engine",
    "engine_name",
    type=click.Choice(sorted(ENGINES)),
    default=DEFAULT_ENGINE.name,
    show_default=True,
    help="Built-in engine whose parameters are used.",
)
@click.option("--cranks", type=click.IntRange(min=1), help="Override the number of cranks k.")
@click.option("--strokes", type=click.Choice(["2", "4"]), help="Override the working cycle.")
@click.option("--acting", type=click.Choice(["single", "double"]), help="Override single/double acting.")
@click.option("--inclination", type=float, help="Override the cylinder inclination γ, in DEGREES (90 = upright).")
@click.option("--rpm", type=click.FloatRange(min=0, min_open=True), help="Override the mean speed [1/min].")
@click.option(
    "--points", type=click.IntRange(min=1), default=24, show_default=True, help="φ grid points over one revolution."
)
@click.option("--format", "fmt", type=click.Choice(FORMATS), default="table", show_default=True)
def eval_command(engine_name, cranks, strokes, acting, inclination, rpm, points, fmt) -> None:
    """Print U_w*(φ) and Q_u*(φ) of an engine on a coarse φ grid (φ in degrees)."""
    engine = ENGINES[engine_name]
    changes = {
        key: value
        for key, value in dict(
            cranks=cranks,
            strokes=None if strokes is None else int(strokes),
            acting=acting,
            inclination_deg=inclination,
            rpm=rpm,
        ).items()
        if value is not None
    }
    engine = engine.replace(**changes)
    design = engine.design()
    phi_deg = np.arange(points) * (360.0 / points)
    phi = np.radians(phi_deg)
    energy = potential_energy(phi, **design)
    force = generalized_force(phi, **design)
    rows = list(zip(phi_deg.tolist(), energy.tolist(), force.tolist()))
    out = sys.stdout
    if fmt == "json":
        meta = {k: v for k, v in design.items() if k != "phases"}
        meta.update(engine=engine.name, cranks=engine.cranks, strokes=engine.strokes, acting=engine.acting)
        meta["phases_deg"] = np.degrees(design["phases"]).tolist()
        json.dump(
            {"engine": meta, "phi_deg": phi_deg.tolist(), "potential_energy": energy.tolist(),
             "generalized_force": force.tolist()},
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
    out.write(
        f"{engine.name}: k = {engine.cranks}, {engine.strokes}-stroke, {engine.acting}-acting, "
        f"γ = {engine.inclination_deg:g}°, λ = {engine.crank_ratio:.4g}, n = {engine.rpm:g} rpm\n"
        f"u1 = {design['u1']:.6g}, u2 = {design['u2']:.6g} (dimensionless, ÷ I_w ω²)\n\n"
    )
    out.write(f"{'φ [deg]':>9}  {'U_w*':>14}  {'Q_u*':>14}\n")
    for p, u, q in rows:
        out.write(f"{p:9.2f}  {u:14.6e}  {q:14.6e}\n")


if __name__ == "__main__":
    main()
