"""The result of :func:`~multicrank.optimize_counterweights`: the optimum per throw and every
criterion before and after (:class:`CounterweightOptimum`)."""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

from ..machine.machine import Machine
from .criteria import COUNTERWEIGHT_CRITERIA, VOCABULARY

__all__ = ["CounterweightOptimum"]


@dataclass(frozen=True, eq=False)
class CounterweightOptimum:
    """The result of :func:`optimize_counterweights`.

    Attributes
    ----------
    throws : tuple of tuple of int
        The cylinders (indices from 0) of each throw: those at one place along the shaft
        whose crank pins coincide.
    throw_angles : ndarray
        Each throw's pin angle α + γ [rad] in [0, 2π), at φ = 0 from the horizontal.
    counterweights : ndarray
        The optimum first moment m_p r_p of each throw's counterweights [kg·m].
    counterweights_before : ndarray
        The same of the machine as given [kg·m].
    objective : float
        The objective at the optimum (δ [dimensionless], or a force [N]).
    objective_before : float
        The objective of the machine as given.
    objective_name : str
        Which objective: "delta", "gravity_effect", "delta_over_speed_range",
        "max_bearing_load" or "free_force_1".
    delta, delta_before : float
        δ with gravity at ``rpm``, after and before [dimensionless]; NaN where that
        machine stalls there (the machine as given, made to run by the counterweights; or
        an optimum of "max_bearing_load" or "free_force_1", which weigh no δ).
    max_bearing_load, max_bearing_load_before : float
        The largest load on any main bearing over the working cycle [N], after and before
        (:func:`~multicrank.bearing_loads` at ``rpm`` held constant, 720 angles).
    free_force_1, free_force_1_before : float
        The first-order free force [N], after and before: the largest magnitude over a
        revolution of the first-order shaking force, forward + backward of
        :func:`~multicrank.shaking_forces` at ``rpm`` held constant.
    free_moment_1, free_moment_1_before : float
        The first-order free moment about the engine centre z_ref [N·m], after and before, alike.
    max_bearing_load_limit, max_free_force_limit, max_free_moment_limit : float or None
        The constraints the optimum keeps (``max_bearing_load`` ≤ the first [N],
        ``free_force_1`` ≤ the second [N], ``free_moment_1`` ≤ the third [N·m]); None where
        not given.
    at_bound : tuple of bool
        Per throw, whether its optimum lies on a bound of the search (within 1e-6 of the
        search width ``high − low`` of ``low`` or ``high``): the optimiser would have gone
        further, so the objective there is the bounds' as much as the machine's. Widen
        ``bounds`` (or accept the bound as a design limit). ``repr`` says so.
    rpm : float
        The mean speed [1/min] of ``delta`` (and of the "delta" and "gravity_effect"
        objectives), and the constant speed of the frame's criteria, objectives and
        constraints.
    machine, machine_before : Machine
        The machine with the optimum counterweights, and as given.
    success : bool
        Whether the optimiser says it converged.
    message : str
        The optimiser's word on why it stopped.
    nit, nfev : int
        Generations, and designs evaluated (one per design and speed: a steady state, or
        the frame's outputs at ``rpm``, or both in one).
    result : scipy.optimize.OptimizeResult
        The optimiser's whole result.
    """

    throws: tuple[tuple[int, ...], ...]
    throw_angles: np.ndarray
    counterweights: np.ndarray
    counterweights_before: np.ndarray
    objective: float
    objective_before: float
    objective_name: str
    delta: float
    delta_before: float
    max_bearing_load: float
    max_bearing_load_before: float
    free_force_1: float
    free_force_1_before: float
    free_moment_1: float
    free_moment_1_before: float
    max_bearing_load_limit: float | None
    max_free_force_limit: float | None
    max_free_moment_limit: float | None
    at_bound: tuple[bool, ...]
    rpm: float
    machine: Machine
    machine_before: Machine
    success: bool
    message: str
    nit: int
    nfev: int
    result: Any = field(repr=False)

    def __eq__(self, other: object) -> bool:
        """Equal where every field is (arrays element by element, NaN equal to NaN); the
        optimiser's raw ``result`` is not compared."""
        if not isinstance(other, CounterweightOptimum):
            return NotImplemented
        for item in fields(self):
            if item.name == "result":
                continue
            mine, theirs = getattr(self, item.name), getattr(other, item.name)
            if isinstance(mine, np.ndarray) or isinstance(theirs, np.ndarray):
                if not np.array_equal(np.asarray(mine), np.asarray(theirs), equal_nan=True):
                    return False
            elif isinstance(mine, float) and isinstance(theirs, float) and mine != mine and theirs != theirs:
                continue
            elif mine != theirs:
                return False
        return True

    __hash__ = None  # type: ignore[assignment]  # mutable arrays inside: unhashable, as numpy's

    @property
    def improvement(self) -> float:
        """1 − objective/objective_before: the fraction of the objective the optimum removes."""
        return 1.0 - self.objective / self.objective_before if self.objective_before else 0.0

    def criteria(self) -> Any:
        """Every criterion before and after, as a table.

        Returns
        -------
        pandas.DataFrame
            Indexed by ``criterion``: "delta" (δ with gravity at ``rpm``),
            "free_force_1" (the first-order free force [N]), "free_moment_1" (the
            first-order free moment about the engine centre [N·m]) and "max_bearing_load" (the largest
            main-bearing load over the cycle [N]), the last three at ``rpm`` held constant;
            columns ``before`` (the machine as given), ``after`` (the optimum) and ``unit``
            ("" for δ).
        """
        import pandas as pd

        return pd.DataFrame(
            {
                "before": [float(getattr(self, f"{name}_before")) for name in COUNTERWEIGHT_CRITERIA],
                "after": [float(getattr(self, name)) for name in COUNTERWEIGHT_CRITERIA],
                "unit": [VOCABULARY[name].unit for name in COUNTERWEIGHT_CRITERIA],
            },
            index=pd.Index(list(COUNTERWEIGHT_CRITERIA), name="criterion"),
        )

    def to_frame(self) -> Any:
        """The optimum per throw, as a table.

        Returns
        -------
        pandas.DataFrame
            One row per throw: ``throw`` (from 1), ``cylinders`` (from 1, "+"-joined),
            ``angle_deg`` (its pin angle [°]), ``counterweight_before`` and
            ``counterweight`` (first moments [kg·m]) and ``at_bound`` (whether the optimum
            lies on a bound of the search).
        """
        import pandas as pd

        return pd.DataFrame(
            {
                "throw": np.arange(1, len(self.throws) + 1),
                "cylinders": ["+".join(str(j + 1) for j in throw) for throw in self.throws],
                "angle_deg": np.degrees(self.throw_angles),
                "counterweight_before": self.counterweights_before,
                "counterweight": self.counterweights,
                "at_bound": list(self.at_bound),
            }
        )

    def __repr__(self) -> str:
        moments = ", ".join(f"{m:.4g}" for m in self.counterweights)
        bound = ""
        if any(self.at_bound):
            throws = ", ".join(str(t + 1) for t, on in enumerate(self.at_bound) if on)
            bound = f", throw{'s' if sum(self.at_bound) > 1 else ''} {throws} at a bound of the search"
        return (
            f"CounterweightOptimum({self.objective_name}: {self.objective_before:.6g} → {self.objective:.6g}, "
            f"counterweights [{moments}] kg·m{bound}, success={self.success})"
        )
