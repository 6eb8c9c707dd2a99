"""What a :class:`~multicrank.SteadyState` computes when first read — its arrays and its two
comparison δ — asked of a typed object rather than a closure: :class:`CoreQuestion` holds
the native machine and the question the Rust core answered (speed, ratio, gravity, drive
table, route) and asks the core again for the rest; :class:`Computed` holds what a route
that solves everything at once (shooting) found. Neither is pickled: a pickled
:class:`~multicrank.SteadyState` holds every array and number, computed first.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, cast

import numpy as np

from .._inertia_torque import inertia_torque
from .._native import NativeMachine, SteadyResult
from ..machine.machine import Machine
from ._periodic import Rules
from .loads import BALANCE, Torque

__all__ = ["COMPARISONS", "Computed", "CoreQuestion", "cycle_angles", "steady_arrays", "steady_curves"]

#: The comparison δ of a steady state, by their names on :class:`~multicrank.SteadyState`.
COMPARISONS = ("delta_without_gravity", "delta_coasting")


def cycle_angles(cycle: float, points: int) -> np.ndarray:
    """``np.linspace(0, cycle, points)`` to the bit (points ≥ 2): i·(Φ/(points − 1)), the
    last exactly Φ, as linspace makes them from 0 — without its ~10 µs of Python, a sixth
    of reading a warm steady state's ``omega``."""
    phi = np.arange(points, dtype=np.float64)
    phi *= cycle / (points - 1)
    phi[-1] = cycle
    return phi


def steady_arrays(
    machine: Machine,
    rules: Rules,
    gravity: bool,
    curves: dict[str, np.ndarray],
    given: tuple[np.ndarray, ...] | None,
    omega_mean: float,
    mean_load: float,
) -> dict[str, np.ndarray]:
    """The arrays of :class:`~multicrank.SteadyState` (read-only) from φ, ω and t
    (``curves``, :func:`steady_curves`), with J, J′, M_gas and the gravity torque ``given``
    where the core gave them (its cycle's tables), else the machine's own."""
    phi, omega = curves["phi"], curves["omega"]
    count = phi.size
    if given is not None:
        J, slope, gas, weight = given
    else:
        J, slope = machine.reduced_inertia(phi)
        gas = machine.gas_torque(phi)
        weight = machine.gravity_torque(phi) if gravity and machine.g != 0 else np.zeros(count)
    inertia = inertia_torque(slope, omega)
    speed = np.full(count, omega_mean) if rules.route == BALANCE else omega
    drive_ = rules.drive(phi, speed) if rules.drive is not None else np.zeros(count)
    if rules.route == BALANCE:
        load_ = np.full(count, mean_load)
    else:
        load_ = rules.load(phi, omega) if isinstance(rules.load, Torque) else np.zeros(count)
    arrays = dict(
        curves,
        reduced_inertia=J,
        reduced_inertia_slope=slope,
        gas_torque=gas,
        gravity_torque=weight,
        inertia_torque=inertia,
        drive_torque=drive_,
        load_torque=load_,
        acceleration=(gas + weight + inertia + drive_ - load_) / J,
    )
    for array in arrays.values():
        array.flags.writeable = False
    return arrays


def steady_curves(phi: np.ndarray, omega: np.ndarray, time: np.ndarray, period: float) -> dict[str, np.ndarray]:
    """φ, ω and t of a steady state (read-only), t from exactly 0 to exactly t_Φ: what
    reading ``omega`` or ``time`` costs, without the torques."""
    time[0], time[-1] = 0.0, period
    curves = dict(phi=phi, omega=omega, time=time)
    for array in curves.values():
        array.flags.writeable = False
    return curves


# Not frozen: a frozen dataclass sets each of its 13 fields through object.__setattr__, ~2 µs
# of a warm steady state's ~25; nothing outside the result holds one.
@dataclass(eq=False)
class CoreQuestion:
    """A steady state the Rust core solved, and what it takes to ask the core for the rest.

    Attributes
    ----------
    native : NativeMachine
        The machine's native machine (:func:`~multicrank.machine.native.motion_machine`).
    machine : Machine
        The machine.
    rules : Rules
        The load and drive resolved; ``rules.route`` is the route: "balance" (the energy
        method: its curves from the solve it kept, ``found.solved``; the core asked again for
        the comparisons) or the square law (which gave both with its solution).
    omega : float or None
        The mean speed asked for [rad/s] ("balance"; None for the square law).
    gravity : bool
        Whether g was kept.
    ratio : float
        ``min_speed_ratio`` [dimensionless].
    points : int
        Points of the arrays over the closed cycle.
    table : tuple of ndarray or None
        The drive as the core takes it (PPoly breakpoints and coefficients), or None.
    found : SteadyResult
        The core's solution (with the square law's curves at ``phi``; under "balance" with
        the solve kept for its curves, ``solved``).
    phi : ndarray or None
        The square law's angles [rad] (None for "balance", whose angles are made when its
        arrays are read).
    omega_mean, period, mean_load : float
        The solution's ω_m [rad/s], t_Φ [s] and mean load [N·m] as the result holds them.
    """

    native: NativeMachine
    machine: Machine
    rules: Rules
    omega: float | None
    gravity: bool
    ratio: float
    points: int
    table: tuple[np.ndarray, np.ndarray] | None
    found: SteadyResult
    phi: np.ndarray | None
    omega_mean: float
    period: float
    mean_load: float

    @property
    def balance(self) -> bool:
        return self.rules.route == BALANCE

    def curves(self) -> dict[str, np.ndarray]:
        """φ, ω and t: "balance" asks its kept solve for ω and t at ``points`` angles (no
        second solve); the square law's came with its solution."""
        if self.balance:
            assert self.found.solved is not None
            phi = cycle_angles(self.machine.cycle, self.points)
            omega, time = self.found.solved.curves(phi)
        else:
            assert self.phi is not None and self.found.omega is not None and self.found.time is not None
            phi, omega, time = self.phi, self.found.omega, self.found.time
        return steady_curves(phi, omega, time, self.period)

    def arrays(self, curves: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """The arrays by name, ``curves`` among them: J, J′ and the torques from the cycle's
        tables ("balance"), or the square law's, which came with its solution."""
        phi = curves["phi"]
        given: tuple[np.ndarray | None, ...]
        if self.balance:
            given = tuple(self.native.cycle_arrays(phi, gravity=self.gravity, drive=self.table))
        else:  # the square law's solution has none: the machine's own
            found = self.found
            given = (found.reduced_inertia, found.reduced_inertia_slope, found.gas_torque, found.gravity_torque)
        taken = None if any(a is None for a in given) else cast(tuple[np.ndarray, ...], given)
        return steady_arrays(self.machine, self.rules, self.gravity, curves, taken, self.omega_mean, self.mean_load)

    def comparisons(self) -> dict[str, float]:
        """The two comparison δ by name: two more solves for "balance"; the square law's
        came with its solution."""
        if not self.balance:
            found = self.found
            return dict(zip(COMPARISONS, (found.delta_without_gravity, found.delta_coasting), strict=True))
        assert self.omega is not None
        compared = self.native.comparisons(
            self.omega, self.found.delta, self.omega_mean, self.ratio, gravity=self.gravity, drive=self.table
        )
        return dict(zip(COMPARISONS, compared, strict=True))


@dataclass(frozen=True, eq=False)
class Computed:
    """A steady state whose arrays and comparison δ were found with it (shooting).

    Attributes
    ----------
    found_arrays : dict of str to ndarray
        The arrays by name.
    found_comparisons : dict of str to float
        The comparison δ by name.
    """

    found_arrays: dict[str, np.ndarray]
    found_comparisons: dict[str, float]

    def curves(self) -> dict[str, np.ndarray]:
        return {name: self.found_arrays[name] for name in ("phi", "omega", "time")}

    def arrays(self, curves: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        return self.found_arrays

    def comparisons(self) -> dict[str, Any]:
        return self.found_comparisons
