"""matplotlib as the report draws with it: loaded when a figure is drawn (the ``report``
extra), off screen, in the report's style."""

from __future__ import annotations

import math
from types import ModuleType
from typing import Any

from .._optional import require

__all__ = ["plain_log_axis", "pyplot", "symmetric_limit", "threshold_text"]


def pyplot() -> ModuleType:
    """matplotlib.pyplot on the Agg backend, with the report's style.

    Raises
    ------
    OptionalDependencyError
        Where matplotlib is not installed (it names the ``report`` extra).
    """
    matplotlib = require("matplotlib", "report")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"figure.dpi": 110, "axes.grid": True, "grid.alpha": 0.3, "font.size": 9})
    return plt


def plain_log_axis(axis: Any) -> None:
    """Tick labels on a logarithmic axis as plain numbers (60, 100, 200), not 6×10¹, with
    about three to eight ticks for the decades the axis spans. Call it after the data are
    drawn (it reads the axis's limits)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    low, high = sorted(axis.get_view_interval())
    decades = math.log10(high / low) if low > 0 else math.inf
    subs = (1.0, 1.5, 2.0, 3.0, 5.0, 7.0) if decades <= 1.2 else (1.0, 2.0, 5.0) if decades <= 2.5 else (1.0,)
    axis.set_major_locator(LogLocator(subs=subs))
    axis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:g}"))
    axis.set_minor_formatter(NullFormatter())


def symmetric_limit(largest: float, floor: float) -> float:
    """The half-range of a colour scale centred at 0 that covers data of largest magnitude
    ``largest``: the next of 1, 1.5, 2, 2.5, 3, 4, 5, 6, 8 × 10ᵏ at or above it, and at least
    ``floor``, so that values far below the floor show as near-white rather than saturated."""
    value = max(abs(largest), floor) if math.isfinite(largest) else floor
    scale = 10.0 ** math.floor(math.log10(value))
    return next(step * scale for step in (1, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10) if step * scale >= value * (1 - 1e-12))


def threshold_text(threshold: float) -> str:
    """The δ_g threshold as the figures write it: "1/3000" where it is one over a whole number
    (to 1e-9), else its 4 significant digits ("0.0004")."""
    whole = round(1 / threshold)
    return f"1/{whole}" if whole >= 1 and abs(whole * threshold - 1) <= 1e-9 else f"{threshold:.4g}"
