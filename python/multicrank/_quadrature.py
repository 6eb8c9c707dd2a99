"""Quadrature over one working cycle, split where the torques have kinks.

The machine's torques are smooth (analytic) in φ except where a gassed unit's pressure
changes branch — at its dead centres, where a cycle given as a function of θ alone switches
between expansion and compression — and at the breakpoints of a tabulated pressure. The
cycle [0, Φ] is cut at all of those, and each piece into panels no wider than
``max_width``; every panel carries ``order`` Gauss–Legendre nodes. On such panels a smooth
integrand converges spectrally, and a piecewise-smooth one as fast as its pieces allow.

Why not scipy.integrate: quad is adaptive per integral, while the steady state needs the
*running* integral W(φ) = ∫₀^φ M dφ at every node, thousands of times inside a root find;
the panel rule gives that as one matrix product per evaluation (the Legendre interpolant of
each panel integrated exactly, numpy.polynomial), with the kinks placed on panel edges.
"""

from __future__ import annotations

import itertools
import math
from functools import cache
from typing import Any

import numpy as np
import numpy.polynomial.legendre as legendre

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
    breaks = [np.array([0.0, cycle])]
    for cylinder in machine.cylinders:
        pressures = [p for p in (cylinder.pressure, cylinder.pressure_crank_end) if p is not None]
        if cylinder.bore <= 0 or not pressures:
            continue
        alpha = cylinder.phase
        centres = np.arange(0, round(cycle / math.pi) + 1) * math.pi
        breaks.append(np.mod(centres - alpha, cycle))
        for pressure in pressures:
            table = getattr(pressure, "breakpoints", None)
            if table is not None:
                breaks.append(np.mod(np.asarray(table, dtype=float) - alpha, cycle))
    angles = np.unique(np.concatenate(breaks))
    # Breaks closer than this are one break: a sliver panel would only cost nodes.
    keep = np.concatenate([[True], np.diff(angles) > 1e-12 * cycle])
    angles = angles[keep]
    angles[-1] = cycle
    if angles[0] != 0.0:
        angles = np.concatenate([[0.0], angles])
    return angles


@cache
def _panel_rule(order: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes x and weights w on [−1, 1], and the matrix S with
    (S f)_i = ∫_{−1}^{x_i} p(t) dt for the polynomial p through (x_j, f_j)."""
    x, w = legendre.leggauss(order)
    to_coefficients = np.linalg.inv(legendre.legvander(x, order - 1))
    antiderivative = legendre.legint(np.eye(order), lbnd=-1, axis=0)
    running = legendre.legvander(x, order) @ antiderivative @ to_coefficients
    return x, w, running


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
        pieces = []
        for start, stop in itertools.pairwise(breaks):
            count = max(1, math.ceil((stop - start) / max_width))
            pieces.append(np.linspace(start, stop, count + 1)[:-1])
        self.edges = np.concatenate([*pieces, breaks[-1:]])
        x, self._unit_weights, self._running = _panel_rule(order)
        self.half = 0.5 * np.diff(self.edges)[:, None]
        middle = 0.5 * (self.edges[:-1] + self.edges[1:])[:, None]
        self.phi = middle + self.half * x[None, :]
        self.weights = self.half * self._unit_weights[None, :]

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

    def mean(self, values: np.ndarray) -> float:
        """(1/Φ) ∫₀^Φ f dφ."""
        return self.integral(values) / self.cycle

    def running(self, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The running integral F(φ) = ∫₀^φ f dφ: (F at the nodes, shape of ``phi``;
        F at the edges, shape (P + 1,), F(0) = 0 and F(Φ) the whole integral)."""
        panels = self.half[:, 0] * (values @ self._unit_weights)
        at_edges = np.concatenate([[0.0], np.cumsum(panels)])
        at_nodes = at_edges[:-1, None] + self.half * (values @ self._running.T)
        return at_nodes, at_edges
