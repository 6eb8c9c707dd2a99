"""The Rust core's rooms import one another without a circle (issue 37, item 1).

A room is a top-level module of ``rust/core/src`` (a file, or a folder with its ``mod.rs``);
within ``motion/`` each file is a room of its own, its ``mod.rs`` (the entries and the types
they share) apart. An arrow is any path into another room (``crate::forces::…``, or
``super::tables::…`` within motion) outside comments and test code. A circle means two rooms
that cannot be understood, or moved, one without the other.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from .test_imports import find_cycle

CORE = Path(__file__).resolve().parent.parent / "rust" / "core" / "src"
pytestmark = pytest.mark.skipif(not CORE.is_dir(), reason="the Rust sources are not beside the tests")


def code_of(path: Path) -> str:
    """A source file without its comments and its test code (what follows ``#[cfg(test)]``)."""
    text = path.read_text().split("#[cfg(test)]")[0]
    return re.sub(r"//[^\n]*", "", text)


def rooms(folder: Path) -> dict[str, list[Path]]:
    """The rooms of ``folder`` by name and their source files: each .rs file (``mod``, ``lib``
    and ``tests`` apart) with the folder of its name, if any (``gas.rs`` and ``gas/``), and
    each folder (``forces/``), test files left out."""
    found: dict[str, list[Path]] = {}
    for path in folder.iterdir():
        if path.is_dir():
            found.setdefault(path.name, []).extend(p for p in path.rglob("*.rs") if p.name != "tests.rs")
        elif path.suffix == ".rs" and path.stem not in {"lib", "mod", "tests"}:
            found.setdefault(path.stem, []).append(path)
    return found


def graph(folder: Path, prefix: str) -> dict[str, set[str]]:
    """Arrows between the rooms of ``folder``: a path that starts with ``prefix`` and a room."""
    named = rooms(folder)
    arrows: dict[str, set[str]] = {name: set() for name in named}
    single, grouped = re.compile(rf"{prefix}(\w+)"), re.compile(rf"{prefix}\{{([^}}]*)\}}")
    for name, files in named.items():
        for path in files:
            code = code_of(path)
            targets = single.findall(code)
            for group in grouped.findall(code):  # use super::{a, b::C, D}
                targets += [item.strip().split("::")[0] for item in group.split(",")]
            arrows[name].update(t for t in targets if t in named and t != name)
    return arrows


def test_the_core_s_rooms_have_no_circle():
    arrows = graph(CORE, r"crate::")
    assert arrows["motion"] and arrows["machine"], "the check reads the sources"
    cycle = find_cycle(arrows)
    assert cycle is None, f"core rooms in a circle: {' -> '.join(cycle or [])}"


def test_the_motion_room_s_files_have_no_circle():
    arrows = graph(CORE / "motion", r"super::")
    # Within a submodule's own folder (motion/gas/work.rs) super:: is that submodule.
    assert arrows["tables"], "the check reads the sources"
    cycle = find_cycle(arrows)
    assert cycle is None, f"motion's files in a circle: {' -> '.join(cycle or [])}"


def test_the_check_finds_a_circle(tmp_path):
    sources = {"a.rs": "use crate::b::X;", "b.rs": "fn f() { crate::a::y() }", "c.rs": "// crate::a", "d.rs": ""}
    sources["d.rs"] = "use crate::{c::Z, b};"
    for name, body in sources.items():
        (tmp_path / name).write_text(body)
    arrows = graph(tmp_path, r"crate::")
    assert arrows == {"a": {"b"}, "b": {"a"}, "c": set(), "d": {"b", "c"}}
    assert find_cycle(arrows) is not None
