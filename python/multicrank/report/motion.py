"""The report's first part: the machine's steady running with and without gravity — δ, the
flywheel, ω(φ), the torques and their orders, δ over the speed range, where gravity matters
over speed × flywheel — as figures, tables and its HTML section."""

from __future__ import annotations

import html
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from .._native import MechanismError
from .._validation import as_count, rpm_from_omega
from ..machine.machine import Machine
from .plotting import plain_log_axis, pyplot, symmetric_limit, threshold_text
from .prose import map_axes_sentence, neglected_region_sentence, speed_trend_sentence
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


#: The shaft inertias of the "where gravity matters" map, as multiples of the machine's own
#: (log-spaced from the first to the second): a flywheel a quarter of it to four times it.
GRAVITY_MAP_INERTIA = (0.25, 4.0)
#: The least half-range of the map's colours [%]: a change of δ far below it (0.02 %) shows
#: near-white, not as saturated as one of 30 %.
MAP_FLOOR_PERCENT = 1.0
#: How many torque orders the page's table lists, the largest first (motion_orders.csv has all).
LISTED_ORDERS = 8
#: An order whose every amplitude is at most this times the table's largest is rounding:
#: the page leaves it out with those that cancel exactly (torque_orders prints them as 0).
ORDER_ROUNDING = 1e-12
#: The opacity of the hatching where δ_g is below the threshold: the colours show through.
HATCH_ALPHA = 0.3
#: What the map computes (mc.motion_sweep's outputs); ``stalled`` comes with them.
GRAVITY_MAP_OUTPUTS = ("delta", "delta_without_gravity", "gravity_effect")


def gravity_map(settings: ReportSettings) -> pd.DataFrame:
    """The machine's steady running over its speed range × shaft inertias of
    :data:`GRAVITY_MAP_INERTIA` times its own (evenly spaced speeds, log-spaced inertias),
    ``settings.gravity_map_points`` of each: :func:`~multicrank.motion_sweep`'s rows (the
    balance load at each speed) and δ_g, the paper's first-order measure, of each variant."""
    from ..motion.sweep import motion_sweep
    from ..motion.variants import MachineGrid, machine_variant

    machine = settings.machine
    points = as_count(settings.gravity_map_points, "gravity_map_points", minimum=2)
    low, high = speed_range(machine)
    grid = MachineGrid(
        machine,
        shaft_inertia=machine.shaft_inertia * np.geomspace(*GRAVITY_MAP_INERTIA, points),
        rpm=np.linspace(low, high, points),
    )
    frame = motion_sweep(machine, grid, outputs=list(GRAVITY_MAP_OUTPUTS))
    frame["delta_g"] = [
        float(machine_variant(machine, {"shaft_inertia": inertia}).engine(rpm).speed_fluctuation())
        for inertia, rpm in zip(frame["shaft_inertia"], frame["rpm"], strict=True)
    ]
    return frame


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


def gravity_map_figure(results: MotionResults, machine: Machine, threshold: float) -> tuple[Figure, pd.DataFrame]:
    """Where gravity matters: its effect on δ in % over speed × shaft inertia, the colours
    centred at 0, the machine as built marked and the line δ_g = ``threshold`` where it
    crosses the map."""
    plt = pyplot()
    from matplotlib import patheffects
    from matplotlib.colors import CenteredNorm
    from matplotlib.ticker import MaxNLocator

    frame = results.gravity_map
    effect = 100 * frame.pivot(index="shaft_inertia", columns="rpm", values="gravity_effect").to_numpy()
    speeds, inertias = np.unique(frame["rpm"]), np.unique(frame["shaft_inertia"])
    # The colours cover the data (a round limit at or above its largest magnitude) and never
    # less than ±MAP_FLOOR_PERCENT, so that a change of 0.02 % shows near-white, not saturated.
    largest = float(np.nanmax(np.abs(effect))) if np.isfinite(effect).any() else 0.0
    limit = symmetric_limit(largest, MAP_FLOOR_PERCENT)
    fig, ax = plt.subplots(figsize=(8, 4.8))
    filled = ax.contourf(speeds, inertias, effect, levels=np.linspace(-limit, limit, 41), cmap="RdBu_r",
                         norm=CenteredNorm(vcenter=0.0, halfrange=limit))  # fmt: skip
    label = "gravity's effect on δ: δ / δ without gravity − 1 [%]"
    ticks = np.asarray(MaxNLocator(nbins=8, symmetric=True).tick_values(-limit, limit))
    fig.colorbar(filled, ax=ax, label=label, ticks=ticks[np.abs(ticks) <= limit * (1 + 1e-9)], format="%+g")
    lines = ax.contour(speeds, inertias, effect, levels=6, colors="0.15", linewidths=0.6)
    halo = [patheffects.withStroke(linewidth=2.5, foreground="white")]
    for label in ax.clabel(lines, fmt="%+.3g %%", fontsize=8):
        # Upright: a label along a line reads left to right, or bottom to top where the line is
        # (nearly) vertical; matplotlib may turn one by −90° (top to bottom) or past 90°.
        label.set_rotation((label.get_rotation() + 80) % 180 - 80)
        label.set_path_effects(halo)
    handles: list[Any] = ax.plot(results.rpm, machine.shaft_inertia, "*", ms=15, mfc="white", mec="black",
                                 label=f"as built: {100 * results.state.gravity_effect:+.3g} %")  # fmt: skip
    ax.set_yscale("log")
    handles += _threshold_line(ax, frame, threshold, halo)
    ax.legend(handles=handles, loc="upper left", fontsize=8, framealpha=0.9)
    plain_log_axis(ax.yaxis)
    ax.grid(False)
    ax.set_xlabel("mean speed [rpm]")
    ax.set_ylabel("shaft inertia I_w [kg·m²]")
    ax.set_title("where gravity matters: how much it changes δ, over speed × flywheel")
    ax.grid(False)
    return fig, frame


def threshold_curve(frame: pd.DataFrame, threshold: float, points: int = 400) -> tuple[np.ndarray, np.ndarray]:
    """The shaft inertia [kg·m²] at which δ_g = ``threshold``, at ``points`` speeds [1/min]
    over the map of ``frame`` (gravity_map's rows): δ_g = c/(I_w n²) exactly (U* is
    U/(I_w ω²)), c = δ_g I_w n² of the map's rows, so the curve is I_w = c/(threshold n²);
    δ_g is below the threshold above it. Returns the speeds and those inertias (inf where
    δ_g is 0)."""
    constant = float(np.median(frame["delta_g"] * frame["shaft_inertia"] * frame["rpm"] ** 2))
    speeds = np.linspace(frame["rpm"].min(), frame["rpm"].max(), points)
    return speeds, constant / (threshold * speeds**2)


def _threshold_line(ax: Any, frame: pd.DataFrame, threshold: float, halo: list[Any]) -> list[Any]:
    """Draw δ_g = ``threshold`` on the map: a thick line with its label, the side where δ_g is
    below it hatched; or, where it crosses nowhere, a note saying on which side the whole map
    lies. Returns the legend's handles."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    written = threshold_text(threshold)
    speeds, curve = threshold_curve(frame, threshold)
    low, top = frame["shaft_inertia"].min(), frame["shaft_inertia"].max()
    inside = (curve >= low) & (curve <= top)
    if inside.sum() < 2:
        below = bool((frame["delta_g"] < threshold).all())
        note = (
            f"δ_g < {written} everywhere on this map:\ngravity negligible by the first-order measure"
            if below
            else f"δ_g > {written} everywhere on this map:\nthe first-order measure never calls gravity negligible"
        )
        ax.text(0.98, 0.03, note, transform=ax.transAxes, ha="right", va="bottom", fontsize=8,
                bbox=dict(boxstyle="round", facecolor="white", edgecolor="0.3", alpha=0.9))  # fmt: skip
        return []
    ax.fill_between(speeds, np.clip(curve, low, top), top, facecolor="none", edgecolor="black", hatch="///",
                    linewidth=0, alpha=HATCH_ALPHA)  # fmt: skip
    speeds, inertias = speeds[inside], curve[inside]
    (line,) = ax.plot(speeds, inertias, color="black", lw=2.4, solid_capstyle="butt")
    line.set_path_effects(halo)
    # The label points at the middle of the curve as drawn (in the axes' own coordinates,
    # the inertia axis logarithmic), from the side towards the map's centre, so that it
    # reads on a long curve and on a short one in a corner alike.
    middle = len(speeds) // 2
    x, y = ax.transAxes.inverted().transform(ax.transData.transform((speeds[middle], inertias[middle])))
    text = (0.5 + 0.6 * (x - 0.5) if abs(x - 0.5) > 0.2 else x, 0.5 + 0.6 * (y - 0.5) if abs(y - 0.5) > 0.2 else y)
    ax.annotate(
        f"δ_g = {written}",
        (speeds[middle], inertias[middle]),
        xytext=text,
        textcoords="axes fraction",
        ha="center",
        va="center",
        fontsize=9,
        fontweight="bold",
        bbox=dict(boxstyle="round", facecolor="white", edgecolor="black", alpha=0.9),
        arrowprops=dict(arrowstyle="->", color="black", lw=1.2),
    )
    negligible = f"δ_g < {written}: gravity negligible to first order"
    return [
        Line2D([], [], color="black", lw=2.4, label=f"δ_g = {written}, the report's threshold"),
        Patch(facecolor="none", edgecolor="black", hatch="///", alpha=HATCH_ALPHA, label=negligible),
    ]


def _gravity_map_caption(results: MotionResults, machine: Machine, threshold: float) -> str:
    """What the "where gravity matters" map shows, with its numbers."""
    frame = results.gravity_map
    effect = 100 * frame["gravity_effect"]
    points = int(np.sqrt(len(frame)))
    low, high = frame["rpm"].min(), frame["rpm"].max()
    lightest, heaviest = frame["shaft_inertia"].min(), frame["shaft_inertia"].max()
    delta_g = frame["delta_g"]
    if delta_g.min() >= threshold:
        line = f"δ<sub>g</sub> is above the threshold {threshold:.2g} everywhere on the map."
    elif delta_g.max() <= threshold:
        line = f"δ<sub>g</sub> is below the threshold {threshold:.2g} everywhere on the map."
    else:
        line = (
            f"The thick black line is δ<sub>g</sub> = {threshold_text(threshold)}, the threshold of the "
            "gravity-significance map below: beyond it (hatched), towards higher speed and a heavier flywheel, the "
            "first-order measure calls gravity negligible."
        )
    line += " " + neglected_region_sentence(frame, threshold)
    stalled = (
        f" Blank: the machine stalls ({int(frame['stalled'].sum())} of {len(frame)})." if frame["stalled"].any() else ""
    )
    return (
        f"<p>How much gravity changes the coefficient of speed fluctuation, δ/δ<sub>without gravity</sub> − 1 in %, "
        f"for this machine at mean speeds {low:.4g} … {high:.4g} rpm and shaft inertias I<sub>w</sub> "
        f"{lightest:.4g} … {heaviest:.4g} kg·m² ({GRAVITY_MAP_INERTIA[0]:g} … {GRAVITY_MAP_INERTIA[1]:g} times its "
        f"own, log-spaced): {points} × {points} exact steady states (<code>mc.motion_sweep</code>, the balance "
        f"load at each speed). Red: gravity makes δ larger; blue: smaller; white: no change. The star is the machine "
        f"as built ({100 * results.state.gravity_effect:+.3g} %); over the map gravity changes δ by "
        f"{effect.min():+.3g} … {effect.max():+.3g} %. {map_axes_sentence(frame)} The paper's first-order measure "
        f"δ<sub>g</sub> = max U* − min U* falls as 1/(I<sub>w</sub>n²) everywhere. {line}{stalled}</p>"
    )


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
{_gravity_map_caption(results, machine, threshold)}
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
