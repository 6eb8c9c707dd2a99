"""A machine's shaft as a torsional chain (issue "Firing orders and counterweights judged as an
engine designer judges them", item 1): inertias joined by torsional stiffnesses, and its
natural frequencies and mode shapes.

The undamped free–free chain J θ̈ + K θ = 0, with J = diag(J_0 … J_{n−1}) [kg·m²] and K the
tridiagonal stiffness matrix of the n − 1 shaft sections k_i [N·m/rad] between nodes i and
i + 1 (K_ii = k_{i−1} + k_i, K_{i,i+1} = −k_i), has modes θ = a e^{iωt} with K a = ω² J a. SciPy's
generalized symmetric eigen solver (``scipy.linalg.eigh(K, J)``) gives them; the first, ω = 0,
turns the shaft as a rigid body, and the elastic modes 1, 2, … follow.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._native import MechanismError
from .._validation import MAGNITUDE_LIMIT, as_real_array

__all__ = ["Shaft", "ShaftModes"]


def _positive_list(values: Any, name: str, unit: str) -> tuple[float, ...]:
    array = as_real_array(values, name).astype(float)
    if array.ndim != 1:
        raise MechanismError(f"{name} must be a 1-D sequence [{unit}], got shape {array.shape}")
    bad = np.flatnonzero(~((array > 0) & (array <= MAGNITUDE_LIMIT)))  # NaN fails too
    if bad.size:
        raise MechanismError(
            f"{name}[{bad[0]}] = {array[bad[0]]} is out of range; allowed: 0 < {name} <= {MAGNITUDE_LIMIT:g} [{unit}]"
        )
    return tuple(float(v) for v in array)


@dataclass(frozen=True)
class ShaftModes:
    """The elastic modes of a :class:`Shaft` (the rigid-body mode left out).

    Attributes
    ----------
    natural_frequency : ndarray
        f_m [Hz] of modes 1, 2, … (increasing), shape (modes,).
    shapes : ndarray
        The mode shapes a_m: the nodes' relative amplitudes, shape (nodes, modes), each
        column scaled so that its largest magnitude is 1, positive at the first node that has
        it.
    """

    natural_frequency: np.ndarray
    shapes: np.ndarray


@dataclass(frozen=True)
class Shaft:
    """A shaft as a chain of torsional inertias and stiffnesses.

    Parameters
    ----------
    inertia : sequence of float
        J_i [kg·m²] > 0 of each node along the chain (the throws, the flywheel, the driven
        machine), at least two.
    stiffness : sequence of float
        k_i [N·m/rad] > 0 of the shaft section between node i and node i + 1: one fewer than
        the nodes.
    cylinder_nodes : sequence of int
        The node of each cylinder, in ``machine.cylinders`` order (several cylinders may share
        a node: a V's throw).
    damping : sequence of float, optional
        c_i [N·m·s/rad] ≥ 0 of each section, kept for the forced response a torsional tool
        computes (the natural frequencies here are those of the undamped chain).

    Notes
    -----
    A node's inertia is used as given: for the mean inertia of a cylinder's running gear add
    its share to its node (the crank's rotating masses m r², and half the reciprocating mass
    m_rec r²/2 on average over a revolution).

    Examples
    --------
    Two equal discs on a shaft: one elastic mode, at √(2k/J)/(2π), the discs swinging against
    each other.

    >>> import multicrank as mc
    >>> shaft = mc.Shaft([1.0, 1.0], [2.0e4], cylinder_nodes=[0])
    >>> modes = shaft.modes()
    >>> round(float(modes.natural_frequency[0]), 3)
    31.831
    >>> modes.shapes[:, 0].round(6).tolist()
    [1.0, -1.0]
    """

    inertia: tuple[float, ...]
    stiffness: tuple[float, ...]
    cylinder_nodes: tuple[int, ...]
    damping: tuple[float, ...] | None = None

    def __init__(self, inertia: Any, stiffness: Any, *, cylinder_nodes: Any, damping: Any = None) -> None:
        inertias = _positive_list(inertia, "inertia", "kg·m²")
        if len(inertias) < 2:
            raise MechanismError(f"inertia must hold at least two nodes, got {len(inertias)}")
        stiffnesses = _positive_list(stiffness, "stiffness", "N·m/rad")
        if len(stiffnesses) != len(inertias) - 1:
            raise MechanismError(
                f"stiffness must hold one fewer value than inertia ({len(inertias) - 1}), got {len(stiffnesses)}"
            )
        try:
            nodes = np.asarray(cylinder_nodes)
        except (ValueError, TypeError):  # ragged
            nodes = np.asarray(None)
        if nodes.ndim != 1 or nodes.size == 0 or nodes.dtype.kind not in "iu":
            raise MechanismError(f"cylinder_nodes must be a non-empty 1-D sequence of integers, got {cylinder_nodes!r}")
        bad = np.flatnonzero((nodes < 0) | (nodes >= len(inertias)))
        if bad.size:
            raise MechanismError(
                f"cylinder_nodes[{bad[0]}] = {nodes[bad[0]]} is out of range; allowed: 0 <= node < {len(inertias)}"
            )
        dampings = None
        if damping is not None:
            array = as_real_array(damping, "damping").astype(float)
            if array.shape != (len(stiffnesses),) or not np.all((array >= 0) & (array <= MAGNITUDE_LIMIT)):
                raise MechanismError(
                    f"damping must hold {len(stiffnesses)} values 0 <= c <= {MAGNITUDE_LIMIT:g} [N·m·s/rad], one per "
                    "shaft section"
                )
            dampings = tuple(float(v) for v in array)
        object.__setattr__(self, "inertia", inertias)
        object.__setattr__(self, "stiffness", stiffnesses)
        object.__setattr__(self, "cylinder_nodes", tuple(int(n) for n in nodes))
        object.__setattr__(self, "damping", dampings)

    def stiffness_matrix(self) -> np.ndarray:
        """The chain's stiffness matrix.

        Returns
        -------
        ndarray
            K [N·m/rad], tridiagonal, nodes × nodes: K_ii = k_{i−1} + k_i, K_{i,i+1} = −k_i.
        """
        k = np.asarray(self.stiffness)
        count = len(self.inertia)
        matrix = np.zeros((count, count))
        index = np.arange(count - 1)
        matrix[index, index] += k
        matrix[index + 1, index + 1] += k
        matrix[index, index + 1] = matrix[index + 1, index] = -k
        return matrix

    def modes(self) -> ShaftModes:
        """The elastic modes of the undamped free–free chain, from SciPy's generalized
        symmetric eigen solver: natural frequencies [Hz] and mode shapes (nodes × modes).

        Returns
        -------
        ShaftModes
            ``natural_frequency`` (increasing) and ``shapes`` (each scaled to a largest
            magnitude of +1).
        """
        from scipy.linalg import eigh  # type: ignore[import-untyped,unused-ignore]

        values, vectors = eigh(self.stiffness_matrix(), np.diag(self.inertia))
        # The rigid-body mode (ω = 0, to rounding) comes first: the elastic ones follow.
        omega_squared = np.maximum(values[1:], 0.0)
        shapes = vectors[:, 1:]
        # Each shape scaled to a largest magnitude of 1, the first node that has it (to
        # rounding: two nodes may swing equally) positive.
        size = np.abs(shapes).max(axis=0)
        first = np.argmax(np.abs(shapes) >= size * (1 - 1e-9), axis=0)
        scale = size * np.sign(shapes[first, np.arange(shapes.shape[1])])
        return ShaftModes(np.sqrt(omega_squared) / (2 * math.pi), shapes / scale)
