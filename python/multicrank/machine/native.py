"""A :class:`~multicrank.Machine` as the Rust core's steady state takes it: :func:`native_machine`,
the one place where a machine becomes a :class:`multicrank._native.MotionMachine` (its unit
columns, its gas as the indicator diagrams' SciPy ``PPoly`` arrays, I_w, the strokes and g),
converted and checked once and reused by every call.
"""

from __future__ import annotations

import threading
import weakref

import numpy as np

from .._native import MotionMachine
from .._validation import contiguous
from ..pressure.diagram import IndicatorDiagram
from .cylinder import unit_columns
from .machine import Machine

__all__ = ["motion_machine", "native_machine"]

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


#: The native machines made so far, by (id of the Machine, gravity kept): each made once and
#: kept while its Machine lives (a Machine is immutable), so that its cycle's tables, made by
#: the first steady state, serve every later one.
_MADE: dict[tuple[int, bool], MotionMachine | None] = {}
_MAKING = threading.Lock()


def motion_machine(machine: Machine, *, gravity: bool = True) -> MotionMachine | None:
    """The :class:`~multicrank._native.MotionMachine` of ``machine`` (with g = 0 where
    ``gravity`` is False), made on first use and kept while ``machine`` lives; None where a
    pressure is a Python callable (see :func:`native_machine`)."""
    key = (id(machine), gravity or machine.g == 0)
    known = _MADE.get(key, _MAKING)  # a lookup needs no lock; _MAKING marks "not made yet"
    if known is not _MAKING:
        return known  # type: ignore[return-value]
    made = native_machine(machine if key[1] else machine.replace(g=0.0))
    with _MAKING:
        if key not in _MADE:
            _MADE[key] = made
            weakref.finalize(machine, _MADE.pop, key, None)
        return _MADE[key]
