"""The work of the gas forces, W(φ) = ∫₀^φ M_gas dφ [J], exact also for tabulated pressures.

The gas torque of unit j is F(θ_j)·s'(ψ_j) with ψ_j = φ + α_j and θ_j = ψ_j mod Φ, so its work
from φ = 0 is G(φ + α_j) − G(α_j), where G(x) = ∫₀^x F(θ) s'(θ) dθ is the indicator work of
that unit's cylinder alone, counted from its own outer dead centre (continued beyond one cycle
by G(x + Φ) = G(x) + G(Φ)). Units that differ only in phase, inclination and masses — every
cylinder of a usual machine — share one G.

G is integrated once per distinct cylinder on a rule of its own, cut at the cylinder's dead
centres and at *every* breakpoint of its pressure tables, with 4 Gauss points per table
interval: a pressure table interpolated piecewise (PCHIP, cubic spline, linear) is a
polynomial on each interval, so each panel's integrand is smooth and the rule is exact to
rounding for any table — at a cost that grows with the table, not with the number of
cylinders. Splitting the machine's own quadrature at every unit's table angles instead would
take a panel per table interval per unit (a 12-cylinder engine with 1441-point tables:
17 000 panels), and not splitting them leaves errors of ~1e-6 in the cycle's work.
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict
from typing import Any

import numpy as np

from .._validation import has_gas
from ..machine.cylinder import Cylinder
from ..machine.machine import Machine
from ..pressure.diagram import IndicatorDiagram
from ._quadrature import CycleQuadrature, cycle_breaks

__all__ = ["GasWork"]

#: Gauss points per panel and the widest panel [rad] for a cylinder with pressure tables
#: (each table interval is a panel or is split to this width) …
TABLE_ORDER, TABLE_WIDTH = 4, math.pi / 64
#: … and for one whose pressures are smooth callables (panels cut at the dead centres only).
SMOOTH_ORDER, SMOOTH_WIDTH = 12, math.pi / 16


#: How many cylinders' indicator works are kept (see _indicator).
CACHE_SIZE = 16
_cache: OrderedDict[tuple[Any, ...], _Indicator] = OrderedDict()
_cache_lock = threading.Lock()


class _Indicator:
    """G(x) = ∫₀^x F(θ) s'(θ) dθ of one cylinder at phase 0 [J], for any real x."""

    def __init__(self, cylinder: Cylinder, strokes: int) -> None:
        unit = Machine([cylinder.replace(phase=0.0)], shaft_inertia=1.0, strokes=strokes, g=0.0)
        tabulated = any(
            getattr(p, "breakpoints", None) is not None for p in (cylinder.pressure, cylinder.pressure_crank_end)
        )
        order, width = (TABLE_ORDER, TABLE_WIDTH) if tabulated else (SMOOTH_ORDER, SMOOTH_WIDTH)
        self.cycle = unit.cycle
        self.rule = CycleQuadrature(cycle_breaks(unit), order=order, max_width=width)
        torque = unit.gas_torque(self.rule.phi)
        _, at_edges, self.series = self.rule.antiderivative(torque)
        self.per_cycle = float(at_edges[-1])

    def __call__(self, x: np.ndarray) -> np.ndarray:
        turns = np.floor(x / self.cycle)
        return turns * self.per_cycle + self.series(x - turns * self.cycle)


def _indicator(cylinder: Cylinder, strokes: int) -> _Indicator:
    """G of a cylinder; kept for the CACHE_SIZE most recent cylinders whose pressures are
    :class:`~multicrank.pressure.IndicatorDiagram` (immutable: their tables are read-only), so
    that a sweep over speeds or flywheels integrates a table once. A user's callable may
    depend on state of its own, and is integrated every time."""
    pressures = (cylinder.pressure, cylinder.pressure_crank_end)
    if not all(p is None or isinstance(p, IndicatorDiagram) for p in pressures):
        return _Indicator(cylinder, strokes)
    # The diagrams themselves in the key (compared by identity): kept alive while cached.
    key = (*pressures, cylinder.bore, cylinder.piston_rod_diameter, cylinder.crank_radius, cylinder.rod_length, strokes)
    with _cache_lock:
        found = _cache.get(key)
        if found is not None:
            _cache.move_to_end(key)
            return found
    found = _Indicator(cylinder, strokes)
    with _cache_lock:
        _cache[key] = found
        while len(_cache) > CACHE_SIZE:
            _cache.popitem(last=False)
    return found


class GasWork:
    """W(φ) = ∫₀^φ M_gas dφ [J] of a machine, any φ (an array of any shape).

    Attributes
    ----------
    per_cycle : float
        W(Φ) [J], the indicated work of one cycle (the cycle mean of M_gas is per_cycle/Φ).
    """

    def __init__(self, machine: Machine) -> None:
        groups: dict[tuple[Any, ...], tuple[Cylinder, list[float]]] = {}
        for cylinder in machine.cylinders:
            if not has_gas(cylinder):
                continue
            key = (
                id(cylinder.pressure),
                id(cylinder.pressure_crank_end),
                cylinder.bore,
                cylinder.piston_rod_diameter,
                cylinder.crank_radius,
                cylinder.rod_length,
            )
            groups.setdefault(key, (cylinder, []))[1].append(cylinder.phase)
        self._groups = [(_indicator(c, machine.strokes), np.array(phases)) for c, phases in groups.values()]
        self._origin = sum(float(np.sum(g(phases))) for g, phases in self._groups)
        self.per_cycle = sum(g.per_cycle * phases.size for g, phases in self._groups)

    def __call__(self, phi: Any) -> np.ndarray:
        angles = np.asarray(phi, dtype=float)
        total = np.full(angles.shape, -self._origin)
        for g, phases in self._groups:
            shifted = angles.reshape(-1, 1) + phases[None, :]
            total += g(shifted.ravel()).reshape(shifted.shape).sum(axis=1).reshape(angles.shape)
        return total
