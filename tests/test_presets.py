"""The built-in machines: each a full mc.Machine whose flywheel gives the usual coefficient of
speed fluctuation δ of its class, by the textbook estimate δ ≈ ΔE/(mean J · ω²)."""

import math
import re
import subprocess
import sys

import numpy as np
import pytest

import multicrank as mc
from multicrank import presets
from multicrank.presets import MACHINE_CLASSES, MACHINES, SPEED_FLUCTUATION


def estimated_delta(machine, rpm=None, points_per_revolution=8192):
    """The textbook estimate of δ at ``rpm`` (default the machine's): ΔE/(mean(J) ω²), ΔE the
    largest swing over one cycle of ∫(M − mean M) dφ, M = gas + gravity + inertia torque
    (−½J'ω²) at steady speed, the load taking the mean (trapezoidal rule on a fine grid)."""
    omega = math.pi * (machine.rpm if rpm is None else rpm) / 30
    phi = np.linspace(0.0, machine.cycle, points_per_revolution * machine.strokes // 2 + 1)
    torque = machine.gas_torque(phi) + machine.gravity_torque(phi) + machine.inertia_torque(phi, omega)
    excess = torque - np.trapezoid(torque, phi) / machine.cycle
    energy = np.concatenate(([0.0], np.cumsum(0.5 * (excess[1:] + excess[:-1]) * np.diff(phi))))
    inertia, _ = machine.reduced_inertia(phi)
    mean_inertia = np.trapezoid(inertia, phi) / machine.cycle
    return (energy.max() - energy.min()) / (mean_inertia * omega**2)


def test_the_estimate_of_an_unbalanced_flywheel():
    """A rotating unbalance m·ρ alone (no reciprocating mass, no gas): gravity trades 2 m g ρ of
    energy per revolution against a constant inertia, δ = 2 m g ρ/(I_w ω²)."""
    web = mc.Cylinder(
        crank_radius=0.1,
        rod_length=0.4,
        piston_mass=0.0,
        rod_mass=0.0,
        rod_cg=0.0,
        crank_mass=30.0,
        crank_cg_radius=0.2,
    )
    machine = mc.Machine([web], shaft_inertia=12.0, rpm=60.0)
    omega = 2 * math.pi
    expected = 2 * 30.0 * 0.2 * mc.STANDARD_GRAVITY / (12.0 * omega**2)
    assert estimated_delta(machine) == pytest.approx(expected, rel=1e-6)
    assert estimated_delta(machine, rpm=120.0) == pytest.approx(expected / 4, rel=1e-6)


def test_the_first_presets_keep_their_names():
    assert {"slow-compressor", "marine-2t-twin", "inline-4", "inline-6", "slow-diesel-12"} <= set(MACHINES)
    assert set(MACHINE_CLASSES) == set(MACHINES) and set(MACHINE_CLASSES.values()) <= set(SPEED_FLUCTUATION)
    with pytest.raises(AttributeError):
        presets.NO_SUCH_PRESET  # noqa: B018


@pytest.mark.parametrize("name", list(MACHINES))
def test_each_preset_has_the_speed_fluctuation_of_its_class(name):
    machine = MACHINES[name]
    assert isinstance(machine, mc.Machine) and machine.name == name
    kind = MACHINE_CLASSES[name]
    low, high = SPEED_FLUCTUATION[kind]
    delta = estimated_delta(machine)
    assert low <= delta <= high, f"{name}: δ ≈ 1/{1 / delta:.0f}, outside its class {kind} (1/{1 / high:.0f} …)"
    # The note names the class and states the δ it gets (to 5 %).
    assert f"class: {kind}" in machine.note
    (stated,) = re.findall(r"δ ≈ 1/(\d+)", machine.note)
    assert 1 / delta == pytest.approx(float(stated), rel=0.05)


@pytest.mark.parametrize("name", list(MACHINES))
def test_each_preset_is_a_whole_machine(name):
    machine = MACHINES[name]
    assert machine.rpm is not None and machine.rpm_range is not None
    assert machine.rpm_range[0] <= machine.rpm <= machine.rpm_range[1]
    for cylinder in machine.cylinders:
        assert cylinder.bore > 0 and isinstance(cylinder.pressure, mc.IndicatorDiagram)
        assert cylinder.pressure.cycle == pytest.approx(machine.cycle, rel=1e-15)
    phi = np.linspace(0.0, machine.cycle, 20001)
    work = np.trapezoid(machine.gas_torque(phi), phi)
    # Engines give work, compressors take it.
    assert (work < 0) == (MACHINE_CLASSES[name] == "compressor")
    # The gravity engine at the running speed is the one the report and the CLI use.
    assert machine.engine().name == f"{name} at {machine.rpm:g} rpm"


def test_the_machines_are_in_the_order_of_their_files():
    assert list(presets.MACHINES) == list(presets.MACHINE_FILES)
    assert presets.DEFAULT_MACHINE_NAME == "slow-compressor"
    assert presets.DEFAULT_MACHINE is presets.MACHINES["slow-compressor"]


@pytest.mark.parametrize(
    ("old", "new"),
    [
        ("ENGINES", "MACHINES"),
        ("DEFAULT_ENGINE_NAME", "DEFAULT_MACHINE_NAME"),
        ("DEFAULT_ENGINE", "DEFAULT_MACHINE"),
        ("engine_by_name_or_file", "machine_by_name_or_file"),
        ("load_engine", "load_machine"),
    ],
)
def test_the_former_names_still_work_and_warn(old, new):
    """0.1's names of the built-in machines are the same objects, read with a DeprecationWarning."""
    said = rf"multicrank\.presets\.{old} is deprecated .* use multicrank\.presets\.{new}"
    with pytest.warns(DeprecationWarning, match=said):
        value = getattr(presets, old)
    assert value is getattr(presets, new)
    assert old not in presets.__all__


def test_each_preset_is_read_from_its_file_by_the_one_loader():
    for name, path in presets.MACHINE_FILES.items():
        assert path.parent.name == "machines" and path.parent.parent.name == "data"
        assert mc.Machine.from_toml(path) == MACHINES[name]
        assert presets.machine_by_name_or_file(path) == presets.machine_by_name_or_file(name)


def test_double_acting_compressors_work_both_faces():
    for name in ("slow-compressor", "boxer-compressor"):
        for cylinder in MACHINES[name].cylinders:
            assert cylinder.piston_rod_diameter > 0 and isinstance(cylinder.pressure_crank_end, mc.IndicatorDiagram)


def test_presets_are_built_on_first_use():
    code = (
        "import sys, multicrank as mc\n"
        "assert 'scipy' not in sys.modules, 'import multicrank built the presets'\n"
        "names = list(mc.presets.MACHINES)\n"
        "assert 'scipy' not in sys.modules\n"
        "mc.presets.MACHINES['inline-4']\n"
        "assert 'scipy' in sys.modules\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr


@pytest.mark.parametrize("name", list(MACHINES))
def test_each_preset_runs_with_the_delta_of_its_class_exactly(name):
    """The exact steady state (not only the textbook estimate the flywheels were sized with)
    puts every preset's δ at its running speed inside its class."""
    machine = MACHINES[name]
    low, high = SPEED_FLUCTUATION[MACHINE_CLASSES[name]]
    state = mc.steady_state(machine, rpm=machine.rpm)
    assert low <= state.delta <= high
    assert low <= state.delta_without_gravity <= high
