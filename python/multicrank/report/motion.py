"""The report's first part: the machine's steady running with and without gravity — δ, the
flywheel, ω(φ), the torques and their orders, δ over the speed range — as figures, tables
and its HTML section."""

from __future__ import annotations

import html
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from .._shaft import rpm_from_omega
from ..machine.machine import Machine
from .plotting import pyplot
from .settings import ReportSettings, running_speed, speed_range

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "MotionResults",
    "motion_html",
    "motion_results",
    "orders_figure",
    "speed_figure",
    "speed_range_figure",
    "torque_figure",
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
    flywheel: Any  # FlywheelInertia for ``target``
    speeds: pd.DataFrame
    orders: pd.DataFrame


def motion_results(settings: ReportSettings, speeds: int = 9) -> MotionResults:
    """Steady state at the machine's speed with and without gravity, over its speed range,
    the flywheel for the class's δ (or ``settings.delta``) and the torque orders."""
    from ..motion.flywheel import flywheel_inertia
    from ..motion.orders import torque_orders
    from ..motion.steady import StallError, steady_state
    from ..presets import MACHINE_CLASSES, SPEED_FLUCTUATION

    machine = settings.machine
    rpm = running_speed(machine)
    state = steady_state(machine, rpm=rpm)
    without = steady_state(machine, rpm=rpm, gravity=False)
    if settings.delta is not None:
        target, source = settings.delta, "asked for (--delta)"
    elif machine.name in MACHINE_CLASSES:
        kind = MACHINE_CLASSES[machine.name]
        target, source = SPEED_FLUCTUATION[kind][1], f"the {kind} class's limit"
    else:
        target, source = without.delta, "the machine's own δ without gravity (no class known)"
    flywheel = flywheel_inertia(machine, delta=target, rpm=rpm)
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
                    delta_gravity_only=s.delta_gravity_only,
                    delta_g=float(machine.engine(float(n)).speed_fluctuation()),
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
        speeds=pd.DataFrame(rows),
        orders=torque_orders(machine, rpm),
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
    """δ over the speed range: with and without gravity, gravity alone and the paper's δ_g."""
    plt = pyplot()
    frame = results.speeds.dropna(subset=["delta"]) if "delta" in results.speeds else results.speeds.iloc[:0]
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for column, label, style in (
        ("delta", "δ with gravity", "-o"),
        ("delta_without_gravity", "δ without gravity", "--s"),
        ("delta_gravity_only", "δ without gas and load (gravity and J(φ) alone)", ":^"),
        ("delta_g", "δ_g = max U* − min U* (first order)", "-."),
    ):
        if column in frame:
            ax.plot(frame["rpm"], frame[column], style, label=label, ms=4)
    ax.axhline(results.target, color="0.5", lw=0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
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


def motion_html(results: MotionResults, machine: Machine, figures: dict[str, str]) -> str:
    """The report's first section: what gravity does to this machine's speed fluctuation."""
    state, without, flywheel = results.state, results.without, results.flywheel
    change = 100 * (state.delta / without.delta - 1)
    extra = 100 * (flywheel.shaft_inertia / flywheel.shaft_inertia_without_gravity - 1)
    load = state.mean_load_torque
    rows = [
        ("mean speed", f"{results.rpm:g} rpm (ω<sub>m</sub> = {state.omega_mean:.6g} rad/s)"),
        ("δ with gravity", f"{state.delta:.5g} (1/{1 / state.delta:.4g})"),
        ("δ without gravity (g = 0)", f"{without.delta:.5g} (1/{1 / without.delta:.4g})"),
        ("gravity changes δ by", f"<b>{change:+.3g} %</b>"),
        ("δ without gas and load (gravity and J(φ) alone, exact)", f"{state.delta_gravity_only:.4g}"),
        ("δ<sub>g</sub> = max U* − min U* (the paper's first-order measure)", f"{results.delta_g:.4g}"),
        ("δ about the midrange (textbook convention)", f"{state.delta_midrange:.5g}"),
        ("speed swing", f"{rpm_from_omega(state.omega_min):.6g} … {rpm_from_omega(state.omega_max):.6g} rpm"),
        ("load torque (balance)", f"{load:.6g} N·m ({load * state.omega_mean / 1e3:.4g} kW)"),
        ("shaft inertia I<sub>w</sub> (as built)", f"{machine.shaft_inertia:.6g} kg·m²"),
    ]
    body = "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in rows)
    fly = [
        ("target δ", f"{results.target:.4g} (1/{1 / results.target:.4g}): {html.escape(results.target_source)}"),
        ("I<sub>w</sub> with gravity (exact)", f"{flywheel.shaft_inertia:.6g} kg·m²"),
        ("I<sub>w</sub> without gravity (exact)", f"{flywheel.shaft_inertia_without_gravity:.6g} kg·m²"),
        ("gravity asks for", f"<b>{extra:+.3g} %</b> flywheel inertia"),
        (
            "textbook ΔE/(δω²) − mean(J − I<sub>w</sub>)",
            f"{flywheel.textbook:.6g} kg·m² ({100 * flywheel.textbook_error:+.2g} % off the exact)",
        ),
    ]
    fly_body = "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in fly)
    top = results.orders.sort_values("total_amplitude", ascending=False).head(8)
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
<h3>The flywheel</h3>
<table>{fly_body}</table>
<img src="{figures["motion_speed"]}" alt="speed over the cycle with and without gravity">
<img src="{figures["motion_torques"]}" alt="torque components over the cycle">
<h3>Over the speed range</h3>
<p>Gravity's torque does not depend on the speed, the gas and inertia torques' effect on δ falls or grows with
it: gravity matters most at low speed. The grey line is the target δ.</p>
<img src="{figures["motion_speed_range"]}" alt="δ over the speed range">
<h3>Torque orders at {results.rpm:g} rpm</h3>
<p>Fourier amplitudes per order (harmonics per revolution; half orders in a four-stroke cycle) in N·m, for
torsional-vibration tools: gravity and inertia exact, gas from the cycle quadrature. The eight largest:</p>
<table><tr><th>order</th><th>gas</th><th>inertia</th><th>gravity</th><th>total</th></tr>{order_rows}</table>
<img src="{figures["motion_orders"]}" alt="torque orders">
<p class="note">Data: motion_speed.csv, motion_torques.csv, motion_speed_range.csv, motion_orders.csv</p>
"""
