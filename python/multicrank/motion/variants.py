"""Machines that differ from a base machine in a few numbers: how a row of a motion sweep's
design columns becomes a :class:`~multicrank.Machine` (:func:`machine_variant`, the one place
of that rule, used by :func:`~multicrank.motion_sweep` and its tests), which columns there
are, and grids of them (:class:`MachineGrid`).

The columns: ``shaft_inertia`` and ``g`` replace the machine's own (:meth:`Machine.replace
<multicrank.Machine.replace>`); ``rpm`` is the mean speed asked of the steady state (not
stored on the machine, whose ``rpm_range`` describes where it is meant to run, not where it
may be studied); ``pressure_scale`` multiplies every indicator diagram of every cylinder;
every other column is a :class:`~multicrank.Cylinder` field set on every cylinder
(:meth:`Cylinder.replace <multicrank.Cylinder.replace>`), except ``"phase[j]"``,
``"counterweight_mass[j]"`` and ``"counterweight_radius[j]"``, which set that field of
cylinder j alone (a firing order, a counterweight per throw), after the columns of every
cylinder.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._native import MechanismError
from .._text import counted
from .._validation import SPEED_LIMITS, as_instance, as_real_array, as_rpm, omega_from_rpm, refused, reworded
from ..machine.cylinder import Cylinder, Pressure
from ..machine.machine import Machine
from ..pressure.diagram import IndicatorDiagram
from ..sweeps.designs import ProductGrid
from .columns import CYLINDER_COLUMNS, MACHINE_COLUMNS, UNIT_COLUMNS

__all__ = [
    "CYLINDER_COLUMNS",
    "MACHINE_COLUMNS",
    "UNIT_COLUMNS",
    "MachineGrid",
    "ScaledPressure",
    "check_values",
    "machine_columns",
    "machine_variant",
    "row_variant",
    "scaled_pressure",
]

_UNIT_COLUMN = re.compile(r"(?P<field>[a-z_]+)\[(?P<index>[0-9]+)\]")


def machine_columns(machine: Machine) -> tuple[str, ...]:
    """Every column a design of ``machine`` may have: :data:`MACHINE_COLUMNS`, then
    ``"field[j]"`` for each field of :data:`UNIT_COLUMNS` and each cylinder j."""
    own = (f"{field}[{j}]" for j in range(len(machine.cylinders)) for field in UNIT_COLUMNS)
    return (*MACHINE_COLUMNS, *own)


def _unit_column(name: str) -> tuple[str, int] | None:
    """The field and cylinder of a one-cylinder column ``"field[j]"``; None for any other name."""
    match = _UNIT_COLUMN.fullmatch(name)
    if match is None or match["field"] not in UNIT_COLUMNS:
        return None
    return match["field"], int(match["index"])


@dataclass(frozen=True)
class ScaledPressure:
    """A pressure callable times a factor: ``pressure_scale`` for a pressure that is not an
    :class:`~multicrank.IndicatorDiagram` (picklable wherever ``function`` is).

    Attributes
    ----------
    function : callable
        The gauge pressure p(θ) [Pa] of the cycle angle θ [rad].
    factor : float
        The multiplier [dimensionless].
    """

    function: Pressure
    factor: float

    def __call__(self, theta: Any) -> np.ndarray:
        return self.factor * np.asarray(self.function(theta), dtype=float)

    @property
    def cycle(self) -> Any:
        """The wrapped pressure's cycle [rad], where it has one (None otherwise)."""
        return getattr(self.function, "cycle", None)

    @property
    def breakpoints(self) -> Any:
        """The wrapped pressure's breakpoints [rad], where it has them (None otherwise)."""
        return getattr(self.function, "breakpoints", None)


def scaled_pressure(pressure: Pressure | None, factor: float) -> Pressure | None:
    """``pressure`` times ``factor``: a diagram's :meth:`~multicrank.IndicatorDiagram.scaled`,
    a :class:`ScaledPressure` of another callable, None for None."""
    if pressure is None or factor == 1.0:
        return pressure
    if isinstance(pressure, IndicatorDiagram):
        return pressure.scaled(factor)
    return ScaledPressure(pressure, factor)


def _cylinder_variant(cylinder: Cylinder, fields: dict[str, float], scale: float | None) -> Cylinder:
    changes: dict[str, Any] = dict(fields)
    if scale is not None:
        changes["pressure"] = scaled_pressure(cylinder.pressure, scale)
        changes["pressure_crank_end"] = scaled_pressure(cylinder.pressure_crank_end, scale)
    return cylinder.replace(**changes) if changes else cylinder


def machine_variant(machine: Machine, design: Mapping[str, Any]) -> Machine:
    """The machine a design describes: ``machine`` with the design's columns applied.

    Parameters
    ----------
    machine : Machine
        The base machine.
    design : mapping of str to float
        Column name → value, names from :func:`machine_columns` (others are ignored, as is
        ``rpm``: the speed is asked of the steady state, not stored on the machine).

    Returns
    -------
    Machine
        ``machine`` itself where nothing changes; otherwise a checked copy. A cylinder field
        is set on every cylinder; a two-mass rod (``rod_inertia`` left to its default)
        stays one when the design changes the rod's mass, length or centre of gravity,
        unless ``rod_inertia`` is a column too, as :meth:`Cylinder.replace` does. A column
        ``"field[j]"`` sets that field of cylinder j alone, after the columns of every cylinder.

    Raises
    ------
    MechanismError
        For a value the machine or a cylinder refuses, naming the field; for a column of a
        cylinder the machine does not have.
    """
    changes: dict[str, Any] = {name: float(design[name]) for name in ("shaft_inertia", "g") if name in design}
    fields = {name: float(design[name]) for name in CYLINDER_COLUMNS if name in design}
    scale = float(design["pressure_scale"]) if "pressure_scale" in design else None
    own: dict[int, dict[str, float]] = {}
    for name, value in design.items():
        parsed = _unit_column(str(name))
        if parsed is not None:
            field, index = parsed
            if index >= len(machine.cylinders):
                raise refused(
                    "designs",
                    f"the column {name!r} sets cylinder {index}, but machine {machine.name!r} has "
                    f"{len(machine.cylinders)} (numbered from 0)",
                )
            own.setdefault(index, {})[field] = float(value)
    if fields or scale is not None or own:
        cylinders = [_cylinder_variant(c, fields, scale) for c in machine.cylinders]
        for index, values in own.items():
            cylinders[index] = cylinders[index].replace(**values)
        changes["cylinders"] = cylinders
    return machine.replace(**changes) if changes else machine


def check_values(name: str, values: Any, rows: Any = None) -> np.ndarray:
    """The values of design column ``name`` as float64, checked: finite reals (``rpm``: within
    the speeds the package takes). Ranges that depend on the machine (a rod longer than its
    crank, a positive shaft inertia) are the machine's to check (:func:`machine_variant`).
    ``rows``: the labels of a table's rows (its index), for the refusal to name the first
    bad value's row as :func:`row_variant` does."""
    array = as_real_array(values, name).astype(np.float64, copy=False)
    if name == "rpm":
        low, high = SPEED_LIMITS  # the core's rule, on ω [rad/s]
        omega = omega_from_rpm(array)
        bad = np.flatnonzero(~((omega >= low) & (omega <= high)))  # NaN fails both
    else:
        bad = np.flatnonzero(~np.isfinite(array))
    if bad.size:
        value = array.flat[bad[0]]
        try:
            if name == "rpm":
                as_rpm(value, "rpm")  # raises, with the speeds' own range
            raise refused(name, f"{name} = {value} is out of range; allowed: a finite number")
        except MechanismError as error:
            if rows is None:
                raise
            raise reworded(error, f"design {rows[bad[0]]} ({name} = {value:g}): {error}") from None
    return array


def row_variant(machine: Machine, design: Mapping[str, Any], row: Any) -> Machine:
    """:func:`machine_variant`, its refusal naming the row and its design."""
    try:
        return machine_variant(machine, design)
    except MechanismError as error:
        known = machine_columns(machine)
        values = ", ".join(f"{k} = {v:g}" for k, v in design.items() if k in known)
        raise reworded(error, f"design {row} ({values}): {error}") from None


class MachineGrid(ProductGrid):
    """Variants of one machine: the Cartesian product of axes of its numbers, lazily.

    1-D axes span the grid (C order, the first axis varies slowest); scalars are constant
    columns. ``len(grid)`` is the number of designs; ``grid.frame(start, stop)`` builds only
    those rows. Names and values are checked here: every value of every axis by building
    the machine of the first row with that value (every such machine is a row of the grid),
    and the last row's machine, so that a misspelt name or a bad value fails at once.

    Parameters
    ----------
    machine : Machine
        The base machine; every design is it with the design's columns changed.
    **axes
        Columns by name, each a 1-D sequence (an axis) or a scalar (a constant):
        ``shaft_inertia`` I_w [kg·m²], ``rpm`` the mean speed [1/min], ``g`` [m/s²],
        ``pressure_scale`` [dimensionless] (multiplies every indicator diagram), and any
        :class:`Cylinder` field set on every cylinder: ``crank_radius``, ``rod_length``,
        ``rod_cg``, ``counterweight_radius``, ``crank_cg_radius``, ``bore`` [m],
        ``piston_mass``, ``rod_mass``, ``crank_mass``, ``counterweight_mass`` [kg],
        ``rod_inertia`` [kg·m²]; and a field of cylinder j alone (from 0; pass these as
        ``**{"phase[1]": ...}``): ``"phase[j]"`` [rad], ``"counterweight_mass[j]"`` [kg],
        ``"counterweight_radius[j]"`` [m].

    Attributes
    ----------
    machine : Machine
        The base machine.
    axes : dict of str to ndarray
        The 1-D axes, in the order given.
    constants : dict
        The scalar columns.
    shape : tuple of int
        The length of every axis.

    See Also
    --------
    motion_sweep : Takes a grid and sweeps it chunk by chunk.
    DesignGrid : The same for the dimensionless designs of :func:`sweep`.

    Examples
    --------
    >>> import numpy as np
    >>> import multicrank as mc
    >>> compressor = mc.presets.MACHINES["slow-compressor"]
    >>> grid = mc.MachineGrid(compressor, shaft_inertia=[250.0, 350.0, 450.0],
    ...                       rpm=np.linspace(90, 150, 5), pressure_scale=1.2)
    >>> len(grid), grid.shape
    (15, (3, 5))
    >>> grid.frame(0, 2)
       shaft_inertia    rpm  pressure_scale
    0          250.0   90.0             1.2
    1          250.0  105.0             1.2
    """

    KNOWN = MACHINE_COLUMNS
    COLUMN = "a machine column"
    GRID = "a machine grid"

    def __init__(self, machine: Machine, **axes: Any) -> None:
        self.machine = as_instance(machine, Machine, "machine")
        super().__init__(**axes)
        for index in self._checked_rows():
            frame = self.frame(index, index + 1)
            row_variant(self.machine, {str(k): v for k, v in frame.iloc[0].items()}, index)

    def _known(self) -> tuple[str, ...]:
        return machine_columns(self.machine)

    def _check_values(self, name: str, values: np.ndarray) -> None:
        check_values(name, values)

    def _checked_rows(self) -> list[int]:
        """The first row, the last, and for each axis the two rows that take it to its smallest
        and its largest value, the other axes at their first. Each value alone was checked by
        ``_check_values``; the rules between a machine's fields (λ = r/l < 1, the rod's centre
        of gravity on the rod, a positive inertia beside the shaft) are monotonic in each field,
        so an axis breaks one at an extreme if anywhere. (A machine built for every value of
        every axis cost about half a millisecond a value: 13 s for an axis of 20 000 speeds.)"""
        rows = {0, len(self) - 1}
        for axis, values in enumerate(self.axes.values()):
            for position in {int(np.argmin(values)), int(np.argmax(values))}:
                index = [0] * len(self.shape)
                index[axis] = position
                rows.add(int(np.ravel_multi_index(tuple(index), self.shape)))
        return sorted(rows)

    def __eq__(self, other: object) -> bool:
        equal = super().__eq__(other)
        if equal is NotImplemented or not equal:
            return equal
        assert isinstance(other, MachineGrid)
        return self.machine == other.machine

    def __repr__(self) -> str:
        axes = ", ".join(f"{name}: {len(values)}" for name, values in self.axes.items())
        designs = counted(len(self), "design")
        return f"MachineGrid({self.machine.name!r}, {designs}; axes {axes}; constants {self.constants})"
