"""Torsion: the torsional questions about a machine's shaft (the shaft itself, :class:`Shaft`, is
a part of the machine: :mod:`multicrank.machine.shaft`, re-exported here) — the chain's modes
(``_chain``, which :meth:`Shaft.modes` asks), the torsional merit of a firing order
(:func:`~multicrank.torsional_merit`, in ``merit``) and the hand-off to openTorsion
(``handoff``)."""

from __future__ import annotations

from ..machine.shaft import Shaft, ShaftModes

# merit (torsional_merit) imports the Machine, which imports the Shaft: mc.torsional_merit
# loads it on first use.
__all__ = ["Shaft", "ShaftModes"]
