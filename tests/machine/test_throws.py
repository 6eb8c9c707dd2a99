"""Where things are along the shaft (issue 28, item 1): cylinders' axial positions, throws, main
bearings, a layout's spacing, machine files, pickles.

The oracles are hand-computed positions and the textbook rule for an in-line crank's free
couples: a planar crank whose pins lie at angles β_j at axial positions z_j (from their centre)
has an order-n couple proportional to |Σ_j z_j e^{inβ_j}|, which vanishes for a mirror-symmetric
crank and not for the in-line four written in firing order along the shaft (0°, 180°, 0°, 180°).
"""

from __future__ import annotations

import copy
import math
import pickle
from pathlib import Path

import numpy as np
import pytest

import multicrank as mc
from multicrank.design.firing import _candidate_machines
from multicrank.motion.variants import machine_variant

CYLINDER = mc.Cylinder(
    crank_radius=0.05, rod_length=0.2, piston_mass=1.0, rod_mass=1.0, rod_cg=0.05, crank_mass=1.0, crank_cg_radius=0.02
)
PICKLES = Path(__file__).resolve().parents[1] / "data" / "pickles-0.1.0.pickle"


def placed(*positions: float, radius: float = 0.05) -> mc.Machine:
    return mc.Machine(
        [CYLINDER.replace(axial_position=z, crank_radius=radius, phase=0.3 * j) for j, z in enumerate(positions)],
        shaft_inertia=0.5,
    )


# -- a cylinder's axial position -------------------------------------------------------------


def test_axial_position_defaults_to_zero_and_is_kept_by_replace():
    assert CYLINDER.axial_position == 0.0
    moved = CYLINDER.replace(axial_position=-0.25)
    assert moved.axial_position == -0.25 and moved != CYLINDER
    assert moved.replace(phase=1.0).axial_position == -0.25  # a phase change keeps the place
    assert mc.Cylinder(0.05, 0.2, 1.0, 1.0, 0.05).axial_position == 0.0  # positional order unchanged


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, 1e31, "front", [0.1, 0.2], None])
def test_a_bad_axial_position_is_refused_by_name(value):
    with pytest.raises(mc.MechanismError, match="axial_position"):
        CYLINDER.replace(axial_position=value)


def test_axial_position_is_no_sweep_column_and_not_the_cores():
    from multicrank.machine.cylinder import UNIT_FIELDS, unit_columns
    from multicrank.motion.columns import MACHINE_COLUMNS, UNIT_COLUMNS

    assert "axial_position" not in MACHINE_COLUMNS + UNIT_COLUMNS + UNIT_FIELDS
    assert "axial_position" not in unit_columns([CYLINDER])


# -- throws and default bearings -------------------------------------------------------------


def test_throws_are_the_distinct_positions_and_each_cylinder_knows_its_own():
    machine = placed(0.3, 0.1, 0.1 + 1e-14, 0.45)  # 1e-14 m apart: one throw
    assert machine.throws == (0.1, 0.3, 0.45)
    assert machine.throw_index == (1, 0, 0, 2)
    assert placed(0.1, 0.1 + 1e-9).throws == (0.1, 0.1 + 1e-9)  # a nanometre apart: two


def test_default_bearings_interleave_the_throws():
    # Throws at 0.1, 0.3, 0.45: midpoints 0.2 and 0.375; outside, 0.1 − 0.2/2 and 0.45 + 0.15/2.
    assert placed(0.3, 0.1, 0.45).bearings == pytest.approx((0.0, 0.2, 0.375, 0.525), abs=1e-15)
    assert placed(0.0, 0.1).bearings == pytest.approx((-0.05, 0.05, 0.15), abs=1e-15)
    assert placed(-0.2, 0.2).bearings == pytest.approx((-0.4, 0.0, 0.4), abs=1e-15)


def test_one_throw_gets_a_bearing_one_crank_radius_either_side():
    machine = mc.Machine(
        [CYLINDER.replace(axial_position=0.2), CYLINDER.replace(axial_position=0.2, crank_radius=0.07)],
        shaft_inertia=0.5,
    )
    assert machine.throws == (0.2,) and machine.throw_index == (0, 0)
    assert machine.bearings == pytest.approx((0.13, 0.27), abs=1e-15)
    assert mc.presets.MACHINES["slow-compressor"].bearings == pytest.approx((-0.15, 0.15))  # r = 0.15 m


# -- given main bearings --------------------------------------------------------------------------


def test_given_bearings_are_kept_compared_pickled_and_replaced():
    machine = placed(0.1, 0.3).replace(main_bearings=[0, 0.2, 0.5])
    assert machine.main_bearings == (0.0, 0.2, 0.5) and machine.bearings == (0.0, 0.2, 0.5)
    assert all(type(z) is float for z in machine.main_bearings)
    assert machine != placed(0.1, 0.3) and machine == placed(0.1, 0.3).replace(main_bearings=(0.0, 0.2, 0.5))
    assert machine != placed(0.1, 0.3).replace(main_bearings=(0.0, 0.2, 0.6))
    for copied in (pickle.loads(pickle.dumps(machine)), copy.deepcopy(machine)):
        assert copied == machine and copied.main_bearings == (0.0, 0.2, 0.5)
    # replace keeps them (and the cylinders' places); None removes them
    assert machine.replace(shaft_inertia=1.0).main_bearings == (0.0, 0.2, 0.5)
    assert machine.replace(main_bearings=None).bearings == pytest.approx((0.0, 0.2, 0.4))
    with pytest.raises(AttributeError):
        machine.main_bearings = (0.0, 1.0)  # type: ignore[misc]


@pytest.mark.parametrize(
    "bearings, words",
    [
        ([0.15, 0.2, 0.5], "the throw at z = 0.1 m (cylinders[0]) is overhung, before the first bearing"),
        ([0.0, 0.2, 0.25], "the throw at z = 0.3 m (cylinders[1]) is overhung, beyond the last bearing"),
        ([0.0, 0.1, 0.5], "main_bearings[1] = 0.1 m is at the throw at z = 0.1 m"),
        ([0.0, 0.3 + 1e-15, 0.5], "main_bearings[1] = 0.3 m is at the throw at z = 0.3 m"),
        ([0.0, 0.5, 0.2], "main_bearings[2] = 0.2 m is not beyond main_bearings[1] = 0.5 m"),
        ([0.0, 0.0, 0.5], "main_bearings[1] = 0 m is not beyond"),
        ([0.0, math.nan, 0.5], "main_bearings[1] = nan is out of range"),
        ([0.0, math.inf], "main_bearings[1] = inf is out of range"),
        ([0.0], "at least two"),
        ([], "at least two"),
        (0.4, "at least two"),
        ([[0.0, 0.5]], "at least two"),
        (["front", "back"], "main_bearings must be a real number"),
        ([True, False], "main_bearings must be a real number"),
    ],
)
def test_bad_bearings_are_refused_naming_main_bearings_and_the_throw(bearings, words):
    with pytest.raises(mc.MechanismError) as error:
        placed(0.1, 0.3).replace(main_bearings=bearings)
    assert "main_bearings" in str(error.value) and words in str(error.value)


def test_moving_cylinders_out_of_given_bearings_is_refused():
    machine = placed(0.1, 0.3).replace(main_bearings=[0, 0.2, 0.5])
    moved = [c.replace(axial_position=0.6) if j == 1 else c for j, c in enumerate(machine.cylinders)]
    with pytest.raises(mc.MechanismError, match="overhung, beyond the last bearing"):
        machine.replace(cylinders=moved)


# -- a layout along the shaft ---------------------------------------------------------------------


def test_cylinder_spacing_places_each_throw_with_all_its_cylinders():
    vee = mc.Machine.from_layout("v6-60", CYLINDER, shaft_inertia=0.5, cylinder_spacing=0.1)
    assert [c.axial_position for c in vee.cylinders] == pytest.approx([0, 0, 0.1, 0.1, 0.2, 0.2], abs=1e-15)
    assert vee.throw_index == (0, 0, 1, 1, 2, 2)
    # the web and counterweight belong to the throw: on its first cylinder only
    assert [c.crank_mass for c in vee.cylinders] == [1.0, 0.0] * 3
    shifted = mc.Machine.from_layout(
        "boxer-2", CYLINDER.replace(axial_position=0.5), shaft_inertia=0.5, cylinder_spacing=0.12
    )
    assert shifted.throws == pytest.approx((0.5, 0.62), abs=1e-15)  # z₀ + t·s; a boxer's opposed pair on two throws
    together = mc.Machine.from_layout("v6-60", CYLINDER.replace(axial_position=0.5), shaft_inertia=0.5)
    assert together.throws == (0.5,)  # no spacing: every cylinder at the template's place


@pytest.mark.parametrize("spacing", [0.0, -0.1, math.nan, math.inf, "wide", [0.1, 0.2]])
def test_a_bad_spacing_is_refused_by_name(spacing):
    with pytest.raises(mc.MechanismError, match="cylinder_spacing"):
        mc.Machine.from_layout("v6-60", CYLINDER, shaft_inertia=0.5, cylinder_spacing=spacing)


def test_from_layout_passes_main_bearings_on():
    four = mc.Machine.from_layout(
        "inline-4-2t", CYLINDER, shaft_inertia=0.5, cylinder_spacing=0.1, main_bearings=[-0.05, 0.15, 0.35]
    )
    assert four.bearings == (-0.05, 0.15, 0.35) and four.throws == pytest.approx((0, 0.1, 0.2, 0.3), abs=1e-15)
    with pytest.raises(mc.MechanismError, match=r"main_bearings: the throw at z = 0 m .* is overhung"):
        mc.Machine.from_layout(
            "inline-4-2t", CYLINDER, shaft_inertia=0.5, cylinder_spacing=0.1, main_bearings=[0.05, 1]
        )


def crank_along_the_shaft(machine: mc.Machine) -> tuple[np.ndarray, np.ndarray]:
    """Pin angles [deg] (α + γ, mod 360, from the front pin's) and positions [m] from their
    centre, in order along the shaft: read off the cylinders' fields, nothing of the library's."""
    ordered = sorted(machine.cylinders, key=lambda c: c.axial_position)
    pins = np.degrees([c.phase + c.inclination for c in ordered])
    pins = np.round(np.mod(pins - pins[0], 360.0), 9) % 360.0
    z = np.array([c.axial_position for c in ordered])
    return pins, z - z.mean()


def couple(pins: np.ndarray, z: np.ndarray, order: int) -> float:
    """|Σ z_j e^{inβ_j}| [m]: the order-n free couple of a planar crank per unit rotating force."""
    return float(abs(np.sum(z * np.exp(1j * order * np.radians(pins)))))


def test_the_inline_four_is_the_textbook_crank_along_the_shaft():
    four = mc.Machine.from_layout("inline-4-4t", CYLINDER, shaft_inertia=0.5, cylinder_spacing=0.09)
    pins, z = crank_along_the_shaft(four)
    assert list(pins) == [0.0, 180.0, 180.0, 0.0]
    assert couple(pins, z, 1) == pytest.approx(0, abs=1e-15) and couple(pins, z, 2) == pytest.approx(0, abs=1e-15)
    # the firing order written along the shaft would rock the frame at first order
    wrong = np.array([0.0, 180.0, 0.0, 180.0])
    assert couple(wrong, z, 1) == pytest.approx(0.18)  # 2·(0.135 + 0.045) m


def test_the_inline_six_and_eight_are_mirror_symmetric_without_couples():
    for cylinders, expected in ((6, [0, 240, 120, 120, 240, 0]), (8, [0, 180, 270, 90, 90, 270, 180, 0])):
        machine = mc.Machine.from_layout(f"inline-{cylinders}-4t", CYLINDER, shaft_inertia=0.5, cylinder_spacing=0.1)
        pins, z = crank_along_the_shaft(machine)
        # 1-5-3-6-2-4: the pins of 1 and 6, 2 and 5, 3 and 4 pair up, 120° apart (0-120-240 in
        # the sense against rotation); the straight eight is two flat fours end to end, mirrored
        assert list(pins) == expected and list(pins) == list(pins[::-1])
        for order in (1, 2):
            assert couple(pins, z, order) == pytest.approx(0, abs=1e-14)


def test_the_firing_order_and_the_design_aid_keep_the_places():
    vee = mc.Machine.from_layout(
        "v-twin-90", CYLINDER, shaft_inertia=0.5, strokes=4, firing=np.radians([45, 675]), cylinder_spacing=0.03
    )
    assert [c.axial_position for c in vee.cylinders] == [0.0, 0.0]  # one shared pin: one throw
    four = mc.Machine.from_layout("inline-4-4t", CYLINDER, shaft_inertia=0.5, cylinder_spacing=0.1)
    bearing = four.replace(main_bearings=[-0.05, 0.05, 0.15, 0.25, 0.35])
    places = [c.axial_position for c in four.cylinders]
    phases = np.array([[c.phase for c in four.cylinders][::-1]])
    (candidate,) = _candidate_machines(bearing, phases)
    variant = machine_variant(bearing, {"phase[0]": 1.0, "counterweight_mass": 0.5})
    for changed in (candidate, variant):
        assert [c.axial_position for c in changed.cylinders] == places
        assert changed.main_bearings == bearing.main_bearings


def test_places_change_no_torque_and_the_motion_sweep_runs():
    base = mc.presets.MACHINES["inline-4"]
    spaced = mc.Machine.from_layout(
        "inline-4-4t",
        base.cylinders[0],
        shaft_inertia=base.shaft_inertia,
        rpm=base.rpm,
        cylinder_spacing=0.092,
        main_bearings=[-0.046, 0.046, 0.138, 0.23, 0.322],
    )
    # the same cylinders but for their places (the preset has its own spacing)
    unplaced = [c.replace(axial_position=0.0) for c in base.cylinders]
    assert [c.replace(axial_position=0.0) for c in spaced.cylinders] == unplaced
    assert mc.steady_state(spaced).delta == mc.steady_state(base).delta
    axes = {"rpm": [3000.0, 6000.0], "counterweight_mass": [0.5, 1.3]}
    swept = mc.motion_sweep(spaced, mc.MachineGrid(spaced, **axes))
    expected = mc.motion_sweep(base, mc.MachineGrid(base, **axes))
    assert len(swept) == 4 and np.array_equal(swept["delta"].to_numpy(), expected["delta"].to_numpy())


# -- machine files ----------------------------------------------------------------------------------

CYLINDER_TOML = """crank_radius = 0.05
rod_length = 0.2
piston_mass = 1.0
rod_mass = 1.0
rod_cg = 0.05
crank_mass = 1.0
crank_cg_radius = 0.02"""


def test_a_file_places_cylinders_spaces_a_layout_and_gives_bearings(tmp_path):
    listed = tmp_path / "listed.toml"
    listed.write_text(
        f"shaft_inertia = 0.5\nmain_bearings = [-0.1, 0.05, 0.2]\n"
        f"[[cylinder]]\n{CYLINDER_TOML}\naxial_position = -0.025\n"
        f"[[cylinder]]\n{CYLINDER_TOML}\naxial_position = 0.125\nphase_deg = 180\n",
        encoding="utf-8",
    )
    machine = mc.Machine.from_toml(listed)
    expected = mc.Machine(
        [CYLINDER.replace(axial_position=-0.025), CYLINDER.replace(axial_position=0.125, phase=math.pi)],
        shaft_inertia=0.5,
        main_bearings=[-0.1, 0.05, 0.2],
        name="listed",
    )
    assert machine == expected and machine.main_bearings == (-0.1, 0.05, 0.2)
    layout = tmp_path / "layout.toml"
    layout.write_text(
        f'layout = "v6-60"\nshaft_inertia = 0.5\ncylinder_spacing = 0.11\n[cylinder]\n{CYLINDER_TOML}\n'
        "axial_position = 0.02\n",
        encoding="utf-8",
    )
    spaced = mc.Machine.from_toml(layout)
    assert spaced == mc.Machine.from_layout(
        "v6-60", CYLINDER.replace(axial_position=0.02), shaft_inertia=0.5, cylinder_spacing=0.11, name="layout"
    )
    assert spaced.throws == pytest.approx((0.02, 0.13, 0.24), abs=1e-15)


@pytest.mark.parametrize(
    "head, extra, words",
    [
        ("cylinder_spacing = 0.1\n", "", "cylinder_spacing: cylinder_spacing places a layout's throws"),
        ('layout = "v6-60"\ncylinder_spacing = -0.1\n', "", "cylinder_spacing = -0.1 is out of range"),
        ('layout = "v6-60"\ncylinder_spacing = "wide"\n', "", "cylinder_spacing: must be a number"),
        ("main_bearings = [0.1, 0.2]\n", "", "main_bearings: the throw at z = 0 m (cylinders[0]) is overhung"),
        ("main_bearings = [-0.1, 0.0, 0.2]\n", "", "main_bearings[1] = 0 m is at the throw"),
        ("main_bearings = [0.1]\n", "", "at least two"),
        ("main_bearings = 0.1\n", "", "main_bearings: must be an array of numbers"),
        ("", "axial_position = nan\n", "axial_position = nan is out of range"),
        ("", 'axial_position = "front"\n', "cylinder.axial_position: must be a number"),
    ],
)
def test_file_mistakes_name_the_file_and_the_key(tmp_path, head, extra, words):
    path = tmp_path / "bad.toml"
    path.write_text(f"shaft_inertia = 0.5\n{head}[cylinder]\n{CYLINDER_TOML}\n{extra}", encoding="utf-8")
    with pytest.raises(mc.MechanismError) as error:
        mc.Machine.from_toml(path)
    message = str(error.value)
    assert message.startswith(f"{path}: ") and words in message and "\n" not in message


# -- pickles of 0.1 -----------------------------------------------------------------------------------


def test_machines_and_cylinders_of_0_1_load_with_no_places_and_default_bearings():
    with PICKLES.open("rb") as handle:
        old = pickle.load(handle)["objects"]
    assert old["cylinder"].axial_position == 0.0 and "axial_position" not in vars(old["cylinder"])
    for key in ("machine:slow-compressor", "machine:inline-4", "machine:boxer-compressor"):
        machine = old[key]
        assert "main_bearings" not in vars(machine) and machine.main_bearings is None
        assert {c.axial_position for c in machine.cylinders} == {0.0}
        assert machine.throws == (0.0,) and machine.throw_index == (0,) * len(machine)
        radius = max(c.crank_radius for c in machine.cylinders)
        assert machine.bearings == (-radius, radius)
        assert machine.replace(main_bearings=[-1.0, 1.0]).bearings == (-1.0, 1.0)
