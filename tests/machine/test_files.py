"""Machine files (TOML): what they build, against the same machine built in code and against
closed forms; every user mistake a MechanismError naming the file and the key; every key
documented with its unit."""

import json
import math
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import multicrank as mc
from multicrank.machine.files import CYLINDER_KEYS, LAYOUT_KEYS, MACHINE_KEYS, PRESSURE_KEYS, SHAFT_KEYS
from multicrank.pressure import EXAMPLE_COMPRESSOR_CSV

ROOT = Path(__file__).resolve().parents[2]
PHI = np.linspace(0.0, 4 * np.pi, 721)

CYLINDER = dict(
    crank_radius=0.15,
    rod_length=0.6,
    piston_mass=85.0,
    rod_mass=60.0,
    rod_cg=0.4,
    crank_mass=40.0,
    crank_cg_radius=0.08,
    counterweight_mass=30.0,
    counterweight_radius=0.12,
    bore=0.3,
    piston_rod_diameter=0.06,
)
CYLINDER_TOML = "\n".join(f"{key} = {value!r}" for key, value in CYLINDER.items())
WEBLESS_TOML = CYLINDER_TOML.replace("crank_mass = 40.0", "crank_mass = 0").replace(
    "counterweight_mass = 30.0", "counterweight_mass = 0"
)


def travel(theta, r, l):
    """s(θ) = r[(1 − cos θ) + (1 − √(1 − λ² sin² θ))/λ], written out."""
    lam = r / l
    return r * ((1 - np.cos(theta)) + (1 - np.sqrt(1 - (lam * np.sin(theta)) ** 2)) / lam)


def write(tmp_path, text, name="machine.toml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


# -- the cylinder's chambers and its synthetic cycles -----------------------------------------


def test_chamber_volumes_are_the_clearance_plus_the_swept_part():
    cylinder = mc.Cylinder(**CYLINDER, phase=1.3)  # the phase does not enter: θ is the cycle angle
    theta = np.linspace(-1.0, 13.0, 57).reshape(3, 19)
    s = travel(theta, 0.15, 0.6)
    area, rod_area = math.pi * 0.3**2 / 4, math.pi * (0.3**2 - 0.06**2) / 4
    np.testing.assert_allclose(cylinder.chamber_volume(theta, 1e-3), 1e-3 + area * s, rtol=1e-14)
    np.testing.assert_allclose(
        cylinder.chamber_volume(theta, 2e-3, end="crank"), 2e-3 + rod_area * (0.3 - s), rtol=1e-13
    )
    assert cylinder.swept_volume() == pytest.approx(area * 0.3, rel=1e-15)
    assert cylinder.swept_volume("crank") == pytest.approx(rod_area * 0.3, rel=1e-15)
    for bad, name in [
        ({"clearance_volume": 0.0}, "clearance_volume"),
        ({"clearance_volume": 1e-3, "end": "rod"}, "end"),
    ]:
        with pytest.raises(mc.MechanismError, match=name):
            cylinder.chamber_volume(theta, **bad)


def test_synthetic_cycles_use_the_cylinders_own_volume():
    cylinder = mc.Cylinder(**CYLINDER)
    swept = cylinder.swept_volume()
    by_hand = mc.IndicatorDiagram.compressor(
        lambda t: 0.08 * swept + math.pi * 0.3**2 / 4 * travel(t, 0.15, 0.6),
        suction_pressure=1e5,
        discharge_pressure=4e5,
    )
    made = cylinder.compressor_diagram(suction_pressure=1e5, discharge_pressure=4e5, clearance_ratio=0.08)
    np.testing.assert_allclose(made.angle, by_hand.angle, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(made.pressure, by_hand.pressure, rtol=1e-9, atol=1e-6)
    crank_end = cylinder.compressor_diagram(
        suction_pressure=1e5, discharge_pressure=4e5, clearance_volume=0.08 * swept, end="crank"
    )
    # The crank end compresses while the head end sucks: discharge around inner dead centre.
    assert crank_end(np.pi) == pytest.approx(4e5 - 101325.0) and crank_end(0.0) < 0
    engine = cylinder.engine_diagram(intake_pressure=1e5, heat_release=0.0, compression_ratio=10.0)
    # Motored (no heat): a polytrope from the intake at inner dead centre: p V^1.35 = const.
    assert engine(0.0) + 101325.0 == pytest.approx(1e5 * 10.0**1.35, rel=1e-9)
    by_volume = cylinder.engine_diagram(intake_pressure=1e5, heat_release=0.0, clearance_volume=swept / 9.0)
    np.testing.assert_allclose(by_volume.pressure, engine.pressure, rtol=1e-12)


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda c: c.compressor_diagram(suction_pressure=1e5, discharge_pressure=4e5), "clearance_ratio"),
        (
            lambda c: c.compressor_diagram(
                suction_pressure=1e5, discharge_pressure=4e5, clearance_ratio=0.1, clearance_volume=1e-3
            ),
            "exactly one",
        ),
        (
            lambda c: c.compressor_diagram(suction_pressure=1e5, discharge_pressure=4e5, clearance_ratio=-1),
            "clearance_ratio",
        ),
        (lambda c: c.engine_diagram(intake_pressure=1e5, heat_release=1e3, compression_ratio=1.0), "compression_ratio"),
        (
            lambda c: c.replace(bore=0.0, piston_rod_diameter=0.0).engine_diagram(
                intake_pressure=1e5, heat_release=1e3, compression_ratio=9.0
            ),
            "bore",
        ),
    ],
)
def test_bad_synthetic_cycles_name_the_parameter(call, name):
    with pytest.raises(mc.MechanismError, match=name):
        call(mc.Cylinder(**CYLINDER))


def test_the_inline_design_is_only_for_identical_cylinders():
    cylinder = mc.Cylinder(**CYLINDER)
    machine = mc.Machine([cylinder.replace(phase=a) for a in mc.crank_phases(3)], shaft_inertia=45.0, rpm=120.0)
    design = machine.design()
    engine = machine.engine()
    assert design["u1"] == engine.u1[0] and design["u2"] == engine.u2[0] and design["crank_ratio"] == 0.25
    np.testing.assert_array_equal(design["phases"], engine.phase)
    np.testing.assert_array_equal(mc.potential_energy(PHI, **design), machine.engine().potential_energy(PHI))
    assert machine.design(240)["u1"] == pytest.approx(design["u1"] / 4, rel=1e-14)
    with pytest.raises(mc.MechanismError, match="inclination"):
        mc.Machine.from_layout("v-twin-90", cylinder, shaft_inertia=1.0, rpm=100.0).design()


# -- files that build machines ------------------------------------------------------------------


def test_a_double_acting_compressor_file_is_the_machine_built_in_code(tmp_path):
    path = write(
        tmp_path,
        f"""
name = "my compressor"
note = "a test"
shaft_inertia = 350.0
rpm = 120
rpm_range = [60, 300]

[cylinder]
{CYLINDER_TOML}
inclination_deg = 60

[cylinder.pressure]
type = "compressor"
pressure_unit = "bar"
suction_pressure = 1.0
discharge_pressure = 4.0
clearance_ratio = 0.08

[cylinder.pressure_crank_end]
type = "compressor"
suction_pressure = 1.0e5
discharge_pressure = 4.0e5
clearance_ratio = 0.08
""",
    )
    machine = mc.Machine.from_toml(path)
    cylinder = mc.Cylinder(**CYLINDER, inclination=math.radians(60))
    air = dict(suction_pressure=1e5, discharge_pressure=4e5, clearance_ratio=0.08)
    expected = mc.Machine(
        [
            cylinder.replace(
                pressure=cylinder.compressor_diagram(**air),
                pressure_crank_end=cylinder.compressor_diagram(end="crank", **air),
            )
        ],
        shaft_inertia=350.0,
    )
    assert (machine.name, machine.note, machine.rpm, machine.rpm_range, machine.strokes) == (
        "my compressor",
        "a test",
        120.0,
        (60.0, 300.0),
        2,
    )
    np.testing.assert_allclose(machine.gas_torque(PHI), expected.gas_torque(PHI), rtol=1e-12, atol=1e-6)
    np.testing.assert_array_equal(machine.reduced_inertia(PHI)[0], expected.reduced_inertia(PHI)[0])
    np.testing.assert_array_equal(machine.gravity_torque(PHI), expected.gravity_torque(PHI))
    assert machine.cylinders[0].inclination == pytest.approx(math.radians(60), rel=1e-15)


def test_a_layout_file_is_machine_from_layout(tmp_path):
    path = write(
        tmp_path,
        f"""
layout = "v8-cross"
shaft_inertia = 0.25
strokes = 4
rpm = 3000
firing_deg = [45, 675, 135, 405, 315, 225, 585, 495]

[cylinder]
{CYLINDER_TOML}

[cylinder.pressure]
type = "engine"
intake_pressure = 1.0e5
heat_release = 3.0e4
compression_ratio = 10
start_of_combustion_deg = -12
combustion_duration_deg = 50
""",
        name="vee.toml",
    )
    machine = mc.Machine.from_toml(path)
    cylinder = mc.Cylinder(**CYLINDER)
    diagram = cylinder.engine_diagram(
        intake_pressure=1e5,
        heat_release=3e4,
        compression_ratio=10,
        start_of_combustion=math.radians(-12),
        combustion_duration=math.radians(50),
    )
    expected = mc.Machine.from_layout("v8-cross", cylinder.replace(pressure=diagram), shaft_inertia=0.25, strokes=4)
    assert machine.name == "vee" and machine.note == mc.LAYOUTS["v8-cross"].note  # the file's stem, the layout's note
    np.testing.assert_allclose([c.phase for c in machine.cylinders], [c.phase for c in expected.cylinders], atol=1e-12)
    np.testing.assert_allclose(machine.gas_torque(PHI), expected.gas_torque(PHI), rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(machine.gravity_torque(PHI), expected.gravity_torque(PHI), rtol=1e-12, atol=1e-12)


def test_an_explicit_list_and_a_layout_of_ones_own(tmp_path):
    listed = write(
        tmp_path,
        f"""
shaft_inertia = 2.0
[[cylinder]]
{CYLINDER_TOML}
phase_deg = 0
inclination_deg = 45
[[cylinder]]
{WEBLESS_TOML}
phase_deg = -90
inclination_deg = 135
""",
        name="listed.toml",
    )
    own = write(
        tmp_path,
        f"""
shaft_inertia = 2.0
layout = {{ throws_deg = [45], banks_deg = [[45, 135]], name = "vee" }}
[cylinder]
{CYLINDER_TOML}
""",
        name="own.toml",
    )
    a, b = mc.Machine.from_toml(listed), mc.Machine.from_toml(own)
    assert len(a) == len(b) == 2 and b.name == "own"
    np.testing.assert_allclose(a.gravity_torque(PHI), b.gravity_torque(PHI), rtol=1e-12, atol=1e-10)
    np.testing.assert_allclose(a.reduced_inertia(PHI)[0], b.reduced_inertia(PHI)[0], rtol=1e-14)


def test_a_csv_pressure_is_read_relative_to_the_file(tmp_path):
    (tmp_path / "data").mkdir()
    shutil.copy(EXAMPLE_COMPRESSOR_CSV, tmp_path / "data" / "p.csv")
    (tmp_path / "machines").mkdir()
    path = write(
        tmp_path / "machines",
        """
shaft_inertia = 0.05
[cylinder]
crank_radius = 0.03
rod_length = 0.12
piston_mass = 0.3
rod_mass = 0.25
rod_cg = 0.08
bore = 0.08
[cylinder.pressure]
type = "table"
path = "../data/p.csv"
pressure_unit = "bar"
absolute = true
reference_pressure = 1.01325
""",
    )
    machine = mc.Machine.from_toml(path)
    expected = mc.IndicatorDiagram.from_csv(EXAMPLE_COMPRESSOR_CSV, pressure_unit="bar", absolute=True)
    theta = np.linspace(0, 2 * np.pi, 101)
    np.testing.assert_allclose(machine.cylinders[0].pressure(theta), expected(theta), rtol=1e-12, atol=1e-6)


# -- mistakes --------------------------------------------------------------------------------------

MINIMAL = f"shaft_inertia = 1.0\n[cylinder]\n{CYLINDER_TOML}\n"


@pytest.mark.parametrize(
    "text, key",
    [
        ("wheels = 4\n" + MINIMAL, "wheels"),
        (MINIMAL + "wheels = 4\n", "cylinder.wheels"),
        (f"[cylinder]\n{CYLINDER_TOML}\n", "shaft_inertia"),
        ("shaft_inertia = 1.0\n", "cylinder"),
        (
            "shaft_inertia = 1.0\n[cylinder]\ncrank_radius = 0.1\nrod_length = 0.5\npiston_mass = 1\nrod_cg = 0.2\n",
            "rod_mass",
        ),
        (MINIMAL.replace("crank_radius = 0.15", 'crank_radius = "0.15"'), "cylinder.crank_radius"),
        (MINIMAL.replace("bore = 0.3", "bore = true"), "cylinder.bore"),
        ("strokes = 4.0\n" + MINIMAL, "strokes"),
        ("strokes = 3\n" + MINIMAL, "strokes"),
        (MINIMAL.replace("rod_length = 0.6", "rod_length = 0.1"), "rod_length"),
        ("shaft_inertia = -1.0\n" + MINIMAL.split("\n", 1)[1], "shaft_inertia"),
        ("rpm = 400\nrpm_range = [60, 300]\n" + MINIMAL, "rpm"),
        ("rpm_range = [60, 300, 900]\n" + MINIMAL, "rpm_range"),
        ("rpm_range = [60, 'fast']\n" + MINIMAL, "rpm_range"),
        ('layout = "v7"\n' + MINIMAL, "layout"),
        ('layout = "v8-cross"\n' + MINIMAL + "phase_deg = 10\n", "cylinder.phase_deg"),
        ('layout = "v8-cross"\n' + MINIMAL.replace("[cylinder]", "[[cylinder]]"), "cylinder"),
        ("firing_deg = [0]\n" + MINIMAL, "firing_deg"),
        ('layout = "inline-2-4t"\nfiring_deg = [0, 90]\n' + MINIMAL, "firing_deg"),
        ("layout = { throws_deg = [0, 90], banks_deg = [[90]] }\n" + MINIMAL, "layout.banks_deg"),
        ("layout = { throws_deg = [0] }\n" + MINIMAL, "layout.banks_deg"),
        ("shaft_inertia = 1.0\ncylinder = []\n", "cylinder"),
        (MINIMAL + "[cylinder.pressure]\nsuction_pressure = 1e5\n", "cylinder.pressure.type"),
        (MINIMAL + '[cylinder.pressure]\ntype = "steam"\n', "cylinder.pressure.type"),
        (
            MINIMAL + '[cylinder.pressure]\ntype = "compressor"\nsuction_pressure = 1e5\ndischarge_pressure = 4e5\n',
            "cylinder.pressure.clearance_volume",
        ),
        (
            MINIMAL
            + '[cylinder.pressure]\ntype = "compressor"\nsuction_pressure = 1e5\ndischarge_pressure = 4e5\n'
            + "clearance_ratio = 0.1\nclearance_volume = 0.001\n",
            "cylinder.pressure.clearance_volume",
        ),
        (
            MINIMAL + '[cylinder.pressure]\ntype = "compressor"\nsuction_pressure = 1e5\nclearance_ratio = 0.1\n',
            "cylinder.pressure.discharge_pressure",
        ),
        (
            MINIMAL
            + '[cylinder.pressure]\ntype = "compressor"\nsuction_pressure = 4e5\ndischarge_pressure = 1e5\n'
            + "clearance_ratio = 0.1\n",
            "cylinder.pressure",
        ),
        (
            MINIMAL
            + '[cylinder.pressure]\ntype = "compressor"\nsuction_pressure = 1\ndischarge_pressure = 4\n'
            + 'clearance_ratio = 0.1\npressure_unit = "atm"\n',
            "cylinder.pressure.pressure_unit",
        ),
        (
            MINIMAL
            + '[cylinder.pressure]\ntype = "compressor"\nsuction_pressure = 1e5\ndischarge_pressure = 4e5\n'
            + "clearance_ratio = 0.1\nheat_release = 3\n",
            "cylinder.pressure.heat_release",
        ),
        (
            MINIMAL
            + '[cylinder.pressure_crank_end]\ntype = "engine"\nintake_pressure = 1e5\nheat_release = 1e3\n'
            + "compression_ratio = 10\n",
            "cylinder.pressure_crank_end",
        ),
        (MINIMAL + '[cylinder.pressure]\ntype = "table"\npath = "nowhere.csv"\n', "cylinder.pressure"),
        (MINIMAL + '[cylinder.pressure]\ntype = "table"\npath = 3\n', "cylinder.pressure.path"),
        ("[engine]\ncranks = 4\n", "engine"),
        ("shaft_inertia = = 1\n", "TOML"),
    ],
)
def test_mistakes_name_the_file_and_the_key(tmp_path, text, key):
    path = write(tmp_path, text)
    with pytest.raises(mc.MechanismError) as error:
        mc.Machine.from_toml(path)
    message = str(error.value)
    assert message.startswith(f"{path}: ") and key in message and "\n" not in message


def test_files_that_are_not_there_or_not_files(tmp_path):
    for path, words in [(tmp_path / "none.toml", "no such file"), (tmp_path, "directory")]:
        with pytest.raises(mc.MechanismError, match=words):
            mc.Machine.from_toml(path)
    with pytest.raises(mc.MechanismError, match="path"):
        mc.Machine.from_toml(3)


# -- documentation -----------------------------------------------------------------------------------


def every_key():
    keys = set(MACHINE_KEYS) | set(CYLINDER_KEYS) | set(LAYOUT_KEYS) | set(SHAFT_KEYS)
    for table in PRESSURE_KEYS.values():
        keys |= set(table)
    return sorted(keys)


@pytest.mark.parametrize("key", every_key())
def test_every_key_is_documented_with_its_unit(key):
    docs = (ROOT / "docs" / "machine-files.md").read_text(encoding="utf-8")
    assert f"`{key}`" in docs, f"docs/machine-files.md does not document {key}"
    assert f"``{key}``" in (mc.Machine.from_toml.__doc__ or ""), f"Machine.from_toml's table lacks {key}"


# -- any value of any type in any key (issue 13, item 8) -------------------------------------------

_TOML_VALUES = st.one_of(
    st.integers(-(2**63), 2**63 - 1),
    st.floats(allow_nan=True, allow_infinity=True),
    st.booleans(),
    st.text(max_size=6),
    st.lists(st.floats(-10, 10), max_size=3),
    st.lists(st.text(max_size=3), max_size=2),
    st.dictionaries(st.sampled_from(["a", "kind", "rpm"]), st.integers(-5, 5), max_size=2),
)
_EXAMPLE = 'shaft_inertia = 45.0\nstrokes = 2\nrpm = 120.0\nname = "x"\n[cylinder]\n' + CYLINDER_TOML + "\n"


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_any_value_in_any_key_is_accepted_or_named(tmp_path, data):
    """A machine file with one key given a random TOML value of any type either loads or is
    one MechanismError naming the file (never a TypeError, KeyError or a traceback)."""
    table = tomllib.loads(_EXAMPLE)
    section = data.draw(st.sampled_from(["machine", "cylinder"]))
    keys = sorted(set(MACHINE_KEYS) - {"cylinder"}) if section == "machine" else sorted(CYLINDER_KEYS)
    key = data.draw(st.sampled_from(keys))
    value = data.draw(_TOML_VALUES)
    target = table if section == "machine" else table["cylinder"]
    target[key] = value
    path = tmp_path / "random.toml"
    path.write_text(_dumps(table), encoding="utf-8")
    try:
        mc.Machine.from_toml(path)
    except mc.MechanismError as error:
        assert str(error).startswith(f"{path}: ") and "\n" not in str(error)


def _dumps(table: dict) -> str:
    """A minimal TOML writer for the values drawn above (tomllib reads, it does not write)."""

    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, float):
            return "nan" if math.isnan(v) else ("inf" if v == math.inf else "-inf" if v == -math.inf else repr(v))
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + "}"
        return repr(v)

    head = [f"{k} = {value(v)}" for k, v in table.items() if k != "cylinder"]
    body = [f"{k} = {value(v)}" for k, v in table["cylinder"].items()]
    return "\n".join([*head, "[cylinder]", *body]) + "\n"


@pytest.mark.parametrize(
    ("pressures", "unit", "likely"),
    [
        ("suction_pressure = 1e5\ndischarge_pressure = 4e5\n", "bar", "Pa"),
        ("suction_pressure = 1\ndischarge_pressure = 4\n", "Pa", "bar"),
    ],
)
def test_pressures_absurd_for_the_files_unit_warn_naming_the_key(tmp_path, pressures, unit, likely):
    """Issue 26, item 6: Pa read as bar (a suction pressure of 10⁵ bar) gave a machine that
    silently stalls; the file says which key and what unit was likely meant."""
    from multicrank.pressure import PressureUnitWarning

    text = (
        MINIMAL
        + f'[cylinder.pressure]\ntype = "compressor"\npressure_unit = "{unit}"\nclearance_ratio = 0.1\n{pressures}'
    )
    path = write(tmp_path, text)
    with pytest.warns(PressureUnitWarning, match=rf"machine\.toml: cylinder\.pressure: .*did you give {likely} where"):
        mc.Machine.from_toml(path)
    fixed = write(tmp_path, text.replace(f'pressure_unit = "{unit}"', f'pressure_unit = "{likely}"'))
    mc.Machine.from_toml(fixed)  # no warning: an error under the test settings
