"""`multicrank sweep motion`: variants of a machine swept from the command line, run as a user
would (a real subprocess) for the results, in-process for the many one-line refusals."""

from __future__ import annotations

import io
import json
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from click.testing import CliRunner

import multicrank as mc
from multicrank import cli
from multicrank.cli.motion_sweep import MOTION_AXES
from multicrank.motion.variants import MACHINE_COLUMNS
from multicrank.presets import MACHINES

SCRIPT = Path(sys.executable).with_name("multicrank")
COMPRESSOR = MACHINES["slow-compressor"]


def run(*args: str) -> str:
    result = subprocess.run([str(SCRIPT), *args], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return result.stdout


def refused(*args: str) -> str:
    """The last line of a refusal: exit status 2, no traceback."""
    result = CliRunner().invoke(cli.main, ["sweep", "motion", "--no-progress", *args])
    assert result.exit_code == 2, result.output
    assert isinstance(result.exception, SystemExit) and "Traceback" not in result.output
    return result.output.strip().splitlines()[-1]


def test_a_small_grid_to_parquet_is_the_api_sweep(tmp_path):
    out = tmp_path / "m.parquet"
    text = run(
        "sweep", "motion", "--shaft-inertia", "250,450", "--rpm", "90:150:3", "--delta-target", "0.04",
        "--out", str(out), "--no-progress",
    )  # fmt: skip
    assert "6 designs" in text and str(out) in text and "gravity_effect" in text
    grid = mc.MachineGrid(COMPRESSOR, shaft_inertia=[250.0, 450.0], rpm=[90.0, 120.0, 150.0])
    expected = mc.motion_sweep(COMPRESSOR, grid, delta_target=0.04)
    pd.testing.assert_frame_equal(pd.read_parquet(out), expected, check_like=False, check_exact=True)


def test_a_small_grid_printed_as_a_table_and_as_csv():
    args = ["sweep", "motion", "--machine", "inline-4", "--rpm", "1000,3000", "--g", "9.81,20", "--no-progress"]
    grid = mc.MachineGrid(MACHINES["inline-4"], rpm=[1000.0, 3000.0], g=[9.81, 20.0])
    expected = mc.motion_sweep(MACHINES["inline-4"], grid)
    table = run(*args)
    assert "inline-4: 4 designs (load balance)" in table and "gravity_effect" in table
    assert len(table.strip().splitlines()) == 8  # two lines of summary, a blank one, the header, four rows
    frame = pd.read_csv(io.StringIO(run(*args, "--format", "csv", "--outputs", "delta,gravity_effect")), index_col=0)
    assert list(frame.columns) == ["rpm", "g", "delta", "gravity_effect", "stalled", "near_stall"]
    pd.testing.assert_series_equal(frame["delta"], expected["delta"], rtol=1e-11)
    data = json.loads(run(*args, "--format", "json", "--outputs", "delta"))
    assert data["machine"] == "inline-4" and [row["delta"] for row in data["rows"]] == pytest.approx(
        expected["delta"].tolist(), rel=1e-12
    )


def test_a_config_file_gives_axes_outputs_and_load(tmp_path):
    config = tmp_path / "motion.toml"
    config.write_text(
        'outputs = "delta, gravity_effect"\nload = "balance"\n'
        '[axes]\nrpm = "90:150:3"\nshaft_inertia = [250.0, 350.0]\n'
    )
    frame = pd.read_csv(
        io.StringIO(run("sweep", "motion", "--config", str(config), "--format", "csv", "--no-progress")), index_col=0
    )
    grid = mc.MachineGrid(COMPRESSOR, shaft_inertia=[250.0, 350.0], rpm=[90.0, 120.0, 150.0])
    expected = mc.motion_sweep(COMPRESSOR, grid, outputs=["delta", "gravity_effect"])
    pd.testing.assert_frame_equal(frame, expected, rtol=1e-11, check_dtype=False)
    # An option overrides the config's axis.
    override = run("sweep", "motion", "--config", str(config), "--rpm", "100", "--format", "csv", "--no-progress")
    assert set(pd.read_csv(io.StringIO(override))["rpm"]) == {100.0}


def test_delta_is_the_former_name_of_delta_target(tmp_path):
    """--delta and delta in --config (0.1's names of the target δ) still size the flywheel,
    each with one line on stderr naming the new name; both keys given is refused."""
    args = ["sweep", "motion", "--rpm", "100,120", "--outputs", "flywheel_inertia", "--format", "csv", "--no-progress"]
    new = CliRunner().invoke(cli.main, [*args, "--delta-target", "0.04"])
    assert new.exit_code == 0 and new.stderr == "", new.output
    grid = mc.MachineGrid(COMPRESSOR, rpm=[100.0, 120.0])
    expected = mc.motion_sweep(COMPRESSOR, grid, outputs=["flywheel_inertia"], delta_target=0.04)
    frame = pd.read_csv(io.StringIO(new.stdout), index_col=0)
    pd.testing.assert_series_equal(frame["flywheel_inertia"], expected["flywheel_inertia"], rtol=1e-11)
    old = CliRunner().invoke(cli.main, [*args, "--delta", "0.04"])
    assert old.exit_code == 0 and old.stdout == new.stdout, old.output
    assert old.stderr.splitlines() == ["note: --delta is now --delta-target (the old name goes in 0.3)"]
    config = tmp_path / "motion.toml"
    config.write_text("delta = 0.04\n")
    key = CliRunner().invoke(cli.main, [*args, "--config", str(config)])
    assert key.exit_code == 0 and key.stdout == new.stdout, key.output
    assert key.stderr.splitlines() == ["note: delta in --config is now delta_target (the old name goes in 0.3)"]
    config.write_text("delta_target = 0.04\n")
    assert CliRunner().invoke(cli.main, [*args, "--config", str(config)]).stdout == new.stdout
    config.write_text("delta = 0.04\ndelta_target = 0.04\n")
    assert refused("--rpm", "100", "--config", str(config)).endswith(
        "delta_target and delta are one key (delta its former name): give it once"
    )


@pytest.mark.parametrize(
    ("args", "named"),
    [
        (["--rpm", "90:150"], "--rpm"),
        (["--rpm", "abc"], "--rpm"),
        (["--rpm", ","], "--rpm"),
        (["--rpm", "0:100:3"], "rpm"),
        (["--rod-length", "0.01"], "rod_length"),
        (["--rpm", "100", "--outputs", "delta,nope"], "nope"),
        (["--rpm", "100", "--outputs", "flywheel_inertia"], "delta"),
        (["--rpm", "100", "--load", "wat"], "--load"),
        (["--rpm", "100", "--load", "power:100:120"], "rpm"),
        (["--rpm", "100", "--delta-target", "0"], "delta"),
        (["--rpm", "100", "--resume"], "--resume"),
        (["--rpm", "100", "--out", "x.parquet", "--format", "csv"], "--format"),
        ([], "no axes"),
        (["--machine", "steam-hammer", "--rpm", "100"], "--machine"),
    ],
)
def test_mistakes_are_one_line(args, named):
    assert named in refused(*args)


@pytest.mark.parametrize(
    ("config", "named"),
    [
        ("[axes]\nrpms = 3\n", "rpms"),
        ("phi = 36\n[axes]\nrpm = 100\n", "phi"),
        ("[axes]\nrpm = [true]\n", "[axes] rpm"),
        ("[axes]\nrpm = []\n", "[axes] rpm"),
        ('[axes]\nrpm = "1:2:0"\n', "[axes] rpm"),
        ("axes = 3\n", "axes"),
        ("outputs = 7\n[axes]\nrpm = 100\n", "outputs"),
        ('delta_target = "x"\n[axes]\nrpm = 100\n', "delta_target"),
        ("load = [1]\n[axes]\nrpm = 100\n", "load"),
        ("[axes\n", "not a valid TOML file"),
    ],
)
def test_config_mistakes_are_one_line(tmp_path, config, named):
    path = tmp_path / "motion.toml"
    path.write_text(config)
    assert named in refused("--config", str(path))


def test_gravity_options_before_motion_are_refused():
    result = CliRunner().invoke(cli.main, ["sweep", "--crank-ratio", "0.3", "motion", "--rpm", "100"])
    assert result.exit_code == 2 and "--crank-ratio: given before 'motion'" in result.output


def test_help_names_every_axis_with_its_unit():
    assert tuple(MOTION_AXES) == MACHINE_COLUMNS
    group = run("sweep", "--help")
    assert "DEGREES" in group and "motion" in group.split("Commands:")[1]
    text = run("sweep", "motion", "--help")
    for name in MACHINE_COLUMNS:
        assert f"--{name.replace('_', '-')} AXIS" in text
    for unit in ("[kg·m²]", "[1/min]", "[m/s²]", "[m]", "[kg]"):
        assert unit in text
    assert "--machine, --engine NAME|FILE" in text
