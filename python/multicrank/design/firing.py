"""The firing orders a machine's crank allows, made distinct and ranked by δ with gravity
(:func:`firing_orders`).

A four-stroke machine's crank fixes each cylinder's phase only modulo 2π (its cam decides
whether it fires on this revolution or the next): 2^(k−1) phase assignments, once moving
every cylinder by 2π (the same motion, a revolution later) is set aside. A two-stroke
machine's phases are its crank: the arrangements of its throws' angles over its throws, each
throw keeping its cylinders (a V's banks their angle): (t − 1)! of them for a regular set of
t angles (turning the whole crank is the same motion, later), t! otherwise.

Two candidates run alike — the same motion, shifted by some angle s — when their gas
torques, their reduced inertia J(φ) and their gravity torque agree after the shift. The gas
torque of a cylinder is a function of (φ + α_j) mod Φ alone, for cylinders with the same
pressure, bore and crank (its *gas kind*), so the gas torques agree exactly when the
multisets of (gas kind, α_j mod Φ) do, up to the shift; J and the gravity torque are sums
over cylinders in which opposed masses can cancel (a boxer's), so they are compared as
functions, sampled, for each shift the gas allows.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from typing import Any

import numpy as np

from .._native import MechanismError
from .._validation import as_count, as_flag, as_instance, as_speed
from ..machine.machine import Machine
from ._crank import throws

__all__ = ["firing_orders"]

#: Angles are compared in ticks of a nanoradian: the layouts' phases are exact or within
#: 1e-13 rad of it, and a shift is a difference of phases.
_RESOLUTION = 1e-9
#: J and the gravity torque are compared at this many angles of a revolution, off any
#: symmetry of the crank (a prime count, started off zero).
_SAMPLES = 97
#: …and agree when they differ by less than this fraction of their swing (and of 1e-4 of
#: their cylinders' own swings, where those cancel).
_AGREE = 1e-8


def _gas_kinds(machine: Machine) -> list[int | None]:
    """Each cylinder's gas kind (alike pressures, bore and crank share one), None for a
    cylinder without gas."""
    kinds: list[int | None] = []
    known: list[tuple[Any, ...]] = []
    for cylinder in machine.cylinders:
        if cylinder.bore == 0 or (cylinder.pressure is None and cylinder.pressure_crank_end is None):
            kinds.append(None)
            continue
        key = (
            cylinder.pressure,
            cylinder.pressure_crank_end,
            cylinder.bore,
            cylinder.piston_rod_diameter,
            cylinder.crank_radius,
            cylinder.rod_length,
        )
        for index, other in enumerate(known):
            if other == key:
                kinds.append(index)
                break
        else:
            known.append(key)
            kinds.append(len(known) - 1)
    return kinds


def _kinds(machine: Machine) -> list[int]:
    """Each cylinder's kind: cylinders equal but for their phase share one."""
    known: list[Any] = []
    kinds = []
    for cylinder in machine.cylinders:
        template = cylinder.replace(phase=0.0)
        kinds.append(next((i for i, other in enumerate(known) if other == template), len(known)))
        if kinds[-1] == len(known):
            known.append(template)
    return kinds


def _arrangements(kinds: list[Any], fixed: bool) -> Iterator[tuple[Any, ...]]:
    """The distinct orders of the multiset ``kinds`` (its first element kept first where
    ``fixed``), in lexicographic order of their positions in ``sorted(set(kinds))``.

    itertools.permutations would give each order once per exchange of equal elements (11!
    orders of twelve alike throws for the one that exists); this is the classic
    next-permutation step, which visits each distinct order once.
    """
    labels = sorted(set(kinds))
    head = [labels.index(kinds[0])] if fixed else []
    rest = sorted(labels.index(k) for k in (kinds[1:] if fixed else kinds))
    while True:
        yield tuple(labels[i] for i in (*head, *rest))
        # The rightmost ascent, swapped with the rightmost larger element, the tail reversed.
        i = len(rest) - 2
        while i >= 0 and rest[i] >= rest[i + 1]:
            i -= 1
        if i < 0:
            return
        j = len(rest) - 1
        while rest[j] <= rest[i]:
            j -= 1
        rest[i], rest[j] = rest[j], rest[i]
        rest[i + 1 :] = reversed(rest[i + 1 :])


def _arrangement_count(kinds: list[Any], fixed: bool) -> int:
    """How many :func:`_arrangements` there are: a multinomial coefficient."""
    counted = kinds[1:] if fixed else kinds
    count = math.factorial(len(counted))
    for kind in set(counted):
        count //= math.factorial(counted.count(kind))
    return count


def _candidates(machine: Machine, limit: int) -> tuple[np.ndarray, int]:
    """The phase assignments [rad] the crank allows (at most ``limit`` rows, in a fixed
    order, the machine's own first), and how many there are."""
    phases = np.array([c.phase for c in machine.cylinders])
    k = phases.size
    if machine.strokes == 4:
        # Cylinder 0 keeps its phase: moving every cylinder by 2π is the same motion, later.
        total = 2 ** (k - 1)
        count = min(total, limit)
        moved = (np.arange(count)[:, None] >> np.arange(k - 1)[None, :]) & 1
        shifts = np.concatenate((np.zeros((count, 1)), moved), axis=1) * 2 * math.pi
        return np.mod(phases[None, :] + shifts, 4 * math.pi), total
    # Two strokes: a throw is its cylinders (their kinds, which hold their inclinations),
    # and alike throws are interchangeable.
    inclinations = np.array([c.inclination for c in machine.cylinders])
    members, angles = throws(machine)
    kinds = _kinds(machine)
    throw_kinds = [tuple(sorted(kinds[j] for j in cylinders)) for cylinders in members]
    spacing = np.diff(np.sort(angles), append=angles.min() + 2 * math.pi)
    # Turning a regular crank by its spacing maps it onto itself: the first throw keeps its
    # angle. Another set of angles is arranged every way.
    regular = bool(np.all(np.abs(spacing - 2 * math.pi / len(angles)) <= _RESOLUTION))
    total = _arrangement_count(throw_kinds, regular)
    found = []
    # The crank as it is first (each throw at its own angle), then every other arrangement.
    own = tuple(throw_kinds)
    others = (order for order in _arrangements(throw_kinds, regular) if order != own)
    for order in itertools.islice(itertools.chain([own], others), limit):
        # The i-th angle to the first throw of kind order[i] not yet placed.
        free = {kind: [t for t, its in enumerate(throw_kinds) if its == kind] for kind in set(throw_kinds)}
        pin = np.empty(k)
        for angle, kind in zip(angles, order, strict=True):
            pin[list(members[free[kind].pop(0)])] = angle
        found.append(np.mod(pin - inclinations, 2 * math.pi))
    return np.array(found), total


class _Motions:
    """Which candidates run alike: the gas compared exactly (multisets of phases relative to
    one gassed cylinder, in ticks), J and the gravity torque as sampled functions for each
    shift the gas allows."""

    def __init__(self, machine: Machine, phases: np.ndarray) -> None:
        self.machine = machine
        self.phases = np.mod(phases, machine.cycle)
        self.kinds = _gas_kinds(machine)
        self.gassed = [j for j, kind in enumerate(self.kinds) if kind is not None]
        self.period = round(machine.cycle / _RESOLUTION)
        self.phi = 2 * math.pi * (np.arange(_SAMPLES) + 0.37) / _SAMPLES
        self._curves: dict[tuple[int, ...], np.ndarray] = {}
        # The size of the cylinders' own terms, which opposed cylinders can cancel (a boxer's
        # gravity sums to rounding): the scale of the comparison's rounding.
        parts = [self._curves_of(machine.replace(cylinders=[c]), self.phi) for c in machine.cylinders]
        self.parts = np.sum([np.ptp(p, axis=1) for p in parts], axis=0)[:, None]

    def ticks(self, angles: np.ndarray, cycle: float) -> list[int]:
        """Angles [rad] modulo ``cycle``, in ticks (each rounded once)."""
        period = round(cycle / _RESOLUTION)
        return [int(t) % period for t in np.round(np.mod(angles, cycle) / _RESOLUTION)]

    def _gas(self, row: int, anchor: int) -> tuple[tuple[int | None, int], ...]:
        """The (gas kind, phase) multiset of candidate ``row``, phases less cylinder
        ``anchor``'s."""
        relative = self.ticks(self.phases[row, self.gassed] - self.phases[row, anchor], self.machine.cycle)
        return tuple(sorted(zip([self.kinds[j] for j in self.gassed], relative, strict=True)))

    def form(self, row: int) -> tuple[tuple[int | None, int], ...]:
        """The candidate's gas up to a shift: its least multiset relative to a gassed cylinder."""
        return min((self._gas(row, j) for j in self.gassed), default=())

    def _shifts(self, row: int, other: int) -> list[float]:
        """The shifts s [rad] with the gas of ``row`` at φ − s that of ``other`` at φ."""
        if not self.gassed:
            return list({float(a - b) for a in self.phases[row] for b in self.phases[other]})
        first = self.gassed[0]
        target = self._gas(other, first)
        return [
            float(self.phases[row, j] - self.phases[other, first])
            for j in self.gassed
            if self.kinds[j] == self.kinds[first] and self._gas(row, j) == target
        ]

    def _inertial(self, row: int, shift: float) -> np.ndarray:
        """J and the gravity torque of candidate ``row`` at φ − s, φ the sample angles (both
        2π-periodic: kept by the phases and the shift modulo a revolution)."""
        key = tuple(self.ticks(np.append(self.phases[row], shift), 2 * math.pi))
        if key not in self._curves:
            candidate = self.machine.replace(
                cylinders=[
                    c.replace(phase=float(a)) for c, a in zip(self.machine.cylinders, self.phases[row], strict=True)
                ]
            )
            self._curves[key] = self._curves_of(candidate, self.phi - shift)
        return self._curves[key]

    @staticmethod
    def _curves_of(machine: Machine, phi: np.ndarray) -> np.ndarray:
        return np.stack([machine.reduced_inertia(phi)[0], machine.gravity_torque(phi)])

    def alike(self, row: int, other: int) -> bool:
        """Whether candidates ``row`` and ``other`` run alike (``other`` is ``row`` shifted)."""
        reference = self._inertial(other, 0.0)
        tolerance = _AGREE * (np.ptp(reference, axis=1, keepdims=True) + 1e-4 * self.parts)
        return any(
            bool(np.all(np.abs(self._inertial(row, shift) - reference) <= tolerance))
            for shift in self._shifts(row, other)
        )


def _distinct(machine: Machine, phases: np.ndarray) -> list[int]:
    """The candidates (row indices, in order) that run unlike every earlier one."""
    motions = _Motions(machine, phases)
    kinds = _kinds(machine)
    machines: set[tuple[tuple[int, int], ...]] = set()
    buckets: dict[tuple[Any, ...], list[int]] = {}
    kept = []
    for row in range(len(phases)):
        # The same cylinders at the same phases, numbered otherwise: the same machine.
        same = tuple(sorted(zip(kinds, motions.ticks(phases[row], machine.cycle), strict=True)))
        if same in machines:
            continue
        machines.add(same)
        same_gas = buckets.setdefault(motions.form(row), [])
        if not any(motions.alike(row, other) for other in same_gas):
            same_gas.append(row)
            kept.append(row)
    return kept


def _firing_sequence(phases: np.ndarray, cycle: float) -> str:
    """The cylinders (numbered from 1) in the order they fire, from cylinder 1, those firing
    together joined by "+" (a cylinder fires at θ = (φ + α) mod Φ = 0, so at
    φ = (−α) mod Φ)."""
    period = round(cycle / _RESOLUTION)
    when = (np.round(np.mod(phases[0] - phases, cycle) / _RESOLUTION).astype(np.int64)) % period
    groups = ["+".join(str(int(j) + 1) for j in np.flatnonzero(when == instant)) for instant in np.unique(when)]
    return "-".join(groups)


def _largest_orders(machine: Machine, phases: np.ndarray, rpm: float, highest: int) -> tuple[np.ndarray, np.ndarray]:
    """The order 0 < ν ≤ ``highest`` of the largest total torque amplitude of each candidate
    (rows of ``phases``), and that amplitude [N·m].

    Every part of the torque (gas, inertia at the mean speed, gravity) is a sum over
    cylinders of a function of φ + α_j: each cylinder's orders are found once, at phase 0
    (:func:`~multicrank.torque_orders` of the cylinder alone), and moved to α_j by the shift
    theorem, c_ν → c_ν e^{iνα_j} with c_ν = a_ν − i b_ν.
    """
    from ..motion.orders import torque_orders

    total: np.ndarray | None = None
    for j, cylinder in enumerate(machine.cylinders):
        alone = machine.replace(cylinders=[cylinder.replace(phase=0.0)])
        orders = torque_orders(alone, rpm, max_order=highest)
        orders = orders[orders.index > 0]
        nu = orders.index.to_numpy()
        c = orders["total_cos"].to_numpy() - 1j * orders["total_sin"].to_numpy()
        moved = c[None, :] * np.exp(1j * nu[None, :] * phases[:, j : j + 1])
        total = moved if total is None else total + moved
    assert total is not None
    amplitude = np.abs(total)
    largest = np.argmax(amplitude, axis=1)
    return nu[largest], amplitude[np.arange(len(phases)), largest]


def firing_orders(
    machine: Machine,
    *,
    rpm: Any = None,
    max_order: Any = 12,
    max_candidates: Any = 100_000,
    progress: Any = False,
) -> Any:
    """The distinct firing orders a machine's crank allows, ranked by δ with gravity.

    Each candidate is the machine with other phases α_j; candidates that run alike (the same
    motion, shifted in φ) are one row. Every row's steady state ("balance" load, at ``rpm``)
    is solved by :func:`~multicrank.motion_sweep`, the candidates its designs (columns
    ``"phase[j]"``).

    Parameters
    ----------
    machine : Machine
        The machine: its cylinders, crank and pressures; its own phases are one candidate.
    rpm : float, optional
        The mean speed n [1/min] of the steady states; default the machine's own ``rpm``.
    max_order : int, default 12
        The highest torque order ν (per revolution) that ``largest_order`` considers.
    max_candidates : int, default 100000
        At most this many candidates are made (in a fixed order, the machine's own first);
        where the crank allows more, the table says so (``attrs["exhaustive"]`` False).
    progress : bool, default False
        Show a progress bar of the steady states.

    Returns
    -------
    pandas.DataFrame
        One row per distinct candidate, sorted by ``delta`` (stalled ones last): ``firing``
        (the cylinders, numbered from 1, in the order they fire from cylinder 1; "+" joins
        those that fire together), ``as_given`` (True for the one row that runs as the
        machine given), ``phases`` (α_j [rad], a tuple in the machine's cylinder order),
        ``delta``, ``delta_without_gravity`` and
        ``gravity_effect`` (δ/δ₀ − 1) of the steady state [dimensionless], ``stalled``,
        ``largest_order`` (the order 0 < ν ≤ max_order of the largest amplitude of the total
        torque — gas, inertia at the mean speed and gravity — on the shaft; half orders for
        four strokes) and ``largest_order_amplitude`` [N·m], and ``machine`` (the
        candidate's :class:`~multicrank.Machine`). ``attrs``: ``candidates`` (how many
        assignments the crank allows), ``distinct`` (the rows), ``exhaustive`` (whether
        every candidate was made) and ``rpm``.

    Raises
    ------
    MechanismError
        For bad input, naming the parameter.

    Notes
    -----
    A four-stroke crank fixes each phase modulo 2π: 2^(k−1) candidates once the common move
    by 2π is set aside. A two-stroke crank is its throws' angles: the (t − 1)! arrangements
    of a regular set of t throws (t! of another set). Two candidates run alike when their
    gas torques, J(φ) and gravity torques agree after a common shift of φ: the gas exactly,
    by the multiset of each cylinder's phase over the cycle and its pressure, bore and
    crank; J and gravity sampled at 97 angles, to 1e-8 of their swing.

    Examples
    --------
    >>> import multicrank as mc
    >>> engine = mc.presets.MACHINES["inline-4"]
    >>> table = mc.firing_orders(engine)
    >>> table.attrs["candidates"], table.attrs["distinct"]
    (8, 3)
    >>> table[["firing", "delta", "largest_order"]].round(4)  # the even firing runs smoothest
        firing   delta  largest_order
    0  1-4-3-2  0.0075            2.0
    1  1-2+4-3  0.0180            2.0
    2  1+3-2+4  0.0250            2.0
    """
    import pandas as pd

    from ..motion.sweep import motion_sweep

    machine = as_instance(machine, Machine, "machine")
    highest = as_count(max_order, "max_order", minimum=1)
    limit = as_count(max_candidates, "max_candidates", minimum=1)
    progress = as_flag(progress, "progress")
    if rpm is None and machine.rpm is None:
        raise MechanismError(f"rpm is required: machine {machine.name!r} has no rpm of its own")
    speed = as_speed(machine.rpm if rpm is None else rpm, "rpm")
    found, total = _candidates(machine, limit)
    kept = _distinct(machine, found)
    phases = found[kept]
    designs = pd.DataFrame({f"phase[{j}]": phases[:, j] for j in range(phases.shape[1])})
    designs["rpm"] = speed
    solved = motion_sweep(
        machine, designs, outputs=["delta", "delta_without_gravity", "gravity_effect"], progress=progress
    )
    largest, amplitude = _largest_orders(machine, phases, speed, highest)
    table = pd.DataFrame(
        {
            "firing": [_firing_sequence(p, machine.cycle) for p in phases],
            "as_given": [row == 0 for row in kept],  # candidate 0 is the machine's own phases
            "phases": [tuple(p.tolist()) for p in phases],
            "delta": solved["delta"].to_numpy(),
            "delta_without_gravity": solved["delta_without_gravity"].to_numpy(),
            "gravity_effect": solved["gravity_effect"].to_numpy(),
            "stalled": solved["stalled"].to_numpy(),
            "largest_order": largest,
            "largest_order_amplitude": amplitude,
            "machine": [
                machine.replace(
                    cylinders=[c.replace(phase=float(a)) for c, a in zip(machine.cylinders, p, strict=True)]
                )
                for p in phases
            ],
        }
    )
    table = table.sort_values("delta", na_position="last", kind="stable").reset_index(drop=True)
    table.attrs.update(candidates=total, distinct=len(table), exhaustive=len(found) == total, rpm=speed)
    return table
