"""The report's sentences that state a trend or a comparison, each made from the numbers it
is about (the tables the report shows beside it), so that a machine whose numbers go the
other way reads the other way.

Every function takes the report's own tables and returns HTML text (numbers formatted, no
markup beyond ``<sub>``)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

__all__ = ["FLAT", "map_axes_sentence", "neglected_region_sentence", "significance_sentence", "speed_trend_sentence"]

#: A change over the speed range smaller than this fraction of its largest magnitude is "about
#: the same at every speed"; steps smaller than this fraction do not break a rise or a fall.
FLAT = 0.05


def _percent(value: float) -> str:
    return "0 %" if value == 0 else f"{value:+.3g} %"


def _span(values: np.ndarray | pd.Series) -> str:
    """ "+A … +B %" of the values, or one value where both ends print alike."""
    low, high = _percent(float(np.min(values))), _percent(float(np.max(values)))
    return low if low == high else f"{low[:-2]} … {high}"


def _monotonic(values: np.ndarray, sign: int, tolerance: float) -> bool:
    """Whether ``values`` never moves against ``sign`` (+1 rising, −1 falling) by more than
    ``tolerance``."""
    return bool(np.all(sign * np.diff(values) >= -tolerance))


def speed_trend_sentence(speeds: pd.DataFrame) -> str:
    """How gravity's effect on δ, δ/δ_without gravity − 1, changes over the speed range, from
    the rows of ``speeds`` (columns ``rpm``, ``delta``, ``delta_without_gravity``) that run.

    The magnitude |effect| decides "grows" and "falls"; the sentence gives the values at the
    ends and, where the largest or smallest lies inside the range, there too."""
    if not {"delta", "delta_without_gravity"} <= set(speeds.columns):
        return "The machine stalls at every speed of its range: there is no trend to show."
    rows = speeds.dropna(subset=["delta", "delta_without_gravity"]).sort_values("rpm")
    if len(rows) < 2:
        return "The machine runs at fewer than two speeds of its range: there is no trend to show."
    rpm = rows["rpm"].to_numpy()
    effect = 100 * (rows["delta"].to_numpy() / rows["delta_without_gravity"].to_numpy() - 1)
    size = np.abs(effect)
    largest = float(size.max())
    ends = f"{_percent(effect[0])} at {rpm[0]:.4g} rpm"
    last = f"{_percent(effect[-1])} at {rpm[-1]:.4g} rpm"
    if largest == 0.0:
        return f"Gravity does not change δ at any speed of the range ({rpm[0]:.4g} … {rpm[-1]:.4g} rpm)."
    tolerance = FLAT * largest
    if float(size.max() - size.min()) <= tolerance:
        return (
            f"Gravity changes δ by about the same at every speed of the range ({rpm[0]:.4g} … {rpm[-1]:.4g} rpm): "
            f"{_span(effect)}."
        )
    peak, dip = int(np.argmax(size)), int(np.argmin(size))
    inside = "" if peak == len(size) - 1 else f" (largest {_percent(effect[peak])} at {rpm[peak]:.4g} rpm)"
    if _monotonic(size, +1, tolerance):
        return (
            f"Gravity's effect on δ grows with the speed, from {ends} to {last}{inside}: it matters most at high speed."
        )
    inside = "" if peak == 0 else f" (largest {_percent(effect[peak])} at {rpm[peak]:.4g} rpm)"
    if _monotonic(size, -1, tolerance):
        return (
            f"Gravity's effect on δ falls with the speed, from {ends} to {last}{inside}: it matters most at low speed."
        )
    turn, word = (peak, "largest") if 0 < peak < len(size) - 1 else (dip, "smallest")
    middle = f"{_percent(effect[turn])} at {rpm[turn]:.4g} rpm"
    if _monotonic(size[: turn + 1], +1 if word == "largest" else -1, tolerance) and _monotonic(
        size[turn:], -1 if word == "largest" else +1, tolerance
    ):
        rise, fall = ("grows", "falls") if word == "largest" else ("falls", "grows")
        return (
            f"Gravity's effect on δ {rise} from {ends} to {middle}, then {fall} to {last}: "
            f"it matters most at {rpm[peak]:.4g} rpm."
        )
    return (
        f"Gravity's effect on δ goes up and down over the speed range: {ends}, {last}; largest at "
        f"{rpm[peak]:.4g} rpm ({_percent(effect[peak])}), smallest at {rpm[dip]:.4g} rpm ({_percent(effect[dip])})."
    )


def map_axes_sentence(frame: pd.DataFrame) -> str:
    """Which axis of the speed × shaft-inertia map moves gravity's effect on δ more, from the
    map's rows (``rpm``, ``shaft_inertia``, ``gravity_effect``): the largest change along
    the inertia axis at one speed against the largest change along the speed axis at one
    inertia, in percentage points."""
    effect = 100 * frame.pivot(index="shaft_inertia", columns="rpm", values="gravity_effect")
    along_inertia = float(np.nanmax(effect.max(axis=0) - effect.min(axis=0)))
    along_speed = float(np.nanmax(effect.max(axis=1) - effect.min(axis=1)))
    if not (math.isfinite(along_inertia) and math.isfinite(along_speed)):
        return ""
    values = effect.to_numpy()[np.isfinite(effect.to_numpy())]
    if max(along_inertia, along_speed) <= FLAT * float(np.max(np.abs(values))):
        return f"Gravity changes δ by about the same everywhere on the map: {_span(values)}."
    if along_speed > 2 * along_inertia:
        verdict = "the speed decides it far more than the flywheel"
    elif along_inertia > 2 * along_speed:
        verdict = "the flywheel decides it far more than the speed"
    else:
        verdict = "speed and flywheel both move it"
    return (
        f"At any one speed the change varies by at most {along_inertia:.3g} percentage points over the flywheels "
        f"shown, at any one flywheel by up to {along_speed:.3g} over the speeds: {verdict}."
    )


def neglected_region_sentence(frame: pd.DataFrame, threshold: float) -> str:
    """What gravity does to δ where the paper's first-order measure δ_g calls it negligible
    (δ_g below ``threshold``) and where it does not, from the map's rows (``delta_g``,
    ``gravity_effect``)."""
    effect = 100 * frame["gravity_effect"]
    below = frame["delta_g"] < threshold
    parts = []
    for mask, where in ((below, "below"), (~below, "at or above")):
        values = effect[mask].dropna()
        if len(values):
            parts.append(
                f"where δ<sub>g</sub> is {where} the threshold {threshold:.2g} ({int(mask.sum())} of {len(frame)} "
                f"variants), gravity changes δ by {_span(values)}"
            )
    return ("In the exact steady states, " + "; ".join(parts) + ".") if parts else ""


def significance_sentence(
    crank_ratio: float, deltas: Mapping[int, Sequence[float]], threshold: float, ks: Sequence[int]
) -> str:
    """For the machine's crank unit at its λ on k = ``ks`` cranks, per cycle (``deltas`` maps
    the strokes to δ_g per k): for which k δ_g is above the threshold, and how far below it
    the others are."""
    sentences = []
    for strokes, given in deltas.items():
        values = np.asarray(given, dtype=float)
        above = [k for k, d in zip(ks, values, strict=True) if d >= threshold]
        below = [k for k, d in zip(ks, values, strict=True) if d < threshold]
        name = f"{strokes}-stroke"
        if not below:
            sentences.append(f"{name}: above the threshold for every k")
        elif not above:
            sentences.append(f"{name}: below the threshold for every k (δ<sub>g</sub> ≤ {values.max():.2g})")
        else:
            worst = max(d for k, d in zip(ks, values, strict=True) if k in below)
            sentences.append(
                f"{name}: above the threshold for k = {', '.join(map(str, above))}; below for k = "
                f"{', '.join(map(str, below))} (δ<sub>g</sub> ≤ {worst:.2g}"
                + (
                    f", {math.log10(values[0] / worst):.0f} orders of magnitude below k = 1)"
                    if ks[0] == 1 and values[0] > 0 and worst > 0
                    else ")"
                )
            )
    return f"At this machine's λ = {crank_ratio:.3g}: " + "; ".join(sentences) + "."
