"""Every preset in one place: the built-in machines with physical parameters, and the crank
and cylinder layouts (in-line, V, boxer, W, odd-fire).

The machines' numbers are illustrative: plausible for the class of machine named, not taken
from any one manufacturer's data sheet.
"""

from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ._native import MechanismError
from .layouts import LAYOUTS, Layout, layout_engine
from .mechanism import STANDARD_GRAVITY, crank_phases, dimensionless_moments

__all__ = [
    "DEFAULT_ENGINE",
    "ENGINES",
    "LAYOUTS",
    "Layout",
    "Machine",
    "engine_by_name_or_file",
    "layout_engine",
    "load_engine",
]


@dataclass(frozen=True)
class Machine:
    """An in-line machine of identical slider-crank units on one shaft, in SI units (for the
    cylinder-level description of any layout see :class:`multicrank.Engine`).

    Masses are per cylinder; ``shaft_inertia`` is the whole shaft with everything turning
    with it (flywheel included); ``inclination_deg`` is the cylinder axis to the horizontal
    (90 = upright).
    """

    name: str
    note: str
    cranks: int
    strokes: int
    acting: str
    inclination_deg: float
    crank_radius: float
    rod_length: float
    rod_cg: float
    piston_mass: float
    rod_mass: float
    crank_mass: float
    crank_cg_radius: float
    counterweight_mass: float
    counterweight_radius: float
    shaft_inertia: float
    rpm: float
    #: The speeds [rpm] over which the machine runs (for the gravity-significance map).
    rpm_range: tuple[float, float] = (0.0, 0.0)
    g: float = STANDARD_GRAVITY

    @property
    def crank_ratio(self) -> float:
        """λ = r/l."""
        return self.crank_radius / self.rod_length

    @property
    def inclination(self) -> float:
        """γ in radians."""
        return math.radians(self.inclination_deg)

    def phases(self) -> np.ndarray:
        """The crank phases α_j (rad)."""
        return crank_phases(self.cranks, self.strokes, self.acting)

    def moments(self, rpm: float | None = None) -> tuple[float, float]:
        """(u1, u2) at ``rpm`` (default: the engine's own speed)."""
        u1, u2 = self.moments_over(self.rpm if rpm is None else rpm)
        return float(u1), float(u2)

    def moments_over(self, rpm: Any) -> tuple[Any, Any]:
        """(u1, u2) at every speed of ``rpm`` [1/min] (arrays of its shape)."""
        return dimensionless_moments(
            crank_radius=self.crank_radius,
            rod_length=self.rod_length,
            rod_cg=self.rod_cg,
            piston_mass=self.piston_mass,
            rod_mass=self.rod_mass,
            crank_mass=self.crank_mass,
            crank_cg_radius=self.crank_cg_radius,
            counterweight_mass=self.counterweight_mass,
            counterweight_radius=self.counterweight_radius,
            shaft_inertia=self.shaft_inertia,
            rpm=rpm,
            g=self.g,
        )

    def design(self, rpm: float | None = None) -> dict:
        """The keywords of the evaluation functions for this engine."""
        u1, u2 = self.moments(rpm)
        return dict(
            crank_ratio=self.crank_ratio,
            inclination=self.inclination,
            u1=u1,
            u2=u2,
            phases=self.phases(),
        )

    def speeds(self) -> tuple[float, float]:
        """The speed range [rpm]; the running speed ±50 % where none was given."""
        low, high = self.rpm_range
        return (low, high) if high > low > 0 else (0.5 * self.rpm, 1.5 * self.rpm)

    def replace(self, **changes) -> Machine:
        return dataclasses.replace(self, **changes)


SLOW_COMPRESSOR = Machine(
    name="slow-compressor",
    note=(
        "Illustrative heavy, slow single-cylinder upright double-acting air compressor: "
        "300 mm stroke, 85 kg piston with rod, light flywheel, 120 rpm — the kind of "
        "machine the paper had in mind, where gravity is not negligible."
    ),
    cranks=1,
    strokes=2,
    acting="double",
    inclination_deg=90.0,
    crank_radius=0.150,
    rod_length=0.600,
    rod_cg=0.400,
    piston_mass=85.0,
    rod_mass=60.0,
    crank_mass=40.0,
    crank_cg_radius=0.080,
    counterweight_mass=30.0,
    counterweight_radius=0.120,
    shaft_inertia=45.0,
    rpm=120.0,
    rpm_range=(60.0, 300.0),
)

MARINE_TWIN = Machine(
    name="marine-2t-twin",
    note=(
        "Illustrative two-cylinder two-stroke marine engine (small fishing-vessel class): "
        "300 mm stroke, λ ≈ 0.23, cranks at 180°, 300 rpm rated."
    ),
    cranks=2,
    strokes=2,
    acting="single",
    inclination_deg=90.0,
    crank_radius=0.150,
    rod_length=0.650,
    rod_cg=0.430,
    piston_mass=60.0,
    rod_mass=55.0,
    crank_mass=45.0,
    crank_cg_radius=0.090,
    counterweight_mass=40.0,
    counterweight_radius=0.130,
    shaft_inertia=60.0,
    rpm=300.0,
    rpm_range=(150.0, 400.0),
)

INLINE_FOUR = Machine(
    name="inline-4",
    note=(
        "Illustrative in-line four four-stroke car petrol engine: 85 mm stroke, 140 mm rods, "
        "flywheel and crank 0.18 kg·m², from 800 rpm idle."
    ),
    cranks=4,
    strokes=4,
    acting="single",
    inclination_deg=90.0,
    crank_radius=0.0425,
    rod_length=0.140,
    rod_cg=0.100,
    piston_mass=0.45,
    rod_mass=0.55,
    crank_mass=1.2,
    crank_cg_radius=0.030,
    counterweight_mass=1.3,
    counterweight_radius=0.035,
    shaft_inertia=0.18,
    rpm=800.0,
    rpm_range=(600.0, 6500.0),
)

INLINE_SIX = Machine(
    name="inline-6",
    note=(
        "Illustrative in-line six four-stroke truck diesel: 140 mm stroke, 230 mm rods, "
        "1.8 kg·m² with flywheel, 600 rpm idle to 2200 rpm."
    ),
    cranks=6,
    strokes=4,
    acting="single",
    inclination_deg=90.0,
    crank_radius=0.070,
    rod_length=0.230,
    rod_cg=0.160,
    piston_mass=2.5,
    rod_mass=3.0,
    crank_mass=4.0,
    crank_cg_radius=0.045,
    counterweight_mass=4.2,
    counterweight_radius=0.060,
    shaft_inertia=1.8,
    rpm=600.0,
    rpm_range=(500.0, 2200.0),
)

SLOW_DIESEL_12 = Machine(
    name="slow-diesel-12",
    note=(
        "Illustrative in-line twelve-cylinder slow-speed two-stroke crosshead diesel (large "
        "ship propulsion): 2.5 m stroke, piston + piston rod + crosshead ≈ 15 t per cylinder, "
        "shaft with flywheel and propeller ≈ 1.5·10⁶ kg·m², 90 rpm rated."
    ),
    cranks=12,
    strokes=2,
    acting="single",
    inclination_deg=90.0,
    crank_radius=1.25,
    rod_length=3.0,
    rod_cg=2.0,
    piston_mass=15000.0,
    rod_mass=12000.0,
    crank_mass=18000.0,
    crank_cg_radius=0.8,
    counterweight_mass=12000.0,
    counterweight_radius=1.2,
    shaft_inertia=1.5e6,
    rpm=90.0,
    rpm_range=(25.0, 100.0),
)

DEFAULT_ENGINE = SLOW_COMPRESSOR
ENGINES = {e.name: e for e in (SLOW_COMPRESSOR, MARINE_TWIN, INLINE_FOUR, INLINE_SIX, SLOW_DIESEL_12)}


def load_engine(path: str | os.PathLike) -> Machine:
    """An engine from a TOML file: the fields of :class:`Machine` at top level or in an
    ``[engine]`` table (``name`` and ``note`` optional; ``rpm_range`` a two-element list)."""
    import tomllib

    with open(path, "rb") as handle:
        data = tomllib.load(handle)
    data = data.get("engine", data)
    data.setdefault("name", Path(path).stem)
    data.setdefault("note", f"user engine from {Path(path).name}")
    known = {f.name for f in dataclasses.fields(Machine)}
    unknown = sorted(set(data) - known)
    if unknown:
        raise MechanismError(f"{path}: unknown engine field(s) {', '.join(unknown)}; known: {', '.join(sorted(known))}")
    missing = sorted(
        f.name for f in dataclasses.fields(Machine) if f.name not in data and f.default is dataclasses.MISSING
    )
    if missing:
        raise MechanismError(f"{path}: missing engine field(s) {', '.join(missing)}")
    if "rpm_range" in data:
        data["rpm_range"] = tuple(float(v) for v in data["rpm_range"])
    engine = Machine(**data)
    engine.design()  # validates every number through the API
    return engine


def engine_by_name_or_file(spec: str) -> Machine:
    """A built-in engine by name, or one loaded from a TOML file path."""
    if spec in ENGINES:
        return ENGINES[spec]
    if os.path.exists(spec):
        return load_engine(spec)
    raise MechanismError(f"engine = {spec!r} is neither a built-in engine ({', '.join(ENGINES)}) nor a TOML file")
