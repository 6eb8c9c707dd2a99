"""Machine.from_layout: any preset layout with one cylinder template on every bank — its phases,
its firing order, its crank webs per throw, and its gravity against the dimensionless paths."""

import math

import numpy as np
import pytest

import multicrank as mc
from multicrank.gravity.layouts import LAYOUTS, Layout

#: A car cylinder with a web and counterweight (the old inline-4 preset's numbers).
CYLINDER = mc.Cylinder(
    crank_radius=0.0425,
    rod_length=0.140,
    rod_cg=0.100,
    piston_mass=0.45,
    rod_mass=0.55,
    crank_mass=1.2,
    crank_cg_radius=0.030,
    counterweight_mass=1.3,
    counterweight_radius=0.035,
)
SHAFT, RPM = 0.18, 800.0
PHI = np.linspace(-1.0, 2 * np.pi + 1.0, 97)


def layout_machine(name, cylinder=CYLINDER, **options):
    return mc.Machine.from_layout(name, cylinder, shaft_inertia=SHAFT, rpm=RPM, **options)


def phases_deg(machine):
    return np.degrees([c.phase for c in machine.cylinders])


def firing_intervals(machine):
    """The gaps [deg] between the cylinders' phases around the cycle, sorted."""
    cycle = 180.0 * machine.strokes
    ordered = np.sort(np.mod(phases_deg(machine), cycle))
    return np.sort(np.diff(np.append(ordered, ordered[0] + cycle)))


def old_layout_engine(layout, cylinder, *, shaft_inertia, rpm, g=mc.STANDARD_GRAVITY):
    """The removed ``Layout.physical_engine`` rebuilt from the public dimensionless pieces: every
    cylinder the piston and rod (u1, and the rod's big end in u2) on the layout's throws, and
    every throw one purely rotating unit (u1 = 0, γ = 0, α = β) for its web and counterweight.
    (Checked number for number against the method before it was removed, commit 278adff.)"""
    common = dict(
        crank_radius=cylinder.crank_radius,
        rod_length=cylinder.rod_length,
        rod_cg=cylinder.rod_cg,
        shaft_inertia=shaft_inertia,
        rpm=rpm,
        g=g,
    )
    u1, rod_u2 = mc.dimensionless_moments(piston_mass=cylinder.piston_mass, rod_mass=cylinder.rod_mass, **common)
    _, web_u2 = mc.dimensionless_moments(
        piston_mass=0.0,
        rod_mass=0.0,
        crank_mass=cylinder.crank_mass,
        crank_cg_radius=cylinder.crank_cg_radius,
        counterweight_mass=cylinder.counterweight_mass,
        counterweight_radius=cylinder.counterweight_radius,
        **common,
    )
    cylinders = layout.engine(crank_ratio=cylinder.crank_ratio, u1=float(u1), u2=float(rod_u2))
    throws = np.radians(layout.throws)
    return mc.Engine(
        phase=np.concatenate([cylinders.phase, throws]),
        inclination=np.concatenate([cylinders.inclination, np.zeros(len(throws))]),
        crank_ratio=cylinder.crank_ratio,
        u1=np.concatenate([cylinders.u1, np.zeros(len(throws))]),
        u2=np.concatenate([cylinders.u2, np.full(len(throws), float(web_u2))]),
    )


@pytest.mark.parametrize("strokes", [2, 4])
@pytest.mark.parametrize("cranks", range(1, 13))
def test_inline_layouts_keep_the_regular_phase_set(cranks, strokes):
    machine = layout_machine(f"inline-{cranks}-{strokes}t")
    assert machine.strokes == strokes and len(machine) == cranks
    # The set (the four-stroke 4, 5, 6 and 8 are numbered as their textbook cranks).
    phases = np.sort([c.phase for c in machine.cylinders])
    np.testing.assert_allclose(phases, mc.crank_phases(cranks, strokes), atol=1e-12)
    assert all(c.inclination == math.pi / 2 for c in machine.cylinders)


@pytest.mark.parametrize(
    "name, intervals",
    [
        ("v8-cross", [90] * 8),
        ("v8-flat", [90] * 8),
        ("v12-60", [60] * 12),
        ("w12", [60] * 12),
        ("boxer-4", [180] * 4),
        ("boxer-6", [120] * 6),
        ("v-180-4", [180] * 4),
        ("v-twin-45", [315, 405]),  # the classic 45° V-twin's uneven beat
        ("v-twin-90", [270, 450]),
        ("twin-270", [270, 450]),
        ("boxer-2", [360, 360]),
    ],
)
def test_four_stroke_firing_is_as_even_as_the_crank_allows(name, intervals):
    machine = layout_machine(name, strokes=4)
    np.testing.assert_allclose(firing_intervals(machine), sorted(intervals), atol=1e-9)


@pytest.mark.parametrize("name", sorted(LAYOUTS))
def test_every_layout_places_its_cylinders_by_its_throws(name):
    layout = LAYOUTS[name]
    for strokes in [layout.strokes] if layout.strokes else [2, 4]:
        machine = layout_machine(name, strokes=strokes)
        crank = [beta - gamma for beta, banks in zip(layout.throws, layout.banks, strict=True) for gamma in banks]
        gammas = [gamma for banks in layout.banks for gamma in banks]
        assert len(machine) == layout.cylinders == len(crank)
        # α ≡ β − γ (mod 360°), in [0, cycle); γ the bank.
        turns = (phases_deg(machine) - np.asarray(crank)) / 360.0
        np.testing.assert_allclose(turns, np.round(turns), atol=1e-12)
        assert np.all((phases_deg(machine) >= 0) & (phases_deg(machine) < 180.0 * strokes))
        np.testing.assert_allclose(np.degrees([c.inclination for c in machine.cylinders]), gammas, atol=1e-12)
        # One web per throw: the first cylinder on each throw.
        webs = [c.crank_mass for c in machine.cylinders]
        expected = [CYLINDER.crank_mass if i == 0 else 0.0 for banks in layout.banks for i in range(len(banks))]
        assert webs == expected
        assert [c.counterweight_mass for c in machine.cylinders] == [
            CYLINDER.counterweight_mass * (w > 0) for w in expected
        ]
        if strokes == 4:
            # No single cylinder moved by a turn makes the firing more even (largest interval, then spread).
            best = firing_intervals(machine)
            for j in range(len(machine)):
                moved = machine.cylinders[j].phase + 2 * math.pi
                other = machine.replace(
                    cylinders=[
                        *machine.cylinders[:j],
                        machine.cylinders[j].replace(phase=moved),
                        *machine.cylinders[j + 1 :],
                    ]
                )
                gaps = firing_intervals(other)
                assert (round(gaps.max(), 9), round(np.sum(gaps**2), 6)) >= (
                    round(best.max(), 9),
                    round(np.sum(best**2), 6),
                )


@pytest.mark.parametrize("name", sorted(LAYOUTS))
def test_gravity_is_the_old_physical_layout_engines(name):
    """U and Q of machine.engine(rpm) equal the removed Layout.physical_engine's (webs as units of
    their own on the throws): the same masses in the same places, one web per throw."""
    layout = LAYOUTS[name]
    machine = layout_machine(name)
    old = old_layout_engine(layout, CYLINDER, shaft_inertia=SHAFT, rpm=RPM)
    engine = machine.engine()
    np.testing.assert_allclose(engine.generalized_force(PHI), old.generalized_force(PHI), rtol=1e-12, atol=1e-16)
    # Each unit's energy is measured from its own ψ = 0: the web folded into a cylinder moves that
    # zero by a constant, so energies agree up to one.
    shift = engine.potential_energy(PHI) - old.potential_energy(PHI)
    np.testing.assert_allclose(shift, shift[0], rtol=0, atol=1e-15)
    # In joules: U* × I_w ω² is the machine's own potential energy (up to the same kind of constant).
    scale = SHAFT * (math.pi * RPM / 30) ** 2
    joules = machine.potential_energy(PHI)
    np.testing.assert_allclose(
        joules - joules[0], scale * (old.potential_energy(PHI) - old.potential_energy(PHI[0])), rtol=1e-12, atol=1e-13
    )
    np.testing.assert_allclose(machine.gravity_torque(PHI), -scale * old.generalized_force(PHI), rtol=1e-12, atol=1e-13)


@pytest.mark.parametrize("name", sorted(LAYOUTS))
def test_gravity_is_the_dimensionless_layout_engine_where_it_applies(name):
    """Layout.engine(crank_ratio, u1, u2) puts the same u2 on every cylinder: the machine's where
    every cylinder has its own throw (in-line, boxer, 270° twin), and for any layout when the
    cylinder has no web."""
    layout = LAYOUTS[name]
    own_throws = all(len(banks) == 1 for banks in layout.banks)
    cylinder = CYLINDER if own_throws else CYLINDER.replace(crank_mass=0.0, counterweight_mass=0.0)
    machine = layout_machine(name, cylinder)
    u1, u2 = mc.dimensionless_moments(
        **{f: getattr(cylinder, f) for f in ("crank_radius", "rod_length", "rod_cg", "piston_mass", "rod_mass")},
        crank_mass=cylinder.crank_mass,
        crank_cg_radius=cylinder.crank_cg_radius,
        counterweight_mass=cylinder.counterweight_mass,
        counterweight_radius=cylinder.counterweight_radius,
        shaft_inertia=SHAFT,
        rpm=RPM,
    )
    expected = layout.engine(crank_ratio=cylinder.crank_ratio, u1=u1, u2=u2)
    engine = machine.engine()
    np.testing.assert_allclose(engine.potential_energy(PHI), expected.potential_energy(PHI), rtol=1e-12, atol=1e-16)
    np.testing.assert_allclose(engine.generalized_force(PHI), expected.generalized_force(PHI), rtol=1e-12, atol=1e-16)
    assert engine.speed_fluctuation() == pytest.approx(expected.speed_fluctuation(), rel=1e-9, abs=1e-18)


def test_a_v_twin_has_one_web_on_its_shared_pin():
    machine = layout_machine("v-twin-90")
    no_web = layout_machine("v-twin-90", CYLINDER.replace(crank_mass=0.0, counterweight_mass=0.0))
    # The web's gravity torque alone: g (m_s r_s − m_p r_p) cos(pin angle), the pin at φ + 90°.
    web = mc.STANDARD_GRAVITY * (1.2 * 0.030 - 1.3 * 0.035)
    np.testing.assert_allclose(
        machine.gravity_torque(PHI) - no_web.gravity_torque(PHI),
        -web * np.cos(PHI + math.pi / 2),
        rtol=1e-12,
        atol=1e-14,
    )


def test_names_notes_and_the_templates_place_are_the_layouts():
    template = CYLINDER.replace(phase=1.0, inclination=0.3)
    machine = mc.Machine.from_layout("v8-cross", template, shaft_inertia=1.0)
    assert machine.name == "v8-cross" and machine.note == LAYOUTS["v8-cross"].note and machine.strokes == 2
    assert {round(c.inclination, 12) for c in machine.cylinders} == {
        round(math.radians(45), 12),
        round(math.radians(135), 12),
    }
    named = mc.Machine.from_layout(
        LAYOUTS["v8-cross"], template, shaft_inertia=1.0, name="mine", note="n", rpm=3000, rpm_range=(800, 6000), g=0.0
    )
    assert (named.name, named.note, named.rpm, named.rpm_range, named.g) == ("mine", "n", 3000.0, (800.0, 6000.0), 0.0)
    assert layout_machine("inline-4-4t").strokes == 4  # the layout's own cycle


def test_firing_by_hand():
    crank = np.radians([0.0, 180.0, 540.0, 360.0])  # inline-4-4t as written: 1-3-4-2
    order = crank + np.radians([0.0, 360.0, -360.0, 0.0])  # 1-2-4-3 instead
    machine = layout_machine("inline-4-4t", firing=order)
    np.testing.assert_allclose([c.phase for c in machine.cylinders], np.mod(order, 4 * math.pi), atol=1e-12)
    with pytest.raises(mc.MechanismError, match=r"firing\[1\]"):
        layout_machine("inline-4-4t", firing=crank + np.radians([0.0, 90.0, 0.0, 0.0]))
    with pytest.raises(mc.MechanismError, match="firing"):
        layout_machine("inline-4-4t", firing=crank[:3])


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: mc.Machine.from_layout("v7", CYLINDER, shaft_inertia=1.0), "layout"),
        (lambda: mc.Machine.from_layout(7, CYLINDER, shaft_inertia=1.0), "layout"),
        (lambda: mc.Machine.from_layout("v8-cross", {"bore": 0.1}, shaft_inertia=1.0), "cylinder"),
        (lambda: mc.Machine.from_layout("inline-4-4t", CYLINDER, shaft_inertia=1.0, strokes=2), "strokes"),
        (lambda: mc.Machine.from_layout("v8-cross", CYLINDER, shaft_inertia=1.0, strokes=3), "strokes"),
        (lambda: mc.Machine.from_layout("v8-cross", CYLINDER, shaft_inertia=-1.0), "shaft_inertia"),
        (lambda: mc.Machine.from_layout("v8-cross", CYLINDER, shaft_inertia=1.0, rpm=-5), "rpm"),
        (
            lambda: mc.Machine.from_layout(
                Layout("v20", "twenty", tuple(range(0, 360, 36)), ((45.0, 135.0),) * 10),
                CYLINDER,
                shaft_inertia=1.0,
                strokes=4,
            ),
            "firing",
        ),
        (
            lambda: mc.Machine.from_layout(Layout("odd", "bad", (0.0, 90.0), ((90.0,),)), CYLINDER, shaft_inertia=1.0),
            "banks",
        ),
    ],
)
def test_bad_layout_machines_name_the_parameter(call, name):
    with pytest.raises(mc.MechanismError, match=name):
        call()


def test_a_four_stroke_diagram_needs_a_four_stroke_machine():
    cylinder = CYLINDER.replace(bore=0.086)
    four = cylinder.replace(
        pressure=cylinder.engine_diagram(intake_pressure=1e5, heat_release=1300.0, compression_ratio=10.5)
    )
    with pytest.raises(mc.MechanismError, match=r"cylinders\[0\]\.pressure .*strokes=4"):
        mc.Machine.from_layout("v8-cross", four, shaft_inertia=0.25, strokes=2)
    with pytest.raises(mc.MechanismError, match=r"cylinders\[0\]\.pressure .*strokes=4"):
        mc.Machine([four], shaft_inertia=0.25)
    # Without strokes, the template's diagram says four (the layout has no cycle of its own).
    assert mc.Machine.from_layout("v8-cross", four, shaft_inertia=0.25).strokes == 4
    assert mc.Machine.from_layout("v8-cross", CYLINDER, shaft_inertia=0.25).strokes == 2
    # A compressor's 2π diagram repeats over a four-stroke cycle: allowed.
    two = cylinder.replace(
        pressure=cylinder.compressor_diagram(suction_pressure=1e5, discharge_pressure=4e5, clearance_ratio=0.1)
    )
    machine = mc.Machine([two], shaft_inertia=1.0, strokes=4)
    phi = np.linspace(0, 2 * np.pi, 50)
    np.testing.assert_allclose(machine.gas_torque(phi + 2 * np.pi), machine.gas_torque(phi), rtol=1e-12, atol=1e-9)
