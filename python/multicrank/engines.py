"""Engines of any layout: in-line, V, boxer, W, odd-fire, unequal cylinders.

An :class:`Engine` is a list of slider-crank units, each with its own crank phase α_j,
cylinder inclination γ_j, crank ratio λ_j and gravity moments u1_j, u2_j. Unit j's crank
angle is ψ_j = φ + α_j from its own outer dead centre, and its crank pin sits at the
absolute angle ψ_j + γ_j (docs/theory.md, "Conventions"). So cylinders that share a crank pin whose
absolute angle is φ + β (V, W, a 180° V) have α_j = β − γ_j; :meth:`Engine.from_throws`
does that bookkeeping. Everything runs in the Rust core with one set of coefficients per
unit, at the speed of the in-line path. The preset layouts (``LAYOUTS``, ``layout_engine``)
are in :mod:`multicrank.layouts` (and :mod:`multicrank.presets`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ._native import MechanismError
from ._native import engine_evaluate as _native_engine_evaluate
from ._native import engine_extrema as _native_engine_extrema
from ._native import engine_fourier as _native_engine_fourier
from ._native import engine_leading_harmonic as _native_engine_leading_harmonic
from ._native import engine_sensitivity as _native_engine_sensitivity
from ._validation import as_count, as_design, as_label, as_nonnegative, as_option, check_size, contiguous, finish
from .extrema import EnergyExtrema
from .grids import as_phi
from .mechanism import crank_phases

__all__ = ["Engine"]

_FIELDS = ("phase", "inclination", "crank_ratio", "u1", "u2")


class Engine:
    """A cylinder-level engine description (dimensionless, angles in radians).

    Parameters
    ----------
    phase : α_j, each unit's crank angle is ψ_j = φ + α_j
    inclination : γ_j, each unit's cylinder axis to the horizontal (+π/2 upright)
    crank_ratio : λ_j, 0 ≤ λ < 1
    u1, u2 : the units' dimensionless gravity moments (see :func:`dimensionless_moments`);
        a unit with u1 = 0 is a purely rotating mass (a crank web or counterweight)

    All five broadcast to one 1-D length (the number of units). ``name`` is a label.
    """

    def __init__(self, *, phase: Any, inclination: Any, crank_ratio: Any, u1: Any, u2: Any, name: str = "engine"):
        columns = {
            "phase": as_design(phase, "phase"),
            "inclination": as_design(inclination, "inclination"),
            "crank_ratio": as_design(crank_ratio, "crank_ratio", low=0.0, high=1.0),
            "u1": as_design(u1, "u1"),
            "u2": as_design(u2, "u2"),
        }
        name = as_label(name, "name")
        for key, column in columns.items():
            if column.ndim > 1:
                raise MechanismError(f"{key} must be a scalar or 1-D (one entry per unit), got shape {column.shape}")
        lengths = {key: column.shape[0] for key, column in columns.items() if column.ndim == 1}
        sizes = set(lengths.values()) - {1}
        if len(sizes) > 1:
            listed = ", ".join(f"{key} has {n}" for key, n in lengths.items())
            raise MechanismError(f"engine columns do not broadcast to one length (the number of units): {listed}")
        length = sizes.pop() if sizes else 1
        if length == 0:
            empty = ", ".join(key for key, n in lengths.items() if n == 0)
            raise MechanismError(f"{empty}: an engine needs at least one unit, got an empty column")
        self._columns = {k: contiguous(np.broadcast_to(v, (length,))).copy() for k, v in columns.items()}
        for column in self._columns.values():
            column.setflags(write=False)
        self.name = name

    # -- construction -------------------------------------------------------------------
    @classmethod
    def inline(
        cls,
        cranks: int,
        strokes: int = 2,
        acting: str = "single",
        *,
        crank_ratio,
        inclination,
        u1,
        u2,
        name: str | None = None,
    ) -> Engine:
        """A regular in-line machine (docs/theory.md, "Crank phases"): identical units at α_j = j·α."""
        phases = crank_phases(cranks, strokes, acting)
        if name is None:
            name = f"inline-{cranks} {strokes}-stroke {acting}-acting"
        return cls(phase=phases, inclination=inclination, crank_ratio=crank_ratio, u1=u1, u2=u2, name=name)

    @classmethod
    def from_throws(
        cls,
        throws: Sequence[float] | np.ndarray,
        banks: Sequence[Sequence[float] | np.ndarray],
        *,
        crank_ratio,
        u1,
        u2,
        name: str = "engine",
    ) -> Engine:
        """Cylinders on crank throws: throw t's pin is at the absolute angle φ + β_t
        (``throws``, rad), and carries one cylinder per inclination in ``banks[t]`` (rad).
        Each cylinder's phase is α = β_t − γ. ``crank_ratio``, ``u1``, ``u2`` are per
        cylinder (scalars or arrays in the cylinders' order)."""
        beta = as_design(throws, "throws")
        if beta.ndim != 1:
            raise MechanismError(f"throws must be a 1-D array of angles [rad], got shape {beta.shape}")
        if isinstance(banks, (str, bytes, Mapping)) or not isinstance(banks, (Sequence, np.ndarray)):
            raise MechanismError(
                f"banks must be a sequence with one array of inclinations [rad] per throw, got {type(banks).__name__}"
            )
        if len(banks) != len(beta):
            raise MechanismError(f"throws has {len(beta)} entries but banks {len(banks)}")
        phase: list[np.ndarray] = []
        inclination: list[np.ndarray] = []
        for t, gammas in enumerate(banks):
            gamma = as_design(gammas, f"banks[{t}]")
            if gamma.ndim > 1:
                raise MechanismError(f"banks[{t}] must be a 1-D array of inclinations [rad], got shape {gamma.shape}")
            gamma = gamma.reshape(-1)
            phase.append(beta[t] - gamma)
            inclination.append(gamma)
        if not sum(g.size for g in inclination):
            raise MechanismError("banks hold no cylinder: an engine needs at least one unit")
        return cls(
            phase=np.concatenate(phase),
            inclination=np.concatenate(inclination),
            crank_ratio=crank_ratio,
            u1=u1,
            u2=u2,
            name=name,
        )

    def replace(self, **changes) -> Engine:
        """A copy with some columns (or the name) replaced."""
        columns = {k: changes.pop(k, v) for k, v in self._columns.items()}
        name = changes.pop("name", self.name)
        if changes:
            raise MechanismError(f"unknown engine field(s) {', '.join(changes)}; known: {', '.join(_FIELDS)}")
        return Engine(**columns, name=name)

    # -- description --------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self._columns["phase"])

    def __getattr__(self, name: str) -> np.ndarray:
        if name in _FIELDS:
            return self._columns[name]
        raise AttributeError(name)

    def __repr__(self) -> str:
        return f"Engine({self.name!r}, {len(self)} units)"

    def columns(self) -> dict[str, np.ndarray]:
        """The units' columns (read-only float64 arrays), keyed by field name."""
        return self._columns

    def to_frame(self):
        """The units as a pandas DataFrame (angles in radians)."""
        import pandas as pd

        return pd.DataFrame(self._columns)

    # -- evaluation ---------------------------------------------------------------------
    def _evaluate(self, quantity: str, phi: Any):
        phi_shape, angles = as_phi(phi)
        flat = _native_engine_evaluate(quantity, angles, self.columns())
        return finish(flat, phi_shape)

    def potential_energy(self, phi: Any):
        """U_w*(φ) = Σ_j U*_j(φ + α_j), each unit from its own ψ = 0 position; shape of φ."""
        return self._evaluate("potential_energy", phi)

    def generalized_force(self, phi: Any, method: str = "exact"):
        """Q_u*(φ) = dU_w*/dφ: "exact" (closed form) or "series" (machine-precision Fourier form)."""
        method = as_option(method, "method", ("exact", "series"))
        return self._evaluate("generalized_force" if method == "exact" else "series", phi)

    def force_derivative(self, phi: Any):
        """dQ_u*/dφ, closed form."""
        return self._evaluate("force_derivative", phi)

    def fourier_coefficients(self, n_max: int = 24) -> tuple[np.ndarray, np.ndarray]:
        """(a, b): Q_u*(φ) = Σ_{n ≤ n_max} a_n cos nφ + b_n sin nφ, exact Λ_n.

        a_1 = Σ_j N_j cos α_j + W1_j sin α_j, b_1 = Σ_j W1_j cos α_j − N_j sin α_j, and for even
        n a_n = Σ_j W_nj sin nα_j, b_n = Σ_j W_nj cos nα_j, W_nj = −u1_j sin γ_j Λ_n(λ_j); a sum
        below its rounding noise is exactly 0 (the harmonic cancelled).
        """
        n_max = as_count(n_max, "n_max", minimum=0)
        check_size("n_max", n_max, 2 * (n_max + 1))
        coefficients = _native_engine_fourier(self.columns(), n_max)
        return coefficients["a"], coefficients["b"]

    def surviving_harmonics(self, n_max: int = 24) -> list[int]:
        """The harmonics n ≤ n_max of Q_u* that do not cancel (numerically, from the weighted
        phase sums; a cancelled sum is below its own rounding noise)."""
        a, b = self.fourier_coefficients(n_max)
        return [int(n) for n in np.flatnonzero(np.hypot(a, b) > 0)]

    def leading_harmonic(self) -> tuple[int, float]:
        """(n, amplitude √(a_n² + b_n²)) of the largest harmonic of Q_u*; (0, 0) if Q ≡ 0.

        Every harmonic of the machine-precision series is considered: the same as a sweep's
        ``leading_harmonic``."""
        leading = _native_engine_leading_harmonic(self.columns())
        return int(leading["n"]), float(leading["amplitude"])

    def energy_extrema(self):
        """The exact extrema of U_w* over a revolution (see :func:`multicrank.energy_extrema`)."""
        return EnergyExtrema(**{k: np.float64(v) for k, v in _native_engine_extrema(self.columns()).items()})

    def speed_fluctuation(self) -> np.float64:
        """δ_g = max U_w* − min U_w* over a revolution, from the exact extrema."""
        return self.energy_extrema().range

    # -- tolerances ---------------------------------------------------------------------
    def harmonic_sensitivity(self, *, u1_rel: float = 0.0, u2_rel: float = 0.0, phase: float = 0.0, n_max: int = 24):
        """First-order scatter of every harmonic of Q_u* under independent random errors of
        the units: relative standard deviations ``u1_rel``, ``u2_rel`` of u1_j, u2_j (unequal
        masses) and a standard deviation ``phase`` [rad] of α_j (phase errors).

        For harmonic n, c_n = a_n + i b_n is linear in u1_j, u2_j and depends on α_j through
        e^{±inα_j}, so to first order E|δc_n|² = Σ_j |∂c_n/∂u1_j|² (u1_rel u1_j)² +
        |∂c_n/∂u2_j|² (u2_rel u2_j)² + |∂c_n/∂α_j|² phase². Harmonics that cancel for identical
        cylinders come back with about this rms amplitude.

        Returns a pandas DataFrame indexed by n: ``amplitude`` (nominal) and ``scatter_rms``.
        """
        import pandas as pd

        n_max = as_count(n_max, "n_max", minimum=1)
        check_size("n_max", n_max, 2 * (n_max + 1))
        u1_rel, u2_rel, phase = _scatter(u1_rel, u2_rel, phase)
        rows = _native_engine_sensitivity(self.columns(), u1_rel, u2_rel, phase, n_max)
        n = rows.pop("n").astype(np.int64)
        return pd.DataFrame(rows, index=pd.Index(n, name="n"))

    def perturbed(
        self, rng: np.random.Generator, *, u1_rel: float = 0.0, u2_rel: float = 0.0, phase: float = 0.0
    ) -> Engine:
        """A random sample of this engine with the errors of :meth:`harmonic_sensitivity`,
        drawn from ``rng`` (a :class:`numpy.random.Generator`, e.g. ``np.random.default_rng(1)``)."""
        if not isinstance(rng, np.random.Generator):
            raise MechanismError(
                f"rng must be a numpy.random.Generator (np.random.default_rng(seed)), got {type(rng).__name__}"
            )
        u1_rel, u2_rel, phase = _scatter(u1_rel, u2_rel, phase)
        size = len(self)
        return self.replace(
            u1=self.u1 * (1 + u1_rel * rng.standard_normal(size)),
            u2=self.u2 * (1 + u2_rel * rng.standard_normal(size)),
            phase=self.phase + phase * rng.standard_normal(size),
        )


def _scatter(u1_rel: Any, u2_rel: Any, phase: Any) -> tuple[float, float, float]:
    """The standard deviations of the tolerance model: finite and ≥ 0 (a NaN would give NaN)."""
    return as_nonnegative(u1_rel, "u1_rel"), as_nonnegative(u2_rel, "u2_rel"), as_nonnegative(phase, "phase")
