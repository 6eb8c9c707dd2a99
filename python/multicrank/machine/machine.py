"""The physical machine of any layout, in SI units: cylinders on one shaft.

A :class:`Machine` is its cylinders (:class:`~multicrank.Cylinder`), the shaft's moment of
inertia and the working cycle. It gives the quantities of the machine's equation of motion
(docs/theory.md): the reduced moment of inertia J(φ) and J'(φ), the potential energy U(φ)
and the gravity torque −dU/dφ, the gas torque and the inertia torque, all computed in the
Rust core; and the dimensionless :class:`~multicrank.Engine` of gravity at any speed.
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Sequence
from typing import Any

import numpy as np

from .._native import MechanismError
from .._native import machine_engine as _native_machine_engine
from .._native import machine_evaluate as _native_machine_evaluate
from .._native import machine_gas_torque as _native_machine_gas_torque
from .._native import machine_inertia as _native_machine_inertia
from .._shaft import inertia_torque as _inertia_torque
from .._text import counted
from .._validation import (
    as_real_array,
    as_returned,
    as_scalar,
    as_speed,
    as_strokes,
    as_threshold,
    check_fields,
    check_magnitude,
    contiguous,
)
from .._validation import as_speed_range as _speed_range
from ..gravity.engines import Engine
from ..gravity.grids import as_phi
from ..gravity.layouts import Layout, as_layout
from ..gravity.mechanism import STANDARD_GRAVITY
from .cylinder import Cylinder, Pressure, diagram_strokes, unit_columns
from .files import read_machine_file
from .firing import chosen_firing, even_firing

__all__ = ["Machine"]

#: A machine's fields, as :meth:`Machine.replace` takes them.
_MACHINE_FIELDS = ("cylinders", "shaft_inertia", "strokes", "g", "name", "rpm", "rpm_range", "note", "delta_target")


class Machine:
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
        :meth:`engine` (and of the report). Descriptive; nothing else depends on it.
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

    Attributes
    ----------
    cylinders : tuple of Cylinder
        The cylinders, in the order given.
    shaft_inertia, strokes, g, name, rpm, rpm_range, note, delta_target
        The parameters as given (``rpm``, ``rpm_range`` and ``delta_target`` None where not
        given). Read them; :meth:`replace` makes a changed copy.

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

    # A machine pickled before delta_target existed has none in its __dict__: it reads None.
    delta_target: float | None = None

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
    ) -> None:
        if isinstance(cylinders, Cylinder) or not isinstance(cylinders, Sequence):
            raise MechanismError("cylinders must be a sequence of multicrank.Cylinder")
        cylinders = tuple(cylinders)
        if not cylinders:
            raise MechanismError("cylinders must not be empty: a machine needs at least one cylinder")
        if not all(isinstance(c, Cylinder) for c in cylinders):
            raise MechanismError("cylinders must all be multicrank.Cylinder")
        self.cylinders: tuple[Cylinder, ...] = cylinders
        self.shaft_inertia = check_magnitude(as_scalar(shaft_inertia, "shaft_inertia"), "shaft_inertia", "kg·m²")
        if not (math.isfinite(self.shaft_inertia) and self.shaft_inertia > 0):
            raise MechanismError(f"shaft_inertia = {self.shaft_inertia} is out of range; allowed: shaft_inertia > 0")
        self.strokes = as_strokes(strokes)
        self.g = check_magnitude(as_scalar(g, "g"), "g", "m/s²")
        if not math.isfinite(self.g):
            raise MechanismError(f"g = {self.g} is out of range; allowed: any finite real")
        if not isinstance(name, str):
            raise MechanismError(f"name must be a str, got {type(name).__name__}")
        if not isinstance(note, str):
            raise MechanismError(f"note must be a str, got {type(note).__name__}")
        self.name = name
        self.note = note
        self.rpm: float | None = None if rpm is None else as_speed(rpm, "rpm")
        self.rpm_range: tuple[float, float] | None = None if rpm_range is None else _speed_range(rpm_range)
        if self.rpm is not None and self.rpm_range is not None:
            low, high = self.rpm_range
            if not low <= self.rpm <= high:
                raise MechanismError(
                    f"rpm = {self.rpm:g} is out of range; allowed: inside rpm_range = ({low:g}, {high:g}) [1/min]"
                )
        for j, cylinder in enumerate(cylinders):
            for end in ("pressure", "pressure_crank_end"):
                period = getattr(getattr(cylinder, end), "cycle", None)
                if isinstance(period, float) and period > self.cycle * (1 + 1e-9):
                    # A 2π diagram repeats over a 4π cycle; a 4π one over a 2π cycle would be cut in half.
                    raise MechanismError(
                        f"cylinders[{j}].{end} is a {round(period / math.pi)}-stroke indicator diagram (cycle "
                        f"{period:.6g} rad), longer than this {self.strokes}-stroke machine's cycle; give strokes="
                        f"{round(period / math.pi)} or a diagram of the machine's cycle"
                    )
        self.delta_target: float | None = None if delta_target is None else _delta_target(delta_target)
        self._units = unit_columns(cylinders)

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
            raise MechanismError(
                f"cylinder must be a multicrank.Cylinder (the template), got {type(cylinder).__name__}"
            )
        if len(layout.throws) != len(layout.banks):
            raise MechanismError(
                f"layout {layout.name!r} has {len(layout.throws)} throws but {len(layout.banks)} banks entries"
            )
        if strokes is None:
            strokes = layout.strokes or diagram_strokes(cylinder) or 2
        cycle_strokes = as_strokes(strokes)
        if layout.strokes is not None and cycle_strokes != layout.strokes:
            raise MechanismError(
                f"strokes = {cycle_strokes} contradicts layout {layout.name!r}, whose throws are the "
                f"{layout.strokes}-stroke phase set"
            )
        written: list[float] = []  # β − γ [deg], as the layout writes it
        inclinations: list[float] = []
        first: list[bool] = []
        for beta, gammas in zip(layout.throws, layout.banks, strict=True):
            if not len(gammas):
                raise MechanismError(f"layout {layout.name!r} has a throw at {beta:g}° without a cylinder")
            for index, gamma in enumerate(gammas):
                written.append(float(beta) - float(gamma))
                inclinations.append(float(gamma))
                first.append(index == 0)
        crank = np.asarray(written)
        if not np.all(np.isfinite(crank)) or not np.all(np.isfinite(inclinations)):
            raise MechanismError(f"layout {layout.name!r} has a throw or bank angle that is not finite")
        if firing is None:
            phases = even_firing(crank, cycle_strokes)
        else:
            phases = chosen_firing(firing, crank, cycle_strokes)
        bare = {"crank_mass": 0.0, "counterweight_mass": 0.0}
        cylinders = [
            cylinder.replace(phase=phase, inclination=math.radians(gamma), **({} if keeps_web else bare))
            for phase, gamma, keeps_web in zip(phases, inclinations, first, strict=True)
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
        )

    @classmethod
    def from_toml(cls, path: str | os.PathLike[str]) -> Machine:
        """A machine from a TOML machine file (docs/machine-files.md).

        The built-in machines are such files (``multicrank.presets.MACHINE_FILES``), and
        docs/machines/ holds more examples.

        A file describes either (a) a ``layout`` (a name in ``LAYOUTS`` or a table of one's
        own) with one ``[cylinder]`` template on every bank (see :meth:`from_layout`), or
        (b) the cylinders one by one in ``[[cylinder]]`` tables (a single ``[cylinder]``
        table: a one-cylinder machine). Keys are the fields of :class:`Machine` and
        :class:`Cylinder`; angles are in degrees, with ``_deg`` in their names.

        Parameters
        ----------
        path : str or os.PathLike
            The TOML file. A pressure table's ``path`` is relative to it.

        Returns
        -------
        Machine
            The machine the file describes, its name the file's stem unless it gives one.

        Raises
        ------
        MechanismError
            Naming the file and the key: a file that cannot be read or is not TOML, an
            unknown or missing key, a value of the wrong type or out of range.

        Notes
        -----
        The keys, their units and meanings (:doc:`/machine-files` explains them with
        examples):

        ========================== ============ ==================================================
        key                        unit         meaning
        ========================== ============ ==================================================
        **top level**
        ``name``, ``note``         text         default name: the file's stem
        ``shaft_inertia``          kg·m²        required; I_w, everything turning with the shaft
        ``strokes``                2 or 4       default 2 (with a layout: the layout's own)
        ``g``                      m/s²         default 9.80665; 0 switches gravity off
        ``rpm``                    1/min        the running speed (optional)
        ``rpm_range``              1/min        [low, high] (optional)
        ``delta_target``           1            the δ it is meant to run at (optional)
        ``class``                  text         its class: ``delta_target`` its limit
                                                (``presets.SPEED_FLUCTUATION``; optional)
        ``layout``                 name, table  a name in LAYOUTS, or a table of one's own:
                                                ``throws_deg`` (the throws β [deg]), ``banks_deg``
                                                (per throw, the bank inclinations γ [deg]),
                                                ``name``, ``note``, ``strokes``
        ``firing_deg``             deg          with a layout: every cylinder's phase α (firing)
        ``cylinder``               table(s)     required; ``[cylinder]`` (one cylinder, or the
                                                layout's template) or ``[[cylinder]]`` (one each)
        **[cylinder]**
        ``crank_radius``           m            required; r
        ``rod_length``             m            required; l
        ``piston_mass``            kg           required; m_t (crosshead, piston rod included)
        ``rod_mass``               kg           required; m_k
        ``rod_cg``                 m            required; z_k from the piston-pin axis
        ``rod_inertia``            kg·m²        I_k about the rod's centre of gravity
        ``crank_mass``             kg           m_s, crank web and pin
        ``crank_cg_radius``        m            r_s
        ``counterweight_mass``     kg           m_p
        ``counterweight_radius``   m            r_p
        ``bore``                   m            D (0: no gas force)
        ``piston_rod_diameter``    m            d, double acting
        ``phase_deg``              deg          α (not with a layout)
        ``inclination_deg``        deg          γ, 90 upright (not with a layout)
        ``pressure``               table        the crown's (head end's) gas pressure, below
        ``pressure_crank_end``     table        double acting: the crank end's, below
        **pressure tables**                     ``[cylinder.pressure]``, ``[cylinder.pressure_crank_end]``
        ``type``                   text         "compressor", "engine" or "table" (required)
        ``pressure_unit``          text         Pa (default), kPa, bar, MPa, psi: the unit of
                                                every pressure in the table and in a CSV file
        ``reference_pressure``     pressure     the crankcase pressure (default 101325 Pa)
        ``kind``                   text         the interpolation, as IndicatorDiagram's
        *compressor*                            ``suction_pressure``, ``discharge_pressure`` (required),
                                                ``polytropic_exponent``, ``points``, ``absolute`` (default
                                                true) as :meth:`IndicatorDiagram.compressor`; one of
                                                ``clearance_volume`` [m³] or ``clearance_ratio`` (V_c over
                                                the chamber's swept volume)
        *engine*                                ``intake_pressure``, ``heat_release`` [J] (required),
                                                ``compression_exponent``, ``expansion_exponent``, ``wiebe_a``,
                                                ``wiebe_m``, ``points``, ``absolute`` (default true), the
                                                angles ``start_of_combustion_deg``,
                                                ``combustion_duration_deg``, ``exhaust_opening_deg``,
                                                ``intake_closing_deg`` as :meth:`IndicatorDiagram.engine`;
                                                one of ``compression_ratio`` ((V_s + V_c)/V_c) or
                                                ``clearance_volume`` [m³]; head end only
        *table*                                 ``path`` (required; relative to the TOML file),
                                                ``angle_unit``, ``absolute`` (default false),
                                                ``angle_column``, ``pressure_column``, ``delimiter``,
                                                ``closure_tolerance`` as :meth:`IndicatorDiagram.from_csv`
        ========================== ============ ==================================================

        The synthetic cycles are built from the chamber's own volume,
        :meth:`Cylinder.chamber_volume` (V_c + A·s(θ) at the head end, V_c + A_c·(2r − s(θ))
        at the crank end), over the machine's cycle.

        Examples
        --------
        A V-twin with one cylinder template, written to a temporary file:

        >>> import tempfile
        >>> from pathlib import Path
        >>> import multicrank as mc
        >>> text = '''
        ... shaft_inertia = 0.3   # kg·m²
        ... strokes = 4
        ... rpm = 3000            # 1/min
        ... layout = "v-twin-90"
        ... [cylinder]
        ... crank_radius = 0.045  # m
        ... rod_length = 0.15     # m
        ... rod_cg = 0.1          # m, from the piston-pin axis
        ... piston_mass = 0.5     # kg
        ... rod_mass = 0.45       # kg
        ... '''
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     path = Path(folder) / "twin.toml"
        ...     _ = path.write_text(text, encoding="utf-8")
        ...     machine = mc.Machine.from_toml(path)
        >>> machine.name, len(machine), machine.strokes, machine.rpm
        ('twin', 2, 4, 3000.0)
        """
        file = read_machine_file(path)
        cycle = math.pi * (file.strokes or _layout_strokes(file.layout))
        cylinders = []
        for spec in file.cylinders:
            with file.context(spec.key):
                cylinder = Cylinder(**spec.fields)
            for end, pressure in spec.pressures.items():
                with file.context(pressure.key):
                    diagram = pressure.diagram(cylinder, "head" if end == "pressure" else "crank", cycle)
                    cylinder = cylinder.replace(**{end: diagram})
            cylinders.append(cylinder)
        if file.layout is not None:
            with file.context("firing_deg" if file.firing is not None else ""):
                return cls.from_layout(file.layout, cylinders[0], firing=file.firing, **file.fields)
        with file.context(""):
            return cls(cylinders, **file.fields)

    # -- description ---------------------------------------------------------------------
    @property
    def cycle(self) -> float:
        """Φ [rad]: the crank angle of one working cycle, π·strokes."""
        return math.pi * self.strokes

    def __len__(self) -> int:
        return len(self.cylinders)

    def __repr__(self) -> str:
        speed = "" if self.rpm is None else f", {self.rpm:g} rpm"
        return (
            f"Machine({self.name!r}, {counted(len(self), 'cylinder')}, shaft_inertia={self.shaft_inertia:g} kg·m², "
            f"{self.strokes}-stroke{speed}, g={self.g:g})"
        )

    def __eq__(self, other: object) -> bool:
        # By value: every field equal (the cylinders, and so their indicator diagrams, by value).
        if not isinstance(other, Machine):
            return NotImplemented
        return all(getattr(self, field) == getattr(other, field) for field in _MACHINE_FIELDS)

    # Not hashable: the fields are attributes that may be set, and a hash must not change.
    __hash__ = None  # type: ignore[assignment]

    def replace(self, **changes: Any) -> Machine:
        """A copy with some of its fields changed.

        Parameters
        ----------
        **changes
            New values of ``cylinders``, ``shaft_inertia``, ``strokes``, ``g``, ``name``,
            ``rpm``, ``rpm_range``, ``note`` or ``delta_target`` (as for :class:`Machine`);
            ``rpm=None``, ``rpm_range=None`` or ``delta_target=None`` removes them.

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

    def engine(self, rpm: float | None = None) -> Engine:
        """The dimensionless gravity engine at a speed.

        One unit per cylinder, with u1, u2 = U1, U2 ÷ I_w ω², ω = π·rpm/30; a cylinder's crank
        web and counterweight are in its u2. U* × I_w ω² is :meth:`potential_energy` up to a
        constant, and Q_u* × I_w ω² is −:meth:`gravity_torque`.

        Parameters
        ----------
        rpm : float, optional
            The speed n [1/min], > 0; default the machine's own ``rpm``.

        Returns
        -------
        Engine
            Named "<machine name> at <rpm> rpm".

        Raises
        ------
        MechanismError
            When no ``rpm`` is given and the machine has none.
        """
        if rpm is None:
            if self.rpm is None:
                raise MechanismError(f"rpm is required: machine {self.name!r} has no running speed (rpm) of its own")
            rpm = self.rpm
        speed = as_speed(rpm, "rpm")
        columns = _native_machine_engine(self._units, self.g, self.shaft_inertia, speed)
        return Engine(**columns, name=f"{self.name} at {speed:g} rpm")

    def design(self, rpm: float | None = None) -> dict[str, Any]:
        """The keywords of the in-line functions for this machine at a speed.

        The keywords of :func:`~multicrank.potential_energy`,
        :func:`~multicrank.generalized_force`, :func:`~multicrank.speed_fluctuation`, …:
        ``crank_ratio``, ``inclination`` [rad], ``u1``, ``u2`` and ``phases`` [rad]. Only for
        a machine of identical units that differ in phase alone (an in-line machine with a
        web on every crank, the paper's machine); any other has no single (λ, γ, u1, u2): use
        :meth:`engine`.

        Parameters
        ----------
        rpm : float, optional
            The speed n [1/min], > 0; default the machine's own ``rpm``.

        Returns
        -------
        dict
            ``crank_ratio``, ``inclination``, ``u1``, ``u2`` (floats) and ``phases`` (an
            array), to pass as ``**design``.

        Raises
        ------
        MechanismError
            When the cylinders differ in anything but their phase.

        Examples
        --------
        >>> import numpy as np
        >>> import multicrank as mc
        >>> design = mc.presets.MACHINES["slow-compressor"].design()
        >>> sorted(design)
        ['crank_ratio', 'inclination', 'phases', 'u1', 'u2']
        >>> print(f"δ_g = {mc.speed_fluctuation(**design):.6f}")
        δ_g = 0.007576
        """
        engine = self.engine(rpm)
        shared = {}
        for field in ("crank_ratio", "inclination", "u1", "u2"):
            column = getattr(engine, field)
            if not np.all(column == column[0]):
                raise MechanismError(
                    f"machine {self.name!r} has cylinders that differ in {field}: the in-line design (one "
                    f"crank_ratio, inclination, u1, u2 for all) is for machines of identical cylinders; use engine()"
                )
            shared[field] = float(column[0])
        return {**shared, "phases": engine.phase.copy()}

    # -- the quantities of the equation of motion -----------------------------------------
    def reduced_inertia(self, phi: Any, *, parallel_threshold: Any = None) -> tuple[np.ndarray, np.ndarray]:
        """(J, dJ/dφ): the reduced moment of inertia [kg·m²] and its slope [kg·m²/rad].

        J(φ) = I_w + Σ_j [m_k3 r² + (m_t + m_k1) s'(ψ_j)² + ΔI β'(ψ_j)²], with the rod split
        exactly into m_k1 = m_k (l − z_k)/l at the piston pin, m_k3 = m_k z_k/l at the crank
        pin and ΔI turning with the rod angle β; ½ J φ̇² is the machine's kinetic energy.

        Parameters
        ----------
        phi : array_like or UniformGrid
            Crank angle φ [rad]; any shape.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default
            (:func:`~multicrank.set_parallel_threshold`).

        Returns
        -------
        J : ndarray
            The reduced moment of inertia [kg·m²], the shape of ``phi``.
        dJ_dphi : ndarray
            Its slope dJ/dφ [kg·m²/rad], the shape of ``phi``.
        """
        shape, angles = as_phi(phi)
        result = _native_machine_inertia(self._units, self.shaft_inertia, angles, as_threshold(parallel_threshold))
        return result["J"].reshape(shape), result["dJ_dphi"].reshape(shape)

    def _evaluate(self, quantity: str, phi: Any, parallel_threshold: Any, per_unit: bool = False) -> np.ndarray:
        """One of the core's per-angle quantities, shaped as ``phi`` (with a leading unit axis
        for per-unit ones)."""
        shape, angles = as_phi(phi)
        flat = _native_machine_evaluate(quantity, self._units, self.g, angles, as_threshold(parallel_threshold))
        return flat.reshape((len(self), *shape) if per_unit else shape)

    def potential_energy(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """U(φ) = Σ m·g·height, the potential energy of gravity.

        Parameters
        ----------
        phi : array_like or UniformGrid
            Crank angle φ [rad]; any shape.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default.

        Returns
        -------
        ndarray
            U [J], the shape of ``phi``; each unit measured from its own ψ = 0 configuration.
        """
        return self._evaluate("potential_energy", phi, parallel_threshold)

    def gravity_torque(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """The torque of gravity on the shaft, −dU/dφ.

        Parameters
        ----------
        phi : array_like or UniformGrid
            Crank angle φ [rad]; any shape.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default.

        Returns
        -------
        ndarray
            The torque [N·m], positive accelerating the shaft; the shape of ``phi``.
        """
        return self._evaluate("gravity_torque", phi, parallel_threshold)

    def piston_travel(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """Every piston's travel s(ψ_j) from its outer dead centre.

        Parameters
        ----------
        phi : array_like or UniformGrid
            Crank angle φ [rad]; any shape.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default.

        Returns
        -------
        ndarray
            s [m], shape (units,) + phi.shape.
        """
        return self._evaluate("travel", phi, parallel_threshold, per_unit=True)

    def cycle_angles(self, phi: Any) -> np.ndarray:
        """θ_j = (φ + α_j) mod Φ, each unit's place in its working cycle.

        Parameters
        ----------
        phi : array_like
            Crank angle φ [rad]; any shape.

        Returns
        -------
        ndarray
            θ [rad] in [0, Φ), shape (units,) + phi.shape.
        """
        angles = np.asarray(as_real_array(phi, "phi"))
        phases = self._units["phase"].reshape((-1,) + (1,) * angles.ndim)
        return np.mod(angles + phases, self.cycle)

    def piston_forces(self, phi: Any) -> np.ndarray:
        """The net gas force on every piston, p(θ)·A − p_c(θ)·A_c.

        Parameters
        ----------
        phi : array_like
            Crank angle φ [rad]; any shape.

        Returns
        -------
        ndarray
            The force [N], positive toward the shaft; shape (units,) + phi.shape.
        """
        angles = np.asarray(as_real_array(phi, "phi"))
        theta = self.cycle_angles(angles)
        forces = np.zeros(theta.shape)
        for name, area, sign in (("pressure", "piston_area", 1.0), ("pressure_crank_end", "crank_end_area", -1.0)):
            # Units that share one pressure callable (one indicator diagram for every
            # cylinder, the usual case) take it in one call: per call overhead dominates.
            groups: dict[int, tuple[Pressure, list[int]]] = {}
            for j, c in enumerate(self.cylinders):
                function = getattr(c, name)
                if function is not None and c.bore > 0:
                    groups.setdefault(id(function), (function, []))[1].append(j)
            for function, units in groups.values():
                pressures = _pressure(function, theta[units], name)
                forces[units] += (
                    sign
                    * pressures
                    * np.array([getattr(self.cylinders[j], area) for j in units]).reshape((-1,) + (1,) * angles.ndim)
                )
        return forces

    def gas_torque(self, phi: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """The gas torque Σ_j F_j(θ_j)·s'(ψ_j), by the virtual work of the piston forces.

        Parameters
        ----------
        phi : array_like
            Crank angle φ [rad]; any shape.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default.

        Returns
        -------
        ndarray
            The torque [N·m], positive driving the shaft; the shape of ``phi``.
        """
        angles = np.asarray(as_real_array(phi, "phi"), dtype=float)
        flat = contiguous(angles).reshape(-1)
        forces = contiguous(self.piston_forces(flat)).reshape(-1)
        torque = _native_machine_gas_torque(self._units, flat, forces, as_threshold(parallel_threshold))
        return torque.reshape(angles.shape)

    def inertia_torque(self, phi: Any, omega: Any, *, parallel_threshold: Any = None) -> np.ndarray:
        """The inertia torque at a steady speed (φ̈ = 0): −½ J'(φ) ω².

        Parameters
        ----------
        phi : array_like
            Crank angle φ [rad]; any shape.
        omega : array_like
            The shaft speed ω [rad/s]; broadcasts against ``phi``.
        parallel_threshold : int, optional
            The work size from which this call runs on all cores; None: the global default.

        Returns
        -------
        ndarray
            The torque [N·m], the broadcast shape of ``phi`` and ``omega``.
        """
        _, slope = self.reduced_inertia(phi, parallel_threshold=parallel_threshold)
        return _inertia_torque(slope, as_real_array(omega, "omega"))


def _delta_target(value: Any) -> float:
    """A target coefficient of speed fluctuation: a finite number > 0."""
    delta = as_scalar(value, "delta_target")
    if not (math.isfinite(delta) and delta > 0):
        raise MechanismError(
            f"delta_target = {delta} is out of range; allowed: delta_target > 0 (a coefficient of speed "
            "fluctuation, e.g. 0.05 = 1/20 for a compressor)"
        )
    return delta


def _layout_strokes(layout: Layout | None) -> int:
    """The strokes a layout implies where a file gives none: its own, else 2."""
    return 2 if layout is None else layout.strokes or 2


def _pressure(function: Pressure, theta: np.ndarray, name: str) -> np.ndarray:
    """A pressure callable's values at θ, checked: real, finite, the shape of θ."""
    try:
        values = function(theta)
    except MechanismError:
        raise
    except Exception as error:
        raise MechanismError(f"{name} failed at the cycle angles given: {error}") from error
    return as_returned(values, name, "pressure", "Pa", theta.shape)
