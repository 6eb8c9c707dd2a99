"""`multicrank forces` through click's CliRunner: each format, a preset and a machine file,
--steady, --out, and mistakes as one line with exit status 2.

The command only shapes :func:`multicrank.shaking_forces`'s table (its physics is tested
against an independent oracle in tests/forces/test_shaking.py), so its numbers are checked
against that function; the textbook facts of an in-line four are checked on what it prints.
"""

from __future__ import annotations

import io
import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import multicrank as mc
from multicrank import cli
from multicrank.forces.shaking import ShakingForces

SHOWN = ("force_vertical", "force_horizontal", "force_forward", "force_backward", "moment_pitch", "moment_yaw")

SPACING = 0.09  # m, throw to throw

# An in-line four placed along the shaft: the textbook crank 0-180-180-0 from the front.
INLINE_FOUR = f"""
name = "four"
layout = "inline-4-4t"
shaft_inertia = 0.2
cylinder_spacing = {SPACING}
rpm = 4000.0

[cylinder]
crank_radius = 0.04
rod_length = 0.14
rod_cg = 0.1
piston_mass = 0.5
rod_mass = 0.6
crank_mass = 1.2
crank_cg_radius = 0.03
counterweight_mass = 1.0
counterweight_radius = 0.035
"""


def invoke(*args: str) -> str:
    result = CliRunner().invoke(cli.main, ["forces", *args])
    assert result.exit_code == 0, result.output
    return result.stdout


def refused(*args: str) -> str:
    """The refusal as its one line: exit status 2, no traceback."""
    result = CliRunner().invoke(cli.main, ["forces", *args])
    assert result.exit_code == 2, result.output
    assert isinstance(result.exception, SystemExit) and "Traceback" not in result.output
    (line,) = result.output.strip().splitlines()
    return line


def printed_table(text: str) -> pd.DataFrame:
    """The table of the text format, read back: the rows after the line ``order`` up to the
    first empty line, by the column names of the header."""
    lines = text.splitlines()
    header = next(n for n, line in enumerate(lines) if line.split()[:2] == ["force_vertical", "[N]"])
    names = [word for word in lines[header].split() if not word.startswith("[")]
    assert lines[header + 1].split() == ["order"]
    rows = []
    for line in lines[header + 2 :]:
        if not line.strip():
            break
        rows.append([float(word) for word in line.split()])
    values = np.array(rows)
    return pd.DataFrame(values[:, 1:], index=pd.Index(values[:, 0], name="order"), columns=names)


@pytest.fixture
def four_file(tmp_path):
    path = tmp_path / "four.toml"
    path.write_text(INLINE_FOUR, encoding="utf-8")
    return path


def test_the_table_of_a_preset_is_the_libraries_to_four_digits():
    machine = mc.presets.MACHINES["slow-compressor"]
    text = invoke("--machine", "slow-compressor", "--rpm", "100", "--max-order", "4")
    lines = text.splitlines()
    assert lines[0].startswith("slow-compressor: ") and "constant speed 100 rpm" in lines[0]
    table = printed_table(text)
    expected = mc.shaking_forces(machine, 100, max_order=4).orders
    assert list(table.columns) == list(SHOWN)
    assert list(table.index) == [1.0, 2.0, 3.0, 4.0]
    for name in SHOWN:
        np.testing.assert_allclose(table[name], expected[name], rtol=5e-4, atol=0, err_msg=name)
    # the units in the header, and the line on what counterweights can cancel, with the
    # forward first order of this machine
    assert "force_vertical [N]" in text and "moment_pitch [N·m]" in text
    below = next(" ".join(part.split()) for part in text.split("\n\n") if part.startswith("counterweights"))
    assert below.startswith("counterweights turn with the crank: they can cancel only the forward first order")
    assert f"{expected.loc[1, 'force_forward']:.4g} N" in below and "balance shafts" in below


def test_the_machines_own_speed_by_default():
    machine = mc.presets.MACHINES["inline-4"]
    text = invoke("--machine", "inline-4", "--max-order", "2")
    assert f"constant speed {machine.rpm:g} rpm" in text.splitlines()[0]
    table = printed_table(text)
    expected = mc.shaking_forces(machine, max_order=2).orders
    np.testing.assert_allclose(table["force_vertical"], expected["force_vertical"], rtol=5e-4)


def test_an_inline_four_from_a_file_has_no_first_order_and_its_second_at_the_middle(four_file):
    """Textbook facts on the printed table: the crank 0-180-180-0 along the shaft cancels every
    first-order force and couple (and every odd order); its second-order forces are in phase,
    so their resultant acts at the middle of the crank, 1.5 spacings from the front — the
    engine centre the moments are taken about, so its moment is 0 — and is vertical (upright
    cylinders)."""
    table = printed_table(invoke("--machine", str(four_file), "--max-order", "6"))
    for odd in (1.0, 3.0, 5.0):
        assert (table.loc[odd] == 0).all(), table.loc[odd]
    assert table.loc[2.0, "force_vertical"] > 0 and table.loc[2.0, "force_horizontal"] == 0
    assert table.loc[2.0, "moment_yaw"] == 0
    assert table.loc[2.0, "moment_pitch"] == 0
    # a line's order: half turns with the crank, half against it
    assert table.loc[2.0, "force_forward"] == table.loc[2.0, "force_backward"]
    assert table.loc[2.0, "force_forward"] == pytest.approx(table.loc[2.0, "force_vertical"] / 2, rel=1e-3)


def test_csv_is_every_column_of_the_libraries_orders(four_file):
    out = invoke("--machine", str(four_file), "--rpm", "2500", "--max-order", "8", "--format", "csv")
    frame = pd.read_csv(io.StringIO(out), index_col="order")
    expected = mc.shaking_forces(mc.Machine.from_toml(four_file), 2500, max_order=8).orders
    assert list(frame.columns) == list(ShakingForces.COLUMNS)
    assert list(frame.index) == list(expected.index)
    np.testing.assert_allclose(frame.to_numpy(), expected.to_numpy(), rtol=1e-11, atol=1e-9)
    assert (frame.loc[1, ["force_vertical", "force_forward", "moment_pitch", "moment_forward"]] == 0).all()


def test_json_holds_the_rows_and_the_speed_and_units_steady():
    machine = mc.presets.MACHINES["inline-4"]
    out = invoke("--machine", "inline-4", "--rpm", "1000", "--max-order", "3", "--steady", "--format", "json")
    data = json.loads(out)
    expected = mc.shaking_forces(machine, 1000, max_order=3, steady=True)
    assert data["machine"] == "inline-4" and data["steady"] is True and data["max_order"] == 3
    assert data["rpm"] == pytest.approx(1000) and data["omega"] == pytest.approx(1000 * math.pi / 30)
    assert data["units"]["force_vertical"] == "N" and data["units"]["moment_pitch"] == "N·m"
    assert data["units"]["force_vertical_phase"] == "rad"
    rows = pd.DataFrame(data["rows"]).set_index("order")
    # four-stroke steady running repeats once per working cycle: half orders
    assert list(rows.index) == [0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
    assert list(rows.columns) == list(ShakingForces.COLUMNS)
    np.testing.assert_allclose(rows.to_numpy(), expected.orders.to_numpy(), rtol=1e-13, atol=1e-12)
    # and the steady running is not the constant speed's
    constant = mc.shaking_forces(machine, 1000, max_order=3).orders
    assert rows.loc[2.0, "force_vertical"] != constant.loc[2.0, "force_vertical"]


def test_steady_text_says_so_and_lists_half_orders():
    text = invoke("--machine", "inline-4", "--rpm", "1000", "--max-order", "2", "--steady")
    assert "steady running at a mean 1000 rpm" in text.splitlines()[0]
    assert list(printed_table(text).index) == [0.5, 1.0, 1.5, 2.0]


def test_out_writes_the_file(tmp_path):
    target = tmp_path / "orders.json"
    result = CliRunner().invoke(
        cli.main, ["forces", "--machine", "marine-2t-twin", "--format", "json", "--out", str(target)]
    )
    assert result.exit_code == 0, result.output
    assert result.stdout == "" and f"written: {target}" in result.stderr
    data = json.loads(target.read_text(encoding="utf-8"))
    assert len(data["rows"]) == 12 and data["steady"] is False


def test_an_unplaced_machine_is_said_to_have_no_moments():
    """The documentation's V8 file gives no cylinder_spacing, so its cylinders stay at z = 0:
    the moments are 0, and the text says why; a placed machine has no such note."""
    v8 = Path(__file__).resolve().parents[2] / "docs" / "machines" / "v8-cross.toml"
    assert "none placed along the shaft" in invoke("--machine", str(v8), "--max-order", "2")
    assert "none placed along the shaft" not in invoke("--machine", "inline-4", "--max-order", "2")


@pytest.mark.parametrize(
    ("args", "named"),
    [
        (["--machine", "steam-hammer"], "--machine"),
        (["--rpm", "0"], "--rpm"),
        (["--rpm", "-100"], "--rpm"),
        (["--rpm", "nan"], "--rpm"),
        (["--max-order", "0"], "--max-order"),
        (["--max-order", "5000"], "--max-order"),
        (["--max-order", "400", "--steady"], "--max-order"),
    ],
)
def test_mistakes_are_one_line_naming_the_option(args, named):
    line = refused(*args)
    assert line.startswith("Error: ") and named in line
    if named == "--max-order":
        assert line.endswith("<= 2048" if "--steady" not in args else "<= 360")


def test_a_machine_without_a_speed_asks_for_rpm(tmp_path):
    path = tmp_path / "no-speed.toml"
    path.write_text(INLINE_FOUR.replace("rpm = 4000.0\n", ""), encoding="utf-8")
    line = refused("--machine", str(path))
    assert "no running speed" in line and "--rpm" in line
    assert printed_table(invoke("--machine", str(path), "--rpm", "3000", "--max-order", "2")).loc[1.0].eq(0).all()


def test_the_main_bearings_are_summed_up_below_the_orders():
    """The bearing lines are mc.bearing_loads' summary at the same speed (the physics is
    tested in tests/forces): one line per bearing, and json's bearings records."""
    machine = mc.presets.MACHINES["boxer-compressor"]
    summary = mc.bearing_loads(machine).summary
    table = CliRunner().invoke(cli.main, ["forces", "--machine", "boxer-compressor"])
    assert table.exit_code == 0, table.output
    lines = table.output.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("main bearings"))
    rows = lines[start + 2 : start + 2 + len(summary)]
    for (index, row), line in zip(summary.iterrows(), rows, strict=True):
        cells = line.split()
        assert int(cells[0]) == index and float(cells[2]) == pytest.approx(row["max"], rel=1e-3)
    as_json = CliRunner().invoke(cli.main, ["forces", "--machine", "boxer-compressor", "--format", "json"])
    records = json.loads(as_json.output)["bearings"]
    assert [r["max"] for r in records] == pytest.approx(list(summary["max"]), rel=1e-12)


def notations(lines: list[str]) -> list[set[str]]:
    """For each whitespace-separated column of ``lines``, the notations its numbers are
    written in: "exponent" (8.726e+03) or "fixed" (8726, 0.0925); 0 counts as either."""
    columns: list[set[str]] = []
    for line in lines:
        for i, cell in enumerate(line.split()):
            while len(columns) <= i:
                columns.append(set())
            if cell != "0":
                float(cell)  # a number
                columns[i].add("exponent" if "e" in cell else "fixed")
    return columns


@pytest.mark.parametrize("machine", ["slow-compressor", "slow-diesel-12", "inline-6", "boxer-compressor"])
def test_every_column_of_the_tables_to_read_is_in_one_notation(machine):
    """The orders' table and the bearings' lines: a column is fixed, with 4 significant digits,
    or, where one of its numbers needs an exponent, all with an exponent — never 8726 above
    1.139e+04 (the slow compressor's bearings and orders, the slow diesel's moments did)."""
    text = invoke("--machine", machine)
    lines = text.splitlines()
    header = next(n for n, line in enumerate(lines) if line.split()[:2] == ["force_vertical", "[N]"])
    orders = lines[header + 2 : lines.index("", header)]
    start = next(i for i, line in enumerate(lines) if line.startswith("main bearings"))
    bearings = lines[start + 2 :]
    assert len(bearings) == len(mc.presets.MACHINES[machine].bearings)
    for table in (orders, bearings):
        for column, found in enumerate(notations(table)):
            assert len(found) <= 1, (machine, column, table)
    # fixed numbers have 4 significant digits at most (trailing zeros dropped, as %g does)
    for line in orders:
        for cell in line.split()[1:]:
            if "e" not in cell and cell != "0":
                assert len(cell.lstrip("-0.").replace(".", "")) <= 4 or float(cell).is_integer(), cell
    summary = mc.bearing_loads(mc.presets.MACHINES[machine]).summary
    for (_, row), line in zip(summary.iterrows(), bearings, strict=True):
        assert float(line.split()[2]) == pytest.approx(row["max"], rel=5e-4)


@pytest.mark.parametrize(("second", "couple"), [(0.0, False), (90.0, True)])
def test_a_twin_s_couple_and_what_counterweights_can_cancel(tmp_path, second, couple):
    """A 360° twin (cranks together) has no first-order couple about its centre, wherever it
    sits along the shaft: counterweights can cancel its forward force and no moment. A twin
    with cranks 90° apart (the 270° twin) rocks: its first order leaves a force and a moment,
    and the output says that such a moment depends on the point it is taken about."""
    cylinder = INLINE_FOUR.split("[cylinder]")[1]
    text = f"""
name = "twin"
shaft_inertia = 0.2
rpm = 4000.0
strokes = 4

[[cylinder]]
{cylinder}
axial_position = 7.0
phase_deg = 0.0

[[cylinder]]
{cylinder}
axial_position = 7.1
phase_deg = {second}
"""
    path = tmp_path / "twin.toml"
    path.write_text(text, encoding="utf-8")
    out = invoke("--machine", str(path), "--max-order", "2")
    machine = mc.Machine.from_toml(path)
    orders = mc.shaking_forces(machine, max_order=2).orders
    below = " ".join(" ".join(part.split()) for part in out.split("\n\n"))
    force = orders.loc[1, "force_forward"]
    if couple:
        assert orders.loc[1, "moment_forward"] > 0
        assert f"here {force:.4g} N and {orders.loc[1, 'moment_forward']:.4g} N·m" in below
        assert "order 1 leaves a free force as well as a moment" in below and "z_ref = 7.05 m" in below
    else:
        assert orders.loc[1, "moment_forward"] == orders.loc[1, "moment_backward"] == 0
        assert f"here {force:.4g} N);" in below and "free force as well as a moment" not in below


def test_steady_forces_and_bearing_loads_share_one_steady_state(monkeypatch):
    """--steady: the orders and the bearing lines are of one steady state, solved once (the
    bearings' "gravity adds" asks one more, of the machine with g = 0); the bearing lines are
    still mc.bearing_loads' own steady summary, which solves its own."""
    from multicrank.motion import steady

    solved = []
    route = steady._native_solution

    def counted(machine, rules, omega, gravity, ratio, points):
        solved.append(gravity)
        return route(machine, rules, omega, gravity, ratio, points)

    monkeypatch.setattr(steady, "_native_solution", counted)
    out = CliRunner().invoke(
        cli.main, ["forces", "--machine", "inline-4", "--max-order", "2", "--steady", "--format", "json"]
    )
    assert out.exit_code == 0, out.output
    assert solved == [True, False]
    monkeypatch.undo()
    summary = mc.bearing_loads(mc.presets.MACHINES["inline-4"], steady=True).summary
    records = json.loads(out.output)["bearings"]
    assert [r["max"] for r in records] == pytest.approx(list(summary["max"]), rel=1e-12)
    assert [r["gravity_adds"] for r in records] == pytest.approx(list(summary["gravity_adds"]), rel=1e-12)
