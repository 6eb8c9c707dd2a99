"""The textbook flywheel estimate (docs/theory.md, "The flywheel"): ΔE/(δω_m²) − mean(J − I_w),
ΔE the swing of the turning-moment diagram's energy at the mean speed — gas, gravity, the
balancing load *and* the inertia torque −½J′ω_m² — is exact to first order in δ.

The oracle for ΔE is this file's own integral of the machine's torques sampled densely
(``gas_torque``, ``gravity_torque``, ``inertia_torque`` at ω_m; Gauss–Legendre between every
unit's dead centres and pressure-table breakpoints, where they are smooth), not the library's
energy swing; the exact flywheel is checked by solving the steady state on it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import multicrank as mc

GAUSS_X, GAUSS_W = np.polynomial.legendre.leggauss(8)
MACHINES = ["inline-6", "inline-4", "marine-2t-twin"]


def smooth_pieces(machine: mc.Machine, finest: float = 2e-3) -> np.ndarray:
    """Edges in [0, Φ]: every unit's dead centres and table breakpoints (θ = φ + α), then split
    to at most ``finest`` rad."""
    cycle = machine.cycle
    angles = [np.array([0.0, cycle])]
    for unit in machine.cylinders:
        angles.append(np.mod(np.arange(0.0, cycle, math.pi) - unit.phase, cycle))
        for pressure in (unit.pressure, unit.pressure_crank_end):
            if pressure is not None:
                angles.append(np.mod(np.asarray(pressure.breakpoints) - unit.phase, cycle))
    edges = np.unique(np.concatenate(angles))
    edges = edges[np.concatenate([[True], np.diff(edges) > 1e-12])]
    counts = np.maximum(1, np.ceil(np.diff(edges) / finest).astype(int))
    return np.concatenate(
        [np.linspace(a, b, n + 1)[:-1] for a, b, n in zip(edges[:-1], edges[1:], counts, strict=True)] + [[cycle]]
    )


def turning_moment_swing(machine: mc.Machine, rpm: float) -> tuple[float, float]:
    """(ΔE [J], mean(J − I_w) [kg·m²]) at the constant speed ω_m of ``rpm``: the swing of
    ∫(M_gas + M_gravity + M_inertia − M_load) dφ, M_load the cycle mean of the gas torque."""
    omega = rpm * math.pi / 30
    edges = smooth_pieces(machine)
    half, middle = 0.5 * np.diff(edges), 0.5 * (edges[1:] + edges[:-1])
    nodes = middle[:, None] + half[:, None] * GAUSS_X[None, :]
    torque = machine.gas_torque(nodes) + machine.gravity_torque(nodes) + machine.inertia_torque(nodes, omega)
    work = half * (torque @ GAUSS_W)
    load = float(np.sum(half * (machine.gas_torque(nodes) @ GAUSS_W))) / machine.cycle
    # The energy at every edge; between edges the extremes are within ~(2e-3)² of them, and
    # refined below on the pieces beside the extreme edges.
    energy = np.concatenate([[0.0], np.cumsum(work - load * 2 * half)])

    def extreme(sign: float) -> float:
        i = int(np.argmax(sign * energy))
        best = sign * energy[i]
        for k in (i - 1, i):
            if 0 <= k < edges.size - 1:
                fine = np.linspace(edges[k], edges[k + 1], 2001)
                t = (
                    machine.gas_torque(fine) + machine.gravity_torque(fine) + machine.inertia_torque(fine, omega)
                ) - load
                # cumulative trapezoid from the piece's start, anchored at the Gauss value
                run = np.concatenate([[0.0], np.cumsum(0.5 * (t[1:] + t[:-1]) * np.diff(fine))])
                best = max(best, float(np.max(sign * (energy[k] + run))))
        return sign * best

    rest = machine.reduced_inertia(nodes)[0] - machine.shaft_inertia
    mean_rest = float(np.sum(half * (rest @ GAUSS_W))) / machine.cycle
    return extreme(1.0) - extreme(-1.0), mean_rest


@pytest.mark.parametrize("name", MACHINES)
def test_energy_swing_is_the_turning_moment_diagrams_inertia_torque_included(name):
    machine = mc.presets.MACHINES[name]
    rpm = machine.rpm
    swing, mean_rest = turning_moment_swing(machine, rpm)
    found = mc.flywheel_inertia(machine, delta=1e-3, rpm=rpm)
    assert found.energy_swing == pytest.approx(swing, rel=1e-7)
    omega = rpm * math.pi / 30
    assert found.textbook == pytest.approx(swing / (1e-3 * omega**2) - mean_rest, rel=1e-7)


@pytest.mark.parametrize("name", MACHINES)
def test_textbook_error_vanishes_like_delta(name):
    machine = mc.presets.MACHINES[name]
    errors = []
    for delta in (1e-3, 1e-4, 1e-5, 1e-6):
        found = mc.flywheel_inertia(machine, delta=delta, rpm=machine.rpm)
        # the exact flywheel is what it says
        exact = mc.steady_state(machine.replace(shaft_inertia=found.shaft_inertia), rpm=machine.rpm, points=2)
        assert exact.delta == pytest.approx(delta, rel=1e-6)
        errors.append(abs(found.textbook_error))
    # O(δ): within a modest multiple of δ, and ten times smaller per decade (until the
    # exact flywheel's own accuracy, ~1e-7, is reached).
    for delta, error in zip((1e-3, 1e-4, 1e-5, 1e-6), errors, strict=True):
        assert error <= 5 * delta + 1e-7
    assert errors[1] <= 0.2 * errors[0] + 1e-7 and errors[2] <= 0.2 * errors[1] + 1e-7
