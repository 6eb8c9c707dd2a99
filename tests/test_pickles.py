"""Pickles keep loading, and the public value classes compare by value (issue 19, items 1 and 5).

tests/data/pickles-0.1.0.pickle was written by the 0.1.0 wheel, before the package was split
into subpackages: ``{"version": "0.1.0", "objects": {...}}``. Its classes are named by 0.1's
module paths (``multicrank.engines.Engine``, ``multicrank.pressure.IndicatorDiagram``, …) and
its indicator diagrams carry their SciPy interpolant. Each object must load, and equal the same
object built now.
"""

from __future__ import annotations

import copy
import math
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import multicrank as mc
from multicrank.presets import LAYOUTS, MACHINES

DATA = Path(__file__).resolve().parent / "data" / "pickles-0.1.0.pickle"


def unplaced(machine: mc.Machine) -> mc.Machine:
    """A preset as 0.1 knew it: no cylinder placed along the shaft (0.1 had no axial_position;
    its pickles read 0), the bearings by default, no torsional shaft (0.1 had none: its
    pickles read None)."""
    return machine.replace(
        cylinders=[c.replace(axial_position=0.0) for c in machine.cylinders], main_bearings=None, shaft=None
    )


def built_now() -> dict[str, object]:
    """The objects of the 0.1.0 pickle, as the current code builds them."""
    compressor = MACHINES["slow-compressor"]
    return {
        "machine:slow-compressor": compressor.replace(shaft=None),  # 0.1 had no torsional shaft
        # 0.1 numbered the in-line four's cylinders by their phases (0°, 180°, 360°, 540°); the
        # layout is now the textbook crank numbered along the shaft (firing 1-3-4-2): the
        # same cylinders, in 0.1's order.
        "machine:inline-4": unplaced(MACHINES["inline-4"]).replace(
            cylinders=sorted(unplaced(MACHINES["inline-4"]).cylinders, key=lambda cylinder: cylinder.phase)
        ),
        "machine:boxer-compressor": unplaced(MACHINES["boxer-compressor"]),
        "cylinder": compressor.cylinders[0],
        "diagram": compressor.cylinders[0].pressure,
        "layout": LAYOUTS["v8-cross"],
        "engine": mc.layout_engine("v8-cross", crank_ratio=0.3, u1=1e-3, u2=2e-4),
        "load": mc.PowerLawLoad(100.0, rpm=50.0 * 30 / math.pi, exponent=2),  # 0.1 held ω_n = 50 rad/s
        "design_grid": mc.DesignGrid(
            crank_ratio=[0.2, 0.3], inclination=[0.0, 1.0], u1=[1e-3], u2=0.0, cranks=[1, 2], strokes=[2]
        ),
        "extrema": mc.energy_extrema(crank_ratio=0.3, inclination=1.0, u1=1e-3, u2=2e-4, phases=mc.crank_phases(4)),
    }


#: How far a preset's pressure table built here may lie from the one 0.1.0 pickled, in
#: roundings (machine epsilons) of the table's largest pressure: the synthetic diagrams'
#: polytropes (``**`` on arrays, pressure/synthetic.py) are numpy's vectorised power, whose last
#: bit depends on the CPU (AVX-512 or not), and the pickle was written on a machine with
#: AVX-512 (here: a few per cent of the entries, each within one rounding). The rest of every
#: object must be the same.
TABLE_ROUNDINGS = 4


def load_old() -> dict[str, object]:
    # Loading imports 0.1's module paths (multicrank.loads, …) through multicrank._moved.
    with DATA.open("rb") as handle:
        data = pickle.load(handle)
    assert data["version"] == "0.1.0"
    return data["objects"]


def with_pickled_tables(now: object, then: object) -> object:
    """``now`` with the pressure tables of ``then`` (the pickled object) wherever the two are
    the same diagram but for the last bits of the table (``TABLE_ROUNDINGS``, checked here)."""
    if isinstance(now, mc.IndicatorDiagram):
        assert isinstance(then, mc.IndicatorDiagram)
        assert (now.cycle, now.kind) == (then.cycle, then.kind) and np.array_equal(now.angle, then.angle)
        bound = TABLE_ROUNDINGS * np.finfo(float).eps * np.abs(now.pressure).max()
        assert np.abs(then.pressure - now.pressure).max() <= bound
        return then
    if isinstance(now, mc.Cylinder):
        assert isinstance(then, mc.Cylinder)
        ends = {}
        for end in ("pressure", "pressure_crank_end"):
            mine, theirs = getattr(now, end), getattr(then, end)
            if isinstance(mine, mc.IndicatorDiagram):
                ends[end] = with_pickled_tables(mine, theirs)
        return now.replace(**ends)
    if isinstance(now, mc.Machine):
        assert isinstance(then, mc.Machine)
        pairs = zip(now.cylinders, then.cylinders, strict=True)
        return now.replace(cylinders=[with_pickled_tables(c, t) for c, t in pairs])
    return now


OLD = load_old()
#: The objects built now, their preset pressure tables the pickle's (to TABLE_ROUNDINGS).
NOW = {key: with_pickled_tables(value, OLD[key]) for key, value in built_now().items()}
MACHINE_KEYS = [key for key in NOW if key.startswith("machine:")]


@pytest.fixture(scope="module")
def old():
    return load_old()


def test_the_preset_tables_are_the_pickled_ones_to_their_last_bits():
    # Each within TABLE_ROUNDINGS (with_pickled_tables checks it); and not all bit-equal only where
    # the CPU's power rounds differently (the count of entries that differ is small).
    fresh, pickled = built_now()["diagram"], OLD["diagram"]
    assert isinstance(fresh, mc.IndicatorDiagram) and isinstance(pickled, mc.IndicatorDiagram)
    with_pickled_tables(fresh, pickled)
    assert np.count_nonzero(fresh.pressure != pickled.pressure) <= fresh.pressure.size // 20


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


@pytest.mark.parametrize("key", MACHINE_KEYS)
def test_an_old_machine_states_no_load_law(old, key):
    """0.1 knew no load law: its machines read None, their diagrams as given at every speed."""
    assert old[key].load_law is None and old[key].load_factor(30.0) == 1.0


def test_an_old_diagram_with_its_interpolant_loads_as_a_new_one(old):
    """0.1's diagrams pickled their SciPy interpolant (slot _poly); it loads, and the diagram is
    rebuilt from its table: read-only arrays, the same values and slopes as a fresh one."""
    assert b"_poly" in DATA.read_bytes()
    diagram = old["diagram"]
    fresh = mc.IndicatorDiagram(diagram.angle, diagram.pressure, cycle=diagram.cycle, kind=diagram.kind)
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


# -- every public exception and result pickles (issue 26, item 5) ------------------------------

# The rooms whose names are the library's API: the package, each room's __init__, and the public
# modules beside them.
ROOMS = (
    "multicrank",
    "multicrank.gravity",
    "multicrank.machine",
    "multicrank.pressure",
    "multicrank.motion",
    "multicrank.sweeps.designs",
    "multicrank.sweeps.driver",
    "multicrank.motion.sweep",
    "multicrank.design",
    "multicrank.report",
    "multicrank.symbolic",
)


def _stall_error() -> mc.StallError:
    with pytest.raises(mc.StallError) as caught:
        mc.steady_state(MACHINES["slow-compressor"], rpm=5)
    return caught.value


def _internal_stall() -> Exception:
    from multicrank.motion._shooting import Stall

    return Stall(1.25, "stops at φ = 1.25 rad")


def _missing_optional() -> Exception:
    from multicrank._optional import require

    with pytest.raises(ImportError) as caught:
        require("multicrank_no_such_module", "report")
    return caught.value


def _cli_error(name: str) -> Exception:
    from multicrank.cli import _group

    return getattr(_group, name)("a machine file without rpm")


def _pressure_unit_warning() -> Warning:
    from multicrank.pressure.diagram import PressureUnitWarning

    return PressureUnitWarning("a peak of 8e5 bar: most likely Pa")


def _symbolic(which: str) -> object:
    pytest.importorskip("sympy")
    from multicrank import symbolic

    return getattr(symbolic, which)(cranks=2)


#: A real instance of each class, by name; a class of the rooms or an exception of the package
#: missing here fails test_every_public_class_has_an_instance_here.
INSTANCES = {
    "BearingLoads": lambda: mc.bearing_loads(MACHINES["boxer-compressor"], phi=np.linspace(0.0, 1.0, 5)),
    "CounterweightOptimum": lambda: mc.optimize_counterweights(MACHINES["marine-2t-twin"], seed=7, maxiter=3),
    "Cylinder": lambda: NOW["cylinder"],
    "DesignGrid": lambda: NOW["design_grid"],
    "EnergyExtrema": lambda: NOW["extrema"],
    "Engine": lambda: NOW["engine"],
    "FlywheelInertia": lambda: mc.flywheel_inertia(MACHINES["inline-4"], delta=0.04, rpm=1500.0),
    "IndicatorDiagram": lambda: NOW["diagram"],
    "Layout": lambda: NOW["layout"],
    "Machine": lambda: NOW["machine:slow-compressor"],
    "MachineGrid": lambda: mc.MachineGrid(MACHINES["inline-4"], rpm=[1000.0, 2000.0], shaft_inertia=[0.1, 0.2]),
    "MechanismError": lambda: mc.MechanismError("rpm = -1 is out of range; allowed: rpm > 0 [1/min]"),
    "MissingExtra": lambda: _cli_error("MissingExtra"),
    "UserError": lambda: _cli_error("UserError"),
    "OptionalDependencyError": _missing_optional,
    "PowerLawLoad": lambda: NOW["load"],
    "PressureUnitWarning": lambda: _pressure_unit_warning(),
    "ReportSettings": lambda: __import__("multicrank.report", fromlist=["ReportSettings"]).ReportSettings(),
    "Shaft": lambda: mc.Shaft([1.0, 2.0], [1e4], cylinder_nodes=[0, 1], damping=[0.5], node_damping=[0.0, 2.0]),
    "ShakingForces": lambda: mc.shaking_forces(MACHINES["inline-4"], max_order=3, steady=True),
    "Stall": _internal_stall,
    "StallError": _stall_error,
    "SteadyState": lambda: mc.steady_state(MACHINES["inline-4"], points=37),
    "SymbolicGravity": lambda: _symbolic("gravity"),
    "SymbolicInertia": lambda: _symbolic("reduced_inertia"),
    "TorsionalModel": lambda: mc.to_opentorsion(MACHINES["inline-6"], max_order=2),
    "Transient": lambda: mc.simulate(MACHINES["inline-4"], np.linspace(0.0, 0.05, 11), rpm0=1500.0, load="balance"),
    "UniformGrid": lambda: mc.uniform_grid(100),
}


def _package_modules() -> list[str]:
    import pkgutil

    return ["multicrank", *(module.name for module in pkgutil.walk_packages(mc.__path__, "multicrank."))]


def public_classes() -> set[type]:
    """Every class a room exports, and every exception class the package defines anywhere (a
    private one may still reach a user, or a worker's parent)."""
    import importlib
    import inspect

    found: set[type] = set()
    for room in ROOMS:
        module = importlib.import_module(room)
        found |= {value for name in module.__all__ if inspect.isclass(value := getattr(module, name))}
    for name in _package_modules():
        if name.endswith("__main__"):
            continue
        module = importlib.import_module(name)
        found |= {
            value
            for value in vars(module).values()
            if inspect.isclass(value) and issubclass(value, BaseException) and value.__module__.startswith("multicrank")
        }
    # A base class is covered by its subclasses here (MotionResult by SteadyState, …); an
    # exception is raised as itself too.
    return {
        cls
        for cls in found
        if issubclass(cls, BaseException) or not any(other is not cls and issubclass(other, cls) for other in found)
    }


def test_every_public_class_has_an_instance_here():
    assert {cls.__name__ for cls in public_classes()} == set(INSTANCES)


def same(a: object, b: object, where: str = "value") -> None:
    """a and b are of one type with equal attributes, recursively (arrays bit for bit, NaN
    equal to NaN); an object without attributes compares by ==."""
    import dataclasses

    import pandas as pd

    assert type(a) is type(b), where
    if isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"), where
    elif isinstance(a, pd.DataFrame | pd.Series):
        compare = pd.testing.assert_frame_equal if isinstance(a, pd.DataFrame) else pd.testing.assert_series_equal
        compare(a, b)
        same(a.attrs, b.attrs, f"{where}.attrs")
    elif isinstance(a, dict):
        assert list(a) == list(b), where
        for key in a:
            same(a[key], b[key], f"{where}[{key!r}]")
    elif isinstance(a, list | tuple):
        assert len(a) == len(b), where
        for index, (x, y) in enumerate(zip(a, b, strict=True)):
            same(x, y, f"{where}[{index}]")
    elif isinstance(a, float):
        assert a == b or (np.isnan(a) and np.isnan(b)), where
    elif isinstance(a, BaseException):
        assert str(a) == str(b), where
        same(a.args, b.args, f"{where}.args")
        same(vars(a), vars(b), f"{where}.__dict__")
    elif type(a).__module__.startswith(("multicrank", "opentorsion")):  # openTorsion's, in a TorsionalModel
        if "__getstate__" in {name for cls in type(a).__mro__[:-1] for name in vars(cls)}:
            same(a.__getstate__(), b.__getstate__(), f"{where}.__getstate__()")  # what it says it is
            return
        names = {field.name for field in dataclasses.fields(a)} if dataclasses.is_dataclass(a) else set()
        names |= set(getattr(a, "__dict__", {}))
        names |= {name for cls in type(a).__mro__ for name in getattr(cls, "__slots__", ()) if name != "_cache"}
        for name in sorted(names):
            same(getattr(a, name), getattr(b, name), f"{where}.{name}")
    else:
        assert a == b, where


#: The classes whose == is identity, by design, and why: their copies are checked attribute by
#: attribute (:func:`same`) only. Every other class compares by value, and its copies must be
#: == to it (and not !=).
IDENTITY_EQUALITY = {
    # results that hold arrays (dataclasses with eq=False): no single truth for == of arrays
    "BearingLoads": "a result of arrays",
    "ShakingForces": "a result of arrays",
    "SteadyState": "a result of arrays",
    "Transient": "a result of arrays",
    # exceptions and warnings compare by identity, as Python's own do
    "MechanismError": "an exception",
    "MissingExtra": "an exception",
    "OptionalDependencyError": "an exception",
    "PressureUnitWarning": "a warning",
    "Stall": "an exception",
    "StallError": "an exception",
    "UserError": "an exception",
    # a NamedTuple of openTorsion's Assembly and PeriodicExcitation, which compare by identity:
    # the tuple's == holds for the very same objects only
    "TorsionalModel": "openTorsion's objects",
}
#: Array-likes, whose == is element-wise, as numpy's.
ELEMENTWISE_EQUALITY = {"UniformGrid"}


def test_the_equality_lists_name_classes_here():
    assert IDENTITY_EQUALITY.keys() <= INSTANCES.keys() and ELEMENTWISE_EQUALITY <= INSTANCES.keys()
    assert not IDENTITY_EQUALITY.keys() & ELEMENTWISE_EQUALITY


def check_equal(copied: object, value: object, name: str, how: str) -> None:
    """``copied`` (``value`` after ``how``) compares as its class says: == by value, element
    by element for an array-like, and for a class of :data:`IDENTITY_EQUALITY` not at all."""
    if name in ELEMENTWISE_EQUALITY:
        assert np.array_equal(copied, value) and not np.any(copied != value), (name, how)
    elif name in IDENTITY_EQUALITY:
        # If this fails, the class has come to compare by value: take it out of IDENTITY_EQUALITY.
        # (A shallow copy shares what the original holds: a tuple of the same objects is ==.)
        assert how == "copy" or not copied == value, (name, how, IDENTITY_EQUALITY[name])
    else:
        equal, unequal = copied == value, copied != value
        assert type(equal) is bool and type(unequal) is bool, (name, how, type(equal), type(unequal))
        assert equal and not unequal, (name, how)


@pytest.mark.parametrize("name", sorted(INSTANCES))
def test_every_public_class_round_trips_a_pickle(name):
    """A copy has the same attributes (bit for bit) and, where the class compares by value,
    is == to the original: a pickle, a deep copy and a shallow one."""
    value = INSTANCES[name]()
    for how, copied in (
        ("pickle", pickle.loads(pickle.dumps(value))),
        ("deepcopy", copy.deepcopy(value)),
        ("copy", copy.copy(value)),
    ):
        same(copied, value, f"{name} ({how})")
        check_equal(copied, value, name, how)


@pytest.mark.parametrize("old", ["multicrank.motion", "multicrank.motion.steady"])
@pytest.mark.parametrize("name", ["SteadyState", "StallError"])
def test_a_steady_state_pickled_under_an_older_module_path_loads(name, old):
    """SteadyState and StallError live in motion/steady_result.py since steady.py was split
    (issue 27, item 6); a pickle names a class by the module of its day (0.1:
    multicrank.motion, 0.2 before the split: multicrank.motion.steady), which must still
    answer with the same class."""
    value = INSTANCES[name]()
    # Protocol 2 names a class as GLOBAL "module\nname\n": rename the module there.
    data = pickle.dumps(value, protocol=2)
    where = f"c{type(value).__module__}\n{name}\n".encode()
    assert where in data
    same(pickle.loads(data.replace(where, f"c{old}\n{name}\n".encode())), value, name)


def test_the_tables_of_the_design_aid_and_the_sweeps_round_trip_a_pickle():
    inline = MACHINES["inline-4"]
    tables = {
        "firing_orders": mc.firing_orders(inline, max_candidates=2),
        "motion_sweep": mc.motion_sweep(inline, mc.MachineGrid(inline, rpm=[1000.0, 2000.0])),
        "sweep": mc.sweep(NOW["design_grid"], phi=36),
    }
    for name, table in tables.items():
        same(pickle.loads(pickle.dumps(table)), table, name)


def test_a_stall_in_a_process_pool_comes_back_to_the_parent():
    """A worker's StallError is pickled back to the parent: before it pickled, the pool's
    result thread died on it and .get() waited for ever (the timeout is only a guard)."""
    import multiprocessing

    compressor = MACHINES["slow-compressor"]
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        pending = pool.apply_async(mc.steady_state, (compressor,), {"rpm": 5.0})
        with pytest.raises(mc.StallError) as caught:
            pending.get(timeout=600)
    expected = _stall_error()
    assert caught.value.min_rpm == expected.min_rpm and caught.value.angle == expected.angle
    assert str(caught.value) == str(expected)


def test_the_machines_firing_module_is_phases_and_its_old_path_warns():
    """Two modules were named firing (issue 27, item 7): the machine's, which gives a layout's
    cylinders their phases, is machine.phases; its old path is the same module, with a warning."""
    code = (
        "import warnings; warnings.simplefilter('error')\n"
        "import multicrank.machine.phases as phases, multicrank.design.firing as design\n"
        "assert design.firing_orders and phases.even_firing\n"
        "try:\n"
        "    import multicrank.machine.firing\n"
        "except DeprecationWarning as warning:\n"
        "    assert 'use multicrank.machine.phases' in str(warning), warning\n"
        "else:\n"
        "    raise AssertionError('no DeprecationWarning')\n"
        "warnings.simplefilter('ignore')\n"
        "import multicrank.machine.firing as old\n"
        "assert old is phases and old.__spec__.name == 'multicrank.machine.phases'\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
