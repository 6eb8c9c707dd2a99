"""Torsion: the torsional questions about a machine's shaft. The shaft itself (:class:`Shaft`) is
a part of the machine (``machine/shaft``, re-exported here); this room holds the chain's modes
(``_chain``, which :meth:`Shaft.modes` asks), each cylinder's excitation of the shaft
(``excitation``: its torque orders at its phase), the torsional merit of a firing order
(:func:`~multicrank.torsional_merit`, in ``merit``) and the hand-off to openTorsion
(:func:`~multicrank.to_opentorsion` and :class:`~multicrank.TorsionalModel`, in ``handoff``).
It imports the machine and its motion; nothing below it imports it at load time."""

from __future__ import annotations

from ..machine.shaft import Shaft, ShaftModes
from .handoff import TorsionalModel, to_opentorsion
from .merit import torsional_merit

__all__ = ["Shaft", "ShaftModes", "TorsionalModel", "to_opentorsion", "torsional_merit"]
