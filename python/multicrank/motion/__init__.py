"""The machine in motion: J(φ)φ̈ + ½J′(φ)φ̇² = M_gas − dU/dφ + M_drive − M_load.

- `loads`: drive and load torques (numbers, "balance", `PowerLawLoad`, callables);
- `steady`: the exact periodic steady state (`steady_state`), and `steady_result` its result
  (`SteadyState`, `StallError`), which `steady` re-exports;
- `flywheel`: the flywheel for a coefficient of speed fluctuation;
- `transient`: the motion in time (`simulate` and its result, `Transient`), `_integration` its
  right-hand side and SciPy's integrators with the stall event;
- `orders`: the torque orders of the cycle (each cylinder's, and their hand-off to openTorsion,
  are the torsion room's);
- `variants` and `sweep`: machines that differ in a few numbers (`MachineGrid`) and their
  steady states at sweep scale (`motion_sweep`); loaded on first use (they need pandas);
- `columns`: the names of a motion sweep's design columns, their meanings and units (light: the
  command line takes its options from it);
- `_result`: what the results share (``solved``, ``to_pandas``, ``to_xarray``);
- `_periodic`: the rules of a periodic solution and its route, which `steady` and `flywheel`
  share: "balance" (beside any drive) and the square law are the Rust core's alone, a load or
  drive that depends on the speed is shot in Python;
- `_shooting`: that last route (SciPy's solve_ivp on the core's K₀ and J), and the flywheel
  for it.

Units and names: a speed's name carries its unit — ``rpm…`` in 1/min, ``omega…`` in rad/s
(ω = πn/30); the torques on the shaft are ``gas_torque``, ``gravity_torque``,
``inertia_torque``, ``drive_torque`` and ``load_torque`` [N·m], the reduced inertia
``reduced_inertia`` [kg·m²] and its slope ``reduced_inertia_slope`` [kg·m²/rad], as the
:class:`~multicrank.Machine` methods that give them.
"""

from ._result import MotionResult
from .flywheel import FlywheelInertia, flywheel_inertia
from .loads import PowerLawLoad
from .orders import torque_orders
from .steady import NEAR_STALL_DELTA, StallError, SteadyState, steady_state
from .transient import Transient, simulate

__all__ = [
    "NEAR_STALL_DELTA",
    "FlywheelInertia",
    "MotionResult",
    "PowerLawLoad",
    "StallError",
    "SteadyState",
    "Transient",
    "flywheel_inertia",
    "simulate",
    "steady_state",
    "torque_orders",
]
