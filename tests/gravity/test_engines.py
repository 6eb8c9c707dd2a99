"""Engines of any layout: against first-principles geometry of V and boxer engines (every
mass's position, Σ m·g·h in mpmath), against the in-line results they reduce to, and the
tolerance analysis against Monte-Carlo."""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

import multicrank as mc
from multicrank.presets import LAYOUTS

mp.mp.dps = 40
G = mp.mpf("9.80665")


def physical_unit(r, l, zk, mt, mk):
    """u1, u2 of one cylinder (no web or counterweight) at I_w ω² = 1 (g folded in)."""
    return float(r * G * (mt + (l - zk) / l * mk)), float(G * r * zk / l * mk)


def oracle_energy(phi, throws, banks, r, l, zk, mt, mk, web=(0.0, 0.0)):
    """Σ m·g·h of every moving mass of an engine, each cylinder measured from its own outer
    dead centre, with I_w ω² = 1. Crank pin of throw t at absolute angle θ = φ + β_t; a
    cylinder with axis direction (cos γ, sin γ) has its piston pin at distance
    x = r cos(θ − γ) + √(l² − r² sin²(θ − γ)) along that axis; the rod's centre of gravity is
    z_k from the piston pin towards the crank pin. `web` = (mass·radius) of an unbalanced crank
    web per throw, in line with the pin, measured (like a unit with γ = 0) from the position
    where it points horizontally."""
    phi = mp.mpf(phi)
    total = mp.mpf(0)
    for beta, gammas in zip(throws, banks, strict=True):
        beta = mp.mpf(beta)
        for gamma in gammas:
            gamma = mp.mpf(gamma)

            def height(theta, gamma=gamma):
                pin = (r * mp.cos(theta), r * mp.sin(theta))
                x = r * mp.cos(theta - gamma) + mp.sqrt(l**2 - (r * mp.sin(theta - gamma)) ** 2)
                piston = (x * mp.cos(gamma), x * mp.sin(gamma))
                rod_cg = tuple(p + zk / l * (c - p) for p, c in zip(piston, pin, strict=True))
                return mt * piston[1] + mk * rod_cg[1]

            # This cylinder's own outer dead centre: the pin on its axis, θ = γ.
            total += G * (height(phi + beta) - height(gamma))
        total += G * web[0] * mp.sin(phi + beta)  # rotating web
    return total


def oracle_force(phi, *args, **kwargs):
    return mp.diff(lambda x: oracle_energy(x, *args, **kwargs), mp.mpf(phi))


GEOMETRY = dict(r=mp.mpf("0.045"), l=mp.mpf("0.15"), zk=mp.mpf("0.105"), mt=mp.mpf("0.5"), mk=mp.mpf("0.6"))


@pytest.mark.parametrize(
    "name",
    [
        "v-twin-45",
        "v-twin-90",
        "v6-60",
        "v8-cross",
        "v8-flat",
        "boxer-2",
        "boxer-4",
        "boxer-6",
        "v-180-2",
        "w12",
        "twin-270",
        "v12-60",
    ],
)
def test_layouts_against_first_principles(name):
    layout = LAYOUTS[name]
    throws = [mp.radians(mp.mpf(t)) for t in layout.throws]
    banks = [[mp.radians(mp.mpf(g)) for g in b] for b in layout.banks]
    u1, u2 = physical_unit(**GEOMETRY)
    engine = layout.engine(crank_ratio=float(GEOMETRY["r"] / GEOMETRY["l"]), u1=u1, u2=u2)
    phi = np.linspace(-2.0, 8.0, 23)
    energy = engine.potential_energy(phi)
    force = engine.generalized_force(phi)
    series = engine.generalized_force(phi, method="series")
    expected_u = np.array([float(oracle_energy(p, throws, banks, **GEOMETRY)) for p in phi])
    expected_q = np.array([float(oracle_force(p, throws, banks, **GEOMETRY)) for p in phi])
    scale = layout.cylinders * (abs(u1) + abs(u2))
    np.testing.assert_allclose(energy, expected_u, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(force, expected_q, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(series, expected_q, rtol=0, atol=1e-13 * scale)


def test_unbalanced_webs_and_unequal_cylinders_against_first_principles():
    """A V-twin whose two cylinders differ (another piston mass) plus an unbalanced crank web."""
    r, l, zk = GEOMETRY["r"], GEOMETRY["l"], GEOMETRY["zk"]
    gammas = [mp.radians(45), mp.radians(135)]
    beta = mp.radians(90)
    web = mp.mpf("0.03")  # kg·m of unbalance in line with the pin
    pistons = [mp.mpf("0.5"), mp.mpf("0.8")]
    units = [physical_unit(r, l, zk, m, GEOMETRY["mk"]) for m in pistons]
    engine = mc.Engine(
        phase=[float(beta - g) for g in gammas] + [float(beta)],
        inclination=[float(g) for g in gammas] + [0.0],  # the web: a rotating-only unit
        crank_ratio=float(r / l),
        u1=[units[0][0], units[1][0], 0.0],
        u2=[units[0][1], units[1][1], float(G * web)],
    )
    phi = np.linspace(0, 2 * np.pi, 17)
    expected = []
    for p in phi:
        total = oracle_energy(p, [beta], [[gammas[0]]], r, l, zk, pistons[0], GEOMETRY["mk"])
        total += oracle_energy(p, [beta], [[gammas[1]]], r, l, zk, pistons[1], GEOMETRY["mk"], web=(web, 0))
        expected.append(float(total))
    np.testing.assert_allclose(engine.potential_energy(phi), expected, rtol=0, atol=1e-14)


def test_vee_at_zero_bank_angle_is_inline_with_paired_throws():
    throws = mc.crank_phases(3, 4)
    vee = mc.Engine.from_throws(throws + np.pi / 2, [[np.pi / 2, np.pi / 2]] * 3, crank_ratio=0.3, u1=0.2, u2=0.05)
    inline = dict(crank_ratio=0.3, inclination=np.pi / 2, u1=0.4, u2=0.1, phases=throws)  # paired: twice the moments
    phi = np.linspace(-4, 4, 301)
    np.testing.assert_allclose(vee.generalized_force(phi), mc.generalized_force(phi, **inline), rtol=0, atol=1e-15)
    np.testing.assert_allclose(vee.potential_energy(phi), mc.potential_energy(phi, **inline), rtol=0, atol=1e-15)
    assert vee.speed_fluctuation() == pytest.approx(mc.speed_fluctuation(**inline), rel=1e-12, abs=1e-18)


@pytest.mark.parametrize("cranks, strokes", [(1, 2), (4, 4), (6, 4), (3, 2), (12, 2)])
def test_inline_layouts_match_the_inline_path(cranks, strokes):
    design = dict(crank_ratio=0.35, inclination=np.pi / 2, u1=0.3, u2=-0.1)
    engine = LAYOUTS[f"inline-{cranks}-{strokes}t"].engine(crank_ratio=0.35, u1=0.3, u2=-0.1)
    phases = mc.crank_phases(cranks, strokes)
    phi = np.linspace(0, 2 * np.pi, 97)
    np.testing.assert_allclose(
        engine.generalized_force(phi), mc.generalized_force(phi, phases=phases, **design), rtol=0, atol=1e-14 * cranks
    )
    a, b = engine.fourier_coefficients(24)
    a_inline, b_inline = mc.fourier_coefficients(phases=phases, n_max=24, **design)
    np.testing.assert_allclose(np.hypot(a, b), np.hypot(a_inline, b_inline), rtol=1e-12, atol=1e-15 * cranks)
    assert engine.surviving_harmonics(24) == [n for n in mc.surviving_harmonics(cranks, strokes, n_max=24)]
    assert engine.speed_fluctuation() == pytest.approx(
        mc.speed_fluctuation(phases=phases, **design), rel=1e-10, abs=1e-16
    )


def test_boxer_is_not_the_180_degree_vee():
    boxer = LAYOUTS["boxer-2"].engine(crank_ratio=0.3, u1=0.2, u2=0.05)
    vee = LAYOUTS["v-180-2"].engine(crank_ratio=0.3, u1=0.2, u2=0.05)
    # Opposed pistons of a boxer reach outer dead centre together; those of a 180° V alternate.
    np.testing.assert_allclose(boxer.phase % (2 * np.pi), [0.0, 0.0], atol=1e-15)
    assert abs(np.ptp(vee.phase)) == pytest.approx(np.pi)
    # Horizontal cylinders: only the rotating parts act; the boxer's pins are 180° apart and
    # cancel, the 180° V's shared pin does not.
    assert boxer.speed_fluctuation() < 1e-15
    assert vee.speed_fluctuation() == pytest.approx(4 * 0.05, rel=1e-12)


def test_fourier_coefficients_against_fft():
    engine = (
        LAYOUTS["v8-cross"]
        .engine(crank_ratio=0.3, u1=np.linspace(0.1, 0.2, 8), u2=0.02)
        .replace(phase=LAYOUTS["v8-cross"].engine(crank_ratio=0.3, u1=0.1, u2=0.02).phase + np.linspace(0, 0.01, 8))
    )
    grid = np.arange(2048) * (2 * np.pi / 2048)
    spectrum = np.fft.rfft(engine.generalized_force(grid)) * 2 / grid.size
    a, b = engine.fourier_coefficients(24)
    np.testing.assert_allclose(a[1:25], spectrum.real[1:25], rtol=0, atol=1e-14)
    np.testing.assert_allclose(b[1:25], -spectrum.imag[1:25], rtol=0, atol=1e-14)


def test_sensitivity_matches_monte_carlo():
    """Harmonics that cancel for identical cylinders come back with the predicted scatter."""
    nominal = LAYOUTS["inline-6-4t"].engine(crank_ratio=0.3, u1=0.01, u2=0.003)
    errors = dict(u1_rel=0.02, u2_rel=0.05, phase=0.003)
    predicted = nominal.harmonic_sensitivity(n_max=12, **errors)
    assert predicted.loc[1, "amplitude"] == 0 and predicted.loc[2, "amplitude"] == 0  # cancelled
    rng = np.random.default_rng(7)
    samples = []
    for _ in range(1500):
        a, b = nominal.perturbed(rng, **errors).fourier_coefficients(12)
        nominal_a, nominal_b = nominal.fourier_coefficients(12)
        samples.append(np.hypot(a - nominal_a, b - nominal_b))
    observed = np.sqrt(np.mean(np.square(samples), axis=0))
    for n in (1, 2, 4, 6, 8):
        assert observed[n] == pytest.approx(predicted.loc[n, "scatter_rms"], rel=0.1), n


def test_engine_errors():
    with pytest.raises(mc.MechanismError, match="crank_ratio"):
        mc.Engine(phase=[0, 1], inclination=0.0, crank_ratio=1.2, u1=1, u2=0)
    with pytest.raises(mc.MechanismError, match="phase"):
        mc.Engine(phase=[0, np.nan], inclination=0.0, crank_ratio=0.3, u1=1, u2=0)
    with pytest.raises(mc.MechanismError, match="broadcast"):
        mc.Engine(phase=[0, 1, 2], inclination=[0.0, 1.0], crank_ratio=0.3, u1=1, u2=0)
    with pytest.raises(mc.MechanismError, match="layout"):
        mc.layout_engine("v7", crank_ratio=0.3, u1=1, u2=0)
    with pytest.raises(mc.MechanismError, match="method"):
        mc.layout_engine("v8-flat", crank_ratio=0.3, u1=1, u2=0).generalized_force([0.0], method="paper")
    engine = mc.layout_engine("v8-flat", crank_ratio=0.3, u1=1, u2=0)
    assert engine.generalized_force(0.5).shape == () and engine.potential_energy(np.zeros((2, 3))).shape == (2, 3)


def test_monte_carlo_through_sweep_matches_first_order_prediction():
    """δ_g of an in-line six with unequal cylinders and phase errors, sampled through
    mc.sweep: its rms is dominated by the first harmonic that comes back, δ_g ≈ 2|c_1|, so
    rms(δ_g) ≈ 2·scatter_rms(n = 1)."""
    nominal = LAYOUTS["inline-6-4t"].engine(crank_ratio=0.3, u1=0.01, u2=0.003)
    errors = dict(u1_rel=0.02, u2_rel=0.05, phase=0.003)
    rng = np.random.default_rng(11)
    samples = [nominal.perturbed(rng, **errors) for _ in range(800)]
    result = mc.sweep(samples, phi=360, outputs=["energy_range", "leading_harmonic", "force_max_abs"])
    assert len(result) == 800 and (result["cylinders"] == 6).all()
    assert (result["leading_harmonic"] == 1).mean() > 0.95  # the cancelled first harmonic leads
    predicted = nominal.harmonic_sensitivity(n_max=4, **errors).loc[1, "scatter_rms"]
    observed = np.sqrt(np.mean(result["energy_range"] ** 2))
    assert observed == pytest.approx(2 * predicted, rel=0.1)
    assert nominal.speed_fluctuation() < 1e-3 * observed  # nominally balanced
    # One row agrees with the engine's own methods.
    first = samples[0]
    assert result["energy_range"].iloc[0] == first.speed_fluctuation()
    phi = np.arange(360) * (2 * np.pi / 360)
    assert result["force_max_abs"].iloc[0] == np.max(np.abs(first.generalized_force(phi)))


def test_physical_layout_counts_one_web_per_throw():
    """A V-twin from physical masses: two cylinders on one pin, one web and counterweight."""
    from multicrank.presets import MACHINES

    preset = MACHINES["inline-4"]
    machine = mc.Machine.from_layout(
        "v-twin-90", preset.cylinders[0], shaft_inertia=preset.shaft_inertia, rpm=preset.rpm
    )
    engine = machine.engine()
    # Two units, the web and counterweight on the first cylinder of the shared pin only.
    assert len(engine) == 2 and machine.cylinders[1].crank_mass == machine.cylinders[1].counterweight_mass == 0.0
    cylinder = machine.cylinders[0]
    r, l, zk = (mp.mpf(cylinder.crank_radius), mp.mpf(cylinder.rod_length), mp.mpf(cylinder.rod_cg))
    omega = mp.pi * mp.mpf(machine.rpm) / 30
    scale = mp.mpf(machine.shaft_inertia) * omega**2
    web = mp.mpf(cylinder.crank_mass) * mp.mpf(cylinder.crank_cg_radius) - mp.mpf(cylinder.counterweight_mass) * mp.mpf(
        cylinder.counterweight_radius
    )
    throws, banks = [mp.radians(90)], [[mp.radians(45), mp.radians(135)]]
    phi = np.linspace(0, 2 * np.pi, 13)
    expected = [
        float(
            oracle_energy(
                p, throws, banks, r, l, zk, mp.mpf(cylinder.piston_mass), mp.mpf(cylinder.rod_mass), web=(web, 0)
            )
            / scale
        )
        for p in phi
    ]
    # The web folded into the first cylinder is measured from that cylinder's outer dead centre,
    # the oracle's from where it points horizontally: the energies differ by one constant.
    energy = engine.potential_energy(phi)
    np.testing.assert_allclose(energy - energy[0], np.subtract(expected, expected[0]), rtol=0, atol=1e-15)
