"""The gas forces of a :class:`~multicrank.Machine`: each unit's place in its working cycle,
the net gas force on every piston from its cylinder's pressure callables (p(θ)·A − p_c(θ)·A_c)
and the gas torque they make on the shaft, by virtual work in the Rust core.
:class:`MachineGas` holds these methods; :class:`~multicrank.Machine` inherits them and holds
the data.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from .._native import MechanismError, NativeMachine
from .._native import piston_forces as _native_piston_forces
from .._validation import as_real_array, as_returned, as_threshold, contiguous, refused
from .cylinder import Cylinder, Pressure

__all__ = ["MachineGas"]


class MachineGas:
    """The methods of :class:`~multicrank.Machine` that give its gas forces and torque; a
    part of that class, without data of its own."""

    if TYPE_CHECKING:  # the fields Machine sets
        cylinders: tuple[Cylinder, ...]

        @property
        def _units(self) -> dict[str, np.ndarray]: ...  # made on first use

        @property
        def _core(self) -> NativeMachine: ...  # made on first use

        @property
        def cycle(self) -> float: ...

    def cycle_angles(self, phi: Any) -> np.ndarray:
        """θ_j = (φ + α_j) mod Φ, each unit's place in its working cycle.

        Parameters
        ----------
        phi : array_like
            Crank angle φ [rad]; any shape.

        Returns
        -------
        ndarray
            θ [rad] in [0, Φ), shape (units,) + phi.shape.
        """
        angles = np.asarray(as_real_array(phi, "phi"))
        phases = self._units["phase"].reshape((-1,) + (1,) * angles.ndim)
        return np.mod(angles + phases, self.cycle)

    def piston_forces(self, phi: Any) -> np.ndarray:
        """The net gas force on every piston, p(θ)·A − p_c(θ)·A_c.

        Parameters
        ----------
        phi : array_like
            Crank angle φ [rad]; any shape.

        Returns
        -------
        ndarray
            The force [N], positive toward the shaft; shape (units,) + phi.shape.
        """
        angles = np.asarray(as_real_array(phi, "phi"))
        theta = self.cycle_angles(angles)
        ends = {name: np.zeros(theta.shape) for name in ("pressure", "pressure_crank_end")}
        for name, pressures in ends.items():
            # Units that share one pressure callable (one indicator diagram for every
            # cylinder, the usual case) take it in one call: per call overhead dominates.
            groups: dict[int, tuple[Pressure, list[int]]] = {}
            for j, c in enumerate(self.cylinders):
                function = getattr(c, name)
                if function is not None and c.bore > 0:
                    groups.setdefault(id(function), (function, []))[1].append(j)
            for function, units in groups.values():
                pressures[units] = _pressure(function, theta[units], name)
        bore, rod = (np.array([getattr(c, field) for c in self.cylinders]) for field in ("bore", "piston_rod_diameter"))
        forces = _native_piston_forces(bore, rod, *(contiguous(p).reshape(-1) for p in ends.values()))
        return forces.reshape(theta.shape)

    def gas_torque(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """The gas torque Σ_j F_j(θ_j)·s'(ψ_j), by the virtual work of the piston forces.

        Parameters
        ----------
        phi : array_like
            Crank angle φ [rad]; any shape.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default.

        Returns
        -------
        ndarray
            The torque [N·m], positive driving the shaft; the shape of ``phi``.
        """
        angles = np.asarray(as_real_array(phi, "phi"), dtype=float)
        flat = contiguous(angles).reshape(-1)
        forces = contiguous(self.piston_forces(flat)).reshape(-1)
        torque = self._core.gas_torque(flat, forces, as_threshold(parallel_threshold))
        return torque.reshape(angles.shape)


def _pressure(
    function: Callable[[np.ndarray], Any], theta: np.ndarray, name: str, quantity: str = "pressure", unit: str = "Pa"
) -> np.ndarray:
    """A callable's values at θ (a pressure [Pa] unless ``quantity`` and ``unit`` say
    otherwise), checked: real, finite, the shape of θ."""
    try:
        values = function(theta)
    except MechanismError:
        raise
    except Exception as error:
        raise refused(name, f"{name} failed at the cycle angles given: {error}") from error
    return as_returned(values, name, quantity, unit, theta.shape)
