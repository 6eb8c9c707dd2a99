"""mc.Cylinder and mc.Machine: their relation to the dimensionless API, their errors, and
the parallel threshold. (The first-principles mpmath oracle is tests/machine/test_machine_oracle.py.)"""

import math

import numpy as np
import pytest

import multicrank as mc

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
)


def inline_machine(cranks=3, strokes=4, **changes):
    phases = mc.crank_phases(cranks, strokes)
    cylinder = mc.Cylinder(**{**CYLINDER, **changes})
    return mc.Machine([cylinder.replace(phase=a) for a in phases], shaft_inertia=45.0, strokes=strokes)


def test_engine_at_a_speed_is_the_dimensionless_moments():
    machine = inline_machine(inclination=1.1)
    engine = machine.engine(120)
    u1, u2 = mc.dimensionless_moments(**{k: v for k, v in CYLINDER.items()}, shaft_inertia=45.0, rpm=120)
    np.testing.assert_allclose(engine.u1, u1, rtol=1e-15)
    np.testing.assert_allclose(engine.u2, u2, rtol=1e-15)
    np.testing.assert_array_equal(engine.phase, mc.crank_phases(3, 4))
    np.testing.assert_array_equal(engine.inclination, 1.1)
    assert engine.crank_ratio[0] == pytest.approx(0.25, rel=1e-15)


def test_energy_and_torque_are_the_engines_times_i_omega_squared():
    machine = inline_machine(inclination=0.7)
    phi = np.linspace(-1, 8, 301)
    omega = math.pi * 300 / 30
    scale = machine.shaft_inertia * omega**2
    engine = machine.engine(300)
    np.testing.assert_allclose(
        machine.potential_energy(phi), scale * engine.potential_energy(phi), rtol=1e-13, atol=1e-11
    )
    np.testing.assert_allclose(
        machine.gravity_torque(phi), -scale * engine.generalized_force(phi), rtol=1e-13, atol=1e-11
    )
    assert np.all(machine.replace(g=0.0).potential_energy(phi) == 0.0)


def test_shapes_grids_and_the_inertia_torque():
    machine = inline_machine()
    phi = np.linspace(0, 4 * np.pi, 24).reshape(2, 3, 4)
    j, dj = machine.reduced_inertia(phi)
    assert j.shape == dj.shape == (2, 3, 4)
    assert machine.piston_travel(phi).shape == (3, 2, 3, 4)
    np.testing.assert_array_equal(machine.inertia_torque(phi, 20.0), -0.5 * dj * 400.0)
    grid = mc.uniform_grid(1000, 0, 4 * np.pi)
    j_grid, _ = machine.reduced_inertia(grid)
    j_points, _ = machine.reduced_inertia(np.asarray(grid))
    np.testing.assert_allclose(j_grid, j_points, rtol=1e-14)
    # J never falls below the shaft's own inertia plus the rods' big ends.
    big_ends = 3 * 60.0 * (0.4 / 0.6) * 0.15**2
    assert j.min() >= 45.0 + big_ends - 1e-12


def test_reduced_inertia_names_its_pair_as_the_motion_results_do():
    """J and J′ come as a pair that also says which is which (issue 27, item 7): the names of
    the steady state's and the transient's arrays, ``reduced_inertia`` and ``reduced_inertia_slope``."""
    machine = inline_machine(cranks=2, strokes=2)
    phi, h = np.linspace(0.0, 2 * np.pi, 7), 1e-5
    pair = machine.reduced_inertia(phi)
    inertia, slope = pair  # still unpacks as two arrays
    assert pair._fields == ("reduced_inertia", "reduced_inertia_slope")
    assert pair.reduced_inertia is inertia and pair.reduced_inertia_slope is slope
    # the slope is dJ/dφ: a central difference of J (error ~h²·J‴ ≈ 1e-10 kg·m²/rad)
    numeric = (machine.reduced_inertia(phi + h)[0] - machine.reduced_inertia(phi - h)[0]) / (2 * h)
    np.testing.assert_allclose(slope, numeric, rtol=0, atol=1e-7)
    # J ≥ the shaft's inertia plus both rods' big ends m_k z_k/l r²
    assert np.all(inertia >= 45.0 + 2 * 60.0 * (0.4 / 0.6) * 0.15**2 - 1e-12)


def test_threshold_per_call_changes_no_bit():
    machine = inline_machine(cranks=6, bore=0.2, pressure=lambda t: 1e5 * (1 + np.cos(t)))
    phi = np.linspace(0, 4 * np.pi, 50_001)
    serial = [
        machine.reduced_inertia(phi, parallel_threshold=2**62)[1],
        machine.gas_torque(phi, parallel_threshold=2**62),
    ]
    parallel = [machine.reduced_inertia(phi, parallel_threshold=0)[1], machine.gas_torque(phi, parallel_threshold=0)]
    for a, b in zip(serial, parallel, strict=True):
        assert a.tobytes() == b.tobytes()


def test_a_constant_pressure_does_its_work_over_each_stroke():
    # ∫ M_gas dφ over a revolution = Σ p·A·(stroke down) for a pressure on the way down only:
    # p = const while θ ∈ [0, π) (outer → inner dead centre), else 0.
    p = 3e5
    cylinder = dict(CYLINDER, bore=0.25, pressure=lambda t: np.where(np.mod(t, 2 * np.pi) < np.pi, p, 0.0))
    machine = mc.Machine([mc.Cylinder(**cylinder)], shaft_inertia=10.0)
    phi = np.linspace(0, np.pi, 200_001)
    work = np.trapezoid(machine.gas_torque(phi), phi)
    assert work == pytest.approx(p * math.pi * 0.25**2 / 4 * 2 * 0.15, rel=1e-9)


@pytest.mark.parametrize(
    "changes, name",
    [
        ({"bore": -0.1}, "bore"),
        ({"bore": 0.1, "piston_rod_diameter": 0.1}, "piston_rod_diameter"),
        ({"rod_length": 0.1}, "rod_length"),
        ({"rod_cg": 0.7}, "rod_cg"),
        ({"piston_mass": -1.0}, "piston_mass"),
        ({"rod_inertia": float("nan")}, "rod_inertia"),
        ({"crank_radius": "big"}, "crank_radius"),
        ({"pressure": 3.0}, "pressure"),
        ({"phase": float("inf")}, "phase"),
        ({"counterweight_radius": -0.1}, "counterweight_radius"),
    ],
)
def test_bad_cylinders_name_the_parameter(changes, name):
    with pytest.raises(mc.MechanismError, match=name):
        mc.Cylinder(**{**CYLINDER, **changes})


@pytest.mark.parametrize(
    "build, name",
    [
        (lambda c: mc.Machine([], shaft_inertia=1.0), "cylinders"),
        (lambda c: mc.Machine(c, shaft_inertia=1.0), "cylinders"),
        (lambda c: mc.Machine([c], shaft_inertia=0.0), "shaft_inertia"),
        (lambda c: mc.Machine([c], shaft_inertia=1.0, strokes=3), "strokes"),
        (lambda c: mc.Machine([c], shaft_inertia=1.0, g=float("nan")), "g"),
        (lambda c: mc.Machine([c], shaft_inertia=1.0).engine(0.0), "rpm"),
        (lambda c: mc.Machine([c], shaft_inertia=1.0).replace(bore=1), "bore"),
    ],
)
def test_bad_machines_name_the_parameter(build, name):
    with pytest.raises(mc.MechanismError, match=name):
        build(mc.Cylinder(**CYLINDER))


def test_a_pressure_that_fails_or_returns_nan_is_named():
    nan = mc.Machine([mc.Cylinder(**CYLINDER, bore=0.2, pressure=lambda t: np.full_like(t, np.nan))], shaft_inertia=1)
    with pytest.raises(mc.MechanismError, match="pressure"):
        nan.gas_torque(np.linspace(0, 1, 5))
    broken = mc.Machine([mc.Cylinder(**CYLINDER, bore=0.2, pressure_crank_end=lambda t: 1 / 0)], shaft_inertia=1)
    with pytest.raises(mc.MechanismError, match="pressure_crank_end"):
        broken.gas_torque(np.linspace(0, 1, 5))


def test_descriptive_fields_are_kept_and_carried_by_replace():
    machine = inline_machine().replace(rpm=120, rpm_range=(60, 300), note="a test machine")
    assert (machine.rpm, machine.rpm_range, machine.note) == (120.0, (60.0, 300.0), "a test machine")
    faster = machine.replace(shaft_inertia=50.0)
    assert (faster.rpm, faster.rpm_range, faster.note, faster.shaft_inertia) == (
        120.0,
        (60.0, 300.0),
        "a test machine",
        50.0,
    )
    assert machine.replace(rpm=None).rpm is None and machine.replace(rpm_range=None).rpm_range is None
    assert "120 rpm" in repr(machine)
    # engine() defaults to the machine's own speed and equals an explicit one.
    np.testing.assert_array_equal(machine.engine().u1, machine.engine(120).u1)
    assert machine.engine().u1[0] != machine.engine(240).u1[0]
    with pytest.raises(mc.MechanismError, match="rpm is required"):
        inline_machine().engine()


@pytest.mark.parametrize(
    "changes, name",
    [
        ({"rpm": 0.0}, "rpm"),
        ({"rpm": float("nan")}, "rpm"),
        ({"rpm": "fast"}, "rpm"),
        ({"rpm_range": (300.0, 60.0)}, "rpm_range"),
        ({"rpm_range": (0.0, 60.0)}, "rpm_range"),
        ({"rpm_range": (60.0,)}, "rpm_range"),
        ({"rpm": 400.0, "rpm_range": (60.0, 300.0)}, "rpm"),
        ({"note": 3}, "note"),
        ({"name": None}, "name"),
        ({"flywheel": 3.0}, "flywheel"),
    ],
)
def test_bad_descriptive_fields_name_the_parameter(changes, name):
    with pytest.raises(mc.MechanismError, match=name):
        inline_machine().replace(**changes)


def test_a_two_mass_rod_stays_one_when_its_rod_changes():
    """replace() of a rod's mass, length or centre of gravity recomputes a default (two-mass)
    rod inertia — a sweep of rod_mass would otherwise keep the first rod's — and keeps one
    that was given."""
    default = mc.Cylinder(crank_radius=0.1, rod_length=0.4, piston_mass=5.0, rod_mass=3.0, rod_cg=0.15)
    assert default.rod_inertia == 3.0 * 0.15 * (0.4 - 0.15)
    for change in ({"rod_mass": 6.0}, {"rod_length": 0.5}, {"rod_cg": 0.1}):
        changed = default.replace(**change)
        fresh = mc.Cylinder(
            **{**dict(crank_radius=0.1, rod_length=0.4, piston_mass=5.0, rod_mass=3.0, rod_cg=0.15), **change}
        )
        assert changed.rod_inertia == fresh.rod_inertia != default.rod_inertia
    given = default.replace(rod_inertia=0.01)
    assert given.replace(rod_mass=6.0).rod_inertia == 0.01
    assert default.replace(rod_mass=6.0, rod_inertia=0.02).rod_inertia == 0.02
    assert default.replace(piston_mass=9.0).rod_inertia == default.rod_inertia


def test_a_machine_is_immutable_so_its_native_machine_never_answers_for_an_old_one():
    """A field set after a machine's first steady state would leave the native machine it owns
    (with the tables of that steady state) answering for the old machine: a machine refuses
    it, in the words of a frozen dataclass, and points to replace(); replace() gives a new
    machine whose answer is its own (a heavier shaft: a smaller δ)."""
    import dataclasses
    import pickle

    compressor = mc.presets.MACHINES["slow-compressor"]
    machine = compressor.replace(name="mine")
    before = mc.steady_state(machine, rpm=120).delta
    with pytest.raises(dataclasses.FrozenInstanceError, match=r"shaft_inertia.*replace\(shaft_inertia="):
        machine.shaft_inertia = 10 * machine.shaft_inertia
    with pytest.raises(AttributeError, match="immutable"):
        del machine.name
    assert mc.steady_state(machine, rpm=120).delta == before
    heavier = machine.replace(shaft_inertia=10 * machine.shaft_inertia)
    assert mc.steady_state(heavier, rpm=120).delta < 0.2 * before
    with pytest.raises(AttributeError, match="immutable"):
        pickle.loads(pickle.dumps(machine)).g = 0.0
