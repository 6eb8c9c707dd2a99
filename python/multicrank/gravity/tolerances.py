"""An engine's tolerances: the first-order scatter of its gravity harmonics under random errors
of its units (:meth:`Engine.harmonic_sensitivity`), and random samples of those errors
(:meth:`Engine.perturbed`). Written here, with their documentation; :class:`Engine` takes them
as methods."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._native import engine_sensitivity as _native_engine_sensitivity
from .._validation import as_count, as_nonnegative, check_size, refused

if TYPE_CHECKING:  # pandas is imported where a table is made, not with multicrank
    import pandas as pd

    from .engines import Engine

__all__ = ["harmonic_sensitivity", "perturbed"]


def harmonic_sensitivity(
    self: Engine, *, u1_rel: float = 0.0, u2_rel: float = 0.0, phase: float = 0.0, n_max: int = 24
) -> pd.DataFrame:
    r"""First-order scatter of every harmonic of Q_u* under random errors of the units.

    The errors are independent: relative standard deviations ``u1_rel``, ``u2_rel`` of
    u1_j, u2_j (unequal masses) and a standard deviation ``phase`` of α_j (phase errors).
    For harmonic n, c_n = a_n + i b_n is linear in u1_j, u2_j and depends on α_j through
    e^{±inα_j}, so to first order

    .. math::

        E|\delta c_n|^2 = \sum_j \left|\frac{\partial c_n}{\partial u_{1j}}\right|^2
            (\sigma_1 u_{1j})^2 + \left|\frac{\partial c_n}{\partial u_{2j}}\right|^2
            (\sigma_2 u_{2j})^2 + \left|\frac{\partial c_n}{\partial \alpha_j}\right|^2
            \sigma_\alpha^2

    with σ_1 = ``u1_rel``, σ_2 = ``u2_rel`` and σ_α = ``phase``. Harmonics that cancel for
    identical cylinders come back with about this rms amplitude.

    Parameters
    ----------
    u1_rel, u2_rel : float, default 0
        The relative standard deviations of u1_j and u2_j [dimensionless], ≥ 0.
    phase : float, default 0
        The standard deviation of α_j [rad], ≥ 0.
    n_max : int, default 24
        The highest harmonic, ≥ 1.

    Returns
    -------
    pandas.DataFrame
        Indexed by n (1 and the even n ≤ n_max): ``amplitude``, the nominal
        √(a_n² + b_n²), and ``scatter_rms``, the rms of its first-order change
        [dimensionless].

    See Also
    --------
    perturbed : One random sample of these errors.

    Examples
    --------
    A cross-plane V8 with 2 % scatter of the reciprocating masses and 0.2° of the phases:
    the cancelled first and second harmonics come back.

    >>> import numpy as np
    >>> import multicrank as mc
    >>> v8 = mc.layout_engine("v8-cross", crank_ratio=0.3, u1=1e-3, u2=2e-4)
    >>> table = v8.harmonic_sensitivity(u1_rel=0.02, phase=np.radians(0.2), n_max=4)
    >>> print(table.to_string(float_format=lambda v: f"{v:.3e}"))
      amplitude scatter_rms
    n
    1 0.000e+00   4.089e-05
    2 0.000e+00   6.504e-06
    4 1.024e-05   8.827e-08
    """
    import pandas as pd

    n_max = as_count(n_max, "n_max", minimum=1)
    check_size("n_max", n_max, 2 * (n_max + 1))
    u1_rel, u2_rel, phase = _scatter(u1_rel, u2_rel, phase)
    rows = _native_engine_sensitivity(self.columns(), u1_rel, u2_rel, phase, n_max)
    n = rows.pop("n").astype(np.int64)
    return pd.DataFrame(rows, index=pd.Index(n, name="n"))


def perturbed(
    self: Engine, rng: np.random.Generator, *, u1_rel: float = 0.0, u2_rel: float = 0.0, phase: float = 0.0
) -> Engine:
    """A random sample of this engine with the errors of :meth:`harmonic_sensitivity`.

    Parameters
    ----------
    rng : numpy.random.Generator
        The random numbers, e.g. ``np.random.default_rng(1)``.
    u1_rel, u2_rel : float, default 0
        The relative standard deviations of u1_j and u2_j [dimensionless], ≥ 0.
    phase : float, default 0
        The standard deviation of α_j [rad], ≥ 0.

    Returns
    -------
    Engine
        A copy with u1_j·(1 + u1_rel·ξ), u2_j·(1 + u2_rel·ξ′) and α_j + phase·ξ″, the ξ
        independent standard normal numbers.

    Examples
    --------
    A Monte-Carlo of tolerances: 1000 samples of an in-line three, swept at once.

    >>> import numpy as np
    >>> import multicrank as mc
    >>> three = mc.Engine.inline(3, crank_ratio=0.25, inclination=np.pi / 2,
    ...                          u1=1e-3, u2=2e-4)
    >>> rng = np.random.default_rng(1)
    >>> samples = [three.perturbed(rng, u1_rel=0.02) for _ in range(1000)]
    >>> result = mc.sweep(samples, outputs=["energy_range"])
    >>> print(f"δ_g: nominal {three.speed_fluctuation():.2e}, "
    ...       f"95th percentile {result['energy_range'].quantile(0.95):.2e}")
    δ_g: nominal 1.24e-08, 95th percentile 1.21e-04
    """
    if not isinstance(rng, np.random.Generator):
        raise refused(
            "rng", f"rng must be a numpy.random.Generator (np.random.default_rng(seed)), got {type(rng).__name__}"
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
