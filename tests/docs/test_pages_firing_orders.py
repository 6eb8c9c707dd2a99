"""docs/machine-files.md says how the in-line layouts fire: every firing order it names, and its
rule for the in-line layouts that are not the textbook cranks (1-k-…-2), are those that
``mc.firing_orders`` reports for a machine built from the layout."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import multicrank as mc
from multicrank.gravity.layouts import TEXTBOOK_FIRING

PAGE = Path(__file__).resolve().parents[2] / "docs" / "machine-files.md"
# "`inline-6-2t` 1-6-5-4-3-2", or "`inline-3-2t` and `inline-3-4t` fire 1-3-2".
NAMED = re.compile(r"((?:`inline-\d+-[24]t`(?:,| and)?\s+)+)(?:fire\s+)?(\d+(?:-\d+)+)")
INLINE = [name for name in mc.LAYOUTS if name.startswith("inline-")]


def text() -> str:
    return re.sub(r"\s+", " ", PAGE.read_text(encoding="utf-8"))


def firing(layout: str) -> str:
    """The firing order ``mc.firing_orders`` gives a machine of the layout as it is built."""
    cylinder = mc.Cylinder(crank_radius=0.05, rod_length=0.2, piston_mass=1.0, rod_mass=1.0, rod_cg=0.1)
    machine = mc.Machine.from_layout(layout, cylinder, shaft_inertia=1.0, rpm=1500.0)
    table = mc.firing_orders(machine, max_candidates=1)
    (given,) = table.loc[table["as_given"], "firing"]
    return str(given)


def named() -> dict[str, str]:
    """Every in-line layout the page names with a firing order, and that order."""
    found: dict[str, str] = {}
    for match in NAMED.finditer(text()):
        for layout in re.findall(r"`(inline-\d+-[24]t)`", match[1]):
            found[layout] = match[2]
    return found


def test_the_page_names_firing_orders_of_both_kinds_of_in_line_layout():
    orders = named()
    assert {f"inline-{k}-4t" for k in TEXTBOOK_FIRING} <= set(orders)
    assert {"inline-3-4t", "inline-6-2t"} <= set(orders)  # the two


@pytest.mark.parametrize("layout", sorted(named()))
def test_every_firing_order_the_page_names_is_the_librarys(layout):
    assert firing(layout) == named()[layout]


@pytest.mark.parametrize("layout", INLINE)
def test_the_other_in_line_layouts_fire_as_the_page_says(layout):
    """The page's rule, 1-k-…-2 for every in-line layout but the textbook cranks, and never
    the former claim that their cylinders are listed in firing order."""
    page = text()
    assert "in firing order" not in page
    assert "1-k-…-2" in page
    cylinders = mc.LAYOUTS[layout].cylinders
    if layout.endswith("-4t") and cylinders in TEXTBOOK_FIRING:
        expected = "-".join(map(str, TEXTBOOK_FIRING[cylinders]))
    else:
        expected = "-".join(map(str, [1, *range(cylinders, 1, -1)]))
    assert firing(layout) == expected
