"""mc.torque_orders (motion.md §6): the orders of the gas, inertia and gravity torques.

Oracles: the machine's own torques on a dense grid (the series must sum back to them), an FFT of
the gravity torque (which also checks the scaling U = I_w ω² U*), the textbook expansion of a
single cylinder's inertia torque in λ and its exact form in Λ_n computed by mpmath quadrature,
scipy.integrate.quad of a tabulated gas torque between its kinks, and the indicated work of the
diagram.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from mpmath import mp
from scipy.integrate import quad

import multicrank as mc
from multicrank.motion.orders import ORDER_PARTS

RPM = 1500.0
OMEGA = math.pi * RPM / 30


def smooth_four_stroke(theta):
    """A smooth 4π-periodic gauge pressure [Pa], with half orders."""
    theta = np.asarray(theta, dtype=float)
    return 1e5 * (2.0 + np.sin(0.5 * theta) + 0.3 * np.cos(2 * theta) + 0.2 * np.sin(1.5 * theta + 0.4))


CYLINDER = mc.Cylinder(
    crank_radius=0.06,
    rod_length=0.21,
    piston_mass=1.3,
    rod_mass=0.85,
    rod_cg=0.145,
    rod_inertia=0.003,
    crank_mass=3.0,
    crank_cg_radius=0.04,
    counterweight_mass=1.0,
    counterweight_radius=0.05,
    bore=0.09,
    inclination=1.2,
)


def twin(strokes=4, pressure=smooth_four_stroke):
    """Two unequal, differently inclined units."""
    first = CYLINDER.replace(phase=0.3, pressure=pressure)
    second = CYLINDER.replace(phase=2.0, inclination=0.4, piston_mass=1.7, pressure=pressure)
    return mc.Machine([first, second], shaft_inertia=0.25, strokes=strokes)


def synthesize(table, part, phi):
    """Σ_ν a_ν cos νφ + b_ν sin νφ of one part."""
    orders = table.index.to_numpy()[:, None]
    cos, sin = table[f"{part}_cos"].to_numpy()[:, None], table[f"{part}_sin"].to_numpy()[:, None]
    return np.sum(cos * np.cos(orders * phi) + sin * np.sin(orders * phi), axis=0)


def test_the_series_sum_back_to_the_torques():
    machine = twin()
    table = mc.torque_orders(machine, RPM, max_order=30)
    phi = np.linspace(-1.0, 4 * math.pi + 1.0, 1201)
    torques = {
        "gas": machine.gas_torque(phi),
        "inertia": machine.inertia_torque(phi, OMEGA),
        "gravity": machine.gravity_torque(phi),
    }
    torques["total"] = torques["gas"] + torques["inertia"] + torques["gravity"]
    for part, torque in torques.items():
        scale = np.max(np.abs(torque))
        assert scale > 0
        assert np.max(np.abs(synthesize(table, part, phi) - torque)) <= 1e-12 * scale, part


def test_gravity_orders_are_the_fft_of_the_gravity_torque_at_any_speed():
    machine = twin()
    samples = 256
    phi = np.arange(samples) * (2 * math.pi / samples)
    spectrum = np.fft.rfft(machine.gravity_torque(phi)) * (2 / samples)
    for rpm in (100.0, 3000.0):
        table = mc.torque_orders(machine, rpm, max_order=20)
        integer = table.loc[np.arange(21.0)]
        scale = np.max(np.abs(spectrum))
        np.testing.assert_allclose(integer["gravity_cos"].to_numpy()[1:], spectrum.real[1:21], atol=1e-13 * scale)
        np.testing.assert_allclose(integer["gravity_sin"].to_numpy(), -spectrum.imag[:21], atol=1e-13 * scale)
        assert integer["gravity_cos"].iloc[0] == 0.0  # U is periodic: no mean torque
        assert np.max(integer["gravity_amplitude"]) > 1.0  # N·m: not trivially zero


def _lambda_coefficients(lam, count):
    """Λ_2, Λ_4, … of f(ψ) = λ sin 2ψ / (2√(1 − λ² sin² ψ)) = Σ Λ_n sin nψ, by mpmath quadrature."""
    with mp.workdps(30):
        lam = mp.mpf(lam)

        def f(psi):
            return lam * mp.sin(2 * psi) / (2 * mp.sqrt(1 - lam**2 * mp.sin(psi) ** 2))

        return [
            float(mp.quad(lambda p, n=n: f(p) * mp.sin(n * p), [0, mp.pi, 2 * mp.pi]) / mp.pi)
            for n in range(2, 2 * count + 1, 2)
        ]


def piston_only(lam, mass=2.0, radius=0.05):
    cylinder = mc.Cylinder(crank_radius=radius, rod_length=radius / lam, piston_mass=mass, rod_mass=0.0, rod_cg=0.0)
    return mc.Machine([cylinder], shaft_inertia=0.1, strokes=2)


def test_single_cylinder_inertia_orders_are_the_textbook_ones_to_leading_order_in_lambda():
    """M = (m r² ω²/2)[(λ/2) sin φ − sin 2φ − (3λ/2) sin 3φ] + O(λ²): orders 1 and 3 to O(λ³),
    order 2 to O(λ⁴), the cosines zero (the torque is odd in φ)."""
    lam, mass, radius = 0.05, 2.0, 0.05
    table = mc.torque_orders(piston_only(lam, mass, radius), RPM, max_order=6)
    unit = mass * radius**2 * OMEGA**2
    textbook = {1: unit * lam / 4, 2: -unit / 2, 3: -unit * 3 * lam / 4}
    for order, value in textbook.items():
        assert table.loc[float(order), "inertia_sin"] == pytest.approx(value, abs=unit * lam**3)
    assert abs(table.loc[4.0, "inertia_sin"]) == pytest.approx(unit * lam**2 / 4, rel=0.01)  # Λ_2² first
    np.testing.assert_allclose(table["inertia_cos"], 0.0, atol=1e-14 * unit)
    # and the textbook expansion is not what the library does: at λ = 0.05 its λ³ error is visible
    assert table.loc[1.0, "inertia_sin"] != pytest.approx(textbook[1], abs=1e-3 * unit * lam**3)


def test_single_cylinder_inertia_orders_exactly_in_lambda_n():
    """With s'/r = sin ψ + Σ Λ_n sin nψ and M = −m s' s'' ω²: b_1 = m r²ω² Λ_2/2,
    b_2 = −m r²ω² (½ − Σ Λ_n Λ_{n+2}), b_3 = −(3/2) m r²ω² (Λ_2 − Λ_4)."""
    lam, mass, radius = 0.3, 2.0, 0.05
    table = mc.torque_orders(piston_only(lam, mass, radius), RPM, max_order=4)
    coefficients = _lambda_coefficients(lam, 12)
    unit = mass * radius**2 * OMEGA**2
    b1 = unit * coefficients[0] / 2
    b2 = -unit * (0.5 - sum(a * b for a, b in itertools.pairwise(coefficients)))
    b3 = -1.5 * unit * (coefficients[0] - coefficients[1])
    got = table.loc[[1.0, 2.0, 3.0], "inertia_sin"].to_numpy()
    np.testing.assert_allclose(got, [b1, b2, b3], rtol=1e-13)


def test_half_orders_come_only_from_a_four_stroke_gas_cycle():
    half = np.arange(0.5, 12, 1.0)
    no_gas = mc.torque_orders(twin(pressure=None), RPM)
    assert np.all(no_gas.loc[half].to_numpy() == 0.0)
    assert np.all(no_gas.filter(like="gas_").to_numpy() == 0.0)
    gassed = mc.torque_orders(twin(), RPM)
    assert np.all(gassed.loc[half, ["inertia_cos", "inertia_sin", "gravity_cos", "gravity_sin"]].to_numpy() == 0.0)
    assert gassed.loc[0.5, "gas_amplitude"] > 1.0 and gassed.loc[1.5, "gas_amplitude"] > 1.0
    two_stroke = mc.torque_orders(twin(strokes=2, pressure=lambda t: 1e5 * (1 + np.cos(t))), RPM, max_order=5)
    assert two_stroke.index.tolist() == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]
    assert gassed.index.tolist() == list(np.arange(25) / 2)


def test_what_cancels_exactly_is_zero_not_rounding():
    """Orders that vanish by symmetry are exactly 0 in the table (not 1e-15 N·m): a flat-plane
    in-line four's phase sums Σ e^(iνα) (α = 0, π, π, 0) vanish for odd ν, so its inertia and
    gravity have no odd orders; one cylinder's gravity has ν = 1 and even ν only (the Λ_n), and
    inertia −½J′ω² has no mean (J is periodic). What does not cancel stays."""
    four = mc.presets.MACHINES["inline-4"]
    table = mc.torque_orders(four, 3000, max_order=12)
    odd = [1.0, 3.0, 5.0, 7.0, 9.0, 11.0]
    for part in ("inertia", "gravity"):
        assert np.all(table.loc[odd, [f"{part}_cos", f"{part}_sin", f"{part}_amplitude"]].to_numpy() == 0.0), part
    assert table.loc[0.0, "inertia_amplitude"] == 0.0
    assert np.all(table.loc[[2.0, 4.0, 6.0, 8.0], "inertia_amplitude"] > 0)
    one = mc.presets.MACHINES["slow-compressor"]
    single = mc.torque_orders(one, 120, max_order=12)
    assert np.all(single.loc[[3.0, 5.0, 7.0, 9.0, 11.0], "gravity_amplitude"] == 0.0)
    assert single.loc[0.0, "inertia_amplitude"] == 0.0
    assert np.all(single.loc[[1.0, 2.0, 4.0, 6.0, 8.0], "gravity_amplitude"] > 0)
    assert np.all(single.loc[1.0:12.0, "inertia_amplitude"] > 0)  # a single cylinder's inertia has every order


def test_tabulated_gas_orders_against_quad_between_the_kinks():
    angle = np.linspace(0.0, 4 * math.pi, 13)
    pressure = 1e5 * np.array([30.0, 12, 5, 2, 1, 0.5, 0.5, 0.8, 1.5, 3, 8, 18, 30])
    diagram = mc.IndicatorDiagram(angle, pressure, cycle=4 * math.pi, kind="linear")
    alpha = 0.7
    machine = mc.Machine([CYLINDER.replace(pressure=diagram, phase=alpha)], shaft_inertia=0.3, strokes=4)
    table = mc.torque_orders(machine, RPM, max_order=3)
    kinks = np.mod(np.concatenate([angle, np.arange(5) * math.pi]) - alpha, 4 * math.pi)
    edges = np.unique(np.concatenate([[0.0, 4 * math.pi], kinks]))

    def gas(phi):
        return float(machine.gas_torque(phi))

    def coefficient(order, weight):
        if order == 0:
            total = sum(quad(gas, a, b, epsabs=1e-9, epsrel=1e-12)[0] for a, b in itertools.pairwise(edges))
            return total / (4 * math.pi)
        options = {"weight": weight, "wvar": order, "epsabs": 1e-9, "epsrel": 1e-12}
        return sum(quad(gas, a, b, **options)[0] for a, b in itertools.pairwise(edges)) / (2 * math.pi)

    scale = table["gas_amplitude"].max()
    for order in (0.0, 0.5, 1.0, 2.5):
        assert table.loc[order, "gas_cos"] == pytest.approx(coefficient(order, "cos"), abs=1e-11 * scale)
        if order:
            assert table.loc[order, "gas_sin"] == pytest.approx(coefficient(order, "sin"), abs=1e-11 * scale)


def test_mean_gas_torque_is_the_indicated_work_per_cycle():
    bare = mc.Machine([CYLINDER], shaft_inertia=0.3, strokes=4)
    area = CYLINDER.piston_area

    def volume(theta):
        return 5e-5 + area * bare.piston_travel(np.asarray(theta))[0]

    diagram = mc.IndicatorDiagram.engine(volume, intake_pressure=1.0e5, heat_release=600.0)
    machine = bare.replace(cylinders=[CYLINDER.replace(pressure=diagram)])
    table = mc.torque_orders(machine, RPM)
    work = diagram.indicated_work(volume)
    assert work > 100.0
    assert table.loc[0.0, "gas_cos"] == pytest.approx(work / (4 * math.pi), rel=1e-9)
    assert table.loc[0.0, "total_cos"] == pytest.approx(work / (4 * math.pi), rel=1e-9)


def test_table_layout_amplitude_phase_and_attrs():
    table = mc.torque_orders(twin(), RPM, max_order=4)
    assert table.index.name == "order"
    assert list(table.columns) == [f"{p}_{k}" for p in ORDER_PARTS for k in ("cos", "sin", "amplitude", "phase")]
    for part in ORDER_PARTS:
        cos, sin = table[f"{part}_cos"], table[f"{part}_sin"]
        np.testing.assert_allclose(table[f"{part}_amplitude"] * np.cos(table[f"{part}_phase"]), cos, atol=1e-12)
        np.testing.assert_allclose(table[f"{part}_amplitude"] * np.sin(table[f"{part}_phase"]), sin, atol=1e-12)
    total = table["gas_cos"] + table["inertia_cos"] + table["gravity_cos"]
    np.testing.assert_array_equal(table["total_cos"], total)
    assert table.attrs["rpm"] == RPM and table.attrs["omega"] == pytest.approx(OMEGA) and table.attrs["strokes"] == 4
    assert table.attrs["units"]["gas_cos"] == "N·m" and table.attrs["units"]["total_phase"] == "rad"
    no_gravity = mc.torque_orders(twin(), RPM, max_order=4, gravity=False)
    assert np.all(no_gravity.filter(like="gravity_").to_numpy() == 0.0)
    np.testing.assert_array_equal(no_gravity["gas_cos"], table["gas_cos"])


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ({"rpm": 0.0}, "rpm = 0.0 is out of range"),
        ({"rpm": math.nan}, "rpm"),
        ({"max_order": 0}, "max_order = 0 is out of range"),
        ({"max_order": 2.5}, "max_order must be an integer"),
        ({"gravity": "no"}, "gravity must be True or False"),
        ({"machine": "engine"}, "machine must be a multicrank.Machine"),
    ],
    ids=repr,
)
def test_bad_input_names_the_parameter(arguments, message):
    arguments = {"machine": twin(), "rpm": RPM, **arguments}
    with pytest.raises(mc.MechanismError, match=message):
        mc.torque_orders(arguments.pop("machine"), arguments.pop("rpm"), **arguments)


def test_a_thousand_orders_need_memory_in_proportion_to_the_work_and_are_the_fft():
    """max_order=1000 formed an orders × nodes matrix (the nodes grow with the orders):
    3.4 GB. Now its memory is that of the nodes. Its values against an FFT of the torques
    sampled densely over the cycle (each part is analytic here, so the FFT is exact to
    rounding), to 1e-12 of the largest amplitude."""
    import tracemalloc

    machine = twin()
    tracemalloc.start()
    try:
        table = mc.torque_orders(machine, RPM, max_order=1000)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 200e6, f"{peak / 1e6:.0f} MB"
    samples = 8192
    phi = np.arange(samples) * machine.cycle / samples
    torques = {
        "gas": machine.gas_torque(phi),
        "inertia": machine.inertia_torque(phi, OMEGA),
        "gravity": machine.gravity_torque(phi),
    }
    torques["total"] = torques["gas"] + torques["inertia"] + torques["gravity"]
    harmonic = np.round(table.index.to_numpy() * machine.strokes / 2).astype(int)  # of the cycle
    assert harmonic[-1] == 2000 and len(table) == 2001
    largest = max(table[f"{part}_amplitude"].max() for part in ORDER_PARTS)
    for part, torque in torques.items():
        spectrum = np.fft.rfft(torque) * (2 / samples)
        spectrum[0] /= 2  # the mean
        np.testing.assert_allclose(table[f"{part}_cos"], spectrum.real[harmonic], rtol=0, atol=1e-12 * largest)
        np.testing.assert_allclose(table[f"{part}_sin"], -spectrum.imag[harmonic], rtol=0, atol=1e-12 * largest)


@pytest.mark.parametrize("max_order", [2**50, 2**62, 2**64 - 1])
def test_more_orders_than_memory_holds_are_refused_by_name(max_order):
    """A max_order whose quadrature nodes cannot be allocated is refused before any work
    (numpy's MemoryError or an overflow once; an abort in the core, unchecked)."""
    with pytest.raises(mc.MechanismError, match=r"^max_order = \d+ asks for"):
        mc.torque_orders(twin(), RPM, max_order=max_order)
