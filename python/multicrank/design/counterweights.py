"""The counterweights per throw that keep δ with gravity lowest, or the main-bearing loads or
the first-order free force, within limits on those and on the first-order free moment
(:func:`optimize_counterweights`).

A counterweight enters the machine's motion only through gravity: its first moment m_p r_p,
opposite its crank pin, turns with the pin and adds −g m_p r_p cos(φ + pin angle) to the
torque on the shaft (its moment of inertia is part of the shaft's). On the frame it acts by
its inertia too: it turns with the pin and pulls on the main bearings, and its centrifugal
force m_p r_p ω² cancels part of the forward first-order free force. Cylinders whose pins
coincide at one place along the shaft (a V's banks on one throw) share a throw, and only the
sum of their counterweights' first moments counts: the design variables are one first moment per
throw [kg·m], spread equally over the throw's cylinders, each at its own counterweight radius
(the crank radius where it has none).

The optimiser is SciPy's differential evolution — bounded, global, reproducible from its
seed, limits on the bearing load, the free force and the free moment kept by its own
constraint handling —
evaluating each generation as one :func:`~multicrank.motion_sweep` of
``"counterweight_mass[j]"`` columns, then polished by L-BFGS-B.
"""

from __future__ import annotations

import inspect
import math
from typing import Any

import numpy as np

from .._validation import (
    as_count,
    as_flag,
    as_instance,
    as_option,
    omega_from_rpm,
    refused,
    running_rpm,
    warn_renamed,
)
from ..machine.machine import Machine
from ._crank import throws as crank_throws
from ._steps import _as_bounds, _as_limit, _at_bound, _nearest_alike, _nothing_runs, _polish, _radius, _unmet
from .criteria import COUNTERWEIGHT_CRITERIA
from .optimum import CounterweightOptimum

__all__ = ["OBJECTIVES", "RENAMED_OBJECTIVES", "CounterweightOptimum", "optimize_counterweights"]

#: The objectives :func:`optimize_counterweights` minimises, named as the criteria they are
#: (:data:`~multicrank.design.criteria.VOCABULARY`).
OBJECTIVES: tuple[str, ...] = ("delta", "gravity_effect", "delta_over_speed_range", "max_bearing_load", "free_force_1")
#: The objectives' names of 0.1, deprecated (they go in 0.3): the criterion each is.
RENAMED_OBJECTIVES = {"bearing_load": "max_bearing_load", "shaking_force": "free_force_1"}
#: Speeds at which "delta_over_speed_range" evaluates δ, evenly over the machine's rpm_range.
SPEEDS_IN_RANGE = 9
# The objectives that are δ's, whose optimum only the counterweights' resultant fixes.
_DELTA_OBJECTIVES = ("delta", "gravity_effect", "delta_over_speed_range")
# The objectives that are the frame's, each the motion_sweep output it minimises (at rpm held
# constant; no steady state solved, so none stalls).
_FRAME_OBJECTIVES = ("max_bearing_load", "free_force_1")
# Each constraint (the parameter) and the motion_sweep output it bounds from above.
_CONSTRAINTS = {
    "max_bearing_load": "max_bearing_load",
    "max_free_force": "free_force_1",
    "max_free_moment": "free_moment_1",
}


def optimize_counterweights(
    machine: Machine,
    *,
    objective: str = "delta",
    bounds: Any = None,
    rpm: Any = None,
    max_bearing_load: Any = None,
    max_free_force: Any = None,
    max_free_moment: Any = None,
    seed: Any = 0,
    maxiter: Any = 200,
    progress: Any = False,
) -> CounterweightOptimum:
    """The counterweights (first moments per throw, opposite the pin) that minimise δ with
    gravity, the main-bearing loads or the first-order free force, within limits on those and
    on the first-order free moment.

    Parameters
    ----------
    machine : Machine
        The machine: everything but its counterweights stays as given.
    objective : str, default "delta"
        What to minimise, one of :data:`OBJECTIVES` (each named as the criterion it is):
        "delta", δ with gravity at ``rpm`` [dimensionless];
        "gravity_effect", the size of gravity's effect on δ, the absolute value of δ/δ₀ − 1
        (δ₀ with g = 0), so that the machine runs as if gravity were not there;
        "delta_over_speed_range", the largest δ at 9 speeds evenly over the machine's
        ``rpm_range``; "max_bearing_load", the largest load on any main bearing over the working
        cycle [N] (:func:`~multicrank.bearing_loads` at ``rpm`` held constant, 720 angles);
        "free_force_1", the first-order free force [N], inertial, at ``rpm`` held constant
        (the largest magnitude of the first-order shaking force over a revolution: forward +
        backward of :func:`~multicrank.shaking_forces`). The names of 0.1, "bearing_load"
        and "shaking_force", still work with a DeprecationWarning (they go in 0.3).
    bounds : (low, high) or sequence of them, optional
        The first moment m_p r_p [kg·m] of each throw's counterweights: one pair for every
        throw, or one per throw. Default: from 0 to twice the throw's own first moment of
        crank web, rod and piston masses at the crank radius.
    rpm : float, optional
        The mean speed n [1/min] ("balance" load) of δ, and the constant speed of the
        bearing loads and free forces; default the machine's own ``rpm``.
    max_bearing_load : float, optional
        A constraint: the optimum's largest main-bearing load over the cycle (as for
        "max_bearing_load", at ``rpm``) is at most this [N], finite, >= 0.
    max_free_force : float, optional
        A constraint: the optimum's first-order free force (as for "free_force_1", at
        ``rpm``) is at most this [N], finite, >= 0.
    max_free_moment : float, optional
        A constraint: the optimum's first-order free moment about the engine centre
        (``free_moment_1``: the largest magnitude over a revolution of the first-order
        shaking moment, pitch and yaw together, at ``rpm`` held constant) is at most this
        [N·m], finite, >= 0. Counterweights that differ along the shaft make a moment of
        their own: bound it where the optimum must not rock the frame.
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
        stalls and counterweights make it run), every criterion after and before — δ
        (``delta``), the largest main-bearing load (``max_bearing_load`` [N]), the
        first-order free force (``free_force_1`` [N]) and moment (``free_moment_1`` [N·m]),
        each with ``…_before``, and all in ``criteria()`` — the constraints
        (``max_bearing_load_limit``, ``max_free_force_limit``, ``max_free_moment_limit``),
        ``at_bound`` (per throw, whether its optimum lies on a bound of the search: widen
        ``bounds`` to see past it), the optimised ``machine`` and the optimiser's
        convergence (``success``, ``message``, ``nit``, ``nfev``, ``result``).

    Raises
    ------
    MechanismError
        For bad input, naming the parameter; where no design within ``bounds`` that the
        optimiser tried keeps the constraints, naming each one it could not keep with the
        smallest value reached.
    StallError
        Where no counterweights within ``bounds`` (keeping the constraints) run at ``rpm``
        (or over the speed range): every design tried stalls. Its ``min_rpm`` is the
        machine as given's lowest speed that runs.

    Notes
    -----
    Only a throw's total first moment is a design variable (a throw: the cylinders at one
    place along the shaft whose pins coincide, as a V's two banks on one pin); it is spread
    equally over its cylinders, each at its own ``counterweight_radius`` (or the crank
    radius where that is 0). Throws apart along the shaft are apart here even where their
    pins point the same way (an in-line four's cylinders 1 and 4): δ and the free force see
    only their sum, the bearing loads and the free moments each one.
    The counterweights' moments of inertia are the shaft's (``shaft_inertia``), unchanged
    here. The machine as given is a member of the first generation, so that within the
    bounds (and the constraints, where it keeps them) the optimum is never worse than it; a
    constraint the machine as given breaks is allowed, and the optimum keeps it. A design
    that stalls scores +∞ (only the δ objectives solve a steady state).

    The constraints are kept by differential evolution's own rule (Lampinen's: a design that
    keeps them beats one that does not; of two that do not, the one that breaks them less
    wins), and the polish by L-BFGS-B scores a design that breaks one as it scores a stall,
    by a finite penalty above every value found, so that it never returns one. The
    criteria, and so the constraints, are those of ``rpm`` alone, also for
    "delta_over_speed_range" (give ``rpm`` the top of the range to hold the loads there).

    δ and the first-order free force depend on the counterweights only through their
    resultant Σ m_p r_p e^{iθ} over the throws (θ the pin angles); for the δ objectives and
    "free_force_1", of all those that run alike, the one nearest the machine as given
    (least squares) is returned, unless it breaks a constraint. The main-bearing loads and
    the free moments depend on where along the shaft each counterweight sits: for
    "max_bearing_load" the optimiser's own point is returned. Counterweights turn with the
    crank, so they cancel only the forward part of the first-order free force (the rotating
    masses and half the reciprocating first order): its backward half and the higher orders
    remain (:func:`~multicrank.shaking_forces` of ``optimum.machine`` has every order).

    Examples
    --------
    >>> import multicrank as mc
    >>> compressor = mc.presets.MACHINES["slow-compressor"]
    >>> best = mc.optimize_counterweights(compressor)
    >>> best.to_frame().round(2)
       throw cylinders  angle_deg  counterweight_before  counterweight  at_bound
    0      1         1       90.0                   3.6          24.62     False
    >>> round(best.delta_before, 5), round(best.delta, 5)
    (0.02953, 0.02526)

    Least δ loads the bearings more than as built; the bearings' load kept as built:

    >>> kept = mc.optimize_counterweights(compressor, max_bearing_load=best.max_bearing_load_before)
    >>> bool(kept.max_bearing_load <= best.max_bearing_load_before < best.max_bearing_load)
    True
    >>> bool(best.delta <= kept.delta <= best.delta_before)
    True
    """
    import pandas as pd
    from scipy.optimize import NonlinearConstraint, differential_evolution  # type: ignore[import-untyped,unused-ignore]

    from ..motion.sweep import motion_sweep
    from ..motion.variants import machine_variant

    machine = as_instance(machine, Machine, "machine")
    if isinstance(objective, str) and objective in RENAMED_OBJECTIVES:
        warn_renamed(f"objective={objective!r}", f"objective={RENAMED_OBJECTIVES[objective]!r}")
        objective = RENAMED_OBJECTIVES[objective]
    objective = as_option(objective, "objective", OBJECTIVES)
    speed = running_rpm(machine, rpm)
    given = {name: _as_limit(value, name) for name, value in (("max_bearing_load", max_bearing_load),
                                                              ("max_free_force", max_free_force),
                                                              ("max_free_moment", max_free_moment))}  # fmt: skip
    limits_of = {name: limit for name, limit in given.items() if limit is not None}
    seed = as_count(seed, "seed", minimum=0)
    generations = as_count(maxiter, "maxiter", minimum=1)
    progress = as_flag(progress, "progress")
    throws, angles = crank_throws(machine)
    limits = _as_bounds(bounds, machine, throws)
    if objective == "delta_over_speed_range":
        if machine.rpm_range is None:
            raise refused(
                "objective",
                f"objective='delta_over_speed_range' needs the machine's rpm_range; machine {machine.name!r} has none",
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

    def designs(moments: np.ndarray, at: np.ndarray) -> pd.DataFrame:
        """Rows: each column of ``moments`` (throws × candidates) at each speed of ``at``."""
        masses = np.repeat(share @ moments, len(at), axis=1)
        table = pd.DataFrame({f"counterweight_mass[{j}]": masses[j] for j in range(len(machine.cylinders))})
        for name, value in fixed.items():
            table[name] = value
        table["rpm"] = np.tile(at, moments.shape[1])
        return table

    # What each evaluation asks of motion_sweep: the objective's output (δ, or gravity's
    # effect, at each speed; or the frame's at rpm) and the outputs the constraints bound
    # (the frame's, at rpm): one sweep, or two where δ is taken over the speed range.
    measured = objective if objective in (*_FRAME_OBJECTIVES, "gravity_effect") else "delta"
    steady = [] if objective in _FRAME_OBJECTIVES else list(dict.fromkeys(["delta", measured]))
    bounded = [_CONSTRAINTS[name] for name in limits_of]
    framed = list(dict.fromkeys([*([measured] if objective in _FRAME_OBJECTIVES else []), *bounded]))
    apart = bool(steady) and bool(framed) and len(speeds) > 1
    least = dict.fromkeys(limits_of, math.inf)
    evaluations = 0

    def evaluate(moments: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The objective of each column of ``moments`` (throws × candidates; +∞ where a design
        stalls) and the outputs the constraints bound (constraints × candidates)."""
        nonlocal evaluations
        count = moments.shape[1]
        if count == 0:  # a generation none of whose trials keeps the constraints
            return np.empty(0), np.empty((len(bounded), 0))
        at = np.array([speed]) if not steady else speeds
        found = motion_sweep(machine, designs(moments, at), outputs=steady + ([] if apart else framed))
        evaluations += len(found)
        frame = found
        if apart:
            frame = motion_sweep(machine, designs(moments, np.array([speed])), outputs=framed)
            evaluations += len(frame)
        value = np.abs(found[measured].to_numpy(dtype=float))
        # A stalled design (NaN δ) scores +∞; over the speed range, its worst speed counts.
        value = np.where(np.isfinite(value), value, math.inf).reshape(count, len(at)).max(axis=1)
        held = np.array([frame[output].to_numpy(dtype=float) for output in bounded]).reshape(len(bounded), count)
        for name, row in zip(limits_of, held, strict=True):
            least[name] = min(least[name], float(row.min()))
        return value, held

    # The last batch whose constraints SciPy asked, by design: its objective comes next, for
    # the designs that keep them, and is not solved twice.
    batch: dict[bytes, float] = {}

    def constrained(x: np.ndarray) -> np.ndarray:
        moments = np.asarray(x, dtype=float)
        columns = moments.reshape(len(throws), -1)
        value, held = evaluate(columns)
        batch.clear()
        batch.update((columns[:, k].tobytes(), float(value[k])) for k in range(columns.shape[1]))
        return held if moments.ndim == 2 else held[:, 0]

    def scores(x: np.ndarray) -> Any:
        moments = np.asarray(x, dtype=float)
        columns = moments.reshape(len(throws), -1)
        keys = [columns[:, k].tobytes() for k in range(columns.shape[1])]
        if not all(key in batch for key in keys):
            value = evaluate(columns)[0]
        else:
            value = np.array([batch[key] for key in keys])
        return float(value[0]) if moments.ndim == 1 else value  # the polish calls with one x

    def kept(x: np.ndarray) -> tuple[float, list[str], dict[str, float]]:
        """The objective of one design, the constraints it breaks, and what they bound."""
        value, held = evaluate(np.asarray(x, dtype=float)[:, None])
        bound = {name: float(v) for name, v in zip(limits_of, held[:, 0], strict=True)}
        return float(value[0]), [name for name, v in bound.items() if v > limits_of[name]], bound

    # As given: a counterweight at radius 0 has no first moment, whatever its mass.
    before = np.array(
        [sum(machine.cylinders[j].counterweight_mass * machine.cylinders[j].counterweight_radius for j in throw)
         for throw in throws]
    )  # fmt: skip
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=generations, desc="counterweights", unit="generation")

    def advance(*_: Any, **__: Any) -> None:
        if bar is not None:
            bar.update(1)

    randomness = {"rng": seed} if "rng" in inspect.signature(differential_evolution).parameters else {"seed": seed}
    # SciPy's constraint handling, vectorized alike: the constraints of a whole generation
    # in one sweep (which computes its objective too, kept in ``batch``).
    constraints = [NonlinearConstraint(constrained, -np.inf, np.array(list(limits_of.values())))] if limits_of else []
    try:
        result = differential_evolution(
            scores,
            bounds=limits,
            maxiter=generations,
            vectorized=True,
            updating="deferred",
            x0=np.clip(before, limits[:, 0], limits[:, 1]),
            callback=advance,
            constraints=constraints,
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
            # A free force a counterweight cancels is 0 at its optimum, where a relative
            # spread never converges: also converged at 1e-9 of the centrifugal force of the
            # heaviest counterweight the bounds allow.
            atol=1e-9 * omega_from_rpm(speed) ** 2 * float(limits[:, 1].max())
            if objective in _FRAME_OBJECTIVES
            else 0.0,
            **randomness,
        )
    finally:
        if bar is not None:
            bar.close()
    found = np.asarray(result.x, dtype=float)
    if limits_of:
        # The best is the least violating design where none keeps the constraints.
        _, broken, closest = kept(found)
        if broken:
            raise _unmet(limits_of, closest, least, limits, evaluations)
    if not math.isfinite(result.fun):
        raise _nothing_runs(machine, objective, speed, limits, constrained=bool(limits_of))

    def polished_scores(x: np.ndarray) -> float:
        # A design that breaks a constraint scores as a stall: the polish never returns it.
        value, broken, _ = kept(x) if limits_of else (scores(x), [], {})
        return math.inf if broken else value

    _polish(result, polished_scores, limits)
    best = np.asarray(result.x, dtype=float)
    if objective not in _FRAME_OBJECTIVES or objective == "free_force_1":
        # Only the resultant fixes δ and the free force: move along the designs alike to the
        # nearest the machine as given, unless that breaks a constraint (the bearing loads
        # are not alike along them).
        moved = _nearest_alike(best, before, angles, limits)
        if moved is not best and not (limits_of and kept(moved)[1]):
            best = moved
    optimum = machine_variant(
        machine, {str(name): value for name, value in designs(best[:, None], np.array([speed])).iloc[0].items()}
    )

    # Every criterion of the machine as given and of the optimum in one sweep: the machine's
    # own counterweights (a mass at radius 0 still weighs on the bearings), and the optimum's.
    own = [(c.counterweight_mass, c.counterweight_radius) for c in machine.cylinders]
    after = share @ best
    table = pd.DataFrame(
        {
            **{f"counterweight_mass[{j}]": [own[j][0], after[j]] for j in range(len(own))},
            **{f"counterweight_radius[{j}]": [own[j][1], radius[j]] for j in range(len(own))},
            "rpm": [speed, speed],
        }
    )
    reported = [*COUNTERWEIGHT_CRITERIA, *(["gravity_effect"] if objective == "gravity_effect" else [])]
    criteria = motion_sweep(machine, table, outputs=reported)
    evaluations += len(criteria)
    if objective == "delta_over_speed_range":
        on_speeds = motion_sweep(machine, pd.DataFrame({"rpm": speeds}), outputs=["delta"])["delta"].to_numpy()
        evaluations += len(on_speeds)
        objective_before = float(np.max(np.where(np.isfinite(on_speeds), on_speeds, math.inf)))
        objective_after = scores(best)
    else:
        values = np.abs(criteria[measured].to_numpy(dtype=float))
        objective_before, objective_after = (float(v) if math.isfinite(v) else math.inf for v in values)

    return CounterweightOptimum(
        throws=throws,
        throw_angles=angles,
        counterweights=best,
        counterweights_before=before,
        objective=objective_after,
        objective_before=objective_before,
        objective_name=objective,
        **{f"{name}_before": float(criteria[name].iloc[0]) for name in COUNTERWEIGHT_CRITERIA},
        **{name: float(criteria[name].iloc[1]) for name in COUNTERWEIGHT_CRITERIA},
        max_bearing_load_limit=given["max_bearing_load"],
        max_free_force_limit=given["max_free_force"],
        max_free_moment_limit=given["max_free_moment"],
        at_bound=_at_bound(best, limits),
        rpm=speed,
        machine=optimum,
        machine_before=machine,
        success=bool(result.success),
        message=str(result.message),
        nit=int(result.nit),
        nfev=evaluations,
        result=result,
    )
