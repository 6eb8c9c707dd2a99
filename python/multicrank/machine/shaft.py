"""A machine's shaft as a torsional chain (issue "Firing orders and counterweights judged as an
engine designer judges them", item 1): inertias joined by torsional stiffnesses, a part of the
machine (``Machine.shaft``) like its cylinders, and its natural frequencies and mode shapes.

The undamped free–free chain J θ̈ + K θ = 0, with J = diag(J_0 … J_{n−1}) [kg·m²] and K the
tridiagonal stiffness matrix of the n − 1 shaft sections k_i [N·m/rad] between nodes i and
i + 1 (K_ii = k_{i−1} + k_i, K_{i,i+1} = −k_i), has modes θ = a e^{iωt} with K a = ω² J a. The
first, ω = 0, turns the shaft as a rigid body, and the elastic modes 1, 2, … follow; the
torsion room's ``_chain``, which :meth:`Shaft.modes` asks, finds them from the chain's numbers
directly (Holzer's recurrence, bisected on its Sturm count), each ω² to a few units in its last
digit however stiff, light or long the chain, in time and memory of the order of the nodes × the
modes asked.

A shaft comes from numbers (:class:`Shaft`), from a machine file's ``[shaft]`` table
(:meth:`Shaft.from_toml`) or from an openTorsion model (:meth:`Shaft.from_opentorsion`);
the torsional questions about it are the torsion room's (:mod:`multicrank.torsion`:
:func:`~multicrank.torsional_merit`, and :func:`~multicrank.to_opentorsion`, which hands a
machine and its shaft back to openTorsion). This module imports nothing of that room at load
time: the machine is below it.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._native import MechanismError
from .._optional import require
from .._validation import MAGNITUDE_LIMIT, as_count, as_instance, as_real_array, as_scalar, part_of, refused
from .files import MachineFile, read_shaft_file

__all__ = ["Shaft", "ShaftModes", "shaft_of", "shaft_of_file"]

# The one loader of a whole machine file, Machine.from_toml, handed over by machine.machine
# when it is defined (use_machine_loader): it builds this module's Shafts, so this module
# cannot import it without a circle (tests/test_imports.py counts lazy imports too);
# Shaft.from_toml of a machine file checks it through it.
_machine_loader: Callable[[Any], Any] | None = None


def use_machine_loader(load: Callable[[Any], Any]) -> None:
    """Set the reader of whole machine files that :meth:`Shaft.from_toml` checks them by
    (``Machine.from_toml``; machine.machine calls this once)."""
    global _machine_loader
    _machine_loader = load


def _positive_list(values: Any, name: str, unit: str) -> tuple[float, ...]:
    array = as_real_array(values, name).astype(float)
    if array.ndim != 1:
        raise refused(name, f"{name} must be a 1-D sequence [{unit}], got shape {array.shape}")
    bad = np.flatnonzero(~((array > 0) & (array <= MAGNITUDE_LIMIT)))  # NaN fails too
    if bad.size:
        raise refused(
            name,
            f"{name}[{bad[0]}] = {array[bad[0]]} is out of range; allowed: 0 < {name} <= {MAGNITUDE_LIMIT:g} [{unit}]",
        )
    return tuple(float(v) for v in array)


def _damping_list(values: Any, name: str, count: int, where: str) -> tuple[float, ...] | None:
    """None, or ``count`` damping coefficients 0 <= c <= MAGNITUDE_LIMIT [N·m·s/rad], one per
    ``where``."""
    if values is None:
        return None
    array = as_real_array(values, name).astype(float)
    if array.shape != (count,) or not np.all((array >= 0) & (array <= MAGNITUDE_LIMIT)):  # NaN fails too
        raise refused(
            name, f"{name} must hold {count} values 0 <= c <= {MAGNITUDE_LIMIT:g} [N·m·s/rad], one per {where}"
        )
    return tuple(float(v) for v in array)


@dataclass(frozen=True, eq=False)
class ShaftModes:
    """The elastic modes of a :class:`Shaft` (the rigid-body mode left out).

    Attributes
    ----------
    natural_frequency : ndarray
        f_m [Hz] of modes 1, 2, … (increasing), shape (modes,): every elastic mode, or the
        lowest ``count`` asked of :meth:`Shaft.modes`.
    shapes : ndarray
        The mode shapes a_m: the nodes' relative amplitudes, shape (nodes, modes), each
        column scaled so that its largest magnitude is 1, positive at the first node that has
        it (to 1e-9: two nodes may swing equally).
    """

    natural_frequency: np.ndarray
    shapes: np.ndarray


@dataclass(frozen=True)
class Shaft:
    """A shaft as a chain of torsional inertias and stiffnesses.

    Parameters
    ----------
    inertia : sequence of float
        J_i [kg·m²] > 0 of each node along the chain (the throws, the flywheel, the driven
        machine), at least two.
    stiffness : sequence of float
        k_i [N·m/rad] > 0 of the shaft section between node i and node i + 1: one fewer than
        the nodes.
    cylinder_nodes : sequence of int
        The node of each cylinder, in ``machine.cylinders`` order (several cylinders may share
        a node: a V's throw).
    damping : sequence of float, optional
        c_i [N·m·s/rad] ≥ 0 of each section (its internal damping, between nodes i and i + 1),
        kept for the forced response a torsional tool computes (the natural frequencies here
        are those of the undamped chain). None: 0 in every section.
    node_damping : sequence of float, optional
        c_i [N·m·s/rad] ≥ 0 of each node, one per node: damping to ground, absolute (a
        propeller in the water, a damper), the torque −c_i θ̇_i on node i;
        openTorsion's disk damping. Like ``damping``, for the forced response only. None: 0
        at every node.

    Notes
    -----
    A node's inertia is used as given: for the mean inertia of a cylinder's running gear add
    its share to its node (the crank's rotating masses m r², and half the reciprocating mass
    m_rec r²/2 on average over a revolution).

    Examples
    --------
    Two equal discs on a shaft: one elastic mode, at √(2k/J)/(2π), the discs swinging against
    each other.

    >>> import multicrank as mc
    >>> shaft = mc.Shaft([1.0, 1.0], [2.0e4], cylinder_nodes=[0])
    >>> modes = shaft.modes()
    >>> round(float(modes.natural_frequency[0]), 3)
    31.831
    >>> modes.shapes[:, 0].round(6).tolist()
    [1.0, -1.0]
    """

    inertia: tuple[float, ...]
    stiffness: tuple[float, ...]
    cylinder_nodes: tuple[int, ...]
    damping: tuple[float, ...] | None = None
    # A class default too: a shaft pickled before node damping existed reads None.
    node_damping: tuple[float, ...] | None = None

    def __init__(
        self, inertia: Any, stiffness: Any, *, cylinder_nodes: Any, damping: Any = None, node_damping: Any = None
    ) -> None:
        inertias = _positive_list(inertia, "inertia", "kg·m²")
        if len(inertias) < 2:
            raise refused("inertia", f"inertia must hold at least two nodes, got {len(inertias)}")
        stiffnesses = _positive_list(stiffness, "stiffness", "N·m/rad")
        if len(stiffnesses) != len(inertias) - 1:
            raise refused(
                "stiffness",
                f"stiffness must hold one fewer value than inertia ({len(inertias) - 1}), got {len(stiffnesses)}",
            )
        try:
            nodes = np.asarray(cylinder_nodes)
        except (ValueError, TypeError):  # ragged
            nodes = np.asarray(None)
        if nodes.ndim != 1 or nodes.size == 0 or nodes.dtype.kind not in "iu":
            raise refused(
                "cylinder_nodes", f"cylinder_nodes must be a non-empty 1-D sequence of integers, got {cylinder_nodes!r}"
            )
        bad = np.flatnonzero((nodes < 0) | (nodes >= len(inertias)))
        if bad.size:
            raise refused(
                "cylinder_nodes",
                f"cylinder_nodes[{bad[0]}] = {nodes[bad[0]]} is out of range; allowed: 0 <= node < {len(inertias)}",
            )
        dampings = _damping_list(damping, "damping", len(stiffnesses), "shaft section")
        node_dampings = _damping_list(node_damping, "node_damping", len(inertias), "node")
        object.__setattr__(self, "inertia", inertias)
        object.__setattr__(self, "stiffness", stiffnesses)
        object.__setattr__(self, "cylinder_nodes", tuple(int(n) for n in nodes))
        object.__setattr__(self, "damping", dampings)
        object.__setattr__(self, "node_damping", node_dampings)

    @classmethod
    def from_opentorsion(cls, assembly: Any, *, cylinder_nodes: Any) -> Shaft:
        """The shaft of an openTorsion model (the ``torsion`` extra).

        Parameters
        ----------
        assembly : opentorsion.Assembly
            A chain: shaft elements (``opentorsion.Shaft``) each joining two neighbouring
            nodes i and i + 1 (in any order in the list), one per section, every node
            0 … n − 1 on it, and disks (``opentorsion.Disk``) at its nodes, each with its
            inertia I and, where it has one, its damping c to ground.
        cylinder_nodes : sequence of int
            The node of each cylinder, as for :class:`Shaft`.

        Returns
        -------
        Shaft
            ``inertia`` J_i [kg·m²]: the disks' I at node i plus the inertia each shaft element
            lumps there — half of its own, the sum of its mass matrix's row (openTorsion gives
            an element a consistent mass matrix m·[[2, 1], [1, 2]], of total 6 m: ρ I_p L for
            one given by its geometry, 6 I for one given ``k`` and ``I``); ``stiffness`` the
            elements' k [N·m/rad]; ``damping`` their c [N·m·s/rad], None where every c is 0;
            ``node_damping`` the disks' c at node i [N·m·s/rad] (summed where several share
            it), None where every c is 0.

        Raises
        ------
        MechanismError
            For what a chain of inertias and stiffnesses cannot hold, naming it: gear or
            elastic-gear elements, a disk's stiffness k to ground, an element
            that joins nodes not neighbours (a branched model), two on one section, a node
            that no element reaches (a broken chain), a node without inertia; and for what
            :class:`Shaft` refuses (a stiffness ≤ 0, a damping < 0, a bad ``cylinder_nodes``),
            naming it.
        OptionalDependencyError
            Without openTorsion.

        Notes
        -----
        The element inertias are *lumped* at their ends, where openTorsion's matrix is
        consistent (the total inertia, the rigid body's, is the same): for elements with
        inertia the natural frequencies here differ from openTorsion's, typically lower —
        slightly where the disks outweigh the elements (a crankshaft's throws and flywheel),
        more where they do not (split such an element into several). For massless elements
        (``I=0``, the default with ``k``) the two models are the same.

        Examples
        --------
        >>> import opentorsion as ot
        >>> import multicrank as mc
        >>> model = ot.Assembly([ot.Shaft(0, 1, k=2.0e4)], disk_elements=[ot.Disk(0, I=1.0), ot.Disk(1, I=1.0)])
        >>> shaft = mc.Shaft.from_opentorsion(model, cylinder_nodes=[0])
        >>> shaft.inertia, shaft.stiffness, shaft.damping, shaft.node_damping
        ((1.0, 1.0), (20000.0,), None, None)
        """
        opentorsion = require("opentorsion", "torsion")
        if not isinstance(assembly, opentorsion.Assembly):
            raise refused("assembly", f"assembly must be an opentorsion.Assembly, got {type(assembly).__name__}")
        for attribute, kind in (("gear_elements", "Gear"), ("elastic_gear_elements", "ElasticGear")):
            if getattr(assembly, attribute, None):
                raise refused(
                    "assembly",
                    f"assembly holds {attribute} (opentorsion.{kind}): a Shaft is one chain of inertias and "
                    "stiffnesses, without gears",
                )
        count = _node(getattr(assembly, "dofs", None), "assembly.dofs", None)
        inertia = np.zeros(count)
        stiffness: list[float | None] = [None] * max(count - 1, 0)
        damping = [0.0] * max(count - 1, 0)
        node_damping = [0.0] * count
        for index, element in enumerate(assembly.shaft_elements or ()):
            ends = sorted(
                _node(getattr(element, end, None), f"assembly.shaft_elements[{index}].{end}", count)
                for end in ("nl", "nr")
            )
            section = ends[0]
            if ends[1] != section + 1:
                raise refused(
                    "assembly",
                    f"assembly.shaft_elements[{index}] joins nodes {ends[0]} and {ends[1]}: a Shaft's section i "
                    "joins node i to node i + 1 (a branched or looped model cannot be one chain)",
                )
            if stiffness[section] is not None:
                raise refused(
                    "assembly",
                    f"assembly.shaft_elements[{index}] is a second element between nodes {section} and "
                    f"{section + 1}: a Shaft holds one per section",
                )
            stiffness[section] = _number(element.k, f"assembly.shaft_elements[{index}].k")
            damping[section] = _number(element.c, f"assembly.shaft_elements[{index}].c")
            # Lumped: each end takes its row of the element's mass matrix (half the element).
            inertia[ends] += np.asarray(element.M(), dtype=float).sum(axis=1)
        for index, disk in enumerate(assembly.disk_elements or ()):
            where = f"assembly.disk_elements[{index}]"
            at = _node(getattr(disk, "node", None), f"{where}.node", count)
            grounded = _number(getattr(disk, "k", 0.0), f"{where}.k")
            if grounded != 0:
                raise refused(
                    "assembly",
                    f"{where}.k = {grounded!r}: a stiffness to ground at node {at}; a Shaft is a free chain, "
                    "without one",
                )
            inertia[at] += _number(disk.I, f"{where}.I")
            node_damping[at] += _number(getattr(disk, "c", 0.0), f"{where}.c")
        broken = [i for i, k in enumerate(stiffness) if k is None]
        if broken:
            raise refused(
                "assembly",
                f"assembly has no shaft element between nodes {broken[0]} and {broken[0] + 1}: the chain is broken",
            )
        empty = np.flatnonzero(inertia == 0)
        if empty.size:
            raise refused(
                "assembly",
                f"assembly: node {empty[0]} has no inertia (no disk there, and no element with inertia ends there)",
            )
        try:
            return cls(
                inertia,
                stiffness,
                cylinder_nodes=cylinder_nodes,
                damping=damping if any(c != 0 for c in damping) else None,
                node_damping=node_damping if any(c != 0 for c in node_damping) else None,
            )
        except MechanismError as error:  # the model's numbers are the assembly's; cylinder_nodes is its own
            if error.parameter == "cylinder_nodes":
                raise
            raise refused("assembly", f"assembly: {error}") from None

    @classmethod
    def from_toml(cls, path: str | os.PathLike[str]) -> Shaft:
        """The shaft of a TOML file's ``[shaft]`` table (docs/machine-files.md).

        Parameters
        ----------
        path : str or os.PathLike
            A file holding a ``[shaft]`` table alone, or a whole machine file (one with
            ``cylinder`` or ``shaft_inertia``): that is read and checked as one machine, by
            :meth:`Machine.from_toml <multicrank.Machine.from_toml>`, and its shaft returned.

        Returns
        -------
        Shaft
            ``inertia`` [kg·m²], ``stiffness`` [N·m/rad], ``cylinder_nodes``, ``damping`` and
            ``node_damping`` [N·m·s/rad] as the table gives them.

        Raises
        ------
        MechanismError
            Naming the file and the key: a file that cannot be read or is not TOML, no
            ``[shaft]`` table, an unknown or missing key, a value of the wrong type or out of
            range; for a machine file, whatever ``Machine.from_toml`` refuses in it (a
            cylinder, a pressure table, a ``cylinder_nodes`` without one node per cylinder),
            with its message.
        """
        # The machine files' reader: one place for the [shaft] table's keys and types.
        file = read_shaft_file(path)
        if file is not None:
            return shaft_of_file(file)
        if _machine_loader is None:  # pragma: no cover - the package's import sets it
            raise refused("path", f"{os.fspath(path)}: a machine file needs multicrank.Machine loaded")
        shaft = _machine_loader(path).shaft
        if shaft is None:
            raise refused(
                "path", f"{os.fspath(path)}: shaft: missing required table [shaft] (the shaft as a torsional chain)"
            )
        return shaft

    def stiffness_matrix(self) -> np.ndarray:
        """The chain's stiffness matrix.

        Returns
        -------
        ndarray
            K [N·m/rad], tridiagonal, nodes × nodes: K_ii = k_{i−1} + k_i, K_{i,i+1} = −k_i.
        """
        k = np.asarray(self.stiffness)
        count = len(self.inertia)
        matrix = np.zeros((count, count))
        index = np.arange(count - 1)
        matrix[index, index] += k
        matrix[index + 1, index + 1] += k
        matrix[index, index + 1] = matrix[index + 1, index] = -k
        return matrix

    def modes(self, count: Any = None) -> ShaftModes:
        """The lowest elastic modes of the undamped free–free chain: natural frequencies [Hz]
        and mode shapes (nodes × modes).

        Parameters
        ----------
        count : int, optional
            How many, from the lowest (mode 1): 1 <= count <= nodes − 1. Default every
            elastic mode (nodes − 1).

        Returns
        -------
        ShaftModes
            ``natural_frequency`` (increasing) and ``shapes`` (each scaled to a largest
            magnitude of +1), ``count`` modes.

        Raises
        ------
        MechanismError
            For a ``count`` that is not an integer in range, naming it.

        Notes
        -----
        Each ω² = (2π f)² is found from the chain's numbers to a few units in its last digit
        — Holzer's recurrence (the pivots of K − σJ) bisected on its count of the modes below
        σ, from Gershgorin's bracket, in the Rust core — and each shape by the same
        recurrence from both ends, every node's amplitude to a relative precision. A general
        eigen solver is accurate only to a few ε of the largest ω²: a light node between stiff
        sections, or a long chain's lowest modes, would lose digits. The cost is of the order
        of nodes × ``count`` (a 4000-node chain's lowest modes take a fraction of a second),
        without an n × n matrix.

        Examples
        --------
        Two heavy discs joined through two light ones by a soft section between stiff ones: the
        first mode, the heavy discs swinging against each other, is 10¹³ times below the
        others in ω² and keeps every digit (0.0711761828096906… Hz to 40 digits).

        >>> import multicrank as mc
        >>> stiff = mc.Shaft([1e4, 1e-4, 1e-4, 1e4], [1e9, 1e3, 1e9], cylinder_nodes=[0])
        >>> first = stiff.modes(count=1)
        >>> round(float(first.natural_frequency[0]), 12)
        0.07117618281
        >>> first.shapes[:, 0].round(6).tolist()
        [1.0, 0.999998, -0.999998, -1.0]
        """
        # The chain's modes are the torsion room's mathematics; the machine part asks it when
        # asked, so that machine/ imports nothing above it at load time (tests/test_rooms.py).
        from ..torsion._chain import chain_modes

        elastic = len(self.inertia) - 1
        wanted = elastic if count is None else as_count(count, "count", minimum=1, maximum=elastic)
        omega_squared, shapes = chain_modes(np.asarray(self.stiffness), np.asarray(self.inertia), wanted)
        return ShaftModes(np.sqrt(omega_squared) / (2 * math.pi), shapes)


def shaft_of_file(file: MachineFile) -> Shaft:
    """The :class:`Shaft` of a machine file's ``[shaft]`` table, read and type-checked
    (``file.shaft``, :mod:`multicrank.machine.files`): its ranges checked by the Shaft, a bad
    one named with the file and the table (``Shaft.from_toml``, ``Machine.from_toml``)."""
    assert file.shaft is not None  # the callers ask only a file that has one
    with file.context("shaft"):
        return Shaft(**file.shaft)


def _node(value: Any, name: str, count: int | None) -> int:
    """A node index of an openTorsion model, 0 <= value < count (a count ≥ 1 where ``count``
    is None); refused as the ``assembly``'s, its message naming ``name``."""
    with part_of("assembly"):
        if count is None:
            return as_count(value, name, minimum=1)
        return as_count(value, name, minimum=0, maximum=count - 1)


def _number(value: Any, name: str) -> float:
    """A finite real number of an openTorsion element; refused as the ``assembly``'s, its
    message naming ``name``."""
    with part_of("assembly"):
        number = as_scalar(value, name)
    if not math.isfinite(number):
        raise refused("assembly", f"{name} = {value!r} is not a finite real number")
    return number


def shaft_of(machine: Any, shaft: Any) -> Shaft:
    """The shaft a torsional question of ``machine`` (a :class:`~multicrank.Machine`) uses:
    ``shaft`` where given (checked against the machine: one node per cylinder), else the
    machine's own; refused by name where there is neither."""
    if shaft is None:
        if machine.shaft is None:
            raise refused(
                "shaft",
                f"shaft is required: machine {machine.name!r} has none (give shaft=mc.Shaft(...) or "
                "Machine(shaft=...), or a [shaft] section in its machine file)",
            )
        return machine.shaft
    return machine.replace(shaft=as_instance(shaft, Shaft, "shaft")).shaft
