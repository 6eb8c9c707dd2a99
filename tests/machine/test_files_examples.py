"""The machine files: the built-in machines' (multicrank/data/machines/, presets.MACHINE_FILES)
and the examples in docs/machines/. Every one loads and evaluates, through the API and the
command line; each built-in machine's file is that machine."""

import filecmp
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import multicrank as mc
from multicrank.presets import MACHINE_FILES, MACHINES
from multicrank.pressure import EXAMPLE_COMPRESSOR_CSV

EXAMPLES = Path(__file__).resolve().parents[2] / "docs" / "machines"
PRESETS = Path(mc.__file__).resolve().parent / "data" / "machines"
FILES = sorted(EXAMPLES.glob("*.toml")) + sorted(PRESETS.glob("*.toml"))
SCRIPT = Path(sys.executable).with_name("multicrank")


def test_the_examples_are_there():
    assert {"v8-cross.toml", "workshop-compressor-csv.toml"} <= {path.name for path in EXAMPLES.glob("*.toml")}
    # One file per built-in machine, named after it, and no other.
    assert sorted(PRESETS.glob("*.toml")) == sorted(MACHINE_FILES.values())
    assert all(path.stem == name for name, path in MACHINE_FILES.items())
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
        [str(SCRIPT), "eval", "--machine", str(path), "--points", "8", "--format", "json"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    np.testing.assert_allclose(
        data["potential_energy"], engine.potential_energy(np.radians(data["phi_deg"])), rtol=1e-12, atol=1e-18
    )


@pytest.mark.parametrize("name", list(MACHINE_FILES))
def test_a_built_in_machine_is_its_file(name):
    machine = mc.Machine.from_toml(MACHINE_FILES[name])
    assert machine == MACHINES[name] and machine.name == name
    assert machine.note == MACHINES[name].note and len(machine.note) > 100  # why the numbers are what they are
