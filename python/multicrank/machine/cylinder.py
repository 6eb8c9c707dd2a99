"""One slider-crank unit of a machine, in SI units: :class:`Cylinder`.

A cylinder is its geometry, moving masses, crank web and counterweight, bore, place on the
shaft (phase) and in space (inclination), and the gas pressure on its piston; it gives its
chambers' volumes and the synthetic indicator diagrams in them
(:meth:`Cylinder.compressor_diagram`, :meth:`Cylinder.engine_diagram`). The core's
kinematics check it; :class:`~multicrank.Machine` puts cylinders on one shaft.
"""

from __future__ import annotations

import dataclasses
import math
import operator
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._native import piston_forces as _native_piston_forces
from .._native import two_mass_rod_inertia as _native_two_mass_rod_inertia
from .._native import unit_travel as _native_unit_travel
from .._validation import as_option, as_real_array, as_scalar, check_fields, check_magnitude, contiguous, refused
from ..pressure.diagram import IndicatorDiagram

__all__ = ["CYLINDER_FIELDS", "UNIT_FIELDS", "Cylinder", "Pressure", "diagram_strokes", "unit_columns"]

#: Every number of a cylinder, with what it is and its SI unit: the fields that the core's
#: kinematics and gravity take first, in its order (:data:`UNIT_FIELDS`), then those of its gas
#: force. The one place of these names; the design columns of a motion sweep and the options of
#: ``multicrank sweep motion`` are taken from it. ``axial_position`` (where the cylinder sits
#: along the shaft) is not among them: no torque of the shaft depends on it, so it is no design
#: column and the core's unit columns do not carry it.
CYLINDER_FIELDS: dict[str, tuple[str, str]] = {
    "crank_radius": ("crank radius", "m"),
    "rod_length": ("rod length", "m"),
    "piston_mass": ("piston mass", "kg"),
    "rod_mass": ("rod mass", "kg"),
    "rod_cg": ("rod centre of gravity from the piston-pin axis", "m"),
    "rod_inertia": ("rod moment of inertia about its centre of gravity", "kg·m²"),
    "crank_mass": ("crank mass", "kg"),
    "crank_cg_radius": ("crank centre-of-gravity radius", "m"),
    "counterweight_mass": ("counterweight mass", "kg"),
    "counterweight_radius": ("counterweight radius", "m"),
    "phase": ("crank phase", "rad"),
    "inclination": ("cylinder inclination to the horizontal", "rad"),
    "bore": ("cylinder bore", "m"),
    "piston_rod_diameter": ("piston-rod diameter", "m"),
}
#: The numbers of a cylinder that its gas force takes and the core's kinematics do not.
_GAS_FIELDS = ("bore", "piston_rod_diameter")
#: The fields of a cylinder that the core's kinematics and gravity take, in its order.
UNIT_FIELDS = tuple(field for field in CYLINDER_FIELDS if field not in _GAS_FIELDS)

#: The SI unit of each field of a cylinder that is a physical quantity (the angles aside): each
#: is at most MAGNITUDE_LIMIT (10³⁰) in magnitude.
_UNITS = {field: unit for field, (_, unit) in CYLINDER_FIELDS.items() if unit != "rad"}

#: A gauge pressure p(θ) [Pa] as a vectorised function of the cycle angle θ [rad].
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
        angle θ [rad] (an :class:`~multicrank.pressure.IndicatorDiagram`, say), returning
        real pressures in an array of θ's shape. It pushes the piston toward the shaft.
        A function that is not a table is evaluated once per machine, on panels of at most
        π/256 with eight Gauss–Legendre nodes each, and the steady state uses the polynomial
        through those values: it must be a pure function of θ (not one whose answer changes
        between calls), and a kink it has between nodes is rounded over one panel.
    pressure_crank_end : callable or None
        Double-acting cylinders: the crank-end chamber's gauge pressure p_c(θ) [Pa], acting
        on the area π D²/4 − π d²/4 and pushing the piston away from the shaft.
    piston_rod_diameter : float
        d [m], 0 ≤ d < D: the piston rod through the crank-end chamber.
    axial_position : float
        z [m], any finite real, default 0: where the cylinder's axis crosses the shaft, along
        the shaft from an origin of one's choice. The cylinders at one axial position are one
        **throw** (a V's two banks on a shared pin); its crank web and counterweight belong to
        it. It places the throws between the main bearings
        (:attr:`Machine.bearings <multicrank.Machine.bearings>`) and gives the moments of the
        frame's forces; no torque of the shaft depends on it.

    Raises
    ------
    MechanismError
        For any field out of its range (naming it) or geometry the core refuses. Every
        length, mass and inertia is at most 10³⁰ in magnitude (SI units; ``MAGNITUDE_LIMIT``):
        far beyond any machine, and where the products the motion forms of them stay finite.

    See Also
    --------
    Machine : Cylinders on one shaft.
    IndicatorDiagram : The gas pressure over a working cycle.

    Examples
    --------
    A car engine's cylinder with a synthetic four-stroke cycle in its own volume:

    >>> import multicrank as mc
    >>> cylinder = mc.Cylinder(crank_radius=0.04, rod_length=0.13, piston_mass=0.4,
    ...                        rod_mass=0.5, rod_cg=0.09, bore=0.09)
    >>> swept = cylinder.swept_volume()
    >>> print(f"λ = {cylinder.crank_ratio:.4f}, swept volume {swept * 1e6:.1f} cm³")
    λ = 0.3077, swept volume 508.9 cm³
    >>> cylinder = cylinder.replace(pressure=cylinder.engine_diagram(
    ...     intake_pressure=1e5, heat_release=1200, compression_ratio=10))
    >>> cylinder.pressure.strokes
    4
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
    # Last, so that the positional order of the fields above stays; a cylinder pickled before
    # it existed has none in its __dict__ and reads this class default, 0.
    axial_position: float = 0.0

    def __post_init__(self) -> None:
        for field in CYLINDER_FIELDS:
            value = getattr(self, field)
            if field == "rod_inertia" and value is None:
                continue
            value = as_scalar(value, field)
            if field in _UNITS:
                check_magnitude(value, field, _UNITS[field])
            object.__setattr__(self, field, value)
        if self.rod_inertia is None:
            object.__setattr__(self, "rod_inertia", self._two_mass_rod_inertia())
        position = check_magnitude(as_scalar(self.axial_position, "axial_position"), "axial_position", "m")
        if not math.isfinite(position):
            raise refused(
                "axial_position", f"axial_position = {position} is out of range; allowed: any finite real [m]"
            )
        object.__setattr__(self, "axial_position", position)
        if not (math.isfinite(self.bore) and self.bore >= 0):
            raise refused("bore", f"bore = {self.bore} is out of range; allowed: bore >= 0 [m]")
        if not (math.isfinite(self.piston_rod_diameter) and 0 <= self.piston_rod_diameter):
            raise refused(
                "piston_rod_diameter",
                f"piston_rod_diameter = {self.piston_rod_diameter} is out of range; allowed: >= 0 [m]",
            )
        if self.piston_rod_diameter > 0 and self.piston_rod_diameter >= self.bore:
            raise refused(
                "piston_rod_diameter",
                f"piston_rod_diameter = {self.piston_rod_diameter} is out of range; "
                f"allowed: less than bore = {self.bore}",
            )
        for name in ("pressure", "pressure_crank_end"):
            value = getattr(self, name)
            if value is not None and not callable(value):
                raise refused(name, f"{name} must be None or a callable of the cycle angle [rad] -> Pa")
        # Geometry and masses: the core's rules, checked now rather than at first use.
        _native_unit_travel(unit_columns([self]), np.zeros(0))

    @property
    def crank_ratio(self) -> float:
        """λ = r/l."""
        return self.crank_radius / self.rod_length

    @property
    def piston_area(self) -> float:
        """π D²/4 [m²], the crown's area: the core's force of a unit pressure on the head end."""
        return self._unit_pressure_force(1.0, 0.0)

    @property
    def crank_end_area(self) -> float:
        """π (D² − d²)/4 [m²], the crank-end face's area around the piston rod: the core's
        force of a unit pressure on the crank end, which pushes away from the shaft."""
        return -self._unit_pressure_force(0.0, 1.0)

    def _unit_pressure_force(self, head: float, crank_end: float) -> float:
        bore, rod = np.array([self.bore]), np.array([self.piston_rod_diameter])
        return float(_native_piston_forces(bore, rod, np.array([head]), np.array([crank_end]))[0])

    @property
    def stroke(self) -> float:
        """2r [m]: the piston's travel from outer to inner dead centre."""
        return 2.0 * self.crank_radius

    def chamber_volume(self, theta: Any, clearance_volume: float, *, end: str = "head") -> np.ndarray:
        """The volume [m³] of one of the cylinder's chambers at cycle angles θ [rad].

        The head end (over the crown): V(θ) = V_c + A·s(θ), smallest at θ = 0 (outer dead
        centre). The crank end of a double-acting cylinder (around the piston rod):
        V(θ) = V_c + A_c·(2r − s(θ)), smallest at inner dead centre. s is the piston travel
        of :meth:`Machine.piston_travel` with the cylinder's own crank angle ψ = θ (θ and ψ
        differ by whole turns, and s has period 2π), so V is the volume the synthetic cycles
        of :class:`~multicrank.IndicatorDiagram` take.

        Parameters
        ----------
        theta : array_like
            Cycle angles θ [rad], any shape.
        clearance_volume : float
            V_c [m³] > 0: the chamber's volume at its dead centre.
        end : {"head", "crank"}, default "head"
            Which chamber.

        Returns
        -------
        ndarray
            V [m³], the shape of ``theta``.

        Examples
        --------
        >>> import numpy as np
        >>> import multicrank as mc
        >>> cylinder = mc.Cylinder(crank_radius=0.04, rod_length=0.13, piston_mass=0.4,
        ...                        rod_mass=0.5, rod_cg=0.09, bore=0.09)
        >>> volume = cylinder.chamber_volume(np.radians([0, 180]), clearance_volume=1e-4)
        >>> volume * 1e6  # cm³
        array([100.        , 608.93800988])
        """
        end = as_option(end, "end", ("head", "crank"))
        clearance = as_scalar(clearance_volume, "clearance_volume")
        if not (math.isfinite(clearance) and clearance > 0):
            raise refused("clearance_volume", f"clearance_volume = {clearance} is out of range; allowed: > 0 [m³]")
        angles = as_real_array(theta, "theta")
        own = dict(unit_columns([self]), phase=np.zeros(1))
        travel = _native_unit_travel(own, contiguous(angles).reshape(-1)).reshape(angles.shape)
        if end == "head":
            return clearance + self.piston_area * travel
        return clearance + self.crank_end_area * (self.stroke - travel)

    def swept_volume(self, end: str = "head") -> float:
        """The volume a chamber's face sweeps: A·2r at the head end, A_c·2r at the crank end.

        Parameters
        ----------
        end : {"head", "crank"}, default "head"
            Which chamber.

        Returns
        -------
        float
            The swept volume [m³].
        """
        end = as_option(end, "end", ("head", "crank"))
        return (self.piston_area if end == "head" else self.crank_end_area) * self.stroke

    def _clearance(self, end: str, given: dict[str, Any]) -> float:
        """V_c [m³] from exactly one of clearance_volume, clearance_ratio, compression_ratio."""
        named = {name: value for name, value in given.items() if value is not None}
        if len(named) != 1:
            raise refused(
                next(iter(given)), f"give exactly one of {', '.join(given)} (got {', '.join(named) or 'none'})"
            )
        if not self.bore > 0:
            raise refused("bore", f"bore = {self.bore}: a synthetic cycle needs a piston (bore > 0) [m]")
        ((name, value),) = named.items()
        value = as_scalar(value, name)
        swept = self.swept_volume(end)
        if name == "clearance_volume" and math.isfinite(value) and value > 0:
            return value
        if name == "clearance_ratio" and math.isfinite(value) and value > 0:
            return value * swept
        if name == "compression_ratio" and math.isfinite(value) and value > 1:
            return swept / (value - 1.0)
        allowed = {
            "clearance_volume": "> 0 [m³]",
            "clearance_ratio": "> 0 (V_c over the swept volume)",
            "compression_ratio": "> 1 ((V_s + V_c)/V_c)",
        }
        raise refused(name, f"{name} = {value} is out of range; allowed: {allowed[name]}")

    def compressor_diagram(
        self,
        *,
        suction_pressure: float,
        discharge_pressure: float,
        clearance_ratio: float | None = None,
        clearance_volume: float | None = None,
        end: str = "head",
        **options: Any,
    ) -> IndicatorDiagram:
        """The ideal compressor cycle (:meth:`IndicatorDiagram.compressor`) in one of this
        cylinder's chambers, of volume :meth:`chamber_volume`.

        Parameters
        ----------
        suction_pressure, discharge_pressure : float
            [Pa], absolute unless ``absolute=False`` is among ``options``.
        clearance_ratio, clearance_volume : float
            Exactly one: V_c over the chamber's swept volume (:meth:`swept_volume`), or V_c [m³].
        end : {"head", "crank"}
            The chamber: "crank" for the crank end of a double-acting cylinder (its diagram
            goes to ``pressure_crank_end``).
        **options
            The other keywords of :meth:`IndicatorDiagram.compressor` (``cycle`` 2π by
            default: the machine's cycle is the one to give).

        Returns
        -------
        IndicatorDiagram
            Gauge pressures [Pa] over the cycle.

        Examples
        --------
        >>> import multicrank as mc
        >>> cylinder = mc.Cylinder(crank_radius=0.15, rod_length=0.6, piston_mass=85,
        ...                        rod_mass=60, rod_cg=0.4, bore=0.3)
        >>> diagram = cylinder.compressor_diagram(
        ...     suction_pressure=1e5, discharge_pressure=4e5, clearance_ratio=0.08)
        >>> clearance = 0.08 * cylinder.swept_volume()
        >>> work = diagram.indicated_work(
        ...     lambda theta: cylinder.chamber_volume(theta, clearance))
        >>> print(f"∮p dV = {work:.0f} J per cycle (the work the compressor takes)")
        ∮p dV = -2936 J per cycle (the work the compressor takes)
        """
        end = as_option(end, "end", ("head", "crank"))
        clearance = self._clearance(end, {"clearance_ratio": clearance_ratio, "clearance_volume": clearance_volume})
        return IndicatorDiagram.compressor(
            lambda theta: self.chamber_volume(theta, clearance, end=end),
            suction_pressure=suction_pressure,
            discharge_pressure=discharge_pressure,
            **options,
        )

    def engine_diagram(
        self,
        *,
        intake_pressure: float,
        heat_release: float,
        compression_ratio: float | None = None,
        clearance_volume: float | None = None,
        **options: Any,
    ) -> IndicatorDiagram:
        """The single-zone engine cycle (:meth:`IndicatorDiagram.engine`) over this cylinder's
        crown, in the head-end volume :meth:`chamber_volume`; it fires at θ = 0.

        Parameters
        ----------
        intake_pressure : float
            [Pa], absolute unless ``absolute=False`` is among ``options``.
        heat_release : float
            [J per cycle].
        compression_ratio, clearance_volume : float
            Exactly one: ε = (V_s + V_c)/V_c, or V_c [m³].
        **options
            The other keywords of :meth:`IndicatorDiagram.engine` (``cycle`` 4π by default).

        Returns
        -------
        IndicatorDiagram
            Gauge pressures [Pa] over the cycle.
        """
        clearance = self._clearance(
            "head", {"compression_ratio": compression_ratio, "clearance_volume": clearance_volume}
        )
        return IndicatorDiagram.engine(
            lambda theta: self.chamber_volume(theta, clearance),
            intake_pressure=intake_pressure,
            heat_release=heat_release,
            **options,
        )

    def replace(self, **changes: Any) -> Cylinder:
        """A copy with some fields changed.

        Parameters
        ----------
        **changes
            New values of any of the fields (the parameters of :class:`Cylinder`).

        Returns
        -------
        Cylinder
            The changed copy, checked as a new one is. A two-mass rod stays one: where
            ``rod_inertia`` is the two-mass value m_k z_k (l − z_k) (the default) and the
            change moves ``rod_mass``, ``rod_length`` or ``rod_cg`` but gives no
            ``rod_inertia``, the copy's is the two-mass value of its own rod.

        Raises
        ------
        MechanismError
            For a keyword that is no field (naming it and listing the fields), or a value the
            new cylinder refuses.
        """
        check_fields(changes, tuple(f.name for f in dataclasses.fields(self)), "cylinder")
        rod = {"rod_mass", "rod_length", "rod_cg"}
        if "rod_inertia" not in changes and rod & changes.keys() and self._two_mass_rod():
            changes["rod_inertia"] = None
        return dataclasses.replace(self, **changes)

    def _two_mass_rod_inertia(self) -> float:
        """The two-mass rod's I_k (ΔI = 0), by the core's formula; at least 0, so that a rod_cg
        outside 0…l is reported as such by the core's check, not as a negative inertia."""
        return max(_native_two_mass_rod_inertia(self.rod_mass, self.rod_length, self.rod_cg), 0.0)

    def _two_mass_rod(self) -> bool:
        """Whether the rod's inertia is the two-mass rod's (ΔI = 0)."""
        return self.rod_inertia == self._two_mass_rod_inertia()


def unit_columns(cylinders: Sequence[Cylinder]) -> dict[str, np.ndarray]:
    """The units as the core's bundle of equal-length float64 columns: the rows of one new
    (fields, units) array, each C-contiguous (made in one call: a machine's first question
    pays for this)."""
    # A row of fields a unit, read by attrgetter in one call (a getattr a field and unit
    # took a V12's first steady state ~3%), then turned into a column a field.
    rows = np.array([_unit_row(c) for c in cylinders], dtype=np.float64).reshape(len(cylinders), len(UNIT_FIELDS))
    return dict(zip(UNIT_FIELDS, rows.T.copy(), strict=True))


_unit_row = operator.attrgetter(*UNIT_FIELDS)


def diagram_strokes(cylinder: Cylinder) -> int | None:
    """The strokes of the longest indicator diagram (one with a ``cycle``) on a cylinder, if any."""
    cycles = [getattr(getattr(cylinder, end), "cycle", None) for end in ("pressure", "pressure_crank_end")]
    longest = max((c for c in cycles if isinstance(c, float)), default=None)
    return None if longest is None else round(longest / math.pi)
