"""A :class:`~multicrank.Machine` as the Rust core's steady state takes it: :func:`native_machine`,
the one place where a machine becomes a :class:`multicrank._native.MotionMachine` (its unit
columns, its gas as the indicator diagrams' SciPy ``PPoly`` arrays, I_w, the strokes and g),
converted and checked once and reused by every call.
"""

from __future__ import annotations

import numpy as np

from .._native import MotionMachine
from .._validation import contiguous
from ..pressure.diagram import IndicatorDiagram
from .cylinder import unit_columns
from .machine import Machine

__all__ = ["native_machine"]

_Table = tuple[np.ndarray, np.ndarray] | None


def _table(pressure: object) -> _Table:
    """A cylinder end's pressure as the (x, c) arrays of the ``PPoly`` the diagram evaluates."""
    assert isinstance(pressure, IndicatorDiagram)
    poly = pressure._poly  # the interpolant itself (pressure/diagram.py): the very same doubles
    c = np.asarray(poly.c, dtype=np.float64)
    return contiguous(poly.x), contiguous(c.reshape(c.shape[0], c.shape[1]))


def native_machine(machine: Machine) -> MotionMachine | None:
    """``machine`` as the core's :class:`~multicrank._native.MotionMachine`.

    Parameters
    ----------
    machine : Machine
        Any machine.

    Returns
    -------
    MotionMachine or None
        None where a cylinder's pressure (either end) is not an
        :class:`~multicrank.IndicatorDiagram`: only tables cross to Rust, a Python callable
        stays with the Python implementation.

    Raises
    ------
    MechanismError
        Where the core refuses the machine, naming the parameter.
    """
    ends: dict[str, list[_Table]] = {"pressure": [], "pressure_crank_end": []}
    for cylinder in machine.cylinders:
        for end, tables in ends.items():
            pressure = getattr(cylinder, end)
            if pressure is None:
                tables.append(None)
            elif isinstance(pressure, IndicatorDiagram):
                tables.append(_table(pressure))
            else:
                return None
    return MotionMachine(
        unit_columns(machine.cylinders),
        contiguous(np.array([c.bore for c in machine.cylinders], dtype=float)),
        contiguous(np.array([c.piston_rod_diameter for c in machine.cylinders], dtype=float)),
        ends["pressure"],
        ends["pressure_crank_end"],
        shaft_inertia=machine.shaft_inertia,
        strokes=machine.strokes,
        g=machine.g,
    )
