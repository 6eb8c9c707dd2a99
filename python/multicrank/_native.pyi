"""Type stubs of the Rust extension module (checked by mypy.stubtest in the tests)."""

import numpy as np
import numpy.typing as npt

__all__ = [
    "crank_phases",
    "evaluate",
    "dimensionless_moments",
    "evaluate_series",
    "lambda_coefficients",
    "paper_coefficient",
    "surviving_harmonics",
    "fourier_coefficients",
    "energy_extrema",
    "sweep",
    "engine_evaluate",
    "engine_fourier",
    "engine_extrema",
    "get_parallel_threshold",
    "set_parallel_threshold",
    "_after_fork_in_child",
    "MechanismError",
    "__version__",
    "build_profile",
]

__version__: str
build_profile: str

class MechanismError(ValueError): ...

def crank_phases(cranks: int, strokes: int, acting: str) -> npt.NDArray[np.float64]: ...
def evaluate(
    quantity: str,
    phi: npt.NDArray[np.float64],
    crank_ratio: npt.NDArray[np.float64],
    inclination: npt.NDArray[np.float64],
    u1: npt.NDArray[np.float64],
    u2: npt.NDArray[np.float64],
    phases: npt.NDArray[np.float64],
    uniform: tuple[float, float, int] | None = None,
) -> npt.NDArray[np.float64]: ...
def dimensionless_moments(
    crank_radius: npt.NDArray[np.float64],
    rod_length: npt.NDArray[np.float64],
    rod_cg: npt.NDArray[np.float64],
    piston_mass: npt.NDArray[np.float64],
    rod_mass: npt.NDArray[np.float64],
    crank_mass: npt.NDArray[np.float64],
    crank_cg_radius: npt.NDArray[np.float64],
    counterweight_mass: npt.NDArray[np.float64],
    counterweight_radius: npt.NDArray[np.float64],
    shaft_inertia: npt.NDArray[np.float64],
    rpm: npt.NDArray[np.float64],
    g: npt.NDArray[np.float64],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def get_parallel_threshold() -> int: ...
def set_parallel_threshold(threshold: int) -> None: ...
def _after_fork_in_child() -> None: ...
def evaluate_series(
    method: str,
    phi: npt.NDArray[np.float64],
    crank_ratio: npt.NDArray[np.float64],
    inclination: npt.NDArray[np.float64],
    u1: npt.NDArray[np.float64],
    u2: npt.NDArray[np.float64],
    phases: npt.NDArray[np.float64],
    uniform: tuple[float, float, int] | None = None,
) -> npt.NDArray[np.float64]: ...
def lambda_coefficients(crank_ratio: npt.NDArray[np.float64], n_max: int, method: str) -> npt.NDArray[np.float64]: ...
def paper_coefficient(i: int, j: int) -> tuple[int, int]: ...
def surviving_harmonics(cranks: int, strokes: int, acting: str, n_max: int) -> list[int]: ...
def fourier_coefficients(
    crank_ratio: npt.NDArray[np.float64],
    inclination: npt.NDArray[np.float64],
    u1: npt.NDArray[np.float64],
    u2: npt.NDArray[np.float64],
    phases: npt.NDArray[np.float64],
    n_max: int,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def energy_extrema(
    crank_ratio: npt.NDArray[np.float64],
    inclination: npt.NDArray[np.float64],
    u1: npt.NDArray[np.float64],
    u2: npt.NDArray[np.float64],
    phases: npt.NDArray[np.float64],
) -> tuple[
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
]: ...
def sweep(
    crank_ratio: npt.NDArray[np.float64],
    inclination: npt.NDArray[np.float64],
    u1: npt.NDArray[np.float64],
    u2: npt.NDArray[np.float64],
    phase_set: npt.NDArray[np.uint32],
    set_phases: npt.NDArray[np.float64],
    set_offsets: npt.NDArray[np.uint64],
    phi: npt.NDArray[np.float64],
    force: bool,
    energy: bool,
    harmonic: bool,
) -> list[npt.NDArray[np.float64]]: ...
def engine_evaluate(
    quantity: str,
    phi: npt.NDArray[np.float64],
    phase: npt.NDArray[np.float64],
    inclination: npt.NDArray[np.float64],
    crank_ratio: npt.NDArray[np.float64],
    u1: npt.NDArray[np.float64],
    u2: npt.NDArray[np.float64],
    uniform: tuple[float, float, int] | None = None,
) -> npt.NDArray[np.float64]: ...
def engine_fourier(
    phase: npt.NDArray[np.float64],
    inclination: npt.NDArray[np.float64],
    crank_ratio: npt.NDArray[np.float64],
    u1: npt.NDArray[np.float64],
    u2: npt.NDArray[np.float64],
    n_max: int,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def engine_extrema(
    phase: npt.NDArray[np.float64],
    inclination: npt.NDArray[np.float64],
    crank_ratio: npt.NDArray[np.float64],
    u1: npt.NDArray[np.float64],
    u2: npt.NDArray[np.float64],
) -> tuple[float, float, float, float, float]: ...
