"""The propeller law in the answers of the orders (Machine.load_law): mc.torque_orders,
mc.to_opentorsion and mc.torsional_merit at a speed n below the rated n_r, against the oracle of
the same machine without a law whose diagrams were scaled by hand — each absolute pressure
p_amb + (p − p_amb)·(n/n_r)², made from the raw pressure table, no code of the law's."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc
from multicrank.torsion.excitation import cylinder_orders

SHIP = mc.presets.MACHINES["slow-diesel-12"]  # a propeller's law, rated at 90 rpm
TWIN = mc.presets.MACHINES["marine-2t-twin"].replace(load_law="propeller")  # rated at 300 rpm
#: The ambient (crankcase) pressure the presets' diagrams are gauge to [Pa].
AMBIENT = 101325.0
#: A ship's shaft: twelve throws, a flywheel and a propeller with its entrained water behind a
#: soft intermediate shaft, so that many orders of two modes resonate below the rated speed.
SHAFT = mc.Shaft(
    [4.0e4] * 12 + [1.0e5, 1.5e6], [1.0e10] * 11 + [5.0e9, 1.0e8], cylinder_nodes=list(range(12)), damping=[1e5] * 13
)


def by_hand(machine: mc.Machine, rpm: float) -> mc.Machine:
    """``machine`` without a load law, every diagram the load of ``rpm``: its table's gauge
    pressures made absolute, p_amb + (p − p_amb)(n/n_r)², and gauge again."""
    ratio = (rpm / machine.rpm) ** 2

    def scaled(diagram):
        if diagram is None:
            return None
        absolute = np.asarray(diagram.pressure) + AMBIENT
        gauge = AMBIENT + (absolute - AMBIENT) * ratio - AMBIENT
        return mc.IndicatorDiagram(diagram.angle, gauge, cycle=diagram.cycle, kind=diagram.kind)

    cylinders = [
        c.replace(pressure=scaled(c.pressure), pressure_crank_end=scaled(c.pressure_crank_end))
        for c in machine.cylinders
    ]
    return machine.replace(cylinders=cylinders, load_law=None)


def assert_same_orders(got, expected, parts):
    for part in parts:
        for side in ("cos", "sin"):
            column = f"{part}_{side}"
            scale = np.abs(expected[column]).max()
            np.testing.assert_allclose(got[column], expected[column], rtol=0, atol=1e-11 * scale, err_msg=column)


@pytest.mark.parametrize("fraction", [0.3, 2 / 3])
def test_the_gas_orders_are_those_of_the_diagram_scaled_by_hand(fraction):
    rpm = fraction * SHIP.rpm
    got = mc.torque_orders(SHIP, rpm, max_order=12)
    expected = mc.torque_orders(by_hand(SHIP, rpm), rpm, max_order=12)
    assert_same_orders(got, expected, ("gas", "inertia", "gravity", "total"))
    # At 30 % speed the mean gas torque is 9 % of the rated one, not all of it.
    rated = mc.torque_orders(SHIP, SHIP.rpm, max_order=1)
    assert got.loc[0.0, "gas_cos"] == pytest.approx(fraction**2 * rated.loc[0.0, "gas_cos"], rel=1e-9)


@settings(max_examples=15, deadline=None)
@given(rpm=st.floats(60.0, 450.0))
def test_at_any_speed_the_gas_orders_are_those_of_that_load(rpm):
    got = mc.torque_orders(TWIN, rpm, max_order=8)
    assert_same_orders(got, mc.torque_orders(by_hand(TWIN, rpm), rpm, max_order=8), ("gas", "total"))


def test_without_a_law_the_diagram_is_the_same_at_every_speed():
    plain = SHIP.replace(load_law=None)
    at_rated = mc.torque_orders(SHIP, SHIP.rpm, max_order=6)
    for rpm in (27.0, 90.0):
        slow = mc.torque_orders(plain, rpm, max_order=6)
        np.testing.assert_array_equal(slow["gas_cos"], at_rated["gas_cos"])
        np.testing.assert_array_equal(slow["gas_sin"], at_rated["gas_sin"])


def test_to_opentorsion_drives_the_shaft_with_the_load_of_its_speed():
    pytest.importorskip("opentorsion")
    rpm = 0.3 * SHIP.rpm
    got = mc.to_opentorsion(SHIP, shaft=SHAFT, rpm=rpm)
    expected = mc.to_opentorsion(by_hand(SHIP, rpm), shaft=SHAFT, rpm=rpm)
    np.testing.assert_allclose(got.excitation.omegas, expected.excitation.omegas, rtol=1e-15)
    U, V = got.excitation.U, expected.excitation.U
    np.testing.assert_allclose(U, V, rtol=0, atol=1e-11 * np.abs(V).max())
    # The gas alone: 0.3² = 9 % of the rated load's.
    gas = mc.to_opentorsion(SHIP, shaft=SHAFT, rpm=rpm, part="gas").excitation.U
    full = mc.to_opentorsion(SHIP.replace(load_law=None), shaft=SHAFT, rpm=rpm, part="gas").excitation.U
    np.testing.assert_allclose(gas, 0.09 * full, rtol=0, atol=1e-11 * np.abs(full).max())
    # The table form of the same speed is the law's too: summed over the nodes, the machine's.
    table = mc.to_opentorsion(mc.torque_orders(SHIP, rpm, max_order=12), dofs=14, node=0)
    np.testing.assert_allclose(table.U[0], U.sum(axis=0), rtol=0, atol=1e-9 * np.abs(U.sum(axis=0)).max())


def test_each_resonance_below_the_rated_speed_is_driven_by_the_load_of_its_own_speed():
    merit = mc.torsional_merit(SHIP, SHAFT, modes=2)
    below = merit[merit["resonance_rpm"] < SHIP.rpm]
    assert len(below) >= 10  # the first mode's orders from 2 up, the second's 12th
    for row in below.itertuples():
        oracle = mc.torsional_merit(by_hand(SHIP, row.resonance_rpm), SHAFT, modes=2)
        expected = oracle[(oracle["mode"] == row.mode) & (oracle["order"] == row.order)]["excitation"].item()
        assert row.excitation == pytest.approx(expected, rel=1e-9, abs=1e-12 * merit["excitation"].max())
    # Above it (the law extrapolates), the same rule.
    above = merit[merit["resonance_rpm"] > SHIP.rpm].iloc[0]
    oracle = mc.torsional_merit(by_hand(SHIP, above["resonance_rpm"]), SHAFT, modes=2)
    expected = oracle[(oracle["mode"] == above["mode"]) & (oracle["order"] == above["order"])]["excitation"].item()
    assert above["excitation"] == pytest.approx(expected, rel=1e-9)


def test_the_cylinders_orders_keep_the_law_in_a_selection():
    harmonics = cylinder_orders(SHIP, 12)
    assert harmonics.rated_omega == pytest.approx(SHIP.rpm * np.pi / 30, rel=1e-15)
    phases = np.array([c.phase for c in SHIP.cylinders])
    omega = np.linspace(2.0, 9.0, harmonics.orders.size)  # a speed per order [rad/s]
    keep = harmonics.orders % 3 == 0
    chosen = harmonics.only(keep)
    np.testing.assert_array_equal(chosen.orders, harmonics.orders[keep])
    np.testing.assert_array_equal(chosen.at(phases, omega[keep]), harmonics.at(phases, omega)[:, keep])
    assert cylinder_orders(SHIP.replace(load_law=None), 12).rated_omega is None
