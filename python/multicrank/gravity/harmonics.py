"""Harmonics of Q_u*: Λ_n, the surviving harmonics, the paper's Tables 1–2 and the Fourier
coefficients of any machine (docs/theory.md, "Fourier form and Λ_n" and "Which harmonics
survive")."""

from __future__ import annotations

import math
from fractions import Fraction
from typing import TYPE_CHECKING, Any

import numpy as np

from .._broadcasting import as_design, as_phases, broadcast_designs, broadcast_shape, design_keywords
from .._native import fourier_coefficients as _native_fourier_coefficients
from .._native import lambda_coefficients as _native_lambda_coefficients
from .._native import paper_coefficient as _native_paper_coefficient
from .._native import surviving_harmonics as _native_surviving_harmonics
from .._validation import as_count, as_option, as_strokes, check_size, contiguous

if TYPE_CHECKING:  # pandas is imported where a table is made, not with multicrank
    import pandas as pd

__all__ = [
    "fourier_coefficients",
    "harmonic_table",
    "lambda_coefficients",
    "paper_coefficient",
    "surviving_harmonics",
]

_U32_MAX = 2**32 - 1


def lambda_coefficients(crank_ratio: Any, n_max: int, method: str = "exact") -> np.ndarray:
    r"""Λ_0 … Λ_{n_max}: the sine coefficients of f(ψ) = (λ/2) sin 2ψ / √(1 − λ² sin² ψ).

    .. math::

        f(\psi) = \sum_{n=2,4,\dots} \Lambda_n(\lambda) \sin n\psi, \qquad
        \Lambda_{2m} = 2m\binom{1/2}{m} t^{2m-1}\,
            {}_2F_1\!\left(-\tfrac12, m-\tfrac12; m+1; t^4\right),\quad
        t = \frac{\lambda}{1 + \sqrt{1-\lambda^2}}.

    Λ_0 and the odd entries are 0; the sign of Λ_{2m} is (−1)^{m−1}.

    Parameters
    ----------
    crank_ratio : array_like
        λ [dimensionless], 0 ≤ λ < 1; any shape.
    n_max : int
        The highest index returned, ≥ 0.
    method : {"exact", "paper"}, default "exact"
        ``"exact"``: the closed form above (t and t^{2m−1} in double-double, ≤ ~1e-15·n
        relative). ``"paper"``: eq. (15), the λ-series through λ¹¹ with exact rational
        coefficients (:func:`paper_coefficient`), harmonics n ≤ 12; entries above 12 are 0,
        as the paper cuts there.

    Returns
    -------
    ndarray
        Λ_n [dimensionless], shape λ.shape + (n_max + 1,): entry n is Λ_n.

    Examples
    --------
    >>> import multicrank as mc
    >>> exact = mc.lambda_coefficients(0.3, 6)
    >>> paper = mc.lambda_coefficients(0.3, 6, method="paper")
    >>> for n in (2, 4, 6):
    ...     print(f"Λ_{n} = {exact[n]:+.10e} (paper: {paper[n]:+.10e})")
    Λ_2 = +1.5352532953e-01 (paper: +1.5352532751e-01)
    Λ_4 = -1.8094237492e-03 (paper: -1.8094210395e-03)
    Λ_6 = +3.1989457773e-05 (paper: +3.1987411055e-05)
    """
    lam = as_design(crank_ratio, "crank_ratio", low=0.0, high=1.0)
    n_max = as_count(n_max, "n_max", minimum=0)
    method = as_option(method, "method", ("exact", "paper"))
    check_size("n_max", n_max, lam.size * (n_max + 1))
    flat = _native_lambda_coefficients(contiguous(lam).reshape(-1), n_max, method)
    return flat.reshape((*lam.shape, n_max + 1))


def paper_coefficient(i: int, j: int) -> Fraction:
    """The exact rational coefficient of λ^{2j+1} in the paper's series of Λ_{2i}.

    Eq. (15): (−1)^{i+1} · (2i/(j+1)) · C(2j, j) · C(2j+2, j+1−i) / 4^{2j+1}, and 0 for
    j < i − 1.

    Parameters
    ----------
    i : int
        The harmonic's half index, ≥ 1 (Λ_{2i}).
    j : int
        The power's index, ≥ 0 (λ^{2j+1}), at most the paper's order (j ≤ 5, λ¹¹).

    Returns
    -------
    fractions.Fraction
        The coefficient, exactly.

    Examples
    --------
    Λ_2 = λ/2 + λ³/8 + …, Λ_4 = −λ³/16 − …:

    >>> import multicrank as mc
    >>> [mc.paper_coefficient(i, j) for i, j in [(1, 0), (1, 1), (2, 1)]]
    [Fraction(1, 2), Fraction(1, 8), Fraction(-1, 16)]
    """
    # The core takes 32-bit indices (and refuses j above the paper's λ¹¹ order itself).
    i = as_count(i, "i", minimum=1, maximum=_U32_MAX)
    j = as_count(j, "j", minimum=0, maximum=_U32_MAX)
    numerator, denominator = _native_paper_coefficient(i, j)
    return Fraction(numerator, denominator)


def surviving_harmonics(cranks: int, strokes: int = 2, acting: str = "single", n_max: int = 24) -> list[int]:
    """The harmonics n ≤ n_max of Q_u* that survive the sum over a regular crank set
    (docs/theory.md, "Which harmonics survive").

    Only n = 1 (the N and W1 terms) and even n (the W_n terms) carry coefficients; each
    survives when its phase sum S_n = Σ_j e^{inα_j} is non-zero. With α = 2πp/q the sum is
    k when q | np and zero when q ∤ np but q | npk — decided in exact integer arithmetic.

    Parameters
    ----------
    cranks : int
        The number of cranks k, ≥ 1.
    strokes : {2, 4}, default 2
        The working cycle (see :func:`crank_phases`).
    acting : {"single", "double"}, default "single"
        Single- or double-acting cylinders.
    n_max : int, default 24
        The highest harmonic considered, ≥ 0.

    Returns
    -------
    list of int
        The surviving harmonics, ascending.

    See Also
    --------
    harmonic_table : The same for k = 1 … k_max as a table.
    Engine.surviving_harmonics : The same for any layout, numerically.

    Examples
    --------
    >>> import multicrank as mc
    >>> mc.surviving_harmonics(6, strokes=4)
    [6, 12, 18, 24]
    >>> mc.surviving_harmonics(1, n_max=8)
    [1, 2, 4, 6, 8]
    """
    n_max = as_count(n_max, "n_max", minimum=0)
    harmonics = _native_surviving_harmonics(
        as_count(cranks, "cranks", minimum=1),
        as_strokes(strokes),
        as_option(acting, "acting", ("single", "double")),
        n_max,
    )
    # A list holds a pointer and an int object (~40 bytes) per harmonic: 5x the array.
    check_size("n_max", n_max, len(harmonics), item_bytes=40)
    return harmonics.tolist()


def harmonic_table(strokes: int = 2, acting: str = "single", k_max: int = 12, n_max: int = 12) -> pd.DataFrame:
    """Which W_n are non-zero for k = 1 … k_max cranks: the paper's Table 1 and its kin.

    Two-stroke single-acting is the paper's Table 1, four-stroke single-acting its
    unprinted Table 2; ``acting="double"`` gives the double-acting tables.

    Parameters
    ----------
    strokes : {2, 4}, default 2
        The working cycle.
    acting : {"single", "double"}, default "single"
        Single- or double-acting cylinders.
    k_max : int, default 12
        The largest number of cranks, ≥ 1.
    n_max : int, default 12
        The highest harmonic, ≥ 1.

    Returns
    -------
    pandas.DataFrame
        Booleans: rows n (1 and the even n ≤ n_max, index "n"), columns k = 1 … k_max
        (named "k"); True where harmonic n survives the sum over k cranks.

    Examples
    --------
    >>> import multicrank as mc
    >>> mc.harmonic_table(strokes=2, k_max=6, n_max=8).astype(int)
    k  1  2  3  4  5  6
    n
    1  1  0  0  0  0  0
    2  1  1  0  0  0  0
    4  1  1  0  1  0  0
    6  1  1  1  0  0  1
    8  1  1  0  1  0  0
    """
    import pandas as pd

    strokes = as_strokes(strokes)
    acting = as_option(acting, "acting", ("single", "double"))
    k_max = as_count(k_max, "k_max", minimum=1)
    n_max = as_count(n_max, "n_max", minimum=1)
    check_size("n_max", n_max, n_max // 2 + 1, item_bytes=8)
    check_size("k_max", k_max, (n_max // 2 + 1) * k_max, item_bytes=1)
    rows = [1, *list(range(2, n_max + 1, 2))]
    table = pd.DataFrame(
        False, index=pd.Index(rows, name="n"), columns=pd.Index(range(1, k_max + 1), name="k"), dtype=bool
    )
    for k in range(1, k_max + 1):
        surviving = set(surviving_harmonics(k, strokes, acting, n_max))
        table[k] = [n in surviving for n in rows]
    return table


def fourier_coefficients(
    *, crank_ratio: Any, inclination: Any, u1: Any, u2: Any, phases: Any = None, n_max: int = 24
) -> tuple[np.ndarray, np.ndarray]:
    """Fourier coefficients of Q_u*(φ) = Σ_{n=0}^{n_max} a_n cos nφ + b_n sin nφ, exact Λ_n.

    Per unit Q = N cos ψ + W1 sin ψ + Σ_{n even} W_n sin nψ with N = U2 cos γ,
    N1 = −U1 sin γ, N2 = −U2 sin γ, W1 = N1 + N2, W_n = N1 Λ_n (eq. 14); summed over the
    cranks with C_n + iS_n = Σ_j e^{inα_j}::

        a_1 = N C_1 + W1 S_1,  b_1 = W1 C_1 − N S_1,  a_n = W_n S_n,  b_n = W_n C_n (n even).

    Works for any phase set; a phase sum below its rounding noise is taken as exactly 0
    (the harmonic has cancelled). a_0 = 0 and the odd a_n, b_n above n = 1 are 0.

    Parameters
    ----------
    crank_ratio : array_like
        λ = r/l [dimensionless], 0 ≤ λ < 1.
    inclination : array_like
        γ [rad], the cylinder axis to the horizontal (+π/2 upright).
    u1, u2 : array_like
        The dimensionless gravity moments [dimensionless], see :func:`dimensionless_moments`.
    phases : array_like, optional
        The crank phases α_j [rad], 1-D; None means one crank at 0.
    n_max : int, default 24
        The highest harmonic, ≥ 0.

    Returns
    -------
    a, b : ndarray
        The cosine and sine coefficients [dimensionless], each of shape D + (n_max + 1,)
        (D: the broadcast shape of the design keywords); entry n is harmonic n.

    Examples
    --------
    An upright in-line three (two-stroke): only the third harmonics of the crank-rod term
    survive, n = 6 and 12.

    >>> import numpy as np
    >>> import multicrank as mc
    >>> a, b = mc.fourier_coefficients(crank_ratio=0.25, inclination=np.pi / 2, u1=1e-3,
    ...                                u2=2e-4, phases=mc.crank_phases(3), n_max=12)
    >>> [int(n) for n in np.flatnonzero(np.hypot(a, b))]
    [6, 12]
    >>> print(f"b_6 = {b[6]:.6e}")
    b_6 = -3.718952e-08
    """
    keywords = design_keywords(crank_ratio, inclination, u1, u2)
    n_max = as_count(n_max, "n_max", minimum=0)
    designs = math.prod(broadcast_shape("design parameters", keywords))
    check_size("n_max", n_max, 2 * designs * (n_max + 1))
    shape, design = broadcast_designs(**keywords)
    coefficients = _native_fourier_coefficients(design, as_phases(phases), n_max)
    width = (n_max + 1,)
    return coefficients["a"].reshape(shape + width), coefficients["b"].reshape(shape + width)
