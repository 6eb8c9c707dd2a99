"""The hand-off to openTorsion (the ``torsion`` extra): :func:`to_opentorsion`, of a table of
torque orders (an excitation at one node) or of a machine (its shaft as an openTorsion model,
:func:`torsional_model`, driven by every cylinder's excitation at its own node).

The shaft (:class:`~multicrank.Shaft`) becomes an ``opentorsion.Assembly`` of one disk per node
(I = J_i, its damping to ground c = the node's) and one massless shaft element per section (k_i,
c_i); each cylinder's torque acts at
its own node, node i taking the sum over the cylinders on it. A component of angular frequency
ν·ω_m and complex amplitude T stands, in openTorsion's convention, for Re(T e^{iνω_m t}).

The torque orders are the motion room's (:func:`~multicrank.torque_orders`), each cylinder's
excitation this room's ``excitation``; openTorsion's own model read back as a shaft is the
shaft's constructor, :meth:`Shaft.from_opentorsion <multicrank.Shaft.from_opentorsion>`.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from .._optional import require
from .._validation import SPEED_LIMITS, as_count, as_flag, as_option, refused, running_omega
from ..machine.machine import Machine
from ..machine.shaft import Shaft, shaft_of
from ..motion.orders import ORDER_PARTS
from .excitation import cylinder_orders

__all__ = ["TorsionalModel", "assembly_of", "to_opentorsion", "torsional_model"]


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


def to_opentorsion(
    orders: Any,
    *,
    dofs: Any = None,
    node: Any = None,
    part: str = "total",
    mean: Any = False,
    shaft: Any = None,
    rpm: Any = None,
    max_order: Any = None,
) -> Any:
    """The torque orders as an openTorsion excitation, or a machine as an openTorsion model (the
    ``torsion`` extra).

    Two forms. **A table** of :func:`torque_orders` (``dofs``, ``node``): the excitation of a
    torsional model at one node, where the whole machine acts. **A machine**
    (:class:`~multicrank.Machine`; ``shaft``, ``rpm``, ``max_order``): the model of its shaft
    (:class:`~multicrank.Shaft`) and the excitation of every cylinder at its own node, in one
    call. Each order ν becomes a component of angular frequency ν·ω_m [rad/s] (half orders for
    a four-stroke machine) and a complex amplitude, in openTorsion's convention that a complex
    amplitude u stands for Re(u·e^(iωt)) = abs(u)·cos(ωt + arg u): for the table, A_ν·e^(−iθ_ν),
    so that with φ = ω_m t, Σ_ν A_ν cos(νφ − θ_ν) is the torque of the orders; for a machine,
    at node i the sum Σ_j T_ν,j over the cylinders j on it, T_ν,j = a_ν − i b_ν the harmonic of
    cylinder j's own torque at its phase (each cylinder's torque is Σ_ν Re(T_ν,j e^(iνφ))).

    Parameters
    ----------
    orders : pandas.DataFrame or Machine
        A table of :func:`torque_orders` (its ``attrs`` give ω_m), or a machine.
    dofs : int
        The table form: the number of degrees of freedom of the torsional model, ≥ 1.
    node : int
        The table form: the model's node where the machine acts, 0 ≤ node < dofs.
    part : {"total", "gas", "inertia", "gravity"}, default "total"
        Which torque ("total": gas, inertia and gravity).
    mean : bool, default False
        Whether the mean torque (order 0, frequency 0) is a component too; vibratory
        analyses leave it out.
    shaft : Shaft, optional
        The machine form: the shaft; default the machine's own (``Machine.shaft``).
    rpm : float, optional
        The machine form: the mean speed n [1/min], > 0 (ω_m = π n/30, the inertia torque's
        speed); default the machine's own (``Machine.rpm``).
    max_order : int, optional
        The machine form: the highest order ν, ≥ 1; default 12. Every order from 1 (½ for a
        four-stroke machine) in steps of 1 (½) up to it.

    Returns
    -------
    opentorsion.PeriodicExcitation or TorsionalModel
        For a table: the excitation, ``omegas`` the components' angular frequencies [rad/s];
        ``U[node]`` their complex amplitudes [N·m] (zero at every other node). For a machine:
        a :class:`~multicrank.TorsionalModel` (a named tuple) of ``assembly``,
        an ``opentorsion.Assembly`` (``Disk(i, I=J_i)`` [kg·m²] at each node,
        ``Shaft(i, i + 1, k=k_i, c=c_i)`` [N·m/rad, N·m·s/rad] for each section, massless), and
        ``excitation``, its ``U[i]`` the torques [N·m] of the cylinders at node i.

    Raises
    ------
    MechanismError
        For a table not made by :func:`torque_orders` or changed since (a missing column, a
        non-finite or negative order or amplitude, a non-finite phase, ``attrs["omega"]`` not a
        speed the package takes); a bad ``dofs``, ``node``, ``part``, ``shaft``, ``rpm`` or
        ``max_order``; a machine without a shaft or a speed where none is given; ``dofs`` or
        ``node`` with a machine, ``shaft``, ``rpm`` or ``max_order`` with a table. Each names
        the parameter.
    OptionalDependencyError
        Without openTorsion.

    Notes
    -----
    The table form puts the whole machine at one node, as if its shaft were rigid between the
    cylinders; the machine form puts each cylinder at its own, so that a mode is driven by the
    cylinders as its shape weights them (:func:`~multicrank.torsional_merit` ranks the orders
    so). Summed over the nodes, the machine form's components are the table's of the machine.

    Examples
    --------
    >>> import multicrank as mc
    >>> engine = mc.presets.MACHINES["inline-4"]
    >>> orders = mc.torque_orders(engine, 3000, max_order=4)
    >>> excitation = mc.to_opentorsion(orders, dofs=3, node=0)
    >>> [round(float(w / orders.attrs["omega"]), 6) for w in excitation.omegas]
    [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0]

    The engine with a shaft of four throws and a flywheel, each cylinder at its throw:

    >>> shaft = mc.Shaft([0.02, 0.02, 0.02, 0.02, 0.3], [3e5, 3e5, 3e5, 4e5],
    ...                  cylinder_nodes=[0, 1, 2, 3], damping=[2.0] * 4)
    >>> model = mc.to_opentorsion(engine, shaft=shaft, rpm=3000, max_order=4)
    >>> model.assembly.dofs, model.excitation.U.shape
    (5, (5, 8))
    """
    import pandas as pd

    if isinstance(orders, Machine):
        for name, value in (("dofs", dofs), ("node", node)):
            if value is not None:
                raise refused(
                    name,
                    f"{name} does not apply to a machine: its shaft gives the nodes, each cylinder at its own "
                    "(shaft.cylinder_nodes)",
                )
        return _machine_model(orders, shaft, rpm, 12 if max_order is None else max_order, part, mean)
    if not isinstance(orders, pd.DataFrame) or "omega" not in orders.attrs or orders.index.name != "order":
        raise refused(
            "orders",
            "orders must be a table of mc.torque_orders (indexed by order, with its attrs) or a multicrank.Machine",
        )
    for name, value in (("shaft", shaft), ("rpm", rpm), ("max_order", max_order)):
        if value is not None:
            raise refused(
                name,
                f"{name} applies to a machine only: a table of torque_orders holds its own speed and orders "
                "and acts at one node (give dofs and node)",
            )
    chosen = as_option(part, "part", ORDER_PARTS)
    count = as_count(dofs, "dofs", minimum=1)
    at = as_count(node, "node", minimum=0)
    if at >= count:
        raise refused("node", f"node = {at} is out of range; allowed: 0 <= node < dofs = {count}")
    with_mean = as_flag(mean, "mean")
    omega, index, amplitude, phase = _checked_orders(orders, chosen)
    keep = index > 0 if not with_mean else np.ones(len(orders), dtype=bool)
    opentorsion = require("opentorsion", "torsion")
    frequencies = index[keep] * omega
    excitation = opentorsion.PeriodicExcitation(count, frequencies)
    excitation.add_sines(at, frequencies, amplitude[keep], -phase[keep])
    return excitation


def _machine_model(machine: Machine, shaft: Any, rpm: Any, max_order: Any, part: Any, mean: Any) -> Any:
    """:func:`to_opentorsion`'s machine form: each cylinder's own orders at its phase
    (``excitation.cylinder_orders``), handed to :func:`torsional_model` with the shaft."""
    chosen = shaft_of(machine, shaft)
    omega = running_omega(machine, rpm)
    highest = as_count(max_order, "max_order", minimum=1)
    column = as_option(part, "part", ORDER_PARTS)
    with_mean = as_flag(mean, "mean")
    require("opentorsion", "torsion")  # before the work
    harmonics = cylinder_orders(machine, highest, mean=with_mean)
    phases = np.array([c.phase for c in machine.cylinders])
    parts = ORDER_PARTS[:3] if column == "total" else (column,)
    torques = harmonics.at(phases, np.full(harmonics.orders.shape, omega), parts)
    return torsional_model(chosen, harmonics.orders * omega, torques)


def _checked_orders(orders: Any, part: str) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """(ω_m [rad/s], the orders ν, A_ν [N·m], θ_ν [rad]) of ``part`` in a table of
    :func:`torque_orders`, checked as that function makes them — so that a table changed
    since (NaN amplitudes, a negative speed) is refused rather than handed on."""
    where = "orders (a table of mc.torque_orders)"
    columns = (f"{part}_amplitude", f"{part}_phase")
    missing = [c for c in columns if c not in orders.columns]
    if missing:
        raise refused("orders", f"{where} lacks the column(s) {', '.join(missing)}")
    try:
        omega = float(orders.attrs["omega"])
    except (TypeError, ValueError):
        raise refused("orders", f"{where}: attrs['omega'] = {orders.attrs['omega']!r} is not a speed [rad/s]") from None
    low, high = SPEED_LIMITS
    if not (math.isfinite(omega) and low <= omega <= high):
        raise refused(
            "orders",
            f"{where}: attrs['omega'] = {omega!r} is out of range; allowed: {low:g} <= omega <= {high:g} [rad/s]",
        )
    values = {"order": orders.index, **{c: orders[c] for c in columns}}
    arrays: dict[str, np.ndarray] = {}
    for name, column in values.items():
        array = np.asarray(column)
        if array.dtype.kind not in "iuf":
            raise refused("orders", f"{where}: {name} must hold real numbers, got dtype {array.dtype}")
        arrays[name] = array.astype(np.float64)
    rules: dict[str, tuple[bool, str]] = {  # (whether it is at least 0, what is allowed)
        "order": (True, "finite orders >= 0"),
        columns[0]: (True, "finite amplitudes >= 0 [N·m]"),
        columns[1]: (False, "finite phases [rad]"),
    }
    for name, (nonnegative, allowed) in rules.items():
        array = arrays[name]
        bad = np.flatnonzero(~(np.isfinite(array) & ((array >= 0) if nonnegative else True)))
        if bad.size:
            at = "" if name == "order" else f" at order {orders.index[bad[0]]}"
            raise refused(
                "orders", f"{where}: {name} = {float(arrays[name][bad[0]])!r}{at} is out of range; allowed: {allowed}"
            )
    return omega, arrays["order"], arrays[columns[0]], arrays[columns[1]]
