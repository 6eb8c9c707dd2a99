"""Quadrature over one working cycle, split where the torques have kinks: the panels of the
torque orders (:mod:`~multicrank.motion.orders`).

The machine's torques are smooth (analytic) in φ except where a gassed unit's pressure
changes branch — at its dead centres, where a cycle given as a function of θ alone switches
between expansion and compression — and at the breakpoints of a tabulated pressure. The
cycle [0, Φ] is cut at all of those, and each piece into panels no wider than
``max_width``; every panel carries ``order`` Gauss–Legendre nodes (numpy's ``leggauss``). On
such panels a smooth integrand converges spectrally, and a piecewise-smooth one as fast as
its pieces allow.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.polynomial.legendre as legendre

from .._validation import has_gas

__all__ = ["CycleQuadrature", "cycle_breaks"]

#: Gauss–Legendre nodes per panel.
DEFAULT_ORDER = 12
#: The widest panel [rad].
DEFAULT_MAX_WIDTH = math.pi / 8


def cycle_breaks(machine: Any) -> np.ndarray:
    """The angles φ in [0, Φ] where the machine's torques may have kinks, sorted, with 0 and Φ:
    every gassed unit's dead centres (ψ = φ + α ≡ 0 mod π) and its pressure tables'
    breakpoints (θ = (φ + α) mod Φ at a table angle)."""
    cycle = machine.cycle
    gassed = [c for c in machine.cylinders if has_gas(c)]
    centres = np.arange(0, round(cycle / math.pi) + 1) * math.pi
    phases = np.array([c.phase for c in gassed])
    breaks = [np.array([0.0, cycle]), np.mod(centres[None, :] - phases[:, None], cycle).ravel()]
    for cylinder in gassed:
        for pressure in (cylinder.pressure, cylinder.pressure_crank_end):
            table = getattr(pressure, "breakpoints", None)
            if table is not None:
                breaks.append(np.mod(np.asarray(table, dtype=float) - cylinder.phase, cycle))
    angles = np.unique(np.concatenate(breaks))
    # Breaks closer than this are one break: a sliver panel would only cost nodes.
    keep = np.concatenate([[True], np.diff(angles) > 1e-12 * cycle])
    angles = angles[keep]
    angles[-1] = cycle
    if angles[0] != 0.0:
        angles = np.concatenate([[0.0], angles])
    return angles


class CycleQuadrature:
    """Gauss–Legendre panels over [0, Φ] whose edges include ``breaks``.

    Attributes
    ----------
    edges : ndarray, shape (P + 1,)
        Panel edges [rad], from 0 to Φ.
    phi : ndarray, shape (P, order)
        The nodes [rad].
    weights : ndarray, shape (P, order)
        Quadrature weights [rad]: ``np.sum(weights * f)`` ≈ ∫₀^Φ f dφ.
    """

    def __init__(self, breaks: np.ndarray, *, order: int = DEFAULT_ORDER, max_width: float = DEFAULT_MAX_WIDTH):
        # Each piece between breaks in equal panels no wider than max_width (vectorised: a
        # table's breakpoints make thousands of pieces).
        widths = np.diff(breaks)
        counts = np.maximum(1, np.ceil(widths / max_width)).astype(np.int64)
        within = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
        inner = np.repeat(breaks[:-1], counts) + np.repeat(widths / counts, counts) * within
        self.edges = np.concatenate([inner, breaks[-1:]])
        x, w = legendre.leggauss(order)
        half = 0.5 * np.diff(self.edges)[:, None]
        middle = 0.5 * (self.edges[:-1] + self.edges[1:])[:, None]
        self.phi = middle + half * x[None, :]
        self.weights = half * w[None, :]

    @classmethod
    def of(cls, machine: Any, **options: Any) -> CycleQuadrature:
        """The panels of a machine's cycle, split at :func:`cycle_breaks`."""
        return cls(cycle_breaks(machine), **options)

    @property
    def cycle(self) -> float:
        return float(self.edges[-1])

    def integral(self, values: np.ndarray) -> float:
        """∫₀^Φ f dφ from f at the nodes (shape of ``phi``)."""
        return float(np.sum(self.weights * values))
