"""Machine(load_law=): the field — its values, its rated speed, replace, pickles, equality, the
machine-file key and the preset that states it. What the law does to the answers at a speed is
tests/motion/test_orders_load_law.py's and tests/motion/test_steady_load_law.py's."""

from __future__ import annotations

import copy
import pickle

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc
from multicrank.presets import MACHINES

CYLINDER = mc.Cylinder(crank_radius=0.15, rod_length=0.6, piston_mass=85.0, rod_mass=60.0, rod_cg=0.4, bore=0.3)
TOML = """
shaft_inertia = 45.0
{top}
[cylinder]
crank_radius = 0.15
rod_length = 0.6
piston_mass = 85.0
rod_mass = 60.0
rod_cg = 0.4
"""


def test_the_law_is_none_by_default_and_propeller_where_stated():
    plain = mc.Machine([CYLINDER], shaft_inertia=45.0, rpm=300.0)
    assert plain.load_law is None
    ship = mc.Machine([CYLINDER], shaft_inertia=45.0, rpm=300.0, load_law="propeller")
    assert ship.load_law == "propeller" and ship != plain
    assert mc.Machine.from_layout("inline-2-2t", CYLINDER, shaft_inertia=45.0, rpm=300.0, load_law="propeller") == (
        mc.Machine.from_layout("inline-2-2t", CYLINDER, shaft_inertia=45.0, rpm=300.0).replace(load_law="propeller")
    )


@settings(max_examples=30, deadline=None)
@given(rated=st.floats(10.0, 5000.0), ratio=st.floats(0.05, 1.5))
def test_the_factor_is_the_square_of_the_speed_over_the_rated_one(rated, ratio):
    ship = mc.Machine([CYLINDER], shaft_inertia=45.0, rpm=rated, load_law="propeller")
    speed = ratio * rated
    assert ship.load_factor(speed) == pytest.approx((speed / rated) * (speed / rated), rel=1e-12)
    assert ship.load_factor(rated) == pytest.approx(1.0, rel=1e-15)
    assert ship.replace(load_law=None).load_factor(speed) == 1.0


def test_a_law_needs_the_rated_speed_and_a_known_name():
    with pytest.raises(mc.MechanismError, match=r"^load_law = 'propeller' needs the rated speed"):
        mc.Machine([CYLINDER], shaft_inertia=45.0, load_law="propeller")
    for bad in ("fan", "Propeller", "", 2, True, ["propeller"]):
        with pytest.raises(mc.MechanismError, match=r"^load_law = .* is not allowed; allowed: 'propeller'"):
            mc.Machine([CYLINDER], shaft_inertia=45.0, rpm=300.0, load_law=bad)
    ship = mc.Machine([CYLINDER], shaft_inertia=45.0, rpm=300.0, load_law="propeller")
    with pytest.raises(mc.MechanismError, match=r"^load_law = 'propeller' needs the rated speed"):
        ship.replace(rpm=None)
    with pytest.raises(mc.MechanismError, match=r"^rpm"):
        ship.load_factor(-30.0)


def test_replace_keeps_changes_and_removes_the_law():
    ship = mc.Machine([CYLINDER], shaft_inertia=45.0, rpm=300.0, load_law="propeller")
    assert ship.replace(shaft_inertia=50.0).load_law == "propeller"
    faster = ship.replace(rpm=600.0)  # a new rated speed
    assert faster.load_law == "propeller" and faster.load_factor(300.0) == pytest.approx(0.25, rel=1e-15)
    assert ship.replace(load_law=None).load_law is None
    assert ship.replace(load_law=None, rpm=None).rpm is None


def test_the_law_pickles_and_copies():
    ship = MACHINES["slow-diesel-12"]
    for copied in (pickle.loads(pickle.dumps(ship)), copy.deepcopy(ship), copy.copy(ship)):
        assert copied == ship and copied.load_law == "propeller"
    assert pickle.loads(pickle.dumps(ship.replace(load_law=None))).load_law is None


def test_the_machine_file_key(tmp_path):
    path = tmp_path / "ship.toml"
    path.write_text(TOML.format(top='rpm = 300.0\nload_law = "propeller"'), encoding="utf-8")
    assert mc.Machine.from_toml(path) == mc.Machine([CYLINDER.replace(bore=0.0)], shaft_inertia=45.0, rpm=300.0,
                                                    name="ship", load_law="propeller")  # fmt: skip
    layout = tmp_path / "twin.toml"
    layout.write_text(TOML.format(top='layout = "inline-2-2t"\nrpm = 300.0\nload_law = "propeller"'), encoding="utf-8")
    assert mc.Machine.from_toml(layout).load_law == "propeller"
    path.write_text(TOML.format(top="rpm = 300.0"), encoding="utf-8")
    assert mc.Machine.from_toml(path).load_law is None
    for top, words in (
        ('load_law = "propeller"', r": load_law = 'propeller' needs the rated speed"),
        ('rpm = 300.0\nload_law = "fan"', r": load_law = 'fan' is not allowed"),
        ("rpm = 300.0\nload_law = 2", r": load_law: must be a string, got an integer"),
    ):
        path.write_text(TOML.format(top=top), encoding="utf-8")
        with pytest.raises(mc.MechanismError, match=f"^{path}{words}"):
            mc.Machine.from_toml(path)


def test_the_slow_diesel_drives_a_propeller_and_the_other_presets_state_no_law():
    ship = MACHINES["slow-diesel-12"]
    assert ship.load_law == "propeller" and ship.rpm == 90.0 and "propulsion" in ship.note
    assert ship.load_factor(30.0) == pytest.approx(1 / 9, rel=1e-14)
    assert [name for name, machine in MACHINES.items() if machine.load_law is not None] == ["slow-diesel-12"]
