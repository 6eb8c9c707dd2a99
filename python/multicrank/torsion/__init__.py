"""Torsion: the machine's shaft as a chain of inertias and stiffnesses (:class:`Shaft`) and its
natural frequencies and mode shapes; the torsional merit of a firing order
(:func:`~multicrank.torsional_merit`, in ``merit``)."""

from __future__ import annotations

from .shaft import Shaft, ShaftModes

# merit (torsional_merit) imports the Machine, which imports the Shaft: mc.torsional_merit
# loads it on first use.
__all__ = ["Shaft", "ShaftModes"]
