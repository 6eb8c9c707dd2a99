"""Every preset in one place: the built-in machines (:class:`~multicrank.Machine`) and the crank
and cylinder layouts (``LAYOUTS``, from :mod:`multicrank.layouts`).

The machines' numbers are illustrative: plausible for the class of machine named, not taken
from any one manufacturer's data sheet. Each machine has bores, a synthetic pressure cycle
built from its own cylinder volume V(θ) = V_c + A·s(θ), a running speed and a shaft inertia
(flywheel included) that gives the usual coefficient of speed fluctuation δ of its class
(``SPEED_FLUCTUATION``; the class of each machine in ``MACHINE_CLASSES`` and in its note).
δ is judged at the machine's ``rpm`` with its full-load pressure cycle; the flywheels were
sized with the textbook estimate I_w ≈ ΔE/(δ ω²) − mean(J − I_w), ΔE the largest swing of
∫(M − mean M) dφ over a cycle of the gas, gravity and inertia torques (tests/test_presets.py
checks that each δ lies in its class). The geometry and masses are those of the first
presets, so that the report's gravity analysis is about the same machines.

Each built-in machine is a TOML machine file shipped with the package (``MACHINE_FILES``,
``multicrank/data/machines/<name>.toml``: the numbers, and in its comments why they are
what they are), read by :meth:`multicrank.Machine.from_toml` like any other machine file. Copy
one to start a machine of one's own.

The machines are read on first use (``MACHINES`` is a lazy mapping): their indicator diagrams
need SciPy, which ``import multicrank`` does not load.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from ._validation import refused, warn_renamed
from .gravity.layouts import LAYOUTS, Layout, layout_engine
from .machine.classes import SPEED_FLUCTUATION
from .machine.machine import Machine

# DEFAULT_MACHINE (MACHINES[DEFAULT_MACHINE_NAME]) is a module attribute too, read on first use.
# The former names (_RENAMED) are read through __getattr__ with a DeprecationWarning.
__all__ = [
    "DEFAULT_MACHINE_NAME",
    "LAYOUTS",
    "MACHINES",
    "MACHINE_CLASSES",
    "MACHINE_FILES",
    "SPEED_FLUCTUATION",
    "Layout",
    "layout_engine",
    "load_machine",
    "machine_by_name_or_file",
]

#: The class (a key of ``SPEED_FLUCTUATION``) of every built-in machine.
MACHINE_CLASSES: dict[str, str] = {
    "slow-compressor": "compressor",
    "boxer-compressor": "compressor",
    "marine-2t-twin": "ship propulsion",
    "slow-diesel-12": "ship propulsion",
    "inline-4": "vehicle engine",
    "inline-6": "vehicle engine",
    "genset-v12": "generator set",
}

#: The built-in machine that the command line and the report take when none is named.
DEFAULT_MACHINE_NAME = "slow-compressor"

#: The built-in machines' TOML files by name, in the order of ``MACHINES`` (docs/machine-files.md).
MACHINE_FILES: dict[str, Path] = {
    name: Path(__file__).resolve().parent / "data" / "machines" / f"{name}.toml"
    for name in (
        "slow-compressor",
        "marine-2t-twin",
        "inline-4",
        "inline-6",
        "slow-diesel-12",
        "boxer-compressor",
        "genset-v12",
    )
}


class _Machines(Mapping[str, Machine]):
    """The built-in machines by name, each read from its file on first use and kept."""

    def __init__(self, files: dict[str, Path]) -> None:
        self._files = files
        self._read: dict[str, Machine] = {}

    def __getitem__(self, name: str) -> Machine:
        if name not in self._read:
            self._read[name] = Machine.from_toml(self._files[name])
        return self._read[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._files)

    def __len__(self) -> int:
        return len(self._files)

    def __repr__(self) -> str:
        return f"<the built-in machines: {', '.join(self._files)}>"


#: The built-in machines by name (a mapping; each is read from ``MACHINE_FILES`` when first looked up).
MACHINES: Mapping[str, Machine] = _Machines(MACHINE_FILES)

#: The former names of this module's machines (a machine is a :class:`~multicrank.Machine`; an engine,
#: :class:`~multicrank.Engine`, is its dimensionless crank units at one speed), each the same
#: object as its new name, read with a DeprecationWarning.
_RENAMED = {
    "ENGINES": "MACHINES",
    "DEFAULT_ENGINE_NAME": "DEFAULT_MACHINE_NAME",
    "DEFAULT_ENGINE": "DEFAULT_MACHINE",
    "engine_by_name_or_file": "machine_by_name_or_file",
    "load_engine": "load_machine",
}


def __getattr__(name: str) -> Any:
    if name in _RENAMED:
        new = _RENAMED[name]
        warn_renamed(f"multicrank.presets.{name}", f"multicrank.presets.{new}")
        return globals()[new] if new in globals() else __getattr__(new)
    # DEFAULT_MACHINE (the slow compressor) is read on first use, as every preset is.
    if name == "DEFAULT_MACHINE":
        return MACHINES[DEFAULT_MACHINE_NAME]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def load_machine(path: str | os.PathLike[str]) -> Machine:
    """A machine from a TOML machine file: :meth:`multicrank.Machine.from_toml`.

    Parameters
    ----------
    path : str or os.PathLike
        The TOML file (docs/machine-files.md).

    Returns
    -------
    Machine
        The machine the file describes.
    """
    return Machine.from_toml(path)


def machine_by_name_or_file(spec: str | os.PathLike[str]) -> Machine:
    """A built-in machine by name (``MACHINES``), or one loaded from a TOML machine file.

    What the command line's ``--machine`` takes.

    Parameters
    ----------
    spec : str or os.PathLike
        A key of ``MACHINES``, or the path of a TOML machine file.

    Returns
    -------
    Machine
        The built-in machine, or the one the file describes.

    Raises
    ------
    MechanismError
        When ``spec`` is neither a built-in machine nor an existing file (naming both
        possibilities), or the file is not a valid machine file.

    Examples
    --------
    >>> from multicrank.presets import machine_by_name_or_file
    >>> machine = machine_by_name_or_file("inline-4")
    >>> machine.name, len(machine), machine.strokes, machine.rpm
    ('inline-4', 4, 4, 6000.0)
    """
    if isinstance(spec, str) and spec in MACHINES:
        return MACHINES[spec]
    if not isinstance(spec, str | os.PathLike):
        raise refused("machine", f"machine = {spec!r}: give a built-in machine's name or a machine file's path")
    if os.path.exists(spec):
        return load_machine(spec)
    raise refused(
        "machine",
        f"machine = {str(spec)!r} is neither a built-in machine ({', '.join(MACHINES)}) nor a machine file (TOML)",
    )
