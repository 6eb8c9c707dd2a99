"""`multicrank simulate` and `multicrank motion`, run as a user would (a real subprocess)."""

from __future__ import annotations

import io
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import multicrank as mc
from multicrank.presets import DEFAULT_MACHINE

SCRIPT = Path(sys.executable).with_name("multicrank")


def run(*args: str) -> str:
    result = subprocess.run([str(SCRIPT), *args], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return result.stdout


def run_failing(*args: str) -> str:
    result = subprocess.run([str(SCRIPT), *args], capture_output=True, text=True, timeout=300)
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
    # Our own checks print one line; click's own (a type, a range) add its usage above it.
    return result.stderr.strip().splitlines()[-1]


def test_simulate_csv_is_the_api_run():
    out = run("simulate", "--duration", "0.5", "--samples", "51", "--format", "csv", "--no-progress")
    frame = pd.read_csv(io.StringIO(out), index_col="time")
    machine = DEFAULT_MACHINE
    expected = mc.simulate(machine, np.linspace(0, 0.5, 51), rpm0=machine.rpm, load="balance")
    np.testing.assert_allclose(frame["omega"], expected.omega, rtol=1e-10)
    np.testing.assert_allclose(frame["rpm"], expected.omega * 30 / math.pi, rtol=1e-10)
    np.testing.assert_allclose(frame["gas_torque"], expected.gas_torque, rtol=1e-9, atol=1e-6)


def test_simulate_run_down_without_gas_stalls_and_says_so(tmp_path):
    target = tmp_path / "run.json"
    run(
        "simulate", "--no-gas", "--load", "400", "--rpm", "60", "--duration", "30", "--samples", "301",
        "--format", "json", "--out", str(target), "--no-progress",
    )  # fmt: skip
    data = json.loads(target.read_text())
    assert data["stalled"] is True and data["stall_time"] > 0
    assert data["rows"][-1]["omega"] == 0.0
    assert data["energy_drift"] < 1e-7
    # Pure run-down against a constant load: the energy at the start is spent by the load
    # (and gravity's potential) when it stops: ½J₀ω₀² + U₀ = ∫M dφ + U_end.
    last = data["rows"][-1]
    first = data["rows"][0]
    spent = 400.0 * (last["phi"] - first["phi"])
    assert first["kinetic_energy"] + first["potential_energy"] == pytest.approx(
        spent + last["potential_energy"], rel=1e-6
    )


@pytest.mark.parametrize(
    ("args", "named"),
    [
        (["--load", "abc"], "--load"),
        (["--load", "power:1:0"], "--load"),
        (["--drive", "balance"], "--drive"),
        (["--duration", "-1"], "--duration"),
        (["--rpm", "0"], "--rpm"),
        (["--rpm", "nan"], "--rpm"),
        (["--samples", "1"], "--samples"),
        (["--machine", "no-such-machine"], "--machine"),
    ],
)
def test_simulate_mistakes_are_one_line_naming_the_option(args, named):
    assert named in run_failing("simulate", "--no-progress", *args)


def test_a_bad_sweep_axis_value_is_one_line_not_a_traceback(tmp_path):
    line = run_failing(
        "sweep", "--crank-ratio", "1.5", "--inclination", "90", "--u1", "1", "--out", str(tmp_path / "s.parquet")
    )
    assert "crank_ratio" in line


def test_motion_csv_is_the_api_steady_state_and_flywheel(tmp_path):
    cycle = tmp_path / "cycle.csv"
    out = run(
        "motion", "--rpm", "100", "--rpm", "150", "--delta-target", "0.04", "--cycle", str(cycle), "--format", "csv",
        "--no-progress",
    )  # fmt: skip
    frame = pd.read_csv(io.StringIO(out), index_col="rpm")
    machine = DEFAULT_MACHINE
    for rpm in (100.0, 150.0):
        state = mc.steady_state(machine, rpm=rpm)
        row = frame.loc[rpm]
        assert row["delta"] == pytest.approx(state.delta, rel=1e-10)
        assert row["delta_without_gravity"] == pytest.approx(state.delta_without_gravity, rel=1e-10)
        assert row["gravity_effect"] == pytest.approx(state.delta / state.delta_without_gravity - 1, rel=1e-8)
        assert row["delta_coasting"] == pytest.approx(state.delta_coasting, rel=1e-10)
        assert not row["near_stall"]
        sized = mc.flywheel_inertia(machine, delta=0.04, rpm=rpm)
        assert row["flywheel_inertia"] == pytest.approx(sized.shaft_inertia, rel=1e-8)
        assert row["flywheel_inertia_without_gravity"] == pytest.approx(sized.shaft_inertia_without_gravity, rel=1e-8)
    written = pd.read_csv(cycle)
    state = mc.steady_state(machine, rpm=100.0)
    np.testing.assert_allclose(written["omega"], state.omega, rtol=1e-10)
    np.testing.assert_allclose(written["phi_deg"], np.degrees(state.phi), rtol=1e-12)
    without = mc.steady_state(machine, rpm=100.0, gravity=False)
    np.testing.assert_allclose(written["omega_without_gravity"], without.omega, rtol=1e-10)


def test_motion_runs_at_the_speed_asked_and_its_rpm_columns_round_trip():
    # --rpm 120 is ω_m = 120π/30 rad/s (power = load torque · ω_m); the speed extremes in 1/min
    # are 30ω/π of the API's ω_min and ω_max.
    frame = pd.read_csv(io.StringIO(run("motion", "--rpm", "120", "--format", "csv", "--no-progress")), index_col="rpm")
    row = frame.loc[120.0]
    assert 1000 * row["power_kw"] / row["load_torque"] == pytest.approx(math.pi * 120 / 30, rel=1e-10)
    state = mc.steady_state(DEFAULT_MACHINE, rpm=120)
    assert row["rpm_min"] == pytest.approx(30 * state.omega_min / math.pi, rel=1e-11)
    assert row["rpm_max"] == pytest.approx(30 * state.omega_max / math.pi, rel=1e-11)
    assert row["rpm_min"] < 120 < row["rpm_max"]


def test_motion_over_the_speed_range_with_the_class_flywheel():
    data = json.loads(run("motion", "--points", "3", "--format", "json", "--no-progress"))
    machine = DEFAULT_MACHINE
    speeds = [row["rpm"] for row in data["rows"]]
    assert machine.rpm in speeds and min(speeds) == machine.rpm_range[0] and max(speeds) == machine.rpm_range[1]
    assert data["delta_target"] == pytest.approx(1 / 20)  # the compressor class's limit
    assert data["target_delta"] == data["delta_target"]  # its former name, kept for one release
    assert all(row["flywheel_inertia"] > 0 for row in data["rows"])


def test_delta_is_the_former_name_of_delta_target():
    """--delta (0.1's name of the target δ) still sizes the flywheel, with one line on stderr
    naming --delta-target; both given is one line and exit status 2."""
    from click.testing import CliRunner

    from multicrank import cli

    args = ["motion", "--rpm", "120", "--format", "json", "--no-progress"]
    old = CliRunner().invoke(cli.main, [*args, "--delta", "0.04"])
    assert old.exit_code == 0, old.output
    assert old.stderr.splitlines() == ["note: --delta is now --delta-target (the old name goes in 0.3)"]
    data = json.loads(old.stdout)
    assert data["delta_target"] == data["target_delta"] == 0.04
    sized = mc.flywheel_inertia(DEFAULT_MACHINE, delta=0.04, rpm=120.0)
    assert data["rows"][0]["flywheel_inertia"] == pytest.approx(sized.shaft_inertia, rel=1e-8)
    new = CliRunner().invoke(cli.main, [*args, "--delta-target", "0.04"])
    assert new.exit_code == 0 and new.stderr == "" and json.loads(new.stdout) == data
    both = CliRunner().invoke(cli.main, [*args, "--delta", "0.04", "--delta-target", "0.05"])
    assert both.exit_code == 2 and "Traceback" not in both.output
    assert both.stderr.splitlines()[-1] == (
        "Error: --delta-target and --delta are one option (--delta its former name): give it once"
    )


@pytest.mark.parametrize(
    ("args", "named"),
    [
        (["--rpm", "-5"], "--rpm"),
        (["--delta-target", "2"], "--delta-target"),
        (["--load", "power:100:600", "--rpm", "500"], "--rpm"),
        (["--load", "7"], "load"),
        (["--machine", "docs/no-such.toml"], "--machine"),
    ],
)
def test_motion_mistakes_are_one_line_naming_the_option(args, named):
    assert named in run_failing("motion", "--no-progress", *args)


@pytest.mark.parametrize(
    ("args", "named"),
    [
        (["--crank-ratio", "0.2:0.45:0"], "--crank-ratio"),
        (["--crank-ratio", ","], "--crank-ratio"),
        (["--crank-ratio", "abc"], "--crank-ratio"),
        (["--crank-ratio", "0.3", "--cranks", "1.5"], "--cranks"),
        (["--crank-ratio", "0.3", "--cranks", "3:1"], "--cranks"),
        (["--crank-ratio", "0.1:nan:3"], "--crank-ratio"),
    ],
)
def test_sweep_axes_that_cannot_be_read_are_one_line(tmp_path, args, named):
    """Issue 13, item 8: empty or unparsable axes were tracebacks (IndexError, ValueError)."""
    out = tmp_path / "s.parquet"
    line = run_failing("sweep", "--inclination", "90", "--u1", "1", "--out", str(out), *args)
    assert line.startswith(f"Error: {named} = ") and not out.exists()


def test_eval_and_report_refuse_what_they_cannot_do_in_one_line(tmp_path):
    assert "--points" in run_failing("eval", "--points", "100000000000")
    assert "--threshold" in run_failing("report", "--threshold", "nan", "--out", str(tmp_path / "r"), "--no-progress")
    assert not (tmp_path / "r").exists()
    blocked = tmp_path / "file"
    blocked.write_text("not a directory")
    line = run_failing("report", "--out", str(blocked / "inside"), "--no-progress")
    assert line.startswith(f"Error: --out {blocked / 'inside'}")


@pytest.mark.parametrize(
    ("config", "named"),
    [
        ('outputs = "force_rms,nonsense"\n[axes]\ncrank_ratio = 0.3\ninclination = 90\nu1 = 1\n', "nonsense"),
        ("outputs = 7\n[axes]\ncrank_ratio = 0.3\ninclination = 90\nu1 = 1\n", "outputs"),
        ('outputs = ["force_rms", 3]\n[axes]\ncrank_ratio = 0.3\ninclination = 90\nu1 = 1\n', "outputs"),
        ("[axes]\ncrank_ratio = 0.3\ninclination = 90\nu1 = 1\ncylinders = [2, 4]\n", "cylinders"),
        ("[axes]\ncrank_ratio = 0.3\ninclination = 90\nu1 = 1\ncranks = [2.5]\n", "[axes] cranks"),
        ('[axes]\ncrank_ratio = "0.3"\ninclination = 90\nu1 = true\n', "[axes] u1"),
        ("[axes]\ncrank_ratio = []\ninclination = 90\nu1 = 1\n", "[axes] crank_ratio"),
        ('[axes]\ncrank_ratio = "0.1:0.2:0"\ninclination = 90\nu1 = 1\n', "[axes] crank_ratio"),
        ("axes = 3\n", "axes"),
        ("phi = 0\n[axes]\ncrank_ratio = 0.3\ninclination = 90\nu1 = 1\n", "phi"),
        ('phi = "720"\n[axes]\ncrank_ratio = 0.3\ninclination = 90\nu1 = 1\n', "phi"),
        ("speed = 3\n[axes]\ncrank_ratio = 0.3\ninclination = 90\nu1 = 1\n", "speed"),
        ("[axes\n", "not a valid TOML file"),
    ],
)
def test_sweep_configs_with_wrong_names_or_types_are_one_line(tmp_path, config, named):
    """Issue 13, item 8: a config's outputs = "x" was iterated per character after the sweep
    ran, and unknown [axes] names were silently dropped."""
    path = tmp_path / "sweep.toml"
    path.write_text(config)
    out = tmp_path / "s.parquet"
    line = run_failing("sweep", "--config", str(path), "--out", str(out), "--no-progress")
    assert named in line and not out.exists()


def test_a_sweep_config_that_is_not_utf8_is_one_line(tmp_path):
    path = tmp_path / "sweep.toml"
    path.write_bytes(b"\xff\xfe[axes]\n")
    assert "UTF-8" in run_failing("sweep", "--config", str(path), "--out", str(tmp_path / "s.parquet"))


def test_a_sweep_config_with_outputs_as_a_string_runs(tmp_path):
    path = tmp_path / "sweep.toml"
    path.write_text(
        'outputs = "force_rms, energy_range"\nphi = 36\n[axes]\ncrank_ratio = [0.2, 0.3]\n'
        'inclination = "0:90:3"\nu1 = 1\ncranks = 2\n'
    )
    out = tmp_path / "s.parquet"
    result = subprocess.run(
        [str(SCRIPT), "sweep", "--config", str(path), "--out", str(out), "--no-progress"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    assert "force_rms" in result.stdout and "energy_range" in result.stdout and "6 designs" in result.stdout


def test_a_full_disk_during_a_sweep_is_one_line(tmp_path, monkeypatch):
    import errno

    from click.testing import CliRunner

    from multicrank import cli
    from multicrank.sweeps import driver as sweeps

    def full_disk(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(sweeps, "sweep", full_disk)
    out = tmp_path / "s.parquet"
    args = ["sweep", "--crank-ratio", "0.3", "--inclination", "90", "--u1", "1", "--out", str(out), "--no-progress"]
    result = CliRunner().invoke(cli.main, args)
    assert result.exit_code == 2
    assert result.output.strip().splitlines()[-1] == (
        f"Error: --out {out}: No space left on device; finished chunks are kept for --resume"
    )


@pytest.mark.parametrize("command", ["eval", "motion", "simulate", "report"])
@pytest.mark.parametrize(
    ("content", "named"),
    [
        (None, "is a directory"),
        (b"\xff\xfe\x00shaft_inertia = 1\n", "not a UTF-8 text file"),
        (b"shaft_inertia = [1,\n", "not a valid TOML file"),
        (b"shaft_inertia = 'heavy'\n[cylinder]\ncrank_radius = 0.1\n", "shaft_inertia"),
    ],
)
def test_a_machine_file_that_cannot_be_read_is_one_line_for_every_command(tmp_path, command, content, named):
    """Issue 13, item 8: a machine file that is a directory, not UTF-8, not TOML or wrong-typed."""
    path = tmp_path / "machine.toml"
    if content is None:
        path.mkdir()
    else:
        path.write_bytes(content)
    extra = ["--out", str(tmp_path / "r")] if command == "report" else []
    line = run_failing(command, "--machine", str(path), *extra, *([] if command == "eval" else ["--no-progress"]))
    assert line.startswith(f"Error: --machine: {path}") and named in line
    assert not (tmp_path / "r").exists()


def _notations(lines: list[str]) -> list[set[str]]:
    """For each whitespace-separated column of ``lines``, the notations its numbers are
    written in: "exponent" or "fixed"; 0, nan and the flags count as either."""
    columns: list[set[str]] = []
    for line in lines:
        for i, cell in enumerate(line.split()):
            while len(columns) <= i:
                columns.append(set())
            if cell not in ("0", "nan", "NaN", "True", "False"):
                float(cell)
                columns[i].add("exponent" if "e" in cell else "fixed")
    return columns


@pytest.mark.parametrize(
    "args",
    [
        ("motion", "--machine", "genset-v12", "--rpm", "1500", "--rpm", "6000", "--delta-target", "1e-4"),
        ("motion", "--machine", "inline-6"),
        ("simulate", "--machine", "inline-4", "--duration", "0.05"),
    ],
)
def test_every_column_of_the_tables_to_read_is_in_one_notation(args):
    """A column is fixed, or all with an exponent where one of its numbers needs one — not
    0.000723 above 4.89e-05 (the genset's δ at 1500 and 6000 rpm was)."""
    lines = run(*args, "--no-progress").splitlines()
    start = next(i for i, line in enumerate(lines) if line.split() and line.split()[0] in ("rpm", "time")) + 1
    rows = lines[start:]
    assert rows
    for column, found in enumerate(_notations(rows)):
        assert len(found) <= 1, (column, rows)
