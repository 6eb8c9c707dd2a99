"""Forces on the frame and the bearings: the shaking forces and moments by order
(:func:`shaking_forces`) and the main-bearing loads (:func:`bearing_loads`)."""

from __future__ import annotations

from .bearings import BearingLoads, bearing_loads
from .shaking import ShakingForces, shaking_forces

__all__ = ["BearingLoads", "ShakingForces", "bearing_loads", "shaking_forces"]
