"""Machine.piston_forces and the cylinder's areas (machine/gas.py, machine/cylinder.py) against
the textbook forces written here: F = p·πD²/4 − p_c·π(D² − d²)/4 per piston, evaluated from
the pressure callables at each unit's own cycle angle, with nothing of the core."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import multicrank as mc
from multicrank.presets import MACHINES


def _head(theta):
    return 2e5 * (1 + np.cos(theta)) + 1e4 * np.sin(3 * theta)


def _crank_end(theta):
    return 1.5e5 * (1 - np.cos(theta))


def _machine(bore, rod, phases):
    cylinders = [
        mc.Cylinder(
            crank_radius=0.05,
            rod_length=0.2,
            piston_mass=1.0,
            rod_mass=1.0,
            rod_cg=0.05,
            bore=bore,
            piston_rod_diameter=rod,
            pressure=_head,
            pressure_crank_end=_crank_end if j % 2 == 0 else None,
            phase=phase,
        )
        for j, phase in enumerate(phases)
    ]
    return mc.Machine(cylinders, shaft_inertia=1.0, strokes=2, name="gas")


@given(
    bore=st.floats(0.01, 1.0),
    rod_fraction=st.floats(0.0, 0.9),
    phases=st.lists(st.floats(0.0, 2 * math.pi), min_size=1, max_size=4),
)
def test_piston_forces_are_the_pressures_times_the_areas_at_each_units_cycle_angle(bore, rod_fraction, phases):
    rod = rod_fraction * bore
    machine = _machine(bore, rod, phases)
    phi = np.linspace(-1.0, 8.0, 13)
    forces = machine.piston_forces(phi)
    assert forces.shape == (len(phases), phi.size)
    for j, phase in enumerate(phases):
        theta = np.mod(phi + phase, 2 * math.pi)
        head = _head(theta) * math.pi * bore**2 / 4
        crank = _crank_end(theta) * math.pi * (bore**2 - rod**2) / 4 if j % 2 == 0 else 0.0
        np.testing.assert_allclose(forces[j], head - crank, rtol=1e-13, atol=1e-9 * np.abs(head).max())


def test_piston_forces_keep_the_shape_of_phi_after_the_units():
    machine = _machine(0.1, 0.02, [0.0, 1.0, 2.0])
    phi = np.linspace(0, 6, 12).reshape(3, 4)
    assert machine.piston_forces(phi).shape == (3, 3, 4)
    assert machine.piston_forces(0.5).shape == (3,)
    np.testing.assert_array_equal(machine.piston_forces(phi)[:, 1, 2], machine.piston_forces(phi[1, 2]))


def test_a_cylinder_without_bore_or_pressure_has_no_force():
    cylinders = [
        mc.Cylinder(
            crank_radius=0.05, rod_length=0.2, piston_mass=1.0, rod_mass=1.0, rod_cg=0.05, bore=0.0, pressure=_head
        ),
        mc.Cylinder(crank_radius=0.05, rod_length=0.2, piston_mass=1.0, rod_mass=1.0, rod_cg=0.05, bore=0.1),
    ]
    machine = mc.Machine(cylinders, shaft_inertia=1.0, strokes=2, name="none")
    np.testing.assert_array_equal(machine.piston_forces(np.linspace(0, 6, 7)), 0.0)


@pytest.mark.parametrize("name", list(MACHINES))
def test_the_areas_are_the_circles_of_the_bore_and_around_the_rod(name):
    for cylinder in MACHINES[name].cylinders:
        d, rod = cylinder.bore, cylinder.piston_rod_diameter
        assert cylinder.piston_area == pytest.approx(math.pi * d * d / 4, rel=1e-15)
        assert cylinder.crank_end_area == pytest.approx(math.pi * (d * d - rod * rod) / 4, rel=1e-15)
        assert cylinder.swept_volume() == pytest.approx(math.pi * d * d / 4 * 2 * cylinder.crank_radius, rel=1e-15)


def test_the_native_forces_refuse_mismatched_lengths_by_name():
    from multicrank._native import piston_forces

    one = np.array([0.1])
    with pytest.raises(mc.MechanismError, match="piston_rod_diameter"):
        piston_forces(one, np.array([0.0, 0.0]), one, one)
    with pytest.raises(mc.MechanismError, match="crank_end"):
        piston_forces(one, np.array([0.0]), one, np.array([1.0, 2.0]))
    with pytest.raises(mc.MechanismError, match="piston_rod_diameter"):
        piston_forces(one, np.array([0.2]), one, one)  # a rod wider than the bore
