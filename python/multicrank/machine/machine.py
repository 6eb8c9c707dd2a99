"""The physical machine of any layout, in SI units: cylinders on one shaft.

A :class:`Machine` is its cylinders (:class:`~multicrank.Cylinder`), the shaft's moment of
inertia and the working cycle. It gives the quantities of the machine's equation of motion
(docs/theory.md): the reduced moment of inertia J(φ) and J'(φ), the potential energy U(φ)
and the gravity torque −dU/dφ, the gas torque and the inertia torque, all computed in the
Rust core; and the dimensionless :class:`~multicrank.Engine` of gravity at any speed.

This module builds and checks a machine (its fields, :meth:`Machine.from_layout`,
:meth:`Machine.replace`); the class's other methods live by job beside it and are inherited
or bound here: the description in `description`, the quantities of the equation of motion in
`dynamics`, the gas forces in `gas`, the machine file in `loading` (read by `files`).
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
from ..gravity.layouts import Layout, as_layout
from ..gravity.mechanism import STANDARD_GRAVITY
from .cylinder import Cylinder, diagram_strokes, unit_columns
from .description import MachineDescription
from .dynamics import MachineDynamics
from .gas import MachineGas
from .loading import from_toml as _from_toml
from .phases import chosen_firing, even_firing
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
        _ = self._layout  # the throws and bearings, checked by the core's rules now
        self.shaft: Shaft | None = None if shaft is None else _as_shaft(shaft, len(cylinders))
        self.load_law: str | None = None if load_law is None else _load_law(load_law, self.rpm)
        self._sealed = True

    # -- construction --------------------------------------------------------------------
    @classmethod
    def from_layout(
        cls,
        layout: Layout | str,
        cylinder: Cylinder,
        *,
        shaft_inertia: float,
        strokes: int | None = None,
        firing: Any = None,
        g: float = STANDARD_GRAVITY,
        name: str | None = None,
        rpm: float | None = None,
        rpm_range: tuple[float, float] | None = None,
        note: str | None = None,
        delta_target: float | None = None,
        cylinder_spacing: float | None = None,
        main_bearings: Sequence[float] | None = None,
        shaft: Shaft | None = None,
        load_law: str | None = None,
    ) -> Machine:
        """A machine of a layout with one cylinder template on every bank.

        Parameters
        ----------
        layout : Layout or str
            A :class:`~multicrank.Layout`, or the name of one in ``LAYOUTS``.
        cylinder : Cylinder
            The template: every cylinder is this one, with its ``phase`` and ``inclination``
            replaced by the layout's. Crank webs and counterweights belong to the **throw**:
            the first cylinder on each throw keeps the template's ``crank_mass`` and
            ``counterweight_mass``, the others on that throw get 0 (a V's shared pin carries
            one web, not two).
        shaft_inertia : float
            I_w [kg·m²], as for :class:`Machine`.
        strokes : 2 or 4, optional
            The working cycle; default the layout's own (``Layout.strokes``: the in-line
            presets are made for one), else that of the template's indicator diagrams (a
            four-stroke engine cycle makes a four-stroke machine), else 2. A cycle that
            contradicts the layout's is refused.
        firing : array_like, optional
            The cylinders' phases α_j [rad] in the layout's order (throw by throw, bank by
            bank), to choose the firing order of a four-stroke machine by hand. Each must be
            β − γ of its cylinder plus a whole number of turns (2π); it is taken modulo the cycle.
        g : float, default STANDARD_GRAVITY
            Gravity [m/s²], as for :class:`Machine`.
        name : str, optional
            A label; default the layout's name.
        rpm : float, optional
            The running speed [1/min], as for :class:`Machine`.
        rpm_range : (float, float), optional
            The speeds (low, high) [1/min] the machine runs at, as for :class:`Machine`.
        note : str, optional
            A description; default the layout's note.
        delta_target : float, optional
            The δ the machine is meant to run at, as for :class:`Machine`.
        cylinder_spacing : float, optional
            s [m], > 0: the distance between neighbouring throws along the shaft. Throw t of
            the layout (``Layout.throws``, from 0) is placed at z_t = z₀ + t·s, z₀ the
            template's ``axial_position``, and every cylinder on it (a V's banks on its shared
            pin) there. Default: every cylinder at z₀, one throw.
        main_bearings : sequence of float, optional
            The main bearings' axial positions [m], as for :class:`Machine`; default
            :attr:`bearings` interleaves the throws.
        shaft : Shaft, optional
            The shaft as a torsional chain, its ``cylinder_nodes`` in the layout's cylinder
            order, as for :class:`Machine`.
        load_law : {None, "propeller"}, optional
            How the indicator diagrams follow the speed, as for :class:`Machine`.

        Returns
        -------
        Machine
            One cylinder per bank and throw, in the layout's order.

        Notes
        -----
        A cylinder on a throw at absolute angle β (the crank pin at φ + β) with bank
        inclination γ gets inclination γ and phase α = β − γ, as
        :meth:`~multicrank.Engine.from_throws` does. On a two-stroke machine that is all:
        α is reduced to [0, 2π). On a four-stroke machine the phase also places the
        cylinder in its 4π cycle (θ = (φ + α) mod 4π; it fires at θ = 0), and β − γ fixes it
        only modulo 2π: each cylinder gets α = β − γ or β − γ + 2π (reduced to [0, 4π)),
        chosen so that the firing is as even as the crank allows. Of the 2ⁿ choices the
        rule takes the one whose largest firing interval (gap between neighbouring phases
        around 4π) is smallest; among equals, the one whose intervals' sum of squares is
        smallest (closest to equal intervals); then the one that moves fewest cylinders
        from β − γ as the layout writes its throws (unreduced angles count: the in-line
        presets write the regular phase set j·4π/k of :func:`~multicrank.crank_phases`,
        whose firing is perfectly even, so they keep it exactly); then the one that keeps
        the earlier cylinders as written. Up to 16 cylinders; beyond, give ``firing``.

        **Along the shaft** the layout's throws are taken in their order from the front:
        ``cylinder_spacing`` puts throw t at z₀ + t·s. The four-stroke in-line layouts of
        4, 5, 6 and 8 cylinders (``inline-4-4t``, …) are the textbook cranks numbered from
        the front, their phases from the textbook firing order (1-3-4-2, 1-2-4-5-3,
        1-5-3-6-2-4, 1-6-2-5-8-3-7-4): the in-line four's pins lie at 0°, 180°, 180°, 0°
        along the shaft and the six's at 0°, 120°, 240°, 240°, 120°, 0° (mirror symmetric,
        so without first- and second-order couples), as in real engines. The other in-line
        layouts give cylinder j the phase j·T/k of the regular phase set; as cylinder j
        fires at φ = −α_j, they fire in the reverse of that order after cylinder 1, 1-k-…-2,
        as :func:`~multicrank.firing_orders` names them (``inline-3-4t`` 1-3-2,
        ``inline-6-2t`` 1-6-5-4-3-2): spaced, after cylinder 1 their firing runs from the
        back of the shaft forwards — for three cylinders every order is the same crank up
        to a mirror, but for the others it need not be the crank a real engine of that
        size has, whose couples differ.
        The V, boxer and W layouts write their throws along the shaft (``v8-cross``:
        0°, 90°, 270°, 180°). For another crank, give the cylinders one by one to
        :class:`Machine`, or a :class:`~multicrank.Layout` of one's own.

        Raises
        ------
        MechanismError
            For an unknown layout, a cylinder that is not a :class:`Cylinder`, a bad or
            contradicting ``strokes``, ``firing`` of the wrong length or at a phase the crank
            cannot have, and the fields :class:`Machine` checks.

        Examples
        --------
        A flat four, four-stroke: each opposed pair shares a phase modulo 2π, and the rule
        spreads the firings evenly over the 720° cycle.

        >>> import numpy as np
        >>> import multicrank as mc
        >>> cylinder = mc.Cylinder(crank_radius=0.04, rod_length=0.13, piston_mass=0.4,
        ...                        rod_mass=0.5, rod_cg=0.09, bore=0.09)
        >>> flat_four = mc.Machine.from_layout("boxer-4", cylinder, shaft_inertia=0.15,
        ...                                    strokes=4, rpm=5000)
        >>> len(flat_four), flat_four.strokes, flat_four.cycle
        (4, 4, 12.566370614359172)
        >>> [round(float(np.degrees(c.phase))) for c in flat_four.cylinders]
        [0, 360, 180, 540]
        >>> [round(float(np.degrees(c.inclination))) for c in flat_four.cylinders]
        [0, 180, 0, 180]
        """
        layout = as_layout(layout)
        if not isinstance(cylinder, Cylinder):
            raise refused(
                "cylinder", f"cylinder must be a multicrank.Cylinder (the template), got {type(cylinder).__name__}"
            )
        if len(layout.throws) != len(layout.banks):
            raise refused(
                "layout",
                f"layout {layout.name!r} has {len(layout.throws)} throws but {len(layout.banks)} banks entries",
            )
        if strokes is None:
            strokes = layout.strokes or diagram_strokes(cylinder) or 2
        cycle_strokes = as_strokes(strokes)
        if layout.strokes is not None and cycle_strokes != layout.strokes:
            raise refused(
                "strokes",
                f"strokes = {cycle_strokes} contradicts layout {layout.name!r}, whose throws are the "
                f"{layout.strokes}-stroke phase set",
            )
        written: list[float] = []  # β − γ [deg], as the layout writes it
        inclinations: list[float] = []
        first: list[bool] = []
        for beta, gammas in zip(layout.throws, layout.banks, strict=True):
            if not len(gammas):
                raise refused("layout", f"layout {layout.name!r} has a throw at {beta:g}° without a cylinder")
            for index, gamma in enumerate(gammas):
                written.append(float(beta) - float(gamma))
                inclinations.append(float(gamma))
                first.append(index == 0)
        crank = np.asarray(written)
        if not np.all(np.isfinite(crank)) or not np.all(np.isfinite(inclinations)):
            raise refused("layout", f"layout {layout.name!r} has a throw or bank angle that is not finite")
        if firing is None:
            phases = even_firing(crank, cycle_strokes)
        else:
            phases = chosen_firing(firing, crank, cycle_strokes)
        origin = cylinder.axial_position
        if cylinder_spacing is None:
            positions = [origin] * len(first)
        else:
            spacing = check_magnitude(as_scalar(cylinder_spacing, "cylinder_spacing"), "cylinder_spacing", "m")
            if not (math.isfinite(spacing) and spacing > 0):
                raise refused(
                    "cylinder_spacing",
                    f"cylinder_spacing = {spacing} is out of range; allowed: cylinder_spacing > 0 [m] (the distance "
                    "between neighbouring throws along the shaft)",
                )
            # Throw t of the layout: the count of first cylinders up to and including this one, less one.
            throw_of = np.cumsum(first) - 1
            positions = [origin + float(t) * spacing for t in throw_of]
        bare = {"crank_mass": 0.0, "counterweight_mass": 0.0}
        cylinders = [
            cylinder.replace(
                phase=phase,
                inclination=math.radians(gamma),
                axial_position=position,
                **({} if keeps_web else bare),
            )
            for phase, gamma, keeps_web, position in zip(phases, inclinations, first, positions, strict=True)
        ]
        return cls(
            cylinders,
            shaft_inertia=shaft_inertia,
            strokes=cycle_strokes,
            g=g,
            name=layout.name if name is None else name,
            rpm=rpm,
            rpm_range=rpm_range,
            note=layout.note if note is None else note,
            delta_target=delta_target,
            main_bearings=main_bearings,
            shaft=shaft,
            load_law=load_law,
        )

    # A class method that builds ``cls``: bound from its module, where the type checker
    # takes its ``cls`` as a Machine (in a base class it could not).
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
        # orders (motion/orders.cylinder_orders) stay behind: a copy or an unpickled machine
        # makes its own on first use.
        return {key: value for key, value in self.__dict__.items() if key not in _DERIVED}

    def __setstate__(self, state: dict[str, Any]) -> None:
        # A pickle, of this release or an older one (which knew no sealing), unpickles sealed.
        self.__dict__.update(state)
        self.__dict__["_sealed"] = True

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
