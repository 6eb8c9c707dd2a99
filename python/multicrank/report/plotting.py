"""matplotlib as the report draws with it: loaded when a figure is drawn (the ``report``
extra), off screen, in the report's style."""

from __future__ import annotations

from types import ModuleType

from .._optional import require

__all__ = ["pyplot"]


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
