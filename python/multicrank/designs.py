"""Designs for a sweep: the tables of machines, their validation, and grids of them.

A design is one row: ``crank_ratio``, ``inclination`` [rad], ``u1``, ``u2`` and optionally
``cranks``, ``strokes``, ``acting``; other columns are carried through. Designs come as a
pandas DataFrame, a mapping of columns, or a lazy :class:`DesignGrid` (the Cartesian
product of axes, generated chunk by chunk). The machines' crank phase sets are formed once
per kind of machine (:func:`phase_table`), not once per design.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import pandas as pd

from ._native import SWEEP_OUTPUTS as _NATIVE_SWEEP_OUTPUTS
from ._native import MechanismError
from ._optional import require
from ._validation import as_design, check_size
from .mechanism import crank_phases

__all__ = ["DESIGN_COLUMNS", "OPTIONAL_COLUMNS", "SWEEP_OUTPUTS", "DesignGrid", "design_grid", "to_xarray"]

#: Every output a sweep can compute, in column order (the core's names).
SWEEP_OUTPUTS: tuple[str, ...] = tuple(_NATIVE_SWEEP_OUTPUTS)
DESIGN_COLUMNS = ("crank_ratio", "inclination", "u1", "u2")
OPTIONAL_COLUMNS = {"cranks": 1, "strokes": 2, "acting": "single"}


# ----------------------------------------------------------------------------- tables
def as_frame(designs: Any) -> pd.DataFrame:
    """Designs given as a DataFrame or a mapping of equal-length 1-D columns, as a DataFrame."""
    if isinstance(designs, pd.DataFrame):
        return designs
    if isinstance(designs, Mapping):
        columns = {}
        for name, values in designs.items():
            array = np.asarray(values)
            if array.ndim != 1:
                raise MechanismError(f"designs column {name!r} must be 1-D, got shape {array.shape}")
            columns[name] = array
        lengths = {len(v) for v in columns.values()}
        if len(lengths) > 1:
            sizes = ", ".join(f"{k} {len(v)}" for k, v in columns.items())
            raise MechanismError(f"designs columns must have equal lengths, got {sizes}")
        return pd.DataFrame(columns)
    raise MechanismError(
        "designs must be a pandas DataFrame, a mapping of equal-length 1-D columns, a "
        f"DesignGrid or a dask DataFrame, got {type(designs).__name__}"
    )


def check_columns(columns: Any) -> None:
    """Raise unless ``columns`` holds every required design column."""
    missing = [c for c in DESIGN_COLUMNS if c not in columns]
    if missing:
        raise MechanismError(
            f"designs lack the column(s) {', '.join(missing)}; required: {', '.join(DESIGN_COLUMNS)} "
            f"(optional: {', '.join(OPTIONAL_COLUMNS)})"
        )


def _integer_column(values: Any, name: str, allowed: tuple[int, ...] | None, minimum: int) -> np.ndarray:
    array = np.asarray(values)
    if array.dtype.kind == "f" and np.all(np.isfinite(array)) and np.all(array == np.round(array)):
        array = array.astype(np.int64)
    if array.dtype.kind not in "iu":
        raise MechanismError(f"designs column {name!r} must hold integers, got dtype {array.dtype}")
    if array.size and array.min() < minimum:
        raise MechanismError(f"{name} = {array.min()} is out of range; allowed: an integer >= {minimum}")
    if allowed is not None and array.size and not np.isin(array, allowed).all():
        bad = array[~np.isin(array, allowed)][0]
        raise MechanismError(f"strokes = {bad} is not allowed; allowed: 2 or 4")
    return array.astype(np.int64)


def machine_columns(frame: pd.DataFrame) -> dict[str, np.ndarray]:
    """The validated design columns of a frame (optional columns filled with defaults)."""
    check_columns(frame.columns)
    n = len(frame)
    out = {
        "crank_ratio": as_design(frame["crank_ratio"].to_numpy(), "crank_ratio", low=0.0, high=1.0),
        "inclination": as_design(frame["inclination"].to_numpy(), "inclination"),
        "u1": as_design(frame["u1"].to_numpy(), "u1"),
        "u2": as_design(frame["u2"].to_numpy(), "u2"),
    }
    cranks = frame["cranks"].to_numpy() if "cranks" in frame else np.full(n, 1)
    strokes = frame["strokes"].to_numpy() if "strokes" in frame else np.full(n, 2)
    out["cranks"] = _integer_column(cranks, "cranks", None, 1)
    out["strokes"] = _integer_column(strokes, "strokes", (2, 4), 1)
    # Kept as "is double-acting", not as strings: cheaper to key machine kinds by.
    if "acting" in frame:
        acting = np.asarray(frame["acting"].to_numpy(), dtype=object)
        bad = ~np.isin(acting, ["single", "double"])
        if bad.any():
            raise MechanismError(f"acting = {acting[bad][0]!r} is not allowed; allowed: 'single', 'double'")
        out["double"] = acting == "double"
    else:
        out["double"] = np.zeros(n, dtype=bool)
    return out


def phase_table(columns: dict[str, np.ndarray]) -> tuple[np.ndarray, list[np.ndarray]]:
    """(per-design index into the distinct crank phase sets, those sets)."""
    double = columns["double"]
    # One integer per machine kind: cheaper to make unique than tuples of objects.
    kinds = columns["cranks"] * 4 + (columns["strokes"] == 4) * 2 + double
    unique, codes = np.unique(kinds, return_inverse=True)
    sets = [crank_phases(int(key // 4), 4 if key % 4 >= 2 else 2, "double" if key % 2 else "single") for key in unique]
    return codes.astype(np.uint32), sets


# ----------------------------------------------------------------------------- grids
class DesignGrid:
    """The Cartesian product of design axes, generated lazily chunk by chunk.

    ``DesignGrid(crank_ratio=np.linspace(0.2, 0.45, 26), inclination=..., u1=..., u2=0.0,
    cranks=range(1, 13))``: 1-D axes span the grid (C order, first axis slowest); scalars are
    constant columns. ``len(grid)`` is the number of designs; ``grid.frame(start, stop)``
    builds only those rows, so a sweep of 10⁷ designs never holds them all.
    """

    def __init__(self, **axes: Any) -> None:
        if not axes:
            raise MechanismError("a design grid needs at least one axis")
        self.axes: dict[str, np.ndarray] = {}
        self.constants: dict[str, Any] = {}
        for name, values in axes.items():
            if isinstance(values, str) or np.ndim(values) == 0:
                self.constants[name] = values
            else:
                array = np.asarray(list(values) if isinstance(values, range) else values)
                if array.ndim != 1 or array.size == 0:
                    raise MechanismError(f"grid axis {name!r} must be a scalar or a non-empty 1-D sequence")
                self.axes[name] = array
        self.shape = tuple(len(v) for v in self.axes.values())

    def __len__(self) -> int:
        return math.prod(self.shape)

    def frame(self, start: int = 0, stop: int | None = None) -> pd.DataFrame:
        """Rows start … stop−1 of the product as a DataFrame (index = row number)."""
        stop = len(self) if stop is None else min(stop, len(self))
        # One column per axis and constant, plus the index: checked before any is formed.
        count = max(stop - start, 0)
        check_size("designs", f"{count} rows", count * (len(self.axes) + len(self.constants) + 1))
        rows = np.arange(start, stop)
        index = np.unravel_index(rows, self.shape) if self.shape else ()
        data = {name: values[i] for (name, values), i in zip(self.axes.items(), index, strict=True)}
        for name, value in self.constants.items():
            data[name] = np.full(len(rows), value, dtype=object if isinstance(value, str) else None)
        return pd.DataFrame(data, index=pd.RangeIndex(start, stop))

    def to_frame(self) -> pd.DataFrame:
        return self.frame()

    def axis_lists(self) -> dict[str, list]:
        """The axes as lists, as a grid's frame keeps them in ``attrs["grid_axes"]``."""
        return {k: v.tolist() for k, v in self.axes.items()}


def design_grid(**axes: Any) -> pd.DataFrame:
    """The Cartesian product of the given axes as a DataFrame (one row per design).

    1-D axes span the grid in C order (the first axis varies slowest); scalars become
    constant columns. The frame remembers its axes (``frame.attrs["grid_axes"]``) so that a
    sweep of it converts to an ``xarray.Dataset`` with one dimension per axis
    (:func:`to_xarray`).
    """
    grid = DesignGrid(**axes)
    frame = grid.to_frame()
    frame.attrs["grid_axes"] = grid.axis_lists()
    return frame


def design_rows(designs: Any) -> tuple[int, Callable[[int, int], pd.DataFrame]]:
    """(number of designs, function start, stop -> the DataFrame of those rows)."""
    if isinstance(designs, DesignGrid):
        return len(designs), designs.frame
    frame = as_frame(designs)
    return len(frame), lambda start, stop: frame.iloc[start:stop]


def grid_axes_of(designs: Any) -> dict[str, list] | None:
    """The grid axes that designs come from (a DesignGrid, or a frame of :func:`design_grid`)."""
    if isinstance(designs, DesignGrid):
        return designs.axis_lists()
    return getattr(designs, "attrs", {}).get("grid_axes")


def to_xarray(result: pd.DataFrame, axes: Mapping[str, Any] | None = None) -> Any:
    """A grid sweep's result as an ``xarray.Dataset``: one dimension per grid axis, one
    variable per output. ``axes`` defaults to the ``grid_axes`` the grid left in ``attrs``."""
    xr = require("xarray", "xarray")

    axes = axes if axes is not None else result.attrs.get("grid_axes")
    if not axes:
        raise MechanismError("result does not come from a design grid: pass axes={name: values, ...}")
    shape = tuple(len(v) for v in axes.values())
    if math.prod(shape) != len(result):
        raise MechanismError(f"result has {len(result)} rows, the axes make {math.prod(shape)}")
    outputs = [c for c in result.columns if c in SWEEP_OUTPUTS]
    dims = list(axes)
    return xr.Dataset(
        {name: (dims, result[name].to_numpy().reshape(shape)) for name in outputs},
        coords={name: np.asarray(values) for name, values in axes.items()},
    )
