"""The faults a user can hit on the command line, each one line and an exit status that says
what happened: a machine that is not there (2), a file that cannot be written (2), Ctrl-C at
any moment (130). In-process (CliRunner) where a fault is injected, a real subprocess where a
real SIGINT is sent."""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from multicrank import cli
from multicrank.presets import MACHINES

SCRIPT = Path(sys.executable).with_name("multicrank")

# Every command that takes --machine (and its former name --engine), with what it needs
# besides to get as far as reading the machine.
MACHINE_COMMANDS = {
    "eval": ["eval"],
    "motion": ["motion", "--no-progress"],
    "simulate": ["simulate", "--no-progress"],
    "forces": ["forces"],
    "report": ["report", "--no-progress"],
    "sweep motion": ["sweep", "motion", "--rpm", "100", "--no-progress"],
    "optimize firing": ["optimize", "firing", "--no-progress"],
    "optimize counterweights": ["optimize", "counterweights", "--no-progress"],
}


def refused(args: list[str]) -> str:
    """The refusal of a command as its one line: exit status 2, no traceback."""
    result = CliRunner().invoke(cli.main, args)
    assert result.exit_code == 2, result.output
    assert isinstance(result.exception, SystemExit) and "Traceback" not in result.output
    (line,) = result.output.strip().splitlines()
    return line


@pytest.mark.parametrize("command", MACHINE_COMMANDS)
def test_a_machine_file_that_is_not_there_is_said_so(tmp_path, command):
    """`--machine nosuch.toml` says the file does not exist, naming the option and the path
    (it said 'neither a built-in machine nor a machine file')."""
    missing = tmp_path / "nosuch.toml"
    line = refused([*MACHINE_COMMANDS[command], "--machine", str(missing)])
    assert line == f"Error: --machine: {missing}: no such file"
    relative = refused([*MACHINE_COMMANDS[command], "--engine", "nosuch.toml"])
    assert relative == "Error: --engine: nosuch.toml: no such file"


@pytest.mark.parametrize("option", ["--machine", "--engine"])
@pytest.mark.parametrize("command", MACHINE_COMMANDS)
def test_an_unknown_machine_names_its_option_and_the_built_in_machines(command, option):
    """An unknown name names the option the user typed (--engine said '--machine') and lists
    every built-in machine."""
    line = refused([*MACHINE_COMMANDS[command], option, "steam-hammer"])
    assert line.startswith(f"Error: {option}: 'steam-hammer' is neither a built-in machine (")
    assert all(name in line for name in MACHINES)


def test_machine_and_engine_together_are_refused():
    line = refused(["eval", "--engine", "inline-6", "--machine", "inline-4"])
    assert "--machine" in line and "--engine" in line


def test_engine_still_reads_a_machine():
    by_engine = CliRunner().invoke(cli.main, ["eval", "--engine", "inline-6", "--points", "4", "--format", "csv"])
    by_machine = CliRunner().invoke(cli.main, ["eval", "--machine", "inline-6", "--points", "4", "--format", "csv"])
    assert by_engine.exit_code == 0 and by_engine.stdout == by_machine.stdout


# Every option that names a file to write and whose folder the user must provide (the sweeps
# and the report create theirs): the command, quick, with the option to append.
FILE_OPTIONS = {
    "motion --out": (["motion", "--machine", "slow-compressor", "--rpm", "100", "--no-progress"], "--out"),
    "motion --cycle": (["motion", "--machine", "slow-compressor", "--rpm", "100", "--no-progress"], "--cycle"),
    "simulate --out": (["simulate", "--machine", "slow-compressor", "--duration", "0.5", "--no-progress"], "--out"),
    "forces --out": (["forces", "--machine", "inline-4", "--max-order", "2"], "--out"),
    "optimize firing --out": (["optimize", "firing", "--machine", "marine-2t-twin", "--no-progress"], "--out"),
    "optimize counterweights --out": (
        ["optimize", "counterweights", "--machine", "marine-2t-twin", "--maxiter", "1", "--no-progress"],
        "--out",
    ),
}


@pytest.mark.parametrize("case", FILE_OPTIONS)
def test_a_file_into_a_folder_that_is_not_there_is_one_line(tmp_path, case):
    """`motion --out`, `motion --cycle`, `simulate --out` into a missing folder were a
    traceback and status 1: now one line naming the option and the path, status 2, before
    any work."""
    args, option = FILE_OPTIONS[case]
    target = tmp_path / "missing" / "x.csv"
    assert refused([*args, option, str(target)]) == f"Error: {option} {target}: {target.parent} does not exist"
    blocked = tmp_path / "a-file"
    blocked.write_text("not a folder")
    inside = blocked / "x.csv"
    assert refused([*args, option, str(inside)]) == f"Error: {option} {inside}: {blocked} is not a folder"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a-file"]


@pytest.mark.parametrize("option", ["--out", "--cycle"])
def test_a_file_that_fails_while_written_is_one_line(tmp_path, monkeypatch, option):
    """A write that fails once the work is done (a full disk): one line naming the option."""
    import multicrank._files as files

    def full_disk(path, *args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))

    monkeypatch.setattr(files, "open", full_disk, raising=False)
    target = tmp_path / "x.csv"
    line = refused([*FILE_OPTIONS["motion --out"][0], option, str(target)])
    assert line == f"Error: {option} {target}: {os.strerror(errno.ENOSPC)}"
    assert not list(tmp_path.iterdir())


def _interrupt(*args, **kwargs):
    raise KeyboardInterrupt


# Each command with a place to interrupt it early: reading the machine (or, for the gravity
# sweep and tables, which read none, the first thing each does).
EARLY = {
    **{name: (args, "multicrank.presets.machine_by_name_or_file") for name, args in MACHINE_COMMANDS.items()},
    "sweep": (["sweep", "--crank-ratio", "0.3", "--inclination", "90", "--u1", "1"], "multicrank.cli.sweep.grid_axes"),
    "tables": (["tables"], "multicrank.gravity.harmonics.harmonic_table"),
}


@pytest.mark.parametrize("command", EARLY)
def test_an_early_ctrl_c_exits_130_with_one_line(tmp_path, monkeypatch, command):
    """Ctrl-C while the machine is read (before any progress bar) was click's 'Aborted!' and
    status 1 (`sweep motion`) or a traceback: every command now says 'interrupted' and exits
    with 130, whenever it comes."""
    args, where = EARLY[command]
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(where, _interrupt)
    result = CliRunner().invoke(cli.main, args)
    assert result.exit_code == 130, result.output
    assert "Aborted" not in result.output and "Traceback" not in result.output
    assert result.output.strip().splitlines() == ["interrupted"]
    assert not list(tmp_path.iterdir())  # nothing written


def _sigint_as_ctrl_c() -> None:
    """In the child before it starts: SIGINT back to its default, so that Python makes it a
    KeyboardInterrupt. A test run started in the background of a script (CI, nohup, `&`)
    inherits SIGINT ignored, and Python then leaves it ignored: the child would never see the
    test's Ctrl-C."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _interrupted_once_started(args: list[str], sign: str, cwd: Path) -> subprocess.CompletedProcess:
    """Run the command, wait until ``sign`` is on its stderr (the work has started), send
    SIGINT and wait for it to end. The timeouts only guard against a hang."""
    child = subprocess.Popen(
        [str(SCRIPT), *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=cwd, preexec_fn=_sigint_as_ctrl_c
    )
    assert child.stderr is not None
    seen = b""
    try:
        while sign.encode() not in seen:
            chunk = os.read(child.stderr.fileno(), 4096)
            assert chunk, f"ended before {sign!r} appeared: {seen.decode(errors='replace')}"
            seen += chunk
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=300)
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()
    return subprocess.CompletedProcess(child.args, child.returncode, out.decode(), (seen + err).decode())


# 20 000 designs, each a steady state by the Python loop (a power-law load): minutes of work
# on two cores; its progress bar is the sign.
SWEEP_MOTION_WORK = ["sweep", "motion", "--machine", "inline-4", "--shaft-inertia", "0.1:1:100", "--g", "9:10:200",
                     "--load", "power:195:6000", "--progress"]  # fmt: skip


@pytest.mark.parametrize(
    ("args", "sign"),
    [
        # 1000 steady states over the machine's speed range: the progress bar is the sign.
        (["motion", "--points", "1000", "--progress"], "motion:"),
        (SWEEP_MOTION_WORK, "designs"),
    ],
    ids=["motion", "sweep motion"],
)
def test_ctrl_c_while_working_exits_130_with_one_line(tmp_path, args, sign):
    result = _interrupted_once_started(args, sign, tmp_path)
    assert result.returncode == 130, f"status {result.returncode} (0: finished first); stderr: {result.stderr}"
    assert "Traceback" not in result.stderr and "Aborted" not in result.stderr
    assert result.stderr.strip().splitlines()[-1].startswith("interrupted")
    assert result.stdout == "" and not list(tmp_path.iterdir())


def _help(*args: str) -> str:
    result = CliRunner().invoke(cli.main, [*args, "--help"])
    assert result.exit_code == 0, result.output
    return " ".join(result.stdout.split())  # click's wrapping undone


def test_sweep_motion_measures_the_rod_cg_from_the_piston_pin_as_everything_else():
    """--help said 'from the crank pin'; z_k is measured from the piston-pin axis (Cylinder,
    machine files, theory)."""
    import multicrank as mc

    documented = " ".join(mc.Cylinder.__doc__.split())
    assert "rod_cg : float z_k [m], the rod's centre of gravity measured from the piston-pin axis" in documented
    text = _help("sweep", "motion")
    assert "--rod-cg AXIS Rod centre of gravity from the piston-pin axis [m]." in text
    assert "crank pin" not in text


def test_sweep_motion_offers_no_constant_load_and_refuses_one_clearly(tmp_path):
    """--load offered 'a constant torque [N·m]', which the sweep always refused (a sweep has no
    drive): it is no longer offered, and refused before any work with a line naming --load
    and what it takes."""
    text = _help("sweep", "motion")
    load = text[text.index("--load LOAD") : text.index("--delta-target DELTA")]
    assert "balance" in load and "power:TORQUE:RPM[:EXPONENT]" in load and "constant torque" not in load
    sweep = ["sweep", "motion", "--rpm", "100", "--no-progress"]
    for torque in ("7", "-120.5"):
        line = refused([*sweep, "--load", torque])
        assert line.startswith(f"Error: --load = '{torque}': a constant torque is not a load a motion sweep takes")
        assert line.endswith("give balance or power:TORQUE:RPM[:EXPONENT]")
    config = tmp_path / "motion.toml"
    config.write_text('load = "7"\n[axes]\nrpm = 100\n')
    assert refused(["sweep", "motion", "--config", str(config)]).startswith(
        f"Error: --config {config}: load = '7': a constant torque"
    )
    config.write_text("load = 7\n[axes]\nrpm = 100\n")
    assert refused(["sweep", "motion", "--config", str(config)]) == (
        f"Error: --config {config}: load = 7; it is a string as --load takes it"
    )


# Each command with a former option name (the target δ's --delta) and the quick arguments
# to reach its check; then the values its check refuses.
RENAMED = {
    "motion": (["motion", "--machine", "slow-compressor", "--rpm", "100", "--no-progress"], ["5", "nan", "0", "1"]),
    "sweep motion": (
        ["sweep", "motion", "--machine", "slow-compressor", "--rpm", "100", "--no-progress"],
        ["0", "nan", "1e-12"],
    ),
}
NOTE = "note: --delta is now --delta-target (the old name goes in 0.3)"


@pytest.mark.parametrize("command", RENAMED)
def test_a_bad_value_under_a_former_name_is_one_line(command):
    """`--delta 5` printed the note on --delta's new name and then the error: two lines. A
    bad value is its one line, naming the option as typed, under either name."""
    args, bad = RENAMED[command]
    for value in bad:
        old = refused([*args, "--delta", value])
        assert old.startswith(f"Error: --delta = {float(value)} is out of range; allowed: "), old
        new = refused([*args, "--delta-target", value])
        assert new.startswith(f"Error: --delta-target = {float(value)} is out of range; allowed: "), new


@pytest.mark.parametrize("command", RENAMED)
def test_a_former_name_with_another_mistake_is_one_line(command):
    """A good value under the former name and a mistake elsewhere: the mistake alone (the
    note comes once a command has run)."""
    args, _ = RENAMED[command]
    assert "rpm = -5.0 is out of range" in refused([*args, "--delta", "0.04", "--rpm", "-5"])
    result = CliRunner().invoke(cli.main, [*args, "--delta", "0.04", "--format", "json"])
    assert result.exit_code == 0, result.output
    assert result.stderr.splitlines() == [NOTE]


def test_the_former_names_in_a_sweeps_config_and_outputs_with_a_mistake_are_one_line(tmp_path):
    """delta in --config and the outputs of 0.1 say so once the sweep has run: with a mistake
    (a bad target δ, an unknown output) the mistake is the one line."""
    config = tmp_path / "motion.toml"
    config.write_text("delta = 0.0\n")
    sweep = ["sweep", "motion", "--machine", "slow-compressor", "--rpm", "100", "--no-progress"]
    line = refused([*sweep, "--config", str(config)])
    assert line.startswith(f"Error: --config {config}: delta = 0.0 is out of range; allowed: delta >= 1e-9"), line
    config.write_text("delta = 0.04\n")
    assert refused([*sweep, "--config", str(config), "--outputs", "nosuch"]).startswith("Error: --outputs: outputs ")
    assert refused([*sweep, "--outputs", "delta_gravity_only,nosuch"]).startswith("Error: --outputs: outputs ")
    result = CliRunner().invoke(
        cli.main, [*sweep, "--config", str(config), "--outputs", "delta_gravity_only,flywheel_inertia"]
    )
    assert result.exit_code == 0, result.output
    assert result.stderr.splitlines() == [
        "note: delta in --config is now delta_target (the old name goes in 0.3)",
        "note: the output delta_gravity_only is now delta_coasting (the old name goes in 0.3)",
    ]
