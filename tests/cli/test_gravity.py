"""The `multicrank` console command, run as a user would (a real subprocess)."""

from __future__ import annotations

import csv
import io
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import multicrank as mc
from multicrank.presets import DEFAULT_MACHINE

# The console script installed beside this interpreter (a venv need not be on PATH).
SCRIPT = Path(sys.executable).with_name("multicrank")


def run(*args: str) -> str:
    result = subprocess.run([str(SCRIPT), *args], capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    return result.stdout


def test_eval_table_names_the_machine():
    out = run("eval", "--points", "6")
    assert DEFAULT_MACHINE.name in out
    assert "Q_u*" in out and "U_w*" in out
    table = out.split("Q_u*")[1].strip().splitlines()
    assert len(table) == 6 and all(len(line.split()) == 3 for line in table)


def test_eval_csv_numbers_match_the_api():
    out = run("eval", "--points", "12", "--format", "csv", "--cranks", "3", "--strokes", "4", "--inclination", "60")
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == 12
    # The default machine (double acting) on three cranks of a four-stroke cycle, tilted to 60°.
    first = DEFAULT_MACHINE.cylinders[0].replace(inclination=float(np.radians(60.0)))
    machine = DEFAULT_MACHINE.replace(
        cylinders=[first.replace(phase=float(a)) for a in mc.crank_phases(3, 4, "double")], strokes=4, shaft=None
    )  # three cylinders: the compressor's shaft (one cylinder's node) does not fit them
    phi = np.radians([float(r["phi_deg"]) for r in rows])
    np.testing.assert_array_equal(
        [float(r["potential_energy"]) for r in rows], mc.potential_energy(phi, **machine.design())
    )
    np.testing.assert_array_equal(
        [float(r["generalized_force"]) for r in rows], mc.generalized_force(phi, **machine.design())
    )


def test_eval_json():
    data = json.loads(run("eval", "--points", "4", "--format", "json"))
    assert data["phi_deg"] == [0.0, 90.0, 180.0, 270.0]
    assert data["potential_energy"][0] == 0.0
    assert data["machine"]["crank_ratio"] == pytest.approx(DEFAULT_MACHINE.cylinders[0].crank_ratio)


def test_bad_option_is_a_clear_error():
    result = subprocess.run([str(SCRIPT), "eval", "--strokes", "3"], capture_output=True, text=True, timeout=600)
    assert result.returncode == 2
    assert "strokes" in result.stderr


def test_eval_takes_any_builtin_machine_and_rejects_unknown_ones():
    out = run("eval", "--machine", "inline-6", "--points", "4", "--format", "json")
    assert json.loads(out)["machine"]["cranks"] == 6
    result = subprocess.run(
        [str(SCRIPT), "eval", "--machine", "steam-hammer"], capture_output=True, text=True, timeout=600
    )
    assert result.returncode == 2 and "steam-hammer" in result.stderr


def test_engine_is_the_former_name_of_the_machine_option():
    """--engine, the option's name of 0.1, is the same option as --machine, and the help says so."""
    assert run("eval", "--engine", "inline-6", "--points", "4", "--format", "json") == run(
        "eval", "--machine", "inline-6", "--points", "4", "--format", "json"
    )
    for command in ("eval", "motion", "simulate", "report"):
        assert "--machine, --engine NAME|FILE" in run(command, "--help")
    result = subprocess.run(
        [str(SCRIPT), "eval", "--engine", "steam-hammer"], capture_output=True, text=True, timeout=600
    )
    assert result.returncode == 2 and "--engine: " in result.stderr  # the option typed


def _run_failing(*args: str) -> subprocess.CompletedProcess:
    result = subprocess.run([str(SCRIPT), *args], capture_output=True, text=True, timeout=600)
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
    return result


def test_a_mistake_in_a_machine_file_is_one_line_and_status_two(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(
        'shaft_inertia = 1.0\n[cylinder]\ncrank_radius = 0.1\nrod_length = "long"\npiston_mass = 1\n'
        "rod_mass = 1\nrod_cg = 0.2\n"
    )
    for command in (["eval"], ["report", "--out", str(tmp_path / "out"), "--no-progress"]):
        result = _run_failing(*command, "--machine", str(bad))
        (line,) = result.stderr.strip().splitlines()
        assert line.startswith("Error: ") and str(bad) in line and "cylinder.rod_length" in line
    assert not (tmp_path / "out").exists()


def test_a_machine_without_a_speed_needs_one(tmp_path):
    slow = tmp_path / "slow.toml"
    slow.write_text(
        "shaft_inertia = 45.0\n[cylinder]\ncrank_radius = 0.15\nrod_length = 0.6\npiston_mass = 85\n"
        "rod_mass = 60\nrod_cg = 0.4\n"
    )
    (line,) = _run_failing("eval", "--machine", str(slow)).stderr.strip().splitlines()
    assert "--rpm" in line
    report = _run_failing("report", "--machine", str(slow), "--out", str(tmp_path / "out"), "--no-progress")
    assert "rpm" in report.stderr and not (tmp_path / "out").exists()
    data = json.loads(run("eval", "--machine", str(slow), "--rpm", "120", "--points", "4", "--format", "json"))
    machine = mc.Machine.from_toml(slow)
    np.testing.assert_array_equal(
        data["generalized_force"], mc.generalized_force(np.radians(data["phi_deg"]), **machine.design(120))
    )


def test_eval_of_a_machine_of_unequal_cylinders_uses_its_engine():
    data = json.loads(run("eval", "--machine", "genset-v12", "--points", "6", "--format", "json"))
    from multicrank.presets import MACHINES

    engine = MACHINES["genset-v12"].engine()
    assert data["machine"]["cylinders"] == 12 and "cranks" not in data["machine"]
    np.testing.assert_allclose(data["machine"]["phases_deg"], np.degrees(engine.phase), rtol=1e-15)
    np.testing.assert_array_equal(data["potential_energy"], engine.potential_energy(np.radians(data["phi_deg"])))


def test_eval_overrides_keep_gravity_and_leave_the_gas_cycle_behind():
    """--strokes 2 on a four-stroke engine: U* and Q* of its cylinder on a two-stroke crank."""
    from multicrank.presets import MACHINES

    data = json.loads(run("eval", "--machine", "inline-4", "--strokes", "2", "--cranks", "3", "--format", "json"))
    preset = MACHINES["inline-4"]
    first = preset.cylinders[0].replace(pressure=None)
    machine = mc.Machine(
        [first.replace(phase=float(a)) for a in mc.crank_phases(3, 2)], shaft_inertia=preset.shaft_inertia
    )
    np.testing.assert_array_equal(
        data["generalized_force"], mc.generalized_force(np.radians(data["phi_deg"]), **machine.design(preset.rpm))
    )
