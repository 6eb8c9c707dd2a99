"""Designs for a sweep: the tables of machines, their validation, and grids of them.

A design is one row: ``crank_ratio``, ``inclination`` [rad], ``u1``, ``u2`` and optionally
``cranks``, ``strokes``, ``acting``. Any other column is refused (a misspelt ``cylinders``
for ``cranks`` would otherwise be carried along while the sweep computes one crank), unless
the sweep is told to pass it through. Designs come as a pandas DataFrame, a mapping of
columns, or a lazy :class:`DesignGrid` (the Cartesian product of axes, generated chunk by
chunk), and are validated before any work starts. The machines' crank phase sets are formed
once per kind of machine (:func:`phase_table`), not once per design.

What a sweep puts out (``SWEEP_OUTPUTS``, ``to_xarray``, re-exported here) lives in `outputs`;
the digest of the designs that fingerprints a stored sweep, in `store`.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Iterable, Mapping
from typing import Any, ClassVar

import numpy as np
import pandas as pd

from .._broadcasting import as_design
from .._native import MechanismError
from .._validation import INDEX_MAX, check_size, part_of, refused, reworded
from .._validation import as_array as _as_array
from ..gravity.mechanism import crank_phases
from .outputs import SWEEP_OUTPUTS, to_xarray

__all__ = [
    "DESIGN_COLUMNS",
    "KNOWN_COLUMNS",
    "OPTIONAL_COLUMNS",
    "SWEEP_OUTPUTS",
    "DesignGrid",
    "ProductGrid",
    "design_grid",
    "to_xarray",
]

DESIGN_COLUMNS = ("crank_ratio", "inclination", "u1", "u2")
OPTIONAL_COLUMNS = {"cranks": 1, "strokes": 2, "acting": "single"}
#: Every column a design may have; others only when a sweep passes them through.
KNOWN_COLUMNS: tuple[str, ...] = (*DESIGN_COLUMNS, *OPTIONAL_COLUMNS)
# Rows validated at a time before a sweep of a table starts (bounded memory).
_VALIDATION_ROWS = 1 << 20


# ----------------------------------------------------------------------------- tables
def as_frame(designs: Any) -> pd.DataFrame:
    """Designs given as a DataFrame or a mapping of equal-length 1-D columns, as a DataFrame."""
    if isinstance(designs, pd.DataFrame):
        return designs
    if isinstance(designs, Mapping):
        columns = {}
        for name, values in designs.items():
            array = _as_array(values, f"designs column {name!r}")
            if array.ndim != 1:
                raise refused("designs", f"designs column {name!r} must be 1-D, got shape {array.shape}")
            columns[name] = array
        lengths = {len(v) for v in columns.values()}
        if len(lengths) > 1:
            sizes = ", ".join(f"{k} {len(v)}" for k, v in columns.items())
            raise refused("designs", f"designs columns must have equal lengths, got {sizes}")
        return pd.DataFrame(columns)
    raise refused(
        "designs",
        "designs must be a pandas DataFrame, a mapping of equal-length 1-D columns, a "
        f"DesignGrid or a dask DataFrame, got {type(designs).__name__}",
    )


def as_passthrough(passthrough: Any) -> tuple[str, ...]:
    """The names of the extra columns a sweep carries through: one string or strings."""
    if passthrough is None:
        return ()
    if isinstance(passthrough, str):
        return (passthrough,)
    if not isinstance(passthrough, Iterable) or isinstance(passthrough, (bytes, Mapping)):
        raise refused(
            "passthrough", f"passthrough must be a column name or a list of them, got {type(passthrough).__name__}"
        )
    names = tuple(passthrough)
    bad = [n for n in names if not isinstance(n, str)]
    if bad:
        raise refused("passthrough", f"passthrough must hold column names (strings), got {bad[0]!r}")
    return names


def suggestion(name: Any, known: Iterable[str]) -> str:
    """The hint for the known name closest to ``name`` (" (did you mean 'x'?)"), or "" where none is."""
    close = difflib.get_close_matches(str(name), list(known), n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


def check_columns(
    columns: Any,
    passthrough: tuple[str, ...] = (),
    outputs: tuple[str, ...] = (),
    *,
    known: tuple[str, ...] = KNOWN_COLUMNS,
    required: tuple[str, ...] = DESIGN_COLUMNS,
    what: str = "design",
) -> None:
    """Raise unless ``columns`` holds every ``required`` column, once, and no column but the
    ``known`` ones and those in ``passthrough``; passthrough names must exist and be neither
    known columns nor outputs (which the sweep would overwrite). ``what`` names the columns
    in messages ("design", "machine")."""
    names = list(columns)
    duplicated = sorted({str(n) for n in names if names.count(n) > 1})
    if duplicated:
        raise refused("designs", f"designs have the column(s) {', '.join(duplicated)} more than once")
    missing = [c for c in required if c not in names]
    if missing:
        raise refused(
            "designs",
            f"designs lack the column(s) {', '.join(missing)}; required: {', '.join(required)} "
            f"(optional: {', '.join(c for c in known if c not in required)})",
        )
    clash = [n for n in passthrough if n in known or n in outputs]
    if clash:
        raise refused(
            "passthrough",
            f"passthrough names {', '.join(map(repr, clash))}: {what} columns and outputs are not passed through",
        )
    absent = [n for n in passthrough if n not in names]
    if absent:
        raise refused("passthrough", f"passthrough names {', '.join(map(repr, absent))}, which the designs do not have")
    unknown = [n for n in names if n not in known and n not in passthrough]
    if unknown:
        first = unknown[0]
        raise refused(
            "designs",
            f"designs have the unknown column(s) {', '.join(map(repr, unknown))}{suggestion(first, known)}; "
            f"known: {', '.join(known)}. Carry other columns through the sweep with "
            f"passthrough=[{first!r}, ...]",
        )


def _integer_column(values: Any, name: str, allowed: tuple[int, ...] | None, minimum: int) -> np.ndarray:
    array = _as_array(values, name)
    if array.dtype.kind == "f" and np.all(np.isfinite(array)) and np.all(array == np.round(array)):
        array = array.astype(np.int64)
    if array.dtype.kind not in "iu":
        raise refused(name, f"designs column {name!r} must hold integers, got dtype {array.dtype}")
    if array.size and array.min() < minimum:
        raise refused(name, f"{name} = {array.min()} is out of range; allowed: an integer >= {minimum}")
    if array.size and array.max() > INDEX_MAX:
        raise refused(name, f"{name} = {array.max()} is out of range; allowed: an integer >= {minimum}")
    if allowed is not None and array.size and not np.isin(array, allowed).all():
        bad = array[~np.isin(array, allowed)][0]
        raise refused(name, f"{name} = {bad} is not allowed; allowed: {' or '.join(map(str, allowed))}")
    return array.astype(np.int64)


def _double_acting(values: Any) -> np.ndarray:
    """The ``acting`` column as "is double-acting" (cheaper to key machine kinds by than strings)."""
    acting = np.asarray(_as_array(values, "acting"), dtype=object)
    bad = ~np.isin(acting, ["single", "double"])
    if bad.any():
        raise refused("acting", f"acting = {acting[bad][0]!r} is not allowed; allowed: 'single', 'double'")
    return acting == "double"


def _column(name: str, values: Any) -> np.ndarray:
    """One design column, validated (``acting`` comes back as "is double-acting")."""
    if name == "crank_ratio":
        return as_design(values, name, low=0.0, high=1.0)
    if name in ("inclination", "u1", "u2"):
        return as_design(values, name)
    if name == "cranks":
        return _integer_column(values, name, None, 1)
    if name == "strokes":
        return _integer_column(values, name, (2, 4), 1)
    return _double_acting(values)


def _table_column(name: str, frame: pd.DataFrame) -> np.ndarray:
    """:func:`_column` of a table's column; its refusal names the first row that fails (by the
    frame's index, as a motion sweep names a row) and the value there."""
    values = frame[name].to_numpy()
    try:
        return _column(name, values)
    except MechanismError as error:
        # A column passes exactly when each of its prefixes does: bisect for the first row
        # that fails (a few passes over the column, and only when there is a fault to name).
        good, bad = 0, len(values)
        while bad - good > 1:
            middle = (good + bad) // 2
            try:
                _column(name, values[:middle])
            except MechanismError:
                bad = middle
            else:
                good = middle
        value = values[bad - 1]
        shown = f"{value:g}" if isinstance(value, (float, np.floating)) else repr(value)
        raise reworded(error, f"design {frame.index[bad - 1]} ({name} = {shown}): {error}") from None


def machine_columns(frame: pd.DataFrame) -> dict[str, np.ndarray]:
    """The validated design columns of a frame (optional columns filled with defaults); a
    refused value is named with its row and column."""
    check_columns(frame.columns, passthrough=tuple(c for c in frame.columns if c not in KNOWN_COLUMNS))
    n = len(frame)
    out = {name: _table_column(name, frame) for name in DESIGN_COLUMNS}
    out["cranks"] = _table_column("cranks", frame) if "cranks" in frame else _column("cranks", np.full(n, 1))
    out["strokes"] = _table_column("strokes", frame) if "strokes" in frame else _column("strokes", np.full(n, 2))
    out["double"] = _table_column("acting", frame) if "acting" in frame else np.zeros(n, dtype=bool)
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
class ProductGrid:
    """The lazy Cartesian product of named 1-D axes and scalar constants: what
    :class:`DesignGrid` and :class:`~multicrank.MachineGrid` share.

    A subclass names the columns it takes (``KNOWN``), what they are in words (``COLUMN``,
    ``GRID``, for messages) and checks an axis's values (:meth:`_check_values`); rows are
    formed here, chunk by chunk, in C order (the first axis varies slowest).
    """

    #: The column names an axis may have.
    KNOWN: ClassVar[tuple[str, ...]] = ()
    #: What an axis is, in words ("a design column").
    COLUMN: ClassVar[str] = "a column"
    #: What the grid is, in words ("a design grid").
    GRID: ClassVar[str] = "a grid"

    axes: dict[str, np.ndarray]
    constants: dict[str, Any]
    shape: tuple[int, ...]

    def __init__(self, **axes: Any) -> None:
        if not axes:
            raise refused("axes", f"{self.GRID} needs at least one axis")
        known = self._known()
        unknown = [name for name in axes if name not in known]
        if unknown:
            raise refused(
                unknown[0],
                f"grid axis {unknown[0]!r} is not {self.COLUMN}{suggestion(unknown[0], known)}; "
                f"known: {', '.join(known)}",
            )
        self.axes = {}
        self.constants = {}
        for name, values in axes.items():
            with part_of(name):
                array = _as_array(list(values) if isinstance(values, range) else values, f"grid axis {name!r}")
            if array.ndim == 0:
                self._check_values(name, array.reshape(1))  # validated now, not chunks into a sweep
                self.constants[name] = array.item()
                continue
            if array.ndim != 1 or array.size == 0:
                raise refused(
                    name, f"grid axis {name!r} must be a scalar or a non-empty 1-D sequence, got shape {array.shape}"
                )
            self._check_values(name, array)
            self.axes[name] = array
        self.shape = tuple(len(v) for v in self.axes.values())
        if math.prod(self.shape) > INDEX_MAX:
            sizes = " × ".join(f"{len(v)} {k}" for k, v in self.axes.items())
            raise refused(
                "axes", f"the grid's axes make {math.prod(self.shape)} designs ({sizes}); at most {INDEX_MAX}"
            )

    def _known(self) -> tuple[str, ...]:
        """The column names an axis of this grid may have (``KNOWN``, unless the grid says
        otherwise)."""
        return self.KNOWN

    def _check_values(self, name: str, values: np.ndarray) -> None:
        """Raise unless ``values`` (1-D) are allowed in column ``name``."""
        raise NotImplementedError

    def __len__(self) -> int:
        return math.prod(self.shape)

    def __eq__(self, other: object) -> bool:
        # By value: the same axes and constants in the same order (the order is the rows').
        if type(other) is not type(self):
            return NotImplemented
        assert isinstance(other, ProductGrid)
        return (
            list(self.axes) == list(other.axes)
            and all(np.array_equal(values, other.axes[name]) for name, values in self.axes.items())
            and list(self.constants.items()) == list(other.constants.items())
        )

    # Not hashable: its axes are a dict, which may be changed.
    __hash__ = None  # type: ignore[assignment]

    def frame(self, start: int = 0, stop: int | None = None) -> pd.DataFrame:
        """Some rows of the product.

        Parameters
        ----------
        start : int, default 0
            The first row.
        stop : int, optional
            One past the last row; default (and at most) ``len(grid)``.

        Returns
        -------
        pandas.DataFrame
            Rows start … stop − 1, indexed by row number: one column per axis and constant.
        """
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
        """The whole product (for small grids).

        Returns
        -------
        pandas.DataFrame
            Every row, as :meth:`frame` gives them.
        """
        return self.frame()

    def axis_lists(self) -> dict[str, list]:
        """The axes as lists, as a grid's frame keeps them in ``attrs["grid_axes"]``.

        Returns
        -------
        dict of str to list
            One list per axis, in order.
        """
        return {k: v.tolist() for k, v in self.axes.items()}


class DesignGrid(ProductGrid):
    """The Cartesian product of design axes, generated lazily chunk by chunk.

    1-D axes span the grid (C order, the first axis varies slowest); scalars are constant
    columns. ``len(grid)`` is the number of designs; ``grid.frame(start, stop)`` builds only
    those rows, so a sweep of 10⁷ designs never holds them all. Only design columns are
    accepted, and every value is validated here, so that a misspelt name or a bad value
    fails at once rather than chunks into a sweep.

    Parameters
    ----------
    **axes
        Design columns by name, each a 1-D sequence (an axis) or a scalar (a constant):
        ``crank_ratio`` λ [dimensionless], ``inclination`` γ [rad], ``u1``, ``u2``
        [dimensionless], and optionally ``cranks`` (int ≥ 1, default 1), ``strokes`` (2 or 4,
        default 2) and ``acting`` ("single" or "double", default "single").

    Attributes
    ----------
    axes : dict of str to ndarray
        The 1-D axes, in the order given.
    constants : dict
        The scalar columns.
    shape : tuple of int
        The length of every axis.

    See Also
    --------
    design_grid : The same product as a DataFrame, at once.
    sweep : Takes a grid and sweeps it chunk by chunk.

    Examples
    --------
    >>> import numpy as np
    >>> import multicrank as mc
    >>> grid = mc.DesignGrid(crank_ratio=np.linspace(0.2, 0.45, 26),
    ...                      inclination=np.radians([0, 45, 90]),
    ...                      u1=np.geomspace(1e-4, 1e-1, 31), u2=0.0, cranks=range(1, 13))
    >>> len(grid), grid.shape
    (29016, (26, 3, 31, 12))
    >>> grid.frame(0, 2)
       crank_ratio  inclination      u1  cranks   u2
    0          0.2          0.0  0.0001       1  0.0
    1          0.2          0.0  0.0001       2  0.0
    """

    KNOWN = KNOWN_COLUMNS
    COLUMN = "a design column"
    GRID = "a design grid"

    def _check_values(self, name: str, values: np.ndarray) -> None:
        _column(name, values)


def design_grid(**axes: Any) -> pd.DataFrame:
    """The Cartesian product of the given axes as a DataFrame (one row per design).

    1-D axes span the grid in C order (the first axis varies slowest); scalars become
    constant columns. Names and values are checked as by :class:`DesignGrid`.

    Parameters
    ----------
    **axes
        Design columns by name, each a 1-D sequence (an axis) or a scalar (a constant):
        ``crank_ratio`` λ [dimensionless], ``inclination`` γ [rad], ``u1``, ``u2``
        [dimensionless], and optionally ``cranks``, ``strokes`` and ``acting``.

    Returns
    -------
    pandas.DataFrame
        One row per design. The frame remembers its axes (``frame.attrs["grid_axes"]``), so
        that a sweep of it converts to an ``xarray.Dataset`` with one dimension per axis
        (:func:`to_xarray`).

    Examples
    --------
    >>> import numpy as np
    >>> import multicrank as mc
    >>> grid = mc.design_grid(crank_ratio=[0.2, 0.3], inclination=np.radians([0, 90]),
    ...                       u1=1e-3, u2=0.0, cranks=[1, 2])
    >>> len(grid), list(grid.columns)
    (8, ['crank_ratio', 'inclination', 'cranks', 'u1', 'u2'])
    """
    grid = DesignGrid(**axes)
    frame = grid.to_frame()
    frame.attrs["grid_axes"] = grid.axis_lists()
    return frame


def design_rows(designs: Any) -> tuple[int, Callable[[int, int], pd.DataFrame]]:
    """(number of designs, function start, stop -> the DataFrame of those rows)."""
    if isinstance(designs, ProductGrid):
        return len(designs), designs.frame
    frame = as_frame(designs)
    return len(frame), lambda start, stop: frame.iloc[start:stop]


def grid_axes_of(designs: Any) -> dict[str, list] | None:
    """The grid axes that designs come from (a grid, or a frame of :func:`design_grid`)."""
    if isinstance(designs, ProductGrid):
        return designs.axis_lists()
    return getattr(designs, "attrs", {}).get("grid_axes")


def validate_designs(designs: Any, passthrough: tuple[str, ...], outputs: tuple[str, ...]) -> None:
    """Check every design before a sweep starts: column names (against ``passthrough``) and,
    for a table, every value, chunk by chunk (a grid checked its axes when it was made)."""
    if isinstance(designs, DesignGrid):
        check_columns([*designs.axes, *designs.constants], passthrough, outputs)
        return
    frame = as_frame(designs)
    check_columns(frame.columns, passthrough, outputs)
    for start in range(0, len(frame), _VALIDATION_ROWS):
        machine_columns(frame.iloc[start : start + _VALIDATION_ROWS])
