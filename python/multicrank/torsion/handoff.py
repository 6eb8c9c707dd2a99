"""A machine's shaft and its cylinders' torques as an openTorsion model (the ``torsion`` extra):
:func:`torsional_model`, which :func:`~multicrank.to_opentorsion` calls for a machine.

The shaft (:class:`~multicrank.Shaft`) becomes an ``opentorsion.Assembly`` of one disk per node
(I = J_i, its damping to ground c = the node's) and one massless shaft element per section (k_i,
c_i); each cylinder's torque acts at
its own node, node i taking the sum over the cylinders on it. A component of angular frequency
ν·ω_m and complex amplitude T stands, in openTorsion's convention, for Re(T e^{iνω_m t}).

This module imports neither :mod:`multicrank.motion.orders` (which computes the torques and
calls it) nor :mod:`multicrank.torsion.merit` (which imports that): the package's modules
import one another without a circle.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from .._optional import require
from ..machine.shaft import Shaft

__all__ = ["TorsionalModel", "assembly_of", "torsional_model"]


class TorsionalModel(NamedTuple):
    """A machine's torsional model for openTorsion (:func:`~multicrank.to_opentorsion`).

    Attributes
    ----------
    assembly : opentorsion.Assembly
        The shaft: ``opentorsion.Disk(i, I=J_i, c=node_damping_i)`` at each node [kg·m²,
        N·m·s/rad] and ``opentorsion.Shaft(i, i + 1, k=k_i, c=c_i)`` for each section [N·m/rad,
        N·m·s/rad], massless (its inertia is in the nodes'); a damping the shaft does not give
        is 0.
    excitation : opentorsion.PeriodicExcitation
        ``omegas`` the orders' angular frequencies ν·ω_m [rad/s]; ``U[i]`` the complex
        amplitudes [N·m] of the torques of the cylinders at node i (zero where there are none).
    """

    assembly: Any
    excitation: Any


def assembly_of(shaft: Shaft, opentorsion: Any) -> Any:
    """The ``opentorsion.Assembly`` of a :class:`~multicrank.Shaft`: a disk per node with its
    damping to ground, a massless shaft element per section (``opentorsion`` the module)."""
    damping = shaft.damping or (0.0,) * len(shaft.stiffness)
    node_damping = shaft.node_damping or (0.0,) * len(shaft.inertia)
    elements = [
        opentorsion.Shaft(i, i + 1, k=k, c=c) for i, (k, c) in enumerate(zip(shaft.stiffness, damping, strict=True))
    ]
    disks = [
        opentorsion.Disk(i, I=inertia, c=c)
        for i, (inertia, c) in enumerate(zip(shaft.inertia, node_damping, strict=True))
    ]
    return opentorsion.Assembly(elements, disk_elements=disks)


def torsional_model(shaft: Shaft, frequencies: np.ndarray, torques: np.ndarray) -> TorsionalModel:
    """The openTorsion model of ``shaft`` driven by its cylinders' torques.

    Parameters
    ----------
    shaft : Shaft
        The shaft, each cylinder's node in ``shaft.cylinder_nodes``.
    frequencies : ndarray
        The components' angular frequencies [rad/s], shape (components,).
    torques : ndarray
        Each cylinder's complex amplitude of each component [N·m], shape (cylinders,
        components), in the order of ``shaft.cylinder_nodes``.

    Returns
    -------
    TorsionalModel
        The assembly, and the excitation whose ``U[i]`` sums the torques of the cylinders at
        node i.
    """
    opentorsion = require("opentorsion", "torsion")
    amplitude = np.zeros((len(shaft.inertia), frequencies.size), dtype=complex)
    np.add.at(amplitude, list(shaft.cylinder_nodes), torques)
    excitation = opentorsion.PeriodicExcitation(len(shaft.inertia), frequencies)
    for node in sorted(set(shaft.cylinder_nodes)):
        excitation.add_sines(node, frequencies, np.abs(amplitude[node]), np.angle(amplitude[node]))
    return TorsionalModel(assembly_of(shaft, opentorsion), excitation)
