"""The physical machine of any layout, in SI units: cylinders on one shaft.

A :class:`Cylinder` is one slider-crank unit — its geometry, moving masses, crank web and
counterweight, bore, place on the shaft (phase) and in space (inclination), and the gas
pressure on its piston. A :class:`Machine` is its cylinders, the shaft's moment of inertia
and the working cycle. It gives the quantities of the machine's equation of motion
(docs/theory.md): the reduced moment of inertia J(φ) and J'(φ), the potential energy U(φ)
and the gravity torque −dU/dφ, the gas torque and the inertia torque, all computed in the
Rust core; and the dimensionless :class:`~multicrank.Engine` of gravity at any speed.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._native import MechanismError
from ._native import machine_engine as _native_machine_engine
from ._native import machine_evaluate as _native_machine_evaluate
from ._native import machine_gas_torque as _native_machine_gas_torque
from ._native import machine_inertia as _native_machine_inertia
from ._validation import as_real_array, as_scalar, as_strokes, as_threshold, contiguous
from .engines import Engine
from .grids import as_phi
from .mechanism import STANDARD_GRAVITY

__all__ = ["Cylinder", "Machine"]

#: The fields of a cylinder that the core's kinematics and gravity take, in its order.
_UNIT_FIELDS = (
    "crank_radius",
    "rod_length",
    "piston_mass",
    "rod_mass",
    "rod_cg",
    "rod_inertia",
    "crank_mass",
    "crank_cg_radius",
    "counterweight_mass",
    "counterweight_radius",
    "phase",
    "inclination",
)

Pressure = Callable[[np.ndarray], Any]


@dataclass(frozen=True)
class Cylinder:
    """One slider-crank unit of a machine, in SI units (m, kg, kg·m², rad, Pa).

    Parameters
    ----------
    crank_radius : float
        r [m], > 0.
    rod_length : float
        l [m], > r; the crank ratio is λ = r/l.
    piston_mass : float
        m_t [kg], ≥ 0: the piston complete (rings, pin; crosshead and piston rod where
        there are).
    rod_mass : float
        m_k [kg], ≥ 0.
    rod_cg : float
        z_k [m], the rod's centre of gravity measured from the piston-pin axis, 0 ≤ z_k ≤ l.
    rod_inertia : float, optional
        I_k [kg·m²], the rod's moment of inertia about its own centre of gravity, ≥ 0.
        Default: m_k·z_k·(l − z_k), the two-mass rod. A real rod usually has less; the
        difference ΔI = I_k − m_k z_k (l − z_k) turns with the rod angle and enters J(φ).
    crank_mass, crank_cg_radius : float
        m_s [kg] and r_s [m]: this unit's crank web (and pin) and the radius of its centre
        of gravity. Only their first moment enters (gravity); their inertia is part of
        the machine's ``shaft_inertia``.
    counterweight_mass, counterweight_radius : float
        m_p [kg] and r_p [m], opposite the crank pin; likewise only gravity.
    bore : float
        D [m], ≥ 0; the piston area is π D²/4. 0: no gas force.
    phase : float
        α [rad], any finite real: the unit's crank angle from its own outer dead centre is
        ψ = φ + α, and its cycle angle θ = (φ + α) mod Φ places it in the working cycle.
    inclination : float
        γ [rad]: the cylinder axis to the horizontal, +π/2 upright (the default).
    pressure : callable or None
        Gauge pressure p(θ) [Pa] on the piston crown as a vectorised function of the cycle
        angle θ [rad] (an :class:`~multicrank.pressure.IndicatorDiagram`, say). It pushes
        the piston toward the shaft.
    pressure_crank_end : callable or None
        Double-acting cylinders: the crank-end chamber's gauge pressure p_c(θ) [Pa], acting
        on the area π D²/4 − π d²/4 and pushing the piston away from the shaft.
    piston_rod_diameter : float
        d [m], 0 ≤ d < D: the piston rod through the crank-end chamber.
    """

    crank_radius: float
    rod_length: float
    piston_mass: float
    rod_mass: float
    rod_cg: float
    rod_inertia: float | None = None
    crank_mass: float = 0.0
    crank_cg_radius: float = 0.0
    counterweight_mass: float = 0.0
    counterweight_radius: float = 0.0
    bore: float = 0.0
    phase: float = 0.0
    inclination: float = math.pi / 2
    pressure: Pressure | None = None
    pressure_crank_end: Pressure | None = None
    piston_rod_diameter: float = 0.0

    def __post_init__(self) -> None:
        for field in (*_UNIT_FIELDS, "bore", "piston_rod_diameter"):
            value = getattr(self, field)
            if field == "rod_inertia" and value is None:
                continue
            object.__setattr__(self, field, as_scalar(value, field))
        if self.rod_inertia is None:
            # The two-mass rod (ΔI = 0): valid for any rod_cg the core accepts.
            two_mass = self.rod_mass * self.rod_cg * (self.rod_length - self.rod_cg)
            object.__setattr__(self, "rod_inertia", max(two_mass, 0.0))
        if not (math.isfinite(self.bore) and self.bore >= 0):
            raise MechanismError(f"bore = {self.bore} is out of range; allowed: bore >= 0 [m]")
        if not (math.isfinite(self.piston_rod_diameter) and 0 <= self.piston_rod_diameter):
            raise MechanismError(f"piston_rod_diameter = {self.piston_rod_diameter} is out of range; allowed: >= 0 [m]")
        if self.piston_rod_diameter > 0 and self.piston_rod_diameter >= self.bore:
            raise MechanismError(
                f"piston_rod_diameter = {self.piston_rod_diameter} is out of range; "
                f"allowed: less than bore = {self.bore}"
            )
        for name in ("pressure", "pressure_crank_end"):
            value = getattr(self, name)
            if value is not None and not callable(value):
                raise MechanismError(f"{name} must be None or a callable of the cycle angle [rad] -> Pa")
        # Geometry and masses: the core's rules, checked now rather than at first use.
        _native_machine_evaluate("travel", _columns([self]), 0.0, np.zeros(0))

    @property
    def crank_ratio(self) -> float:
        """λ = r/l."""
        return self.crank_radius / self.rod_length

    @property
    def piston_area(self) -> float:
        """π D²/4 [m²], the crown's area."""
        return math.pi * self.bore**2 / 4

    @property
    def crank_end_area(self) -> float:
        """π (D² − d²)/4 [m²], the crank-end face's area around the piston rod."""
        return math.pi * (self.bore**2 - self.piston_rod_diameter**2) / 4

    def replace(self, **changes: Any) -> Cylinder:
        """A copy with some fields changed."""
        return dataclasses.replace(self, **changes)


def _columns(cylinders: Sequence[Cylinder]) -> dict[str, np.ndarray]:
    """The units as the core's bundle of equal-length float64 columns."""
    return {field: contiguous(np.array([getattr(c, field) for c in cylinders], dtype=float)) for field in _UNIT_FIELDS}


class Machine:
    """A machine: cylinders of any layout on one shaft, in SI units.

    Parameters
    ----------
    cylinders : sequence of :class:`Cylinder`
        At least one.
    shaft_inertia : float
        I_w [kg·m²], > 0: everything that turns rigidly with the shaft — shaft, webs,
        counterweights, flywheel, gears, driven inertia — but not the rods and pistons,
        whose inertia the machine adds exactly.
    strokes : 2 or 4
        The working cycle spans Φ = 2π (two-stroke) or 4π (four-stroke) of crank angle.
    g : float
        Gravity [m/s²], default standard gravity; 0 switches gravity off.
    name : str
        A label.
    """

    def __init__(
        self,
        cylinders: Sequence[Cylinder],
        *,
        shaft_inertia: float,
        strokes: int = 2,
        g: float = STANDARD_GRAVITY,
        name: str = "machine",
    ) -> None:
        if isinstance(cylinders, Cylinder) or not isinstance(cylinders, Sequence):
            raise MechanismError("cylinders must be a sequence of multicrank.Cylinder")
        cylinders = tuple(cylinders)
        if not cylinders:
            raise MechanismError("cylinders must not be empty: a machine needs at least one cylinder")
        if not all(isinstance(c, Cylinder) for c in cylinders):
            raise MechanismError("cylinders must all be multicrank.Cylinder")
        self.cylinders: tuple[Cylinder, ...] = cylinders
        self.shaft_inertia = as_scalar(shaft_inertia, "shaft_inertia")
        if not (math.isfinite(self.shaft_inertia) and self.shaft_inertia > 0):
            raise MechanismError(f"shaft_inertia = {self.shaft_inertia} is out of range; allowed: shaft_inertia > 0")
        self.strokes = as_strokes(strokes)
        self.g = as_scalar(g, "g")
        if not math.isfinite(self.g):
            raise MechanismError(f"g = {self.g} is out of range; allowed: any finite real")
        self.name = str(name)
        self._units = _columns(cylinders)

    # -- description ---------------------------------------------------------------------
    @property
    def cycle(self) -> float:
        """Φ [rad]: the crank angle of one working cycle, π·strokes."""
        return math.pi * self.strokes

    def __len__(self) -> int:
        return len(self.cylinders)

    def __repr__(self) -> str:
        return (
            f"Machine({self.name!r}, {len(self)} cylinders, shaft_inertia={self.shaft_inertia:g} kg·m², "
            f"{self.strokes}-stroke, g={self.g:g})"
        )

    def replace(self, **changes: Any) -> Machine:
        """A copy with some of cylinders, shaft_inertia, strokes, g, name changed."""
        known = ("cylinders", "shaft_inertia", "strokes", "g", "name")
        unknown = set(changes) - set(known)
        if unknown:
            raise MechanismError(f"unknown machine field(s) {', '.join(sorted(unknown))}; known: {', '.join(known)}")
        return Machine(
            changes.get("cylinders", self.cylinders),
            shaft_inertia=changes.get("shaft_inertia", self.shaft_inertia),
            strokes=changes.get("strokes", self.strokes),
            g=changes.get("g", self.g),
            name=changes.get("name", self.name),
        )

    def engine(self, rpm: float) -> Engine:
        """The dimensionless gravity engine at ``rpm`` [1/min]: U1, U2 ÷ I_w ω², ω = π·rpm/30."""
        columns = _native_machine_engine(self._units, self.g, self.shaft_inertia, as_scalar(rpm, "rpm"))
        return Engine(**columns, name=f"{self.name} at {float(rpm):g} rpm")

    # -- the quantities of the equation of motion -----------------------------------------
    def reduced_inertia(self, phi: Any, *, parallel_threshold: Any = None) -> tuple[np.ndarray, np.ndarray]:
        """(J, dJ/dφ): the reduced moment of inertia [kg·m²] and its slope [kg·m²/rad].

        J(φ) = I_w + Σ_j [m_k3 r² + (m_t + m_k1) s'(ψ_j)² + ΔI β'(ψ_j)²], with the rod split
        exactly into m_k1 = m_k (l − z_k)/l at the piston pin, m_k3 = m_k z_k/l at the crank
        pin and ΔI turning with the rod angle β; ½ J φ̇² is the machine's kinetic energy.
        Both arrays have the shape of ``phi`` [rad].
        """
        shape, angles = as_phi(phi)
        result = _native_machine_inertia(self._units, self.shaft_inertia, angles, as_threshold(parallel_threshold))
        return result["J"].reshape(shape), result["dJ_dphi"].reshape(shape)

    def potential_energy(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """U(φ) [J] = Σ m·g·height, each unit measured from its own ψ = 0 configuration."""
        shape, angles = as_phi(phi)
        flat = _native_machine_evaluate(
            "potential_energy", self._units, self.g, angles, as_threshold(parallel_threshold)
        )
        return flat.reshape(shape)

    def gravity_torque(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """The torque of gravity on the shaft, −dU/dφ [N·m] (positive accelerates it)."""
        shape, angles = as_phi(phi)
        flat = _native_machine_evaluate("gravity_torque", self._units, self.g, angles, as_threshold(parallel_threshold))
        return flat.reshape(shape)

    def piston_travel(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """s(ψ_j) [m], every piston's travel from its outer dead centre: shape (units,) + phi.shape."""
        shape, angles = as_phi(phi)
        flat = _native_machine_evaluate("travel", self._units, self.g, angles, as_threshold(parallel_threshold))
        return flat.reshape((len(self), *shape))

    def cycle_angles(self, phi: Any) -> np.ndarray:
        """θ_j = (φ + α_j) mod Φ [rad], each unit's place in the working cycle: (units,) + phi.shape."""
        angles = np.asarray(as_real_array(phi, "phi"))
        phases = self._units["phase"].reshape((-1,) + (1,) * angles.ndim)
        return np.mod(angles + phases, self.cycle)

    def piston_forces(self, phi: Any) -> np.ndarray:
        """The net gas force on every piston [N], positive toward the shaft: p(θ)·A − p_c(θ)·A_c;
        shape (units,) + phi.shape."""
        angles = np.asarray(as_real_array(phi, "phi"))
        theta = self.cycle_angles(angles)
        forces = np.zeros(theta.shape)
        for name, area, sign in (("pressure", "piston_area", 1.0), ("pressure_crank_end", "crank_end_area", -1.0)):
            # Units that share one pressure callable (one indicator diagram for every
            # cylinder, the usual case) take it in one call: per call overhead dominates.
            groups: dict[int, tuple[Pressure, list[int]]] = {}
            for j, c in enumerate(self.cylinders):
                function = getattr(c, name)
                if function is not None and c.bore > 0:
                    groups.setdefault(id(function), (function, []))[1].append(j)
            for function, units in groups.values():
                pressures = _pressure(function, theta[units], name)
                forces[units] += (
                    sign
                    * pressures
                    * np.array([getattr(self.cylinders[j], area) for j in units]).reshape((-1,) + (1,) * angles.ndim)
                )
        return forces

    def gas_torque(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """The gas torque Σ_j F_j(θ_j)·s'(ψ_j) [N·m] (virtual work of the piston forces)."""
        angles = np.asarray(as_real_array(phi, "phi"), dtype=float)
        flat = contiguous(angles).reshape(-1)
        forces = contiguous(self.piston_forces(flat)).reshape(-1)
        torque = _native_machine_gas_torque(self._units, flat, forces, as_threshold(parallel_threshold))
        return torque.reshape(angles.shape)

    def inertia_torque(self, phi: Any, omega: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """The inertia torque at steady speed ω [rad/s] (φ̈ = 0): −½ J'(φ) ω² [N·m].

        ``omega`` broadcasts against ``phi``.
        """
        _, slope = self.reduced_inertia(phi, parallel_threshold=parallel_threshold)
        speed = as_real_array(omega, "omega")
        return -0.5 * slope * speed**2


def _pressure(function: Pressure, theta: np.ndarray, name: str) -> np.ndarray:
    """A pressure callable's values at θ, checked: finite, the shape of θ."""
    try:
        values = np.asarray(function(theta), dtype=float)
    except MechanismError:
        raise
    except Exception as error:
        raise MechanismError(f"{name} failed at the cycle angles given: {error}") from error
    values = np.broadcast_to(values, theta.shape)
    if not np.all(np.isfinite(values)):
        raise MechanismError(f"{name} returned a non-finite pressure (NaN or inf) [Pa]")
    return values
