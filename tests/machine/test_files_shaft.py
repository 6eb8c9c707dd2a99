"""The machine file's [shaft] table and mc.Shaft.from_toml: what they build against the shaft
built in code, every mistake a MechanismError naming the file and the key, and a whole machine
file refused by Shaft.from_toml wherever Machine.from_toml refuses it, with its message."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import multicrank as mc
from multicrank.machine.files import SHAFT_KEYS

from .test_files import _TOML_VALUES, CYLINDER_TOML, WEBLESS_TOML, _dumps, write

ROOT = Path(__file__).resolve().parents[2]

SHAFT_TOML = """
[shaft]
inertia = [0.5, 0.4, 3]        # kg·m² (an integer is a number too)
stiffness = [1.0e6, 2.0e6]     # N·m/rad
cylinder_nodes = [0, 1]
damping = [5.0, 0]             # N·m·s/rad
"""
SHAFT = mc.Shaft([0.5, 0.4, 3.0], [1e6, 2e6], cylinder_nodes=[0, 1], damping=[5.0, 0.0])

TWO = (
    "shaft_inertia = 2.0\n"
    + f"[[cylinder]]\n{CYLINDER_TOML}\nphase_deg = 0\n"
    + f"[[cylinder]]\n{CYLINDER_TOML}\nphase_deg = 90\naxial_position = 0.5\n"
)


def test_a_shaft_table_is_the_shaft_built_in_code(tmp_path):
    path = write(tmp_path, TWO + SHAFT_TOML)
    machine = mc.Machine.from_toml(path)
    assert machine.shaft == SHAFT and isinstance(machine.shaft.inertia[2], float)
    without = mc.Machine.from_toml(write(tmp_path, TWO, "plain.toml"))
    assert without.shaft is None and machine == without.replace(shaft=SHAFT, name="machine")
    # Shaft.from_toml: the machine file's table, and the table alone in a file of its own.
    assert mc.Shaft.from_toml(path) == SHAFT
    assert mc.Shaft.from_toml(write(tmp_path, SHAFT_TOML, "shaft.toml")) == SHAFT
    no_damping = SHAFT_TOML.replace("damping = [5.0, 0]", "")
    bare = mc.Shaft.from_toml(write(tmp_path, no_damping, "bare.toml"))
    assert bare.damping is None and bare.node_damping is None


def test_node_damping_is_the_shafts(tmp_path):
    text = SHAFT_TOML + "node_damping = [0, 1.5, 40]       # N·m·s/rad: a propeller at node 2\n"
    expected = mc.Shaft([0.5, 0.4, 3.0], [1e6, 2e6], cylinder_nodes=[0, 1], damping=[5.0, 0.0],
                        node_damping=[0.0, 1.5, 40.0])  # fmt: skip
    machine = mc.Machine.from_toml(write(tmp_path, TWO + text))
    assert machine.shaft == expected and machine.shaft.node_damping == (0.0, 1.5, 40.0)
    assert mc.Shaft.from_toml(write(tmp_path, text, "shaft.toml")) == expected


def test_with_a_layout_the_nodes_follow_the_layouts_order(tmp_path):
    """A 60° V6 (three throws, two banks on each) and a flywheel: the layout's cylinders throw
    by throw, bank by bank, as Machine.from_layout orders them."""
    head = 'layout = "v6-60"\nshaft_inertia = 0.3\n'
    shaft = (
        "[shaft]\ninertia = [0.02, 0.02, 0.02, 0.3]\nstiffness = [4e5, 4e5, 6e5]\ncylinder_nodes = [0, 0, 1, 1, 2, 2]\n"
    )
    cylinder = f"[cylinder]\n{WEBLESS_TOML}\n"
    machine = mc.Machine.from_toml(write(tmp_path, head + shaft + cylinder))
    expected = mc.Machine.from_layout(
        "v6-60",
        mc.Machine.from_toml(write(tmp_path, head + cylinder, "bare.toml")).cylinders[0],
        shaft_inertia=0.3,
        name="machine",
        shaft=mc.Shaft([0.02, 0.02, 0.02, 0.3], [4e5, 4e5, 6e5], cylinder_nodes=[0, 0, 1, 1, 2, 2]),
    )
    assert machine == expected
    wrong = write(tmp_path, head + shaft.replace("[0, 0, 1, 1, 2, 2]", "[0, 1, 2]") + cylinder, "wrong.toml")
    with pytest.raises(mc.MechanismError) as error:
        mc.Machine.from_toml(wrong)
    assert str(error.value) == (
        f"{wrong}: shaft.cylinder_nodes: must hold one node per cylinder, in the layout's order: 6 cylinders, got 3"
    )


def test_the_v8_example_carries_its_crankshaft():
    path = ROOT / "docs" / "machines" / "v8-cross.toml"
    machine = mc.Machine.from_toml(path)
    assert machine.shaft == mc.Shaft.from_toml(path)
    assert machine.shaft.cylinder_nodes == (1, 1, 2, 2, 3, 3, 4, 4)
    # Plausible: the chain's inertia about the file's shaft_inertia, a first mode of a few
    # hundred hertz; the cross-plane V8's major orders are its firing's, 4 and 8.
    assert sum(machine.shaft.inertia) == pytest.approx(machine.shaft_inertia, rel=0.05)
    assert 200 < machine.shaft.modes().natural_frequency[0] < 800
    merit = mc.torsional_merit(machine, modes=1, max_order=8)
    assert merit.loc[merit["major"], "order"].tolist() == [4.0, 8.0]


@pytest.mark.parametrize(
    ("shaft", "key"),
    [
        (SHAFT_TOML + "wheels = 4\n", "shaft.wheels"),
        (SHAFT_TOML.replace("inertia = [0.5, 0.4, 3]", 'inertia = ["0.5", 0.4, 3]'), "shaft.inertia"),
        (SHAFT_TOML.replace("stiffness = [1.0e6, 2.0e6]", "stiffness = 1.0e6"), "shaft.stiffness"),
        (SHAFT_TOML.replace("cylinder_nodes = [0, 1]", "cylinder_nodes = [0, 1.0]"), "shaft.cylinder_nodes"),
        (SHAFT_TOML.replace("cylinder_nodes = [0, 1]", "cylinder_nodes = [0, true]"), "shaft.cylinder_nodes"),
        (SHAFT_TOML.replace("damping = [5.0, 0]", "damping = true"), "shaft.damping"),
        (SHAFT_TOML.replace("stiffness = [1.0e6, 2.0e6]", ""), "shaft.stiffness"),
        (SHAFT_TOML.replace("cylinder_nodes = [0, 1]", ""), "shaft.cylinder_nodes"),
        ("shaft = 3\n", "shaft"),
        (SHAFT_TOML.replace("inertia = [0.5, 0.4, 3]", "inertia = [-0.5, 0.4, 3]"), "shaft: inertia[0] = -0.5"),
        (SHAFT_TOML.replace("stiffness = [1.0e6, 2.0e6]", "stiffness = [1.0e6]"), "shaft: stiffness must hold"),
        (SHAFT_TOML.replace("cylinder_nodes = [0, 1]", "cylinder_nodes = [0, 3]"), "shaft: cylinder_nodes[1] = 3"),
        (SHAFT_TOML.replace("damping = [5.0, 0]", "damping = [-1, 0]"), "shaft: damping must hold"),
        (SHAFT_TOML + "node_damping = 3.0\n", "shaft.node_damping: must be an array of numbers"),
        (SHAFT_TOML + "node_damping = [1.0, 2.0]\n", "shaft: node_damping must hold 3 values"),
        (SHAFT_TOML + "node_damping = [1.0, -2.0, 0]\n", "shaft: node_damping must hold 3 values"),
        (SHAFT_TOML.replace("cylinder_nodes = [0, 1]", "cylinder_nodes = [0, 1, 2]"), "shaft.cylinder_nodes: must"),
    ],
)
def test_mistakes_name_the_file_and_the_key(tmp_path, shaft, key):
    text = TWO + shaft if not shaft.startswith("shaft =") else shaft + TWO
    path = write(tmp_path, text)
    with pytest.raises(mc.MechanismError) as error:
        mc.Machine.from_toml(path)
    message = str(error.value)
    assert message.startswith(f"{path}: ") and key in message and "\n" not in message
    # Shaft.from_toml reads a machine file as the machine: the same message (one node per
    # cylinder too, a machine's rule: a shaft alone may have any number of cylinders).
    with pytest.raises(mc.MechanismError) as again:
        mc.Shaft.from_toml(path)
    assert str(again.value) == message


#: A compressor's pressure table that no clearance fits: a negative one.
PRESSURE = (
    "[cylinder.pressure]\ntype = 'compressor'\nsuction_pressure = 1e5\ndischarge_pressure = 4e5\n"
    "clearance_ratio = -0.1\n"
)


@pytest.mark.parametrize(
    ("change", "key"),
    [
        (lambda text: text.replace("crank_radius = ", "crank_radius = -", 1), "cylinder[0]: crank_radius"),
        (lambda text: text.replace("shaft_inertia = 2.0", "shaft_inertia = 0.0"), "shaft_inertia"),
        (lambda text: text.replace("phase_deg = 0", "phase_deg = 0\naxial_position = nan"), "cylinder[0]: axial"),
        (
            lambda text: text.replace("axial_position = 0.5\n", "axial_position = 0.5\n" + PRESSURE),
            "cylinder[1].pressure",
        ),
        (lambda text: "rpm_range = [900.0, 600.0]\n" + text, "rpm_range"),
        (lambda text: text.replace("cylinder_nodes = [0, 1]", "cylinder_nodes = [0, 1, 1]"), "shaft.cylinder_nodes"),
        (lambda text: "main_bearings = [0.2, 0.1]\n" + text, "main_bearings"),
    ],
)
def test_a_machine_file_the_machine_refuses_gives_no_shaft(tmp_path, change, key):
    """The machine's own rules (a cylinder's, the machine's, a shaft's node per cylinder),
    which no [shaft] key breaks: Machine.from_toml refuses the file, and so, with its message,
    does Shaft.from_toml (it returned the shaft of such a file)."""
    path = write(tmp_path, change(TWO + SHAFT_TOML))
    with pytest.raises(mc.MechanismError) as error:
        mc.Machine.from_toml(path)
    message = str(error.value)
    assert message.startswith(f"{path}: ") and key in message and "\n" not in message
    with pytest.raises(mc.MechanismError) as again:
        mc.Shaft.from_toml(path)
    assert str(again.value) == message


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (TWO, "shaft: missing required table [shaft]"),
        ("", "shaft: missing required key shaft"),
        ("[shafts]\ninertia = [1, 1]\n", "shafts: unknown key shafts; known here: shaft"),
        (SHAFT_TOML + "[extra]\n", "extra: unknown key extra"),
        ("shaft_inertia = 1.0\n" + SHAFT_TOML, "cylinder: missing required key cylinder"),  # a machine file, read whole
        ("[shaft]\ninertia = [1, 1", "not a valid TOML file"),
    ],
)
def test_a_file_without_a_good_shaft_table_is_named(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(mc.MechanismError) as error:
        mc.Shaft.from_toml(path)
    assert str(error.value).startswith(f"{path}: {message}")


def test_paths_that_are_not_files():
    with pytest.raises(mc.MechanismError, match="path must be a file path"):
        mc.Shaft.from_toml(3)
    with pytest.raises(mc.MechanismError, match="is a directory, not a shaft or machine file"):
        mc.Shaft.from_toml(ROOT)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_any_value_in_any_shaft_key_is_accepted_or_named(tmp_path, data):
    """One [shaft] key given a random TOML value of any type: the file loads or is one
    MechanismError naming the file (never a TypeError, KeyError or a traceback)."""
    table = tomllib.loads(TWO + SHAFT_TOML)
    table["cylinder"] = table["cylinder"][0]  # the writer's one [cylinder]: a one-cylinder machine
    table["shaft"]["cylinder_nodes"] = [1]
    table["shaft"][data.draw(st.sampled_from(sorted(SHAFT_KEYS)))] = data.draw(_TOML_VALUES)
    path = tmp_path / "random.toml"
    path.write_text(_dumps(table), encoding="utf-8")
    for read in (mc.Machine.from_toml, mc.Shaft.from_toml):
        try:
            read(path)
        except mc.MechanismError as error:
            assert str(error).startswith(f"{path}: ") and "\n" not in str(error)
