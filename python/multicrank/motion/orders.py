"""Orders of the shaft torques: their Fourier coefficients per revolution (docs/theory.md, "Orders").

:func:`torque_orders` gives, for the order ν (the harmonic number per revolution: 0, 1, 2,
… for a two-stroke machine, and 0, ½, 1, 1½, … for a four-stroke one, whose working cycle
spans two revolutions), the coefficients of

    M(φ) = Σ_ν [a_ν cos νφ + b_ν sin νφ] = Σ_ν A_ν cos(νφ − θ_ν)

for the gas torque, the inertia torque −½ J'(φ) ω² at the mean speed, the gravity torque
−U'(φ) and their sum, in N·m, as a table for torsional-vibration tools.

- **Inertia and gravity**: J(φ) and U(φ) are analytic and 2π-periodic, so the
  Gauss–Legendre panels of one revolution give the coefficients of the machine's own
  −½ J′(φ) ω² and −U′(φ) (:meth:`~multicrank.Machine.inertia_torque`,
  :meth:`~multicrank.Machine.gravity_torque`) to rounding (spectral convergence); their half
  orders are exactly 0, and so is gravity's mean (U is periodic).
- **Gas**: the same panels over the working cycle, cut at every gassed unit's dead centres and
  at the breakpoints of its pressure tables, on each of which the integrand is smooth: for an
  :class:`~multicrank.IndicatorDiagram` the coefficients of the interpolated diagram's
  torque are exact to rounding as well. The torque itself has kinks there, so its series
  converges only algebraically ("spectral for tabulated gas": the coefficients are right,
  a truncated sum is not the torque). A pressure callable crosses to the core as its
  interpolant on a fine grid (degree 7 on panels at most π/256 wide, cut at the dead
  centres, as ``machine.native.sampled`` makes it), whose coefficients are found the
  same way: for a smooth pressure they are its own to rounding; a kink inside one of those
  panels is smoothed there.
- **Load law**: under a machine's :attr:`~multicrank.Machine.load_law` the gauge pressures at
  the speed n are those given times (n/n_r)² (the propeller law); the gas torque is linear in
  them, so its coefficients are those of the diagrams as given times that factor, exactly.

The Rust core computes the coefficients (``_native.machine_torque_orders`` on the machine's
native ``MotionMachine``); here they are checked, rounded
(:data:`RESOLUTION`) and laid out.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._native import machine_torque_orders
from .._optional import require
from .._validation import (
    SPEED_LIMITS,
    as_count,
    as_flag,
    as_instance,
    as_omega,
    as_option,
    omega_from_rpm,
    refused,
    rpm_from_omega,
    running_omega,
)
from ..machine.machine import Machine, load_factor, rated_omega
from ..machine.native import motion_machine
from ..machine.shaft import shaft_of

__all__ = ["ORDER_PARTS", "CylinderOrders", "cylinder_orders", "to_opentorsion", "torque_orders"]

#: The torques of :func:`torque_orders`, in column order.
ORDER_PARTS = ("gas", "inertia", "gravity", "total")

#: A coefficient pair whose amplitude is below this fraction of its part's scale is exactly 0.
#: The scale is the size of what the part's sum cancels: for inertia and gravity Σ_j max|M_j|
#: over the units alone, for gas the part's largest amplitude, for the total the largest of
#: the three. What cancels (an in-line four's odd orders, a single cylinder's odd gravity
#: orders above the first, inertia's mean) comes out of the quadrature at ≈ 1e-16 … 2e-15 of
#: that scale (the presets up to order 100); 1e-13 is fifty times above that rounding.
RESOLUTION = 1e-13
#: The speed [1/min] at which each cylinder's inertia torque is found alone; it scales as ω².
_REFERENCE_RPM = 1000.0


def torque_orders(machine: Machine, rpm: float, *, max_order: int = 12, gravity: bool = True) -> Any:
    """The orders of the gas, inertia and gravity torques on the shaft [N·m].

    Parameters
    ----------
    machine : Machine
        The machine.
    rpm : float
        The mean speed n [1/min], > 0: the inertia torque is −½ J'(φ) ω² at ω = π n/30; the
        gravity torque does not depend on it, and the gas torque only under the machine's
        ``load_law`` (the propeller law: its gauge pressures, and so its gas torque, times
        (n/n_r)², n_r the machine's ``rpm``).
    max_order : int
        The highest order ν, ≥ 1. Every order from 0 in steps of 1 (two-stroke) or ½
        (four-stroke) up to it is listed.
    gravity : bool
        False gives zero gravity columns (as if g were 0).

    Returns
    -------
    pandas.DataFrame
        Indexed by ``order`` (float: ν per revolution), with the columns ``{part}_cos``,
        ``{part}_sin`` (a_ν, b_ν [N·m]), ``{part}_amplitude`` (A_ν = √(a_ν² + b_ν²) [N·m])
        and ``{part}_phase`` (θ_ν = atan2(b_ν, a_ν) [rad]) for each part in
        :data:`ORDER_PARTS`: "gas", "inertia", "gravity" and their sum "total". Order 0 holds
        the mean (a_0, b_0 = 0). φ is the crank angle of the machine (from the outer dead
        centre of a unit with phase 0), so M(φ) = Σ_ν a_ν cos νφ + b_ν sin νφ. ``attrs``
        holds ``rpm``, ``omega`` [rad/s], ``strokes`` and the ``units``.

    Notes
    -----
    Inertia and gravity are 2π-periodic: their half orders are exactly 0, and only a
    four-stroke gas cycle has half orders. Accuracy: gravity and inertia to rounding; gas
    torques to rounding for smooth or tabulated pressures (docs/theory.md, "Orders"). A
    coefficient pair whose amplitude is below 1e-13 times the size of what its part cancels
    (for inertia and gravity Σ_j max|M_j| of the units alone; for gas, its largest amplitude)
    is exactly 0: what cancels (an in-line four's odd orders, inertia's mean) prints as 0,
    not as 1e-15 N·m of rounding. "total" is the sum of the parts before that, zeroed by the
    same rule at the largest of their scales.

    Examples
    --------
    >>> import multicrank as mc
    >>> compressor = mc.presets.MACHINES["slow-compressor"]
    >>> orders = mc.torque_orders(compressor, 120, max_order=3)
    >>> orders[["gas_amplitude", "gravity_amplitude", "total_amplitude"]].round(1)
           gas_amplitude  gravity_amplitude  total_amplitude
    order
    0.0            916.0                0.0            916.0
    1.0            182.7              209.4            260.4
    2.0           1403.1               19.6           1265.4
    3.0            268.7                0.0            205.7
    """
    import pandas as pd

    machine = as_instance(machine, Machine, "machine")
    omega = as_omega(rpm, "rpm")
    highest = as_count(max_order, "max_order", minimum=1)
    gravity = as_flag(gravity, "gravity")
    found = machine_torque_orders(motion_machine(machine), omega, highest, gravity)
    orders = np.asarray(found["order"])
    parts = {name: (np.asarray(found[f"{name}_cos"]), np.asarray(found[f"{name}_sin"])) for name in ORDER_PARTS[:3]}
    # The load law's gas: the torque is linear in the pressures, so its orders scale as they do.
    factor = load_factor(omega, rated_omega(machine))
    parts["gas"] = (parts["gas"][0] * factor, parts["gas"][1] * factor)
    parts["total"] = (
        parts["gas"][0] + parts["inertia"][0] + parts["gravity"][0],
        parts["gas"][1] + parts["inertia"][1] + parts["gravity"][1],
    )

    # What cancelled to below the quadrature's rounding is 0, not 1e-15 N·m of noise.
    scale = {name: float(np.max(np.hypot(*parts[name]))) for name in ORDER_PARTS}
    scale["inertia"] = max(scale["inertia"], float(found["inertia_scale"]))
    scale["gravity"] = max(scale["gravity"], float(found["gravity_scale"]))
    scale["total"] = max(scale.values())
    columns: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    for name in ORDER_PARTS:
        cos, sin = parts[name]
        resolved = np.hypot(cos, sin) >= RESOLUTION * scale[name]
        cos, sin = np.where(resolved, cos, 0.0), np.where(resolved, sin, 0.0)
        columns[f"{name}_cos"], columns[f"{name}_sin"] = cos, sin
        columns[f"{name}_amplitude"] = np.hypot(cos, sin)
        columns[f"{name}_phase"] = np.arctan2(sin, cos)
        units.update({f"{name}_cos": "N·m", f"{name}_sin": "N·m", f"{name}_amplitude": "N·m", f"{name}_phase": "rad"})
    frame = pd.DataFrame(columns, index=pd.Index(orders, name="order"))
    frame.attrs.update({"rpm": rpm_from_omega(omega), "omega": omega, "strokes": machine.strokes, "units": units})
    return frame


@dataclass(frozen=True)
class CylinderOrders:
    """The order harmonics of each cylinder's own tangential torque, at its phase 0.

    ``orders`` ν > 0 [1/rev] up to the highest asked (halves for four strokes); ``gas`` and
    ``gravity`` (cylinders × orders, complex [N·m]) those torques' harmonics c_ν (the torque
    Σ_ν Re(c_ν e^{iνθ}) of the cylinder's own angle θ), ``gas`` of the diagrams as given;
    ``inertial`` the inertia torque's per (rad/s)², which scales as ω². ``rated_omega``: ω_r
    [rad/s] of the machine's load law (:attr:`~multicrank.Machine.load_law`), under which
    :meth:`at` scales the gas by (ω/ω_r)² at each speed; None without one.
    """

    orders: np.ndarray
    gas: np.ndarray
    gravity: np.ndarray
    inertial: np.ndarray
    rated_omega: float | None = None

    def only(self, keep: np.ndarray) -> CylinderOrders:
        """The same harmonics of the orders ``keep`` selects (an index or a mask over
        :attr:`orders`), the load law kept."""
        return dataclasses.replace(
            self,
            orders=self.orders[keep],
            gas=self.gas[:, keep],
            gravity=self.gravity[:, keep],
            inertial=self.inertial[:, keep],
        )

    def at(
        self, phases: np.ndarray, omega: np.ndarray, parts: tuple[str, ...] = ("gas", "inertia", "gravity")
    ) -> np.ndarray:
        """T_ν,j of every cylinder at its phase α_j (``phases``, (…, cylinders) [rad]) and
        every order at its speed ``omega`` [rad/s] ((…, orders), broadcast against the
        phases' leading axes): (…, cylinders, orders), of the torques named in ``parts``; the
        gas scaled by the load law at each order's speed."""
        coefficient = np.zeros_like(self.gas)
        if "gas" in parts:
            # The load law's factor at each order's speed (1 without a law).
            scale = np.broadcast_to(load_factor(np.asarray(omega, dtype=float), self.rated_omega), np.shape(omega))
            coefficient = coefficient + self.gas * scale[..., None, :]
        if "gravity" in parts:
            coefficient = coefficient + self.gravity
        if "inertia" in parts:
            coefficient = coefficient + self.inertial * np.square(omega)[..., None, :]
        return coefficient * np.exp(1j * phases[..., :, None] * self.orders)


def cylinder_orders(machine: Machine, highest: int, *, mean: bool = False) -> CylinderOrders:
    """The :class:`CylinderOrders` of ``machine`` up to order ``highest`` (and order 0, the
    mean, where ``mean``), each cylinder alone at phase 0 (cylinders alike but for their phase
    and place share one computation), from :func:`torque_orders`, the gas of the diagrams as
    given and the machine's load law beside it; kept on the machine for the next call
    (``Machine._torsion_orders``, never pickled)."""
    cache = machine.__dict__.setdefault("_torsion_orders", {})
    if (highest, mean) in cache:
        return cache[highest, mean]
    omega_squared = omega_from_rpm(_REFERENCE_RPM) ** 2
    found: dict[Any, tuple[np.ndarray, ...]] = {}
    rows = []
    for cylinder in machine.cylinders:
        template = cylinder.replace(phase=0.0, axial_position=0.0)
        if template not in found:
            alone = machine.replace(cylinders=[template], main_bearings=None, shaft=None, load_law=None)
            table = torque_orders(alone, _REFERENCE_RPM, max_order=highest)
            table = table if mean else table[table.index > 0]
            harmonic = {
                part: table[f"{part}_cos"].to_numpy() - 1j * table[f"{part}_sin"].to_numpy()
                for part in ("gas", "inertia", "gravity")
            }
            found[template] = (
                table.index.to_numpy(dtype=float),
                harmonic["gas"],
                harmonic["gravity"],
                harmonic["inertia"] / omega_squared,
            )
        rows.append(found[template])
    gas, gravity, inertial = (np.array([row[i] for row in rows]) for i in (1, 2, 3))
    result = CylinderOrders(rows[0][0], gas, gravity, inertial, rated_omega=rated_omega(machine))
    cache[highest, mean] = result
    return result


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
        a :class:`~multicrank.torsion.handoff.TorsionalModel` (a named tuple) of ``assembly``,
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
    (:func:`cylinder_orders`), handed to :func:`~multicrank.torsion.handoff.torsional_model`
    with the shaft."""
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
    # The torsion room builds openTorsion's objects; it imports nothing of this module (nor
    # torsion.merit, which does), so that the modules import one another without a circle.
    from ..torsion.handoff import torsional_model

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
