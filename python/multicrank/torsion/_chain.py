"""The free–free torsional chain's modes to the precision its numbers hold (:meth:`Shaft.modes
<multicrank.Shaft.modes>`).

The chain of inertias J_i [kg·m²] joined by stiffnesses k_i [N·m/rad] has the modes K a = Ω² J a
(J = diag(J_i), K tridiagonal: K_ii = k_{i−1} + k_i, K_{i,i+1} = −k_i). A symmetric eigen solver
— of the pencil (K, J) or of the tridiagonal J^{−1/2} K J^{−1/2} — finds each Ω² to within a few
ε of the largest: an absolute accuracy. A mode far below the largest keeps only the digits left
over (a light node between stiff sections beside a soft one; a long chain's lowest modes), and
the rigid mode's 0 and a small elastic Ω² blur into each other. The chain's numbers themselves
fix every Ω² to a relative precision: ∂ ln Ω²/∂ ln k_i is section i's share of the mode's strain
energy and −∂ ln Ω²/∂ ln J_i node i's share of its kinetic energy, so changing every k_i and J_i
by a relative η moves every Ω² by at most 2η. This module keeps that precision.

**Eigenvalues.** Holzer's recurrence for a trial Ω² = σ: q_0 = −σJ_0,

    p_i = k_i + q_i,    q_{i+1} = k_i q_i / p_i − σ J_{i+1}    (i < n − 1),    p_{n−1} = q_{n−1},

gives the pivots p_i of K − σJ = L D Lᵀ (K = L diag(k_0 … k_{n−2}, 0) Lᵀ with L unit lower
bidiagonal, its subdiagonal −1): q_i is the dynamic stiffness of nodes 0 … i, and k_i q_i/p_i that
of the same nodes seen through section i (k_i and q_i in series). It is the differential form
of the stationary qd transform (Dhillon & Parlett, "Orthogonal eigenvectors and relative gaps",
SIAM J. Matrix Anal. Appl. 25, 2004): it subtracts no two large numbers, and what it computes
is the exact transform of a chain whose numbers differ from the given ones in their last digits.
By Sylvester's law of inertia the number of negative pivots is the number of modes with
Ω² < σ, the rigid one included, and bisection on that count finds each Ω² to a few units in
its last digit. SciPy's tridiagonal solver (``scipy.linalg.eigh_tridiagonal``) starts it, each Ω²
within 8 ε ‖J^{−1/2} K J^{−1/2}‖ of its estimate (the count checks the bracket, and an end it
refuses moves further out: a long chain's estimates are off by more); several trial values per mode at once
(multisection, :data:`_TRIALS` in all) narrow it in a few sweeps.

**Shapes.** At each Ω², the same recurrence from both ends: q_i from node 0 (pivots p_i) and
q′_i from node n − 1 (q′_{n−1} = −Ω² J_{n−1}, p′_i = k_{i−1} + q′_i, q′_{i−1} = k_{i−1} q′_i / p′_i
− Ω² J_{i−1}). Node r, where γ_r = q_r + q′_r + Ω² J_r (the reciprocal of the (r, r) entry of
(K − Ω² J)^{−1}) is smallest, is where the mode is large; its shape is a_r = 1 and Holzer's
amplitude ratios outwards, a_i = k_i a_{i+1}/p_i to the left and a_i = k_{i−1} a_{i−1}/p′_i to
the right (the twisted factorization's eigenvector): products and quotients, each amplitude to
a relative precision, a light node's too.

Both recurrences are scaled to max k_i = max J_i = 1 and run over all modes at once (numpy,
one step per node).
"""

from __future__ import annotations

import numpy as np

__all__ = ["chain_modes"]

_EPS = float(np.finfo(float).eps)
#: A pivot smaller in magnitude than this is taken as −_PIVMIN (LAPACK's rule): the next q stays
#: finite, and the count is that of a chain perturbed in its last digits.
_PIVMIN = float(np.finfo(float).tiny) / _EPS
#: Trial values a sweep of the count evaluates, over all the modes still open (at least one
#: per mode: bisection): the more per mode, the fewer sweeps.
_TRIALS = 256
#: The width of a bracket, relative to its top, at which it is closed.
_CLOSED = 4 * _EPS


def chain_modes(stiffness: np.ndarray, inertia: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    """The lowest ``count`` elastic modes of the free–free chain.

    Parameters
    ----------
    stiffness : ndarray
        k_i [N·m/rad] > 0, shape (n − 1,).
    inertia : ndarray
        J_i [kg·m²] > 0, shape (n,).
    count : int
        How many elastic modes, 1 ≤ count ≤ n − 1, from the lowest.

    Returns
    -------
    omega_squared : ndarray
        Ω² [rad²/s²] of elastic modes 1 … count, increasing, shape (count,).
    shapes : ndarray
        Their shapes, shape (n, count), each scaled to a largest magnitude of 1, positive at
        the first node that has it (to 1e-9).
    """
    k_scale, j_scale = float(stiffness.max()), float(inertia.max())
    k, J = stiffness / k_scale, inertia / j_scale
    values = _eigenvalues(k, J, count)
    return values * (k_scale / j_scale), _shapes(k, J, values)


def _below(k: np.ndarray, J: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """The number of modes with Ω² < σ, the rigid one included, for each trial σ > 0."""
    q = -sigma * J[0]
    p = np.empty_like(q)
    term = np.empty_like(q)
    negative = np.empty(q.shape, dtype=bool)
    count = np.zeros(q.shape, dtype=np.int64)
    with np.errstate(all="ignore"):
        for k_i, j_next in zip(k.tolist(), J[1:].tolist(), strict=True):
            np.add(q, k_i, out=p)
            np.less(p, _PIVMIN, out=negative)
            count += negative
            np.multiply(q, k_i, out=q)
            np.divide(q, p, out=q)
            np.multiply(sigma, j_next, out=term)
            np.subtract(q, term, out=q)
    count += q < _PIVMIN
    # A pivot of (nearly) 0 made an infinity, and then NaN: those trials again, each pivot
    # smaller than _PIVMIN taken as −_PIVMIN.
    lost = ~np.isfinite(q)
    if lost.any():
        count[lost] = _below_guarded(k, J, sigma[lost])
    return count


def _below_guarded(k: np.ndarray, J: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """:func:`_below` with every pivot guarded (slower)."""
    q = -sigma * J[0]
    count = np.zeros(q.shape, dtype=np.int64)
    for i, k_i in enumerate(k.tolist()):
        p = _guard(q + k_i)
        count += p < 0
        q = k_i * q / p - sigma * J[i + 1]
    return count + (_guard(q) < 0)


def _guard(pivot: np.ndarray) -> np.ndarray:
    """A pivot, those smaller in magnitude than _PIVMIN taken as −_PIVMIN."""
    return np.where(np.abs(pivot) < _PIVMIN, -_PIVMIN, pivot)


def _eigenvalues(k: np.ndarray, J: np.ndarray, count: int) -> np.ndarray:
    """Ω² of elastic modes 1 … count (scaled chain), each to a few units in its last digit."""
    # SciPy on first use: importing multicrank (or its pressures) does not import it.
    from scipy.linalg import eigh_tridiagonal  # type: ignore[import-untyped,unused-ignore]

    n = J.size
    # The tridiagonal J^{-1/2} K J^{-1/2}: its estimates and their absolute accuracy.
    diagonal = (np.r_[k, 0.0] + np.r_[0.0, k]) / J
    off = -k / np.sqrt(J[:-1] * J[1:])
    if count == n - 1:
        estimate = eigh_tridiagonal(diagonal, off, eigvals_only=True, lapack_driver="sterf")[1:]
    else:
        estimate = eigh_tridiagonal(diagonal, off, eigvals_only=True, select="i", select_range=(1, count))
    row = np.abs(diagonal) + np.r_[np.abs(off), 0.0] + np.r_[0.0, np.abs(off)]
    top = float(row.max())
    ceiling = top * (1 + 8 * _EPS)  # Gershgorin: every Ω² is below it
    wanted = np.arange(1, count + 1)  # mode m has m modes (the rigid one, 1 … m − 1) below it
    low, high = _brackets(k, J, estimate, wanted, 8 * _EPS * top, ceiling)

    open_ = np.flatnonzero(high - low > _CLOSED * high)
    while open_.size:
        trials = max(1, _TRIALS // open_.size)
        lo, hi = low[open_, None], high[open_, None]
        step = (np.arange(1, trials + 1) / (trials + 1))[None, :]
        # Evenly spaced where the bracket is narrow, evenly in ln Ω² where it spans more than a
        # factor of 2 (from hi × 2^−64 where it starts at 0).
        floor = np.where(lo > 0, lo, hi * 2.0**-64)
        with np.errstate(divide="ignore"):
            points = np.where(hi > 2 * floor, floor * (hi / floor) ** step, lo + (hi - lo) * step)
        above = _below(k, J, points.ravel()).reshape(points.shape) > wanted[open_, None]
        # The first trial with the mode below it closes the bracket from above, the one before
        # it from below.
        first = np.where(above.any(axis=1), above.argmax(axis=1), trials)
        grid = np.concatenate([lo, points, hi], axis=1)
        rows = np.arange(open_.size)
        new_low, new_high = grid[rows, first], grid[rows, first + 1]
        # No representable value between the ends: closed as it is.
        stuck = (new_low == low[open_]) & (new_high == high[open_])
        low[open_], high[open_] = new_low, new_high
        open_ = open_[(new_high - new_low > _CLOSED * new_high) & ~stuck]
    return 0.5 * (low + high)


def _brackets(
    k: np.ndarray, J: np.ndarray, estimate: np.ndarray, wanted: np.ndarray, width: float, ceiling: float
) -> tuple[np.ndarray, np.ndarray]:
    """A bracket [low, high] of each mode's Ω² (mode m: ``wanted`` m), checked by the count:
    ``estimate`` ± ``width`` at first; an end the count refuses moved 16 times as far out, six
    times at most, then to 0 or ``ceiling`` (σ = 0 has no mode below it, ``ceiling`` every one)."""
    low = np.maximum(estimate - width, 0.0)
    high = np.minimum(estimate + width, ceiling)
    reach = np.full(estimate.size, width)
    unsure = np.arange(estimate.size)
    for attempt in range(7):
        at_low = unsure[low[unsure] > 0]
        ends = _below(k, J, np.concatenate([low[at_low], high[unsure]]))
        too_high = at_low[ends[: at_low.size] > wanted[at_low]]
        too_low = unsure[ends[at_low.size :] <= wanted[unsure]]
        if attempt == 6:
            low[too_high], high[too_low] = 0.0, ceiling
            break
        unsure = np.union1d(too_high, too_low)
        if not unsure.size:
            break
        reach[unsure] *= 16
        low[too_high] = np.maximum(estimate[too_high] - reach[too_high], 0.0)
        high[too_low] = np.minimum(estimate[too_low] + reach[too_low], ceiling)
    return low, high


def _shapes(k: np.ndarray, J: np.ndarray, omega_squared: np.ndarray) -> np.ndarray:
    """The shapes (nodes, modes) at the modes' Ω² (scaled chain), by the twisted Holzer
    recurrence; scaled to a largest magnitude of +1 at the first node that has it."""
    n, modes = J.size, omega_squared.size
    shapes = np.empty((n, modes))  # q′_i, then the ratios to the left, then the shapes
    right = np.empty((n, modes))  # a_i/a_{i−1} to the right
    with np.errstate(all="ignore"):
        q = -omega_squared * J[n - 1]
        for i in range(n - 1, 0, -1):
            shapes[i] = q
            right[i] = k[i - 1] / _guard(q + k[i - 1])
            q = right[i] * q - omega_squared * J[i - 1]
        shapes[0] = q
        smallest = np.full(modes, np.inf)
        twist = np.zeros(modes, dtype=np.int64)
        q = -omega_squared * J[0]
        for i in range(n):
            gamma = np.abs(q + shapes[i] + omega_squared * J[i])
            closer = gamma < smallest
            smallest[closer], twist[closer] = gamma[closer], i
            if i < n - 1:
                shapes[i] = k[i] / _guard(q + k[i])  # a_i/a_{i+1} to the left
                q = shapes[i] * q - omega_squared * J[i + 1]
        # a_i = Π_{j=i}^{r−1} (a_j/a_{j+1}) left of r and Π_{j=r+1}^{i} (a_j/a_{j−1}) right of it.
        nodes = np.arange(n)[:, None]
        np.copyto(shapes, 1.0, where=nodes >= twist)
        np.multiply.accumulate(shapes[::-1], axis=0, out=shapes[::-1])
        np.copyto(right, 1.0, where=nodes <= twist)
        np.multiply.accumulate(right, axis=0, out=right)
        shapes *= right
    del right
    # (Without a temporary of the shapes' size: every mode's may be asked of a long chain.)
    size = np.maximum(shapes.max(axis=0), -shapes.min(axis=0))
    threshold = size * (1 - 1e-9)
    first = np.argmax((shapes >= threshold) | (shapes <= -threshold), axis=0)
    shapes /= size * np.sign(shapes[first, np.arange(modes)])
    return shapes
