"""The design columns of a motion sweep, written once: their names, what each is and its unit.

:mod:`multicrank.motion.variants` applies them to a machine (:func:`~multicrank.motion.variants.machine_variant`)
and ``multicrank sweep motion`` makes an option of each; both take the names from here (and the
cylinder's from :data:`multicrank.machine.cylinder.CYLINDER_FIELDS`). Loading it is cheap (no
pandas), so the command line may.
"""

from __future__ import annotations

from ..machine.cylinder import CYLINDER_FIELDS, UNIT_FIELDS

__all__ = ["COLUMN_MEANINGS", "CYLINDER_COLUMNS", "MACHINE_COLUMNS", "UNIT_COLUMNS"]

#: The columns that are not a field of a cylinder, with what each is and its unit.
_MACHINE_ONLY: dict[str, tuple[str, str]] = {
    "shaft_inertia": ("shaft inertia I_w", "kg·m²"),
    "rpm": ("mean speed", "1/min"),
    "g": ("gravitational acceleration", "m/s²"),
    "pressure_scale": ("factor on every indicator diagram", "dimensionless"),
}
#: The Cylinder fields a design may change, each set on every cylinder: its geometry and
#: masses (not where it sits: phase and inclination) and its bore.
CYLINDER_COLUMNS: tuple[str, ...] = (*(f for f in UNIT_FIELDS if f not in ("phase", "inclination")), "bore")
#: Every column a motion sweep's design may have, in the order of the issue.
MACHINE_COLUMNS: tuple[str, ...] = (*_MACHINE_ONLY, *CYLINDER_COLUMNS)
#: The Cylinder fields a design may set on one cylinder alone, as the column ``"field[j]"``
#: (j the cylinder's index in the machine, from 0): where it sits in the firing order, and
#: its counterweight (only the first moment enters: gravity).
UNIT_COLUMNS: tuple[str, ...] = ("phase", "counterweight_mass", "counterweight_radius")
#: Each of MACHINE_COLUMNS: (what it is, its unit).
COLUMN_MEANINGS: dict[str, tuple[str, str]] = {
    name: _MACHINE_ONLY[name] if name in _MACHINE_ONLY else CYLINDER_FIELDS[name] for name in MACHINE_COLUMNS
}
