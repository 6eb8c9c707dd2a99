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

from . import presets as presets  # public: mc.presets.ENGINES (the built-in machines), mc.presets.LAYOUTS
from ._native import MechanismError, __version__, build_profile
from ._native import _after_fork_in_child as _native_after_fork_in_child
from .engines import Engine
from .evaluation import (
    FORCE_METHODS,
    force_derivative,
    generalized_force,
    get_parallel_threshold,
    potential_energy,
    set_parallel_threshold,
)
from .extrema import EnergyExtrema, energy_extrema, speed_fluctuation
from .grids import UniformGrid, uniform_grid
from .harmonics import (
    fourier_coefficients,
    harmonic_table,
    lambda_coefficients,
    paper_coefficient,
    surviving_harmonics,
)
from .layouts import LAYOUTS, Layout, layout_engine
from .loads import PowerLawLoad
from .machine import Cylinder, Machine
from .mechanism import STANDARD_GRAVITY, crank_phases, dimensionless_moments
from .motion import FlywheelInertia, StallError, SteadyState, flywheel_inertia, steady_state
from .orders import torque_orders
from .pressure import IndicatorDiagram
from .transient import Transient, simulate

# The sweep machinery pulls in pandas (and, where installed, pyarrow's thread pools): load
# it on first use, so that `import multicrank` stays light and starts no threads.
_LAZY = {
    "SWEEP_OUTPUTS": "designs",
    "DesignGrid": "designs",
    "design_grid": "designs",
    "to_xarray": "designs",
    "sweep": "sweeps",
}


def __getattr__(name: str) -> _Any:
    if name in _LAZY:
        module = _importlib.import_module(f"{__name__}.{_LAZY[name]}")
        return getattr(module, name)
    raise AttributeError(f"module 'multicrank' has no attribute {name!r}")


# rayon's worker threads do not survive fork(): a forked child computes serially.
_os.register_at_fork(after_in_child=_native_after_fork_in_child)

__all__ = [
    "FORCE_METHODS",
    "LAYOUTS",
    "STANDARD_GRAVITY",
    "SWEEP_OUTPUTS",
    "Cylinder",
    "DesignGrid",
    "EnergyExtrema",
    "Engine",
    "FlywheelInertia",
    "IndicatorDiagram",
    "Layout",
    "Machine",
    "MechanismError",
    "PowerLawLoad",
    "StallError",
    "SteadyState",
    "Transient",
    "UniformGrid",
    "__version__",
    "build_profile",
    "crank_phases",
    "design_grid",
    "dimensionless_moments",
    "energy_extrema",
    "flywheel_inertia",
    "force_derivative",
    "fourier_coefficients",
    "generalized_force",
    "get_parallel_threshold",
    "harmonic_table",
    "lambda_coefficients",
    "layout_engine",
    "paper_coefficient",
    "potential_energy",
    "set_parallel_threshold",
    "simulate",
    "speed_fluctuation",
    "steady_state",
    "surviving_harmonics",
    "sweep",
    "to_xarray",
    "torque_orders",
    "uniform_grid",
]
