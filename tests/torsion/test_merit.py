"""mc.torsional_merit against brute force: the phase-vector sums summed cylinder by cylinder from
the phases with Python's complex numbers; the excitation as an FFT of the mode-weighted sum of
each cylinder's own torque sampled over the cycle (its gas, inertia and gravity torques evaluated
cylinder by cylinder at its real phase, no shift theorem); the V-bank factor |2 cos(νΘ/2)| of two
cylinders on one pin; the textbook major orders of in-line engines."""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc

INLINE_4 = mc.presets.MACHINES["inline-4"]


def chain(machine: mc.Machine, throw: float = 0.02, flywheel: float = 0.3, stiffness: float = 3e5) -> mc.Shaft:
    """A shaft with a node per throw (the machine's throws along the shaft) and a flywheel."""
    count = len(machine.throws)
    return mc.Shaft(
        [throw] * count + [flywheel],
        [stiffness] * count,
        cylinder_nodes=list(machine.throw_index),
    )


def brute_vector_sum(machine: mc.Machine, shaft: mc.Shaft, mode: int, order: float) -> float:
    """|Σ_j a_j e^{iνθ_j}| cylinder by cylinder, θ_j = (−α_j) mod Φ, a_j scaled to max 1."""
    shape = shaft.modes().shapes[:, mode - 1]
    at = [shape[node] for node in shaft.cylinder_nodes]
    largest = max(abs(a) for a in at)
    total = 0j
    for a, cylinder in zip(at, machine.cylinders, strict=True):
        firing = math.fmod(-cylinder.phase, machine.cycle)
        if firing < 0:
            firing += machine.cycle
        total += a / largest * cmath.exp(1j * order * firing)
    return abs(total)


@pytest.mark.parametrize("name", ["inline-4", "inline-6", "genset-v12", "boxer-compressor", "marine-2t-twin"])
def test_vector_sums_match_brute_force_for_in_line_v_and_boxer_machines(name):
    machine = mc.presets.MACHINES[name]
    shaft = chain(machine)
    merit = mc.torsional_merit(machine, shaft, modes=min(2, len(shaft.inertia) - 1), max_order=12)
    step = 0.5 if machine.strokes == 4 else 1.0
    assert merit["order"].tolist() == list(np.tile(np.arange(step, 12 + step / 2, step), merit["mode"].max()))
    for row in merit.itertuples():
        assert row.vector_sum == pytest.approx(brute_vector_sum(machine, shaft, row.mode, row.order), abs=1e-9)
        assert row.resonance_rpm == pytest.approx(60 * row.natural_frequency / row.order, rel=1e-12)


@settings(max_examples=25, deadline=None)
@given(
    phases=st.lists(st.floats(0.0, 4 * math.pi, allow_nan=False), min_size=4, max_size=4),
    inertia=st.lists(st.floats(0.005, 0.5), min_size=5, max_size=5),
)
def test_vector_sums_of_any_phases_and_chain_match_brute_force(phases, inertia):
    machine = INLINE_4.replace(cylinders=[c.replace(phase=p) for c, p in zip(INLINE_4.cylinders, phases, strict=True)])
    shaft = mc.Shaft(inertia, [2e5, 3e5, 2.5e5, 4e5], cylinder_nodes=[0, 1, 2, 3])
    merit = mc.torsional_merit(machine, shaft, modes=2, max_order=6)
    for row in merit.itertuples():
        assert row.vector_sum == pytest.approx(brute_vector_sum(machine, shaft, row.mode, row.order), abs=1e-9)


def cylinder_torque(machine: mc.Machine, j: int, phi: np.ndarray, rpm: float) -> np.ndarray:
    """Cylinder j's own tangential torque [N·m] at its own phase: gas + inertia at ``rpm`` + gravity."""
    alone = machine.replace(cylinders=[machine.cylinders[j]], main_bearings=None, shaft=None)
    omega = rpm * math.pi / 30
    return alone.gas_torque(phi) + alone.inertia_torque(phi, omega) + alone.gravity_torque(phi)


@pytest.mark.parametrize("name", ["inline-4", "slow-compressor", "boxer-compressor"])
def test_excitation_is_the_order_of_the_mode_weighted_sum_of_the_cylinders_torques(name):
    machine = mc.presets.MACHINES[name]
    shaft = chain(machine, throw=0.05 * machine.shaft_inertia, flywheel=machine.shaft_inertia)
    merit = mc.torsional_merit(machine, shaft, modes=1, max_order=6)
    points = 2**14
    phi = machine.cycle * np.arange(points) / points
    shape = shaft.modes().shapes[:, 0]
    weights = np.array([shape[node] for node in shaft.cylinder_nodes])
    weights /= np.abs(weights).max()
    largest = 0.0
    for row in merit.itertuples():
        total = sum(w * cylinder_torque(machine, j, phi, row.resonance_rpm) for j, w in enumerate(weights))
        spectrum = np.fft.rfft(total) / points * 2  # per cycle: order ν is bin ν·Φ/2π
        found = abs(spectrum[round(row.order * machine.cycle / (2 * math.pi))])
        largest = max(largest, found)
        # the sampled gas torque has kinks at the tables' breakpoints: its FFT converges algebraically
        assert row.excitation == pytest.approx(found, rel=2e-3, abs=1e-6 * largest + 1e-9)


@pytest.mark.parametrize("strokes", [2, 4])
@pytest.mark.parametrize("bank_deg", [45.0, 60.0, 90.0, 120.0])
def test_a_two_cylinder_v_on_one_pin_sums_to_the_bank_factor(strokes, bank_deg):
    template = INLINE_4.cylinders[0].replace(pressure=None)  # the sums depend on the phases alone
    bank = math.radians(bank_deg)
    pin = 0.3  # any absolute pin angle
    gammas = [math.pi / 2 + bank / 2, math.pi / 2 - bank / 2]
    cylinders = [template.replace(inclination=g, phase=(pin - g) % (2 * math.pi), axial_position=0.0) for g in gammas]
    machine = mc.Machine(cylinders, shaft_inertia=0.2, strokes=strokes, rpm=3000)
    shaft = mc.Shaft([0.02, 0.3], [3e5], cylinder_nodes=[0, 0])
    merit = mc.torsional_merit(machine, shaft, modes=1, max_order=8)
    # the banks fire Θ apart in crank angle (two-stroke; a four-stroke V on one pin as well,
    # its phases taken as given)
    expected = np.abs(2 * np.cos(merit["order"] * bank / 2))
    np.testing.assert_allclose(merit["vector_sum"], expected, atol=1e-12)


@pytest.mark.parametrize(
    ("name", "majors"),
    [("inline-4", [2.0, 4.0, 6.0, 8.0]), ("inline-6", [3.0, 6.0, 9.0]), ("genset-v12", [6.0])],
)
def test_major_orders_are_the_textbook_multiples_of_the_firings_per_revolution(name, majors):
    # k evenly spaced firings over the cycle: the multiples of k/2 (four-stroke) are major. A
    # 60° V12 fires every 60°: each bank's third order meets the other's at 3·60° = 180°.
    machine = mc.presets.MACHINES[name]
    merit = mc.torsional_merit(machine, chain(machine), modes=1, max_order=9)
    assert merit.loc[merit["major"], "order"].tolist() == majors
    # a major order's vectors all point one way: its sum is the sum of the amplitudes
    shape = chain(machine).modes().shapes[:, 0]
    at = np.array([shape[node] for node in machine.throw_index])
    at /= np.abs(at).max()
    np.testing.assert_allclose(merit.loc[merit["major"], "vector_sum"], abs(at.sum()), rtol=1e-12)


def test_rpm_range_keeps_the_resonances_inside_it_ends_included():
    shaft = chain(INLINE_4)
    every = mc.torsional_merit(INLINE_4, shaft, modes=2)
    low, high = sorted(every["resonance_rpm"])[3], sorted(every["resonance_rpm"])[10]
    inside = mc.torsional_merit(INLINE_4, shaft, modes=2, rpm_range=(low, high))
    assert len(inside) == 8
    assert inside["resonance_rpm"].between(low, high).all()


def test_the_machine_s_own_shaft_is_the_default_and_the_cache_leaves_equality_and_pickles_alone():
    import pickle

    shaft = chain(INLINE_4)
    machine = INLINE_4.replace(shaft=shaft)
    a = mc.torsional_merit(machine)
    b = mc.torsional_merit(INLINE_4, shaft)
    assert a.equals(b)
    assert machine == pickle.loads(pickle.dumps(machine))
    assert "_torsion_orders" not in pickle.loads(pickle.dumps(machine)).__dict__


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({}, "shaft"),
        ({"shaft": "no"}, "shaft"),
        ({"shaft": mc.Shaft([1.0, 1.0], [1e5], cylinder_nodes=[0])}, "cylinder_nodes"),
        ({"shaft": chain(INLINE_4), "modes": 0}, "modes"),
        ({"shaft": chain(INLINE_4), "modes": 5}, "modes"),
        ({"shaft": chain(INLINE_4), "max_order": 0}, "max_order"),
        ({"shaft": chain(INLINE_4), "rpm_range": (3000, 1000)}, "rpm_range"),
    ],
)
def test_bad_input_is_refused_by_name(kwargs, named):
    with pytest.raises(mc.MechanismError, match=named):
        mc.torsional_merit(INLINE_4, **kwargs)
