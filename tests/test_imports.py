"""The package's import structure: no module imports the package it lives in (only
``__init__`` assembles it), and the modules import one another without a circle.

Read from the source with ``ast`` (every import counts, also those inside functions), so
a circle that only lazy imports keep from failing at run time is caught as well. Imports
under ``if TYPE_CHECKING:`` name types for the checker and never run: they do not count.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = "multicrank"
SOURCE = Path(__file__).resolve().parents[1] / "python" / PACKAGE

# Modules every other module may use: they import nothing of the package but these (_files
# makes its refusals by _validation's one way to make a MechanismError, refused).
LEAVES = {
    "_validation": {"_native"},
    "_optional": set(),
    "_files": {"_native", "_validation"},
    "_inertia_torque": set(),
    "_broadcasting": {"_validation"},
}


def module_name(path: Path, source: Path) -> str:
    """The dotted name of a file of the package, relative to it: ``gravity.engines``; a
    subpackage's ``__init__`` is named by its package (``gravity``), the package's own by
    ``__init__``."""
    parts = path.relative_to(source).with_suffix("").parts
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts) or "__init__"


def module_imports(path: Path, source: Path) -> tuple[set[str], list[str]]:
    """(the package's modules and subpackages that ``path`` imports, its imports of a
    package: the package itself, or — outside an ``__init__`` — a subpackage, whose names
    are to be imported from their modules)."""
    package = source.name
    is_init = path.stem in ("__init__", "__main__")  # they assemble the package
    here = path.relative_to(source).parent.parts  # the package the file's relative imports start from
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and ast.unparse(node.test) in ("TYPE_CHECKING", "typing.TYPE_CHECKING"):
            node.body = []  # for the checker only
    uses: set[str] = set()
    own: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == package or alias.name.startswith(package + "."):
                    own.append(f"line {node.lineno}: import {alias.name}")
        elif isinstance(node, ast.ImportFrom):
            names = ", ".join(alias.name for alias in node.names)
            written = f"line {node.lineno}: from {'.' * node.level}{node.module or ''} import {names}"
            if node.level == 0:
                if node.module == package or (node.module or "").startswith(package + "."):
                    own.append(f"line {node.lineno}: from {node.module} import {names}")
                continue
            if node.level - 1 > len(here):
                own.append(written + " (beyond the package)")
                continue
            base = here[: len(here) - (node.level - 1)]
            if node.module:
                targets = [".".join((*base, node.module))]
            else:
                targets = [".".join((*base, alias.name)) for alias in node.names]
            is_package = [not t or (source / t.replace(".", "/") / "__init__.py").exists() for t in targets]
            if not is_init and (node.module is None or any(is_package)):
                own.append(written)
            uses.update(targets)
    return uses, own


def import_graph(source: Path) -> tuple[dict[str, set[str]], dict[str, list[str]]]:
    """The package's modules → the modules they import, and each module's self-imports."""
    paths = {module_name(path, source): path for path in sorted(source.rglob("*.py"))}
    graph, violations = {}, {}
    for name, path in paths.items():
        uses, own = module_imports(path, source)
        graph[name] = {u for u in uses if u in paths or u == "_native"}
        if own:
            violations[name] = own
    return graph, violations


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One import circle as [a, b, …, a], or None."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return [*path[path.index(nxt) :], nxt]
            if nxt not in state and (cycle := visit(nxt)):
                return cycle
        path.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state and (cycle := visit(node)):
            return cycle
    return None


def test_no_module_imports_its_own_package():
    _, violations = import_graph(SOURCE)
    assert not violations, f"modules that import {PACKAGE} itself (import the names from their modules): {violations}"


def test_no_import_cycle():
    graph, _ = import_graph(SOURCE)
    assert len(graph) > 10, f"no package source at {SOURCE}"
    assert find_cycle(graph) is None, f"import circle: {' -> '.join(find_cycle(graph) or [])}"


@pytest.mark.parametrize("leaf", sorted(LEAVES))
def test_leaf_modules_depend_on_nothing_else(leaf):
    graph, _ = import_graph(SOURCE)
    assert graph[leaf] <= LEAVES[leaf], f"{leaf} imports {sorted(graph[leaf] - LEAVES[leaf])}"


def test_the_checks_catch_a_circle_and_a_self_import(tmp_path):
    """The checks above can fail: a package with both faults is caught."""
    bad = tmp_path / "badpkg"
    bad.mkdir()
    (bad / "__init__.py").write_text("from .a import f\n")
    (bad / "a.py").write_text("from .b import g\n\ndef f():\n    return g()\n")
    (bad / "b.py").write_text("def g():\n    from .a import f\n    return f\n")
    (bad / "c.py").write_text("from . import a\nimport badpkg.b\n")
    (bad / "d.py").write_text("from badpkg import a\n")
    graph, violations = import_graph(bad)
    assert find_cycle(graph) == ["a", "b", "a"]
    assert sorted(violations) == ["c", "d"] and len(violations["c"]) == 2
    (bad / "b.py").write_text("def g():\n    return 1\n")
    assert find_cycle(import_graph(bad)[0]) is None
    # In a subpackage: a module imports its sibling's module, not the subpackage; relative
    # imports that go up resolve to the modules they name.
    sub = bad / "sub"
    sub.mkdir()
    (sub / "__init__.py").write_text("from .e import h\n")
    (sub / "e.py").write_text("from ..a import f\n\ndef h():\n    return f()\n")
    (bad / "b.py").write_text("def g():\n    from .sub.e import h\n    return h\n")
    graph, violations = import_graph(bad)
    assert graph["sub.e"] == {"a"} and graph["sub"] == {"sub.e"}
    assert find_cycle(graph) == ["a", "b", "sub.e", "a"]
    (bad / "b.py").write_text("def g():\n    from .sub import h\n    return h\n")
    assert "b" in import_graph(bad)[1]
    # A type named for the checker only is no import.
    (bad / "b.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .a import f\n")
    assert import_graph(bad)[0]["b"] == set()
