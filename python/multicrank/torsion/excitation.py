"""Each cylinder's excitation of the shaft: the order harmonics of its own tangential torque
(gas, inertia and gravity) at its phase 0 (:class:`CylinderOrders`, :func:`cylinder_orders`),
moved to its phase by the shift theorem.

Cylinders alike but for their phase and place share one computation: each distinct cylinder's
orders come from :func:`~multicrank.torque_orders` of the machine with that cylinder alone
(the core's quadrature), the gas of its diagrams as given and the machine's load law beside
them, so that each order's gas is scaled at its own speed. The torsional merit
(``merit``), the hand-off to openTorsion (``handoff``) and the design
aid's largest torque order (:func:`~multicrank.firing_orders`) weigh these harmonics.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validation import omega_from_rpm
from ..machine.machine import Machine, load_factor, rated_omega
from ..motion.orders import torque_orders

__all__ = ["CylinderOrders", "cylinder_orders"]

#: The speed [1/min] at which each cylinder's inertia torque is found alone; it scales as ω².
_REFERENCE_RPM = 1000.0


@dataclass(frozen=True)
class CylinderOrders:
    """The order harmonics of each cylinder's own tangential torque, at its phase 0.

    ``orders`` ν > 0 [1/rev] up to the highest asked (halves for four strokes); ``gas`` and
    ``gravity`` (cylinders × orders, complex [N·m]) those torques' harmonics c_ν (the torque
    Σ_ν Re(c_ν e^{iνθ}) of the cylinder's own angle θ), ``gas`` of the diagrams as given;
    ``inertial`` the inertia torque's per (rad/s)², which scales as ω². ``rated_omega``: ω_r
    [rad/s] of the machine's load law (:attr:`~multicrank.Machine.load_law`), under which
    :meth:`at` scales the gas by (ω/ω_r)² at each speed; None without one.
    """

    orders: np.ndarray
    gas: np.ndarray
    gravity: np.ndarray
    inertial: np.ndarray
    rated_omega: float | None = None

    def only(self, keep: np.ndarray) -> CylinderOrders:
        """The same harmonics of the orders ``keep`` selects (an index or a mask over
        :attr:`orders`), the load law kept."""
        return dataclasses.replace(
            self,
            orders=self.orders[keep],
            gas=self.gas[:, keep],
            gravity=self.gravity[:, keep],
            inertial=self.inertial[:, keep],
        )

    def at(
        self, phases: np.ndarray, omega: np.ndarray, parts: tuple[str, ...] = ("gas", "inertia", "gravity")
    ) -> np.ndarray:
        """T_ν,j of every cylinder at its phase α_j (``phases``, (…, cylinders) [rad]) and
        every order at its speed ``omega`` [rad/s] ((…, orders), broadcast against the
        phases' leading axes): (…, cylinders, orders), of the torques named in ``parts``; the
        gas scaled by the load law at each order's speed."""
        coefficient = np.zeros_like(self.gas)
        if "gas" in parts:
            # The load law's factor at each order's speed (1 without a law).
            scale = np.broadcast_to(load_factor(np.asarray(omega, dtype=float), self.rated_omega), np.shape(omega))
            coefficient = coefficient + self.gas * scale[..., None, :]
        if "gravity" in parts:
            coefficient = coefficient + self.gravity
        if "inertia" in parts:
            coefficient = coefficient + self.inertial * np.square(omega)[..., None, :]
        return coefficient * np.exp(1j * phases[..., :, None] * self.orders)


def cylinder_orders(machine: Machine, highest: int, *, mean: bool = False) -> CylinderOrders:
    """The :class:`CylinderOrders` of ``machine`` up to order ``highest`` (and order 0, the
    mean, where ``mean``), each cylinder alone at phase 0 (cylinders alike but for their phase
    and place share one computation), from :func:`torque_orders`, the gas of the diagrams as
    given and the machine's load law beside it; kept on the machine for the next call
    (``Machine._torsion_orders``, never pickled)."""
    cache = machine.__dict__.setdefault("_torsion_orders", {})
    if (highest, mean) in cache:
        return cache[highest, mean]
    omega_squared = omega_from_rpm(_REFERENCE_RPM) ** 2
    found: dict[Any, tuple[np.ndarray, ...]] = {}
    rows = []
    for cylinder in machine.cylinders:
        template = cylinder.replace(phase=0.0, axial_position=0.0)
        if template not in found:
            alone = machine.replace(cylinders=[template], main_bearings=None, shaft=None, load_law=None)
            table = torque_orders(alone, _REFERENCE_RPM, max_order=highest)
            table = table if mean else table[table.index > 0]
            harmonic = {
                part: table[f"{part}_cos"].to_numpy() - 1j * table[f"{part}_sin"].to_numpy()
                for part in ("gas", "inertia", "gravity")
            }
            found[template] = (
                table.index.to_numpy(dtype=float),
                harmonic["gas"],
                harmonic["gravity"],
                harmonic["inertia"] / omega_squared,
            )
        rows.append(found[template])
    gas, gravity, inertial = (np.array([row[i] for row in rows]) for i in (1, 2, 3))
    result = CylinderOrders(rows[0][0], gas, gravity, inertial, rated_omega=rated_omega(machine))
    cache[highest, mean] = result
    return result
