"""The physical machine of any layout, in SI units: cylinders on one shaft.

A :class:`Machine` is its cylinders (:class:`~multicrank.Cylinder`), the shaft's moment of
inertia and the working cycle. It gives the quantities of the machine's equation of motion
(docs/theory.md): the reduced moment of inertia J(φ) and J'(φ), the potential energy U(φ)
and the gravity torque −dU/dφ, the gas torque and the inertia torque, all computed in the
Rust core; and the dimensionless :class:`~multicrank.Engine` of gravity at any speed.

This module builds and checks a machine (its fields, :meth:`Machine.replace`); the class's
other methods live by job beside it and are inherited or bound here: the description in
`description`, the quantities of the equation of motion in `dynamics`, the gas forces in
`gas`, a layout's machine in `layout`, the machine file in `loading` (read by `files`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .._native import NativeMachine
from .._validation import (
    as_instance,
    as_omega,
    as_option,
    as_rpm,
    as_scalar,
    as_strokes,
    check_fields,
    check_magnitude,
    omega_from_rpm,
    refused,
)
from .._validation import as_rpm_range as _speed_range
from ..gravity.mechanism import STANDARD_GRAVITY
from .cylinder import Cylinder, unit_columns
from .description import MachineDescription
from .dynamics import MachineDynamics
from .gas import MachineGas
from .layout import from_layout as _from_layout
from .loading import from_toml as _from_toml
from .shaft import Shaft, use_machine_loader
from .throws import ShaftLayout, as_bearings, layout_of

__all__ = ["LOAD_LAWS", "Machine", "load_factor", "rated_omega"]

#: The load laws a machine may state (``Machine.load_law``): how its indicator diagrams follow
#: its speed. "propeller": a fixed-pitch propeller's, the gauge pressures as (n/n_r)².
LOAD_LAWS = ("propeller",)

#: What a machine keeps of its own computations (never pickled, copied or compared).
_DERIVED = ("_layout", "_native", "_native_lock", "_torsion_orders", "_units")

#: A machine's fields, as :meth:`Machine.replace` takes them.
_MACHINE_FIELDS = (
    "cylinders",
    "shaft_inertia",
    "strokes",
    "g",
    "name",
    "rpm",
    "rpm_range",
    "note",
    "delta_target",
    "main_bearings",
    "shaft",
    "load_law",
)


class Machine(MachineDescription, MachineDynamics, MachineGas):
    """A machine: cylinders of any layout on one shaft, in SI units.

    Parameters
    ----------
    cylinders : sequence of :class:`Cylinder`
        At least one.
    shaft_inertia : float
        I_w [kg·m²], > 0: everything that turns rigidly with the shaft — shaft, webs,
        counterweights, flywheel, gears, driven inertia — but not the rods and pistons,
        whose inertia the machine adds exactly.
    strokes : 2 or 4
        The working cycle spans Φ = 2π (two-stroke) or 4π (four-stroke) of crank angle.
    g : float
        Gravity [m/s²], default standard gravity; 0 switches gravity off.
    name : str
        A label.
    rpm : float, optional
        The running speed n [1/min], > 0, where the machine has one: the default speed of
        :meth:`engine` (and of the report), and the rated speed n_r of ``load_law``.
    rpm_range : (float, float), optional
        The speeds (low, high) [1/min] the machine runs at, 0 < low < high; ``rpm``, where
        given too, must lie inside.
    note : str
        A description: what the machine is and where its numbers come from.
    delta_target : float, optional
        The coefficient of speed fluctuation δ = (ω_max − ω_min)/ω_mean the machine is meant
        to run at [dimensionless], > 0, where it has one: its class's limit (compressors
        1/20, vehicle engines 1/100, generator sets 1/300). The report sizes the flywheel
        for it. Descriptive; nothing else depends on it.
    main_bearings : sequence of float, optional
        The main bearings' axial positions z [m] along the shaft (the axis of the cylinders'
        ``axial_position``), at least two, strictly increasing: every throw must lie strictly
        between two bearings — a throw before the first or after the last (overhung) or
        exactly at a bearing is refused. Default: :attr:`bearings` interleaves the throws.
    shaft : Shaft, optional
        The shaft as a torsional chain (:class:`~multicrank.Shaft`: node inertias and section
        stiffnesses, and each cylinder's node), for the torsional questions
        (:func:`~multicrank.torsional_merit`, :func:`~multicrank.firing_orders`,
        :func:`~multicrank.to_opentorsion`); its ``cylinder_nodes`` must name one node per
        cylinder. The rigid machine's motion does not depend on it.
    load_law : {None, "propeller"}, default None
        How the load, and with it the indicator diagrams, follows the speed. None: the
        diagrams as given at every speed. "propeller" (a fixed-pitch propeller, whose torque
        grows as n²): the diagrams are those at the rated speed n_r = ``rpm`` (required), and
        at a speed n every gauge pressure is scaled by :meth:`load_factor` (n/n_r)², that is
        p_abs(n) = p_ref + (p_abs − p_ref)·(n/n_r)² with p_ref the crankcase (ambient)
        pressure the diagrams are gauge to (above n_r the law extrapolates, > 1). The answers
        at a speed use it: :func:`~multicrank.torque_orders`,
        :func:`~multicrank.to_opentorsion`, :func:`~multicrank.torsional_merit` (each
        resonance at its own speed), the largest order and the torsional merit of
        :func:`~multicrank.firing_orders`, and, with ``load="balance"``,
        :func:`~multicrank.steady_state`, :func:`~multicrank.flywheel_inertia` and the steady
        outputs of :func:`~multicrank.motion_sweep` at their mean speed, and the main-bearing
        loads (:func:`~multicrank.bearing_loads`, a motion sweep's ``max_bearing_load``).
        The rest take the diagrams as given: :meth:`gas_torque` and :meth:`piston_forces`
        (no speed), a load that fixes the speed itself (a :class:`~multicrank.PowerLawLoad`,
        a callable) and :func:`~multicrank.simulate`.

    Attributes
    ----------
    cylinders : tuple of Cylinder
        The cylinders, in the order given.
    shaft_inertia, strokes, g, name, rpm, rpm_range, note, delta_target, main_bearings, shaft, load_law
        The parameters as given (``rpm``, ``rpm_range``, ``delta_target``, ``main_bearings``,
        ``shaft`` and ``load_law`` None where not given; ``main_bearings`` a tuple of floats). A
        machine is immutable (setting a field raises ``FrozenInstanceError``, an
        ``AttributeError``): :meth:`replace` makes a changed copy.

    Raises
    ------
    MechanismError
        For any bad field, naming it.

    See Also
    --------
    Machine.from_layout : A machine of a layout with one cylinder template.
    Machine.from_toml : A machine from a TOML machine file.
    multicrank.presets.MACHINES : The built-in machines.

    Examples
    --------
    A single-cylinder machine without gas: its reduced inertia, gravity torque and the
    dimensionless gravity :class:`Engine` at 120 rpm.

    >>> import numpy as np
    >>> import multicrank as mc
    >>> cylinder = mc.Cylinder(crank_radius=0.15, rod_length=0.6, piston_mass=85,
    ...                        rod_mass=60, rod_cg=0.4)
    >>> machine = mc.Machine([cylinder], shaft_inertia=45, rpm=120)
    >>> phi = np.radians([0, 45, 90])
    >>> J, dJ = machine.reduced_inertia(phi)
    >>> J.round(3), dJ.round(3)
    (array([45.9  , 47.544, 48.262]), array([ 0.   ,  2.803, -1.22 ]))
    >>> machine.gravity_torque(phi[1:]).round(2)  # N·m: gravity drives the piston down
    array([170.44, 213.29])
    >>> print(f"δ_g = {machine.engine().speed_fluctuation():.5f}")
    δ_g = 0.06003
    """

    # A machine pickled before delta_target, main_bearings, shaft or load_law existed has none
    # in its __dict__: it reads None.
    delta_target: float | None = None
    main_bearings: tuple[float, ...] | None = None
    shaft: Shaft | None = None
    load_law: str | None = None

    def __init__(
        self,
        cylinders: Sequence[Cylinder],
        *,
        shaft_inertia: float,
        strokes: int = 2,
        g: float = STANDARD_GRAVITY,
        name: str = "machine",
        rpm: float | None = None,
        rpm_range: tuple[float, float] | None = None,
        note: str = "",
        delta_target: float | None = None,
        main_bearings: Sequence[float] | None = None,
        shaft: Shaft | None = None,
        load_law: str | None = None,
    ) -> None:
        if isinstance(cylinders, Cylinder) or not isinstance(cylinders, Sequence):
            raise refused("cylinders", "cylinders must be a sequence of multicrank.Cylinder")
        cylinders = tuple(cylinders)
        if not cylinders:
            raise refused("cylinders", "cylinders must not be empty: a machine needs at least one cylinder")
        if not all(isinstance(c, Cylinder) for c in cylinders):
            raise refused("cylinders", "cylinders must all be multicrank.Cylinder")
        self.cylinders: tuple[Cylinder, ...] = cylinders
        self.shaft_inertia = check_magnitude(as_scalar(shaft_inertia, "shaft_inertia"), "shaft_inertia", "kg·m²")
        if not (math.isfinite(self.shaft_inertia) and self.shaft_inertia > 0):
            raise refused(
                "shaft_inertia", f"shaft_inertia = {self.shaft_inertia} is out of range; allowed: shaft_inertia > 0"
            )
        self.strokes = as_strokes(strokes)
        self.g = check_magnitude(as_scalar(g, "g"), "g", "m/s²")
        if not math.isfinite(self.g):
            raise refused("g", f"g = {self.g} is out of range; allowed: any finite real")
        if not isinstance(name, str):
            raise refused("name", f"name must be a str, got {type(name).__name__}")
        if not isinstance(note, str):
            raise refused("note", f"note must be a str, got {type(note).__name__}")
        self.name = name
        self.note = note
        self.rpm: float | None = None if rpm is None else as_rpm(rpm, "rpm")
        self.rpm_range: tuple[float, float] | None = None if rpm_range is None else _speed_range(rpm_range)
        if self.rpm is not None and self.rpm_range is not None:
            low, high = self.rpm_range
            if not low <= self.rpm <= high:
                raise refused(
                    "rpm",
                    f"rpm = {self.rpm:g} is out of range; allowed: inside rpm_range = ({low:g}, {high:g}) [1/min]",
                )
        for j, cylinder in enumerate(cylinders):
            for end in ("pressure", "pressure_crank_end"):
                period = getattr(getattr(cylinder, end), "cycle", None)
                if isinstance(period, float) and period > self.cycle * (1 + 1e-9):
                    # A 2π diagram repeats over a 4π cycle; a 4π one over a 2π cycle would be cut in half.
                    raise refused(
                        "cylinders",
                        f"cylinders[{j}].{end} is a {round(period / math.pi)}-stroke indicator diagram (cycle "
                        f"{period:.6g} rad), longer than this {self.strokes}-stroke machine's cycle; give strokes="
                        f"{round(period / math.pi)} or a diagram of the machine's cycle",
                    )
        self.delta_target: float | None = None if delta_target is None else _delta_target(delta_target)
        self.main_bearings: tuple[float, ...] | None = None if main_bearings is None else as_bearings(main_bearings)
        if self.main_bearings is not None:
            _ = self._layout  # given bearings are checked by the core's rules now, the rest on first use
        self.shaft: Shaft | None = None if shaft is None else _as_shaft(shaft, len(cylinders))
        self.load_law: str | None = None if load_law is None else _load_law(load_law, self.rpm)
        self._sealed = True

    # -- construction --------------------------------------------------------------------
    # Class methods that build ``cls``: bound from their modules, where the type checker
    # takes their ``cls`` as a Machine (in a base class it could not).
    from_layout = classmethod(_from_layout)
    from_toml = classmethod(_from_toml)

    # -- what a machine is ----------------------------------------------------------------
    @functools.cached_property
    def _units(self) -> dict[str, np.ndarray]:
        """The cylinders as the core's unit columns, made on first use (a machine that is only
        a row of a table — a firing order's, a sweep's variant — never needs them) and kept:
        cached_property writes the instance's dict, past the sealed __setattr__."""
        return unit_columns(self.cylinders)

    @functools.cached_property
    def _layout(self) -> ShaftLayout:
        """The throws and bearings (:func:`~multicrank.machine.throws.layout_of`, the core's
        rules), made on first use and kept."""
        positions = [c.axial_position for c in self.cylinders]
        return layout_of(positions, self.main_bearings, max(c.crank_radius for c in self.cylinders))

    @property
    def _core(self) -> NativeMachine:
        """The core's machine (:func:`~multicrank.machine.native.motion_machine`): made on
        first use and kept, every question about this machine asked of it."""
        from .native import motion_machine  # native packs a Machine: it imports this module

        return motion_machine(self)

    @property
    def cycle(self) -> float:
        """Φ [rad]: the crank angle of one working cycle, π·strokes."""
        return math.pi * self.strokes

    @property
    def throws(self) -> tuple[float, ...]:
        """The throws' axial positions z_t [m], increasing: the distinct ``axial_position`` of
        the cylinders (a throw is the cylinders at one axial position, with its crank web and
        counterweight; positions equal to within 10⁻¹²·max(1, abs z) m are one).

        Examples
        --------
        >>> import multicrank as mc
        >>> cylinder = mc.presets.MACHINES["inline-4"].cylinders[0]
        >>> vee = mc.Machine.from_layout("v6-60", cylinder, shaft_inertia=0.2,
        ...                              cylinder_spacing=0.1)
        >>> vee.throws, vee.throw_index
        ((0.0, 0.1, 0.2), (0, 0, 1, 1, 2, 2))
        >>> [round(z, 6) for z in vee.bearings]
        [-0.05, 0.05, 0.15, 0.25]
        """
        return self._layout.throws

    @property
    def throw_index(self) -> tuple[int, ...]:
        """Each cylinder's throw: its index in :attr:`throws` (an int per cylinder, in the
        machine's order)."""
        return self._layout.throw_index

    @property
    def bearings(self) -> tuple[float, ...]:
        """The main bearings' axial positions [m], increasing: ``main_bearings`` where given,
        else n + 1 bearings interleaving the n :attr:`throws` z₁ < … < zₙ.

        The default puts a bearing at the midpoint between neighbouring throws and, outside,
        at z₁ − d₁/2 and zₙ + dₙ/2 (d₁ = z₂ − z₁, dₙ = zₙ − zₙ₋₁: as far out as the next
        bearing in). A machine of one throw gets z₁ ± r, r the largest ``crank_radius``: the
        lever rule splits a lone throw's load between its two bearings in halves whatever
        their distance, so r only places them plausibly.
        """
        if self.main_bearings is not None:
            return self.main_bearings
        return self._layout.bearings

    def load_factor(self, rpm: Any) -> float:
        """The factor :attr:`load_law` puts on the gauge pressures at the speed n.

        Parameters
        ----------
        rpm : float
            The speed n [1/min], > 0.

        Returns
        -------
        float
            (n/n_r)² under the propeller law (n_r the machine's ``rpm``); 1 without a law.

        Examples
        --------
        >>> import multicrank as mc
        >>> ship = mc.presets.MACHINES["slow-diesel-12"]
        >>> ship.load_law, ship.rpm, round(ship.load_factor(30.0), 6)
        ('propeller', 90.0, 0.111111)
        >>> mc.presets.MACHINES["inline-4"].load_factor(30.0)
        1.0
        """
        return float(load_factor(as_omega(rpm, "rpm"), rated_omega(self)))

    def __len__(self) -> int:
        return len(self.cylinders)

    def __eq__(self, other: object) -> bool:
        # By value: every field equal (the cylinders, and so their indicator diagrams, by value).
        if not isinstance(other, Machine):
            return NotImplemented
        return all(getattr(self, field) == getattr(other, field) for field in _MACHINE_FIELDS)

    # Not hashable: a field may hold an unhashable pressure callable.
    __hash__ = None  # type: ignore[assignment]

    def __setattr__(self, name: str, value: Any) -> None:
        # A machine is immutable once made: its unit columns and the native machine it owns
        # (machine/native.motion_machine, with the cycle tables of every steady state so far)
        # were made from its fields, and a field set afterwards would leave them answering for
        # the old machine. __init__ sets the fields before the machine is sealed.
        if self.__dict__.get("_sealed", False):
            raise dataclasses.FrozenInstanceError(
                f"cannot assign to field {name!r}: a Machine is immutable; machine.replace({name}=...) makes a "
                "changed copy"
            )
        super().__setattr__(name, value)

    def __delattr__(self, name: str) -> None:
        raise dataclasses.FrozenInstanceError(f"cannot delete field {name!r}: a Machine is immutable")

    def __getstate__(self) -> dict[str, Any]:
        # The native machine (machine/native.motion_machine), its lock and the cylinders' torque
        # orders (torsion/excitation.cylinder_orders) stay behind: a copy or an unpickled machine
        # makes its own on first use.
        return {key: value for key, value in self.__dict__.items() if key not in _DERIVED}

    def __setstate__(self, state: dict[str, Any]) -> None:
        # A pickle, of this release or an older one (which knew no sealing), unpickles sealed.
        self.__dict__.update(state)
        self.__dict__["_sealed"] = True

    def _with_phases(self, cylinders: Sequence[Cylinder]) -> Machine:
        """This machine with ``cylinders`` in place of its own, not checked again: for
        cylinders that are its own with other phases (a firing order's candidates), each
        checked as a cylinder already, where no rule of a machine looks (the number of
        cylinders, their diagrams' cycles, places and masses are its own). Nothing derived
        is carried over (the unit columns, the native machine, the orders are made anew)."""
        assert len(cylinders) == len(self.cylinders)
        made = object.__new__(type(self))
        state = self.__getstate__()
        state["cylinders"] = tuple(cylinders)
        made.__setstate__(state)
        return made

    def replace(self, **changes: Any) -> Machine:
        """A copy with some of its fields changed.

        Parameters
        ----------
        **changes
            New values of ``cylinders``, ``shaft_inertia``, ``strokes``, ``g``, ``name``,
            ``rpm``, ``rpm_range``, ``note``, ``delta_target``, ``main_bearings``, ``shaft``
            or ``load_law`` (as for :class:`Machine`); ``rpm=None``, ``rpm_range=None``,
            ``delta_target=None``, ``main_bearings=None``, ``shaft=None`` or
            ``load_law=None`` removes them. New ``cylinders`` keep the given ``main_bearings``
            and ``shaft``, which must still fit them; a machine with a ``load_law`` keeps its
            ``rpm`` (its rated speed) unless the law goes too.

        Returns
        -------
        Machine
            The changed copy, checked as a new one is.

        Raises
        ------
        MechanismError
            For a keyword that is no field of a machine (naming it and listing the fields; a
            cylinder's fields change through ``cylinders``), or a value the new machine refuses.

        Examples
        --------
        >>> import multicrank as mc
        >>> compressor = mc.presets.MACHINES["slow-compressor"]
        >>> bigger = compressor.replace(shaft_inertia=500.0, name="bigger flywheel")
        >>> bigger.name, bigger.shaft_inertia, compressor.shaft_inertia
        ('bigger flywheel', 500.0, 350.0)
        """
        cylinder_fields = tuple(field.name for field in dataclasses.fields(Cylinder))
        check_fields(changes, _MACHINE_FIELDS, "machine", elsewhere=cylinder_fields)
        fields = {field: changes.get(field, getattr(self, field)) for field in _MACHINE_FIELDS}
        return Machine(fields.pop("cylinders"), **fields)


def _as_shaft(value: Any, cylinders: int) -> Shaft:
    """A machine's shaft: a :class:`~multicrank.Shaft` with one node per cylinder."""
    value = as_instance(value, Shaft, "shaft")
    if len(value.cylinder_nodes) != cylinders:
        raise refused(
            "shaft",
            f"shaft.cylinder_nodes holds {len(value.cylinder_nodes)} nodes; the machine has {cylinders} cylinders "
            "(one node per cylinder, in the machine's order)",
        )
    return value


def _load_law(value: Any, rpm: float | None) -> str:
    """A machine's load law: one of :data:`LOAD_LAWS`, with the rated speed it scales from."""
    law = as_option(value, "load_law", LOAD_LAWS)
    if rpm is None:
        raise refused(
            "load_law",
            f"load_law = {law!r} needs the rated speed: the machine's rpm [1/min], from which the gauge pressures "
            "scale as (n/rpm)²; give rpm=...",
        )
    return law


def rated_omega(machine: Machine) -> float | None:
    """ω_r [rad/s] of the machine's load law, its rated speed (``rpm``); None without a law."""
    if machine.load_law is None:
        return None
    assert machine.rpm is not None  # a law needs it (Machine checks)
    return float(omega_from_rpm(machine.rpm))


def load_factor(omega: Any, rated: float | None) -> Any:
    """The factor on the gauge pressures at ω [rad/s] (a number or an array) under the
    propeller law of rated speed ω_r = ``rated`` [rad/s]: (ω/ω_r)²; 1 without a law
    (``rated`` None). The one place of the law's rule (:attr:`Machine.load_law`)."""
    return 1.0 if rated is None else (omega / rated) ** 2


def _delta_target(value: Any) -> float:
    """A target coefficient of speed fluctuation: a finite number > 0."""
    delta = as_scalar(value, "delta_target")
    if not (math.isfinite(delta) and delta > 0):
        raise refused(
            "delta_target",
            f"delta_target = {delta} is out of range; allowed: delta_target > 0 (a coefficient of speed "
            "fluctuation, e.g. 0.05 = 1/20 for a compressor)",
        )
    return delta


# Shaft.from_toml of a whole machine file checks it as this machine (the one loader).
use_machine_loader(Machine.from_toml)
