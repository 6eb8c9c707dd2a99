"""mc.to_opentorsion(machine): a machine and its shaft handed to openTorsion in one call.

Oracles: the table form of the whole machine's torque_orders (the core's quadrature of the
machine's torque) for the sum over the nodes; each cylinder's own torque in the time domain
for each node; the model's matrices written out; and openTorsion's steady-state response
(its own solver) for where the resonances lie and how strongly the orders drive them, against
what mc.torsional_merit says of them."""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

import multicrank as mc
from multicrank._optional import OptionalDependencyError

ot = pytest.importorskip("opentorsion")

ENGINE = mc.presets.MACHINES["inline-4"]  # four-stroke, its cylinders placed along the shaft
#: Four throws and a flywheel, lightly damped: the first mode at 187 Hz.
SHAFT = mc.Shaft([0.02, 0.02, 0.02, 0.02, 0.5], [2e5] * 4, cylinder_nodes=[0, 1, 2, 3], damping=[2.0] * 4)


def smooth_machine() -> mc.Machine:
    # A four-stroke twin whose pressure is smooth over the cycle, so that every torque is
    # analytic and its orders converge geometrically: a truncated sum is the torque.
    def pressure(theta):
        return 8e5 * (1 + np.cos(theta / 2)) ** 2 + 3e5 * np.sin(theta)

    cylinder = mc.Cylinder(
        crank_radius=0.05, rod_length=0.17, piston_mass=0.9, rod_mass=0.7, rod_cg=0.11, bore=0.09,
        crank_mass=1.0, crank_cg_radius=0.02, pressure=pressure, inclination=1.2,
    )  # fmt: skip
    return mc.Machine([cylinder, cylinder.replace(phase=2.5, inclination=1.9)], shaft_inertia=0.3, strokes=4)


# -- the excitation ---------------------------------------------------------------------------------


@pytest.mark.parametrize("part", ["total", "gas", "inertia", "gravity"])
@pytest.mark.parametrize("mean", [False, True])
def test_summed_over_the_nodes_it_is_the_table_of_the_whole_machine(part, mean):
    for machine, shaft, rpm in [
        (ENGINE, SHAFT, 3100.0),
        (
            mc.Machine.from_toml(mc.presets.MACHINE_FILES["boxer-compressor"]),
            mc.Shaft([0.5, 0.4, 3.0], [1e6, 2e6], cylinder_nodes=[0, 1]),
            None,  # the machine's own
        ),
    ]:
        model = mc.to_opentorsion(machine, shaft=shaft, rpm=rpm, max_order=9, part=part, mean=mean)
        table = mc.torque_orders(machine, rpm or machine.rpm, max_order=9)
        whole = mc.to_opentorsion(table, dofs=1, node=0, part=part, mean=mean)
        np.testing.assert_allclose(model.excitation.omegas, whole.omegas, rtol=1e-14)
        summed = model.excitation.U.sum(axis=0)
        scale = table.filter(like="_amplitude").to_numpy().max()  # (a boxer's gravity cancels: all 0)
        np.testing.assert_allclose(summed, whole.U[0], rtol=0, atol=1e-11 * scale)
        assert model.excitation.U.shape == (len(shaft.inertia), len(whole.omegas))


def test_each_node_carries_its_own_cylinders_torque():
    """openTorsion's convention, node by node: Re(U_i e^{iωt}) summed over the components is
    the torque of the cylinders at node i, each computed alone in the time domain."""
    machine = smooth_machine()
    shaft = mc.Shaft([0.1, 0.1, 0.4], [1e5, 2e5], cylinder_nodes=[2, 0])
    rpm = 2400.0
    omega = rpm * math.pi / 30
    model = mc.to_opentorsion(machine, shaft=shaft, rpm=rpm, max_order=40, mean=True)
    phi = np.linspace(0.0, 4 * math.pi, 181)
    U = model.excitation.excitation_matrix()
    synthesis = np.real(U @ np.exp(1j * np.outer(model.excitation.omegas, phi / omega)))  # (nodes, φ)
    for node, cylinder in zip(shaft.cylinder_nodes, machine.cylinders, strict=True):
        alone = machine.replace(cylinders=[cylinder])  # at its phase: its torque in the machine's φ
        torque = alone.gas_torque(phi) + alone.inertia_torque(phi, omega) + alone.gravity_torque(phi)
        np.testing.assert_allclose(synthesis[node], torque, rtol=0, atol=1e-9 * np.abs(torque).max())
    np.testing.assert_array_equal(U[1], 0.0)  # no cylinder there


def test_the_model_is_the_chain_written_out():
    shaft = mc.Shaft(
        [0.03, 0.02, 0.05, 0.8], [3e5, 2e5, 6e5], cylinder_nodes=[0, 0, 1, 2], damping=[1.0, 4.0, 0.5],
        node_damping=[2.0, 0.0, 0.0, 7.0],
    )  # fmt: skip
    model = mc.to_opentorsion(ENGINE, shaft=shaft, max_order=2)
    assert isinstance(model, tuple) and model._fields == ("assembly", "excitation")
    assembly, excitation = model
    assert isinstance(assembly, ot.Assembly) and isinstance(excitation, ot.PeriodicExcitation)
    k, c = np.array([3e5, 2e5, 6e5]), np.array([1.0, 4.0, 0.5])
    K = np.diag(np.r_[k, 0.0] + np.r_[0.0, k]) - np.diag(k, 1) - np.diag(k, -1)
    # The sections' damping between their nodes, the nodes' to ground on the diagonal.
    C = np.diag(np.r_[c, 0.0] + np.r_[0.0, c] + [2.0, 0.0, 0.0, 7.0]) - np.diag(c, 1) - np.diag(c, -1)
    np.testing.assert_array_equal(assembly.M, np.diag([0.03, 0.02, 0.05, 0.8]))
    np.testing.assert_array_equal(assembly.K, K)
    np.testing.assert_array_equal(assembly.C, C)
    assert [disk.c for disk in assembly.disk_elements] == [2.0, 0.0, 0.0, 7.0]
    # The machine's own speed (6000 1/min), orders ½ … 2 of a four-stroke engine.
    np.testing.assert_allclose(excitation.omegas, np.arange(1, 5) / 2 * 6000 * math.pi / 30, rtol=1e-15)
    np.testing.assert_array_equal(excitation.U[3], 0.0)
    # No damping given: elements with c = 0; every cylinder at node 0: nothing elsewhere.
    bare = mc.Shaft(shaft.inertia, shaft.stiffness, cylinder_nodes=[0] * 4)
    plain = mc.to_opentorsion(ENGINE.replace(shaft=bare), max_order=2)
    assert not plain.assembly.C.any() and not plain.excitation.U[1:].any()


# -- openTorsion's forced response against torsional_merit ------------------------------------------


def response(machine, shaft, rpm, order, section):
    """|vibratory torque| [N·m] of the component of ``order`` in ``section`` at ``rpm``, by
    openTorsion's steady-state solver."""
    model = mc.to_opentorsion(machine, shaft=shaft, rpm=rpm, max_order=6)
    index = int(np.argmin(np.abs(model.excitation.omegas / (rpm * math.pi / 30) - order)))
    torque, _ = model.assembly.vibratory_torque(model.excitation)
    return abs(torque[section, index])


def peak(machine, shaft, order, around, section=-1):
    """(speed [1/min], |torque| [N·m]) of the response's peak within ±8 % of ``around``: a
    sweep in steps of 0.25 %, then refined between the neighbours of its largest point."""
    speeds = around * np.linspace(0.92, 1.08, 65)
    sizes = [response(machine, shaft, rpm, order, section) for rpm in speeds]
    top = int(np.argmax(sizes))
    found = minimize_scalar(
        lambda rpm: -response(machine, shaft, rpm, order, section),
        bounds=(speeds[max(top - 1, 0)], speeds[min(top + 1, len(speeds) - 1)]),
        method="bounded",
        options={"xatol": 1e-4 * around},
    )
    return found.x, -found.fun


def merit_row(machine, shaft, order):
    table = mc.torsional_merit(machine, shaft, modes=1, max_order=6)
    return table[table["order"] == order].iloc[0]


#: The in-line four firing 1-2-3-4 every 180° (θ_j = 0, 180°, 360°, 540°): the same engine, other
#: phase vectors for the integer and half orders but the same for the even ones.
RESHUFFLED = ENGINE.replace(
    cylinders=[c.replace(phase=-j * math.pi) for j, c in enumerate(ENGINE.cylinders)], shaft=SHAFT
)


@pytest.mark.parametrize("order", [1.0, 1.5, 2.0, 3.0, 4.0])
def test_the_first_mode_resonates_where_torsional_merit_says(order):
    row = merit_row(ENGINE, SHAFT, order)
    speed, _ = peak(ENGINE, SHAFT, order, row["resonance_rpm"])
    assert speed == pytest.approx(row["resonance_rpm"], rel=0.01)


@pytest.mark.parametrize("order", [1.0, 1.5, 3.0])
def test_resonant_peaks_scale_as_the_excitation_of_the_firing(order):
    """Two firings of one engine on one shaft: the ratio of openTorsion's resonant peaks of an
    order is the ratio of torsional_merit's excitations (the mode, its damping and its
    speed are the same)."""
    mine, other = merit_row(ENGINE, SHAFT, order), merit_row(RESHUFFLED, SHAFT, order)
    assert mine["resonance_rpm"] == other["resonance_rpm"]
    ratio = mine["excitation"] / other["excitation"]
    assert abs(ratio - 1) > 0.05  # the firings differ in this order
    _, first = peak(ENGINE, SHAFT, order, mine["resonance_rpm"])
    _, second = peak(RESHUFFLED, SHAFT, order, other["resonance_rpm"])
    assert first / second == pytest.approx(ratio, rel=0.02)


def test_a_damped_node_takes_what_the_forced_response_says():
    """A propeller at the end of a two-disc shaft: openTorsion's steady response of the model
    is the 2 × 2 complex solve (K − ω²M + iωC) θ = T written out here, C the propeller's c on
    the diagonal; at the resonance the section's twist is the smaller the larger c, inversely
    as the elastic mode's damping φᵀCφ (φ = (1, −J_0/J_1): no net momentum)."""
    J, k, T = (0.4, 2.0), 1e5, 50.0
    omega = math.sqrt(k * (J[0] + J[1]) / (J[0] * J[1]))  # the elastic mode's natural frequency
    M = np.diag(J)
    K = k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    section = 0.05 * np.array([[1.0, -1.0], [-1.0, 1.0]])
    swings = []
    for c in (0.0, 20.0, 40.0):
        shaft = mc.Shaft(list(J), [k], cylinder_nodes=[0, 0], damping=[0.05], node_damping=[0.0, c])
        assembly = mc.to_opentorsion(mc.presets.MACHINES["marine-2t-twin"], shaft=shaft, max_order=1).assembly
        theta, _ = assembly.ss_response(np.array([[T], [0.0]], dtype=complex), np.array([omega]))
        C = section + np.diag([0.0, c])
        expected = np.linalg.solve(K - omega**2 * M + 1j * omega * C, np.array([T, 0.0]))
        np.testing.assert_allclose(theta[:, 0], expected, rtol=1e-10)
        swings.append(abs(theta[0, 0] - theta[1, 0]))  # the section's twist
    shape = np.array([1.0, -J[0] / J[1]])
    modal = [shape @ (section + np.diag([0.0, c])) @ shape for c in (0.0, 20.0, 40.0)]
    assert swings[0] > 10 * swings[1] > 10 * swings[2]  # the section's own damping alone lets it ring
    np.testing.assert_allclose(np.array(swings[1:]) / swings[0], modal[0] / np.array(modal[1:]), rtol=0.02)


def test_a_damper_at_the_front_lowers_the_first_modes_resonant_peak():
    """The in-line four's 2nd order at the first mode: a damper at the free end (node 0, where
    the mode swings most) lowers openTorsion's resonant peak of the section torque as the
    mode's damping grows, φᵀCφ with φ its shape (numpy's eigen solution of the model's M, K)."""
    damper = mc.Shaft(SHAFT.inertia, SHAFT.stiffness, cylinder_nodes=[0, 1, 2, 3], damping=SHAFT.damping,
                      node_damping=[1.0, 0.0, 0.0, 0.0, 0.0])  # fmt: skip
    row = merit_row(ENGINE, SHAFT, 2.0)
    bare_speed, bare = peak(ENGINE, SHAFT, 2.0, row["resonance_rpm"])
    damped_speed, damped = peak(ENGINE, damper, 2.0, row["resonance_rpm"])
    assembly = mc.to_opentorsion(ENGINE, shaft=damper, max_order=2).assembly
    values, vectors = np.linalg.eig(np.linalg.solve(assembly.M, assembly.K))
    shape = vectors[:, np.argsort(values.real)[1]].real
    plain = mc.to_opentorsion(ENGINE, shaft=SHAFT, max_order=2).assembly.C
    assert damped < bare
    assert damped / bare == pytest.approx((shape @ plain @ shape) / (shape @ assembly.C @ shape), rel=0.03)
    assert damped_speed == pytest.approx(bare_speed, rel=0.01)


def test_an_order_whose_vector_sum_vanishes_drives_nothing():
    """Every cylinder on one node of a two-disc shaft: the mode weighs them alike, so the
    in-line four's 3rd order (firing every 180°: its vectors at 0°, 540°, 1080°, 1620°, two
    each way) sums to 0, its 4th (major) to 4."""
    shaft = mc.Shaft([0.08, 0.5], [2e5], cylinder_nodes=[0, 0, 0, 0], damping=[2.0])
    minor, major = merit_row(ENGINE, shaft, 3.0), merit_row(ENGINE, shaft, 4.0)
    assert minor["vector_sum"] < 1e-12 and major["vector_sum"] == pytest.approx(4.0, rel=1e-12) and major["major"]
    _, driven = peak(ENGINE, shaft, 4.0, major["resonance_rpm"], section=0)
    speeds = minor["resonance_rpm"] * np.linspace(0.98, 1.02, 9)
    idle = max(response(ENGINE, shaft, rpm, 3.0, 0) for rpm in speeds)
    assert driven > 1.0 and idle < 1e-9 * driven


# -- defaults, mistakes, the extra ------------------------------------------------------------------


def test_the_machines_shaft_and_speed_are_the_defaults():
    machine = ENGINE.replace(shaft=SHAFT)
    default = mc.to_opentorsion(machine)
    given = mc.to_opentorsion(ENGINE, shaft=SHAFT, rpm=ENGINE.rpm, max_order=12)
    np.testing.assert_array_equal(default.excitation.U, given.excitation.U)
    np.testing.assert_array_equal(default.excitation.omegas, given.excitation.omegas)
    assert default.excitation.omegas[-1] == pytest.approx(12 * ENGINE.rpm * math.pi / 30)


@pytest.mark.parametrize(
    ("call", "named"),
    [
        (lambda: mc.to_opentorsion(ENGINE), r"^shaft is required: machine 'inline-4' has none"),
        (lambda: mc.to_opentorsion(ENGINE.replace(rpm=None, rpm_range=None), shaft=SHAFT), r"^rpm is required"),
        (lambda: mc.to_opentorsion(ENGINE, shaft=SHAFT, rpm=-5.0), r"^rpm = -5\.0 is out of range"),
        (lambda: mc.to_opentorsion(ENGINE, shaft=SHAFT, max_order=0), r"^max_order = 0 is out of range"),
        (lambda: mc.to_opentorsion(ENGINE, shaft=SHAFT, part="load"), r"^part = 'load' is not allowed"),
        (lambda: mc.to_opentorsion(ENGINE, shaft=SHAFT, mean=1), r"^mean must be True or False"),
        (lambda: mc.to_opentorsion(ENGINE, shaft="shaft"), r"^shaft must be a multicrank\.Shaft"),
        (
            lambda: mc.to_opentorsion(ENGINE, shaft=mc.Shaft([1.0, 1.0], [1e5], cylinder_nodes=[0])),
            r"^shaft\.cylinder_nodes holds 1 nodes; the machine has 4 cylinders",
        ),
        (lambda: mc.to_opentorsion(ENGINE, shaft=SHAFT, dofs=5), r"^dofs does not apply to a machine"),
        (lambda: mc.to_opentorsion(ENGINE, shaft=SHAFT, node=0), r"^node does not apply to a machine"),
        (lambda: mc.to_opentorsion(mc.torque_orders(ENGINE, 3000.0), dofs=2, node=0, shaft=SHAFT), r"^shaft applies"),
        (lambda: mc.to_opentorsion(mc.torque_orders(ENGINE, 3000.0), dofs=2, node=0, rpm=3000), r"^rpm applies"),
        (lambda: mc.to_opentorsion(mc.torque_orders(ENGINE, 3000.0), dofs=2, node=0, max_order=4), r"^max_order"),
        (lambda: mc.to_opentorsion(mc.torque_orders(ENGINE, 3000.0), node=0), r"^dofs must be an integer"),
        (lambda: mc.to_opentorsion("inline-4", shaft=SHAFT), r"^orders must be a table of mc\.torque_orders .* or a"),
    ],
)
def test_mistakes_are_named(call, named):
    with pytest.raises(mc.MechanismError, match=named):
        call()


def test_without_opentorsion_the_extra_is_named(monkeypatch):
    assembly = mc.to_opentorsion(ENGINE, shaft=SHAFT, max_order=1).assembly
    for name in [m for m in sys.modules if m.partition(".")[0] == "opentorsion"]:
        monkeypatch.setitem(sys.modules, name, None)  # an import of it fails, as if not installed
    expected = r'^to_opentorsion needs opentorsion: pip install "multicrank\[torsion\]"$'
    with pytest.raises(OptionalDependencyError, match=expected):
        mc.to_opentorsion(ENGINE, shaft=SHAFT)
    with pytest.raises(OptionalDependencyError, match=expected):
        mc.Shaft.from_opentorsion(assembly, cylinder_nodes=[0])
    # Bad input is still named first.
    with pytest.raises(mc.MechanismError, match="part"):
        mc.to_opentorsion(ENGINE, shaft=SHAFT, part="load")
