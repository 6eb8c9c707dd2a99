"""`multicrank optimize firing` and `multicrank optimize counterweights`, in-process through
click's CliRunner: each table is the library's (mc.firing_orders, mc.optimize_counterweights),
each --format reads back, and every mistake is one line with exit status 2."""

from __future__ import annotations

import io
import json
import math

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner, Result

import multicrank as mc
from multicrank import cli
from multicrank.presets import MACHINES

INLINE_4 = MACHINES["inline-4"]  # four-stroke: 8 phase assignments, a few distinct firing orders
TWIN = MACHINES["marine-2t-twin"]  # two throws: a quick optimisation
FAST = ("--maxiter", "3", "--seed", "7")  # a few generations: the command, not the optimum, is tested


def runner() -> CliRunner:
    """A runner whose result keeps stdout apart from stderr (click 8.1 mixes them by default;
    8.2 keeps both, result.stdout alone, and has no mix_stderr)."""
    try:
        return CliRunner(mix_stderr=False)  # type: ignore[call-arg]
    except TypeError:
        return CliRunner()


def invoke(*args: str) -> Result:
    result = runner().invoke(cli.main, ["optimize", *args, "--no-progress"])
    assert result.exit_code == 0, (result.stdout, result.stderr, result.exception)
    return result


def refused(*args: str) -> str:
    """The last line of a refusal: exit status 2, no traceback."""
    result = runner().invoke(cli.main, ["optimize", *args])
    assert result.exit_code == 2, (result.stdout, result.stderr, result.exception)
    assert isinstance(result.exception, SystemExit)
    assert "Traceback" not in result.stdout + result.stderr
    return result.stderr.strip().splitlines()[-1]


def csv_frame(result: Result, index: str) -> pd.DataFrame:
    return pd.read_csv(io.StringIO(result.stdout), index_col=index)


# ------------------------------------------------------------------------------------- firing

SHAFT_4 = """# four throws and a flywheel
[shaft]
inertia = [0.02, 0.02, 0.02, 0.02, 0.3]
stiffness = [3e5, 3e5, 3e5, 4e5]
cylinder_nodes = [0, 1, 2, 3]
"""


def test_firing_with_a_shaft_ranks_by_the_torsional_merit(tmp_path):
    path = tmp_path / "shaft.toml"
    path.write_text(SHAFT_4, encoding="utf-8")
    args = ("firing", "--machine", "inline-4", "--shaft", str(path), "--rank-by", "torsional_merit")
    frame = csv_frame(invoke(*args, "--format", "csv"), "rank")
    shaft = mc.Shaft([0.02] * 4 + [0.3], [3e5, 3e5, 3e5, 4e5], cylinder_nodes=[0, 1, 2, 3])
    expected = mc.firing_orders(INLINE_4, shaft=shaft, rank_by="torsional_merit")
    assert frame["firing"].tolist() == expected["firing"].tolist()
    for column in ("torsional_merit", "free_moment_2", "max_bearing_load"):
        np.testing.assert_allclose(frame[column], expected[column], rtol=1e-10, err_msg=column)
    assert frame["pareto"].tolist() == expected["pareto"].tolist()
    data = json.loads(invoke(*args, "--format", "json").stdout)
    assert data["rank_by"] == "torsional_merit" and data["units"]["torsional_merit"] == "N·m"
    table = invoke(*args).stdout
    assert "ranked by the first mode's largest excitation [N·m]" in table and "on the Pareto front" in table
    assert "torsional_major, torsional_minor [N·m/√(kg·m²)] the largest modal excitation" in table
    # the minor orders' part, over two modes, is a ranking of its own
    minor = csv_frame(invoke(*args[:-1], "torsional_minor", "--modes", "2", "--format", "csv"), "rank")
    expected = mc.firing_orders(INLINE_4, shaft=shaft, rank_by="torsional_minor", modes=2)
    assert minor["firing"].tolist() == expected["firing"].tolist()
    np.testing.assert_allclose(minor["torsional_minor"], expected["torsional_minor"], rtol=1e-10)
    assert list(minor["torsional_minor"]) == sorted(minor["torsional_minor"])


def test_firing_shaft_mistakes_are_one_line_naming_the_option(tmp_path):
    assert "--rank-by" in refused("firing", "--machine", "inline-4", "--rank-by", "torsional_merit", "--no-progress")
    assert "--shaft" in refused("firing", "--machine", "inline-4", "--shaft", str(tmp_path / "none.toml"))
    three = tmp_path / "three.toml"
    three.write_text(SHAFT_4.replace("[0, 1, 2, 3]", "[0, 1, 2]"), encoding="utf-8")
    line = refused("firing", "--machine", "inline-4", "--shaft", str(three))
    assert "--shaft" in line and "cylinder_nodes" in line


def test_firing_shaft_of_a_machine_file_the_machine_refuses_is_refused(tmp_path):
    """--shaft FILE, a whole machine file: its shaft suits the in-line four, but its machine has
    a cylinder out of range, which Machine.from_toml refuses; so does --shaft, on one line."""
    cylinder = "crank_radius = -0.05\nrod_length = 0.2\npiston_mass = 1.0\nrod_mass = 1.0\nrod_cg = 0.05\n"
    bad = tmp_path / "bad.toml"
    bad.write_text(f"shaft_inertia = 0.3\n{SHAFT_4}[[cylinder]]\n{cylinder}", encoding="utf-8")
    with pytest.raises(mc.MechanismError) as error:
        mc.Machine.from_toml(bad)
    result = runner().invoke(cli.main, ["optimize", "firing", "--machine", "inline-4", "--shaft", str(bad)])
    assert result.exit_code == 2 and isinstance(result.exception, SystemExit)
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and not result.stdout
    assert lines[0] == f"Error: --shaft {bad}: {error.value}"
    assert "cylinder[0]: crank_radius = -0.05 is out of range" in lines[0]


def test_firing_csv_is_the_api_ranking():
    result = invoke("firing", "--machine", "inline-4", "--format", "csv")
    frame = csv_frame(result, "rank")
    expected = mc.firing_orders(INLINE_4)
    assert frame.index.tolist() == list(range(1, len(expected) + 1))
    assert frame["firing"].tolist() == expected["firing"].tolist()
    phases = np.radians(frame[[f"phase_{j + 1}_deg" for j in range(len(INLINE_4))]].to_numpy())
    np.testing.assert_allclose(phases, np.array(expected["phases"].tolist()), rtol=1e-11, atol=1e-12)
    for column in ("delta", "delta_without_gravity", "gravity_effect", "largest_order", "largest_order_amplitude"):
        np.testing.assert_allclose(frame[column], expected[column], rtol=1e-10, err_msg=column)
    assert frame["stalled"].tolist() == expected["stalled"].tolist()
    assert "machine" not in frame.columns and "phases" not in frame.columns
    # The note on the enumeration goes to stderr: the CSV stays CSV.
    assert "exhaustive" in result.stderr and "exhaustive" not in result.stdout


def test_firing_json_carries_the_enumeration_and_the_phases_in_degrees():
    data = json.loads(invoke("firing", "--machine", "inline-4", "--format", "json", "--rpm", "3000").stdout)
    expected = mc.firing_orders(INLINE_4, rpm=3000.0)
    assert data["machine"] == "inline-4" and data["rpm"] == 3000.0
    assert (data["candidates"], data["distinct"], data["exhaustive"]) == (8, len(expected), True)
    assert [row["rank"] for row in data["rows"]] == list(range(1, len(expected) + 1))
    for row, (_, want) in zip(data["rows"], expected.iterrows(), strict=True):
        assert row["firing"] == want["firing"]
        np.testing.assert_allclose(np.radians(row["phases_deg"]), want["phases"], rtol=1e-12, atol=1e-12)
        assert row["delta"] == pytest.approx(want["delta"], rel=1e-12)
        assert row["largest_order"] == want["largest_order"]
        assert "machine" not in row


def test_firing_table_says_whether_every_candidate_was_tried():
    text = invoke("firing", "--machine", "inline-4").stdout
    expected = mc.firing_orders(INLINE_4)
    head, table = text.split("\n\n", 1)
    assert "exhaustive: the crank allows 8 phase assignments, all tried" in head
    assert f"{len(expected)} distinct firing orders" in head
    lines = table.strip().splitlines()[2:]  # below the header and the index's name
    assert len(lines) == len(expected)
    for rank, (line, (_, want)) in enumerate(zip(lines, expected.iterrows(), strict=True), start=1):
        words = line.split()
        assert words[:2] == [str(rank), want["firing"]]
        # The phases in whole degrees here (inline-4: 0, 180, 360, 540), in cylinder order.
        degrees = [f"{round(math.degrees(a), 2) + 0.0:g}" for a in want["phases"]]
        assert words[2 : 2 + len(INLINE_4)] == degrees
        assert f"{want['delta']:.6g}" in words

    cut = invoke("firing", "--machine", "inline-4", "--max-candidates", "2").stdout
    assert "not exhaustive: the crank allows 8 phase assignments, only the first 2 tried" in cut
    assert "--max-candidates" in cut


def test_firing_csv_that_is_cut_says_so_on_stderr_and_writes_out(tmp_path):
    target = tmp_path / "firing.csv"
    result = invoke("firing", "--machine", "inline-4", "--max-candidates", "2", "--format", "csv", "--out", str(target))
    assert result.stdout == ""
    assert "not exhaustive" in result.stderr and f"written: {target}" in result.stderr
    written = pd.read_csv(target, index_col="rank")
    expected = mc.firing_orders(INLINE_4, max_candidates=2)
    assert written["firing"].tolist() == expected["firing"].tolist()


def test_a_machine_file_by_engine(tmp_path):
    """The issue's spelling: --engine FILE.toml, here the cross-plane V8's layout file and a
    copy of the marine twin's machine file."""
    from pathlib import Path

    v8 = Path(__file__).resolve().parents[2] / "docs" / "machines" / "v8-cross.toml"
    found = json.loads(invoke("firing", "--engine", str(v8), "--format", "json").stdout)
    expected = mc.firing_orders(mc.Machine.from_toml(v8))
    assert found["distinct"] == expected.attrs["distinct"] and found["candidates"] == expected.attrs["candidates"]
    twin = tmp_path / "twin.toml"
    twin.write_text(mc.presets.MACHINE_FILES["marine-2t-twin"].read_text(encoding="utf-8"), encoding="utf-8")
    optimum = json.loads(invoke("counterweights", "--engine", str(twin), *FAST, "--format", "json").stdout)
    direct = mc.optimize_counterweights(mc.Machine.from_toml(twin), seed=7, maxiter=3)
    assert optimum["objective"] == direct.objective and optimum["objective_before"] == direct.objective_before


def test_firing_max_order_reaches_the_library():
    frame = csv_frame(invoke("firing", "--machine", "inline-4", "--max-order", "1", "--format", "csv"), "rank")
    expected = mc.firing_orders(INLINE_4, max_order=1)
    assert (frame["largest_order"] <= 1).all()
    np.testing.assert_allclose(frame["largest_order_amplitude"], expected["largest_order_amplitude"], rtol=1e-10)


# ----------------------------------------------------------------------------- counterweights


@pytest.fixture(scope="module")
def twin_optimum():
    return mc.optimize_counterweights(TWIN, seed=7, maxiter=3)


def test_counterweights_csv_is_the_api_optimum(twin_optimum):
    result = invoke("counterweights", "--machine", "marine-2t-twin", *FAST, "--format", "csv")
    frame = csv_frame(result, "throw")
    expected = twin_optimum.to_frame().set_index("throw")
    assert frame.index.tolist() == expected.index.tolist()
    assert frame["cylinders"].astype(str).tolist() == expected["cylinders"].astype(str).tolist()
    for column in ("angle_deg", "counterweight_before", "counterweight"):
        np.testing.assert_allclose(frame[column], expected[column], rtol=1e-10, atol=1e-12, err_msg=column)
    # The summary goes to stderr: the CSV stays CSV.
    assert "converged" in result.stderr and "converged" not in result.stdout
    assert f"{twin_optimum.objective:.6g}" in result.stderr


def test_counterweights_json_is_the_summary_and_the_rows(twin_optimum):
    data = json.loads(invoke("counterweights", "--machine", "marine-2t-twin", *FAST, "--format", "json").stdout)
    found = twin_optimum
    assert data["objective_name"] == "delta" == found.objective_name
    assert data["objective"] == pytest.approx(found.objective, rel=1e-12)
    assert data["objective_before"] == pytest.approx(found.objective_before, rel=1e-12)
    assert data["delta"] == pytest.approx(found.delta, rel=1e-12)
    assert data["success"] is bool(found.success) and data["message"] == str(found.message)
    assert data["rpm"] == TWIN.rpm and data["seed"] == 7 and data["maxiter"] == 3
    assert [row["throw"] for row in data["rows"]] == list(range(1, len(found.throws) + 1))
    np.testing.assert_allclose([row["counterweight"] for row in data["rows"]], found.counterweights, rtol=1e-12)


def test_counterweights_table_shows_before_after_and_convergence(twin_optimum):
    text = invoke("counterweights", "--machine", "marine-2t-twin", *FAST).stdout
    head, table = text.split("\n\n", 1)
    assert f"{twin_optimum.objective_before:.6g} as given → {twin_optimum.objective:.6g}" in head
    assert ("converged" if twin_optimum.success else "NOT converged") in head
    assert str(twin_optimum.message) in head
    assert len(table.strip().splitlines()) == 2 + len(twin_optimum.throws)


def test_counterweights_options_reach_the_library(tmp_path):
    target = tmp_path / "cw.json"
    invoke(
        "counterweights", "--machine", "marine-2t-twin", *FAST, "--objective", "gravity_effect", "--bounds", "0",
        "50", "--rpm", "250", "--format", "json", "--out", str(target),
    )  # fmt: skip
    data = json.loads(target.read_text())
    found = mc.optimize_counterweights(
        TWIN, objective="gravity_effect", bounds=(0.0, 50.0), rpm=250.0, seed=7, maxiter=3
    )
    assert data["objective_name"] == "gravity_effect" and data["rpm"] == 250.0 and data["bounds"] == [0.0, 50.0]
    assert data["objective"] == pytest.approx(found.objective, rel=1e-12)
    counterweights = [row["counterweight"] for row in data["rows"]]
    np.testing.assert_allclose(counterweights, found.counterweights, rtol=1e-12)
    assert all(0.0 <= value <= 50.0 for value in counterweights)


CRITERIA = ("delta", "free_force_1", "free_moment_1", "max_bearing_load")


def test_counterweights_bearing_load_and_limits_reach_the_library():
    """--objective max_bearing_load and --max-free-force: the optimum is the library's, every
    criterion before and after is in the JSON, and the limit holds (by mc.shaking_forces)."""
    data = json.loads(
        invoke(
            "counterweights", "--machine", "boxer-compressor", *FAST, "--objective", "max_bearing_load",
            "--max-free-force", "4000", "--format", "json",
        ).stdout
    )  # fmt: skip
    found = mc.optimize_counterweights(
        MACHINES["boxer-compressor"], objective="max_bearing_load", max_free_force=4000.0, seed=7, maxiter=3
    )
    assert data["objective_name"] == "max_bearing_load"
    assert data["objective"] == pytest.approx(found.objective, rel=1e-12)
    np.testing.assert_allclose([row["counterweight"] for row in data["rows"]], found.counterweights, rtol=1e-12)
    for name in CRITERIA:
        assert data[name] == pytest.approx(getattr(found, name), rel=1e-12, abs=1e-12), name
        assert data[f"{name}_before"] == pytest.approx(getattr(found, f"{name}_before"), rel=1e-12, abs=1e-12), name
    assert (data["max_free_force_limit"], data["max_bearing_load_limit"]) == (4000.0, None)
    assert data["units"]["max_bearing_load"] == "N" and data["units"]["free_moment_1"] == "N·m"
    orders = mc.shaking_forces(found.machine).orders
    assert data["free_force_1"] <= 4000.0
    assert data["free_force_1"] == pytest.approx(orders.loc[1, "force_forward"] + orders.loc[1, "force_backward"])


def test_counterweights_table_prints_every_criterion_and_the_limit():
    limit = 12000.0
    result = invoke(
        "counterweights", "--machine", "slow-compressor", "--maxiter", "20", "--max-bearing-load", f"{limit:g}",
    )  # fmt: skip
    head = result.stdout.split("\n\n", 1)[0]
    found = mc.optimize_counterweights(MACHINES["slow-compressor"], max_bearing_load=limit, maxiter=20)
    assert mc.bearing_loads(found.machine).magnitude.max() <= limit
    for label, name in (
        ("δ with gravity", "delta"),
        ("first-order free force [N]", "free_force_1"),
        ("first-order free moment about the engine centre [N·m]", "free_moment_1"),
        ("largest main-bearing load over the cycle [N]", "max_bearing_load"),
    ):
        before, after = getattr(found, f"{name}_before"), getattr(found, name)
        assert f"{label}: {before:.6g} as given → {after:.6g}" in head, label
    assert "kept: --max-bearing-load 12000 N" in head
    # csv: the summary on stderr, the table alone on stdout.
    csv = invoke(
        "counterweights", "--machine", "slow-compressor", "--maxiter", "20", "--objective", "free_force_1",
        "--max-bearing-load", f"{limit:g}", "--format", "csv",
    )  # fmt: skip
    assert "largest main-bearing load over the cycle [N]" in csv.stderr
    assert "largest main-bearing load" not in csv.stdout
    assert csv_frame(csv, "throw").index.tolist() == [1]


def test_a_limit_nothing_meets_is_one_line_naming_the_option():
    line = refused("counterweights", "--machine", "slow-compressor", "--max-bearing-load", "1000", "--maxiter", "3",
                   "--no-progress")  # fmt: skip
    # Named by the option (the refusal's parameter, max_bearing_load), in the library's words.
    assert line.startswith("Error: --max-bearing-load: no counterweights within bounds")
    assert "max_bearing_load <= 1000 N" in line and "(raise max_bearing_load, or widen the bounds)" in line
    both = refused(
        "counterweights", "--machine", "slow-compressor", "--max-bearing-load", "1000", "--max-free-force", "1",
        "--maxiter", "3", "--no-progress",
    )  # fmt: skip
    assert both.startswith("Error: --max-bearing-load: ")
    assert "max_bearing_load <= 1000 N and max_free_force <= 1 N together" in both


# ------------------------------------------------------------------------- mistakes and help


@pytest.mark.parametrize(
    ("args", "named"),
    [
        (["firing", "--rpm", "0"], "--rpm"),
        (["firing", "--rpm", "nan"], "--rpm"),
        (["firing", "--rpm", "fast"], "--rpm"),
        (["firing", "--max-order", "0"], "--max-order"),
        (["firing", "--max-candidates", "0"], "--max-candidates"),
        (["firing", "--format", "xml"], "--format"),
        (["firing", "--machine", "no-such-machine"], "--machine"),
        (["counterweights", "--objective", "smoothness"], "--objective"),
        (["counterweights", "--bounds", "2", "1"], "--bounds"),
        (["counterweights", "--bounds", "0", "inf"], "--bounds"),
        (["counterweights", "--bounds", "-1", "5"], "--bounds"),
        (["counterweights", "--bounds", "0"], "--bounds"),
        (["counterweights", "--maxiter", "0"], "--maxiter"),
        (["counterweights", "--seed", "-1"], "--seed"),
        (["counterweights", "--rpm", "-5"], "--rpm"),
        (["counterweights", "--machine", "no-such-machine"], "--machine"),
        (["counterweights", "--objective", "bearing_loads"], "--objective"),
        (["counterweights", "--max-bearing-load", "-5"], "--max-bearing-load"),
        (["counterweights", "--max-bearing-load", "nan"], "--max-bearing-load"),
        (["counterweights", "--max-bearing-load", "inf"], "--max-bearing-load"),
        (["counterweights", "--max-bearing-load", "heavy"], "--max-bearing-load"),
        (["counterweights", "--max-bearing-load"], "--max-bearing-load"),
        (["counterweights", "--max-free-force", "-1"], "--max-free-force"),
        (["counterweights", "--max-free-force", "nan"], "--max-free-force"),
        (["counterweights", "--max-free-moment", "-1"], "--max-free-moment"),
        (["firing", "--machine", "inline-4", "--rank-by", "torsional_minor"], "--rank-by"),
        (["firing", "--modes", "0"], "--modes"),
        (["tune"], "tune"),
    ],
)
def test_mistakes_are_one_line_naming_the_option(args, named):
    assert named in refused(*args, "--no-progress")


@pytest.mark.parametrize("command", ["firing", "counterweights"])
@pytest.mark.parametrize(
    ("content", "named"),
    [
        (None, "is a directory"),
        (b"shaft_inertia = [1,\n", "not a valid TOML file"),
        (b"shaft_inertia = 'heavy'\n[cylinder]\ncrank_radius = 0.1\n", "shaft_inertia"),
    ],
)
def test_a_machine_file_that_cannot_be_read_is_one_line(tmp_path, command, content, named):
    path = tmp_path / "machine.toml"
    if content is None:
        path.mkdir()
    else:
        path.write_bytes(content)
    line = refused(command, "--machine", str(path), "--no-progress")
    assert line.startswith(f"Error: --machine: {path}") and named in line


@pytest.mark.parametrize("command", ["firing", "counterweights"])
def test_a_machine_without_a_speed_asks_for_rpm(tmp_path, command):
    path = tmp_path / "bare.toml"
    path.write_text(
        'name = "bare"\nshaft_inertia = 5.0\n[cylinder]\ncrank_radius = 0.1\nrod_length = 0.4\nrod_cg = 0.25\n'
        "piston_mass = 2.0\nrod_mass = 1.0\n"
    )
    assert (
        refused(command, "--machine", str(path), "--no-progress")
        == "Error: --rpm: rpm is required: machine 'bare' has no running speed (rpm) of its own"
    )


def test_an_out_that_cannot_be_written_is_one_line(tmp_path):
    blocked = tmp_path / "file"
    blocked.write_text("not a directory")
    line = refused("firing", "--machine", "inline-4", "--out", str(blocked / "inside.csv"), "--no-progress")
    assert line.startswith(f"Error: --out {blocked / 'inside.csv'}")


def helped(*args: str) -> str:
    result = runner().invoke(cli.main, [*args, "--help"])
    assert result.exit_code == 0, result.stderr
    return result.stdout


def test_help():
    assert "optimize" in helped().split("Commands:")[1]
    commands = helped("optimize").split("Commands:")[1]
    assert "firing" in commands and "counterweights" in commands
    alone = runner().invoke(cli.main, ["optimize"])  # the group alone: its help
    assert alone.exit_code == 0 and alone.stdout.split("Commands:")[1] == commands
    firing = helped("optimize", "firing")
    for option in ("--machine, --engine NAME|FILE", "--rpm RPM", "--max-order ORDER", "--max-candidates COUNT"):
        assert option in firing
    counterweights = helped("optimize", "counterweights")
    for option in ("--objective", "delta_over_speed_range", "--bounds LOW HIGH", "kg·m", "--seed", "--maxiter"):
        assert option in counterweights
    for option in ("max_bearing_load", "free_force_1", "--max-bearing-load N", "--max-free-force N", "newtons"):
        assert option in counterweights


def test_the_objectives_names_of_0_1_still_work_with_one_note():
    """--objective bearing_load and shaking_force are the criteria max_bearing_load and
    free_force_1 under their names of 0.1: the same optimum, one note on stderr once the command
    has run; in the library a DeprecationWarning naming the new name."""
    for old, new in (("bearing_load", "max_bearing_load"), ("shaking_force", "free_force_1")):
        args = ("counterweights", "--machine", "slow-compressor", *FAST, "--format", "json")
        former = invoke(*args, "--objective", old)
        assert json.loads(former.stdout) == json.loads(invoke(*args, "--objective", new).stdout)
        assert former.stderr.strip() == f"note: --objective {old} is now --objective {new} (the old name goes in 0.3)"
        with pytest.warns(DeprecationWarning, match=f"objective='{new}'"):
            found = mc.optimize_counterweights(MACHINES["slow-compressor"], objective=old, seed=7, maxiter=3)
        assert found.objective_name == new


def test_counterweights_free_moment_limit_and_a_bound_of_the_search():
    """--max-free-moment reaches the library and is said among what is kept; an optimum on a
    bound of the search (the boxer compressor's least δ, its first throw) is said to be."""
    data = json.loads(
        invoke(
            "counterweights", "--machine", "marine-2t-twin", *FAST, "--objective", "max_bearing_load",
            "--max-free-moment", "5000", "--format", "json",
        ).stdout
    )  # fmt: skip
    found = mc.optimize_counterweights(TWIN, objective="max_bearing_load", max_free_moment=5000.0, seed=7, maxiter=3)
    assert data["max_free_moment_limit"] == 5000.0 and data["units"]["max_free_moment_limit"] == "N·m"
    assert data["free_moment_1"] == pytest.approx(found.free_moment_1, rel=1e-12) and found.free_moment_1 <= 5000.0
    assert data["at_bound"] == list(found.at_bound)
    table = invoke("counterweights", "--machine", "marine-2t-twin", *FAST, "--max-free-moment", "5000").stdout
    assert "kept: --max-free-moment 5000 N·m" in table
    boxer = mc.optimize_counterweights(MACHINES["boxer-compressor"], seed=7, maxiter=3)
    assert boxer.at_bound == (True, False)
    said = invoke("counterweights", "--machine", "boxer-compressor", *FAST).stdout
    assert "at a bound of the search: throw 1 (" in said
    assert "at a bound of the search" not in table
