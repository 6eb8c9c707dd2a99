"""The shaking forces and moments of a machine by order (docs/theory.md, "Forces on the frame").

The frame of a machine takes the inertial reaction −Σ m·a of everything that moves in it:
pistons, rods, crank webs and counterweights (the flywheel and shaft turn about their own
centre and add nothing). For a rigid mechanism of mass M whose centre of mass is r_G(φ), the
first moment along a unit vector e, S_e(φ) = M e·r_G(φ) [kg·m], is the paper's potential U_e
with g = 1, so

    F_e = −M a_G·e = −(S_e″(φ) ω² + S_e′(φ) ε),

and at a constant speed ω the order-n amplitude is n² ω² times that of S_e. With e vertical S_e′ is the
paper's Q; with e horizontal it is the same kernel with every cylinder's inclination turned by
90°; each unit's S_e weighted by its lever z − z_ref gives the moments about the engine centre
z_ref = (z_min + z_max)/2, the midpoint of the outermost cylinders. The two
masses that replace a rod keep its mass and centre of gravity, so all this is exact — the Rust
core computes it from the exact series of its gravity kernels (:class:`ShakingForces` asks it).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from .._native import SHAKING_ORDER_COLUMNS
from .._validation import (
    as_count,
    as_flag,
    as_instance,
    as_real_array,
    contiguous,
    refused,
    rpm_from_omega,
    running_omega,
)
from ..machine.machine import Machine
from ..machine.native import motion_machine

__all__ = ["COMPONENTS", "ShakingForces", "shaking_forces"]

#: The components over φ (:meth:`ShakingForces.curves`), with their units.
COMPONENTS: dict[str, str] = {
    "force_vertical": "N",
    "force_horizontal": "N",
    "moment_pitch": "N·m",
    "moment_yaw": "N·m",
    "torque_reaction": "N·m",
}


#: Samples per revolution of a steady state whose forces are transformed (``steady=True``):
#: ω(φ) has kinks where a tabulated pressure has them, so its spectrum decays only
#: algebraically; at 1440 per revolution what folds onto the first dozen orders is below
#: 1e-9 of the forces.
STEADY_SAMPLES = 1440

#: The points of :meth:`ShakingForces.curves` at a constant speed when no angles are given:
#: every degree of one revolution, both ends included.
CURVE_POINTS = 361


def _order_unit(column: str) -> str:
    """The unit of a column of the orders' table: a phase's rad, a force's N, a moment's N·m."""
    if column.endswith("_phase"):
        return "rad"
    return "N" if column.startswith("force") else "N·m"


@dataclass(frozen=True, eq=False)
class ShakingForces:
    """The shaking forces and moments of a machine, by order.

    Attributes
    ----------
    machine : Machine
        The machine.
    rpm : float
        The speed n [1/min]: constant, or the steady state's mean (``steady``).
    omega : float
        ω = πn/30 [rad/s].
    max_order : int
        The highest order listed.
    steady : bool
        Whether the forces are those of the steady state's ω(φ) and ε(φ) (gravity's and the
        gas's speed fluctuation carried into the inertia forces) rather than of a constant
        speed.
    orders : pandas.DataFrame
        Indexed by the order ``order`` per revolution (1, 2, … ``max_order`` at a constant
        speed; steps of ½ for a four-stroke machine in steady running, whose speed repeats
        once per working cycle); for each of ``force_vertical`` [N] (positive upward),
        ``force_horizontal`` [N] (positive toward a cylinder at inclination γ = 0),
        ``moment_pitch`` [N·m] (Σ (z − z_ref)·F_v of every unit at its axial position z: the vertical
        forces' moment about the horizontal axis through the engine centre z_ref) and
        ``moment_yaw`` [N·m] (Σ (z − z_ref)·F_h) the amplitude √(a² + b²) of its harmonic, and
        its phase ``…_phase`` [rad] (the component is amplitude·cos(νφ − phase) at order ν); then ``force_forward`` and
        ``force_backward`` [N], the magnitudes of the parts of F_h + i·F_v that turn with the
        crank (e^{+iνφ}) and against it (e^{−iνφ}), and ``moment_forward`` and
        ``moment_backward`` [N·m] of M_yaw + i·M_pitch alike. A lone rotating unbalance m·e
        gives a forward first order m·e·ω² and no backward one; forward + backward is the
        largest magnitude the order's force reaches over a cycle. What cancels between the
        units is exactly 0. Computed when first read.

    Notes
    -----
    φ is the crank angle of the machine: a unit of phase α has its crank at ψ = φ + α from
    its outer dead centre, its crank pin at φ + α + γ from the horizontal. Counterweights can
    cancel only the forward first order (they turn with the crank); a backward or a higher
    order needs balance shafts turning at that order.
    """

    machine: Machine
    rpm: float
    omega: float
    max_order: int
    steady: bool
    _found: dict[str, np.ndarray] = field(repr=False)
    _orders: np.ndarray = field(repr=False)
    _state: Any = field(default=None, repr=False)
    _table: list[Any] = field(default_factory=list, repr=False)

    #: The columns of :attr:`orders` (named by the core) with their units.
    COLUMNS: ClassVar[dict[str, str]] = {name: _order_unit(name) for name in SHAKING_ORDER_COLUMNS}

    @property
    def reference_position(self) -> float:
        """The engine centre z_ref = (z_min + z_max)/2 [m] the moments are taken about: the
        midpoint of the outermost cylinders' axial positions. The moment of an order that
        also leaves a free force F depends on this point (about z₀ it is M + (z_ref − z₀)·F);
        that of an order with no free force (a couple) does not."""
        return motion_machine(self.machine).shaking_reference()

    @property
    def orders(self) -> Any:
        """The table of orders (see the class's attributes): a pandas DataFrame."""
        if not self._table:
            import pandas as pd

            index = pd.Index(self._orders, name="order")
            frame = pd.DataFrame({name: self._found[name] for name in self.COLUMNS}, index=index)
            frame.attrs.update(
                {
                    "rpm": self.rpm,
                    "omega": self.omega,
                    "steady": self.steady,
                    "reference_position": self.reference_position,
                    "units": dict(self.COLUMNS),
                }
            )
            self._table.append(frame)
        return self._table[0].copy()

    def curves(self, phi: Any = None) -> Any:
        """The shaking forces and moments over the crank angle.

        Parameters
        ----------
        phi : array_like, optional
            Crank angles φ [rad], 1-D, at a constant speed; default every degree of one
            revolution. In steady running (``steady``) the curves are on the steady state's
            own angles, uniform over its working cycle (give None).

        Returns
        -------
        pandas.DataFrame
            Indexed by ``phi``, with ``force_vertical``, ``force_horizontal`` [N],
            ``moment_pitch`` and ``moment_yaw`` [N·m] there, −(S″ω² + S′ε) of each component
            from the core's closed-form kernels (every order, not a truncated series), and
            ``torque_reaction`` [N·m]: the torque about the shaft axis that the frame receives
            from the moving parts and its mounts take — the moments of the pistons' side
            forces on the cylinder walls, with the gas forces, the rods' inertia and the
            weights (positive in the crank's sense of rotation; over a cycle without gravity
            it averages minus the mean gas torque: the block rolls against the crank).
        """
        import pandas as pd

        if self.steady:
            if phi is not None:
                raise refused(
                    "phi", "phi: in steady running the curves are on the steady state's own angles; give phi = None"
                )
            angles, speeds, accelerations = self._state.phi, self._state.omega, self._state.acceleration
        else:
            given = np.linspace(0.0, 2 * np.pi, CURVE_POINTS) if phi is None else as_real_array(phi, "phi")
            if given.ndim != 1:
                raise refused("phi", f"phi must be 1-D, got shape {given.shape}")
            angles = given.astype(float)
            speeds, accelerations = np.full(angles.shape, self.omega), np.zeros(angles.shape)
        angles = contiguous(np.asarray(angles, dtype=float))
        values = motion_machine(self.machine).shaking_curves(angles, contiguous(speeds), contiguous(accelerations))
        columns = dict(zip(COMPONENTS, values.reshape(len(COMPONENTS), -1), strict=True))
        frame = pd.DataFrame(columns, index=pd.Index(angles, name="phi"))
        frame.attrs.update({"rpm": self.rpm, "omega": self.omega, "steady": self.steady, "units": dict(COMPONENTS)})
        return frame


def shaking_forces(machine: Machine, rpm: Any = None, *, max_order: Any = 12, steady: Any = False) -> ShakingForces:
    """The forces and moments the machine's moving parts shake its frame with, by order.

    Parameters
    ----------
    machine : Machine
        The machine: its cylinders' masses, geometry, phases, inclinations and axial
        positions (``Cylinder.axial_position`` [m]; the moments are about the engine centre
        z_ref = (z_min + z_max)/2, so that no number moves with the origin of z).
    rpm : float, optional
        The speed n [1/min] (constant, or the steady state's mean); default the machine's
        own ``rpm``.
    max_order : int, default 12
        The highest order (per revolution) listed, 1 … 2048 (steady: 1 … 360).
    steady : bool, default False
        False: at the constant speed ω = πn/30, where the order-n amplitude is n²ω² times that of S_n
        exactly. True: in the machine's steady running at that mean speed ("balance" load,
        :func:`~multicrank.steady_state`), with its ω(φ) and ε(φ), so that the speed
        fluctuation (gravity's included) is carried into the inertia forces; the orders then
        come from the discrete Fourier transform of the exact forces at 1440 angles per
        revolution, and a four-stroke machine has half orders.

    Returns
    -------
    ShakingForces
        ``.orders`` (a table by order) and ``.curves(phi)``.

    Raises
    ------
    MechanismError
        For a bad argument, naming it; for a machine without ``rpm`` when none is given.
    StallError
        ``steady=True`` where the machine stalls at that speed.

    Examples
    --------
    An in-line four leaves a vertical second order (and its fourth) and no first; the first
    order of a single cylinder turns both ways, forward more (its crank's own unbalance):

    >>> import multicrank as mc
    >>> four = mc.presets.MACHINES["inline-4"]
    >>> orders = mc.shaking_forces(four, 3000, max_order=4).orders
    >>> orders["force_vertical"].round(1).tolist()
    [0.0, 3166.9, 0.0, 76.5]
    >>> one = mc.presets.MACHINES["slow-compressor"]
    >>> mc.shaking_forces(one, max_order=2).orders[["force_forward", "force_backward"]].round(1)
           force_forward  force_backward
    order
    1.0           2127.9          1243.6
    2.0            315.9           315.9
    """
    machine = as_instance(machine, Machine, "machine")
    omega = running_omega(machine, rpm)
    steady = as_flag(steady, "steady")
    highest = as_count(max_order, "max_order", minimum=1, maximum=STEADY_SAMPLES // 4 if steady else 2048)
    native = motion_machine(machine)
    if not steady:
        found = native.shaking_orders(omega, highest)
        orders = np.arange(1, highest + 1, dtype=float)
        return ShakingForces(machine, rpm_from_omega(omega), omega, highest, False, dict(found), orders)
    from ..motion.steady import balanced_state

    turns = machine.strokes // 2  # revolutions per working cycle
    state = balanced_state(machine, omega, points=STEADY_SAMPLES * turns + 1)
    speeds, accelerations = (contiguous(np.asarray(a[:-1], dtype=float)) for a in (state.omega, state.acceleration))
    found = native.shaking_orders_in_motion(speeds, accelerations, highest * turns)
    orders = np.arange(1, highest * turns + 1, dtype=float) / turns
    return ShakingForces(machine, rpm_from_omega(omega), omega, highest, True, dict(found), orders, state)
