"""Built-in engines with physical parameters.

The numbers are illustrative: plausible for the class of machine named, not taken from
any one manufacturer's data sheet.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .mechanism import STANDARD_GRAVITY, crank_phases, dimensionless_moments

__all__ = ["Engine", "DEFAULT_ENGINE", "ENGINES"]


@dataclass(frozen=True)
class Engine:
    """An in-line machine of identical slider-crank units on one shaft (SI units).

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
        u1, u2 = dimensionless_moments(
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
            rpm=self.rpm if rpm is None else rpm,
            g=self.g,
        )
        return float(u1), float(u2)

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

    def replace(self, **changes) -> "Engine":
        return dataclasses.replace(self, **changes)


SLOW_COMPRESSOR = Engine(
    name="slow-compressor",
    note=(
        "Illustrative heavy, slow single-cylinder upright air compressor: 300 mm stroke, "
        "large crosshead-less piston, light flywheel, 120 rpm — the kind of machine the "
        "paper had in mind, where gravity is not negligible."
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
)

DEFAULT_ENGINE = SLOW_COMPRESSOR
ENGINES = {e.name: e for e in (SLOW_COMPRESSOR,)}
