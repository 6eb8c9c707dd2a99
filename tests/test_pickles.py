"""Pickles keep loading, and the public value classes compare by value (issue 19, items 1 and 5).

tests/data/pickles-0.1.0.pickle was written by the 0.1.0 wheel, before the package was split
into subpackages: ``{"version": "0.1.0", "objects": {...}}``. Its classes are named by 0.1's
module paths (``multicrank.engines.Engine``, ``multicrank.pressure.IndicatorDiagram``, …) and
its indicator diagrams carry their SciPy interpolant. Each object must load, and equal the same
object built now.
"""

from __future__ import annotations

import copy
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import multicrank as mc
from multicrank.presets import LAYOUTS, MACHINES

DATA = Path(__file__).resolve().parent / "data" / "pickles-0.1.0.pickle"


def built_now() -> dict[str, object]:
    """The objects of the 0.1.0 pickle, as the current code builds them."""
    compressor = MACHINES["slow-compressor"]
    return {
        "machine:slow-compressor": compressor,
        "machine:inline-4": MACHINES["inline-4"],
        "machine:boxer-compressor": MACHINES["boxer-compressor"],
        "cylinder": compressor.cylinders[0],
        "diagram": compressor.cylinders[0].pressure,
        "layout": LAYOUTS["v8-cross"],
        "engine": mc.layout_engine("v8-cross", crank_ratio=0.3, u1=1e-3, u2=2e-4),
        "load": mc.PowerLawLoad(100.0, 50.0, exponent=2),
        "design_grid": mc.DesignGrid(
            crank_ratio=[0.2, 0.3], inclination=[0.0, 1.0], u1=[1e-3], u2=0.0, cranks=[1, 2], strokes=[2]
        ),
        "extrema": mc.energy_extrema(crank_ratio=0.3, inclination=1.0, u1=1e-3, u2=2e-4, phases=mc.crank_phases(4)),
    }


NOW = built_now()
MACHINE_KEYS = [key for key in NOW if key.startswith("machine:")]


@pytest.fixture(scope="module")
def old():
    # Loading imports 0.1's module paths (multicrank.loads, …) through multicrank._moved.
    with DATA.open("rb") as handle:
        data = pickle.load(handle)
    assert data["version"] == "0.1.0"
    return data["objects"]


def test_the_file_holds_what_it_says(old):
    assert set(old) == {*NOW, "grid"}


@pytest.mark.parametrize("key", list(NOW))
def test_each_old_object_loads_and_equals_the_one_built_now(old, key):
    assert type(old[key]) is type(NOW[key])
    assert old[key] == NOW[key]


def test_the_old_uniform_grid_is_the_same_grid(old):
    grid = mc.uniform_grid(1000)
    assert isinstance(old["grid"], mc.UniformGrid)
    assert np.array_equal(old["grid"], grid) and (old["grid"].start, old["grid"].step) == (grid.start, grid.step)


@pytest.mark.parametrize("key", list(NOW))
def test_pickles_and_copies_round_trip(key):
    value = NOW[key]
    assert pickle.loads(pickle.dumps(value)) == value
    assert copy.deepcopy(value) == value and copy.copy(value) == value


@pytest.mark.parametrize("key", MACHINE_KEYS)
def test_an_old_machine_computes_what_the_fresh_one_does(old, key):
    loaded, fresh = old[key], NOW[key]
    phi = np.linspace(0.0, fresh.cycle, 37)
    for quantity in ("reduced_inertia", "potential_energy", "gravity_torque", "gas_torque"):
        got, expected = getattr(loaded, quantity)(phi), getattr(fresh, quantity)(phi)
        assert np.array_equal(got, expected), quantity  # bit for bit
    assert loaded.engine() == fresh.engine()


def test_an_old_diagram_with_its_interpolant_loads_as_a_new_one(old):
    """0.1's diagrams pickled their SciPy interpolant (slot _poly); it loads, and the diagram is
    rebuilt from its table: read-only arrays, the same values and slopes as a fresh one."""
    assert b"_poly" in DATA.read_bytes()
    diagram, fresh = old["diagram"], NOW["diagram"]
    assert not diagram.angle.flags.writeable and not diagram.pressure.flags.writeable
    theta = np.linspace(-1.0, 8.0, 101)
    assert np.array_equal(diagram(theta), fresh(theta))
    assert np.array_equal(diagram.derivative(theta), fresh.derivative(theta))
    assert diagram.mean_pressure() == fresh.mean_pressure()


def test_a_new_diagram_pickles_its_table_only():
    text = pickle.dumps(NOW["diagram"])
    assert b"scipy" not in text and b"_poly" not in text


def test_diagrams_hash_by_value():
    diagram = NOW["diagram"]
    same = mc.IndicatorDiagram(diagram.angle.copy(), diagram.pressure.copy(), cycle=diagram.cycle, kind=diagram.kind)
    assert same == diagram and hash(same) == hash(diagram) and same is not diagram
    assert len({diagram, same, copy.deepcopy(diagram)}) == 1
    other = mc.IndicatorDiagram(diagram.angle, diagram.pressure, cycle=diagram.cycle, kind="linear")
    assert other != diagram
    # −0.0 == 0.0, so the hashes agree too.
    angle = np.radians([0.0, 90.0, 180.0, 270.0, 360.0])
    plus, minus = ([1.0, 0.0, 2.0, 0.0, 1.0], [1.0, -0.0, 2.0, -0.0, 1.0])
    a, b = (mc.IndicatorDiagram(angle, p, cycle=2 * np.pi, kind="linear") for p in (plus, minus))
    assert a == b and hash(a) == hash(b)
    # A cylinder (a frozen dataclass) hashes its fields, its diagrams by value among them.
    cylinder = NOW["cylinder"]
    assert hash(copy.deepcopy(cylinder)) == hash(cylinder)


def test_value_classes_compare_by_value_and_not_by_identity():
    machine = MACHINES["inline-4"]
    assert machine.replace() == machine and machine.replace() is not machine
    assert machine.replace(shaft_inertia=0.2) != machine and machine != "inline-4"
    engine = NOW["engine"]
    assert engine.replace() == engine and engine.replace(name="other") != engine
    assert engine.perturbed(np.random.default_rng(1), u1_rel=0.01) != engine
    grid = NOW["design_grid"]
    assert mc.DesignGrid(**grid.axes, **grid.constants) == grid
    assert mc.DesignGrid(crank_ratio=[0.2, 0.3], inclination=[0.0, 1.0], u1=[1e-3], u2=0.0) != grid
    # Mutable: not hashable (a hash must not change while a value can).
    for value in (machine, engine, grid):
        with pytest.raises(TypeError, match="unhashable"):
            hash(value)


def test_an_old_path_leaves_the_module_spec_alone():
    code = (
        "import warnings; warnings.simplefilter('error')\n"
        "import multicrank.motion.loads as loads, multicrank.loads\n"
        "assert loads.__spec__.name == 'multicrank.motion.loads', loads.__spec__.name\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
