"""Machine files: a machine described in TOML (docs/machine-files.md).

:func:`read_machine_file` reads a file into a :class:`MachineFile`: every key known, of the
right type and present where required, angles converted from degrees to radians, pressures
to pascal, a CSV path made relative to the file. The numbers' ranges are checked where they
are used — by :class:`~multicrank.Cylinder`, :class:`~multicrank.Machine` and
:class:`~multicrank.IndicatorDiagram`, the one place for each rule — inside
:meth:`MachineFile.context`, which puts the file and the key in front of their message.
:meth:`multicrank.Machine.from_toml` assembles the machine.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .._files import read_toml
from .._native import MechanismError
from .._validation import refused
from ..gravity.layouts import Layout, as_layout
from ..pressure.diagram import PRESSURE_UNITS, IndicatorDiagram, check_pressure_unit
from .classes import SPEED_FLUCTUATION

__all__ = [
    "CYLINDER_KEYS",
    "LAYOUT_KEYS",
    "MACHINE_KEYS",
    "PRESSURE_KEYS",
    "SHAFT_KEYS",
    "MachineFile",
    "PressureSpec",
    "read_machine_file",
    "read_shaft_file",
]

# The keys of each table and what they hold: "number", "integer", "string", "boolean",
# "numbers" (an array of numbers), "integers" (an array of integers), "column" (an integer or
# a string), "table", "tables" (a table or an array of tables), "layout" (a string or a
# table), "banks" (an array of arrays of numbers). Keys ending in _deg are angles in degrees.
# docs/machine-files.md documents every one with its unit (tests/machine/test_files.py checks
# that it does).

#: The top level: the machine.
MACHINE_KEYS = {
    "name": "string",
    "note": "string",
    "shaft_inertia": "number",
    "strokes": "integer",
    "g": "number",
    "rpm": "number",
    "rpm_range": "numbers",
    "delta_target": "number",
    "class": "string",
    "layout": "layout",
    "firing_deg": "numbers",
    "cylinder_spacing": "number",
    "main_bearings": "numbers",
    "shaft": "table",
    "load_law": "string",
    "cylinder": "tables",
}
_MACHINE_REQUIRED = ("shaft_inertia", "cylinder")

#: A ``[cylinder]`` or ``[[cylinder]]`` table.
CYLINDER_KEYS = {
    "crank_radius": "number",
    "rod_length": "number",
    "piston_mass": "number",
    "rod_mass": "number",
    "rod_cg": "number",
    "rod_inertia": "number",
    "crank_mass": "number",
    "crank_cg_radius": "number",
    "counterweight_mass": "number",
    "counterweight_radius": "number",
    "bore": "number",
    "piston_rod_diameter": "number",
    "phase_deg": "number",
    "inclination_deg": "number",
    "axial_position": "number",
    "pressure": "table",
    "pressure_crank_end": "table",
}
_CYLINDER_REQUIRED = ("crank_radius", "rod_length", "piston_mass", "rod_mass", "rod_cg")
#: Keys of a cylinder that a layout sets.
_PLACED_BY_LAYOUT = ("phase_deg", "inclination_deg")

#: The ``[shaft]`` table: the :class:`~multicrank.Shaft` as a torsional chain (no angles in it).
SHAFT_KEYS = {
    "inertia": "numbers",
    "stiffness": "numbers",
    "cylinder_nodes": "integers",
    "damping": "numbers",
    "node_damping": "numbers",
}
_SHAFT_REQUIRED = ("inertia", "stiffness", "cylinder_nodes")

#: A ``layout = {...}`` table (a layout of one's own).
LAYOUT_KEYS = {"name": "string", "note": "string", "throws_deg": "numbers", "banks_deg": "banks", "strokes": "integer"}
_LAYOUT_REQUIRED = ("throws_deg", "banks_deg")

_COMMON_PRESSURE = {"type": "string", "kind": "string", "pressure_unit": "string", "reference_pressure": "number"}
#: A pressure table, by its ``type``.
PRESSURE_KEYS = {
    "compressor": {
        **_COMMON_PRESSURE,
        "suction_pressure": "number",
        "discharge_pressure": "number",
        "polytropic_exponent": "number",
        "clearance_volume": "number",
        "clearance_ratio": "number",
        "points": "integer",
        "absolute": "boolean",
    },
    "engine": {
        **_COMMON_PRESSURE,
        "intake_pressure": "number",
        "heat_release": "number",
        "compression_ratio": "number",
        "clearance_volume": "number",
        "start_of_combustion_deg": "number",
        "combustion_duration_deg": "number",
        "compression_exponent": "number",
        "expansion_exponent": "number",
        "wiebe_a": "number",
        "wiebe_m": "number",
        "exhaust_opening_deg": "number",
        "intake_closing_deg": "number",
        "points": "integer",
        "absolute": "boolean",
    },
    "table": {
        **_COMMON_PRESSURE,
        "path": "string",
        "angle_unit": "string",
        "absolute": "boolean",
        "angle_column": "column",
        "pressure_column": "column",
        "delimiter": "string",
        "closure_tolerance": "number",
    },
}
_PRESSURE_REQUIRED = {
    "compressor": ("suction_pressure", "discharge_pressure"),
    "engine": ("intake_pressure", "heat_release"),
    "table": ("path",),
}
#: The pressures of each type that ``pressure_unit`` applies to.
_PRESSURES = ("suction_pressure", "discharge_pressure", "intake_pressure", "reference_pressure")
#: Each synthetic type's ways to give the clearance: exactly one of them.
_CLEARANCE = {
    "compressor": ("clearance_volume", "clearance_ratio"),
    "engine": ("compression_ratio", "clearance_volume"),
}

_KINDS = {
    "number": "a number",
    "integer": "an integer",
    "string": "a string",
    "boolean": "true or false",
    "numbers": "an array of numbers",
    "integers": "an array of integers",
    "column": "a column number or name",
    "table": "a table",
    "tables": "a table or an array of tables",
    "layout": "a layout name or a table",
    "banks": "an array of arrays of numbers",
}

#: What to type instead of the [engine] table of multicrank's first file format.
_OLD_FORMAT = (
    "the [engine] table (the fields of the former presets.Machine) is no longer read; a machine file "
    "now holds the machine at top level and its cylinders in [cylinder] or [[cylinder]] tables "
    "(docs/machine-files.md; examples: multicrank.presets.MACHINE_FILES)"
)


@dataclass
class PressureSpec:
    """One pressure table of a file: how to make the cylinder's :class:`IndicatorDiagram`."""

    key: str
    type: str
    arguments: dict[str, Any]
    clearance: tuple[str, float] | None = None

    def diagram(self, cylinder: Any, end: str, cycle: float) -> IndicatorDiagram:
        """The diagram for a :class:`~multicrank.Cylinder`'s chamber ``end`` ("head" or "crank")
        over ``cycle`` [rad]."""
        if self.type == "table":
            return IndicatorDiagram.from_csv(cycle=cycle, **self.arguments)
        assert self.clearance is not None  # the reader insists on one for the synthetic types
        how, value = self.clearance
        if self.type == "compressor":
            return cylinder.compressor_diagram(end=end, cycle=cycle, **{how: value}, **self.arguments)
        if end == "crank":
            raise refused(
                "path",
                "type = 'engine' is not offered for the crank end: the engine cycle fires at the head end's "
                "outer dead centre; give a table (type = 'table') for a double-acting engine's crank end",
            )
        return cylinder.engine_diagram(cycle=cycle, **{how: value}, **self.arguments)


@dataclass
class CylinderSpec:
    """One cylinder table: the :class:`~multicrank.Cylinder` keywords and its pressure tables."""

    key: str
    fields: dict[str, Any]
    pressures: dict[str, PressureSpec] = field(default_factory=dict)


@dataclass
class MachineFile:
    """A machine file, read and type-checked (:func:`read_machine_file`)."""

    path: Path
    fields: dict[str, Any]
    cylinders: list[CylinderSpec]
    layout: Layout | None = None
    firing: list[float] | None = None
    cylinder_spacing: float | None = None
    #: The ``[shaft]`` table's :class:`~multicrank.Shaft` keywords, where the file has one.
    shaft: dict[str, Any] | None = None

    @property
    def strokes(self) -> int | None:
        """The strokes the file gives, if it gives them."""
        strokes = self.fields.get("strokes")
        return None if strokes is None else int(strokes)

    def error(self, key: str, message: str) -> MechanismError:
        """A :class:`MechanismError` that names this file and ``key``."""
        return refused("path", f"{self.path}: {key}: {message}" if key else f"{self.path}: {message}")

    @contextmanager
    def context(self, key: str) -> Iterator[None]:
        """Whatever MechanismError happens inside comes out naming the file and ``key``."""
        try:
            yield
        except MechanismError as error:
            raise self.error(key, str(error)) from None


def _class_limit(file: MachineFile, kind: str) -> float:
    """The δ a class of machine allows at most (``SPEED_FLUCTUATION``): a machine file's
    ``class``, where it gives no ``delta_target``."""
    if kind not in SPEED_FLUCTUATION:
        allowed = ", ".join(repr(k) for k in SPEED_FLUCTUATION)
        raise file.error("class", f"class = {kind!r} is not a class of machine; allowed: {allowed}")
    return SPEED_FLUCTUATION[kind][1]


def read_machine_file(path: str | os.PathLike[str]) -> MachineFile:
    """A machine file read and checked: keys, types, required keys, units (docs/machine-files.md).

    Raises
    ------
    MechanismError
        Naming the file and the key, for a file that cannot be read or is not TOML, an
        unknown or missing key, a value of the wrong type, or a choice that is not offered.
    """
    data = read_toml(path, "a machine file")
    name = Path(os.fspath(path))
    file = MachineFile(path=name, fields={}, cylinders=[])
    if "engine" in data and isinstance(data["engine"], dict):
        raise file.error("engine", _OLD_FORMAT)
    top = _Table(file, "", data, MACHINE_KEYS, _MACHINE_REQUIRED)
    file.fields = {"name": top.get("name", name.stem)}
    for key in ("note", "shaft_inertia", "strokes", "g", "rpm", "load_law"):
        if key in data:
            file.fields[key] = top.get(key)
    if "rpm_range" in data:
        file.fields["rpm_range"] = tuple(top.numbers("rpm_range", length=2))
    if "delta_target" in data:
        file.fields["delta_target"] = top.get("delta_target")
    if "class" in data:
        file.fields.setdefault("delta_target", _class_limit(file, top.get("class")))
    if "layout" in data:
        file.layout = _layout(file, data["layout"])
    if "firing_deg" in data:
        if file.layout is None:
            raise file.error("firing_deg", "firing_deg sets the firing of a layout's cylinders; give layout too")
        file.firing = [math.radians(a) for a in top.numbers("firing_deg")]
    if "cylinder_spacing" in data:
        if file.layout is None:
            raise file.error(
                "cylinder_spacing",
                "cylinder_spacing places a layout's throws along the shaft; give layout too (without one, give "
                "each [[cylinder]] its axial_position)",
            )
        file.cylinder_spacing = top.get("cylinder_spacing")
    if "main_bearings" in data:
        file.fields["main_bearings"] = top.numbers("main_bearings")
    if "shaft" in data:
        file.shaft = _shaft(file, data["shaft"])
    cylinders = data["cylinder"]
    if file.layout is not None:
        if not isinstance(cylinders, dict):
            raise file.error(
                "cylinder",
                "with a layout, the cylinder is one template: a single [cylinder] table, not an array [[cylinder]]",
            )
        file.cylinders = [_cylinder(file, "cylinder", cylinders, placed=True)]
    elif isinstance(cylinders, dict):
        file.cylinders = [_cylinder(file, "cylinder", cylinders, placed=False)]
    else:
        if not cylinders:
            raise file.error("cylinder", "an empty array: a machine needs at least one [[cylinder]]")
        file.cylinders = [_cylinder(file, f"cylinder[{j}]", table, placed=False) for j, table in enumerate(cylinders)]
    return file


def read_shaft_file(path: str | os.PathLike[str]) -> MachineFile | None:
    """A file that holds the ``[shaft]`` table alone, read and checked
    (:meth:`multicrank.Shaft.from_toml`); None for a machine file (one with ``cylinder`` or
    ``shaft_inertia``), which is a machine's, for :meth:`multicrank.Machine.from_toml` to read
    and check as one."""
    data = read_toml(path, "a shaft or machine file")
    if "cylinder" in data or "shaft_inertia" in data:
        return None
    file = MachineFile(path=Path(os.fspath(path)), fields={}, cylinders=[])
    _Table(file, "", data, {"shaft": "table"}, ("shaft",))
    file.shaft = _shaft(file, data["shaft"])
    return file


class _Table:
    """One TOML table of a file, checked against its keys."""

    def __init__(self, file: MachineFile, key: str, data: Any, keys: dict[str, str], required: tuple[str, ...]) -> None:
        self.file, self.key, self.data, self.keys = file, key, data, keys
        if not isinstance(data, dict):
            raise file.error(key, f"must be a table, got {_toml_type(data)}")
        unknown = sorted(set(data) - set(keys))
        if unknown:
            raise file.error(
                self.where(unknown[0]),
                f"unknown key{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}; known here: {', '.join(keys)}",
            )
        missing = [k for k in required if k not in data]
        if missing:
            raise file.error(
                self.where(missing[0]), f"missing required key{'s' if len(missing) > 1 else ''} {', '.join(missing)}"
            )
        for name, value in data.items():
            if not _is(keys[name], value):
                raise file.error(self.where(name), f"must be {_KINDS[keys[name]]}, got {_toml_type(value)} {value!r}")

    def where(self, name: str) -> str:
        return f"{self.key}.{name}" if self.key else name

    def get(self, name: str, default: Any = None) -> Any:
        value = self.data.get(name, default)
        return float(value) if self.keys.get(name) == "number" and value is not None else value

    def numbers(self, name: str, length: int | None = None) -> list[float]:
        values = [float(v) for v in self.data[name]]
        if length is not None and len(values) != length:
            raise self.file.error(self.where(name), f"must hold {length} numbers, got {len(values)}")
        return values


def _is(kind: str, value: Any) -> bool:
    """Whether a TOML value is of a kind of :data:`_KINDS`."""
    number = isinstance(value, (int, float)) and not isinstance(value, bool)
    checks: dict[str, Callable[[Any], bool]] = {
        "number": lambda v: number,
        "integer": lambda v: isinstance(v, int) and not isinstance(v, bool),
        "string": lambda v: isinstance(v, str),
        "boolean": lambda v: isinstance(v, bool),
        "numbers": lambda v: isinstance(v, list) and all(_is("number", x) for x in v),
        "integers": lambda v: isinstance(v, list) and all(_is("integer", x) for x in v),
        "column": lambda v: _is("integer", v) or isinstance(v, str),
        "table": lambda v: isinstance(v, dict),
        "tables": lambda v: isinstance(v, dict) or (isinstance(v, list) and all(isinstance(x, dict) for x in v)),
        "layout": lambda v: isinstance(v, (str, dict)),
        "banks": lambda v: isinstance(v, list) and all(_is("numbers", x) for x in v),
    }
    return checks[kind](value)


def _toml_type(value: Any) -> str:
    names = {
        bool: "a boolean",
        int: "an integer",
        float: "a number",
        str: "a string",
        list: "an array",
        dict: "a table",
    }
    return next((text for kind, text in names.items() if type(value) is kind), type(value).__name__)


def _shaft(file: MachineFile, data: Any) -> dict[str, Any]:
    """The ``[shaft]`` table's keywords of :class:`~multicrank.Shaft`, which checks their ranges."""
    table = _Table(file, "shaft", data, SHAFT_KEYS, _SHAFT_REQUIRED)
    return {
        name: table.numbers(name) if kind == "numbers" else list(data[name])
        for name, kind in SHAFT_KEYS.items()
        if name in data
    }


def _layout(file: MachineFile, value: Any) -> Layout:
    """A preset layout by name, or a layout of the file's own."""
    if isinstance(value, str):
        with file.context("layout"):
            return as_layout(value)
    table = _Table(file, "layout", value, LAYOUT_KEYS, _LAYOUT_REQUIRED)
    throws = table.numbers("throws_deg")
    banks = [tuple(float(g) for g in bank) for bank in value["banks_deg"]]
    if len(banks) != len(throws):
        raise file.error(
            "layout.banks_deg",
            f"must hold one array of bank angles per throw: {len(throws)} throws, {len(banks)} arrays",
        )
    strokes = table.get("strokes")
    return Layout(
        table.get("name", file.path.stem),
        table.get("note", f"the layout of {file.path.name}"),
        tuple(throws),
        tuple(banks),
        strokes,
    )


def _cylinder(file: MachineFile, key: str, data: Any, *, placed: bool) -> CylinderSpec:
    table = _Table(file, key, data, CYLINDER_KEYS, _CYLINDER_REQUIRED)
    if placed:
        for name in _PLACED_BY_LAYOUT:
            if name in data:
                raise file.error(table.where(name), "set by the layout (each cylinder's phase and bank); leave it out")
    fields = {name: table.get(name) for name, kind in CYLINDER_KEYS.items() if kind == "number" and name in data}
    for name in _PLACED_BY_LAYOUT:
        if name in fields:
            fields[name.removesuffix("_deg")] = math.radians(fields.pop(name))
    spec = CylinderSpec(key, fields)
    for end in ("pressure", "pressure_crank_end"):
        if end in data:
            spec.pressures[end] = _pressure(file, table.where(end), data[end])
    return spec


def _pressure(file: MachineFile, key: str, data: dict[str, Any]) -> PressureSpec:
    kind = data.get("type")
    if kind not in PRESSURE_KEYS:
        raise file.error(
            f"{key}.type",
            ("missing required key type" if kind is None else f"type = {kind!r} is not offered")
            + f"; allowed: {', '.join(repr(k) for k in PRESSURE_KEYS)}",
        )
    table = _Table(file, key, data, PRESSURE_KEYS[kind], _PRESSURE_REQUIRED[kind])
    unit = table.get("pressure_unit", "Pa")
    if unit not in PRESSURE_UNITS:
        raise file.error(
            table.where("pressure_unit"),
            f"pressure_unit = {unit!r} is not offered; allowed: {', '.join(PRESSURE_UNITS)}",
        )
    arguments: dict[str, Any] = {}
    clearance: tuple[str, float] | None = None
    for name in data:
        if name in ("type", "pressure_unit") or name in _CLEARANCE.get(kind, ()):
            continue
        value = table.get(name)
        if name.endswith("_deg"):
            arguments[name.removesuffix("_deg")] = math.radians(value)
        elif name in _PRESSURES:
            arguments[name] = value * PRESSURE_UNITS[unit]
        elif name == "path":
            arguments["path"] = file.path.parent / value
        else:
            arguments[name] = value
    if kind == "table":
        arguments["pressure_unit"] = unit  # from_csv checks the table's pressures against it
    else:
        given = [table.get(name) * PRESSURE_UNITS[unit] for name in _PRESSURES if name in data]
        check_pressure_unit(given, unit, f"{file.path}: {key}", stacklevel=5)  # from_toml's caller
        given = [name for name in _CLEARANCE[kind] if name in data]
        if len(given) != 1:
            raise file.error(
                table.where(given[0] if given else _CLEARANCE[kind][0]),
                f"give exactly one of {' and '.join(_CLEARANCE[kind])}" + (", not both" if given else ""),
            )
        clearance = (given[0], table.get(given[0]))
    return PressureSpec(key, kind, arguments, clearance)
