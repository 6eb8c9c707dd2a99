"""A machine file states the δ its machine is meant to run at (``delta_target``, or its
``class``), and the report's flywheel section sizes the flywheel for it (issue 26, item 7):
checked by the steady state of the machine with that flywheel, which must run at that δ."""

from __future__ import annotations

import pytest

import multicrank as mc
from multicrank.presets import MACHINE_FILES, MACHINES, SPEED_FLUCTUATION
from multicrank.report import ReportSettings
from multicrank.report.motion import motion_html, motion_results

PRESET = MACHINE_FILES["slow-compressor"].read_text(encoding="utf-8")


def machine_file(tmp_path, *lines: str) -> mc.Machine:
    """The slow compressor's file under another name (so that no preset's class applies),
    with ``lines`` added at its top level."""
    text = PRESET.replace('name = "slow-compressor"', 'name = "my-compressor"\n' + "\n".join(lines))
    path = tmp_path / "machine.toml"
    path.write_text(text, encoding="utf-8")
    return mc.Machine.from_toml(path)


def test_a_machine_file_states_its_target(tmp_path):
    assert machine_file(tmp_path).delta_target is None
    assert machine_file(tmp_path, "delta_target = 0.025").delta_target == 0.025
    assert machine_file(tmp_path, 'class = "vehicle engine"').delta_target == 1 / 100
    both = machine_file(tmp_path, 'class = "compressor"', "delta_target = 0.03")
    assert both.delta_target == 0.03  # the explicit target wins
    assert both.replace(shaft_inertia=200.0).delta_target == 0.03
    assert both != both.replace(delta_target=None)


@pytest.mark.parametrize(
    ("line", "named"),
    [
        ('class = "steam hammer"', "class"),
        ("delta_target = 0", "delta_target"),
        ("delta_target = -0.1", "delta_target"),
        ('delta_target = "1/20"', "delta_target"),
    ],
)
def test_a_bad_target_names_its_key(tmp_path, line, named):
    with pytest.raises(mc.MechanismError, match=named):
        machine_file(tmp_path, line)


def test_the_report_sizes_the_flywheel_for_the_files_target(tmp_path):
    """Without a target the section returns the flywheel as built (without gravity); with one, a flywheel whose
    exact steady state has that δ (steady_state of the machine with it), and it says so."""
    settings = dict(gravity_map_points=2)
    plain = machine_file(tmp_path)
    results = motion_results(ReportSettings(machine=plain, **settings), speeds=2)
    assert "no target known" in results.target_source
    assert results.flywheel.shaft_inertia_without_gravity == pytest.approx(plain.shaft_inertia, rel=1e-6)

    stated = machine_file(tmp_path, 'class = "compressor"')
    target = SPEED_FLUCTUATION["compressor"][1]
    results = motion_results(ReportSettings(machine=stated, **settings), speeds=2)
    assert results.target == target and "delta_target" in results.target_source
    inertia = results.flywheel.shaft_inertia
    assert abs(inertia / plain.shaft_inertia - 1) > 0.2  # a flywheel of its own, not the one it has
    sized = mc.steady_state(stated.replace(shaft_inertia=inertia), rpm=stated.rpm)
    assert sized.delta == pytest.approx(target, rel=1e-6)
    page = motion_html(results, stated, {name: "" for name in FIGURES}, 1 / 3000)
    assert f"{inertia:.6g} kg·m²" in page and "delta_target" in page

    asked = motion_results(ReportSettings(machine=stated, delta_target=0.04, **settings), speeds=2)
    assert asked.target == 0.04  # --delta-target first


def test_a_preset_keeps_its_class_and_a_changed_one_does_not():
    compressor = MACHINES["slow-compressor"]
    results = motion_results(ReportSettings(machine=compressor, gravity_map_points=2), speeds=2)
    assert results.target == SPEED_FLUCTUATION["compressor"][1] and "compressor class" in results.target_source


FIGURES = ("motion_speed", "motion_torques", "motion_speed_range", "motion_gravity_map", "motion_orders")


def test_the_reports_delta_is_the_former_name_of_delta_target(tmp_path, monkeypatch):
    """multicrank report --delta-target sets the δ the flywheel is sized for; --delta, its
    name of 0.1, still does, with one line on stderr naming the new name."""
    from click.testing import CliRunner

    import multicrank.report.html as report_html
    from multicrank import cli

    asked: list[float | None] = []

    def write_report(out, settings, progress=True):  # the settings the command built, no report
        asked.append(settings.delta_target)
        return tmp_path / "index.html"

    monkeypatch.setattr(report_html, "write_report", write_report)
    args = ["report", "--out", str(tmp_path / "report"), "--machine", "slow-compressor", "--no-progress"]
    new = CliRunner().invoke(cli.main, [*args, "--delta-target", "0.04"])
    assert new.exit_code == 0 and new.stderr == "", new.output
    old = CliRunner().invoke(cli.main, [*args, "--delta", "0.03"])
    assert old.exit_code == 0, old.output
    assert old.stderr.splitlines() == ["note: --delta is now --delta-target (the old name goes in 0.3)"]
    assert asked == [0.04, 0.03]
