"""The steps of :func:`~multicrank.optimize_counterweights` around the optimiser: the bounds
and limits checked, the nearest equivalent counterweights, the polish, and the errors where
nothing runs or keeps the limits."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from .._native import MechanismError
from .._validation import as_real_array, as_scalar, refused
from ..machine.machine import Machine

__all__ = ["_as_bounds", "_as_limit", "_at_bound", "_nearest_alike", "_nothing_runs", "_polish", "_radius", "_unmet"]

#: An optimum within this fraction of its throw's search width of a bound lies on it.
AT_BOUND = 1e-6


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
            raise refused(
                "bounds",
                "bounds is required: a throw of this machine has no crank, rod or piston mass to scale the "
                "counterweights by; give bounds=(low, high) in kg·m",
            )
        return np.stack([np.zeros_like(own), 2 * own], axis=1)
    array = as_real_array(bounds, "bounds").astype(float)
    if array.shape == (2,):
        array = np.tile(array, (len(throws), 1))
    if array.shape != (len(throws), 2):
        raise refused(
            "bounds",
            f"bounds must be (low, high) in kg·m, or one such pair per throw ({len(throws)}), got shape {array.shape}",
        )
    if not (np.all(np.isfinite(array)) and np.all(array[:, 0] >= 0) and np.all(array[:, 0] < array[:, 1])):
        raise refused("bounds", f"bounds = {array.tolist()} is out of range; allowed: finite 0 <= low < high [kg·m]")
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


def _at_bound(found: np.ndarray, limits: np.ndarray) -> tuple[bool, ...]:
    """Per throw, whether ``found`` lies on a bound of the search (within :data:`AT_BOUND`
    of the width ``high − low``)."""
    reach = AT_BOUND * (limits[:, 1] - limits[:, 0])
    near = (np.abs(found - limits[:, 0]) <= reach) | (np.abs(limits[:, 1] - found) <= reach)
    return tuple(bool(b) for b in near)


# What each constraint bounds, in words, and its unit.
_BOUNDED = {
    "max_bearing_load": ("main-bearing load (largest over the cycle)", "N"),
    "max_free_force": ("first-order free force", "N"),
    "max_free_moment": ("first-order free moment", "N·m"),
}


def _as_limit(value: Any, name: str) -> float | None:
    """A constraint: None, or a finite force [N] (or moment [N·m]) >= 0."""
    if value is None:
        return None
    limit = as_scalar(value, name)
    if not (math.isfinite(limit) and limit >= 0):
        what, unit = _BOUNDED[name]
        raise refused(name, f"{name} = {limit} is out of range; allowed: a finite {what} >= 0 [{unit}], or None")
    return limit


def _unmet(
    limits: dict[str, float], closest: dict[str, float], least: dict[str, float], bounds: np.ndarray, tried: int
) -> MechanismError:
    """The error where no design tried keeps the constraints: each named, with the smallest
    value any design reached (one constraint), or the values of the design closest to keeping
    them (several: each alone may be kept)."""
    pairs = ", ".join(f"({low:g}, {high:g})" for low, high in bounds)
    kept = " and ".join(f"{name} <= {limit:g} {_BOUNDED[name][1]}" for name, limit in limits.items())
    if len(limits) == 1:
        (name,) = limits
        what, unit = _BOUNDED[name]
        found = f": the lowest {what} of the {tried} designs tried is {least[name]:.6g} {unit}"
    else:
        values = " and ".join(f"a {_BOUNDED[n][0]} of {closest[n]:.6g} {_BOUNDED[n][1]}" for n in limits)
        found = f" together: the closest of the {tried} designs tried has {values}"
    return refused(
        next(iter(limits)),
        f"no counterweights within bounds = [{pairs}] kg·m keep {kept}{found} "
        f"(raise {' or '.join(limits)}, or widen the bounds)",
    )


def _nothing_runs(
    machine: Machine, objective: str, rpm: float, limits: np.ndarray, constrained: bool = False
) -> MechanismError:
    """The error when every design the optimiser tried (of those that keep the constraints)
    stalls: a StallError naming the speed, with the machine's own stall (where and from which
    speed it runs) where it has one."""
    from ..motion.steady import StallError, steady_state

    speed = rpm
    if objective == "delta_over_speed_range" and machine.rpm_range is not None:
        where, speed = f"over rpm_range = {machine.rpm_range}", machine.rpm_range[0]
    else:
        where = f"at rpm = {rpm:g}"
    pairs = ", ".join(f"({low:g}, {high:g})" for low, high in limits)
    kept = " that keeps the constraints" if constrained else ""
    message = f"no counterweights within bounds = [{pairs}] kg·m run {where}: every design tried{kept} stalls"
    try:
        steady_state(machine, rpm=speed)
    except StallError as error:
        if error.min_rpm is not None:
            message += f"; the machine as given runs from min_rpm = {error.min_rpm:g}"
        return StallError(f"{message} (raise the speed)", angle=error.angle, min_rpm=error.min_rpm)
    return StallError(f"{message} (raise the speed or widen the bounds)", angle=math.nan)


def _polish(result: Any, scores: Callable[[np.ndarray], Any], limits: np.ndarray) -> None:
    """Polish differential evolution's best point by L-BFGS-B, as SciPy's ``polish=True``
    does (``result`` updated in place where it improves), but with a design that ``scores``
    +∞ (a stall, or one that breaks a constraint) scoring a finite penalty above every value
    found: the finite differences beside it then stay finite (SciPy's own polish takes
    +∞ − +∞). The penalty is more than ten times the best value (which is >= 0), so a
    polished point that beats the best is one that runs and keeps the constraints."""
    from scipy.optimize import minimize  # type: ignore[import-untyped,unused-ignore]

    penalty = max(10.0 * float(result.fun), 4.0)

    def finite(x: np.ndarray) -> float:
        value = float(scores(x))
        return value if math.isfinite(value) else penalty

    polished = minimize(finite, np.array(result.x, dtype=float), method="L-BFGS-B", bounds=limits)
    result.nfev += polished.nfev
    if polished.fun < result.fun and np.all(np.isfinite(polished.x)):
        result.x, result.fun, result.jac = polished.x, float(polished.fun), polished.jac
