"""One name per idea, written down (issue 27, item 7): docs/glossary.md names every public
quantity — every attribute of the motion results and of the counterweight optimum, every output
column of ``mc.sweep`` and ``mc.motion_sweep``, every design column — and every name it gives
exists in the package (no stale entry).
"""

from __future__ import annotations

import dataclasses
import inspect
import re
from pathlib import Path

import pytest

import multicrank as mc
from multicrank._validation import renamed
from multicrank.design.criteria import RANKINGS
from multicrank.forces.shaking import COMPONENTS as CURVE_COLUMNS
from multicrank.motion.variants import machine_columns
from multicrank.report.settings import ReportSettings
from multicrank.sweeps.designs import KNOWN_COLUMNS
from multicrank.sweeps.outputs import SWEEP_OUTPUTS
from multicrank.torsion.merit import MERIT_UNITS

GLOSSARY = Path(__file__).resolve().parents[2] / "docs" / "glossary.md"
RESULTS = (mc.SteadyState, mc.FlywheelInertia, mc.Transient, mc.CounterweightOptimum, mc.ShakingForces, mc.BearingLoads)
# The section of names kept for one release, which need not be current names.
DEPRECATED = "## Names of 0.1, deprecated"


def glossary_names() -> set[str]:
    """The names in the first column of the glossary's tables (a cell may hold several)."""
    text = GLOSSARY.read_text(encoding="utf-8").split(DEPRECATED)[0]
    names: set[str] = set()
    for line in text.splitlines():
        cells = line.split("|")
        if line.startswith("|") and len(cells) > 2:
            names |= set(re.findall(r"`([^`]+)`", cells[1]))
    return names


def public_attributes(cls: type) -> set[str]:
    """A result's public attributes: its fields and properties, not its methods, its class
    tables (COLUMNS, NUMBERS) or the deprecated names of 0.1."""
    names = {f.name for f in dataclasses.fields(cls) if not f.name.startswith("_")}  # type: ignore[arg-type]
    for name in dir(cls):
        if name.startswith("_") or name.isupper():
            continue
        if isinstance(inspect.getattr_static(cls, name), property):
            names.add(name)
    return names


def as_entry(column: str) -> str:
    """A per-cylinder column (``phase[0]``) under its glossary name (``phase[j]``)."""
    return re.sub(r"\[\d+\]$", "[j]", column)


def required() -> dict[str, set[str]]:
    """Where each public name comes from → the names."""
    machine = mc.presets.MACHINES["slow-compressor"]
    return {
        **{cls.__name__: public_attributes(cls) for cls in RESULTS},
        "mc.motion_sweep outputs": set(mc.MOTION_SWEEP_OUTPUTS),
        "mc.sweep outputs": set(SWEEP_OUTPUTS),
        "DesignGrid columns": set(KNOWN_COLUMNS),
        "MachineGrid columns": {as_entry(c) for c in machine_columns(machine)},
        "ShakingForces.orders columns": set(mc.ShakingForces.COLUMNS),
        "ShakingForces.curves columns": set(CURVE_COLUMNS),
        "BearingLoads.summary columns": set(mc.bearing_loads(machine).summary.columns),
        "torsional_merit columns": set(MERIT_UNITS),
        "firing_orders criteria": {*RANKINGS, "pareto"},
    }


def existing() -> set[str]:
    """Every name the package has for a quantity: the required ones, the fields and properties
    of the public value classes, and the keywords of the public functions."""
    names = set().union(*required().values())
    machine = mc.presets.MACHINES["slow-compressor"]
    for value in (machine, machine.cylinders[0], mc.PowerLawLoad(1.0, rpm=60.0)):
        for name in dir(value):
            if name.startswith("_") or isinstance(inspect.getattr_static(type(value), name, None), renamed):
                continue
            if not callable(getattr(value, name)):
                names.add(name)
    for name in mc.__all__:
        value = getattr(mc, name)
        if callable(value) and not inspect.isclass(value):
            names |= set(inspect.signature(value).parameters)
    names |= set(inspect.signature(mc.Machine.from_layout).parameters)  # cylinder_spacing
    return names


@pytest.mark.parametrize("source", list(required()))
def test_every_public_name_is_in_the_glossary(source):
    missing = required()[source] - glossary_names()
    assert not missing, f"add to docs/glossary.md ({source}): {sorted(missing)}"


def test_every_glossary_entry_exists():
    stale = glossary_names() - existing()
    assert not stale, f"docs/glossary.md names what the package does not have: {sorted(stale)}"


def test_the_deprecated_names_are_deprecated():
    """The results' names of 0.1 are `renamed` aliases, kept out of the glossary's entries."""
    aliases = {
        f"{cls.__name__}.{name}"
        for cls in RESULTS
        for name in dir(cls)
        if isinstance(inspect.getattr_static(cls, name, None), renamed)
    }
    assert {"Transient.rpm", "SteadyState.J", "SteadyState.dJ_dphi"} <= aliases
    for alias in aliases:
        cls_name, name = alias.split(".")
        assert name not in public_attributes(getattr(mc, cls_name))


def deprecated_attributes() -> set[str]:
    """The ``Class.name`` entries of the glossary's table of names of 0.1 (first column)."""
    text = GLOSSARY.read_text(encoding="utf-8").split(DEPRECATED)[1]
    names: set[str] = set()
    for line in text.splitlines():
        cells = line.split("|")
        if line.startswith("|") and len(cells) > 2:
            names |= set(re.findall(r"`([A-Z]\w*\.\w+)`", cells[1]))
    return names


def test_the_glossarys_deprecated_attributes_are_renamed_aliases():
    """Every ``Class.name`` the glossary lists as a name of 0.1 is a `renamed` alias of that
    public class (so it warns), and the report's δ target is among them."""
    classes = {name: getattr(mc, name) for name in mc.__all__} | {"ReportSettings": ReportSettings}
    found = deprecated_attributes()
    assert {"ReportSettings.delta", "SteadyState.J", "Transient.rpm"} <= found
    for entry in found:
        cls_name, name = entry.split(".")
        assert isinstance(inspect.getattr_static(classes[cls_name], name, None), renamed), entry


def test_the_glossary_is_in_the_docs_toctree():
    index = (GLOSSARY.parent / "index.md").read_text(encoding="utf-8")
    toctree = index.split("```{toctree}")[1].split("```")[0]
    assert "glossary" in toctree.split()
