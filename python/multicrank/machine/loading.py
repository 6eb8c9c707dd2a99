"""A :class:`~multicrank.Machine` from a TOML machine file: :func:`from_toml`, which
:class:`~multicrank.Machine` binds as its class method ``Machine.from_toml``, builds the
machine from what :func:`~multicrank.machine.files.read_machine_file` read (the keys, their
types and units; the ranges are checked by the classes it builds).
"""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING

from ..gravity.layouts import Layout
from .cylinder import Cylinder
from .files import MachineFile, read_machine_file
from .shaft import Shaft, shaft_of_file

if TYPE_CHECKING:
    from .machine import Machine

__all__ = ["from_toml"]


def from_toml(cls: type[Machine], path: str | os.PathLike[str]) -> Machine:
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
    ``cylinder_spacing``       m            with a layout: throw t at z₀ + t·s along the
                                            shaft (z₀ the template's ``axial_position``)
    ``main_bearings``          m            the main bearings' axial positions, increasing
                                            (default: n + 1 interleaving the n throws)
    ``shaft``                  table        the shaft as a torsional chain, ``[shaft]`` below
                                            (optional; :class:`~multicrank.Shaft`)
    ``load_law``               text         "propeller": the gauge pressures scale as
                                            (n/rpm)², rpm the rated speed (optional;
                                            :attr:`Machine.load_law`)
    ``cylinder``               table(s)     required; ``[cylinder]`` (one cylinder, or the
                                            layout's template) or ``[[cylinder]]`` (one each)
    **[shaft]**
    ``inertia``                kg·m²        required; J_i of each node along the chain
    ``stiffness``              N·m/rad      required; k_i of the section between nodes i
                                            and i + 1 (one fewer than the nodes)
    ``cylinder_nodes``         integers     required; each cylinder's node, in the file's
                                            cylinder order (with a layout: the layout's)
    ``damping``                N·m·s/rad    c_i of each section (optional)
    ``node_damping``           N·m·s/rad    c_i of each node, to ground: a propeller, a
                                            damper (optional)
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
    ``axial_position``         m            z along the shaft (default 0; with a layout
                                            the first throw's)
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
    fields = dict(file.fields)
    if file.shaft is not None:
        count = len(cylinders) if file.layout is None else sum(len(bank) for bank in file.layout.banks)
        fields["shaft"] = _shaft(file, count)
    if file.layout is not None:
        # A bad cylinder_spacing or main_bearings is named by its own message.
        with file.context("firing_deg" if file.firing is not None else ""):
            return cls.from_layout(
                file.layout, cylinders[0], firing=file.firing, cylinder_spacing=file.cylinder_spacing, **fields
            )
    with file.context(""):
        return cls(cylinders, **fields)


def _shaft(file: MachineFile, cylinders: int) -> Shaft:
    """The file's :class:`~multicrank.Shaft` (as ``Shaft.from_toml`` reads it), with one node
    per cylinder of the machine's ``cylinders``."""
    shaft = shaft_of_file(file)
    if len(shaft.cylinder_nodes) != cylinders:
        order = "the layout's order" if file.layout is not None else "the order of the [[cylinder]] tables"
        given = len(shaft.cylinder_nodes)
        raise file.error(
            "shaft.cylinder_nodes", f"must hold one node per cylinder, in {order}: {cylinders} cylinders, got {given}"
        )
    return shaft


def _layout_strokes(layout: Layout | None) -> int:
    """The strokes a layout implies where a file gives none: its own, else 2."""
    return 2 if layout is None else layout.strokes or 2
