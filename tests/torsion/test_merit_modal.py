"""mc.torsional_merit's modal excitation, its invariances and its flags, against oracles written
here: the mass-normalised mode shapes from numpy's general eigen solver on J⁻¹K (not the
library's SciPy route), each cylinder's own torque sampled over the cycle and transformed by
numpy's FFT; the same shaft numbered from the other end; a cylinder on a node of a mode; the
two-disc closed form ω² = k (J₁ + J₂)/(J₁ J₂) for a resonance at the running speed."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc

from .test_merit import INLINE_4, chain, cylinder_torque


def normalised_shapes(shaft: mc.Shaft) -> tuple[np.ndarray, np.ndarray]:
    """The elastic modes' frequencies [Hz] and shapes with φᵀJφ = 1 (nodes × modes), by
    numpy.linalg.eig of J⁻¹K, the chain's matrices written here."""
    inertia = np.asarray(shaft.inertia, dtype=float)
    nodes = len(inertia)
    stiffness = np.zeros((nodes, nodes))
    for i, k in enumerate(shaft.stiffness):
        stiffness[i : i + 2, i : i + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    values, vectors = np.linalg.eig(stiffness / inertia[:, None])
    order = np.argsort(values.real)[1:]  # the rigid mode (0) left out
    shapes = vectors[:, order].real
    shapes /= np.sqrt(np.einsum("n,nm,nm->m", inertia, shapes, shapes))
    return np.sqrt(np.abs(values[order].real)) / (2 * math.pi), shapes


@pytest.mark.parametrize("name", ["inline-4", "boxer-compressor"])
def test_modal_excitation_is_the_order_of_the_mass_normalised_weighted_torques(name):
    machine = mc.presets.MACHINES[name]
    shaft = chain(machine, throw=0.05 * machine.shaft_inertia, flywheel=machine.shaft_inertia)
    modes = min(2, len(shaft.inertia) - 1)
    merit = mc.torsional_merit(machine, shaft, modes=modes, max_order=4)
    frequency, shapes = normalised_shapes(shaft)
    np.testing.assert_allclose(merit.groupby("mode")["natural_frequency"].first(), frequency[:modes], rtol=1e-9)
    points = 2**14
    phi = machine.cycle * np.arange(points) / points
    largest = 0.0
    for row in merit.itertuples():
        weights = shapes[list(shaft.cylinder_nodes), row.mode - 1]
        total = sum(w * cylinder_torque(machine, j, phi, row.resonance_rpm) for j, w in enumerate(weights))
        spectrum = np.fft.rfft(total) / points * 2
        found = abs(spectrum[round(row.order * machine.cycle / (2 * math.pi))])
        largest = max(largest, found)
        assert row.modal_excitation == pytest.approx(found, rel=2e-3, abs=1e-6 * largest + 1e-12), row
    assert merit.attrs["units"]["modal_excitation"] == "N·m/√(kg·m²)"


@settings(max_examples=20)
@given(inertia=st.lists(st.floats(0.005, 0.5), min_size=5, max_size=5), scale=st.floats(0.1, 10.0))
def test_no_number_depends_on_which_end_the_nodes_are_counted_from(inertia, scale):
    """The same shaft numbered from the flywheel end (its nodes, sections and each cylinder's
    node reversed) gives the same frequencies, vector sums and excitations; and the modal
    excitation of each mode compares modes: scaling every inertia and stiffness by one factor
    keeps the frequencies and scales it by 1/√factor, the relative vector sums not at all."""
    stiffness = [2e5, 3e5, 2.5e5, 4e5]
    forward = mc.Shaft(inertia, stiffness, cylinder_nodes=[0, 1, 2, 3])
    backward = mc.Shaft(inertia[::-1], stiffness[::-1], cylinder_nodes=[4, 3, 2, 1])
    scaled = mc.Shaft([scale * j for j in inertia], [scale * k for k in stiffness], cylinder_nodes=[0, 1, 2, 3])
    tables = [mc.torsional_merit(INLINE_4, shaft, modes=3, max_order=4) for shaft in (forward, backward, scaled)]
    for column in ("natural_frequency", "vector_sum", "excitation", "modal_excitation"):
        largest = float(tables[0][column].abs().max())
        np.testing.assert_allclose(tables[1][column], tables[0][column], rtol=1e-7, atol=1e-9 * largest, err_msg=column)
    for column in ("natural_frequency", "vector_sum", "excitation"):
        largest = float(tables[0][column].abs().max())
        np.testing.assert_allclose(tables[2][column], tables[0][column], rtol=1e-7, atol=1e-9 * largest, err_msg=column)
    largest = float(tables[0]["modal_excitation"].max())
    np.testing.assert_allclose(
        tables[2]["modal_excitation"] * math.sqrt(scale), tables[0]["modal_excitation"], rtol=1e-7, atol=1e-9 * largest
    )


def test_a_cylinder_on_a_node_of_a_mode_counts_exactly_nothing():
    """A symmetric chain of three equal discs, a cylinder at the middle one: the first elastic
    mode swings the ends against each other and leaves the middle still. The cylinder drives
    that mode not at all — exactly 0, not rounding divided by rounding — and a change of an
    end's inertia by 1e-12 of it changes nothing that is not rounding."""
    one = mc.presets.MACHINES["slow-compressor"]
    shaft = mc.Shaft([10.0, 10.0, 10.0], [1e6, 1e6], cylinder_nodes=[1])
    nudged = mc.Shaft([10.0, 10.0, 10.0 * (1 + 1e-12)], [1e6, 1e6], cylinder_nodes=[1])
    merit = mc.torsional_merit(one, shaft, modes=2, max_order=4)
    first = merit[merit["mode"] == 1]
    for column in ("vector_sum", "excitation", "modal_excitation"):
        assert (first[column] == 0).all(), column
    again = mc.torsional_merit(one, nudged, modes=2, max_order=4)
    second = merit[merit["mode"] == 2]
    assert (second["vector_sum"] == 1).all()  # a lone cylinder off a node: 1
    for column in ("vector_sum", "excitation", "modal_excitation"):
        np.testing.assert_allclose(again[column], merit[column], rtol=1e-9, atol=0, err_msg=column)


@pytest.mark.parametrize(("offset", "flagged"), [(0.96, True), (1.04, True), (0.94, False), (1.06, False)])
def test_a_resonance_within_five_percent_of_the_running_speed_is_flagged(offset, flagged):
    """Two discs J₁, J₂ on a stiffness k: ω² = k (J₁ + J₂)/(J₁ J₂). With k chosen so that the
    order 3 meets the mode at ``offset`` times the machine's speed, only that row is flagged
    where the offset is within ±5 %."""
    machine = mc.presets.MACHINES["slow-compressor"]
    j1, j2 = 20.0, machine.shaft_inertia
    frequency = 3 * offset * machine.rpm / 60  # Hz
    k = (2 * math.pi * frequency) ** 2 * j1 * j2 / (j1 + j2)
    merit = mc.torsional_merit(machine, mc.Shaft([j1, j2], [k], cylinder_nodes=[0]), modes=1, max_order=6)
    order_3 = merit.loc[merit["order"] == 3.0].iloc[0]
    assert order_3["resonance_rpm"] == pytest.approx(offset * machine.rpm, rel=1e-9)
    assert bool(order_3["at_running_speed"]) is flagged
    assert merit.loc[merit["order"] != 3.0, "at_running_speed"].sum() == 0
    without = mc.torsional_merit(
        machine.replace(rpm=None, rpm_range=None), mc.Shaft([j1, j2], [k], cylinder_nodes=[0]), modes=1
    )
    assert not without["at_running_speed"].any()
