"""The free–free torsional chain's modes to the precision its numbers hold (:meth:`Shaft.modes
<multicrank.Shaft.modes>`), found by the core (``multicrank-core``, ``torsion::Chain::modes``).

The chain of inertias J_i [kg·m²] joined by stiffnesses k_i [N·m/rad] has the modes K a = Ω² J a.
The core finds each Ω² from the chain's numbers to a few units in its last digit — Holzer's
recurrence gives the pivots of K − σJ, and bisection on the count of the negative ones (the
modes below σ, Sylvester's law of inertia) closes each mode's bracket — and each shape by the
same recurrence from both ends, every node's amplitude to a relative precision (its module
documentation derives it). A general eigen solver is accurate only to a few ε of the largest Ω².
"""

from __future__ import annotations

import numpy as np

from .._native import chain_modes as _native_chain_modes

__all__ = ["chain_modes"]


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

    Examples
    --------
    Two discs swing against each other at Ω² = k (1/J_1 + 1/J_2), in inverse ratio to their
    inertias:

    >>> import numpy as np
    >>> omega_squared, shapes = chain_modes(np.array([8.0e4]), np.array([2.0, 0.5]), 1)
    >>> float(omega_squared[0]), shapes[:, 0].tolist()
    (200000.0, [-0.25, 1.0])
    """
    omega, shapes = _native_chain_modes(
        np.ascontiguousarray(stiffness, dtype=np.float64), np.ascontiguousarray(inertia, dtype=np.float64), count
    )
    # ω·ω: its square root, as Shaft.modes takes it, is ω again to the last bit.
    return omega * omega, shapes
