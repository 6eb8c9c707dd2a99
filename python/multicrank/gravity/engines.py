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
from typing import TYPE_CHECKING, Any

import numpy as np

from .._broadcasting import as_design, finish
from .._native import engine_evaluate as _native_engine_evaluate
from .._native import engine_extrema as _native_engine_extrema
from .._native import engine_fourier as _native_engine_fourier
from .._native import engine_leading_harmonic as _native_engine_leading_harmonic
from .._text import counted
from .._validation import as_count, as_label, as_option, check_size, contiguous, part_of, refused
from .extrema import EnergyExtrema
from .grids import as_phi
from .mechanism import crank_phases
from .tolerances import harmonic_sensitivity as _harmonic_sensitivity
from .tolerances import perturbed as _perturbed

if TYPE_CHECKING:  # pandas is imported where a table is made, not with multicrank
    import pandas as pd

__all__ = ["Engine"]

_FIELDS = ("phase", "inclination", "crank_ratio", "u1", "u2")


class Engine:
    """A machine of any layout as a list of crank units (dimensionless, angles in radians).

    Unit j's crank angle is ψ_j = φ + α_j from its own outer dead centre, its cylinder is
    inclined at γ_j, and it has its own crank ratio and gravity moments. The five columns
    broadcast to one 1-D length, the number of units; ``len(engine)`` is that number.

    Parameters
    ----------
    phase : array_like
        α_j [rad]: each unit's crank angle is ψ_j = φ + α_j.
    inclination : array_like
        γ_j [rad]: each unit's cylinder axis to the horizontal (+π/2 upright).
    crank_ratio : array_like
        λ_j [dimensionless], 0 ≤ λ < 1.
    u1, u2 : array_like
        The units' dimensionless gravity moments [dimensionless] (see
        :func:`dimensionless_moments`); a unit with u1 = 0 is a purely rotating mass (a
        crank web or counterweight).
    name : str, default "engine"
        A label.

    Attributes
    ----------
    phase, inclination, crank_ratio, u1, u2 : ndarray
        The columns, read-only float64 arrays of one entry per unit (angles [rad], the rest
        dimensionless).
    name : str
        The label.

    See Also
    --------
    Layout.engine, layout_engine : An engine of a built-in or own layout.
    Machine.engine : The engine of a physical machine at a speed.

    Examples
    --------
    >>> import numpy as np
    >>> import multicrank as mc
    >>> v8 = mc.layout_engine("v8-cross", crank_ratio=0.3, u1=1e-3, u2=2e-4)
    >>> v8
    Engine('v8-cross', 8 units)
    >>> v8.surviving_harmonics(12)
    [4, 8, 12]
    >>> print(f"δ_g = {v8.speed_fluctuation():.6e}")
    δ_g = 5.117823e-06
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
                raise refused(key, f"{key} must be a scalar or 1-D (one entry per unit), got shape {column.shape}")
        lengths = {key: column.shape[0] for key, column in columns.items() if column.ndim == 1}
        sizes = set(lengths.values()) - {1}
        if len(sizes) > 1:
            listed = ", ".join(f"{key} has {n}" for key, n in lengths.items())
            sized = [key for key, n in lengths.items() if n != 1]
            mismatched = next(key for key in sized if lengths[key] != lengths[sized[0]])
            raise refused(mismatched, f"engine columns do not broadcast to one length (the number of units): {listed}")
        length = sizes.pop() if sizes else 1
        if length == 0:
            empty = [key for key, n in lengths.items() if n == 0]
            raise refused(empty[0], f"{', '.join(empty)}: an engine needs at least one unit, got an empty column")
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
        crank_ratio: Any,
        inclination: Any,
        u1: Any,
        u2: Any,
        name: str | None = None,
    ) -> Engine:
        """A regular in-line machine: identical units at α_j = j·α (docs/theory.md, "Crank phases").

        Parameters
        ----------
        cranks : int
            The number of cranks k, ≥ 1.
        strokes : {2, 4}, default 2
            The working cycle (see :func:`crank_phases`).
        acting : {"single", "double"}, default "single"
            Single- or double-acting cylinders.
        crank_ratio : float
            λ [dimensionless], 0 ≤ λ < 1.
        inclination : float
            γ [rad], the cylinder axis to the horizontal (+π/2 upright).
        u1, u2 : float
            The dimensionless gravity moments [dimensionless] of each unit.
        name : str, optional
            A label; by default e.g. "inline-4 2-stroke single-acting".

        Returns
        -------
        Engine
            k units at the phases of :func:`crank_phases`.

        Examples
        --------
        >>> import numpy as np
        >>> import multicrank as mc
        >>> mc.Engine.inline(3, crank_ratio=0.25, inclination=np.pi / 2, u1=1e-3, u2=2e-4)
        Engine('inline-3 2-stroke single-acting', 3 units)
        """
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
        crank_ratio: Any,
        u1: Any,
        u2: Any,
        name: str = "engine",
    ) -> Engine:
        """Cylinders on crank throws: V, W, boxer and odd-fire machines.

        Throw t's crank pin is at the absolute angle φ + β_t and carries one cylinder per
        inclination in ``banks[t]``; each cylinder's phase is α = β_t − γ.

        Parameters
        ----------
        throws : array_like
            β_t [rad], 1-D: the throws' pin angles at φ = 0.
        banks : sequence of array_like
            One 1-D array of inclinations γ [rad] per throw: the cylinders on that throw.
        crank_ratio : float or array_like
            λ [dimensionless] per cylinder (a scalar, or one per cylinder in the cylinders'
            order: throw by throw, bank by bank).
        u1, u2 : float or array_like
            The dimensionless gravity moments [dimensionless] per cylinder, likewise.
        name : str, default "engine"
            A label.

        Returns
        -------
        Engine
            One unit per cylinder, throw by throw and bank by bank.

        Examples
        --------
        A 90° V-twin, both cylinders on one pin:

        >>> import numpy as np
        >>> import multicrank as mc
        >>> twin = mc.Engine.from_throws(np.radians([90]), [np.radians([45, 135])],
        ...                              crank_ratio=0.25, u1=1e-3, u2=0.0, name="v-twin")
        >>> np.degrees(twin.phase), np.degrees(twin.inclination)
        (array([ 45., -45.]), array([ 45., 135.]))
        """
        beta, banks_checked = as_throws(throws, banks)
        phase = [beta[t] - gamma for t, gamma in enumerate(banks_checked)]
        inclination = banks_checked
        return cls(
            phase=np.concatenate(phase),
            inclination=np.concatenate(inclination),
            crank_ratio=crank_ratio,
            u1=u1,
            u2=u2,
            name=name,
        )

    def replace(self, **changes: Any) -> Engine:
        """A copy with some columns (or the name) replaced.

        Parameters
        ----------
        **changes
            New values for ``phase``, ``inclination``, ``crank_ratio``, ``u1``, ``u2`` (as
            for :class:`Engine`) or ``name``.

        Returns
        -------
        Engine
            The changed copy.
        """
        columns = {k: changes.pop(k, v) for k, v in self._columns.items()}
        name = changes.pop("name", self.name)
        if changes:
            raise refused(
                next(iter(changes)), f"unknown engine field(s) {', '.join(changes)}; known: {', '.join(_FIELDS)}"
            )
        return Engine(**columns, name=name)

    # -- description --------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self._columns["phase"])

    def __getattr__(self, name: str) -> np.ndarray:
        if name in _FIELDS:
            return self._columns[name]
        raise AttributeError(name)

    def __repr__(self) -> str:
        return f"Engine({self.name!r}, {counted(len(self), 'unit')})"

    def __eq__(self, other: object) -> bool:
        # By value: the same name and the same columns (finite, so no NaN to care about).
        if not isinstance(other, Engine):
            return NotImplemented
        return self.name == other.name and all(np.array_equal(self._columns[k], other._columns[k]) for k in _FIELDS)

    # Not hashable: the name may be set, and a hash must not change.
    __hash__ = None  # type: ignore[assignment]

    def columns(self) -> dict[str, np.ndarray]:
        """The units' columns, keyed by field name.

        Returns
        -------
        dict of str to ndarray
            ``phase``, ``inclination`` [rad], ``crank_ratio``, ``u1`` and ``u2``: read-only
            float64 arrays, one entry per unit.
        """
        return self._columns

    def to_frame(self) -> pd.DataFrame:
        """The units as a table.

        Returns
        -------
        pandas.DataFrame
            One row per unit, the columns of :meth:`columns` (angles in radians).
        """
        import pandas as pd

        return pd.DataFrame(self._columns)

    # -- evaluation ---------------------------------------------------------------------
    def _evaluate(self, quantity: str, phi: Any) -> Any:
        phi_shape, angles = as_phi(phi)
        flat = _native_engine_evaluate(quantity, angles, self.columns())
        return finish(flat, phi_shape)

    def potential_energy(self, phi: Any) -> Any:
        """U_w*(φ) = Σ_j U*_j(φ + α_j), each unit from its own ψ = 0 position.

        Parameters
        ----------
        phi : array_like or UniformGrid
            Crank angle φ [rad]; any shape.

        Returns
        -------
        ndarray or numpy.float64
            U_w* [dimensionless], the shape of ``phi``.
        """
        return self._evaluate("potential_energy", phi)

    def generalized_force(self, phi: Any, method: str = "exact") -> Any:
        """Q_u*(φ) = dU_w*/dφ.

        Parameters
        ----------
        phi : array_like or UniformGrid
            Crank angle φ [rad]; any shape.
        method : {"exact", "series"}, default "exact"
            The closed form, or the Fourier form to machine precision (as for
            :func:`generalized_force`).

        Returns
        -------
        ndarray or numpy.float64
            Q_u* [dimensionless], the shape of ``phi``.
        """
        method = as_option(method, "method", ("exact", "series"))
        return self._evaluate("generalized_force" if method == "exact" else "series", phi)

    def force_derivative(self, phi: Any) -> Any:
        """dQ_u*/dφ, closed form.

        Parameters
        ----------
        phi : array_like or UniformGrid
            Crank angle φ [rad]; any shape.

        Returns
        -------
        ndarray or numpy.float64
            dQ_u*/dφ [dimensionless], the shape of ``phi``.
        """
        return self._evaluate("force_derivative", phi)

    def fourier_coefficients(self, n_max: int = 24) -> tuple[np.ndarray, np.ndarray]:
        """(a, b): Q_u*(φ) = Σ_{n ≤ n_max} a_n cos nφ + b_n sin nφ, exact Λ_n.

        a_1 = Σ_j N_j cos α_j + W1_j sin α_j, b_1 = Σ_j W1_j cos α_j − N_j sin α_j, and for even
        n a_n = Σ_j W_nj sin nα_j, b_n = Σ_j W_nj cos nα_j, W_nj = −u1_j sin γ_j Λ_n(λ_j); a sum
        below its rounding noise is exactly 0 (the harmonic cancelled).

        Parameters
        ----------
        n_max : int, default 24
            The highest harmonic, ≥ 0.

        Returns
        -------
        a, b : ndarray
            The cosine and sine coefficients [dimensionless], shape (n_max + 1,).
        """
        n_max = as_count(n_max, "n_max", minimum=0)
        check_size("n_max", n_max, 2 * (n_max + 1))
        coefficients = _native_engine_fourier(self.columns(), n_max)
        return coefficients["a"], coefficients["b"]

    def surviving_harmonics(self, n_max: int = 24) -> list[int]:
        """The harmonics n ≤ n_max of Q_u* that do not cancel.

        Decided numerically, from the weighted phase sums: a cancelled sum is below its own
        rounding noise and taken as 0.

        Parameters
        ----------
        n_max : int, default 24
            The highest harmonic considered, ≥ 0.

        Returns
        -------
        list of int
            The surviving harmonics, ascending.
        """
        a, b = self.fourier_coefficients(n_max)
        return [int(n) for n in np.flatnonzero(np.hypot(a, b) > 0)]

    def leading_harmonic(self) -> tuple[int, float]:
        """The largest harmonic of Q_u* and its amplitude.

        Every harmonic of the machine-precision series is considered: the same as a sweep's
        ``leading_harmonic``.

        Returns
        -------
        n : int
            The harmonic; 0 if Q_u* ≡ 0.
        amplitude : float
            √(a_n² + b_n²) [dimensionless]; 0 if Q_u* ≡ 0.
        """
        leading = _native_engine_leading_harmonic(self.columns())
        return int(leading["n"]), float(leading["amplitude"])

    def energy_extrema(self) -> EnergyExtrema:
        """The exact extrema of U_w* over a revolution (see :func:`multicrank.energy_extrema`).

        Returns
        -------
        EnergyExtrema
            ``min``, ``min_at`` [rad], ``max``, ``max_at`` [rad] and ``range`` (δ_g), as numpy
            float64 scalars.
        """
        return EnergyExtrema(**{k: np.float64(v) for k, v in _native_engine_extrema(self.columns()).items()})

    def speed_fluctuation(self) -> np.float64:
        """δ_g = max U_w* − min U_w* over a revolution, from the exact extrema.

        Returns
        -------
        numpy.float64
            δ_g [dimensionless], the gravity part of the coefficient of speed fluctuation.
        """
        return np.float64(self.energy_extrema().range)

    # -- tolerances: written, with their documentation, in multicrank.gravity.tolerances --

    harmonic_sensitivity = _harmonic_sensitivity
    perturbed = _perturbed


def as_throws(throws: Any, banks: Any) -> tuple[np.ndarray, list[np.ndarray]]:
    """Throw angles and per-throw bank inclinations, checked (by those names) and returned as
    a 1-D array and one 1-D array per throw; at least one cylinder in all. Unit-agnostic: the
    layouts keep them in degrees, :meth:`Engine.from_throws` takes radians."""
    beta = as_design(throws, "throws")
    if beta.ndim != 1:
        raise refused("throws", f"throws must be a 1-D array of angles, got shape {beta.shape}")
    if isinstance(banks, (str, bytes, Mapping)) or not isinstance(banks, (Sequence, np.ndarray)):
        raise refused(
            "banks", f"banks must be a sequence with one array of inclinations per throw, got {type(banks).__name__}"
        )
    if len(banks) != len(beta):
        raise refused("banks", f"banks has {len(banks)} entries but throws {len(beta)}: one per throw")
    checked = []
    for t, gammas in enumerate(banks):
        with part_of("banks"):
            gamma = as_design(gammas, f"banks[{t}]")
        if gamma.ndim > 1:
            raise refused("banks", f"banks[{t}] must be a 1-D array of inclinations, got shape {gamma.shape}")
        checked.append(gamma.reshape(-1))
    if not sum(g.size for g in checked):
        raise refused("banks", "banks hold no cylinder: an engine needs at least one unit")
    return beta, checked
