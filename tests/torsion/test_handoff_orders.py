"""mc.to_opentorsion: torque orders handed to openTorsion (the real package, the torsion extra)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import multicrank as mc

opentorsion = pytest.importorskip("opentorsion")


def smooth_machine() -> mc.Machine:
    # A four-stroke twin whose pressure is smooth over the cycle, so that every torque is
    # analytic and its orders converge geometrically: a truncated sum is the torque.
    def pressure(theta):
        return 8e5 * (1 + np.cos(theta / 2)) ** 2 + 3e5 * np.sin(theta)

    cylinder = mc.Cylinder(
        crank_radius=0.05, rod_length=0.17, piston_mass=0.9, rod_mass=0.7, rod_cg=0.11, bore=0.09,
        crank_mass=1.0, crank_cg_radius=0.02, pressure=pressure,
    )  # fmt: skip
    return mc.Machine([cylinder, cylinder.replace(phase=2 * math.pi)], shaft_inertia=0.3, strokes=4)


def test_the_excitation_synthesises_the_machines_torque():
    machine = smooth_machine()
    orders = mc.torque_orders(machine, 2400, max_order=40)
    excitation = mc.to_opentorsion(orders, dofs=3, node=1, mean=True)
    assert isinstance(excitation, opentorsion.PeriodicExcitation)
    U = excitation.excitation_matrix()
    assert U.shape == (3, orders.shape[0]) and not U[[0, 2]].any()
    omega = orders.attrs["omega"]
    phi = np.linspace(0.0, 4 * math.pi, 241)
    time = phi / omega
    # openTorsion's convention: a component U at ω is Re(U e^{iωt}).
    synthesis = np.real(U[1][None, :] * np.exp(1j * np.outer(time, excitation.omegas))).sum(axis=1)
    torque = machine.gas_torque(phi) + machine.inertia_torque(phi, omega) + machine.gravity_torque(phi)
    np.testing.assert_allclose(synthesis, torque, rtol=0, atol=1e-10 * np.abs(torque).max())
    # Each part on its own, and half orders for four strokes; no mean unless asked.
    gas = mc.to_opentorsion(orders, dofs=1, node=0, part="gas")
    assert gas.omegas[0] == pytest.approx(0.5 * omega) and len(gas.omegas) == orders.shape[0] - 1


def test_a_torsional_model_takes_it():
    # openTorsion's steady-state response of a two-inertia model to the engine's orders.
    machine = mc.presets.MACHINES["inline-4"]
    orders = mc.torque_orders(machine, 3000, max_order=8)
    excitation = mc.to_opentorsion(orders, dofs=2, node=0)
    shaft = opentorsion.Shaft(0, 1, k=2.0e4, I=0.0)
    disks = [opentorsion.Disk(0, I=machine.shaft_inertia), opentorsion.Disk(1, I=0.5)]
    assembly = opentorsion.Assembly([shaft], disk_elements=disks)
    M, K = assembly.M, assembly.K
    torque, total = assembly.vibratory_torque(excitation, C=np.zeros_like(M))
    assert torque.shape == (1, len(excitation.omegas)) and np.all(np.isfinite(total))
    assert K.shape == (2, 2)


def test_bad_input_is_named():
    orders = mc.torque_orders(mc.presets.MACHINES["inline-4"], 3000, max_order=2)
    with pytest.raises(mc.MechanismError, match="node = 3 is out of range"):
        mc.to_opentorsion(orders, dofs=3, node=3)
    with pytest.raises(mc.MechanismError, match=r"part = 'load' is not allowed"):
        mc.to_opentorsion(orders, dofs=3, node=0, part="load")
    with pytest.raises(mc.MechanismError, match=r"table of mc\.torque_orders"):
        mc.to_opentorsion(orders.reset_index(), dofs=3, node=0)
