"""``multicrank sweep`` (python/multicrank/cli/sweep.py): its axes are the DesignGrid's.

One name per idea (issue 27, item 7): the names of a design's columns are written once, in
multicrank.sweeps.designs; the command's axes, its options and its --config's [axes] follow.
"""

from __future__ import annotations

import click
import pytest
from click.testing import CliRunner

import multicrank as mc
import multicrank.sweeps.designs as designs
from multicrank import cli
from multicrank.cli.sweep import design_axes, sweep_command


def test_the_commands_axes_are_the_design_grids_columns():
    axes = design_axes()
    assert tuple(axes) == mc.DesignGrid.KNOWN == designs.KNOWN_COLUMNS
    assert all(column == name for name, (column, _) in axes.items())
    # the kinds the command parses: reals, γ in degrees, integer counts, the acting a word
    assert {name: kind for name, (_, kind) in axes.items()} == {
        "crank_ratio": float,
        "inclination": "degrees",
        "u1": float,
        "u2": float,
        "cranks": int,
        "strokes": int,
        "acting": str,
    }
    options = {p.name for p in sweep_command.params if isinstance(p, click.Option) and p.metavar == "AXIS"}
    assert options == set(axes)


def test_a_column_added_to_the_designs_is_an_axis_of_the_command(monkeypatch):
    """The axes are read from the designs module, not written out again."""
    monkeypatch.setattr(designs, "OPTIONAL_COLUMNS", {**designs.OPTIONAL_COLUMNS, "banks": 1})
    monkeypatch.setattr(designs, "KNOWN_COLUMNS", (*designs.KNOWN_COLUMNS, "banks"))
    assert design_axes()["banks"] == ("banks", int)


@pytest.mark.parametrize("missing", ["crank_ratio", "inclination", "u1"])
def test_a_missing_design_column_is_named(tmp_path, missing):
    given = {"crank_ratio": "0.3", "inclination": "90", "u1": "0.1"}
    del given[missing]
    args = [f"--{name.replace('_', '-')}={value}" for name, value in given.items()]
    result = CliRunner().invoke(cli.main, ["sweep", *args, "--out", str(tmp_path / "s.parquet"), "--no-progress"])
    assert result.exit_code == 2
    assert f"missing axes: {missing}" in result.output
