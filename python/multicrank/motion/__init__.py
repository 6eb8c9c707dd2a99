"""The machine in motion: J(φ)φ̈ + ½J′(φ)φ̇² = M_gas − dU/dφ + M_drive − M_load.

- `loads`: drive and load torques (numbers, "balance", `PowerLawLoad`, callables);
- `steady`: the exact periodic steady state and the flywheel for a coefficient of speed
  fluctuation;
- `transient`: the motion in time (SciPy's integrators, stall events);
- `orders`: the torque orders of the cycle;
- `_quadrature`, `_work`, `_solvers`: the cycle quadrature, the gas work and the steady-state
  solvers behind them.
"""

from .loads import PowerLawLoad
from .orders import torque_orders
from .steady import FlywheelInertia, StallError, SteadyState, flywheel_inertia, steady_state
from .transient import Transient, simulate

__all__ = [
    "FlywheelInertia",
    "PowerLawLoad",
    "StallError",
    "SteadyState",
    "Transient",
    "flywheel_inertia",
    "simulate",
    "steady_state",
    "torque_orders",
]
