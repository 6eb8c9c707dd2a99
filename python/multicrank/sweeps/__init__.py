"""Design sweeps: `designs` (the design columns and grids of designs, lazily), `outputs` (the
outputs' names and `to_xarray`), `driver` (`sweep`: in memory, to Parquet, or on a dask
DataFrame), `chunks` (how any sweep runs its chunks, shared with
:func:`~multicrank.motion_sweep`) and `store` (the Parquet parts, their fingerprint — the
designs' digest among it — and resume).

Nothing is imported here: the sweep machinery pulls in pandas (and, where installed,
pyarrow's thread pools), and `multicrank` loads it on first use.
"""

from __future__ import annotations

import importlib
from typing import Any

# What multicrank 0.1's module `multicrank.sweeps` held, loaded on first use.
_NAMES = {
    "SWEEP_OUTPUTS": "designs",
    "DesignGrid": "designs",
    "design_grid": "designs",
    "to_xarray": "designs",
    "sweep": "driver",
}


def __getattr__(name: str) -> Any:
    if name in _NAMES:
        return getattr(importlib.import_module(f"{__name__}.{_NAMES[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
