"""`multicrank report` and `multicrank tables`, run as a user runs them, on reduced settings."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import multicrank as mc
from multicrank.presets import MACHINES, load_machine
from multicrank.report import DEFAULT_THRESHOLD, PAPER_TABLE_1

SCRIPT = Path(sys.executable).with_name("multicrank")


def run(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    result = subprocess.run([str(SCRIPT), *args], capture_output=True, text=True, timeout=300)
    if check:
        assert result.returncode == 0, result.stderr
    return result


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("report") / "report"
    _former_report(out)  # which the report replaces whole
    result = run(
        "report",
        "--out",
        str(out),
        "--machine",
        "inline-4",
        "--k-max",
        "4",
        "--n-max",
        "12",
        "--points",
        "91",
        "--no-progress",
    )
    assert "report written" in result.stdout
    return out


def test_report_files(report):
    names = {p.name for p in report.iterdir()}
    for stem in [
        "energy_2stroke",
        "energy_4stroke",
        "force_2stroke",
        "force_4stroke",
        "spectra_2stroke",
        "spectra_4stroke",
        "paper_truncation_error",
        "gravity_significance_k_lambda",
        "gravity_significance_machines",
        "layouts",
        "motion_speed",
        "motion_torques",
        "motion_speed_range",
        "motion_gravity_map",
        "motion_orders",
        "forces_bearing_loads",
    ]:
        assert f"{stem}.png" in names and f"{stem}.csv" in names
        assert (report / f"{stem}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for table in [
        "table1_two_stroke_single",
        "table2_four_stroke_single",
        "two_stroke_double",
        "four_stroke_double",
        "paper_table1_printed",
    ]:
        assert f"{table}.csv" in names
    page = (report / "index.html").read_text(encoding="utf-8")
    assert page.count("data:image/png;base64,") == 16  # self-contained
    for heading in [
        "The machine",
        "Gravity significance",
        "Layouts",
        "Harmonic spectra",
        "Tables 1 and 2",
        "truncated series",
        "Conventions",
        "Errata",
    ]:
        assert heading in page
    assert "agrees with the derived one in every cell" in page


def test_report_tables_are_the_phase_sum_rule(report):
    table1 = pd.read_csv(report / "table1_two_stroke_single.csv", index_col="n")
    assert list(table1.index) == [1, 2, 4, 6, 8, 10, 12] and list(table1.columns) == ["1", "2", "3", "4"]
    for n, ks in PAPER_TABLE_1.items():
        assert [int(k) for k in table1.columns if table1.loc[n, k]] == [k for k in ks if k <= 4]
    table2 = pd.read_csv(report / "table2_four_stroke_single.csv", index_col="n")
    assert table2.loc[1].tolist() == [1, 1, 0, 0]  # four-stroke: n = 1 survives for k = 1, 2 only
    assert table2.loc[6].tolist() == [1, 1, 1, 1]
    double = pd.read_csv(report / "two_stroke_double.csv", index_col="n")
    assert double.loc[1].tolist() == [1, 1, 1, 1]  # S_1 never vanishes for the double-acting two-stroke


def test_report_numbers_match_the_api(report):
    machine = MACHINES["inline-4"]
    # Parsed by Python's float, exact on any pandas (before 3.0 its parser may be an ulp off).
    curves = pd.read_csv(report / "force_4stroke.csv", dtype=str).astype(float)
    phi = np.radians(curves["phi_deg"].to_numpy())
    for k in range(1, 5):
        unit = mc.Machine(
            [machine.cylinders[0]], shaft_inertia=machine.shaft_inertia, strokes=machine.strokes, rpm=machine.rpm
        )
        design = {**unit.design(), "phases": mc.crank_phases(k, 4, "single")}
        np.testing.assert_allclose(curves[f"k{k}"], mc.generalized_force(phi, **design), rtol=1e-15, atol=1e-18)
    machines = pd.read_csv(report / "gravity_significance_machines.csv")
    assert set(machines["machine"]) == set(MACHINES)
    row = machines[machines.machine == "slow-compressor"].iloc[0]
    compressor = MACHINES["slow-compressor"]
    assert row.delta_g == pytest.approx(mc.speed_fluctuation(**compressor.design(row.rpm)), rel=1e-12)
    truncation = pd.read_csv(report / "paper_truncation_error.csv")
    at = (truncation.crank_ratio - 0.4).abs().idxmin()
    assert 0.2 < truncation.loc[at, "Lambda12_relative_error"] < 0.6  # "Λ_12 is 37 % off at λ = 0.4"
    spectra = pd.read_csv(report / "spectra_4stroke.csv")
    assert set(spectra[spectra.k == 4].n) <= {1, 2, 4, 6, 8, 10, 12}
    page = (report / "index.html").read_text(encoding="utf-8")
    delta = float(mc.speed_fluctuation(**MACHINES["inline-4"].design()))
    assert f"{delta:.3g}" in page
    verdict = "may be neglected" if delta < DEFAULT_THRESHOLD else "may NOT be neglected"
    assert verdict in page


def test_report_from_a_toml_machine(tmp_path):
    machine = MACHINES["marine-2t-twin"]
    cylinder = machine.cylinders[0]
    fields = ["crank_radius", "rod_length", "rod_cg", "piston_mass", "rod_mass", "crank_mass", "crank_cg_radius"]
    fields += ["counterweight_mass", "counterweight_radius", "bore"]
    lines = ['name = "my-twin"', 'layout = "inline-2-2t"', f"shaft_inertia = {machine.shaft_inertia!r}"]
    lines += [f"rpm = {machine.rpm!r}", f"rpm_range = {json.dumps(list(machine.rpm_range))}", "[cylinder]"]
    lines += [f"{key} = {getattr(cylinder, key)!r}" for key in fields]
    toml = tmp_path / "twin.toml"
    toml.write_text("\n".join(lines) + "\n")
    loaded = load_machine(toml)
    assert loaded.design()["u1"] == machine.design()["u1"]
    out = tmp_path / "rep"
    run(
        "report",
        "--out",
        str(out),
        "--machine",
        str(toml),
        "--k-max",
        "2",
        "--n-max",
        "4",
        "--points",
        "17",
        "--no-progress",
    )
    assert "my-twin" in (out / "index.html").read_text(encoding="utf-8")


def test_report_rejects_unknown_machines(tmp_path):
    result = run("report", "--out", str(tmp_path), "--machine", "steam-hammer", check=False)
    assert result.returncode == 2 and "steam-hammer" in result.stderr
    bad = tmp_path / "bad.toml"
    bad.write_text("crank_radius = 0.1\nwheels = 4\n")
    result = run("report", "--out", str(tmp_path), "--machine", str(bad), check=False)
    assert result.returncode == 2 and "wheels" in result.stderr


def test_tables_command_formats():
    text = run("tables", "--strokes", "2", "--k-max", "12", "--n-max", "12").stdout
    rows = [
        line
        for line in text.splitlines()
        if line.split()[:1] and line.split()[0].startswith("W_") and len(line.split()) == 13
    ]
    assert len(rows) == 7 and "".join(rows).count("●") == sum(len(v) for v in PAPER_TABLE_1.values())
    data = json.loads(run("tables", "--format", "json", "--n-max", "12").stdout)
    assert {int(n): ks for n, ks in data.items()} == PAPER_TABLE_1
    csv = run("tables", "--format", "csv", "--strokes", "4", "--n-max", "4", "--k-max", "3").stdout
    assert csv.splitlines() == ["n,1,2,3", "1,1,1,0", "2,1,1,0", "4,1,1,0"]


def test_help_texts_name_degrees():
    assert "DEGREES" in run("eval", "--help").stdout
    assert "DEGREES" in run("sweep", "--help").stdout
    for command in ("eval", "tables", "sweep", "report"):
        assert command in run("--help").stdout


def test_report_layouts_table(report):
    layouts = pd.read_csv(report / "layouts.csv")
    assert {"v8-cross", "boxer-4", "w12", "v-180-2", "twin-270"} <= set(layouts["layout"])
    machine = MACHINES["inline-4"]
    v_twin = mc.Machine.from_layout("v-twin-90", machine.cylinders[0], shaft_inertia=machine.shaft_inertia).engine(
        machine.rpm
    )
    row = layouts[layouts.layout == "v-twin-90"].iloc[0]
    assert row.energy_range == pytest.approx(float(v_twin.speed_fluctuation()), rel=1e-12)
    assert row.leading_harmonic == v_twin.leading_harmonic()[0]


def test_report_of_a_machine_that_is_not_in_line(tmp_path):
    """A V8 from a layout file: δ_g is the whole machine's; the k-crank sections say they use
    its first cylinder."""
    example = Path(__file__).resolve().parents[2] / "docs" / "machines" / "v8-cross.toml"
    out = tmp_path / "v8"
    run(
        "report",
        "--out",
        str(out),
        "--machine",
        str(example),
        "--k-max",
        "2",
        "--n-max",
        "4",
        "--points",
        "17",
        "--no-progress",
    )
    page = (out / "index.html").read_text(encoding="utf-8")
    machine = mc.Machine.from_toml(example)
    assert f"{float(machine.engine().speed_fluctuation()):.3g}" in page
    assert "is not a machine of identical cylinders" in page and "45°, 135°" in page
    curves = pd.read_csv(out / "energy_2stroke.csv", dtype=str).astype(float)
    unit = mc.Machine(
        [machine.cylinders[0]], shaft_inertia=machine.shaft_inertia, strokes=machine.strokes, rpm=machine.rpm
    ).design()
    phi = np.radians(curves["phi_deg"].to_numpy())
    np.testing.assert_allclose(
        curves["k2"], mc.potential_energy(phi, **{**unit, "phases": mc.crank_phases(2, 2)}), rtol=1e-15, atol=1e-18
    )


def test_a_flywheel_target_no_shaft_gives_is_said_not_fatal(tmp_path):
    """The slow diesel's shaft and propeller keep δ far below its class's target: the flywheel
    table says why there is none, and the report is written."""
    out = tmp_path / "diesel"
    run("report", "--out", str(out), "--machine", "slow-diesel-12", "--k-max", "2", "--n-max", "4",
        "--points", "17", "--no-progress")  # fmt: skip
    page = (out / "index.html").read_text(encoding="utf-8")
    assert "no shaft inertia gives it" in page and "is unreachable" in page
    assert "What to change" in page


def test_report_leads_with_the_machines_motion(report):
    """The first section is the steady running with and without gravity and the flywheel,
    and its numbers are the API's."""
    page = (report / "index.html").read_text(encoding="utf-8")
    assert page.index("What gravity does to this machine") < page.index("<h2>The machine</h2>")
    machine = MACHINES["inline-4"]
    state = mc.steady_state(machine, rpm=machine.rpm)
    assert f"{state.delta:.5g}" in page and f"{state.delta_without_gravity:.5g}" in page
    sized = mc.flywheel_inertia(machine, delta=1 / 100, rpm=machine.rpm)  # the vehicle class's limit
    assert f"{sized.shaft_inertia:.6g} kg·m²" in page
    assert f"{sized.shaft_inertia_without_gravity:.6g} kg·m²" in page
    speed = pd.read_csv(report / "motion_speed.csv")
    np.testing.assert_allclose(speed["rpm_with_gravity"], state.omega * 30 / np.pi, rtol=1e-10)
    torques = pd.read_csv(report / "motion_torques.csv")
    np.testing.assert_allclose(torques["gravity"], machine.gravity_torque(np.radians(torques["phi_deg"])), atol=1e-9)
    orders = pd.read_csv(report / "motion_orders.csv")
    assert set(orders["order"] * 2) <= set(range(0, 100))  # half orders at most: four-stroke
    ranged = pd.read_csv(report / "motion_speed_range.csv")
    low, high = machine.rpm_range
    assert ranged["rpm"].min() == pytest.approx(low) and ranged["rpm"].max() == pytest.approx(high)
    at_speed = ranged.iloc[(ranged["rpm"] - 2000).abs().idxmin()]
    assert at_speed["delta"] == pytest.approx(mc.steady_state(machine, rpm=at_speed["rpm"]).delta, rel=1e-9)


def test_report_maps_where_gravity_matters(report):
    """The map over speed × shaft inertia is mc.motion_sweep of the machine's variants, with
    δ_g beside it, and the page says what it shows."""
    from multicrank.report import ReportSettings

    machine = MACHINES["inline-4"]
    frame = pd.read_csv(report / "motion_gravity_map.csv", dtype=str)
    columns = ["shaft_inertia", "rpm", "delta", "delta_without_gravity", "gravity_effect", "stalled", "near_stall"]
    assert list(frame.columns) == [*columns, "delta_g"]
    frame = frame.astype({name: float for name in [*columns, "delta_g"] if "stall" not in name})
    points = ReportSettings().gravity_map_points
    assert len(frame) == points**2
    inertias, speeds = np.unique(frame["shaft_inertia"]), np.unique(frame["rpm"])
    assert inertias[[0, -1]] == pytest.approx([0.25 * machine.shaft_inertia, 4 * machine.shaft_inertia])
    assert speeds[[0, -1]] == pytest.approx(machine.rpm_range)
    grid = mc.MachineGrid(machine, shaft_inertia=inertias, rpm=speeds)
    expected = mc.motion_sweep(machine, grid, outputs=["delta", "delta_without_gravity", "gravity_effect"])
    for name in ("shaft_inertia", "rpm", "delta", "delta_without_gravity", "gravity_effect"):
        np.testing.assert_allclose(frame[name], expected[name], rtol=1e-12, err_msg=name)
    assert (frame["stalled"] == "False").all() and not expected["stalled"].any()
    # A light flywheel at low speed nearly stops each cycle: marked, as the sweep marks it.
    np.testing.assert_array_equal(frame["near_stall"] == "True", expected["near_stall"])
    np.testing.assert_array_equal(expected["near_stall"], expected["delta"] > mc.NEAR_STALL_DELTA)
    row = frame.iloc[-1]
    variant = machine.replace(shaft_inertia=row.shaft_inertia)
    assert row.delta_g == pytest.approx(float(variant.engine(row.rpm).speed_fluctuation()), rel=1e-12)
    page = (report / "index.html").read_text(encoding="utf-8")
    assert "Where gravity matters" in page and f"{points} × {points} exact steady states" in page


# The smallest report the command writes: what the interruption tests need, in seconds.
SMALL = ["--machine", "slow-compressor", "--k-max", "2", "--n-max", "4", "--points", "16", "--no-progress"]


def _former_report(folder: Path) -> dict[str, bytes]:
    """A former report in ``folder``: its page, a figure the new one rewrites, a table it does not."""
    files = {"index.html": b"<html>the former report</html>", "motion_speed.png": b"\x89PNG old", "old.csv": b"a\n1\n"}
    folder.mkdir()
    for name, data in files.items():
        (folder / name).write_bytes(data)
    return files


def test_a_finished_report_replaces_the_former_one_whole(report):
    names = {path.name for path in report.iterdir()}
    assert "old.csv" not in names and "the former report" not in (report / "index.html").read_text(encoding="utf-8")
    assert (report / "motion_speed.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [path.name for path in report.parent.iterdir()] == ["report"]  # no temporary folder left


def test_an_interrupted_report_leaves_the_former_one_whole(tmp_path, monkeypatch):
    """Ctrl-C during `multicrank report` left the folder mixing the former report with new
    files: the new one is written beside it and replaces it whole only once complete."""
    from click.testing import CliRunner

    import multicrank.report.html as report_html
    from multicrank import cli

    out = tmp_path / "report"
    former = _former_report(out)
    written: list[str] = []

    def interrupted(*args, **kwargs):  # Ctrl-C at the spectra, after the motion and the curves are written
        written.extend(path.name for path in tmp_path.rglob("*.png") if path.parent != out)
        raise KeyboardInterrupt

    monkeypatch.setattr(report_html, "spectra_figure", interrupted)
    result = CliRunner().invoke(cli.main, ["report", "--out", str(out), *SMALL])
    assert result.exit_code == 130 and "Traceback" not in result.output, result.output
    assert "motion_speed.png" in written and "energy_2stroke.png" in written  # it had written files
    assert {path.name: path.read_bytes() for path in out.iterdir()} == former
    assert [path.name for path in tmp_path.iterdir()] == ["report"]  # no temporary folder left


def test_a_folder_that_is_not_a_report_is_refused_before_any_work(tmp_path, monkeypatch):
    """The report replaces its folder whole, so a folder holding other files (or the current
    folder) is refused, one line naming it, and left as it was."""
    from click.testing import CliRunner

    from multicrank import cli

    (tmp_path / "notes.txt").write_text("mine")
    (tmp_path / "index.html").write_text("mine too")
    cases = [(str(tmp_path), "notes.txt"), (str(tmp_path / "notes.txt" / "r"), "is a file"), (".", "current folder")]
    for out, named in cases:
        if out == ".":
            monkeypatch.chdir(tmp_path)
        result = CliRunner().invoke(cli.main, ["report", "--out", out, *SMALL])
        assert result.exit_code == 2, result.output
        (line,) = result.output.strip().splitlines()
        assert line.startswith(f"Error: --out {out}") and named in line
        assert sorted(path.name for path in tmp_path.iterdir()) == ["index.html", "notes.txt"]
