"""What the design aid weighs besides δ, and how it tells rows apart and marks the best.

An engine designer chooses a firing order by more than the speed fluctuation: by the free
moments it leaves on the frame, the loads on the main bearings and the torsional vibration it
excites. Every criterion here is smaller-is-better:

- ``delta``: δ with gravity of the steady state ("balance" load) [dimensionless];
- ``free_moment_1``, ``free_moment_2`` [N·m]: the largest magnitude over a cycle of the first-
  and second-order shaking moment vector (pitch and yaw together, about the engine centre
  z_ref = (z_min + z_max)/2), inertial, at the table's constant speed (:func:`~multicrank.shaking_forces`);
- ``max_bearing_load`` [N]: the largest load on any main bearing over the working cycle at
  that speed (:func:`~multicrank.bearing_loads` at 720 angles);
- ``torsional_major`` and ``torsional_minor`` [N·m/√(kg·m²)], with a shaft: the largest
  ``modal_excitation`` (:func:`~multicrank.torsional_merit`) over the shaft's modes asked and
  the resonances in the machine's speed range, of the major orders (every cylinder in phase:
  no firing order changes them) and of the minor ones (which the firing order decides).

``torsional_merit`` (the largest classical excitation of the first mode alone) is a column
of the firing orders and a ``rank_by``, but no criterion of the Pareto front: with a major
order resonating it is the same for every firing order.

Values that agree to :data:`AGREE` of the criterion's largest are equal: they are the same
number but for rounding (mirror-image cranks give the same moments by different sums).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..machine.machine import Machine

__all__ = [
    "AGREE",
    "COUNTERWEIGHT_CRITERIA",
    "FIRING_CRITERIA",
    "FRAME_CRITERIA",
    "RANKINGS",
    "SHAFT_CRITERIA",
    "VOCABULARY",
    "Criterion",
    "frame_criteria",
    "pareto_front",
    "ticks",
]


@dataclass(frozen=True)
class Criterion:
    """A criterion of the design aid: its ``name`` (a column of the firing orders, a field of
    a counterweight optimum, an output of :func:`~multicrank.motion_sweep`), its ``unit`` ("" for
    a number without one) and ``words``, what it is, as the command line and the report say it."""

    name: str
    unit: str
    words: str

    @property
    def label(self) -> str:
        """The words with the unit in brackets, where there is one."""
        return f"{self.words} [{self.unit}]" if self.unit else self.words


#: Every criterion the design aid weighs, once: all smaller-is-better.
VOCABULARY: dict[str, Criterion] = {
    c.name: c
    for c in (
        Criterion("delta", "", "δ with gravity"),
        Criterion("gravity_effect", "", "the size of gravity's effect on δ, abs(δ/δ without gravity − 1)"),
        Criterion("delta_over_speed_range", "", "the largest δ over the machine's speed range"),
        Criterion("free_force_1", "N", "first-order free force"),
        Criterion("free_moment_1", "N·m", "first-order free moment about the engine centre"),
        Criterion("free_moment_2", "N·m", "second-order free moment about the engine centre"),
        Criterion("max_bearing_load", "N", "largest main-bearing load over the cycle"),
        Criterion("torsional_major", "N·m/√(kg·m²)", "largest modal excitation by a major order"),
        Criterion("torsional_minor", "N·m/√(kg·m²)", "largest modal excitation by a minor order"),
        Criterion("torsional_merit", "N·m", "the first mode's largest excitation"),
    )
}
#: The criteria of the firing orders' Pareto front, all smaller-is-better (the last two need
#: a shaft).
FIRING_CRITERIA = ("delta", "free_moment_1", "free_moment_2", "max_bearing_load", "torsional_major", "torsional_minor")
#: What firing_orders may rank by: its criteria, and the first mode's classical merit.
RANKINGS = (*FIRING_CRITERIA, "torsional_merit")
#: The criteria that need a shaft.
SHAFT_CRITERIA = ("torsional_major", "torsional_minor", "torsional_merit")
#: The criteria a counterweight optimum reports before and after.
COUNTERWEIGHT_CRITERIA = ("delta", "free_force_1", "free_moment_1", "max_bearing_load")
#: Those the motion sweep's frame outputs give.
FRAME_CRITERIA = ("free_moment_1", "free_moment_2", "max_bearing_load")
#: Values closer than this fraction of the criterion's largest finite value are equal.
AGREE = 1e-8
#: Rows compared at once by :func:`pareto_front` (an array of BLOCK × BLOCK × criteria).
_BLOCK = 512


def frame_criteria(machine: Machine, phases: np.ndarray, rpm: float, progress: bool) -> dict[str, np.ndarray]:
    """The :data:`FRAME_CRITERIA` of the machine with each row of ``phases`` [rad], at ``rpm``
    held constant: one :func:`~multicrank.motion_sweep` (the core, rows in parallel)."""
    import pandas as pd

    from ..motion.sweep import motion_sweep

    designs = pd.DataFrame({f"phase[{j}]": phases[:, j] for j in range(phases.shape[1])})
    designs["rpm"] = rpm
    found = motion_sweep(machine, designs, outputs=list(FRAME_CRITERIA), progress=progress)
    return {name: found[name].to_numpy() for name in FRAME_CRITERIA}


def ticks(values: np.ndarray) -> np.ndarray:
    """``values`` as integers in steps of :data:`AGREE` of their largest finite magnitude, so
    that equal-but-for-rounding values are equal; NaN (a stalled machine's δ) is the largest
    integer, worse than every number."""
    values = np.asarray(values, dtype=float)
    finite = np.isfinite(values)
    scale = float(np.abs(values[finite]).max()) if finite.any() else 0.0
    result = np.full(values.shape, np.iinfo(np.int64).max, dtype=np.int64)
    result[finite] = np.rint(values[finite] / (AGREE * scale)) if scale > 0 else 0
    return result


def pareto_front(scores: np.ndarray) -> np.ndarray:
    """Whether each row of ``scores`` (rows × criteria, integers from :func:`ticks`, smaller is
    better) is on the Pareto front: no other row is at least as good on every criterion and
    better on one.

    A row's dominator comes before it in lexicographic order, and whatever dominates a
    dominated row dominates every row that row dominates; so in that order each block of rows
    need only be compared with the front found so far and with itself. That is rows × front
    comparisons, not rows²: 32 768 firing orders with a handful on the front take a fraction
    of a second instead of most of a minute.
    """
    scores = np.asarray(scores)
    front = np.empty(0, dtype=np.intp)  # rows of scores, in the order found
    order = np.lexsort(scores.T[::-1])  # first criterion first, ties by the next
    for start in range(0, len(order), _BLOCK):
        block = order[start : start + _BLOCK]
        block = block[~_dominated(scores[block], scores[front])]
        block = block[~_dominated(scores[block], scores[block])]
        front = np.concatenate([front, block])
    on_front = np.zeros(len(scores), dtype=bool)
    on_front[front] = True
    return on_front


def _dominated(rows: np.ndarray, by: np.ndarray) -> np.ndarray:
    """Whether each of ``rows`` is dominated by one of ``by`` (both rows × criteria), compared
    :data:`_BLOCK` of ``by`` at a time so that the array stays small."""
    dominated = np.zeros(len(rows), dtype=bool)
    for start in range(0, len(by), _BLOCK):
        others = by[None, start : start + _BLOCK, :]
        no_worse = np.all(others <= rows[:, None, :], axis=2)
        better = np.any(others < rows[:, None, :], axis=2)
        dominated |= np.any(no_worse & better, axis=1)
    return dominated
