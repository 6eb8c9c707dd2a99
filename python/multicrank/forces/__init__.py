"""Forces on the frame: the shaking forces and moments by order (:func:`shaking_forces`)."""

from __future__ import annotations

from .shaking import ShakingForces, shaking_forces

__all__ = ["ShakingForces", "shaking_forces"]
