"""The report's map of where gravity matters, in its first part: the machine's steady running
over its speed range × shaft inertias around its own (:func:`gravity_map`, a motion sweep),
gravity's effect on δ over it with the line where the paper's first-order measure δ_g crosses
the report's threshold (:func:`gravity_map_figure`, :func:`threshold_curve`) and the caption
that says what it shows (:func:`gravity_map_caption`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from .._validation import as_count
from ..machine.machine import Machine
from .plotting import plain_log_axis, pyplot, symmetric_limit, threshold_text
from .prose import map_axes_sentence, neglected_region_sentence
from .settings import ReportSettings, speed_range

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .motion import MotionResults

__all__ = [
    "GRAVITY_MAP_INERTIA",
    "gravity_map",
    "gravity_map_caption",
    "gravity_map_figure",
    "threshold_curve",
]

#: The shaft inertias of the "where gravity matters" map, as multiples of the machine's own
#: (log-spaced from the first to the second): a flywheel a quarter of it to four times it.
GRAVITY_MAP_INERTIA = (0.25, 4.0)
#: The least half-range of the map's colours [%]: a change of δ far below it (0.02 %) shows
#: near-white, not as saturated as one of 30 %.
MAP_FLOOR_PERCENT = 1.0
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


def gravity_map_caption(results: MotionResults, machine: Machine, threshold: float) -> str:
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
