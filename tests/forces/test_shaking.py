"""mc.shaking_forces against an independent oracle: the planar geometry of every rigid body
written here (piston at its pin, the rod's real centre of gravity between its pins, crank web
and counterweight on the crank), first moments Σ m·x summed body by body, derivatives and
harmonics by numpy's FFT (spectral: the geometry is analytic) — no formula of the core. Then
textbook facts (in-line four, three and six, boxer four, cross-plane V8 and its
counterweights) and the identity F_v = −(U″ω² + U′ε)/g against the machine's potential by
finite differences."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc
from multicrank.forces import shaking_forces
from multicrank.presets import MACHINES

TEMPLATE = mc.Cylinder(
    crank_radius=0.05,
    rod_length=0.18,
    piston_mass=1.2,
    rod_mass=1.5,
    rod_cg=0.12,
    crank_mass=2.0,
    crank_cg_radius=0.02,
    counterweight_mass=1.0,
    counterweight_radius=0.04,
)

SAMPLES = 512  # per revolution: the geometry's harmonics are below rounding far before 256


def first_moments(machine, phi):
    """Σ m·(x, y) and Σ z·m·(x, y) [kg·m, kg·m²] of every body of every unit at the angles phi:
    shape (4, phi.size) — vertical, horizontal, and both weighted by the lever z − z_ref about
    the engine centre, the midpoint of the outermost cylinders."""
    out = np.zeros((4, phi.size))
    centre = engine_centre(machine)
    for c in machine.cylinders:
        psi = phi + c.phase
        pin_angle = psi + c.inclination
        pin = c.crank_radius * np.array([np.cos(pin_angle), np.sin(pin_angle)])
        axis = np.array([math.cos(c.inclination), math.sin(c.inclination)])[:, None]
        along = c.crank_radius * np.cos(psi) + np.sqrt(c.rod_length**2 - (c.crank_radius * np.sin(psi)) ** 2)
        piston = along * axis
        rod = piston + (c.rod_cg / c.rod_length) * (pin - piston)
        web = c.crank_cg_radius / c.crank_radius * pin
        counterweight = -c.counterweight_radius / c.crank_radius * pin
        total = c.piston_mass * piston + c.rod_mass * rod + c.crank_mass * web + c.counterweight_mass * counterweight
        out[0] += total[1]
        out[1] += total[0]
        out[2] += (c.axial_position - centre) * total[1]
        out[3] += (c.axial_position - centre) * total[0]
    return out


def engine_centre(machine):
    """z_ref = (z_min + z_max)/2 [m]: the point along the shaft the moments are taken about."""
    positions = [c.axial_position for c in machine.cylinders]
    return (min(positions) + max(positions)) / 2


def spectral(values, turns=1):
    """The FFT coefficients c_k of samples over `turns` revolutions, and the orders k/turns."""
    c = np.fft.fft(values, axis=-1) / values.shape[-1]
    k = np.fft.fftfreq(values.shape[-1], 1.0 / values.shape[-1])
    return c, k / turns


def oracle_orders(machine, rpm, max_order):
    """The table of orders at a constant speed: F = −ω² X″, the order-n harmonic of X by a
    discrete Fourier transform of 128 samples in 30-digit arithmetic (what the units' sum
    cancels is far below double precision's reach in a sampled X), times n²ω²."""
    omega = mpmath.mpf(math.pi * rpm / 30)
    count = 128
    with mpmath.workdps(30):
        samples = [precise_moments(machine, 2 * mpmath.pi * j / count) for j in range(count)]
        spectrum = np.zeros((4, 2 * max_order + 1), dtype=complex)
        orders = list(range(-max_order, max_order + 1))
        for i, n in enumerate(orders):
            turn = [mpmath.expjpi(-2 * mpmath.mpf(n) * j / count) for j in range(count)]
            for row in range(4):
                value = mpmath.fsum(samples[j][row] * turn[j] for j in range(count)) / count
                spectrum[row, i] = complex(value * n * n * omega**2)
    return table(spectrum, np.array(orders, dtype=float), np.arange(1, max_order + 1))


def precise_moments(machine, phi):
    """:func:`first_moments` at one angle in mpmath (the working precision)."""
    out = [mpmath.mpf(0)] * 4
    positions = [mpmath.mpf(c.axial_position) for c in machine.cylinders]
    centre = (min(positions) + max(positions)) / 2
    for c in machine.cylinders:
        r, l = mpmath.mpf(c.crank_radius), mpmath.mpf(c.rod_length)
        z = mpmath.mpf(c.axial_position) - centre
        gamma = mpmath.mpf(c.inclination)
        psi = phi + mpmath.mpf(c.phase)
        pin = (r * mpmath.cos(psi + gamma), r * mpmath.sin(psi + gamma))
        along = r * mpmath.cos(psi) + mpmath.sqrt(l**2 - (r * mpmath.sin(psi)) ** 2)
        piston = (along * mpmath.cos(gamma), along * mpmath.sin(gamma))
        share = mpmath.mpf(c.rod_cg) / l
        rod = tuple(p + share * (q - p) for p, q in zip(piston, pin, strict=True))
        arm = (
            mpmath.mpf(c.crank_mass) * mpmath.mpf(c.crank_cg_radius)
            - mpmath.mpf(c.counterweight_mass) * mpmath.mpf(c.counterweight_radius)
        ) / r
        total = [mpmath.mpf(c.piston_mass) * piston[i] + mpmath.mpf(c.rod_mass) * rod[i] + arm * pin[i] for i in (0, 1)]
        out = [out[0] + total[1], out[1] + total[0], out[2] + z * total[1], out[3] + z * total[0]]
    return out


def table(spectrum, k, orders):
    """Amplitudes, phases and forward/backward parts of a two-sided spectrum (4 × K)."""
    rows = {}
    index = {float(v): i for i, v in enumerate(k)}
    for name, row in zip(("force_vertical", "force_horizontal", "moment_pitch", "moment_yaw"), spectrum, strict=True):
        plus = np.array([row[index[float(n)]] for n in orders])
        a, b = 2 * plus.real, -2 * plus.imag
        rows[name] = np.hypot(a, b)
        rows[f"{name}_phase"] = np.arctan2(b, a)
    for name, (h, v) in (("force", (1, 0)), ("moment", (3, 2))):
        rotating = spectrum[h] + 1j * spectrum[v]
        rows[f"{name}_forward"] = np.abs([rotating[index[float(n)]] for n in orders])
        rows[f"{name}_backward"] = np.abs([rotating[index[float(-n)]] for n in orders])
    return rows


def units_scale(machine, rpm, max_order):
    """What the units shake with alone at the highest order (each moving mass times its
    crank radius, n²ω², and the largest lever |z|): the size below which an order is what
    their sum cancels, 0 in the core and float-rounding of the phases in the oracle."""
    omega = math.pi * rpm / 30
    lever = max(1.0, *(abs(c.axial_position) for c in machine.cylinders))
    mass = sum(
        (c.piston_mass + c.rod_mass) * c.crank_radius
        + c.crank_mass * c.crank_cg_radius
        + c.counterweight_mass * c.counterweight_radius
        for c in machine.cylinders
    )
    return max_order**2 * omega**2 * mass * lever


def assert_orders(found, expected, rtol=1e-9, cancelled=0.0):
    """Each group (forces, moments) to ``rtol`` of its largest amplitude, and to 1e-12 of
    ``cancelled`` (:func:`units_scale`) where the units' sum cancels."""
    for group in ("force", "moment"):
        names = [n for n in expected if n.startswith(group) and not n.endswith("_phase")]
        scale = max(float(np.max(expected[n])) for n in names)
        atol = rtol * scale + 1e-12 * cancelled
        for name in names:
            np.testing.assert_allclose(found[name].to_numpy(), expected[name], rtol=0, atol=atol, err_msg=name)
            phase = f"{name}_phase"
            if phase in expected:
                # a phase is as good as its amplitude is large against the error allowed
                big = expected[name] > 1e3 * atol
                difference = np.angle(np.exp(1j * (found[phase].to_numpy()[big] - expected[phase][big])))
                allowed = 2 * atol / expected[name][big]
                assert np.all(np.abs(difference) <= allowed), (phase, difference, allowed)


def placed(layout, spacing=0.1, **changes):
    return mc.Machine.from_layout(
        layout, TEMPLATE.replace(**changes), shaft_inertia=1.0, cylinder_spacing=spacing, rpm=3000
    )


@pytest.mark.parametrize("name", list(MACHINES))
def test_the_orders_of_every_preset_are_the_oracles(name):
    machine = MACHINES[name]
    found = shaking_forces(machine, 600.0, max_order=12).orders
    assert_orders(found, oracle_orders(machine, 600.0, 12), cancelled=units_scale(machine, 600.0, 12))


@settings(max_examples=25, deadline=None)
@given(
    ratio=st.floats(0.1, 0.45),
    cg=st.floats(0.0, 1.0),
    phases=st.lists(st.floats(0.0, 2 * math.pi), min_size=1, max_size=4),
    inclinations=st.lists(st.floats(-math.pi, math.pi), min_size=4, max_size=4),
    positions=st.lists(st.floats(-0.5, 0.5), min_size=4, max_size=4),
)
def test_any_machine_is_the_oracles(ratio, cg, phases, inclinations, positions):
    cylinders = [
        TEMPLATE.replace(
            rod_length=0.05 / ratio,
            rod_cg=cg * 0.05 / ratio,
            phase=phase,
            inclination=inclinations[j],
            axial_position=positions[j],
        )
        for j, phase in enumerate(phases)
    ]
    machine = mc.Machine(cylinders, shaft_inertia=1.0)
    found = shaking_forces(machine, 1500.0, max_order=8).orders
    assert_orders(found, oracle_orders(machine, 1500.0, 8), cancelled=units_scale(machine, 1500.0, 8))


def test_the_curves_are_minus_omega_squared_times_the_second_derivative():
    machine = placed("v8-cross")
    omega = math.pi * 3000 / 30
    phi = 2 * np.pi * np.arange(SAMPLES) / SAMPLES
    c, k = spectral(first_moments(machine, phi))
    expected = np.fft.ifft(omega**2 * k**2 * c * SAMPLES, axis=-1).real
    curves = shaking_forces(machine, 3000).curves(phi)
    for row, name in zip(expected, ("force_vertical", "force_horizontal", "moment_pitch", "moment_yaw"), strict=True):
        np.testing.assert_allclose(curves[name].to_numpy(), row, rtol=0, atol=1e-9 * np.abs(expected).max())
    assert list(curves.index) == list(phi)
    assert len(shaking_forces(machine, 3000).curves()) == 361


def test_the_identity_with_the_machines_potential_by_finite_differences():
    """F_v = −(U″ω² + U′ε)/g: the vertical force at constant speed from the machine's own
    potential energy (the paper's U, g included), differentiated numerically."""
    # one cylinder, whose force nothing cancels: the difference quotient's rounding (U is
    # hundreds of joules) stays far below it
    machine = mc.Machine([TEMPLATE.replace(inclination=1.0, phase=0.3)], shaft_inertia=1.0)
    omega, h = math.pi * 2000 / 30, 1e-3
    phi = np.linspace(0.1, 6.0, 9)
    U = machine.potential_energy
    second = (-U(phi + 2 * h) + 16 * U(phi + h) - 30 * U(phi) + 16 * U(phi - h) - U(phi - 2 * h)) / (12 * h * h)
    curves = shaking_forces(machine, 2000).curves(phi)
    expected = -second * omega**2 / machine.g
    np.testing.assert_allclose(curves["force_vertical"], expected, rtol=0, atol=1e-7 * np.abs(expected).max())


def single_cylinder_orders(rpm):
    one = mc.Machine([TEMPLATE.replace(inclination=math.pi / 2)], shaft_inertia=1.0)
    return oracle_orders(one, rpm, 4)


def test_an_inline_four_leaves_four_times_one_cylinders_second_order_and_no_first():
    machine = placed("inline-4-4t")
    found = shaking_forces(machine, 3000, max_order=4).orders
    one = single_cylinder_orders(3000)
    assert found.loc[1, "force_vertical"] == 0 and found.loc[3, "force_vertical"] == 0
    assert (found["force_horizontal"] == 0).all()
    assert found.loc[2, "force_vertical"] == pytest.approx(4 * one["force_vertical"][1], rel=1e-12)
    # the crank 0-180-180-0 along the shaft is mirror-symmetric: its second order acts at the
    # engine centre (z = 0.15 m), the point the moments are taken about, and its first orders
    # leave no couple
    assert found.loc[2, "moment_pitch"] == 0
    assert found.loc[1, "moment_pitch"] == 0


@pytest.mark.parametrize(("layout", "crank_angle"), [("inline-2-4t", 0.0), ("twin-270", math.pi / 2)])
def test_an_inline_twin_rocks_about_its_centre_by_the_angle_between_its_cranks(layout, crank_angle):
    """Two equal cylinders a apart with cranks α apart: about the engine centre each order n
    of the vertical (and of the horizontal) force leaves the couple (a/2)·abs(F_2 − F_1) =
    a·abs(sin(nα/2))·F_n of one cylinder: none for the 360° twin (cranks together), a couple
    for the 270° twin (cranks 90° apart), wherever the twin sits along the shaft."""
    one = single_cylinder_orders(3000)
    for start in (0.0, 1.0, -7.3):
        twin = mc.Machine.from_layout(layout, TEMPLATE, shaft_inertia=1.0, cylinder_spacing=0.1, rpm=3000)
        machine = twin.replace(cylinders=[c.replace(axial_position=c.axial_position + start) for c in twin.cylinders])
        found = shaking_forces(machine, 3000, max_order=4).orders
        for n in (1, 2, 3, 4):
            lever = 0.1 * abs(math.sin(n * crank_angle / 2))
            for moment, force in (("moment_pitch", "force_vertical"), ("moment_yaw", "force_horizontal")):
                expected = lever * one[force][n - 1]
                assert found.loc[n, moment] == pytest.approx(expected, rel=1e-9, abs=1e-9 * one[force][0]), (
                    start,
                    n,
                    moment,
                )


@given(
    shift=st.floats(-50.0, 50.0),
    name=st.sampled_from(sorted(MACHINES)),
)
@settings(max_examples=25)
def test_no_reported_number_moves_with_the_origin_along_the_shaft(shift, name):
    """Moving every cylinder and main bearing along the shaft by one distance changes no
    shaking force or moment (moments are about the engine centre, which moves with them), no
    bearing load, and no free moment of the frame sweep or the firing orders."""
    machine = MACHINES[name]
    moved = machine.replace(
        cylinders=[c.replace(axial_position=c.axial_position + shift) for c in machine.cylinders],
        main_bearings=None if machine.main_bearings is None else [z + shift for z in machine.main_bearings],
        shaft=machine.shaft,
    )
    lever = 1.0 + max(abs(c.axial_position) for c in moved.cylinders)
    before, after = (shaking_forces(m, max_order=4).orders for m in (machine, moved))
    for column in before.columns:
        if column.endswith("_phase"):
            continue
        scale = max(float(before[column].max()), 1e-300)
        np.testing.assert_allclose(after[column], before[column], rtol=1e-9, atol=1e-11 * lever * scale, err_msg=column)
    loads = [mc.bearing_loads(m).summary["max"].to_numpy() for m in (machine, moved)]
    np.testing.assert_allclose(loads[1], loads[0], rtol=1e-9)
    frame = [
        mc.motion_sweep(m, mc.MachineGrid(m, rpm=[m.rpm]), outputs=["free_moment_1", "free_moment_2"])
        for m in (machine, moved)
    ]
    for column in ("free_moment_1", "free_moment_2"):
        scale = float(abs(frame[0][column]).max()) + 1e-12 * lever * float(before["force_forward"].max())
        np.testing.assert_allclose(frame[1][column], frame[0][column], rtol=0, atol=1e-9 * scale, err_msg=column)


def test_an_inline_three_rocks_with_first_and_second_order_couples():
    machine = placed("inline-3-4t", spacing=0.1)
    found = shaking_forces(machine, 3000, max_order=3).orders
    one = single_cylinder_orders(3000)
    for n in (1, 2):
        assert found.loc[n, "force_vertical"] == 0 and found.loc[n, "force_horizontal"] == 0
        # three equal forces 120° apart at z = 0, a, 2a: a couple of √3·a times one of them
        assert found.loc[n, "moment_pitch"] == pytest.approx(
            math.sqrt(3) * 0.1 * one["force_vertical"][n - 1], rel=1e-12
        )
    # the crank's rotating unbalance makes a horizontal couple as well, of first order only
    assert found.loc[1, "moment_yaw"] > 0 and found.loc[2, "moment_yaw"] == 0


def test_an_inline_six_is_free_of_first_and_second_order_forces_and_moments():
    found = shaking_forces(placed("inline-6-4t"), 3000, max_order=6).orders
    for n in (1, 2):
        for name in ("force_vertical", "force_horizontal", "moment_pitch", "moment_yaw"):
            assert found.loc[n, name] == 0, (n, name)
    assert found.loc[6, "force_vertical"] > 0


def test_a_boxer_four_cancels_its_forces_and_its_first_order_couple():
    found = shaking_forces(placed("boxer-4"), 3000, max_order=4).orders
    for name in ("force_vertical", "force_horizontal"):
        assert (found[name] == 0).all(), name
    assert found.loc[1, "moment_yaw"] == 0 and found.loc[1, "moment_pitch"] == 0
    assert found.loc[2, "moment_yaw"] > 0  # the second-order couple of the offset pairs


def test_a_cross_plane_v8_has_a_first_order_rotating_couple_that_counterweights_cancel():
    bare = placed("v8-cross", counterweight_mass=0.0)
    found = shaking_forces(bare, 3000, max_order=2).orders
    assert found.loc[1, "force_vertical"] == 0 and found.loc[1, "force_horizontal"] == 0
    assert found.loc[1, "moment_forward"] > 0 and found.loc[1, "moment_backward"] == 0
    assert found.loc[2, "force_vertical"] == 0 and found.loc[2, "moment_pitch"] == 0
    # A 90° V's two pistons on one pin shake it like one rotating mass m_rec at the pin: a
    # counterweight per throw of r·(m_rec + both rods' big ends) + the web cancels the throw's
    # first order, and with it the couple.
    c = TEMPLATE
    reciprocating = c.piston_mass + c.rod_mass * (1 - c.rod_cg / c.rod_length)
    big_ends = 2 * c.rod_mass * c.rod_cg / c.rod_length
    moment = c.crank_radius * (reciprocating + big_ends) + c.crank_mass * c.crank_cg_radius
    balanced = placed("v8-cross", counterweight_mass=moment / 0.04, counterweight_radius=0.04)
    after = shaking_forces(balanced, 3000, max_order=2).orders
    scale = found.loc[1, "moment_forward"]
    assert after.loc[1, "moment_forward"] <= 1e-12 * scale and after.loc[1, "moment_backward"] <= 1e-12 * scale
    assert after.loc[1, "force_forward"] <= 1e-9 * scale


def test_steady_running_carries_the_speed_fluctuation_into_the_forces():
    """steady=True: F = −(X″ω² + X′ε) with the steady state's ω and ε at its own angles, X′ and
    X″ spectrally from the geometry, then the FFT over the working cycle (half orders for a
    four-stroke machine)."""
    machine = MACHINES["inline-4"]
    rpm = 1000.0
    found = shaking_forces(machine, rpm, max_order=4, steady=True)
    state = mc.steady_state(machine, rpm=rpm, points=2 * 1440 + 1)
    phi, omega, epsilon = state.phi[:-1], state.omega[:-1], state.acceleration[:-1]
    # the oracle takes the state's angles as two revolutions of 1440 uniform ones
    np.testing.assert_allclose(phi, 4 * np.pi * np.arange(2880) / 2880, rtol=1e-15, atol=1e-15)
    turn = 2 * np.pi * np.arange(1440) / 1440
    c, k = spectral(first_moments(machine, turn))
    slope = np.tile(np.fft.ifft(1j * k * c * 1440, axis=-1).real, 2)
    curvature = np.tile(np.fft.ifft(-(k**2) * c * 1440, axis=-1).real, 2)
    force = -(curvature * omega**2 + slope * epsilon)
    spectrum, orders = spectral(force, turns=2)
    expected = table(spectrum, orders, np.arange(1, 9) / 2)
    assert list(found.orders.index) == list(np.arange(1, 9) / 2)
    # the mirror-symmetric crank's moments about its centre cancel: rounding in the oracle
    assert_orders(found.orders, expected, cancelled=units_scale(machine, rpm, 4))
    constant = shaking_forces(machine, rpm, max_order=4).orders
    # the fluctuation changes the second order a little, and the curves are the state's
    assert found.orders.loc[2.0, "force_vertical"] != constant.loc[2, "force_vertical"]
    assert found.orders.loc[2.0, "force_vertical"] == pytest.approx(constant.loc[2, "force_vertical"], rel=0.05)
    curves = found.curves()
    np.testing.assert_array_equal(curves.index.to_numpy(), state.phi)


def test_bad_arguments_are_refused_by_name():
    machine = MACHINES["inline-4"]
    with pytest.raises(mc.MechanismError, match="max_order"):
        shaking_forces(machine, 1000, max_order=0)
    with pytest.raises(mc.MechanismError, match="rpm"):
        shaking_forces(machine, -5)
    with pytest.raises(mc.MechanismError, match="steady"):
        shaking_forces(machine, 1000, steady="yes")
    with pytest.raises(mc.MechanismError, match="machine"):
        shaking_forces("inline-4", 1000)
    with pytest.raises(mc.MechanismError, match="phi"):
        shaking_forces(machine, 1000, steady=True).curves(np.zeros(3))
    with pytest.raises(mc.MechanismError, match="phi"):
        shaking_forces(machine, 1000).curves([[0.0, 1.0]])
    no_speed = mc.Machine([TEMPLATE], shaft_inertia=1.0)
    with pytest.raises(mc.MechanismError, match="rpm"):
        shaking_forces(no_speed)


def test_the_default_speed_is_the_machines():
    machine = MACHINES["inline-4"]
    assert shaking_forces(machine).rpm == machine.rpm
    assert shaking_forces(machine).orders.attrs["rpm"] == machine.rpm
