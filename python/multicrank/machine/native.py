"""A :class:`~multicrank.Machine` as the Rust core's steady state takes it: :func:`native_machine`,
the one place where a machine becomes a :class:`multicrank._native.NativeMachine` (its unit
columns, its gas as piecewise polynomials in SciPy's ``PPoly`` layout, I_w, the strokes, g, the
cylinders' axial positions and the main bearings), converted and checked once by the core and
reused by every call: its gravity, kinematics and torques, its motion, its frame's forces.

An :class:`~multicrank.IndicatorDiagram` crosses as its own interpolant. Any other pressure
callable p(θ) is evaluated once on a fixed grid of θ over the working cycle (:func:`sampled`:
panels at most π/16 wide, cut at the dead centres, with 12 Gauss–Legendre nodes each) and
crosses as the polynomial of degree 11 through its values on each panel: for a smooth
pressure that interpolant is the pressure to rounding (the error of a degree-11 interpolant on
a π/16 panel, ~(π/32)¹²/12! times the twelfth derivative), and the core integrates its work
exactly. A pressure with a kink inside a panel is smoothed there, as any quadrature of it is.
A callable drive under the "balance" load, held at the mean speed, crosses the same way
(checked as a torque [N·m] named ``drive``), for the call that gives it.
"""

from __future__ import annotations

import math
import operator
import threading
from functools import cache
from typing import TYPE_CHECKING, Any

import numpy as np

from .._native import NativeMachine
from .._validation import contiguous
from ..pressure.diagram import IndicatorDiagram
from .cylinder import unit_columns
from .gas import _pressure

if TYPE_CHECKING:  # a Machine asks this module for its native machine (Machine._core)
    from .machine import Machine

__all__ = ["SAMPLED_ORDER", "SAMPLED_WIDTH", "motion_machine", "native_machine", "sampled"]

_Table = tuple[np.ndarray, np.ndarray] | None

#: The grid a pressure callable is sampled on: Gauss–Legendre nodes per panel (the degree of
#: its interpolant plus one) and the widest panel [rad].
SAMPLED_ORDER, SAMPLED_WIDTH = 8, math.pi / 256


@cache
def _legendre_to_monomials(order: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The Gauss–Legendre nodes on [0, 1], the map from values there to the Legendre
    coefficients of their interpolant (exact: Gauss quadrature of degree 2·order − 1), and the
    monomial coefficients in t ∈ [0, 1] of the shifted Legendre polynomials P_n(2t − 1),
    integers (−1)^(n+k) C(n, k) C(n+k, k), exact in doubles for these orders."""
    x, w = np.polynomial.legendre.leggauss(order)
    n = np.arange(order)
    legendre = np.polynomial.legendre.legvander(x, order - 1)  # P_n(x_i), (nodes, n)
    to_legendre = (legendre * w[:, None]).T * ((2 * n + 1) / 2)[:, None]  # (n, nodes)
    shifted = np.zeros((order, order))  # (k, n)
    for degree in range(order):
        for k in range(degree + 1):
            shifted[k, degree] = (-1) ** (degree + k) * math.comb(degree, k) * math.comb(degree + k, k)
    return (x + 1) / 2, to_legendre, shifted


def sampled(
    function: Any, cycle: float, name: str = "pressure", quantity: str = "pressure", unit: str = "Pa"
) -> tuple[np.ndarray, np.ndarray]:
    """A callable f(θ) of the crank angle — a pressure p(θ) [Pa], or any periodic ``quantity``
    in ``unit`` (a driving torque [N·m]) — as the (x, c) arrays of a ``PPoly`` over [0, Φ]
    (``cycle``): its values at :data:`SAMPLED_ORDER` Gauss–Legendre nodes on every panel (at
    most :data:`SAMPLED_WIDTH` wide, cut at multiples of π, the dead centres), one call for all
    of them, and on each panel the polynomial through them. A callable that names the angles of
    its kinks (a ``breakpoints`` attribute [rad], over its own ``cycle`` where it has one, as a
    wrapped :class:`~multicrank.IndicatorDiagram` does) is cut there too, so that each panel
    holds one smooth piece. ``name`` names the callable in the error of one that fails or
    returns bad values (not real, not finite, a wrong shape)."""
    turns = round(cycle / math.pi)
    per_turn = math.ceil(math.pi / SAMPLED_WIDTH - 1e-9)
    x = np.linspace(0.0, cycle, turns * per_turn + 1)
    x[::per_turn] = np.arange(turns + 1) * math.pi  # the dead centres exactly
    x = _cut_at_kinks(x, function, cycle)
    nodes, to_legendre, shifted = _legendre_to_monomials(SAMPLED_ORDER)
    width = np.diff(x)
    theta = x[:-1, None] + width[:, None] * nodes[None, :]  # (panels, nodes)
    values = _pressure(function, theta, name, quantity, unit)
    # Legendre coefficients first (stable), then monomials in t = (θ − x_i)/h, then in θ − x_i.
    monomials = (values @ to_legendre.T) @ shifted.T  # (panels, k)
    monomials /= width[:, None] ** np.arange(SAMPLED_ORDER)[None, :]
    return contiguous(x), contiguous(monomials[:, ::-1].T)


def _cut_at_kinks(x: np.ndarray, function: Any, cycle: float) -> np.ndarray:
    """The panel edges ``x`` with the callable's ``breakpoints`` (repeated over [0, Φ] by its
    own ``cycle``, where shorter) added; a kink closer than 1e-9 rad to an edge moves nothing
    (a sliver panel would only cost nodes). The edges already there, the dead centres among
    them, are kept exactly."""
    kinks = getattr(function, "breakpoints", None)
    if kinks is None:
        return x
    kinks = np.asarray(kinks, dtype=float).ravel()
    period = getattr(function, "cycle", None)
    period = cycle if not isinstance(period, float) or not 0 < period <= cycle else period
    repeats = np.arange(round(cycle / period))[:, None] * period
    kinks = np.unique(np.mod(kinks[None, :] + repeats, cycle))
    near = np.abs(kinks[:, None] - x[None, :]).min(axis=1) < 1e-9
    return np.union1d(x, kinks[~near])


def _table(pressure: object, cycle: float) -> _Table:
    """A cylinder end's pressure as the (x, c) arrays of the ``PPoly`` the diagram evaluates,
    over the machine's working cycle ``cycle`` [rad]: a diagram of a shorter cycle (a
    compressor's 2π on a four-stroke machine) repeated until it spans it, the same pieces."""
    assert isinstance(pressure, IndicatorDiagram)
    poly = pressure._poly  # the interpolant itself (pressure/diagram.py): the very same doubles
    c = np.asarray(poly.c, dtype=np.float64)
    x, c = np.asarray(poly.x, dtype=np.float64), c.reshape(c.shape[0], c.shape[1])
    repeats = round(cycle / pressure.cycle)
    if repeats > 1:
        x = np.concatenate([x[:-1] + k * pressure.cycle for k in range(repeats)] + [[cycle]])
        c = np.tile(c, (1, repeats))
    return contiguous(x), contiguous(c)


_gas_row = operator.attrgetter("bore", "piston_rod_diameter", "axial_position")


def native_machine(machine: Machine) -> NativeMachine:
    """``machine`` as the core's :class:`~multicrank._native.NativeMachine`.

    Parameters
    ----------
    machine : Machine
        Any machine.

    Returns
    -------
    NativeMachine
        The core's machine; a pressure that is not an :class:`~multicrank.IndicatorDiagram`
        crosses sampled (:func:`sampled`), each callable evaluated once.

    Raises
    ------
    MechanismError
        Where the core refuses the machine, naming the parameter.
    """
    ends: dict[str, list[_Table]] = {"pressure": [], "pressure_crank_end": []}
    # By id of the pressure: each diagram laid out (or callable sampled) once, and the core
    # converts and checks each distinct pair of arrays once (a V12's twelve cylinders of one
    # diagram cross as one).
    tables_of: dict[int, _Table] = {}
    for cylinder in machine.cylinders:
        for end, tables in ends.items():
            pressure = getattr(cylinder, end)
            if pressure is None:
                tables.append(None)
                continue
            if id(pressure) not in tables_of:
                if isinstance(pressure, IndicatorDiagram):
                    tables_of[id(pressure)] = _table(pressure, machine.cycle)
                else:
                    tables_of[id(pressure)] = sampled(pressure, machine.cycle, end)
            tables.append(tables_of[id(pressure)])
    bearings = machine.main_bearings
    # New arrays of Python floats: C-contiguous and aligned as made.
    bore, rod, axial = np.array([_gas_row(c) for c in machine.cylinders], dtype=np.float64).T.copy()
    return NativeMachine(
        unit_columns(machine.cylinders),
        bore,
        rod,
        ends["pressure"],
        ends["pressure_crank_end"],
        shaft_inertia=machine.shaft_inertia,
        strokes=machine.strokes,
        g=machine.g,
        axial_position=axial,
        main_bearings=None if bearings is None else contiguous(np.array(bearings, dtype=float)),
    )


def motion_machine(machine: Machine) -> NativeMachine:
    """The :class:`~multicrank._native.NativeMachine` of ``machine``, owned by it: made on
    first use (a pressure callable is sampled then, once: see :func:`native_machine`) and kept
    on the machine (``Machine._native``, left out of its pickle, its equality and
    :meth:`~multicrank.Machine.replace`), so that its cycle's tables, made by the first steady
    state, serve every later question, with gravity or without (each method's ``gravity``
    flag). Two threads asking at once get one native machine, made once."""
    made = machine.__dict__.get("_native")
    if made is not None:
        return made
    # dict.setdefault is atomic: every thread gets the one lock of this machine.
    with machine.__dict__.setdefault("_native_lock", threading.Lock()):
        made = machine.__dict__.get("_native")
        if made is None:
            made = machine.__dict__["_native"] = native_machine(machine)
        return made
