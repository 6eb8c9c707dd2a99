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
functions — their Fourier orders, in the frame of each shift the gas allows. Both go into
one hashable signature per candidate (:class:`_Signatures`), so that telling tens of
thousands of candidates apart is one set look-up each, not a comparison of every pair.
"""

from __future__ import annotations

from itertools import pairwise
from typing import Any

import numpy as np

from .._validation import as_count, as_flag, as_instance, as_option, omega_from_rpm, refused, running_rpm
from ..machine.machine import Machine
from ._candidates import _RESOLUTION, _candidates, _groups
from .criteria import AGREE, FIRING_CRITERIA, RANKINGS, SHAFT_CRITERIA, frame_criteria, pareto_front, ticks

__all__ = ["firing_orders"]

#: max_candidates by default: every four-stroke crank of up to 13 cylinders (2^(k−1)) and
#: every two-stroke crank of up to 7 unlike, evenly spaced throws ((t − 1)!) in full; a
#: longer crank's first 4096 arrangements in seconds (each distinct one is a steady state).
DEFAULT_MAX_CANDIDATES = 4096
#: The steady state's columns of a row (its class's: candidates alike on a rigid shaft share them).
MOTION_COLUMNS = ("delta", "delta_without_gravity", "gravity_effect", "stalled", "near_stall")


def _firing_sequences(phases: np.ndarray, cycle: float) -> list[str]:
    """For each row of ``phases``, the cylinders (numbered from 1) in the order they fire,
    from cylinder 1, those firing together joined by "+" (a cylinder fires at
    θ = (φ + α) mod Φ = 0, so at φ = (−α) mod Φ)."""
    period = round(cycle / _RESOLUTION)
    when = np.round(np.mod(phases[:, :1] - phases, cycle) / _RESOLUTION).astype(np.int64) % period
    order = np.argsort(when, axis=1, kind="stable")  # by instant, then by cylinder
    sequences = []
    for instants, cylinders in zip(when.tolist(), order.tolist(), strict=True):
        text = str(cylinders[0] + 1)
        for before, j in pairwise(cylinders):
            text += ("+" if instants[j] == instants[before] else "-") + str(j + 1)
        sequences.append(text)
    return sequences


def _largest_orders(machine: Machine, phases: np.ndarray, rpm: float, highest: int) -> tuple[np.ndarray, np.ndarray]:
    """The order 0 < ν ≤ ``highest`` of the largest total torque amplitude of each candidate
    (rows of ``phases``), and that amplitude [N·m].

    Every part of the torque (gas, inertia at the mean speed, gravity) is a sum over
    cylinders of a function of φ + α_j: each cylinder's orders are found once, at phase 0,
    and moved to α_j by the shift theorem (:func:`~multicrank.torsion.excitation.cylinder_orders`).
    """
    from ..torsion.excitation import cylinder_orders

    harmonics = cylinder_orders(machine, highest)
    omega = np.full(harmonics.orders.shape, omega_from_rpm(rpm))
    amplitude = np.abs(harmonics.at(phases, omega).sum(axis=1))
    largest = np.argmax(amplitude, axis=1)
    return harmonics.orders[largest], amplitude[np.arange(len(phases)), largest]


def _candidate_machines(machine: Machine, phases: np.ndarray) -> list[Machine]:
    """The machine with each row of ``phases`` [rad]; a cylinder at a phase is made once
    (a crank's cylinders take few phases; Cylinder.replace validates, and costs)."""
    made: dict[tuple[int, float], Any] = {}

    def cylinder(j: int, phase: float) -> Any:
        if (j, phase) not in made:
            made[j, phase] = machine.cylinders[j].replace(phase=phase)
        return made[j, phase]

    # Only the phases differ from the machine's own: nothing a machine checks changes.
    return [machine._with_phases([cylinder(j, float(a)) for j, a in enumerate(row)]) for row in phases]


def firing_orders(
    machine: Machine,
    *,
    shaft: Any = None,
    rank_by: Any = "delta",
    rpm: Any = None,
    max_order: Any = 12,
    modes: Any = 2,
    max_candidates: Any = DEFAULT_MAX_CANDIDATES,
    progress: Any = False,
) -> Any:
    """The distinct firing orders a machine's crank allows, judged by every criterion: δ with
    gravity, the free moments, the main-bearing loads and, with a shaft, the torsional merit.

    Each candidate is the machine with other phases α_j. Candidates that run alike on a rigid
    shaft (the same motion, shifted in φ) share one steady state ("balance" load, at ``rpm``,
    solved by :func:`~multicrank.motion_sweep`, the candidates its designs: columns
    ``"phase[j]"``); they are one row where their free moments, bearing loads and torsional
    merit agree too, and separate rows where those (or, with a shaft, the vector sum of any
    order in any mode asked) tell them apart. Every candidate's frame
    criteria come from one motion sweep of its frame outputs.

    Parameters
    ----------
    machine : Machine
        The machine: its cylinders, crank, pressures and places along the shaft; its own
        phases are one candidate.
    shaft : Shaft, optional
        The shaft as a torsional chain; default the machine's own (``Machine.shaft``). With
        one, the table has ``torsional_major``, ``torsional_minor`` and ``torsional_merit``.
    rank_by : str, default "delta"
        The column the rows are sorted by (smallest first; ties keep the candidates' order,
        the machine as given first): "delta", "free_moment_1", "free_moment_2",
        "max_bearing_load", or with a shaft "torsional_major", "torsional_minor" or
        "torsional_merit".
    rpm : float, optional
        The speed n [1/min] of the table: the mean speed of the steady states and the
        constant speed of the frame criteria; default the machine's own ``rpm``.
    max_order : int, default 12
        The highest order ν (per revolution) that ``largest_order`` and the torsional
        criteria consider.
    modes : int, default 2
        With a shaft: how many of its elastic modes, from the lowest, the torsional criteria
        weigh (at most its nodes − 1; fewer where it has fewer).
    max_candidates : int, default 4096
        At most this many candidates are made (in a fixed order, the machine's own first);
        where the crank allows more, the table says so (``attrs["exhaustive"]`` False). Each
        candidate costs its frame criteria (below a millisecond) and each class that runs
        alike a steady state (a few ms); the default covers every four-stroke crank of up to
        13 cylinders and every two-stroke crank of up to 7 unlike throws.
    progress : bool, default False
        Show progress bars of the frame criteria and the steady states.

    Returns
    -------
    pandas.DataFrame
        One row per distinct candidate, sorted by ``rank_by`` (stalled ones last): ``firing``
        (the cylinders, numbered from 1, in the order they fire from cylinder 1; "+" joins
        those that fire together; the convention in the notes), ``as_given`` (True for the one row that runs as the
        machine given), ``phases`` (α_j [rad], a tuple in the machine's cylinder order),
        ``delta``, ``delta_without_gravity`` and
        ``gravity_effect`` (δ/δ₀ − 1) of the steady state [dimensionless], ``stalled``,
        ``near_stall`` (δ > :data:`~multicrank.NEAR_STALL_DELTA`: it nearly stops each cycle),
        ``largest_order`` (the order 0 < ν ≤ max_order of the largest amplitude of the total
        torque — gas, inertia at the mean speed and gravity — on the shaft; half orders for
        four strokes) and ``largest_order_amplitude`` [N·m]; the frame's criteria at
        ``rpm`` held constant: ``free_moment_1`` and ``free_moment_2`` [N·m] (inertial: the
        largest magnitude over the cycle of the first- and second-order shaking moment
        vector, pitch and yaw together, about the engine centre z_ref: :func:`~multicrank.shaking_forces`),
        ``max_bearing_load`` [N] (the largest load on any main bearing over the working
        cycle, gas, inertia and weights: :func:`~multicrank.bearing_loads` at 720 angles); with a
        shaft, of the resonances (mode ≤ ``modes``, order ≤ ``max_order``) whose speed lies in
        the machine's ``rpm_range``, ends included — or from 0 to ``rpm`` where it has none —
        ``torsional_major`` and ``torsional_minor`` [N·m/√(kg·m²)] (the largest
        ``modal_excitation`` of :func:`~multicrank.torsional_merit`, comparable between modes,
        of the major orders — every cylinder in phase, which no firing order changes — and of
        the minor ones, which the firing order decides) and ``torsional_merit`` [N·m] (the
        largest classical ``excitation`` of the first mode, kept for comparison; not a
        criterion of the front), each 0 where no such order resonates there; ``pareto`` (no
        other row is at least as good on every criterion and better on one); and ``machine`` (the
        candidate's :class:`~multicrank.Machine`). ``attrs``: ``candidates`` (how many
        assignments the crank allows), ``distinct`` (the rows), ``exhaustive`` (whether
        every candidate was made), ``rpm``, ``rank_by``, ``criteria`` (the criteria
        weighed, smaller is better) and ``speed_range`` (that of the torsional merit, None
        without a shaft).

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
    by the multiset of each cylinder's phase over the cycle (to 1e-9 rad) and its pressure,
    bore and crank; J and gravity by their Fourier orders 1 … 48, rounded in steps of 1e-8
    of the cylinders' own swings. Each candidate gets one signature of both (its least over
    the shifts the gas allows), and alike candidates are found by a set look-up: the work
    grows as the number of candidates, not its square. Candidates alike on a rigid shaft may
    still load the frame and the bearings differently and excite the shaft's modes
    differently (the cylinders sit at other places along the shaft): they are separate rows
    where a criterion differs by more than 1e-8 of its largest value. The Pareto marks use
    the same rounding, a stalled δ counting worse than any.

    How a firing order is written: cylinders are numbered from 1 in the machine's order
    (for the built-in layouts and machines, along the shaft from the front), and the
    sequence starts at cylinder 1 and follows the order of firing, the direction of
    rotation: cylinder j fires where its cycle angle θ = φ + α_j is 0, at φ = −α_j mod Φ.
    The built-in four-stroke in-line fours, fives, sixes and eights are the textbook cranks,
    so they read as engine people write them: 1-3-4-2, 1-2-4-5-3, 1-5-3-6-2-4,
    1-6-2-5-8-3-7-4. Candidates that run alike are one row, named by the machine as given
    (its ``as_given`` row) or else by the first candidate of its kind: the four's 1-2-4-3
    (another camshaft on the same crank) runs as its 1-3-4-2, with the same loads, and is
    that row. The six's
    other textbook order, 1-4-2-6-3-5, is that of the mirror-image crank (throws 2-5 and 3-4
    exchanged; 1-5-3-6-2-4 read against the rotation): a machine built so prints it. A name
    does not say when each cylinder fires (a twin's "1-2" may be 180° or 540° apart):
    ``phases`` does.

    Examples
    --------
    >>> import multicrank as mc
    >>> engine = mc.presets.MACHINES["inline-4"]
    >>> table = mc.firing_orders(engine)
    >>> table.attrs["candidates"], table.attrs["distinct"]
    (8, 4)
    >>> table[["firing", "delta", "max_bearing_load", "pareto"]].round(4)  # the even firing wins
        firing   delta  max_bearing_load  pareto
    0  1-3-4-2  0.0075        11647.3349    True
    1  1-2+3-4  0.0180        16093.6853   False
    2  1+4-3-2  0.0180        11647.3349   False
    3  1+4-2+3  0.0250        16093.6853   False

    Two firings that run alike on a rigid shaft (δ 0.018) load the bearings differently.
    With a shaft, the torsional merit joins the criteria (1+4-3-2 excites the first mode as
    little as 1-3-4-2, but is worse on δ: not on the Pareto front):

    >>> shaft = mc.Shaft([0.02, 0.02, 0.02, 0.02, 0.3], [3e5, 3e5, 3e5, 4e5],
    ...                  cylinder_nodes=[0, 1, 2, 3])
    >>> by_merit = mc.firing_orders(engine, shaft=shaft, rank_by="torsional_merit")
    >>> by_merit[["firing", "torsional_merit", "pareto"]].round(1)
        firing  torsional_merit  pareto
    0  1-3-4-2             79.7    True
    1  1+4-3-2             79.7   False
    2  1-2+3-4            107.0   False
    3  1+4-2+3            118.2   False
    """
    import pandas as pd

    from ..machine.shaft import shaft_of
    from ..motion.sweep import motion_sweep
    from ..torsion.merit import firing_criteria, speed_window

    machine = as_instance(machine, Machine, "machine")
    chosen_shaft = None if shaft is None and machine.shaft is None else shaft_of(machine, shaft)
    criteria = tuple(c for c in FIRING_CRITERIA if chosen_shaft is not None or c not in SHAFT_CRITERIA)
    order_by = as_option(rank_by, "rank_by", RANKINGS)
    if chosen_shaft is None and order_by in SHAFT_CRITERIA:
        raise refused(
            "rank_by",
            f"rank_by={order_by!r} needs a shaft: give shaft=mc.Shaft(...); machine {machine.name!r} has none",
        )
    highest = as_count(max_order, "max_order", minimum=1)
    mode_count = as_count(modes, "modes", minimum=1)
    limit = as_count(max_candidates, "max_candidates", minimum=1)
    progress = as_flag(progress, "progress")
    speed = running_rpm(machine, rpm)
    found, total = _candidates(machine, limit)

    # Every candidate's criteria; candidates alike on a rigid shaft (one δ, one steady state
    # each) are one row only where those agree too.
    groups = _groups(machine, found)
    values = frame_criteria(machine, found, speed, progress)
    speeds = speed_window(machine, speed)
    shown = list(criteria[1:])
    sums: list[np.ndarray] = []
    if chosen_shaft is not None:
        torsion = firing_criteria(machine, chosen_shaft, found, highest, speeds, mode_count)
        values.update(torsional_major=torsion.major, torsional_minor=torsion.minor, torsional_merit=torsion.merit)
        shown.append("torsional_merit")
        # Every order's vector sum in every mode, in steps of AGREE of the most it can be
        # (Σ_j abs(a_j) <= the cylinders): firings that excite any order differently are apart.
        flat = torsion.vector_sums.reshape(len(found), -1)
        sums = list(np.rint(flat / (AGREE * found.shape[1])).astype(np.int64).T)
    key = np.column_stack([groups, *(ticks(values[name]) for name in shown), *sums])
    _, first = np.unique(key, axis=0, return_index=True)
    kept = np.sort(first)  # candidate 0, the machine as given, first
    phases = found[kept]

    representative = np.unique(groups, return_index=True)[1]  # the first candidate of each class
    designs = pd.DataFrame({f"phase[{j}]": found[representative, j] for j in range(found.shape[1])})
    designs["rpm"] = speed
    solved = motion_sweep(
        machine, designs, outputs=["delta", "delta_without_gravity", "gravity_effect"], progress=progress
    )
    motion = {name: solved[name].to_numpy()[groups[kept]] for name in MOTION_COLUMNS}
    largest, amplitude = _largest_orders(machine, phases, speed, highest)
    table = pd.DataFrame(
        {
            "firing": _firing_sequences(phases, machine.cycle),
            "as_given": kept == 0,  # candidate 0 is the machine's own phases
            "phases": [tuple(p.tolist()) for p in phases],
            **motion,
            "largest_order": largest,
            "largest_order_amplitude": amplitude,
            **{name: values[name][kept] for name in shown},
        }
    )
    scores = np.column_stack([ticks(table[name].to_numpy()) for name in criteria])
    table["pareto"] = pareto_front(scores)
    table["machine"] = pd.Series(_candidate_machines(machine, phases), dtype=object)
    # Sorted by the rounded criterion, so that values equal but for rounding keep the
    # candidates' order (the machine as given first); NaN (stalled) last.
    table = table.iloc[np.argsort(ticks(table[order_by].to_numpy()), kind="stable")].reset_index(drop=True)
    table.attrs.update(
        candidates=total,
        distinct=len(table),
        exhaustive=len(found) == total,
        rpm=speed,
        rank_by=order_by,
        criteria=criteria,
        speed_range=tuple(float(v) for v in speeds) if chosen_shaft is not None else None,
    )
    return table
