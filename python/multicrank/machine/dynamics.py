"""The quantities of a :class:`~multicrank.Machine`'s equation of motion that its mass
gives (docs/theory.md), all computed in the Rust core: the reduced moment of inertia J(φ) and
J'(φ), the potential energy U(φ) and the gravity torque −dU/dφ, the pistons' travel and the
inertia torque. :class:`MachineDynamics` holds these methods; :class:`~multicrank.Machine`
inherits them and holds the data. The gas forces are in `gas`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from .._inertia_torque import inertia_torque as _inertia_torque
from .._native import NativeMachine
from .._validation import as_real_array, as_threshold
from ..gravity.grids import as_phi

__all__ = ["MachineDynamics", "ReducedInertia"]


class ReducedInertia(NamedTuple):
    """What :meth:`~multicrank.Machine.reduced_inertia` returns: J(φ) and J′(φ) under the
    names the motion results give them, and still a pair, ``J, slope = machine.reduced_inertia(phi)``.

    Attributes
    ----------
    reduced_inertia : ndarray
        J(φ) [kg·m²], the reduced moment of inertia.
    reduced_inertia_slope : ndarray
        J′(φ) = dJ/dφ [kg·m²/rad].
    """

    reduced_inertia: np.ndarray
    reduced_inertia_slope: np.ndarray


class MachineDynamics:
    """The methods of :class:`~multicrank.Machine` that give the quantities of its equation
    of motion; a part of that class, without data of its own."""

    if TYPE_CHECKING:  # the fields Machine sets
        shaft_inertia: float
        g: float

        @property
        def _core(self) -> NativeMachine: ...  # made on first use

        def __len__(self) -> int: ...

    def reduced_inertia(self, phi: Any, *, parallel_threshold: Any = None) -> ReducedInertia:
        """(J, J′): the reduced moment of inertia [kg·m²] and its slope dJ/dφ [kg·m²/rad].

        J(φ) = I_w + Σ_j [m_k3 r² + (m_t + m_k1) s'(ψ_j)² + ΔI β'(ψ_j)²], with the rod split
        exactly into m_k1 = m_k (l − z_k)/l at the piston pin, m_k3 = m_k z_k/l at the crank
        pin and ΔI turning with the rod angle β; ½ J φ̇² is the machine's kinetic energy.

        Parameters
        ----------
        phi : array_like or UniformGrid
            Crank angle φ [rad]; any shape.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default
            (:func:`~multicrank.set_parallel_threshold`).

        Returns
        -------
        reduced_inertia : ndarray
            J(φ), the reduced moment of inertia [kg·m²], the shape of ``phi``.
        reduced_inertia_slope : ndarray
            Its slope J′(φ) = dJ/dφ [kg·m²/rad], the shape of ``phi``.

            The two come as a named tuple (``ReducedInertia``): it unpacks as a pair, and
            its fields have the names of the motion results' arrays.
        """
        shape, angles = as_phi(phi)
        result = self._core.reduced_inertia(angles, parallel_threshold=as_threshold(parallel_threshold))
        return ReducedInertia(result["J"].reshape(shape), result["dJ_dphi"].reshape(shape))

    def _evaluate(self, quantity: str, phi: Any, parallel_threshold: Any, per_unit: bool = False) -> np.ndarray:
        """One of the core's per-angle quantities, shaped as ``phi`` (with a leading unit axis
        for per-unit ones)."""
        shape, angles = as_phi(phi)
        flat = self._core.evaluate(quantity, angles, as_threshold(parallel_threshold))
        return flat.reshape((len(self), *shape) if per_unit else shape)

    def potential_energy(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """U(φ) = Σ m·g·height, the potential energy of gravity.

        Parameters
        ----------
        phi : array_like or UniformGrid
            Crank angle φ [rad]; any shape.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default.

        Returns
        -------
        ndarray
            U [J], the shape of ``phi``; each unit measured from its own ψ = 0 configuration.
        """
        return self._evaluate("potential_energy", phi, parallel_threshold)

    def gravity_torque(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """The torque of gravity on the shaft, −dU/dφ.

        Parameters
        ----------
        phi : array_like or UniformGrid
            Crank angle φ [rad]; any shape.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default.

        Returns
        -------
        ndarray
            The torque [N·m], positive accelerating the shaft; the shape of ``phi``.
        """
        return self._evaluate("gravity_torque", phi, parallel_threshold)

    def piston_travel(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """Every piston's travel s(ψ_j) from its outer dead centre.

        Parameters
        ----------
        phi : array_like or UniformGrid
            Crank angle φ [rad]; any shape.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default.

        Returns
        -------
        ndarray
            s [m], shape (units,) + phi.shape.
        """
        return self._evaluate("travel", phi, parallel_threshold, per_unit=True)

    def inertia_torque(self, phi: Any, omega: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """The inertia torque at a steady speed (φ̈ = 0): −½ J'(φ) ω².

        Parameters
        ----------
        phi : array_like
            Crank angle φ [rad]; any shape.
        omega : array_like
            The shaft speed ω [rad/s]; broadcasts against ``phi``.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default.

        Returns
        -------
        ndarray
            The torque [N·m], the broadcast shape of ``phi`` and ``omega``.
        """
        _, slope = self.reduced_inertia(phi, parallel_threshold=parallel_threshold)
        return _inertia_torque(slope, as_real_array(omega, "omega"))
