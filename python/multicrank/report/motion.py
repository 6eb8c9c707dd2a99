"""The report's first part: the machine's steady running with and without gravity — δ, the
flywheel, ω(φ), the torques and their orders, δ over the speed range, where gravity matters
over speed × flywheel — as figures, tables and its HTML section. The map of where gravity
matters is `gravity_map`'s (its names are imported here too, where they were first)."""

from __future__ import annotations

import html
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from .._native import MechanismError
from .._validation import rpm_from_omega
from ..machine.machine import Machine
from .gravity_map import GRAVITY_MAP_INERTIA, gravity_map, gravity_map_caption, gravity_map_figure, threshold_curve
from .plotting import plain_log_axis, pyplot, threshold_text
from .prose import speed_trend_sentence
from .settings import ReportSettings, running_speed, speed_range

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "GRAVITY_MAP_INERTIA",
    "LISTED_ORDERS",
    "ORDER_ROUNDING",
    "MotionResults",
    "gravity_map",
    "gravity_map_figure",
    "motion_html",
    "motion_results",
    "orders_figure",
    "speed_figure",
    "speed_range_figure",
    "threshold_curve",
    "torque_figure",
    "verdict_html",
]


@dataclass(frozen=True)
class MotionResults:
    """The machine's steady running, for the report's first section."""

    rpm: float
    target: float
    target_source: str
    state: Any  # SteadyState with gravity
    without: Any  # SteadyState with g = 0
    delta_g: float
    flywheel: Any  # FlywheelInertia for ``target``; None where no shaft inertia gives it
    flywheel_refusal: str  # why not, where it is None
    speeds: pd.DataFrame
    orders: pd.DataFrame
    gravity_map: pd.DataFrame  # gravity_map(): the map over speed × shaft inertia


#: How many torque orders the page's table lists, the largest first (motion_orders.csv has all).
LISTED_ORDERS = 8
#: An order whose every amplitude is at most this times the table's largest is rounding:
#: the page leaves it out with those that cancel exactly (torque_orders prints them as 0).
ORDER_ROUNDING = 1e-12


def flywheel_target(settings: ReportSettings, own: float) -> tuple[float, str]:
    """The δ the report sizes the flywheel for, and where it comes from: ``settings.delta_target``
    (``--delta-target``), else the machine's ``delta_target`` (a machine file's ``delta_target`` or
    ``class``), else a built-in machine's class limit, else ``own`` (the machine's δ without
    gravity: the flywheel it has)."""
    from ..presets import MACHINE_CLASSES, MACHINES, SPEED_FLUCTUATION

    machine = settings.machine
    if settings.delta_target is not None:
        return settings.delta_target, "asked for (--delta-target)"
    if machine.delta_target is not None:
        return machine.delta_target, "the machine's delta_target (its file's delta_target or class)"
    if machine.name in MACHINE_CLASSES and MACHINES[machine.name] == machine:
        kind = MACHINE_CLASSES[machine.name]
        return SPEED_FLUCTUATION[kind][1], f"the {kind} class's limit"
    return own, (
        "the machine's own δ without gravity: no target known, so this is the flywheel it has "
        "(give delta_target or class in its machine file, or --delta-target)"
    )


def motion_results(settings: ReportSettings, speeds: int = 9) -> MotionResults:
    """Steady state at the machine's speed with and without gravity, over its speed range,
    the flywheel for the class's δ (or ``settings.delta_target``) and the torque orders."""
    from ..motion.flywheel import flywheel_inertia
    from ..motion.orders import torque_orders
    from ..motion.steady import StallError, steady_state

    machine = settings.machine
    rpm = running_speed(machine)
    state = steady_state(machine, rpm=rpm)
    without = steady_state(machine, rpm=rpm, gravity=False)
    target, source = flywheel_target(settings, without.delta)
    try:
        flywheel, refusal = flywheel_inertia(machine, delta=target, rpm=rpm), ""
    except MechanismError as error:
        # A target δ above what even a massless shaft gives (a ship's shaft and propeller
        # are a flywheel of their own): the section says so instead of failing the report.
        flywheel, refusal = None, str(error)
    low, high = speed_range(machine)
    rows: list[dict[str, Any]] = []
    for n in np.geomspace(low, high, speeds):
        try:
            s = steady_state(machine, rpm=float(n))
            rows.append(
                dict(
                    rpm=float(n),
                    delta=s.delta,
                    delta_without_gravity=s.delta_without_gravity,
                    delta_coasting=s.delta_coasting,
                    delta_g=float(machine.engine(float(n)).speed_fluctuation()),
                    near_stall=s.near_stall,
                )
            )
        except StallError as error:
            rows.append(dict(rpm=float(n), stalled_below_rpm=error.min_rpm))
    return MotionResults(
        rpm=rpm,
        target=target,
        target_source=source,
        state=state,
        without=without,
        delta_g=float(machine.engine(rpm).speed_fluctuation()),
        flywheel=flywheel,
        flywheel_refusal=refusal,
        speeds=pd.DataFrame(rows),
        orders=torque_orders(machine, rpm),
        gravity_map=gravity_map(settings),
    )


def speed_figure(results: MotionResults) -> tuple[Figure, pd.DataFrame]:
    """ω(φ) with and without gravity at the machine's speed, in rpm over φ in degrees."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for state, label, style in ((results.state, "with gravity", "-"), (results.without, "without gravity", "--")):
        ax.plot(np.degrees(state.phi), rpm_from_omega(state.omega), style, label=f"{label} (δ = {state.delta:.4g})")
    ax.axhline(results.rpm, color="0.6", lw=0.8)
    ax.set_xlabel("crank angle φ [deg]")
    ax.set_ylabel("speed [rpm]")
    ax.set_xlim(0, np.degrees(results.state.cycle))
    ax.legend(loc="best", fontsize=8)
    ax.set_title(f"steady running at {results.rpm:g} rpm (mean)")
    table = pd.DataFrame(
        {
            "phi_deg": np.degrees(results.state.phi),
            "rpm_with_gravity": rpm_from_omega(results.state.omega),
            "rpm_without_gravity": rpm_from_omega(results.without.omega),
        }
    )
    return fig, table


def torque_figure(results: MotionResults) -> tuple[Figure, pd.DataFrame]:
    """The torque components over the cycle at the machine's speed [N·m]."""
    plt = pyplot()
    state = results.state
    parts = {
        "gas": state.gas_torque,
        "gravity −dU/dφ": state.gravity_torque,
        "inertia −½J′ω²": state.inertia_torque,
        "−M_load (balance)": -state.load_torque,
    }
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for name, values in parts.items():
        ax.plot(np.degrees(state.phi), values, label=name, lw=1.2)
    ax.axhline(0, color="0.6", lw=0.8)
    ax.set_xlabel("crank angle φ [deg]")
    ax.set_ylabel("torque on the shaft [N·m]")
    ax.set_xlim(0, np.degrees(state.cycle))
    ax.legend(loc="best", fontsize=8, ncol=2)
    names = ("gas", "gravity", "inertia", "minus_load")
    table = pd.DataFrame({"phi_deg": np.degrees(state.phi), **dict(zip(names, parts.values(), strict=True))})
    return fig, table


def speed_range_figure(results: MotionResults) -> tuple[Figure, pd.DataFrame]:
    """δ over the speed range: with and without gravity, coasting (gas and load removed: J(φ)
    and gravity together) and the paper's δ_g."""
    plt = pyplot()
    frame = results.speeds.dropna(subset=["delta"]) if "delta" in results.speeds else results.speeds.iloc[:0]
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for column, label, style in (
        ("delta", "δ with gravity", "-o"),
        ("delta_without_gravity", "δ without gravity", "--s"),
        ("delta_coasting", "δ coasting: gas and load removed (J(φ) and gravity together)", ":^"),
        ("delta_g", "δ_g = max U* − min U* (first order)", "-."),
    ):
        if column in frame:
            ax.plot(frame["rpm"], frame[column], style, label=label, ms=4)
    ax.axhline(results.target, color="0.5", lw=0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    plain_log_axis(ax.xaxis)
    ax.set_xlabel("mean speed [rpm]")
    ax.set_ylabel("coefficient of speed fluctuation δ")
    ax.legend(loc="best", fontsize=8)
    return fig, results.speeds


def orders_figure(results: MotionResults) -> tuple[Figure, pd.DataFrame]:
    """Per-order amplitudes of the gas, inertia and gravity torques [N·m]."""
    plt = pyplot()
    orders = results.orders
    fig, ax = plt.subplots(figsize=(8, 3.4))
    width = 0.25 if orders.index.size < 2 else 0.25 * float(np.min(np.diff(orders.index.to_numpy())))
    for i, name in enumerate(("gas", "inertia", "gravity")):
        ax.bar(orders.index.to_numpy() + (i - 1) * width, orders[f"{name}_amplitude"], width, label=name)
    ax.set_yscale("symlog", linthresh=1e-3 * max(float(orders["total_amplitude"].max()), 1e-12))
    ax.set_xlabel("order (harmonics per revolution)")
    ax.set_ylabel("amplitude [N·m]")
    ax.legend(fontsize=8)
    return fig, orders.reset_index()


def _near_stall_html(frame: pd.DataFrame, where: str) -> str:
    """A note on the rows of ``frame`` (its ``near_stall`` column) whose δ is above
    NEAR_STALL_DELTA, or "" where there are none."""
    from ..motion.steady import NEAR_STALL_NOTE

    near = frame["near_stall"].eq(True) if "near_stall" in frame else pd.Series(False, index=frame.index)
    if not near.any():
        return ""
    low, high = frame.loc[near, "rpm"].agg(["min", "max"])
    speeds = f"mean speed {low:.4g} rpm" if low == high else f"mean speeds {low:.4g} … {high:.4g} rpm"
    count = int(near.sum())
    points = f"{count} of {len(frame)} points" if count > 1 else f"1 point of {len(frame)}"
    return f'<p class="note"><b>Near a stall</b> {where} at {points} ({speeds}): {html.escape(NEAR_STALL_NOTE)}.</p>'


def _listed_orders(orders: pd.DataFrame) -> tuple[pd.DataFrame, str]:
    """The rows of the page's orders table — the :data:`LISTED_ORDERS` largest by total
    amplitude, leaving out every order whose every amplitude is 0 (or within
    :data:`ORDER_ROUNDING` of the table's largest) — and the words that introduce them."""
    columns = [f"{part}_amplitude" for part in ("gas", "inertia", "gravity", "total")]
    largest = orders[columns].abs().max(axis=1)
    kept = orders[largest > ORDER_ROUNDING * float(largest.max())]
    top = kept.sort_values("total_amplitude", ascending=False).head(LISTED_ORDERS)
    zero = len(orders) - len(kept)
    if len(kept) > LISTED_ORDERS:
        rest = f"the other {len(kept) - LISTED_ORDERS}" + (f" and the {zero} that are 0" if zero else "")
        return top, f"The {LISTED_ORDERS} largest ({rest} are in motion_orders.csv):"
    if not zero:
        return top, f"Every order from 0 to {orders.index.max():g}:"
    return top, f"The {len(kept)} that are not 0, of the {len(orders)} orders from 0 to {orders.index.max():g}:"


def verdict_html(results: MotionResults, threshold: float) -> str:
    """The paper's verdict on this machine: whether δ_g, its first-order measure of gravity's
    share of δ, is below ``threshold`` at the running speed; shown beside the first table,
    whose exact numbers it is weighed against."""
    verdict = "may be neglected" if results.delta_g < threshold else "may NOT be neglected"
    return (
        f"<p><b>Verdict:</b> with δ<sub>g</sub> = {results.delta_g:.3g} against the threshold "
        f"{threshold_text(threshold)}, "
        f"gravity <b>{verdict}</b> in this machine's speed fluctuation at {results.rpm:g} rpm. "
        "The threshold is a tenth of 1/300, the tightest coefficient of speed fluctuation usually asked of "
        "machines (AC generators); pumps and compressors allow 1/20–1/50 and vehicle engines 1/100–1/200. "
        "δ<sub>g</sub> is the paper's first-order measure; the rows above give the exact change of δ.</p>"
    )


def motion_html(results: MotionResults, machine: Machine, figures: dict[str, str], threshold: float) -> str:
    """The report's first section: what gravity does to this machine's speed fluctuation."""
    from ..motion.steady import NEAR_STALL_NOTE

    state, without, flywheel = results.state, results.without, results.flywheel
    change = 100 * (state.delta / without.delta - 1)
    load = state.mean_load_torque
    rows = [
        ("mean speed", f"{results.rpm:g} rpm (ω<sub>m</sub> = {state.omega_mean:.6g} rad/s)"),
        ("δ with gravity", f"{state.delta:.5g} (1/{1 / state.delta:.4g})"),
        ("δ without gravity (g = 0)", f"{without.delta:.5g} (1/{1 / without.delta:.4g})"),
        ("gravity changes δ by", f"<b>{change:+.3g} %</b>"),
        ("δ coasting: gas and load removed (J(φ) and gravity together, exact)", f"{state.delta_coasting:.4g}"),
        ("δ<sub>g</sub> = max U* − min U* (the paper's first-order measure)", f"{results.delta_g:.4g}"),
        ("δ about the midrange (textbook convention)", f"{state.delta_midrange:.5g}"),
        ("speed swing", f"{rpm_from_omega(state.omega_min):.6g} … {rpm_from_omega(state.omega_max):.6g} rpm"),
        ("load torque (balance)", f"{load:.6g} N·m ({load * state.omega_mean / 1e3:.4g} kW)"),
        ("shaft inertia I<sub>w</sub> (as built)", f"{machine.shaft_inertia:.6g} kg·m²"),
    ]
    if state.near_stall:
        rows.insert(2, ("<b>near a stall</b>", html.escape(NEAR_STALL_NOTE)))
    body = "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in rows)
    fly = [("target δ", f"{results.target:.4g} (1/{1 / results.target:.4g}): {html.escape(results.target_source)}")]
    if flywheel is None:
        fly.append(("no shaft inertia gives it", html.escape(results.flywheel_refusal)))
    else:
        extra = 100 * (flywheel.shaft_inertia / flywheel.shaft_inertia_without_gravity - 1)
        fly += [
            ("I<sub>w</sub> with gravity (exact)", f"{flywheel.shaft_inertia:.6g} kg·m²"),
            ("I<sub>w</sub> without gravity (exact)", f"{flywheel.shaft_inertia_without_gravity:.6g} kg·m²"),
            ("gravity asks for", f"<b>{extra:+.3g} %</b> flywheel inertia"),
            (
                "textbook ΔE/(δω²) − mean(J − I<sub>w</sub>)",
                f"{flywheel.textbook:.6g} kg·m² ({100 * flywheel.textbook_error:+.2g} % off the exact)",
            ),
        ]
    fly_body = "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in fly)
    top, orders_said = _listed_orders(results.orders)
    order_rows = "".join(
        f"<tr><td>{order:g}</td><td>{r.gas_amplitude:.4g}</td><td>{r.inertia_amplitude:.4g}</td>"
        f"<td>{r.gravity_amplitude:.4g}</td><td>{r.total_amplitude:.4g}</td></tr>"
        for order, r in zip(top.index, top.itertuples(), strict=True)
    )
    return f"""
<h2>What gravity does to this machine's running</h2>
<p>The exact periodic steady state of J(φ)φ̈ + ½J′(φ)φ̇² = M<sub>gas</sub> − dU/dφ − M<sub>load</sub>, with
the machine's variable reduced inertia J(φ), its gas pressure and the constant load that balances the cycle's
mean gas torque, at the same mean speed with and without gravity. δ = (ω<sub>max</sub> − ω<sub>min</sub>)/ω<sub>m</sub>
with ω<sub>m</sub> the time mean.</p>
<table>{body}</table>
{verdict_html(results, threshold)}
<h3>The flywheel</h3>
<table>{fly_body}</table>
<img src="{figures["motion_speed"]}" alt="speed over the cycle with and without gravity">
<img src="{figures["motion_torques"]}" alt="torque components over the cycle">
<h3>Over the speed range</h3>
<p>Gravity's torque, like the gas torque of a given indicator diagram, does not depend on the speed, while the
inertia torque grows as n²: so gravity's share of δ may grow or fall with the speed, and δ<sub>g</sub> (∝ 1/n²)
does not tell which. {speed_trend_sentence(results.speeds)} The grey line is the target δ.</p>
<img src="{figures["motion_speed_range"]}" alt="δ over the speed range">
{_near_stall_html(results.speeds, "over the speed range")}
<h3>Where gravity matters: speed × flywheel</h3>
{gravity_map_caption(results, machine, threshold)}
<img src="{figures["motion_gravity_map"]}" alt="gravity's effect on δ over speed and shaft inertia">
{_near_stall_html(results.gravity_map, "on the map")}
<h3>Torque orders at {results.rpm:g} rpm</h3>
<p>Fourier amplitudes per order (harmonics per revolution; half orders in a four-stroke cycle) in N·m, for
torsional-vibration tools: gravity and inertia exact, gas from the cycle quadrature. {orders_said}</p>
<table><tr><th>order</th><th>gas</th><th>inertia</th><th>gravity</th><th>total</th></tr>{order_rows}</table>
<img src="{figures["motion_orders"]}" alt="torque orders">
<p class="note">Data: motion_speed.csv, motion_torques.csv, motion_speed_range.csv, motion_gravity_map.csv,
motion_orders.csv</p>
"""
