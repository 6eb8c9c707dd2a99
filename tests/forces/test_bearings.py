"""mc.bearing_loads against an independent oracle: planar Newton–Euler of each rigid body —
the piston, the rod with its real mass, centre of gravity and moment of inertia, the crank web
and the counterweight — with positions from the exact geometry written here, accelerations as
spectral derivatives of those positions (numpy's FFT over a revolution), the five unknown pin
and wall forces of each unit solved by numpy.linalg.solve at every angle, and the lever rule
written here. Then statics: at rest the bearings carry every weight."""

from __future__ import annotations

import math
import time
import tracemalloc

import numpy as np
import pytest

import multicrank as mc
import multicrank._validation as validation
from multicrank.presets import MACHINES

TURN = 1440  # samples per revolution of the spectral derivatives


def spectral_derivatives(function, phi):
    """f, f′ and f″ at the angles phi of a 2π-periodic vector function f(φ) (shape (2, n)):
    sampled on a uniform grid, differentiated in Fourier space, interpolated back exactly
    (a trigonometric sum at each phi)."""
    grid = 2 * np.pi * np.arange(TURN) / TURN
    c = np.fft.fft(function(grid), axis=-1) / TURN
    k = np.fft.fftfreq(TURN, 1.0 / TURN)
    waves = np.exp(1j * np.outer(k, phi))  # (TURN, n)
    return tuple(np.real((c * (1j * k) ** order) @ waves) for order in (0, 1, 2))


def unit_bodies(c):
    """The unit's body positions as 2π-periodic functions of φ (absolute frame)."""
    axis = np.array([math.cos(c.inclination), math.sin(c.inclination)])[:, None]

    def pin(phi):
        angle = phi + c.phase + c.inclination
        return c.crank_radius * np.array([np.cos(angle), np.sin(angle)])

    def piston(phi):
        psi = phi + c.phase
        along = c.crank_radius * np.cos(psi) + np.sqrt(c.rod_length**2 - (c.crank_radius * np.sin(psi)) ** 2)
        return along * axis

    def rod(phi):
        return piston(phi) + (c.rod_cg / c.rod_length) * (pin(phi) - piston(phi))

    def rod_angle(phi):
        # the rod's angle from the cylinder axis (pin to piston pin: near 0, no wrap), which
        # turns as its absolute angle does
        d = piston(phi) - pin(phi)
        e = axis[:, 0]
        return np.array([np.arctan2(e[0] * d[1] - e[1] * d[0], e @ d), np.zeros(phi.shape)])

    return pin, piston, rod, rod_angle


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def oracle_throw_loads(machine, phi, omega, epsilon, gas, g, walls=None):
    """Each unit's load on its throw (units, 2, n) [N] by Newton–Euler of its bodies; where
    ``walls`` is a list, each unit's wall moment about the shaft axis, −N·|OB|, is appended
    to it (the wall takes −N n at the piston pin B)."""
    gravity = np.array([0.0, -g])
    loads = []
    for j, c in enumerate(machine.cylinders):
        pin, piston, rod, rod_angle = unit_bodies(c)
        acceleration = {}
        positions = {}
        for name, f in (("pin", pin), ("piston", piston), ("rod", rod), ("angle", rod_angle)):
            x, d1, d2 = spectral_derivatives(f, phi)
            positions[name] = x
            acceleration[name] = d2 * omega**2 + d1 * epsilon
        axis = np.array([math.cos(c.inclination), math.sin(c.inclination)])
        normal = np.array([-axis[1], axis[0]])
        out = np.zeros((2, phi.size))
        moment = np.zeros(phi.size)
        for i in range(phi.size):
            B, P, G = positions["piston"][:, i], positions["pin"][:, i], positions["rod"][:, i]
            a_B, a_G, alpha = acceleration["piston"][:, i], acceleration["rod"][:, i], acceleration["angle"][0, i]
            # unknowns: R (rod on piston, 2), N (wall on piston along n), Q (pin on rod, 2)
            A = np.zeros((5, 5))
            rhs = np.zeros(5)
            A[0:2, 0:2] = np.eye(2)
            A[0:2, 2] = normal
            rhs[0:2] = c.piston_mass * (a_B - gravity) + gas[j, i] * axis
            A[2:4, 0:2] = -np.eye(2)
            A[2:4, 3:5] = np.eye(2)
            rhs[2:4] = c.rod_mass * (a_G - gravity)
            # I α = (B − G) × (−R) + (P − G) × Q
            b_g, p_g = B - G, P - G
            A[4, 0:2] = [b_g[1], -b_g[0]]  # −(b_g × R) = −(b_x R_y − b_y R_x)
            A[4, 3:5] = [-p_g[1], p_g[0]]  # p_g × Q
            A[4] = -A[4]
            rhs[4] = -c.rod_inertia * alpha
            _, _, N, Q_x, Q_y = np.linalg.solve(A, rhs)
            if walls is not None:
                moment[i] = cross(B, -N * normal)
            a_P = acceleration["pin"][:, i]
            web = c.crank_cg_radius / c.crank_radius * a_P
            counterweight = -c.counterweight_radius / c.crank_radius * a_P
            out[:, i] = (
                -np.array([Q_x, Q_y])
                + (c.crank_mass + c.counterweight_mass) * gravity
                - c.crank_mass * web
                - c.counterweight_mass * counterweight
            )
        loads.append(out)
        if walls is not None:
            walls.append(moment)
    return np.array(loads)


def lever_rule(machine, throw_loads):
    """Each throw's load shared by its neighbouring bearings: (bearings, 2, n)."""
    bearings = np.asarray(machine.bearings)
    shared = np.zeros((bearings.size, *throw_loads.shape[1:]))
    for c, load in zip(machine.cylinders, throw_loads, strict=True):
        z = c.axial_position
        after = int(np.searchsorted(bearings, z, side="right"))
        a, b = bearings[after - 1], bearings[after]
        shared[after - 1] += (b - z) / (b - a) * load
        shared[after] += (z - a) / (b - a) * load
    return shared


def assert_loads(found, expected):
    scale = np.abs(expected).max()
    np.testing.assert_allclose(found.horizontal, expected[:, 0], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(found.vertical, expected[:, 1], rtol=0, atol=1e-9 * scale)


@pytest.mark.parametrize("name", list(MACHINES))
def test_every_presets_bearings_carry_what_newton_euler_gives(name):
    machine = MACHINES[name]
    phi = np.linspace(0.0, machine.cycle, 37)[:-1]
    found = mc.bearing_loads(machine, phi=phi)
    omega = math.pi * machine.rpm / 30
    gas = machine.piston_forces(phi)
    throws = oracle_throw_loads(machine, phi, omega, 0.0, gas, machine.g)
    assert_loads(found, lever_rule(machine, throws))
    # summed over the bearings: the whole force on the crank, at every angle
    total, scale = throws.sum(axis=0), np.abs(throws).max()  # opposed throws may cancel in the sum
    np.testing.assert_allclose(found.horizontal.sum(axis=0), total[0], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(found.vertical.sum(axis=0), total[1], rtol=0, atol=1e-9 * scale)


def test_the_rods_inertia_counts():
    """Unlike the free forces, the bearing loads depend on the rod's moment of inertia."""
    machine = MACHINES["inline-4"]
    heavy = machine.replace(cylinders=[c.replace(rod_inertia=3 * c.rod_inertia) for c in machine.cylinders])
    phi = np.linspace(0.0, 2 * np.pi, 13)
    light_loads, heavy_loads = mc.bearing_loads(machine, phi=phi), mc.bearing_loads(heavy, phi=phi)
    # the rod's inertia couple acts across the rod: on an upright machine mostly sideways
    assert not np.allclose(light_loads.horizontal, heavy_loads.horizontal, rtol=1e-3)
    gas = heavy.piston_forces(phi)
    expected = lever_rule(heavy, oracle_throw_loads(heavy, phi, math.pi * heavy.rpm / 30, 0.0, gas, heavy.g))
    assert_loads(heavy_loads, expected)
    free, heavy_free = mc.shaking_forces(machine).orders, mc.shaking_forces(heavy).orders
    np.testing.assert_array_equal(free.to_numpy(), heavy_free.to_numpy())


def test_in_steady_running_the_speed_and_acceleration_are_the_steady_states():
    machine = MACHINES["slow-compressor"]
    found = mc.bearing_loads(machine, steady=True)
    state = mc.steady_state(machine, points=721)
    phi, omega, epsilon = state.phi[:-1], state.omega[:-1], state.acceleration[:-1]
    np.testing.assert_array_equal(found.phi, phi)
    gas = machine.piston_forces(phi)
    expected = lever_rule(machine, oracle_throw_loads(machine, phi, omega, epsilon, gas, machine.g))
    assert_loads(found, expected)


def test_at_rest_the_bearings_carry_every_weight():
    """Statics: an upright machine without gas, turning as slowly as a speed may: the walls
    push only horizontally, so the bearings take the whole weight, whatever the angle."""
    # (1e-3 rpm: the inertia forces are 1e-11 of the weights)
    cylinder = mc.Cylinder(
        crank_radius=0.05,
        rod_length=0.2,
        piston_mass=2.0,
        rod_mass=1.5,
        rod_cg=0.14,
        crank_mass=3.0,
        crank_cg_radius=0.02,
        counterweight_mass=1.0,
        counterweight_radius=0.04,
    )
    machine = mc.Machine.from_layout("inline-3-2t", cylinder, shaft_inertia=1.0, cylinder_spacing=0.1)
    loads = mc.bearing_loads(machine, 1e-3, phi=np.linspace(0, 2 * np.pi, 9))
    weight = 3 * (2.0 + 1.5 + 3.0 + 1.0) * machine.g
    np.testing.assert_allclose(loads.vertical.sum(axis=0), -weight, rtol=1e-9)
    # (horizontally the bearings and the walls balance each other: the rods' weight leans)
    summary = loads.summary
    assert summary["gravity_adds"].max() == pytest.approx(summary["max"].max(), rel=1e-6)
    no_weight = mc.bearing_loads(machine, 1e-3, phi=np.linspace(0, 2 * np.pi, 9), gravity=False)
    assert np.abs(no_weight.vertical).max() < 1e-9 * weight


def test_the_summary_and_the_polar_diagram():
    machine = MACHINES["boxer-compressor"]
    loads = mc.bearing_loads(machine)
    summary = loads.summary
    assert list(summary.index) == list(range(len(machine.bearings)))
    np.testing.assert_array_equal(summary["position"], machine.bearings)
    magnitude = np.hypot(loads.horizontal, loads.vertical)
    np.testing.assert_array_equal(summary["max"], magnitude.max(axis=1))
    np.testing.assert_array_equal(summary["phi_max"], loads.phi[magnitude.argmax(axis=1)])
    without = mc.bearing_loads(machine, gravity=False)
    np.testing.assert_array_equal(
        summary["max_without_gravity"], np.hypot(without.horizontal, without.vertical).max(axis=1)
    )
    added = np.hypot(loads.horizontal - without.horizontal, loads.vertical - without.vertical).max(axis=1)
    np.testing.assert_allclose(summary["gravity_adds"], added, rtol=1e-12)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ax = loads.polar(1)
    plt.close(ax.figure)  # no figure left open for a later test to find
    assert ax.get_xlabel() == "horizontal [N]" and len(ax.lines) >= 2
    with pytest.raises(mc.MechanismError, match="bearing"):
        loads.polar(len(machine.bearings))


def test_bad_arguments_are_refused_by_name():
    machine = MACHINES["inline-4"]
    for kwargs, name in (
        ({"rpm": 0}, "rpm"),
        ({"phi": [[0.0]]}, "phi"),
        ({"phi": [np.nan]}, "phi"),
        ({"steady": 1}, "steady"),
        ({"gravity": "no"}, "gravity"),
        ({"steady": True, "phi": [0.0]}, "phi"),
    ):
        with pytest.raises(mc.MechanismError, match=name):
            mc.bearing_loads(machine, **kwargs)
    with pytest.raises(mc.MechanismError, match="machine"):
        mc.bearing_loads("inline-4")


def test_no_angles_and_a_bool_for_a_bearing_are_refused_by_name():
    """phi=[] gave empty loads whose summary and polar diagram failed in numpy, naming
    nothing; polar(True) passed the bearing check (True is an int) and drew bearing 1."""
    machine = MACHINES["boxer-compressor"]
    for empty in ([], np.empty(0), ()):
        with pytest.raises(mc.MechanismError, match=r"^phi must not be empty"):
            mc.bearing_loads(machine, phi=empty)
    loads = mc.bearing_loads(machine, phi=[0.0, 1.0])
    for flag in (True, False, np.True_):
        with pytest.raises(mc.MechanismError, match=r"^bearing must be an integer 0 <= bearing < 3, got "):
            loads.polar(flag)
    for other in (1.0, "1", None):
        with pytest.raises(mc.MechanismError, match=r"^bearing"):
            loads.polar(other)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ax = loads.polar(np.int64(2))
    plt.close(ax.figure)
    assert ax.get_title().startswith("bearing 2 ")


def test_too_many_angles_are_refused_before_anything_of_their_size_is_made(monkeypatch):
    """bearing_loads(phi=<10⁹ zeros>) was refused after 53 s, once the extension found it
    could not have the loads' memory. The angles are counted against the memory the call
    takes — speeds, accelerations, each cylinder's gas force and the two loads of every
    bearing, per angle — by the project's one limit (_validation.check_size), up front."""
    machine = MACHINES["boxer-compressor"]
    per_angle = 2 + len(machine.cylinders) + 2 * len(machine.bearings)
    # Beyond any machine's memory (a view: the angles themselves take none).
    start = time.perf_counter()
    with pytest.raises(mc.MechanismError, match=r"^phi = 10000000000000 angles for 3 bearings asks for "):
        mc.bearing_loads(machine, phi=np.broadcast_to(0.0, (10**13,)))
    assert time.perf_counter() - start < 5.0  # a guard against the work, not a measurement
    # A pretend machine whose memory holds the loads of 1000 angles, and not of 1001.
    monkeypatch.setattr(validation, "allocatable_bytes", lambda: 1000 * per_angle * 8)
    assert mc.bearing_loads(machine, phi=np.linspace(0.0, 1.0, 1000)).vertical.shape == (3, 1000)
    with pytest.raises(mc.MechanismError, match=r"^phi = 1001 angles for 3 bearings .* more than can be allocated"):
        mc.bearing_loads(machine, phi=np.linspace(0.0, 1.0, 1001))
    # Nothing of the angles' size is allocated before the refusal (numpy's allocations are
    # traced): 10⁷ angles as a view, 80 MB as one array of them.
    angles = np.broadcast_to(0.0, (10**7,))
    tracemalloc.start()
    try:
        with pytest.raises(mc.MechanismError, match=r"^phi = 10000000 angles"):
            mc.bearing_loads(machine, phi=angles)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 10**6, peak


@pytest.mark.parametrize("name", ["slow-compressor", "inline-4", "genset-v12"])
def test_the_frame_takes_the_walls_moments_about_the_shaft(name):
    """ShakingForces.curves' torque_reaction: the moments of the pistons' side forces on the
    walls, −Σ N·x_B, from this file's Newton–Euler solution."""
    machine = MACHINES[name]
    phi = np.linspace(0.0, machine.cycle, 25)[:-1]
    walls: list[np.ndarray] = []
    oracle_throw_loads(machine, phi, math.pi * machine.rpm / 30, 0.0, machine.piston_forces(phi), machine.g, walls)
    expected = np.sum(walls, axis=0)
    found = mc.shaking_forces(machine).curves(phi)["torque_reaction"].to_numpy()
    np.testing.assert_allclose(found, expected, rtol=0, atol=1e-9 * np.abs(expected).max())


def test_over_a_cycle_the_block_rolls_against_the_crank_with_the_mean_gas_torque():
    """Without gravity and at a constant speed the mechanism's angular momentum about the
    axis is periodic: the walls' moment averages what the shaft delivers, the mean gas
    torque (an independent integral of Machine.gas_torque), and the frame takes minus that."""
    machine = MACHINES["inline-4"].replace(g=0.0)
    phi = machine.cycle * np.arange(2880) / 2880
    torque = mc.shaking_forces(machine).curves(phi)["torque_reaction"].to_numpy()
    mean_gas = float(np.mean(machine.gas_torque(phi)))
    assert mean_gas > 0
    assert np.mean(torque) == pytest.approx(-mean_gas, rel=1e-6)


def test_the_loads_do_not_depend_on_the_thread_count():
    machine = MACHINES["genset-v12"]
    before = mc.get_parallel_threshold()
    try:
        mc.set_parallel_threshold(2**62)
        serial = mc.bearing_loads(machine)
        mc.set_parallel_threshold(1)
        parallel = mc.bearing_loads(machine)
    finally:
        mc.set_parallel_threshold(before)
    np.testing.assert_array_equal(serial.horizontal, parallel.horizontal)
    np.testing.assert_array_equal(serial.vertical, parallel.vertical)


@pytest.mark.parametrize("name", ["slow-compressor", "inline-4"])  # a two-stroke cycle and a four-stroke one
@pytest.mark.parametrize("steady", [False, True])
def test_the_loads_beside_the_shaking_forces_are_bearing_loads_own(name, steady):
    """bearing_loads_beside (the command line's forces): at the ω of the shaking forces and,
    steady, on their steady state (every 2·turns-th of its 1440 angles per revolution) — the
    loads bearing_loads gives at that speed from a steady state of its own, to the last bit."""
    from multicrank.forces.bearings import bearing_loads_beside

    machine = MACHINES[name]
    forces = mc.shaking_forces(machine, max_order=2, steady=steady)
    beside = bearing_loads_beside(forces)
    own = mc.bearing_loads(machine, steady=steady)
    assert (beside.rpm, beside.omega, beside.steady) == (own.rpm, own.omega, own.steady)
    for field in ("phi", "positions", "vertical", "horizontal"):
        np.testing.assert_array_equal(getattr(beside, field), getattr(own, field), err_msg=field)
