"""The machine files in docs/machines/: every one loads and evaluates, through the API and
the command line; those that restate a preset build the preset's machine."""

import filecmp
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import multicrank as mc
from multicrank.presets import ENGINES
from multicrank.pressure import EXAMPLE_COMPRESSOR_CSV

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "machines"
FILES = sorted(EXAMPLES.glob("*.toml"))
SCRIPT = Path(sys.executable).with_name("multicrank")


def test_the_examples_are_there():
    names = {path.name for path in FILES}
    assert {
        "slow-compressor.toml",
        "inline-four.toml",
        "v8-cross.toml",
        "boxer-compressor.toml",
        "workshop-compressor-csv.toml",
    } <= names
    # The CSV beside them is multicrank's example table, unchanged.
    assert filecmp.cmp(EXAMPLES / "compressor_synthetic.csv", EXAMPLE_COMPRESSOR_CSV, shallow=False)


@pytest.mark.parametrize("path", FILES, ids=[path.stem for path in FILES])
def test_every_example_loads_and_evaluates(path):
    machine = mc.Machine.from_toml(path)
    assert machine.rpm is not None and machine.note
    phi = np.linspace(0.0, machine.cycle, 1441)
    j, dj = machine.reduced_inertia(phi)
    torques = [
        machine.gas_torque(phi),
        machine.gravity_torque(phi),
        machine.inertia_torque(phi, machine.rpm * np.pi / 30),
    ]
    assert np.all(j >= machine.shaft_inertia) and all(np.all(np.isfinite(t)) for t in [dj, *torques])
    assert np.ptp(torques[0]) > 0  # every example has a gas pressure
    engine = machine.engine()
    assert len(engine) == len(machine) and np.isfinite(engine.speed_fluctuation())
    result = subprocess.run(
        [str(SCRIPT), "eval", "--engine", str(path), "--points", "8", "--format", "json"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    np.testing.assert_allclose(
        data["potential_energy"], engine.potential_energy(np.radians(data["phi_deg"])), rtol=1e-12, atol=1e-18
    )


@pytest.mark.parametrize(
    "file, preset",
    [("slow-compressor", "slow-compressor"), ("inline-four", "inline-4"), ("boxer-compressor", "boxer-compressor")],
)
def test_examples_that_restate_a_preset_are_the_preset(file, preset):
    machine, expected = mc.Machine.from_toml(EXAMPLES / f"{file}.toml"), ENGINES[preset]
    assert (machine.name, machine.shaft_inertia, machine.strokes, machine.rpm, machine.rpm_range) == (
        expected.name,
        expected.shaft_inertia,
        expected.strokes,
        expected.rpm,
        expected.rpm_range,
    )
    phi = np.linspace(0.0, expected.cycle, 2881)
    np.testing.assert_allclose([c.phase for c in machine.cylinders], [c.phase for c in expected.cylinders], atol=1e-12)
    np.testing.assert_allclose(
        machine.gas_torque(phi), expected.gas_torque(phi), rtol=1e-9, atol=1e-9 * np.ptp(expected.gas_torque(phi))
    )
    np.testing.assert_allclose(machine.gravity_torque(phi), expected.gravity_torque(phi), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(machine.reduced_inertia(phi)[0], expected.reduced_inertia(phi)[0], rtol=1e-14)
