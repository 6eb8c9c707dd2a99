"""Gravity of the crank mechanism, dimensionless (docs/theory.md): the potential energy U* and
the generalised force Q* = dU*/dφ of any crank layout, exactly and as Fourier series, their
extrema (δ_g) and the harmonics that survive the crank sum.

- `mechanism`: crank phases and the physical → dimensionless moments U1, U2;
- `grids`: the crank-angle grids the kernels recognise;
- `evaluation`: U*, Q*, dQ*/dφ of in-line designs, broadcast over design arrays;
- `harmonics`: Λ_n, the Fourier coefficients and the paper's tables;
- `extrema`: the exact extrema of U* and δ_g;
- `engines`: `Engine`, any layout of crank units with their own phase, inclination and moments;
- `layouts`: named crank and cylinder arrangements (in-line, V, boxer, W).
"""

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
from .harmonics import fourier_coefficients, harmonic_table, lambda_coefficients, paper_coefficient, surviving_harmonics
from .layouts import LAYOUTS, Layout, layout_engine
from .mechanism import STANDARD_GRAVITY, crank_phases, dimensionless_moments

__all__ = [
    "FORCE_METHODS",
    "LAYOUTS",
    "STANDARD_GRAVITY",
    "EnergyExtrema",
    "Engine",
    "Layout",
    "UniformGrid",
    "crank_phases",
    "dimensionless_moments",
    "energy_extrema",
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
    "speed_fluctuation",
    "surviving_harmonics",
    "uniform_grid",
]
