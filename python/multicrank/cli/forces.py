"""The command ``forces``: the forces and moments a machine shakes its frame with, by order
(:func:`multicrank.shaking_forces`)."""

from __future__ import annotations

import math
import textwrap
from typing import TYPE_CHECKING, Any

import click

from .._text import column_text
from ._group import machine_option, options_named
from ._output import format_option, out_option, write_result
from .motion import readable

if TYPE_CHECKING:
    import pandas as pd

    from ..forces.shaking import ShakingForces
    from ..machine.machine import Machine

__all__ = ["bearing_summary", "forces_command"]

#: The columns of the table to read, in this order (csv and json give every column of
#: ``ShakingForces.orders``, phases and the moments' forward and backward parts included).
SHOWN = ("force_vertical", "force_horizontal", "force_forward", "force_backward", "moment_pitch", "moment_yaw")

#: Significant digits of the table to read (csv and json give 12 and 15).
DIGITS = 4

#: The options of the library's parameters, for its refusals (:func:`~._group.options_named`).
OPTIONS = {"rpm": "--rpm", "max_order": "--max-order"}


@click.command("forces", short_help="Shaking forces and moments on the frame, by order.")
@machine_option
@click.option(
    "--rpm",
    type=float,
    default=None,
    metavar="RPM",
    help="The speed [1/min]: constant, or the steady running's mean with --steady [default: the machine's].",
)
@click.option(
    "--max-order",
    "max_order",
    type=int,
    default=12,
    show_default=True,
    metavar="K",
    help="The highest order listed [per revolution]: 1 … 2048, with --steady 1 … 360.",
)
@click.option(
    "--steady",
    is_flag=True,
    help="In the steady running (load balance): its ω(φ) and ε(φ), the speed fluctuation with gravity's "
    "part carried into the inertia forces; a four-stroke machine then has half orders. "
    "Default: at the constant speed --rpm.",
)
@format_option
@out_option
@options_named(OPTIONS)
def forces_command(
    machine: Machine, rpm: float | None, max_order: int, steady: bool, fmt: str, out_path: str | None
) -> None:
    """The forces and moments the machine's moving parts shake its frame with, by order.

    The frame takes the inertial reaction −Σ m·a of the pistons, rods, crank webs and
    counterweights. For each order n (per revolution) the table gives the amplitude of the
    order's harmonic of force_vertical (positive upward) and force_horizontal (positive toward
    a cylinder at inclination 0) [N]; force_forward and force_backward [N], the parts of the
    plane force that turn with the crank and against it; and moment_pitch and moment_yaw
    [N·m], the moments of the vertical and horizontal forces about the engine centre, midway
    between the outermost cylinders, so that no number depends on where z = 0 is (cylinders
    are placed along the shaft by axial_position, or cylinder_spacing with a layout, in the
    machine file). The moment of an order that also leaves a free force depends on the point
    it is taken about: read the two side by side. Counterweights can cancel only the forward
    first order; the rest needs balance shafts.

    --format csv and json give every column of multicrank.shaking_forces(...).orders: the
    phases [rad] as well (an order's component is amplitude·cos(nφ − phase)) and
    moment_forward and moment_backward [N·m]; json adds rpm, omega [rad/s], steady and the
    units.
    """
    from ..forces.shaking import shaking_forces

    # The speed is the library's to default and check, once; its refusals name the option.
    result = shaking_forces(machine, rpm, max_order=max_order, steady=steady)
    orders = result.orders
    bearing_lines, bearing_meta = bearing_summary(machine, result)
    if fmt == "table":
        write_result(
            _readable(orders),
            fmt,
            out_path,
            summary=_header(machine, result),
            json_meta={},
            footer=_reference(orders) + _balancing(orders) + bearing_lines,
        )
        return
    meta = dict(
        machine=machine.name,
        rpm=result.rpm,
        omega=result.omega,
        steady=result.steady,
        max_order=result.max_order,
        reference_position=result.reference_position,
        units=dict(orders.attrs["units"], order="1/revolution", reference_position="m"),
        **bearing_meta,
    )
    write_result(orders, fmt, out_path, summary=[], json_meta=meta)


def bearing_summary(machine: Machine, result: ShakingForces) -> tuple[list[str], dict[str, Any]]:
    """What the command adds about the main bearings (:func:`~multicrank.bearing_loads` at
    the same speed, steady or constant, and in steady running of the same steady state as
    the orders: :func:`~multicrank.forces.bearings.bearing_loads_beside`): lines below the
    table to read — per bearing its position, largest load and where it acts, mean load and
    what gravity adds — and a ``bearings`` entry of json's metadata (one record per bearing,
    the summary's columns)."""
    from ..forces.bearings import bearing_loads_beside

    summary = bearing_loads_beside(result).summary
    lines = ["", "main bearings (force received from the shaft over the working cycle, gravity included):"]
    heading = ("bearing", "z [m]", "max [N]", "at φ [°]", "mean [N]", "gravity adds [N]")
    # Each column in one notation (fixed, or all with an exponent), the angles to 0.1°.
    columns = [
        [f"{index}" for index in summary.index],
        column_text(summary["position"].tolist(), DIGITS),
        column_text(summary["max"].tolist(), DIGITS),
        [f"{math.degrees(phi):.1f}" for phi in summary["phi_max"]],
        column_text(summary["mean"].tolist(), DIGITS),
        column_text(summary["gravity_adds"].tolist(), DIGITS),
    ]
    widths = [max(len(h), *(len(text) for text in column)) for h, column in zip(heading, columns, strict=True)]
    lines.append(" ".join(f"{h:>{w + 1}}" for h, w in zip(heading, widths, strict=True)))
    for row in zip(*columns, strict=True):
        lines.append(" ".join(f"{text:>{w + 1}}" for text, w in zip(row, widths, strict=True)))
    records = [{"bearing": int(index), **{k: float(v) for k, v in row.items()}} for index, row in summary.iterrows()]
    return lines, {"bearings": records, "bearing_units": dict(summary.attrs["units"])}


def _header(machine: Machine, result: ShakingForces) -> list[str]:
    """The lines above the table: the machine and its speed, what the columns are."""
    if result.steady:
        speed = f"steady running at a mean {result.rpm:.6g} rpm (load balance: ω(φ) and ε(φ) with gravity)"
    else:
        speed = f"constant speed {result.rpm:.6g} rpm (ω = {result.omega:.6g} rad/s)"
    lines = [
        f"{machine.name}: shaking forces and moments on the frame by order, {speed}",
        *_wrapped(
            "the amplitude of each order (per revolution) of −Σ m·a: vertical upward, horizontal toward a "
            "cylinder at γ = 0, forward and backward the parts that turn with and against the crank; the "
            "moments about the engine centre z_ref, midway between the outermost cylinders"
        ),
    ]
    if len(machine) > 1 and all(c.axial_position == 0 for c in machine.cylinders):
        lines += _wrapped(
            "note: every cylinder is at z = 0 (none placed along the shaft), so the moments are 0; a machine "
            "file places them by axial_position, or by cylinder_spacing with a layout"
        )
    return lines


def _readable(orders: pd.DataFrame) -> pd.DataFrame:
    """The table to read: the :data:`SHOWN` columns with their units, to :data:`DIGITS`
    significant digits in one notation per column (fixed, or all with an exponent), the
    orders as 1, 1.5, 2."""
    units = orders.attrs["units"]
    shown = readable(orders.loc[:, list(SHOWN)].astype(float), DIGITS)
    shown.columns = [f"{name} [{units[name]}]" for name in SHOWN]
    shown.index = [f"{n:g}" for n in orders.index]
    shown.index.name = "order"
    return shown


def _reference(orders: pd.DataFrame) -> list[str]:
    """A line below the table naming the orders whose moment depends on the point it is
    taken about (those that leave a free force as well), with that point; none where no
    order has both."""
    both = [
        f"{n:g}"
        for n, row in orders.iterrows()
        if row["force_forward"] + row["force_backward"] > 0 and row["moment_forward"] + row["moment_backward"] > 0
    ]
    if not both:
        return []
    which = f"order {both[0]} leaves" if len(both) == 1 else f"orders {', '.join(both)} leave"
    return _wrapped(
        f"{which} a free force as well as a moment: such a moment depends on the point it is taken about, "
        f"here the engine centre z_ref = {orders.attrs['reference_position']:.6g} m"
    )


def _balancing(orders: pd.DataFrame) -> list[str]:
    """The lines below the table: what counterweights can cancel here, and what they cannot."""
    force, moment = orders.loc[1.0, ["force_forward", "moment_forward"]]
    parts = [f"{value:.{DIGITS}g} {unit}" for value, unit in ((force, "N"), (moment, "N·m")) if value]
    here = f"here {' and '.join(parts)}" if parts else "here there is none"
    return _wrapped(
        f"counterweights turn with the crank: they can cancel only the forward first order ({here}); the "
        "backward first order and every higher order need balance shafts turning at that order"
    )


def _wrapped(text: str) -> list[str]:
    """A note as lines of at most 100 characters."""
    return textwrap.wrap(text, 100)
