"""The package's rooms and their order (issue 37, item 5; CONTRIBUTING.md, "The layout"): a module
imports its own room and the rooms below it, never one above — the machine knows nothing of
the questions asked of it, and the torsional questions, the design aid, the report and the
command line sit on top of the machine and its motion.

Read from the source with ``ast``; every import counts, also those inside functions (a lazy
import is an arrow too, taken later), except the few named delegations in :data:`DELEGATIONS`,
each a method of a lower room that hands its work to a room above when it is called. Imports
under ``if TYPE_CHECKING:`` name types for the checker and never run: they do not count.
tests/test_imports.py holds the rest of the import structure (no circle, no self-import, what
the leaf modules may use).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from .test_imports import SOURCE, module_name

#: The rooms from the bottom up: a room may import the rooms on the levels below its own. The
#: first level is the leaves, which import nothing above it (tests/test_imports.py says what each
#: of them may take from the others); two rooms on any other level do not import each other.
LEVELS: tuple[tuple[str, ...], ...] = (
    ("_native", "_validation", "_broadcasting", "_optional", "_files", "_text", "_inertia_torque", "_moved"),
    ("gravity", "reference"),  # the dimensionless mechanism, and its plain-numpy oracle
    ("pressure", "symbolic"),  # indicator diagrams; the SymPy hand-off of gravity's terms
    ("sweeps",),  # design grids, the driver and the store (motion sweeps use the store)
    ("machine",),  # the physical machine: cylinders, the shaft, throws and bearings, files
    ("presets",),  # the built-in machines
    ("motion",),  # the steady state, flywheel, transients, torque orders, motion sweeps
    ("forces",),  # shaking forces, bearing loads
    ("torsion",),  # the chain's modes, each cylinder's excitation, merit, openTorsion hand-off
    ("design",),  # firing orders, counterweights
    ("report",),
    ("cli",),
    ("__init__", "__main__"),  # they assemble the package
)

#: (module, the module it imports inside a function) -> why that arrow up is a delegation.
DELEGATIONS = {
    ("machine.shaft", "torsion._chain"): (
        "Shaft.modes: the chain's modes are the torsion room's mathematics (the core's torsion room "
        "when it has them); the machine part asks it when called"
    ),
}


def room_of(module: str) -> str:
    """The room of a module's dotted name (``motion.orders`` -> ``motion``)."""
    return module.split(".")[0]


def imports(path: Path, source: Path) -> list[tuple[str, int, bool]]:
    """(the module or package of ``source`` imported, its line, whether inside a function) of
    each import of the package in ``path``, without those under ``if TYPE_CHECKING:``."""
    own = source.name + "."
    here = path.relative_to(source).parent.parts
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and ast.unparse(node.test) in ("TYPE_CHECKING", "typing.TYPE_CHECKING"):
            node.body = []
    inside = {
        id(inner)
        for node in ast.walk(tree)
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda)
        for inner in ast.walk(node)
    }
    found = []
    for node in ast.walk(tree):
        targets: list[str] = []
        if isinstance(node, ast.Import):
            targets = [alias.name.removeprefix(own) for alias in node.names if alias.name.startswith(own)]
        elif isinstance(node, ast.ImportFrom):
            if node.level == 0:
                if (node.module or "").startswith(own):
                    targets = [(node.module or "").removeprefix(own)]
            else:
                base = here[: len(here) - (node.level - 1)]
                if node.module:
                    targets = [".".join((*base, node.module))]
                else:
                    targets = [".".join((*base, alias.name)) for alias in node.names]
        found += [(target, node.lineno, id(node) in inside) for target in targets if target]
    return found


def arrows_up(source: Path, levels: tuple[tuple[str, ...], ...], allowed: dict) -> tuple[list[str], set[str]]:
    """(each import of a room by a room not above it, as 'module -> module (line n)'; the
    rooms of ``source`` that ``levels`` does not place). A delegation in ``allowed`` (a lazy
    import, named by its two modules) is no fault; what the leaves (the first level) take from
    one another is left to tests/test_imports.py."""
    level = {room: height for height, rooms in enumerate(levels) for room in rooms}
    faults, unplaced = [], set()
    for path in sorted(source.rglob("*.py")):
        module = module_name(path, source)
        here = room_of(module)
        if here not in level:
            unplaced.add(here)
            continue
        for target, line, lazy in imports(path, source):
            there = room_of(target)
            if there not in level:
                unplaced.add(there)
            elif there != here and level[there] >= level[here] and level[there] > 0:
                if not (lazy and (module, target) in allowed):
                    faults.append(f"{module} -> {target} (line {line}{', inside a function' if lazy else ''})")
    return faults, unplaced


def test_every_room_has_its_place():
    _, unplaced = arrows_up(SOURCE, LEVELS, DELEGATIONS)
    assert not unplaced, f"rooms not in tests/test_rooms.py's LEVELS (give each its level): {sorted(unplaced)}"


def test_no_room_imports_a_room_above_it():
    faults, _ = arrows_up(SOURCE, LEVELS, DELEGATIONS)
    assert not faults, "imports of a room above the importer's (move the code, or ask the room above lazily "
    f"and name the delegation in DELEGATIONS): {faults}"


@pytest.mark.parametrize("arrow", sorted(DELEGATIONS))
def test_each_delegation_is_a_lazy_import_that_exists(arrow):
    """A delegation no code makes any more is taken off the list (and one made at load time is
    no delegation)."""
    module, target = arrow
    path = SOURCE / (module.replace(".", "/") + ".py")
    assert [lazy for found, _, lazy in imports(path, SOURCE) if found == target] == [True]


def test_the_check_catches_an_arrow_up(tmp_path):
    """The check can fail: a low room that imports a high one, at load time or inside a function,
    is caught; a named delegation and an import for the type checker are not; a new room is
    named."""
    bad = tmp_path / "badpkg"
    for folder in (bad, bad / "low", bad / "high"):
        folder.mkdir()
        (folder / "__init__.py").write_text("")
    (bad / "_leaf.py").write_text("def g():\n    from .low import part\n")
    (bad / "_other.py").write_text("from ._leaf import g\n")
    (bad / "high" / "top.py").write_text("from ..low import part\nfrom .._leaf import x\n")
    (bad / "low" / "part.py").write_text("from ..high.top import y\n")
    (bad / "low" / "later.py").write_text("def f():\n    from ..high import top\n")
    (bad / "low" / "typed.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from ..high.top import y\n"
    )
    (bad / "low" / "asks.py").write_text("def f():\n    import badpkg.high.top\n")
    levels = (("_leaf", "_other"), ("low",), ("high",), ("__init__",))
    faults, unplaced = arrows_up(bad, levels, {("low.asks", "high.top"): "a delegation"})
    assert faults == [
        "_leaf -> low (line 2, inside a function)",
        "low.later -> high (line 2, inside a function)",
        "low.part -> high.top (line 1)",
    ]
    assert not unplaced
    (bad / "side.py").write_text("from .low import part\n")
    assert arrows_up(bad, levels, {})[1] == {"side"}
    # Two rooms on one level do not import each other.
    same = arrows_up(bad, (("_leaf", "_other"), ("low", "high"), ("__init__", "side")), {("low.asks", "high.top"): ""})
    assert "high.top -> low (line 1)" in same[0]
