"""The example scripts in docs/examples run, print their summary and draw their figure (short runs)."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"


def load(name):
    spec = importlib.util.spec_from_file_location(f"example_{name}", EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_startup_runs_up_toward_the_propeller_speed(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    figure = tmp_path / "startup.png"
    result = load("startup").main(["--duration", "0.4", "--png", str(figure)])
    assert not result.stalled
    assert result.rpm[-1] > 2 * result.rpm[0]  # from 300 rpm, on its way to 1500
    assert result.energy_drift < 1e-5
    assert "rpm (last cycle)" in capsys.readouterr().out
    assert figure.stat().st_size > 10_000


def test_rundown_stalls_on_a_compression(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    figure = tmp_path / "rundown.png"
    result = load("rundown").main(["--rpm", "150", "--duration", "5", "--png", str(figure)])
    assert result.stalled and result.omega[-1] == 0.0
    assert result.gas_torque[-1] < 0  # it stopped against the gas
    assert result.energy_drift < 1e-7
    assert "stalled after" in capsys.readouterr().out
    assert figure.stat().st_size > 10_000
    assert math.isclose(result.time[-1], result.stall_time)
