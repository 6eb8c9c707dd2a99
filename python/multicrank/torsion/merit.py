"""Torsional merit of a machine's firing order: the classical phase-vector sums
(:func:`torsional_merit`).

A mode m of the shaft swings node i with the amplitude a_i (its shape). The work a cylinder's
torque does on the mode per cycle of order ν is proportional to the product of its order-ν
torque harmonic and the mode's amplitude at its node, so at a resonance — where the speed
makes ν·ω equal the mode's natural frequency — the mode is driven by

    E_ν = abs(Σ_j a_j T_ν,j),

T_ν,j the complex order-ν harmonic of cylinder j's own tangential torque (gas, inertia and
gravity). Cylinders alike but for their phase α_j have T_ν,j = T_ν e^{iνα_j} (the shift
theorem), so that E_ν = abs(T_ν)·abs(Σ_j a_j e^{iνθ_j}), θ_j = (−α_j) mod Φ the crank angle at
which cylinder j fires: the *phase-vector sum* of the order. Where every cylinder fires in
phase for an order (νθ_j equal modulo 2π) the order is *major*: its vectors add whatever the
mode shape does to their lengths. A V's two banks on one pin, Θ apart, fire Θ apart in crank
angle: their vectors for order ν make the angle νΘ, and the pair sums to abs(2 cos(νΘ/2))
times one cylinder's — the V-bank combination factor, which falls out of the phases here.

What it stops short of: damping, and the forced response it limits (the size of the
vibration at resonance, the stresses in the shaft). Hand the model to a torsional tool for
that (:func:`~multicrank.to_opentorsion`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import as_count, as_instance, as_rpm_range, omega_from_rpm, refused
from ..machine.machine import Machine
from ..machine.shaft import Shaft, shaft_of
from .excitation import CylinderOrders, cylinder_orders

__all__ = [
    "AT_RUNNING_SPEED",
    "MERIT_UNITS",
    "ON_NODE",
    "TorsionalCriteria",
    "firing_criteria",
    "mode_excitation",
    "speed_window",
    "torsional_merit",
]

#: Firing angles within this many radians (times the order) are in phase: the layouts'
#: phases are exact to ~1e-13 rad.
IN_PHASE = 1e-9
#: A cylinder whose amplitude in a mode is at most this fraction of the mode's largest over
#: all nodes sits on a node of the mode: it contributes exactly 0 (what an eigen solver gives
#: there is rounding, and rounding divided by rounding is no amplitude).
ON_NODE = 1e-9
#: A resonance within this fraction of the machine's own speed is at its running speed.
AT_RUNNING_SPEED = 0.05
#: Candidates whose excitations are computed at once (an array of this many × modes ×
#: cylinders × orders complex numbers).
_CHUNK = 1024
#: The columns of :func:`torsional_merit`, with their units.
MERIT_UNITS = {
    "mode": "",
    "order": "1/rev",
    "natural_frequency": "Hz",
    "resonance_rpm": "1/min",
    "vector_sum": "",
    "excitation": "N·m",
    "modal_excitation": "N·m/√(kg·m²)",
    "major": "",
    "at_running_speed": "",
}


def speed_window(machine: Machine, rpm: float) -> tuple[float, float]:
    """The speeds [1/min] whose resonances count against a firing order: the machine's
    ``rpm_range``, else from 0 up to ``rpm``."""
    return machine.rpm_range if machine.rpm_range is not None else (0.0, rpm)


def cylinder_amplitudes(shaft: Shaft, shapes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each mode's amplitude at each cylinder's node, (modes, cylinders) twice: scaled so that
    the largest magnitude over the cylinders' nodes is 1 (the classical relative amplitudes
    a_j), and mass-normalised (φ_j of the shape with φᵀJφ = 1 [1/√(kg·m²)]). A cylinder at
    most :data:`ON_NODE` of the mode's largest amplitude over all nodes is exactly 0 in both;
    a mode with every cylinder on a node has a_j = 0 for all."""
    shapes = np.asarray(shapes, dtype=float)  # (nodes, modes)
    norm = np.sqrt(np.einsum("n,nm,nm->m", np.asarray(shaft.inertia, dtype=float), shapes, shapes))
    at = shapes[list(shaft.cylinder_nodes), :].T
    at = np.where(np.abs(at) <= ON_NODE * np.abs(shapes).max(axis=0)[:, None], 0.0, at)
    largest = np.abs(at).max(axis=1, keepdims=True)
    relative = np.divide(at, largest, out=np.zeros_like(at), where=largest > 0)
    return relative, at / norm[:, None]


def firing_angles(phases: np.ndarray, cycle: float) -> np.ndarray:
    """θ_j = (−α_j) mod Φ [rad]: the crank angle at which each cylinder fires."""
    return np.mod(-np.asarray(phases, dtype=float), cycle)


def in_phase(theta: np.ndarray, orders: np.ndarray) -> np.ndarray:
    """Whether every cylinder fires in phase for each order (νθ_j the same angle modulo 2π, to
    rounding scaled by the order): the major orders, (…, orders) of θ (…, cylinders)."""
    turn = np.remainder(orders * (theta[..., :, None] - theta[..., :1, None]) + math.pi, 2 * math.pi) - math.pi
    return np.all(np.abs(turn) <= IN_PHASE * np.maximum(orders, 1.0), axis=-2)


def mode_excitation(
    harmonics: CylinderOrders, amplitude: np.ndarray, phases: np.ndarray, resonance: np.ndarray
) -> np.ndarray:
    """E = abs(Σ_j a_j T_ν,j) of each candidate (rows of ``phases``, (candidates, cylinders)
    [rad]), mode (rows of ``amplitude``, (modes, cylinders)) and order, the inertia torque at
    each mode's and order's ``resonance`` speed ((modes, orders) [1/min]): (candidates,
    modes, orders) [N·m] (times the amplitudes' unit)."""
    omega = omega_from_rpm(resonance)
    found = []
    for start in range(0, len(phases), _CHUNK):
        torque = harmonics.at(phases[start : start + _CHUNK, None, :], omega[None, :, :])  # (n, modes, j, orders)
        found.append(np.abs(np.einsum("mj,nmjo->nmo", amplitude, torque)))
    return np.concatenate(found) if found else np.zeros((0, *resonance.shape))


@dataclass(frozen=True)
class TorsionalCriteria:
    """The torsional criteria of candidates (:func:`firing_criteria`), one value per
    candidate: ``merit`` (the largest classical ``excitation`` of the first mode) and
    ``major``/``minor`` (the largest ``modal_excitation`` over every mode asked, of the
    major resp. minor orders) of the resonances in the speed range [N·m, N·m/√(kg·m²)], 0
    where none; and ``vector_sums`` (candidates, modes, orders), every order's."""

    merit: np.ndarray
    major: np.ndarray
    minor: np.ndarray
    vector_sums: np.ndarray


def firing_criteria(
    machine: Machine, shaft: Shaft, phases: np.ndarray, highest: int, speeds: tuple[float, float], modes: int
) -> TorsionalCriteria:
    """The :class:`TorsionalCriteria` of each candidate (rows of ``phases`` [rad]) on the
    shaft's lowest ``modes`` elastic modes (at most its nodes − 1), orders up to ``highest``,
    resonances whose speed lies in ``speeds`` (low, high) [1/min], ends included."""
    count = min(modes, len(shaft.inertia) - 1)
    found = shaft.modes(count)
    relative, modal = cylinder_amplitudes(shaft, found.shapes[:, :count])
    harmonics = cylinder_orders(machine, highest)
    orders = harmonics.orders
    resonance = 60.0 * found.natural_frequency[:count, None] / orders[None, :]  # (modes, orders)
    inside = (resonance >= speeds[0]) & (resonance <= speeds[1])
    theta = firing_angles(phases, machine.cycle)
    vectors = np.exp(1j * orders * theta[:, :, None])  # (candidates, cylinders, orders)
    vector_sums = np.abs(np.einsum("mj,njo->nmo", relative, vectors))
    none = np.zeros(len(phases))
    if not inside.any():
        return TorsionalCriteria(none, none, none, vector_sums)
    used = inside.any(axis=0)  # the orders that resonate in some mode
    chosen = harmonics.only(used)
    modal_excitation = mode_excitation(chosen, modal, phases, resonance[:, used])
    counted = inside[None, :, used]
    major = in_phase(theta, orders[used])[:, None, :]  # (candidates, 1, orders)

    def largest(mask: np.ndarray) -> np.ndarray:
        return np.where(mask, modal_excitation, 0.0).max(axis=(1, 2))

    first = inside[0, used]
    merit = none
    if first.any():
        classical = mode_excitation(chosen.only(first), relative[:1], phases, resonance[:1, used][:, first])
        merit = classical[:, 0, :].max(axis=1)
    return TorsionalCriteria(merit, largest(counted & major), largest(counted & ~major), vector_sums)


def torsional_merit(
    machine: Machine,
    shaft: Any = None,
    *,
    modes: Any = 2,
    max_order: Any = 12,
    rpm_range: Any = None,
) -> Any:
    """The excitation of the shaft's torsional modes by each order of the machine's firing.

    Parameters
    ----------
    machine : Machine
        The machine: its cylinders' phases (the firing order), pressures, masses and crank.
    shaft : Shaft, optional
        The shaft as a torsional chain; default the machine's own (``Machine.shaft``).
    modes : int, default 2
        How many elastic modes, from the lowest (mode 1), ≥ 1 and at most nodes − 1.
    max_order : int, default 12
        The highest order ν [per revolution]; every order from 1 (½ for a four-stroke
        machine) in steps of 1 (½) up to it.
    rpm_range : (float, float), optional
        Keep only the rows whose resonance speed lies in (low, high) [1/min], ends included;
        default every row.

    Returns
    -------
    pandas.DataFrame
        One row per (mode, order), by mode then order: ``mode`` (1 = the first elastic
        mode), ``order`` ν [1/rev], ``natural_frequency`` f [Hz], ``resonance_rpm`` = 60 f/ν
        [1/min] (where order ν meets the mode), ``vector_sum`` abs(Σ_j a_j e^{iνθ_j})
        [dimensionless], ``excitation`` abs(Σ_j a_j T_ν,j) [N·m], ``modal_excitation``
        abs(Σ_j φ_j T_ν,j) [N·m/√(kg·m²)], ``major`` (every cylinder fires in phase for that
        order) and ``at_running_speed`` (the resonance lies within ±5 % of the machine's own
        ``rpm``: the machine runs on it; False without an ``rpm``). a_j is the mode's
        amplitude at cylinder j's node, scaled so that the largest magnitude over the
        cylinders' nodes is 1 (a lone cylinder has a_j = 1 wherever it sits): the classical
        relative amplitudes, which compare firing orders within one mode. φ_j is the same
        amplitude of the mass-normalised shape (φᵀJφ = 1), so that ``modal_excitation``
        compares modes too: at resonance the mode's modal amplitude is modal_excitation /
        (2 ζ ω_m²) for a modal damping ratio ζ. A cylinder whose amplitude is at most 1e-9
        of the mode's largest over all nodes sits on a node of it and counts exactly 0.
        θ_j = (−α_j) mod Φ is cylinder j's firing angle; T_ν,j the complex order-ν harmonic
        of its own tangential torque — gas, gravity and inertia, the inertia torque taken
        at the row's ``resonance_rpm`` (and the gas too, by the machine's ``load_law``).
        ``attrs``: ``units``, ``machine`` (its name), ``strokes``.

    Raises
    ------
    MechanismError
        For bad input, naming the parameter; for a machine without a shaft when none is given.

    Notes
    -----
    This is the classical method of the phase-vector sums (docs/theory.md,
    "Torsional merit of a firing order"): a mode is driven at resonance by the work its
    order's torques do on it, which grows with E_ν. It ranks firing orders and tells major
    orders from minor ones; it does not give the size of the vibration, which damping
    limits — hand the model to openTorsion (:func:`~multicrank.to_opentorsion`) for the
    forced response. The node inertias are used as given: add each cylinder's running gear
    to its node.

    Examples
    --------
    An in-line four on a shaft of five nodes (four throws and a flywheel): its second order
    (two firings per revolution) is major; its first mode's 2nd-order vector sum is the sum
    of the four throws' amplitudes.

    >>> import multicrank as mc
    >>> engine = mc.presets.MACHINES["inline-4"]
    >>> shaft = mc.Shaft([0.02, 0.02, 0.02, 0.02, 0.3], [3e5, 3e5, 3e5, 4e5],
    ...                  cylinder_nodes=[0, 1, 2, 3])
    >>> merit = mc.torsional_merit(engine, shaft, modes=1, max_order=4)
    >>> merit[["order", "resonance_rpm", "vector_sum", "major"]].round(1)
       order  resonance_rpm  vector_sum  major
    0    0.5        30021.6         0.9  False
    1    1.0        15010.8         0.2  False
    2    1.5        10007.2         0.9  False
    3    2.0         7505.4         2.5   True
    4    2.5         6004.3         0.9  False
    5    3.0         5003.6         0.2  False
    6    3.5         4288.8         0.9  False
    7    4.0         3752.7         2.5   True
    """
    import pandas as pd

    machine = as_instance(machine, Machine, "machine")
    chosen = shaft_of(machine, shaft)
    elastic = len(chosen.inertia) - 1
    count = as_count(modes, "modes", minimum=1)
    if count > elastic:
        raise refused(
            "modes", f"modes = {count} is out of range; allowed: 1 <= modes <= {elastic} (the shaft's nodes − 1)"
        )
    highest = as_count(max_order, "max_order", minimum=1)
    window = None if rpm_range is None else as_rpm_range(rpm_range)

    found = chosen.modes(count)
    frequency = found.natural_frequency[:count]
    relative, modal = cylinder_amplitudes(chosen, found.shapes[:, :count])  # (modes, cylinders)
    harmonics = cylinder_orders(machine, highest)
    orders = harmonics.orders
    phases = np.array([c.phase for c in machine.cylinders])
    theta = firing_angles(phases, machine.cycle)
    resonance = 60.0 * frequency[:, None] / orders[None, :]  # (modes, orders) [1/min]
    vectors = np.exp(1j * orders[:, None] * theta[None, :])  # (orders, cylinders)
    vector_sum = np.abs(relative @ vectors.T)  # (modes, orders)
    excitation = mode_excitation(harmonics, relative, phases[None, :], resonance)[0]
    modal_excitation = mode_excitation(harmonics, modal, phases[None, :], resonance)[0]
    major = in_phase(theta, orders)
    rated = machine.rpm
    at_running = np.zeros(resonance.shape, dtype=bool)
    if rated is not None:
        at_running = np.abs(resonance - rated) <= AT_RUNNING_SPEED * rated

    table = pd.DataFrame(
        {
            "mode": np.repeat(np.arange(1, count + 1), orders.size),
            "order": np.tile(orders, count),
            "natural_frequency": np.repeat(frequency, orders.size),
            "resonance_rpm": resonance.ravel(),
            "vector_sum": vector_sum.ravel(),
            "excitation": excitation.ravel(),
            "modal_excitation": modal_excitation.ravel(),
            "major": np.tile(major, count),
            "at_running_speed": at_running.ravel(),
        }
    )
    if window is not None:
        low, high = window
        table = table[(table["resonance_rpm"] >= low) & (table["resonance_rpm"] <= high)].reset_index(drop=True)
    table.attrs.update(units=dict(MERIT_UNITS), machine=machine.name, strokes=machine.strokes)
    return table
