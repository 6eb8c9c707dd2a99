"""Type stubs of the Rust extension module (checked by mypy.stubtest in the tests).

Bundles: ``design`` is a dict of four equal-length float64 arrays (crank_ratio, inclination,
u1, u2); ``engine`` a dict of five (phase, inclination, crank_ratio, u1, u2); ``phi`` the
points or a uniform grid (start, step, count). Several results come back as dicts keyed
by name.
"""

from collections.abc import Callable, Mapping, Sequence
from typing import Any, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "EXTREMA_FIELDS",
    "FRAME_OUTPUTS",
    "MOTION_SWEEP_OUTPUTS",
    "SHAKING_ORDER_COLUMNS",
    "SPEED_LIMITS",
    "STANDARD_GRAVITY",
    "SWEEP_OUTPUTS",
    "FlywheelResult",
    "MechanismError",
    "NativeMachine",
    "SolvedSteadyState",
    "SteadyResult",
    "__version__",
    "_after_fork_in_child",
    "bearing_layout",
    "build_profile",
    "chain_modes",
    "crank_phases",
    "dimensionless_moments",
    "energy_extrema",
    "engine_evaluate",
    "engine_extrema",
    "engine_fourier",
    "engine_leading_harmonic",
    "engine_sensitivity",
    "evaluate",
    "fourier_coefficients",
    "get_parallel_threshold",
    "lambda_coefficients",
    "paper_coefficient",
    "piston_forces",
    "set_parallel_threshold",
    "size_shaft_inertia",
    "surviving_harmonics",
    "sweep",
    "sweep_engines",
    "two_mass_rod_inertia",
    "unit_travel",
]

_Array = npt.NDArray[np.float64]
_Columns = Mapping[str, _Array]
_Phi = _Array | tuple[float, float, int]

__version__: str
build_profile: str
SPEED_LIMITS: tuple[float, float]
STANDARD_GRAVITY: float
SWEEP_OUTPUTS: list[str]
EXTREMA_FIELDS: list[str]
MOTION_SWEEP_OUTPUTS: list[str]
FRAME_OUTPUTS: list[str]
SHAKING_ORDER_COLUMNS: list[str]

class MechanismError(ValueError):
    """A bad value, by name: the message names the parameter and its allowed range, and
    ``parameter`` names it as data (None on the class, and where an error names none). A
    design row's error also carries ``row`` (from 0) and ``reason`` (its own message)."""

    parameter: str | None

_Table = tuple[_Array, _Array] | None

@final
class SteadyResult:
    """A steady state as the core found it (SI units, immutable): its numbers, and the curves
    and arrays at the angles asked for (None where none were asked), how the solve ended
    (``status``, ``message``) and its evaluation counts (``nfev``, ``nit``)."""

    def solution(self) -> dict[str, Any]: ...
    @property
    def omega_mean(self) -> float: ...
    @property
    def period(self) -> float: ...
    @property
    def omega_max(self) -> float: ...
    @property
    def omega_min(self) -> float: ...
    @property
    def phi_max(self) -> float: ...
    @property
    def phi_min(self) -> float: ...
    @property
    def energy_at_zero(self) -> float: ...
    @property
    def mean_load_torque(self) -> float: ...
    @property
    def delta(self) -> float: ...
    @property
    def delta_midrange(self) -> float: ...
    @property
    def delta_without_gravity(self) -> float: ...
    @property
    def delta_coasting(self) -> float: ...
    @property
    def status(self) -> int:
        """0: converged (SciPy's success); a stall is an error, never a result."""
    @property
    def message(self) -> str:
        """How the solve ended, in words."""
    @property
    def nfev(self) -> int:
        """Evaluations of the function whose root is found (0 for the closed form) [count]."""
    @property
    def nit(self) -> int:
        """Of those, Brent's method's own [count]."""
    @property
    def omega(self) -> _Array | None: ...
    @property
    def time(self) -> _Array | None: ...
    @property
    def reduced_inertia(self) -> _Array | None: ...
    @property
    def reduced_inertia_slope(self) -> _Array | None: ...
    @property
    def gas_torque(self) -> _Array | None: ...
    @property
    def gravity_torque(self) -> _Array | None: ...
    @property
    def solved(self) -> SolvedSteadyState | None:
        """The solve kept for its curves (the "balance" load's; None for the square law)."""

@final
class SolvedSteadyState:
    """A steady state's solve under the "balance" load, kept for its curves."""

    def curves(self, phi: _Array) -> list[_Array]:
        """ω [rad/s] and t [s from φ = 0] at ``phi`` [rad, each in [0, Φ]]: the doubles
        ``steady_state`` gives with ``phi``, without a second solve."""

@final
class FlywheelResult:
    """The shaft inertia sized for a coefficient of speed fluctuation (SI units, immutable)."""

    @property
    def shaft_inertia(self) -> float: ...
    @property
    def shaft_inertia_without_gravity(self) -> float: ...
    @property
    def textbook(self) -> float: ...
    @property
    def textbook_error(self) -> float: ...
    @property
    def energy_swing(self) -> float: ...
    @property
    def delta(self) -> float: ...
    @property
    def omega_mean(self) -> float: ...

@final
class NativeMachine:
    """A machine as the core holds it, converted and checked once (immutable): its gravity,
    kinematics and torques, its motion, the forces on its frame.

    ``pressure`` and ``pressure_crank_end``: per unit None or the gauge pressure's SciPy
    ``PPoly`` arrays (x, c), c of shape (K, len(x) - 1). A stall is a MechanismError with
    attributes ``angle`` [rad], ``omega_mean`` and ``min_omega`` [rad/s, or None]. Every
    speed is ω [rad/s], within ``SPEED_LIMITS``.
    """

    def __new__(
        cls,
        units: _Columns,
        bore: _Array,
        piston_rod_diameter: _Array,
        pressure: Sequence[_Table],
        pressure_crank_end: Sequence[_Table],
        shaft_inertia: float,
        strokes: int,
        g: float,
        axial_position: _Array | None = None,
        main_bearings: _Array | None = None,
    ) -> NativeMachine: ...
    def evaluate(self, quantity: str, phi: _Phi, parallel_threshold: int | None = None) -> _Array: ...
    def reduced_inertia(
        self, phi: _Phi, shaft_inertia: float | None = None, parallel_threshold: int | None = None
    ) -> dict[str, _Array]: ...
    def gas_torque(self, phi: _Phi, forces: _Array, parallel_threshold: int | None = None) -> _Array: ...
    def engine(self, omega: float, shaft_inertia: float | None = None) -> dict[str, _Array]: ...
    def layout(self) -> tuple[list[float], list[int], list[float]]: ...
    def bearing_loads(
        self, phi: _Array, omega: _Array, acceleration: _Array, gravity: bool = True
    ) -> tuple[_Array, _Array]: ...
    def bearing_loads_at_speed(self, omega: float, pressure_scale: float, gravity: bool) -> tuple[_Array, _Array]: ...
    def frame_sweep(
        self,
        designs: Mapping[str, _Array],
        outputs: Sequence[str],
        omega: float | None,
        parallel_threshold: int | None = None,
    ) -> dict[str, _Array]: ...
    def torque_orders(self, omega: float, max_order: int, gravity: bool = True) -> dict[str, _Array | float]: ...
    def steady_state(
        self,
        omega_mean: float,
        min_speed_ratio: float = 1e-3,
        phi: _Array | None = None,
        compare: bool = True,
        shaft_inertia: float | None = None,
        gravity: bool = True,
        drive: _Table = None,
        arrays: bool = True,
    ) -> SteadyResult: ...
    def cycle_arrays(
        self, phi: _Array, shaft_inertia: float | None = None, gravity: bool = True, drive: _Table = None
    ) -> list[_Array]: ...
    def comparisons(
        self,
        omega: float,
        delta: float,
        omega_mean: float,
        min_speed_ratio: float = 1e-3,
        shaft_inertia: float | None = None,
        gravity: bool = True,
        drive: _Table = None,
    ) -> tuple[float, float]: ...
    def mean_gas_torque(self) -> float: ...
    def shaking_reference(self) -> float: ...
    def shaking_orders(self, omega: float, max_order: int) -> dict[str, _Array]: ...
    def shaking_curves(self, phi: _Array, omega: _Array, acceleration: _Array) -> _Array: ...
    def shaking_orders_in_motion(self, omega: _Array, acceleration: _Array, max_harmonic: int) -> dict[str, _Array]: ...
    def gas_and_gravity_work(self, phi: _Array, gravity: bool = True) -> _Array: ...
    def textbook_flywheel(
        self, delta: float, omega_mean: float, drive: _Table = None, gravity: bool = True
    ) -> tuple[float, float]: ...
    def square_law(
        self,
        coefficient: float,
        drive: float = 0.0,
        min_speed_ratio: float = 1e-3,
        phi: _Array | None = None,
        gravity: bool = True,
    ) -> SteadyResult: ...
    def flywheel_inertia(
        self,
        delta: float,
        omega_mean: float,
        min_speed_ratio: float = 1e-3,
        without_gravity: bool = True,
        gravity: bool = True,
        drive: _Table = None,
    ) -> FlywheelResult: ...
    def square_law_flywheel_inertia(
        self,
        coefficient: float,
        delta: float,
        drive: float = 0.0,
        min_speed_ratio: float = 1e-3,
        gravity: bool = True,
    ) -> FlywheelResult: ...
    def sweep(
        self,
        designs: dict[str, _Array],
        outputs: Sequence[str],
        omega: float | None = None,
        target_delta: float | None = None,
        min_speed_ratio: float = 1e-3,
        parallel_threshold: int | None = None,
    ) -> dict[str, npt.NDArray[Any]]: ...

def crank_phases(cranks: int, strokes: int, acting: str) -> _Array: ...
def evaluate(
    quantity: str, phi: _Phi, design: _Columns, phases: _Array, parallel_threshold: int | None = None
) -> _Array: ...
def dimensionless_moments(units: _Columns) -> dict[str, _Array]: ...
def lambda_coefficients(
    crank_ratio: _Array, n_max: int, method: str, parallel_threshold: int | None = None
) -> _Array: ...
def paper_coefficient(i: int, j: int) -> tuple[int, int]: ...
def surviving_harmonics(cranks: int, strokes: int, acting: str, n_max: int) -> npt.NDArray[np.uint64]: ...
def fourier_coefficients(
    design: _Columns, phases: _Array, n_max: int, parallel_threshold: int | None = None
) -> dict[str, _Array]: ...
def energy_extrema(design: _Columns, phases: _Array, parallel_threshold: int | None = None) -> dict[str, _Array]: ...
def sweep(
    design: _Columns,
    phase_set: npt.NDArray[np.uint32],
    phase_sets: Sequence[_Array],
    phi: _Array,
    outputs: Sequence[str],
    parallel_threshold: int | None = None,
) -> dict[str, _Array]: ...
def sweep_engines(
    engines: Sequence[_Columns], phi: _Array, outputs: Sequence[str], parallel_threshold: int | None = None
) -> dict[str, _Array]: ...
def engine_evaluate(quantity: str, phi: _Phi, engine: _Columns, parallel_threshold: int | None = None) -> _Array: ...
def engine_fourier(engine: _Columns, n_max: int) -> dict[str, _Array]: ...
def engine_extrema(engine: _Columns) -> dict[str, float]: ...
def engine_leading_harmonic(engine: _Columns) -> dict[str, float]: ...
def engine_sensitivity(
    engine: _Columns, u1_rel: float, u2_rel: float, phase: float, n_max: int
) -> dict[str, _Array]: ...
def bearing_layout(
    axial_position: Sequence[float], main_bearings: Sequence[float] | None, crank_radius: float
) -> tuple[list[float], list[int], list[float]]: ...
def unit_travel(units: _Columns, phi: _Phi) -> _Array: ...
def size_shaft_inertia(delta_at: Callable[[float], float | None], rest: float, delta: float, start: float) -> float: ...
def piston_forces(bore: _Array, piston_rod_diameter: _Array, head: _Array, crank_end: _Array) -> _Array: ...
def two_mass_rod_inertia(rod_mass: float, rod_length: float, rod_cg: float) -> float: ...
def get_parallel_threshold() -> int: ...
def set_parallel_threshold(threshold: int) -> None: ...
def _after_fork_in_child() -> None: ...
def chain_modes(stiffness: _Array, inertia: _Array, count: int) -> tuple[_Array, _Array]: ...
