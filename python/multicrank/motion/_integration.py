"""The time integration behind :func:`~multicrank.simulate`: the right-hand side of the equation
of motion for the state (φ, ω, W) (:class:`_Model`), and SciPy's ``solve_ivp`` with the stall
event and the progress bar (:func:`_integrate`), within the tolerances it can honour
(:func:`_tolerances`):

    J(φ) φ̈ + ½ J'(φ) φ̇² = M_gas(φ) − U'(φ) + M_drive(φ, φ̇) − M_load(φ, φ̇),
    dW/dt = (M_gas + M_drive − M_load)·ω.

:mod:`multicrank.motion.transient` holds the API (:func:`~multicrank.simulate`) and its result
(:class:`~multicrank.Transient`). SciPy is imported when a run starts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._inertia_torque import inertia_torque
from .._validation import as_scalar, has_gas, refused
from ..machine.machine import Machine
from .loads import Torque

__all__ = ["METHODS"]

#: The integrators of ``scipy.integrate.solve_ivp`` that :func:`simulate` accepts.
METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")

#: The smallest rtol solve_ivp honours (100 machine epsilons).
_RTOL_FLOOR = 100 * float(np.finfo(float).eps)
#: The smallest atol taken. solve_ivp's error norm squares err/(atol + rtol·|y|), and at the
#: start φ and W may be 0, leaving atol alone in the denominator: a first step's error of up to
#: ~1e50 (far beyond any φ [rad], ω [rad/s] or W [J] of a machine) over atol must stay below
#: √(largest double) ≈ 1e154 for its square not to overflow (as it did, with a RuntimeWarning,
#: at atol = 3.7e-181). Nothing is lost: an absolute error below 1e-100 is under the rounding
#: of every state but one within 1e-84 of zero, and rtol governs there anyway.
_ATOL_FLOOR = 1e-100


# -- the model --------------------------------------------------------------------------------


class _Model:
    """The right-hand side of the equation of motion and the torques at the samples."""

    def __init__(self, machine: Machine, drive: Torque | None, load: Torque | None, gravity: bool) -> None:
        self.machine, self.drive, self.load, self.gravity = machine, drive, load, gravity
        # Without a gassed cylinder the gas torque is 0: skip its (Python) pressure calls.
        self.gas = any(has_gas(c) for c in machine.cylinders)

    def external(self, phi: np.ndarray, omega: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(M_gas, M_drive, M_load) [N·m] at φ, ω (arrays of one shape)."""
        zero = np.zeros(np.shape(phi))
        gas = self.machine.gas_torque(phi) if self.gas else zero
        drive = self.drive(phi, omega) if self.drive is not None else zero
        load = self.load(phi, omega) if self.load is not None else zero
        return gas, drive, load

    def gravity_torque(self, phi: np.ndarray) -> np.ndarray:
        return self.machine.gravity_torque(phi) if self.gravity else np.zeros(np.shape(phi))

    def potential_energy(self, phi: np.ndarray) -> np.ndarray:
        return self.machine.potential_energy(phi) if self.gravity else np.zeros(np.shape(phi))

    def rhs(self, t: float, y: np.ndarray) -> list[float]:
        phi, omega = np.asarray(y[0]), np.asarray(y[1])
        inertia, slope = self.machine.reduced_inertia(phi)
        gas, drive, load = self.external(phi, omega)
        external = float(gas + drive - load)
        torque = external + float(self.gravity_torque(phi)) + float(inertia_torque(slope, omega))
        return [float(omega), torque / float(inertia), external * float(omega)]


@dataclass(frozen=True)
class _Solution:
    time: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    work: np.ndarray
    stalled: bool
    stall_time: float | None
    nfev: int
    message: str


def _integrate(
    model: _Model,
    times: np.ndarray,
    phi0: float,
    omega0: float,
    tolerances: dict[str, float],
    method: str,
    max_step: float,
    progress: bool,
) -> _Solution:
    import scipy.integrate  # type: ignore[import-untyped,unused-ignore]

    def stall(t: float, y: np.ndarray) -> float:
        return float(y[1])

    stall.terminal = True  # type: ignore[attr-defined]
    stall.direction = -1  # type: ignore[attr-defined]

    rhs = model.rhs
    bar = None
    if progress:
        from tqdm.auto import tqdm

        # Counted in output times passed: an integer total (a float one prints "0.00/2.00").
        steps = int(times.size - 1)
        bar = tqdm(total=steps, desc="simulate", unit="point")
        passed = [0]

        def rhs(t: float, y: np.ndarray) -> list[float]:
            done = min(int(np.searchsorted(times, t, side="right")) - 1, steps)
            if done > passed[0]:
                assert bar is not None
                bar.update(done - passed[0])
                passed[0] = done
            return model.rhs(t, y)

    try:
        ode = scipy.integrate.solve_ivp(
            rhs,
            (float(times[0]), float(times[-1])),
            np.array([phi0, omega0, 0.0]),
            method=method,
            t_eval=times,
            events=stall,
            max_step=max_step,
            **tolerances,
        )
    finally:
        if bar is not None:
            bar.close()
    if ode.status < 0:
        raise refused("method", f"the integration failed: {ode.message}")
    time, state = np.asarray(ode.t, dtype=float), np.asarray(ode.y, dtype=float)
    stalled = ode.status == 1 and len(ode.t_events[0]) > 0
    stall_time = None
    if stalled:
        stall_time = float(ode.t_events[0][0])
        at_stall = np.array(ode.y_events[0][0], dtype=float)
        at_stall[1] = 0.0  # the event's root: ω = 0 up to rounding
        keep = time < stall_time
        time = np.append(time[keep], stall_time)
        state = np.concatenate([state[:, keep], at_stall[:, None]], axis=1)
    return _Solution(
        time=time,
        phi=state[0].copy(),
        omega=state[1].copy(),
        work=state[2].copy(),
        stalled=bool(stalled),
        stall_time=stall_time,
        nfev=int(ode.nfev),
        message=str(ode.message),
    )


def _tolerances(rtol: Any, atol: Any) -> dict[str, float]:
    """solve_ivp's rtol and atol, checked up front against what it can honour."""
    relative, absolute = as_scalar(rtol, "rtol"), as_scalar(atol, "atol")
    # Below the floor solve_ivp would raise rtol itself, with a warning; at 1 or more it would
    # accept an error as large as the state.
    if not (math.isfinite(relative) and _RTOL_FLOOR <= relative < 1):
        raise refused("rtol", f"rtol = {relative} is out of range; allowed: {_RTOL_FLOOR:.3g} <= rtol < 1")
    if not (math.isfinite(absolute) and absolute >= _ATOL_FLOOR):
        raise refused("atol", f"atol = {absolute} is out of range; allowed: atol >= {_ATOL_FLOOR:g}, finite")
    return {"rtol": relative, "atol": absolute}
