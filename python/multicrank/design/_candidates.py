"""The candidates of :func:`~multicrank.firing_orders`: the phase assignments a machine's crank
allows (:func:`_candidates`) and which of them run alike on a rigid shaft (:func:`_groups`, by
one hashable signature per candidate, :class:`_Signatures`). The module :mod:`.firing` says
how both work."""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from typing import Any

import numpy as np

from .._validation import has_gas
from ..machine.machine import Machine
from ._crank import throws

__all__ = ["_candidates", "_groups"]

#: Angles are compared in ticks of a nanoradian: the layouts' phases are exact or within
#: 1e-13 rad of it, and a shift is a difference of phases.
_RESOLUTION = 1e-9
#: J and the gravity torque are compared by their Fourier orders 1 … _HARMONICS (a crank's
#: terms fall off as λⁿ: order 48 is far below the rounding below for any real crank) …
_HARMONICS = 48
#: … the frame of the least signature chosen by the first few where they decide …
_FIRST_ORDERS = 4
#: … found from this many samples of a revolution of each cylinder's own terms …
_FFT_POINTS = 256
#: … and agree when they round alike in steps of this fraction of the cylinders' own swings
#: summed (the scale of what a cancelling sum — a boxer's gravity — leaves).
_AGREE = 1e-8


def _gas_kinds(machine: Machine) -> list[int | None]:
    """Each cylinder's gas kind (alike pressures, bore and crank share one), None for a
    cylinder without gas."""
    kinds: list[int | None] = []
    known: list[tuple[Any, ...]] = []
    for cylinder in machine.cylinders:
        if not has_gas(cylinder):
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
    """Each cylinder's kind: cylinders equal but for their phase share one (and but for their
    place along the shaft, which changes no torque, so not δ either)."""
    known: list[Any] = []
    kinds = []
    for cylinder in machine.cylinders:
        template = cylinder.replace(phase=0.0, axial_position=0.0)
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
    # Alike throws at other places along the shaft are not interchangeable: the frame's moments,
    # the bearings' loads and the shaft's modes tell which angle sits where. Where the machine
    # is placed each throw's place is part of its kind; unplaced, alike throws are one.
    place = machine.throw_index
    placed = len(machine.throws) > 1
    throw_kinds = [
        (*sorted(kinds[j] for j in cylinders), *((-1 - place[cylinders[0]],) if placed else ()))
        for cylinders in members
    ]
    spacing = np.diff(np.sort(angles), append=angles.min() + 2 * math.pi)
    # Turning a regular crank by its spacing maps it onto itself: the first throw keeps its
    # angle. Another set of angles is arranged every way.
    regular = bool(np.all(np.abs(spacing - 2 * math.pi / len(angles)) <= _RESOLUTION))
    total = _arrangement_count(throw_kinds, regular)
    # The crank as it is first (each throw at its own angle), then every other arrangement.
    own = tuple(throw_kinds)
    others = (order for order in _arrangements(throw_kinds, regular) if order != own)
    labels = sorted(set(throw_kinds))
    code = {kind: i for i, kind in enumerate(labels)}
    orders = np.array(
        [[code[kind] for kind in order] for order in itertools.islice(itertools.chain([own], others), limit)]
    )
    # The i-th angle goes to the first throw of kind orders[:, i] not yet placed: the
    # (number of that kind before it)-th throw of that kind.
    throw = np.empty_like(orders)
    for label, kind in enumerate(labels):
        mask = orders == label
        of_kind = np.array([t for t, its in enumerate(throw_kinds) if its == kind])
        throw[mask] = of_kind[(np.cumsum(mask, axis=1) - 1)[mask]]
    pin = np.empty(orders.shape)
    pin[np.arange(len(orders))[:, None], throw] = angles[None, :]
    cylinder_throw = np.empty(k, dtype=np.int64)
    for t, cylinders in enumerate(members):
        cylinder_throw[list(cylinders)] = t
    return np.mod(pin[:, cylinder_throw] - inclinations, 2 * math.pi), total


class _Signatures:
    """A hashable signature of each candidate's motion, equal for candidates that run alike
    (the same motion, shifted in φ).

    The gas: each gassed cylinder's (gas kind, phase), the phases taken relative to one gassed
    cylinder (the *anchor*), in ticks of :data:`_RESOLUTION` modulo the cycle, as a sorted
    multiset; the anchors that give the least multiset are the shifts the gas allows. J(φ)
    and the gravity torque: each is a sum over cylinders of the cylinder's own term at
    φ + α_j (opposed masses may cancel in the sum: a boxer's gravity), so its Fourier
    coefficients are the terms' coefficients moved by the shift theorem, c_n e^{inα_j},
    summed; in an anchor's frame (φ from the anchor's phase) they are multiplied by
    e^{−inα_anchor}. Orders 1 … :data:`_HARMONICS` of both, rounded to :data:`_AGREE` of the
    cylinders' own swings, in the allowed anchor's frame that gives the least, are the rest
    of the signature. Two candidates get one signature when some shift maps one's gas onto
    the other's and their J and gravity agree after it, to that rounding. The work is linear
    in the number of candidates (signed in blocks, then one set look-up each), not pairwise.
    """

    #: Candidates signed at once (a block's arrays are some tens of MB).
    BLOCK = 1024

    def __init__(self, machine: Machine) -> None:
        self.machine = machine
        gas = _gas_kinds(machine)
        self.gassed = np.array([j for j, kind in enumerate(gas) if kind is not None], dtype=np.int64)
        self.gas_kind = np.array([-1 if kind is None else kind for kind in gas], dtype=np.int64)
        self.period = round(machine.cycle / _RESOLUTION)
        self.order = np.arange(1, _HARMONICS + 1)
        # Each cylinder's J and gravity torque alone at phase 0, over a revolution, and their
        # Fourier coefficients c_n (f = Σ c_n e^{inφ}); alike cylinders share them.
        phi = 2 * math.pi * np.arange(_FFT_POINTS) / _FFT_POINTS
        terms: dict[Any, np.ndarray] = {}
        coefficients, parts = [], np.zeros(2)
        for cylinder in machine.cylinders:
            template = cylinder.replace(phase=0.0, axial_position=0.0)  # its place moves no torque
            if template not in terms:
                alone = machine.replace(cylinders=[template], main_bearings=None, shaft=None)
                terms[template] = np.stack([alone.reduced_inertia(phi)[0], alone.gravity_torque(phi)])
            coefficients.append(np.fft.rfft(terms[template], axis=1)[:, 1 : _HARMONICS + 1] / _FFT_POINTS)
            parts += np.ptp(terms[template], axis=1)
        self.coefficients = np.array(coefficients)  # (cylinders, 2, harmonics)
        # The rounding's scale: the cylinders' own swings, which a sum may cancel.
        self.step = (_AGREE * np.where(parts > 0, parts, 1.0))[:, None]

    @staticmethod
    def _least(values: np.ndarray, allowed: np.ndarray) -> np.ndarray:
        """Of each row's anchors (axis 1) still ``allowed``, those whose vector (axis 2) is
        lexicographically least."""
        allowed = allowed.copy()
        for column in range(values.shape[2]):
            entry = values[:, :, column]
            least = np.where(allowed, entry, np.iinfo(np.int64).max).min(axis=1, keepdims=True)
            allowed &= entry == least
        return allowed

    def __call__(self, phases: np.ndarray) -> list[bytes]:
        """The signature of each row of ``phases`` [rad]."""
        blocks = (self._block(phases[start : start + self.BLOCK]) for start in range(0, len(phases), self.BLOCK))
        return [signature for block in blocks for signature in block]

    def _rounded(self, total: np.ndarray, turn: np.ndarray) -> np.ndarray:
        """Orders ``total`` (…, 2, h) moved into frames by the rotations ``turn`` (…, A, h),
        e^{−inα_anchor}, rounded: (…, A, 4h), harmonic by harmonic (J, gravity; re, im)."""
        framed = total[..., None, :, :] * turn[..., :, None, :] / self.step[:, : turn.shape[-1]]
        parts = np.stack((framed.real, framed.imag), axis=-1)  # (…, A, 2, h, 2)
        return np.rint(np.moveaxis(parts, -3, -2)).astype(np.int64).reshape(*turn.shape[:-1], -1)

    def _block(self, phases: np.ndarray) -> list[bytes]:
        n, k = phases.shape
        anchors = self.gassed if self.gassed.size else np.arange(k)
        # The gas relative to each anchor: (kind, phase) as one integer, sorted; each
        # difference of phases rounded to ticks once (rounding the phases first would split
        # a tick: 3π and 2π, π apart, round to ticks 1 apart from π's).
        difference = np.mod(phases[:, None, self.gassed] - phases[:, anchors, None], self.machine.cycle)
        relative = np.round(difference / _RESOLUTION).astype(np.int64) % self.period
        gas = np.sort(self.gas_kind[self.gassed] * self.period + relative, axis=2)
        allowed = self._least(gas, np.ones((n, anchors.size), dtype=bool))
        # J's and gravity's orders Σ_j c_n e^{inα_j} (e^{inα} made once per angle that occurs).
        angles, index = np.unique(np.mod(phases, 2 * math.pi), return_inverse=True)
        rotation = np.exp(1j * angles[:, None] * self.order)
        index = index.reshape(n, k)
        total = np.einsum("jqh,njh->nqh", self.coefficients, rotation[index])
        # The least frame among those the gas allows, by the first orders (each anchor's) …
        back = np.conj(rotation[index[:, anchors]])  # (n, A, H)
        first = _FIRST_ORDERS
        allowed = self._least(self._rounded(total[:, :, :first], back[:, :, :first]), allowed)
        # … and by all of them where a candidate's symmetry leaves a tie.
        tied = np.flatnonzero(allowed.sum(axis=1) > 1)
        if tied.size:
            allowed[tied] = self._least(self._rounded(total[tied], back[tied]), allowed[tied])
        chosen = allowed.argmax(axis=1)
        rows = np.arange(n)
        rounded = self._rounded(total, back[rows, chosen][:, None, :])[:, 0, :]
        return [gas[i, a].tobytes() + rounded[i].tobytes() for i, a in enumerate(chosen)]


def _groups(machine: Machine, phases: np.ndarray) -> np.ndarray:
    """Each candidate's class of candidates that run alike on a rigid shaft (an integer per
    row, numbered in order of first appearance): a dictionary look-up of its
    :class:`_Signatures`."""
    seen: dict[bytes, int] = {}
    return np.array(
        [seen.setdefault(signature, len(seen)) for signature in _Signatures(machine)(phases)], dtype=np.int64
    )
