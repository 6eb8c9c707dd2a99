"""multicrank — gravitational potential energy and generalised Lagrange forces of
multi-crank piston mechanisms (after M. Stańczak), exact and fast, with a Rust core.

Conventions (docs/theory.md, "Conventions"): angles in radians, φ from outer dead centre, γ the
cylinder's inclination to the horizontal (+π/2 upright), energies dimensionless
(U* = U/(I_w ω²)), Q_u* = +dU_w*/dφ.
"""

from __future__ import annotations

import importlib as _importlib
import os as _os
from typing import Any as _Any

from . import _moved
from . import presets as presets  # public: mc.presets.MACHINES (the built-in machines), mc.presets.LAYOUTS
from ._native import MechanismError, __version__, build_profile
from ._native import _after_fork_in_child as _native_after_fork_in_child
from .gravity import (
    FORCE_METHODS,
    LAYOUTS,
    STANDARD_GRAVITY,
    EnergyExtrema,
    Engine,
    Layout,
    UniformGrid,
    crank_phases,
    dimensionless_moments,
    energy_extrema,
    force_derivative,
    fourier_coefficients,
    generalized_force,
    get_parallel_threshold,
    harmonic_table,
    lambda_coefficients,
    layout_engine,
    paper_coefficient,
    potential_energy,
    set_parallel_threshold,
    speed_fluctuation,
    surviving_harmonics,
    uniform_grid,
)
from .machine import Cylinder, Machine, Shaft
from .motion import (
    NEAR_STALL_DELTA,
    FlywheelInertia,
    PowerLawLoad,
    StallError,
    SteadyState,
    Transient,
    flywheel_inertia,
    simulate,
    steady_state,
    torque_orders,
)
from .pressure import IndicatorDiagram

# The sweep machinery pulls in pandas (and, where installed, pyarrow's thread pools): load
# it on first use, so that `import multicrank` stays light and starts no threads.
_LAZY = {
    "SWEEP_OUTPUTS": "sweeps.designs",
    "DesignGrid": "sweeps.designs",
    "design_grid": "sweeps.designs",
    "to_xarray": "sweeps.designs",
    "sweep": "sweeps.driver",
    "MOTION_SWEEP_OUTPUTS": "motion.sweep",
    "MachineGrid": "motion.variants",
    "motion_sweep": "motion.sweep",
    "firing_orders": "design.firing",
    "optimize_counterweights": "design.counterweights",
    "CounterweightOptimum": "design.optimum",
    "shaking_forces": "forces.shaking",
    "ShakingForces": "forces.shaking",
    "bearing_loads": "forces.bearings",
    "BearingLoads": "forces.bearings",
    "torsional_merit": "torsion.merit",
    "TorsionalModel": "torsion.handoff",
    "to_opentorsion": "torsion.handoff",
}


def __getattr__(name: str) -> _Any:
    if name in _LAZY:
        module = _importlib.import_module(f"{__name__}.{_LAZY[name]}")
        return getattr(module, name)
    raise AttributeError(f"module 'multicrank' has no attribute {name!r}")


# Old module paths (pickles of 0.1) resolve to where the modules live now.
_moved.install()

# rayon's worker threads do not survive fork(): a forked child computes serially.
_os.register_at_fork(after_in_child=_native_after_fork_in_child)

__all__ = [
    "FORCE_METHODS",
    "LAYOUTS",
    "MOTION_SWEEP_OUTPUTS",
    "NEAR_STALL_DELTA",
    "STANDARD_GRAVITY",
    "SWEEP_OUTPUTS",
    "BearingLoads",
    "CounterweightOptimum",
    "Cylinder",
    "DesignGrid",
    "EnergyExtrema",
    "Engine",
    "FlywheelInertia",
    "IndicatorDiagram",
    "Layout",
    "Machine",
    "MachineGrid",
    "MechanismError",
    "PowerLawLoad",
    "Shaft",
    "ShakingForces",
    "StallError",
    "SteadyState",
    "TorsionalModel",
    "Transient",
    "UniformGrid",
    "__version__",
    "bearing_loads",
    "build_profile",
    "crank_phases",
    "design_grid",
    "dimensionless_moments",
    "energy_extrema",
    "firing_orders",
    "flywheel_inertia",
    "force_derivative",
    "fourier_coefficients",
    "generalized_force",
    "get_parallel_threshold",
    "harmonic_table",
    "lambda_coefficients",
    "layout_engine",
    "motion_sweep",
    "optimize_counterweights",
    "paper_coefficient",
    "potential_energy",
    "set_parallel_threshold",
    "shaking_forces",
    "simulate",
    "speed_fluctuation",
    "steady_state",
    "surviving_harmonics",
    "sweep",
    "to_opentorsion",
    "to_xarray",
    "torque_orders",
    "torsional_merit",
    "uniform_grid",
]
