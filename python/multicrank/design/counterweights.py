"""The counterweights per throw that keep δ lowest with gravity (:func:`optimize_counterweights`).

A counterweight enters the machine's motion only through gravity: its first moment m_p r_p,
opposite its crank pin, turns with the pin and adds −g m_p r_p cos(φ + pin angle) to the
torque on the shaft (its moment of inertia is part of the shaft's). Cylinders whose pins
coincide (a V's banks on one throw) share a throw, and only the sum of their counterweights'
first moments counts: the design variables are one first moment per throw [kg·m], spread
equally over the throw's cylinders, each at its own counterweight radius (the crank radius
where it has none).

The optimiser is SciPy's differential evolution — bounded, global, reproducible from its
seed — evaluating each generation as one :func:`~multicrank.motion_sweep` of
``"counterweight_mass[j]"`` columns, then polished by L-BFGS-B.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._native import MechanismError
from .._validation import as_count, as_flag, as_instance, as_option, as_real_array, as_speed
from ..machine.machine import Machine
from ._crank import throws as crank_throws

__all__ = ["OBJECTIVES", "CounterweightOptimum", "optimize_counterweights"]

#: The objectives :func:`optimize_counterweights` minimises, by name.
OBJECTIVES: tuple[str, ...] = ("delta", "gravity_effect", "delta_over_speed_range")
#: Speeds at which "delta_over_speed_range" evaluates δ, evenly over the machine's rpm_range.
SPEEDS_IN_RANGE = 9


@dataclass(frozen=True)
class CounterweightOptimum:
    """The result of :func:`optimize_counterweights`.

    Attributes
    ----------
    throws : tuple of tuple of int
        The cylinders (indices from 0) of each throw: those whose crank pins coincide.
    throw_angles : ndarray
        Each throw's pin angle α + γ [rad] in [0, 2π), at φ = 0 from the horizontal.
    counterweights : ndarray
        The optimum first moment m_p r_p of each throw's counterweights [kg·m].
    counterweights_before : ndarray
        The same of the machine as given [kg·m].
    objective : float
        The objective at the optimum.
    objective_before : float
        The objective of the machine as given.
    objective_name : str
        Which objective: "delta", "gravity_effect" or "delta_over_speed_range".
    delta, delta_before : float
        δ with gravity at ``rpm``, after and before [dimensionless] (``delta_before`` NaN
        where the machine as given stalls and the counterweights make it run).
    rpm : float
        The mean speed [1/min] of ``delta`` (and of the "delta" and "gravity_effect"
        objectives).
    machine, machine_before : Machine
        The machine with the optimum counterweights, and as given.
    success : bool
        Whether the optimiser says it converged.
    message : str
        The optimiser's word on why it stopped.
    nit, nfev : int
        Generations, and steady states solved (one per design and speed).
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
    rpm: float
    machine: Machine
    machine_before: Machine
    success: bool
    message: str
    nit: int
    nfev: int
    result: Any = field(repr=False)

    @property
    def improvement(self) -> float:
        """1 − objective/objective_before: the fraction of the objective the optimum removes."""
        return 1.0 - self.objective / self.objective_before if self.objective_before else 0.0

    def to_frame(self) -> Any:
        """The optimum per throw, as a table.

        Returns
        -------
        pandas.DataFrame
            One row per throw: ``throw`` (from 1), ``cylinders`` (from 1, "+"-joined),
            ``angle_deg`` (its pin angle [°]), ``counterweight_before`` and
            ``counterweight`` (first moments [kg·m]).
        """
        import pandas as pd

        return pd.DataFrame(
            {
                "throw": np.arange(1, len(self.throws) + 1),
                "cylinders": ["+".join(str(j + 1) for j in throw) for throw in self.throws],
                "angle_deg": np.degrees(self.throw_angles),
                "counterweight_before": self.counterweights_before,
                "counterweight": self.counterweights,
            }
        )

    def __repr__(self) -> str:
        moments = ", ".join(f"{m:.4g}" for m in self.counterweights)
        return (
            f"CounterweightOptimum({self.objective_name}: {self.objective_before:.6g} → {self.objective:.6g}, "
            f"counterweights [{moments}] kg·m, success={self.success})"
        )


def _radius(cylinder: Any) -> float:
    """Where a cylinder's counterweight sits [m]: its own radius, or the crank's."""
    return cylinder.counterweight_radius if cylinder.counterweight_radius > 0 else cylinder.crank_radius


def _as_bounds(bounds: Any, machine: Machine, throws: tuple[tuple[int, ...], ...]) -> np.ndarray:
    """(low, high) [kg·m] per throw: given once for all, or per throw; by default from 0 to
    twice the throw's own first moment of crank web, rod and piston at the crank radius."""
    if bounds is None:
        own = np.array(
            [
                sum(
                    c.crank_mass * c.crank_cg_radius + (c.rod_mass + c.piston_mass) * c.crank_radius
                    for c in (machine.cylinders[j] for j in throw)
                )
                for throw in throws
            ]
        )
        if not np.all(own > 0):
            raise MechanismError(
                "bounds is required: a throw of this machine has no crank, rod or piston mass to scale the "
                "counterweights by; give bounds=(low, high) in kg·m"
            )
        return np.stack([np.zeros_like(own), 2 * own], axis=1)
    array = as_real_array(bounds, "bounds").astype(float)
    if array.shape == (2,):
        array = np.tile(array, (len(throws), 1))
    if array.shape != (len(throws), 2):
        raise MechanismError(
            f"bounds must be (low, high) in kg·m, or one such pair per throw ({len(throws)}), got shape {array.shape}"
        )
    if not (np.all(np.isfinite(array)) and np.all(array[:, 0] >= 0) and np.all(array[:, 0] < array[:, 1])):
        raise MechanismError(f"bounds = {array.tolist()} is out of range; allowed: finite 0 <= low < high [kg·m]")
    return array


def _nearest_alike(found: np.ndarray, before: np.ndarray, angles: np.ndarray, limits: np.ndarray) -> np.ndarray:
    """The counterweights within ``limits`` nearest ``before`` that run as ``found`` does.

    The counterweights act only through their resultant R = Σ_t x_t e^{iθ_t} (θ_t the pins'
    angles): every x with the same R is the same machine in motion, and a machine with more
    than two throws (or two opposed) has a whole set of them. Of that set, the one that
    changes the machine as given least (least squares, by SLSQP) is the answer a designer
    can use.
    """
    from scipy.optimize import minimize  # type: ignore[import-untyped,unused-ignore]

    resultant = np.stack([np.cos(angles), np.sin(angles)])
    # The independent rows of R = A x (a crank whose pins are all in line has one).
    left, singular, _ = np.linalg.svd(resultant, full_matrices=False)
    rows = (left[:, singular > 1e-9 * singular[0]].T) @ resultant
    if rows.shape[0] == len(found):
        return found  # R fixes x
    target = rows @ found
    nearest = minimize(
        lambda x: float(np.sum((x - before) ** 2)),
        np.clip(before, limits[:, 0], limits[:, 1]),
        jac=lambda x: 2 * (x - before),
        method="SLSQP",
        bounds=limits,
        constraints=[{"type": "eq", "fun": lambda x: rows @ x - target, "jac": lambda x: rows}],
        options={"ftol": 1e-15, "maxiter": 200},
    )
    moved = np.clip(nearest.x, limits[:, 0], limits[:, 1])
    scale = np.abs(found).max() + np.abs(before).max()
    # Kept where it keeps R to rounding (else the optimiser's own point stands).
    return moved if nearest.success and np.abs(rows @ moved - target).max() <= 1e-12 * scale else found


def _delta_or_nan(machine: Machine, rpm: float) -> float:
    """δ with gravity at ``rpm`` [dimensionless]; NaN where the machine stalls there."""
    from ..motion.steady import StallError, steady_state

    try:
        return steady_state(machine, rpm=rpm).delta
    except StallError:
        return math.nan


def _nothing_runs(machine: Machine, objective: str, rpm: float, limits: np.ndarray) -> MechanismError:
    """The error when every design the optimiser tried stalls: a StallError naming the speed,
    with the machine's own stall (where and from which speed it runs) where it has one."""
    from ..motion.steady import StallError, steady_state

    speed = rpm
    if objective == "delta_over_speed_range" and machine.rpm_range is not None:
        where, speed = f"over rpm_range = {machine.rpm_range}", machine.rpm_range[0]
    else:
        where = f"at rpm = {rpm:g}"
    pairs = ", ".join(f"({low:g}, {high:g})" for low, high in limits)
    message = f"no counterweights within bounds = [{pairs}] kg·m run {where}: every design tried stalls"
    try:
        steady_state(machine, rpm=speed)
    except StallError as error:
        if error.min_rpm is not None:
            message += f"; the machine as given runs from min_rpm = {error.min_rpm:g}"
        return StallError(f"{message} (raise the speed)", angle=error.angle, min_rpm=error.min_rpm)
    return StallError(f"{message} (raise the speed or widen the bounds)", angle=math.nan)


def _polish(result: Any, scores: Callable[[np.ndarray], Any], limits: np.ndarray) -> None:
    """Polish differential evolution's best point by L-BFGS-B, as SciPy's ``polish=True``
    does (``result`` updated in place where it improves), but with a stalled design scoring a
    finite penalty above every value found: the finite differences beside a stall then stay
    finite (SciPy's own polish takes +∞ − +∞). The penalty is more than ten times the best
    value, so a polished point that beats the best is one that runs."""
    from scipy.optimize import minimize  # type: ignore[import-untyped,unused-ignore]

    penalty = max(10.0 * float(result.fun), 4.0)

    def finite(x: np.ndarray) -> float:
        value = float(scores(x))
        return value if math.isfinite(value) else penalty

    polished = minimize(finite, np.array(result.x, dtype=float), method="L-BFGS-B", bounds=limits)
    result.nfev += polished.nfev
    if polished.fun < result.fun and np.all(np.isfinite(polished.x)):
        result.x, result.fun, result.jac = polished.x, float(polished.fun), polished.jac


def optimize_counterweights(
    machine: Machine,
    *,
    objective: str = "delta",
    bounds: Any = None,
    rpm: Any = None,
    seed: Any = 0,
    maxiter: Any = 200,
    progress: Any = False,
) -> CounterweightOptimum:
    """The counterweights (first moments per throw, opposite the pin) that minimise δ with
    gravity, or another objective.

    Parameters
    ----------
    machine : Machine
        The machine: everything but its counterweights stays as given.
    objective : {"delta", "gravity_effect", "delta_over_speed_range"}, default "delta"
        What to minimise: δ with gravity at ``rpm``; the size of gravity's effect on δ,
        the absolute value of δ/δ₀ − 1 (δ₀ with g = 0), so that the machine runs as if gravity were not there;
        or the largest δ at 9 speeds evenly over the machine's ``rpm_range``.
    bounds : (low, high) or sequence of them, optional
        The first moment m_p r_p [kg·m] of each throw's counterweights: one pair for every
        throw, or one per throw. Default: from 0 to twice the throw's own first moment of
        crank web, rod and piston masses at the crank radius.
    rpm : float, optional
        The mean speed n [1/min] ("balance" load); default the machine's own ``rpm``.
    seed : int, default 0
        The optimiser's seed: the same seed, the same result.
    maxiter : int, default 200
        The most generations of differential evolution.
    progress : bool, default False
        Show a progress bar of the generations.

    Returns
    -------
    CounterweightOptimum
        The optimum per throw (``counterweights``, ``to_frame()``), ``objective`` after and
        ``objective_before`` (the machine as given; +∞ and ``delta_before`` NaN where it
        stalls and counterweights make it run), δ after and before, the optimised
        ``machine`` and the optimiser's convergence (``success``, ``message``, ``nit``,
        ``nfev``, ``result``).

    Raises
    ------
    MechanismError
        For bad input, naming the parameter.
    StallError
        Where no counterweights within ``bounds`` run at ``rpm`` (or over the speed range):
        every design tried stalls. Its ``min_rpm`` is the machine as given's lowest speed
        that runs.

    Notes
    -----
    Only a throw's total first moment counts (the pins of its cylinders coincide); it is
    spread equally over its cylinders, each at its own ``counterweight_radius`` (or the crank
    radius where that is 0). The counterweights' moments of inertia are the shaft's
    (``shaft_inertia``), unchanged here. The machine as given is a member of the first
    generation, so that within the bounds the optimum is never worse than it. A design that
    stalls scores +∞. Counterweights act only through their resultant Σ m_p r_p e^{iθ} over
    the throws (θ the pin angles): of all those that run alike, the one nearest the machine
    as given (least squares) is returned. They are chosen for δ alone: the shaking forces
    and main-bearing loads, which usually set counterweights, are not weighed here — judge
    the optimum by :func:`~multicrank.shaking_forces` and :func:`~multicrank.bearing_loads`
    of ``optimum.machine`` (the report's "What to change" shows both before and after).

    Examples
    --------
    >>> import multicrank as mc
    >>> compressor = mc.presets.MACHINES["slow-compressor"]
    >>> best = mc.optimize_counterweights(compressor)
    >>> best.to_frame().round(2)
       throw cylinders  angle_deg  counterweight_before  counterweight
    0      1         1       90.0                   3.6          24.62
    >>> round(best.delta_before, 5), round(best.delta, 5)
    (0.02953, 0.02526)
    """
    import pandas as pd
    from scipy.optimize import differential_evolution  # type: ignore[import-untyped,unused-ignore]

    from ..motion.steady import steady_state
    from ..motion.sweep import motion_sweep
    from ..motion.variants import machine_variant

    machine = as_instance(machine, Machine, "machine")
    objective = as_option(objective, "objective", OBJECTIVES)
    if rpm is None and machine.rpm is None:
        raise MechanismError(f"rpm is required: machine {machine.name!r} has no rpm of its own")
    speed = as_speed(machine.rpm if rpm is None else rpm, "rpm")
    seed = as_count(seed, "seed", minimum=0)
    generations = as_count(maxiter, "maxiter", minimum=1)
    progress = as_flag(progress, "progress")
    throws, angles = crank_throws(machine)
    limits = _as_bounds(bounds, machine, throws)
    if objective == "delta_over_speed_range":
        if machine.rpm_range is None:
            raise MechanismError(
                f"objective='delta_over_speed_range' needs the machine's rpm_range; machine {machine.name!r} has none"
            )
        speeds = np.linspace(*machine.rpm_range, SPEEDS_IN_RANGE)
    else:
        speeds = np.array([speed])

    # Each throw's moment spread equally over its cylinders, each at its radius.
    radius = np.array([_radius(c) for c in machine.cylinders])
    share = np.zeros((len(machine.cylinders), len(throws)))
    for t, throw in enumerate(throws):
        share[list(throw), t] = 1.0 / (len(throw) * radius[list(throw)])
    fixed = {
        f"counterweight_radius[{j}]": radius[j] for j, c in enumerate(machine.cylinders) if c.counterweight_radius <= 0
    }

    def designs(moments: np.ndarray) -> pd.DataFrame:
        """Rows: each column of ``moments`` (throws × candidates) at each speed."""
        masses = np.repeat(share @ moments, len(speeds), axis=1)
        table = pd.DataFrame({f"counterweight_mass[{j}]": masses[j] for j in range(len(machine.cylinders))})
        for name, value in fixed.items():
            table[name] = value
        table["rpm"] = np.tile(speeds, moments.shape[1])
        return table

    outputs = ["delta", "gravity_effect"] if objective == "gravity_effect" else ["delta"]
    evaluations = 0

    def objective_of(table: pd.DataFrame) -> np.ndarray:
        """The objective of each design of ``table`` (its rows: each design at each speed)."""
        nonlocal evaluations
        found = motion_sweep(machine, table, outputs=outputs)
        evaluations += len(found)
        column = "gravity_effect" if objective == "gravity_effect" else "delta"
        value = np.abs(found[column].to_numpy())
        # A stalled design (NaN) scores +∞.
        return np.where(np.isfinite(value), value, math.inf).reshape(-1, len(speeds)).max(axis=1)

    def scores(x: np.ndarray) -> Any:
        moments = np.asarray(x, dtype=float)
        value = objective_of(designs(moments.reshape(len(throws), -1)))
        return float(value[0]) if moments.ndim == 1 else value  # the polish calls with one x

    # As given: a counterweight at radius 0 has no first moment, whatever its mass.
    before = np.array(
        [sum(machine.cylinders[j].counterweight_mass * machine.cylinders[j].counterweight_radius for j in throw)
         for throw in throws]
    )  # fmt: skip
    objective_before = float(objective_of(pd.DataFrame({"rpm": speeds}))[0])
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=generations, desc="counterweights", unit="generation")

    def advance(*_: Any, **__: Any) -> None:
        if bar is not None:
            bar.update(1)

    randomness = {"rng": seed} if "rng" in inspect.signature(differential_evolution).parameters else {"seed": seed}
    try:
        result = differential_evolution(
            scores,
            bounds=limits,
            maxiter=generations,
            vectorized=True,
            updating="deferred",
            x0=np.clip(before, limits[:, 0], limits[:, 1]),
            callback=advance,
            # Polished below, where a stalled design scores a finite penalty: SciPy's own
            # polish differences +∞ − +∞ (NaN) beside a stall.
            polish=False,
            # No crossover: a trial is the whole mutant b + F(r1 − r2), whose resultant is
            # the same step among the resultants — evolution in the resultant's two
            # dimensions, however many throws (a twelve-throw crank converges in 80
            # generations instead of not in 200).
            recombination=1.0,
            # δ may barely depend on the counterweights: converge on the objective's
            # spread to 1e-7 of it, not SciPy's default 1 %.
            tol=1e-7,
            **randomness,
        )
    finally:
        if bar is not None:
            bar.close()
    if not math.isfinite(result.fun):
        raise _nothing_runs(machine, objective, speed, limits)
    _polish(result, scores, limits)
    best = _nearest_alike(np.asarray(result.x, dtype=float), before, angles, limits)
    optimum = machine_variant(machine, {str(name): value for name, value in designs(best[:, None]).iloc[0].items()})
    objective_after = scores(best)
    return CounterweightOptimum(
        throws=throws,
        throw_angles=angles,
        counterweights=best,
        counterweights_before=before,
        objective=objective_after,
        objective_before=objective_before,
        objective_name=objective,
        delta=steady_state(optimum, rpm=speed).delta,
        delta_before=_delta_or_nan(machine, speed),
        rpm=speed,
        machine=optimum,
        machine_before=machine,
        success=bool(result.success),
        message=str(result.message),
        nit=int(result.nit),
        nfev=evaluations,
        result=result,
    )
