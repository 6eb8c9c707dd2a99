"""Torsion: the machine's shaft as a chain of inertias and stiffnesses (:class:`Shaft`) and its
natural frequencies and mode shapes."""

from __future__ import annotations

from .shaft import Shaft, ShaftModes

__all__ = ["Shaft", "ShaftModes"]
