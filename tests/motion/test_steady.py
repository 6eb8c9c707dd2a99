"""Steady running (docs/theory.md, "Steady running"): mc.steady_state and mc.flywheel_inertia against oracles that
do not share the library's formulas — a constant-inertia problem solved in closed form with
mpmath, time integrations with SciPy's solve_ivp at rtol 1e-12 (the equation of motion written
out here, in time, from the machine's torques), adaptive quadrature of the period, and the
dimensionless δ_g (docs/theory.md, "Speed fluctuation due to gravity").

Accuracy measured on this code (max over the cases below, the references' own errors
included): smooth torques δ 1e-11, ω_m 2e-13; tabulated pressures (PCHIP and linear tables)
δ 7e-8, ω_m 3e-9; the power-law closed form against 40 cycles of time integration δ 7e-9,
ω_m 5e-10. The assertions keep a margin of 10–100 below the targets (smooth δ 1e-7, ω_m 1e-9;
tables δ 1e-3, ω_m 1e-7).
"""

from __future__ import annotations

import dataclasses
import math

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq, minimize_scalar

import multicrank as mc

TWO_PI = 2 * math.pi


# -- machines ------------------------------------------------------------------------------------


def smooth_pressure(theta):
    """A smooth periodic gauge pressure [Pa] that does work (its peak lags outer dead centre)."""
    return 8e5 * np.exp(4 * (np.cos(theta - 0.35) - 1)) - 0.2e5


def cylinder(**changes):
    base = dict(
        crank_radius=0.08,
        rod_length=0.28,
        piston_mass=3.0,
        rod_mass=2.0,
        rod_cg=0.19,
        bore=0.1,
        crank_mass=4.0,
        crank_cg_radius=0.04,
        counterweight_mass=3.0,
        counterweight_radius=0.06,
    )
    return mc.Cylinder(**{**base, **changes})


# Two-mass rod: I_k = m_k z_k (l − z_k) = 2·0.19·0.09 = 0.0342 kg·m²; below it ΔI < 0, above ΔI > 0.
SMOOTH_MACHINES = {
    "single, ΔI < 0": mc.Machine([cylinder(rod_inertia=0.005, pressure=smooth_pressure)], shaft_inertia=0.4),
    "single, ΔI > 0": mc.Machine([cylinder(rod_inertia=0.05, pressure=smooth_pressure)], shaft_inertia=0.4),
    # A 90° V: both rods on one crank pin, so α₁ = γ₀ − γ₁.
    "V twin": mc.Machine(
        [
            cylinder(inclination=math.pi / 4, pressure=smooth_pressure),
            cylinder(inclination=3 * math.pi / 4, phase=-math.pi / 2, rod_inertia=0.01, pressure=smooth_pressure),
        ],
        shaft_inertia=0.5,
    ),
    # A boxer: lying cylinders facing each other, throws 180° apart.
    "boxer": mc.Machine(
        [cylinder(inclination=0.0, pressure=smooth_pressure), cylinder(inclination=math.pi, pressure=smooth_pressure)],
        shaft_inertia=0.5,
    ),
}


def _volume(theta):
    """V(θ) [m³] of `cylinder()`: clearance plus A·s(θ), s from the machine's own kinematics."""
    area = math.pi * 0.1**2 / 4
    travel = mc.Machine([cylinder()], shaft_inertia=1.0).piston_travel(np.asarray(theta, dtype=float))[0]
    return area * 0.16 / 12 + area * travel


def tabulated_machines():
    compressor = mc.IndicatorDiagram.compressor(_volume, suction_pressure=1e5, discharge_pressure=6e5)
    coarse = mc.IndicatorDiagram.compressor(
        _volume, suction_pressure=1e5, discharge_pressure=6e5, points=145, kind="linear"
    )
    engine = mc.IndicatorDiagram.engine(_volume, intake_pressure=1e5, heat_release=600.0)
    return {
        "compressor, PCHIP": mc.Machine(
            [cylinder(pressure=compressor), cylinder(phase=math.pi / 2, inclination=0.0, pressure=compressor)],
            shaft_inertia=0.6,
        ),
        "compressor, linear": mc.Machine(
            [cylinder(pressure=coarse), cylinder(phase=math.pi / 2, inclination=0.0, pressure=coarse)],
            shaft_inertia=0.6,
        ),
        "four-stroke engine, PCHIP": mc.Machine(
            [cylinder(pressure=engine), cylinder(phase=TWO_PI, pressure=engine)], shaft_inertia=0.3, strokes=4
        ),
    }


# -- the independent reference: the equation of motion in time ---------------------------------


def integrate_in_time(machine, omega0, *, load=0.0, drive=None, cycles=1, rtol=1e-12):
    """φ(t), ω(t) from φ = 0, ω = omega0 by solve_ivp (DOP853) of J φ̈ = M_gas − U' − ½J'φ̇² + drive −
    load. Returns the last cycle's period, its ω extremes (dense output, polished by a bounded
    minimiser) and ω at its end."""
    cycle = machine.cycle

    def rates(t, y):
        phi, omega = y
        at = np.array([phi])
        J, slope = machine.reduced_inertia(at)
        torque = machine.gas_torque(at)[0] + machine.gravity_torque(at)[0] - 0.5 * slope[0] * omega**2
        torque += drive(phi, omega) if drive is not None else 0.0
        torque -= load(phi, omega) if callable(load) else load
        return [omega, torque / J[0]]

    def turn(t, y):
        return y[0] - cycle * round(y[0] / cycle) if y[0] > 0.5 * cycle else -1.0

    turn.direction = 1

    def done(t, y):
        return y[0] - cycles * cycle

    done.terminal, done.direction = True, 1
    scale = cycle / omega0
    run = solve_ivp(
        rates,
        (0.0, 10 * cycles * scale),
        [0.0, omega0],
        method="DOP853",
        rtol=rtol,
        atol=[1e-14 * cycle, 1e-14 * omega0],
        events=[turn, done],
        dense_output=True,
    )
    ends = np.concatenate([[0.0], run.t_events[0]])
    assert ends.size == cycles + 1
    start, stop = ends[-2], ends[-1]
    times = np.linspace(start, stop, 20001)
    omega = run.sol(times)[1]
    extremes = []
    for sign in (1.0, -1.0):
        i = int(np.argmax(sign * omega))
        found = minimize_scalar(
            lambda t, sign=sign: -sign * run.sol(t)[1],
            bounds=(times[max(i - 1, 0)], times[min(i + 1, times.size - 1)]),
            method="bounded",
            options={"xatol": 1e-15 * stop},
        )
        extremes.append(sign * max(sign * omega[i], -found.fun))
    return {"period": stop - start, "omega_max": extremes[0], "omega_min": extremes[1], "omega_end": run.y[1, -1]}


def relative(a, b):
    return abs(a - b) / abs(b)


def check_against_time(result, reference, *, delta_tol, omega_tol):
    mean = result.cycle / reference["period"]
    delta = (reference["omega_max"] - reference["omega_min"]) / mean
    assert relative(result.omega_mean, mean) < omega_tol
    assert relative(result.delta, delta) < delta_tol
    # and the steady state is periodic: one cycle later the speed is back where it started
    assert relative(reference["omega_end"], result.omega[0]) < 10 * omega_tol


# -- the textbook flywheel problem, in closed form ------------------------------------------------


def pure_flywheel(inertia, strokes=2):
    """A machine that is a flywheel alone: one unit with no masses and no bore."""
    ghost = mc.Cylinder(crank_radius=0.1, rod_length=0.4, piston_mass=0, rod_mass=0, rod_cg=0)
    return mc.Machine([ghost], shaft_inertia=inertia, strokes=strokes)


def textbook_drive(phi, omega):
    return 1000 + 300 * np.sin(2 * phi) - 500 * np.cos(2 * phi)


def test_textbook_flywheel_in_closed_form():
    # M = 1000 + 300 sin 2θ − 500 cos 2θ against the constant load 1000 N·m on I = 64 kg·m²:
    # K(θ) = ∫(M − 1000) = 150(1 − cos 2θ) − 250 sin 2θ = 150 − A cos(2θ − β), A = √(150² + 250²),
    # tan β = 250/150, so ΔE = 2A = √(300² + 500²) J; ω² = ω₀² + 2K/I, and ω₀ gives the time mean
    # 2π/∫dθ/ω = 250 rpm (mpmath, 30 digits).
    inertia, rpm = 64, 250
    result = mc.steady_state(pure_flywheel(inertia), rpm=rpm, drive=textbook_drive)

    mpmath.mp.dps = 30
    A, beta = mpmath.sqrt(150**2 + 250**2), mpmath.atan2(250, 150)

    def K(theta):
        return 150 - A * mpmath.cos(2 * theta - beta)

    def mean_speed(w0sq):
        period = mpmath.quad(lambda t: 1 / mpmath.sqrt(w0sq + 2 * K(t) / inertia), mpmath.linspace(0, 2 * mpmath.pi, 5))
        return 2 * mpmath.pi / period

    omega_mean = mpmath.mpf(rpm) * mpmath.pi / 30
    w0sq = mpmath.findroot(lambda x: mean_speed(x) - omega_mean, omega_mean**2)
    omega_max = mpmath.sqrt(w0sq + 2 * (150 + A) / inertia)
    omega_min = mpmath.sqrt(w0sq + 2 * (150 - A) / inertia)

    assert result.method == "energy" and result.mean_load_torque == pytest.approx(1000, rel=1e-13)
    swing = 0.5 * inertia * (result.omega_max**2 - result.omega_min**2)
    assert swing == pytest.approx(math.hypot(300, 500), rel=1e-12)
    assert result.delta == pytest.approx(float((omega_max - omega_min) / omega_mean), rel=1e-12)
    assert result.delta_midrange == pytest.approx(
        float(2 * (omega_max - omega_min) / (omega_max + omega_min)), rel=1e-12
    )
    assert result.omega_mean == pytest.approx(float(omega_mean), rel=1e-14)
    assert result.phi_min == pytest.approx(float(beta / 2), abs=1e-7)
    assert result.phi_max == pytest.approx(float((beta + mpmath.pi) / 2), abs=1e-7)
    # The arrays: ω(φ) and t(φ) at every point, against the closed form and the quadrature.
    exact = [float(mpmath.sqrt(w0sq + 2 * K(t) / inertia)) for t in result.phi]
    np.testing.assert_allclose(result.omega, exact, rtol=1e-13)
    half = mpmath.quad(lambda t: 1 / mpmath.sqrt(w0sq + 2 * K(t) / inertia), [0, mpmath.pi / 2, mpmath.pi])
    assert np.interp(math.pi, result.phi, result.time) == pytest.approx(float(half), rel=1e-12)
    assert result.time[-1] == pytest.approx(float(2 * mpmath.pi / omega_mean), rel=1e-14)
    assert result.delta_coasting == 0.0 and result.delta_without_gravity == result.delta


def test_a_callable_drive_under_balance_is_called_once_per_question():
    """The "balance" load beside a drive f(φ, ω) is the core's question: the callable is sampled once,
    held at ω_m (one call with every node at once, each ω the mean speed), for the solve and its
    two comparisons alike; only the arrays (the drive torque at their angles) call it again."""
    calls = []

    def counted(phi, omega):
        calls.append((np.size(phi), np.unique(omega)))
        return textbook_drive(phi, omega)

    rpm = 250
    result = mc.steady_state(pure_flywheel(64), rpm=rpm, drive=counted)
    assert result.method == "energy"
    assert len(calls) == 1 and calls[0][0] > 1000
    np.testing.assert_allclose(calls[0][1], [rpm * math.pi / 30], rtol=1e-15)
    result.delta_without_gravity, result.delta_coasting  # noqa: B018 (read: solved now)
    assert len(calls) == 1
    result.drive_torque  # noqa: B018
    assert len(calls) == 2 and calls[1][0] == result.phi.size


# -- steady state against time integration ---------------------------------------------------------


@pytest.mark.parametrize("rpm", [600, 3000])
@pytest.mark.parametrize("name", list(SMOOTH_MACHINES))
def test_smooth_machines_match_time_integration(name, rpm):
    machine = SMOOTH_MACHINES[name]
    result = mc.steady_state(machine, rpm=rpm)
    assert result.delta > 1e-3  # a fluctuation worth measuring
    reference = integrate_in_time(machine, result.omega[0], load=result.mean_load_torque)
    check_against_time(result, reference, delta_tol=1e-9, omega_tol=1e-11)


@pytest.mark.parametrize("name", ["compressor, PCHIP", "compressor, linear", "four-stroke engine, PCHIP"])
def test_tabulated_pressures_match_time_integration(name):
    machine = tabulated_machines()[name]
    result = mc.steady_state(machine, rpm=1500)
    reference = integrate_in_time(machine, result.omega[0], load=result.mean_load_torque)
    check_against_time(result, reference, delta_tol=1e-5, omega_tol=1e-8)


def test_gravity_changes_the_fluctuation_and_off_is_g_zero():
    machine = SMOOTH_MACHINES["V twin"]
    with_gravity = mc.steady_state(machine, rpm=600)
    without = mc.steady_state(machine, rpm=600, gravity=False)
    zero_g = mc.steady_state(machine.replace(g=0.0), rpm=600)
    for name in SteadyStateArrays:
        np.testing.assert_array_equal(getattr(without, name), getattr(zero_g, name))
    assert without.delta == zero_g.delta
    assert with_gravity.delta_without_gravity == pytest.approx(zero_g.delta, rel=1e-14)
    assert not np.any(without.gravity_torque) and np.any(with_gravity.gravity_torque)
    # gravity matters here (heavy parts at a low speed) and the result says by how much
    assert abs(with_gravity.gravity_effect) > 1e-3  # more than 0.1 %
    assert with_gravity.gravity_effect == with_gravity.delta / zero_g.delta - 1


SteadyStateArrays = mc.SteadyState.ARRAYS


# -- the square-law load: closed form, shooting, long time integration ----------------------------


def test_power_law_closed_form_is_the_periodic_orbit_of_a_long_run():
    machine = mc.Machine(
        [cylinder(pressure=smooth_pressure), cylinder(phase=math.pi, inclination=0.3, pressure=smooth_pressure)],
        shaft_inertia=0.5,
    )
    load = mc.PowerLawLoad(torque=300.0, rpm=150.0 * 30 / math.pi)
    result = mc.steady_state(machine, load=load)
    assert result.method == "closed form"
    # Start 1e-4 off the orbit: after 40 cycles the disturbance has decayed by e^{−40·A(Φ)} ≈ 2e-5
    # of itself (A(Φ) = ∫2c/J ≈ 0.27).
    reference = integrate_in_time(
        machine, result.omega[0] * 1.0001, load=lambda phi, w: load.coefficient * w * abs(w), cycles=40
    )
    check_against_time(result, reference, delta_tol=1e-6, omega_tol=1e-8)
    # In steady state the load's mean takes the mean of the gas torque, whatever the speed.
    phi = np.linspace(0, TWO_PI, 200_001)
    assert result.mean_load_torque == pytest.approx(np.trapezoid(machine.gas_torque(phi), phi) / TWO_PI, rel=1e-8)
    assert result.mean_load_torque == pytest.approx(np.mean(result.load_torque[:-1]), rel=1e-2)


def test_shooting_agrees_with_the_closed_form():
    # The same square law as a callable: the general route (solve_ivp shooting) must find the
    # orbit the closed form gives.
    machine = mc.Machine([cylinder(pressure=smooth_pressure, rod_inertia=0.01)], shaft_inertia=0.4)
    law = mc.PowerLawLoad(torque=100.0, rpm=100.0 * 30 / math.pi)
    closed = mc.steady_state(machine, load=law)
    shot = mc.steady_state(machine, load=lambda phi, omega: law.coefficient * omega * np.abs(omega))
    assert (closed.method, shot.method) == ("closed form", "shooting")
    assert shot.omega_mean == pytest.approx(closed.omega_mean, rel=1e-10)
    assert shot.delta == pytest.approx(closed.delta, rel=1e-8)
    assert shot.delta_without_gravity == pytest.approx(closed.delta_without_gravity, rel=1e-8)
    assert shot.mean_load_torque == pytest.approx(closed.mean_load_torque, rel=1e-9)
    np.testing.assert_allclose(shot.omega, closed.omega, rtol=1e-9)
    np.testing.assert_allclose(shot.time, closed.time, rtol=1e-9, atol=1e-14)


# -- the machine coasting, and δ_g ------------------------------------------------------------------


@pytest.mark.parametrize("g", [mc.STANDARD_GRAVITY, 0.0])
def test_delta_coasting_is_the_machine_coasting_in_time(g):
    # δ_coasting is δ of the machine with gas, drive and load removed, at the same mean speed:
    # J(φ)'s variation and gravity together, so with g = 0 it is not 0. The reference: the
    # equation of motion of the machine without its pressures, integrated in time (DOP853),
    # shooting on ω(0) until one cycle takes Φ/ω_m.
    machine = SMOOTH_MACHINES["V twin"].replace(g=g)
    state = mc.steady_state(machine, rpm=300)
    coasting = machine.replace(cylinders=[c.replace(pressure=None) for c in machine.cylinders])
    period = machine.cycle / state.omega_mean
    start = brentq(
        lambda w0: integrate_in_time(coasting, w0, rtol=1e-11)["period"] - period,
        0.9 * state.omega_mean,
        1.1 * state.omega_mean,
        xtol=1e-13 * state.omega_mean,
    )
    reference = integrate_in_time(coasting, start, rtol=1e-11)
    delta = (reference["omega_max"] - reference["omega_min"]) * reference["period"] / machine.cycle
    assert state.delta_coasting == pytest.approx(delta, rel=1e-8)
    assert state.delta_coasting > 0.01  # J(φ) alone shakes the shaft: not gravity's
    # and it is the steady state of the machine without gas (the balance load then 0)
    assert mc.steady_state(coasting, rpm=300).delta == pytest.approx(state.delta_coasting, rel=1e-10)
    with pytest.warns(
        DeprecationWarning, match="SteadyState.delta_gravity_only is deprecated .* use SteadyState.delta_coasting"
    ):
        assert state.delta_gravity_only == state.delta_coasting


def test_coasting_tends_to_delta_g_when_J_is_constant():
    # Crank webs and counterweights only: gravity acts, J = I_w is constant, and with I_w large
    # the exact δ of the conservative machine tends to δ_g = max U* − min U* (docs/theory.md).
    unit = mc.Cylinder(
        crank_radius=0.1, rod_length=0.4, piston_mass=0, rod_mass=0, rod_cg=0, crank_mass=20.0, crank_cg_radius=0.08
    )
    machine = mc.Machine([unit, unit.replace(phase=2.0, inclination=0.3)], shaft_inertia=1.0)
    errors = []
    for inertia in (1.0, 10.0, 100.0, 1000.0):
        sized = machine.replace(shaft_inertia=inertia)
        result = mc.steady_state(sized, rpm=200)
        delta_g = float(sized.engine(200).speed_fluctuation())
        errors.append(abs(result.delta_coasting / delta_g - 1))
    assert errors == sorted(errors, reverse=True)  # it converges …
    assert errors[-1] < 1e-5 < errors[0]  # … as δ_g², the next order


def test_coasting_with_variable_J_is_the_range_of_the_pseudo_potential():
    # With reciprocating masses J varies, and for a heavy shaft ln ω = ½ ln 2(E − ΔU) − ½ ln J gives
    # δ → range[U + ½ ω_m² (J − I_w)]/(I_w ω_m²): the J-variation counts as much as gravity.
    machine = SMOOTH_MACHINES["V twin"]
    phi = np.linspace(0, TWO_PI, 400_001)
    ratios = []
    for inertia in (10.0, 1000.0):
        sized = machine.replace(shaft_inertia=inertia)
        omega = 300 * math.pi / 30
        result = mc.steady_state(sized, rpm=300)
        pseudo = sized.potential_energy(phi) + 0.5 * omega**2 * (sized.reduced_inertia(phi)[0] - inertia)
        ratios.append(result.delta_coasting / (np.ptp(pseudo) / (inertia * omega**2)))
    assert abs(ratios[1] - 1) < 1e-4 < abs(ratios[0] - 1)


# -- stall ----------------------------------------------------------------------------------------


HEAVY = mc.Machine(
    [
        mc.Cylinder(
            crank_radius=0.1,
            rod_length=0.35,
            piston_mass=20.0,
            rod_mass=8.0,
            rod_cg=0.25,
            crank_mass=5,
            crank_cg_radius=0.05,
        )
    ],
    shaft_inertia=0.2,
)


def test_a_heavy_machine_at_a_crawl_stalls_and_says_where_and_how_fast_it_runs():
    with pytest.raises(mc.StallError) as caught:
        mc.steady_state(HEAVY, rpm=20)
    error = caught.value
    assert isinstance(error, mc.MechanismError)
    # It crawls where the potential energy is highest (gravity alone on an upright unit).
    phi = np.linspace(0, TWO_PI, 100_001)
    assert error.angle == pytest.approx(phi[np.argmax(HEAVY.potential_energy(phi))], abs=1e-4)
    assert 20 < error.min_rpm < 60 and "min_rpm" in str(error)
    # Just above min_rpm it runs, with its speed minimum at min_speed_ratio of the mean …
    result = mc.steady_state(HEAVY, rpm=error.min_rpm * (1 + 1e-7))
    assert result.omega_min / result.omega_mean == pytest.approx(1e-3, rel=1e-5)
    # … and its period is right even so (adaptive quadrature of ∫ √(J/2E) dφ as the oracle).
    U0 = HEAVY.potential_energy(0.0)
    E0 = 0.5 * HEAVY.reduced_inertia(0.0)[0] * result.omega[0] ** 2

    def slowness(p):
        return math.sqrt(HEAVY.reduced_inertia(p)[0] / (2 * (E0 - (HEAVY.potential_energy(p) - U0))))

    period = quad(slowness, 0, TWO_PI, points=[result.phi_min], limit=400, epsabs=0, epsrel=1e-12)[0]
    assert result.period == pytest.approx(period, rel=1e-9)
    # … and just below it stalls; a smaller ratio lets it crawl slower.
    with pytest.raises(mc.StallError):
        mc.steady_state(HEAVY, rpm=error.min_rpm * (1 - 1e-4))
    assert mc.steady_state(HEAVY, rpm=error.min_rpm * 0.9, min_speed_ratio=1e-5).omega_min > 0


@pytest.mark.parametrize("route", ["closed form", "shooting"])
def test_a_load_too_strong_at_low_speed_stalls_the_machine(route):
    # 2 N·m of drive against c·ω² balance at 10 rad/s, where ½Jω² ≈ 13 J cannot lift the
    # heavy parts (ΔU ≈ 60 J) over the top: no periodic solution with a positive speed.
    law = mc.PowerLawLoad(torque=0.5, rpm=5.0 * 30 / math.pi)
    load = law if route == "closed form" else (lambda phi, omega: law.coefficient * omega * np.abs(omega))
    with pytest.raises(mc.StallError, match="stalls with this load") as caught:
        mc.steady_state(HEAVY, load=load, drive=2.0)
    assert caught.value.min_rpm is None
    # It stops short of the top, where the potential energy is highest (φ = 0).
    assert math.cos(caught.value.angle) > 0.9


# -- the flywheel ---------------------------------------------------------------------------------


def test_flywheel_inertia_gives_the_delta_asked_for():
    machine = tabulated_machines()["four-stroke engine, PCHIP"]
    found = mc.flywheel_inertia(machine, delta=0.02, rpm=1500)
    assert float(found) == found.shaft_inertia > 0
    check = mc.steady_state(machine.replace(shaft_inertia=found.shaft_inertia), rpm=1500)
    assert check.delta == pytest.approx(0.02, rel=1e-6)
    plain = mc.steady_state(machine.replace(shaft_inertia=found.shaft_inertia_without_gravity, g=0.0), rpm=1500)
    assert plain.delta == pytest.approx(0.02, rel=1e-6)
    assert "kg·m²" in repr(found)


def test_flywheel_for_a_square_law_load_at_the_speed_it_settles_to():
    machine = mc.Machine(
        [cylinder(pressure=smooth_pressure), cylinder(phase=math.pi, inclination=0.3, pressure=smooth_pressure)],
        shaft_inertia=0.5,
    )
    load = mc.PowerLawLoad(torque=300.0, rpm=150.0 * 30 / math.pi)
    found = mc.flywheel_inertia(machine, delta=0.01, load=load)
    check = mc.steady_state(machine.replace(shaft_inertia=found.shaft_inertia), load=load)
    assert check.delta == pytest.approx(0.01, rel=1e-6) and found.rpm == pytest.approx(check.rpm, rel=1e-9)
    # The textbook estimate takes every torque at the constant mean speed, the square law's
    # too, and the inertia torque of the rods and pistons with them: first-order right here
    # as well (without the inertia torque it asked for over 50 % too much flywheel).
    assert abs(found.textbook_error) < 0.05
    with pytest.raises(mc.MechanismError, match="rpm = 700 is not allowed"):
        mc.flywheel_inertia(machine, delta=0.01, load=load, rpm=700)


def test_flywheel_for_a_load_solved_by_shooting_is_the_closed_forms():
    # The square law as a callable takes the general route: the core's flywheel search over
    # shot steady states (solve_ivp), the textbook estimate from the core with the load at the
    # mean speed crossing as a table. The closed form answers the same question independently:
    # the same I_w to the shooting's accuracy (~1e-11 seen).
    machine = mc.Machine(
        [cylinder(pressure=smooth_pressure), cylinder(phase=math.pi, inclination=0.3, pressure=smooth_pressure)],
        shaft_inertia=0.5,
    )
    law = mc.PowerLawLoad(torque=300.0, rpm=150.0 * 30 / math.pi)
    closed = mc.flywheel_inertia(machine, delta=0.01, load=law)
    shot = mc.flywheel_inertia(machine, delta=0.01, load=lambda phi, omega: law.coefficient * omega * np.abs(omega))
    assert (closed.method, shot.method) == ("closed form", "shooting")
    assert shot.shaft_inertia == pytest.approx(closed.shaft_inertia, rel=1e-9)
    assert shot.shaft_inertia_without_gravity == pytest.approx(closed.shaft_inertia_without_gravity, rel=1e-9)
    assert shot.rpm == pytest.approx(closed.rpm, rel=1e-9)
    assert shot.textbook == pytest.approx(closed.textbook, rel=1e-8)
    assert shot.energy_swing == pytest.approx(closed.energy_swing, rel=1e-8)


def test_flywheel_for_a_drive_that_varies_over_the_cycle_by_shooting():
    # A drive D + a·sin φ beside a square law: the general route. The flywheel gives the δ asked
    # for, and its ΔE is the swing of the turning-moment diagram at the mean speed reached,
    # ∫(M_gas + M_drive − M_load − ½J′ω_m² − mean) dφ, summed here on a dense grid.
    machine = mc.Machine(
        [cylinder(pressure=smooth_pressure), cylinder(phase=math.pi, inclination=0.3, pressure=smooth_pressure)],
        shaft_inertia=0.5,
    )
    law = mc.PowerLawLoad(torque=300.0, rpm=150.0 * 30 / math.pi)
    drive = lambda phi, omega: 100.0 + 150.0 * np.sin(phi)  # noqa: E731
    found = mc.flywheel_inertia(machine, delta=0.02, load=law, drive=drive, gravity=False)
    assert found.method == "shooting" and found.shaft_inertia_without_gravity == found.shaft_inertia
    check = mc.steady_state(machine.replace(shaft_inertia=found.shaft_inertia), load=law, drive=drive, gravity=False)
    assert check.delta == pytest.approx(0.02, rel=1e-6) and found.rpm == pytest.approx(check.rpm, rel=1e-9)
    omega = found.rpm * math.pi / 30
    phi = np.linspace(0.0, TWO_PI, 400_001)
    torque = machine.gas_torque(phi) + drive(phi, omega) + machine.inertia_torque(phi, omega)
    diagram = np.concatenate([[0.0], np.cumsum(0.5 * (torque[1:] + torque[:-1]) * np.diff(phi))])
    diagram -= diagram[-1] * phi / TWO_PI  # less the constant load that balances the cycle
    assert found.energy_swing == pytest.approx(np.ptp(diagram), rel=1e-7)


def test_textbook_estimate_is_first_order_in_delta():
    # For a pure flywheel the textbook I = ΔE/(δ ω_m²) is exact to first order: its error is O(δ).
    machine = pure_flywheel(1.0)
    errors = [
        abs(mc.flywheel_inertia(machine, delta=delta, rpm=250, drive=textbook_drive).textbook_error)
        for delta in (1e-2, 1e-3)
    ]
    assert errors[1] < 2e-3 and errors[1] < errors[0] / 5
    found = mc.flywheel_inertia(machine, delta=1e-3, rpm=250, drive=textbook_drive)
    assert found.energy_swing == pytest.approx(math.hypot(300, 500), rel=1e-12)
    assert found.shaft_inertia_without_gravity == found.shaft_inertia  # no masses: no gravity


def test_a_delta_the_machine_cannot_reach_is_refused_naming_delta():
    # At 40 rpm the heavy machine stalls on a shaft lighter than ~0.1 kg·m², where δ ≈ 6.5.
    with pytest.raises(mc.MechanismError, match=r"delta = 8.0 is unreachable at this speed: the machine stalls"):
        mc.flywheel_inertia(HEAVY, delta=8.0, rpm=40)
    # Without gravity nothing but the variation of J shakes it, and that is bounded (≈ 0.94)
    # however light the shaft.
    with pytest.raises(mc.MechanismError, match=r"delta = 3.0 is unreachable: even a massless shaft"):
        mc.flywheel_inertia(HEAVY, delta=3.0, rpm=40, gravity=False)
    # With gravity δ = 3 is reached; without it, not: the answer says so with NaN.
    found = mc.flywheel_inertia(HEAVY, delta=3.0, rpm=40)
    assert found.shaft_inertia > 0 and math.isnan(found.shaft_inertia_without_gravity)


# -- properties ---------------------------------------------------------------------------------


@settings(max_examples=15, deadline=None)
@given(
    inertia=st.floats(0.2, 20.0),
    factor=st.floats(1.1, 4.0),
    rpm=st.floats(300.0, 3000.0),
)
def test_delta_falls_as_the_shaft_inertia_grows(inertia, factor, rpm):
    machine = SMOOTH_MACHINES["single, ΔI < 0"]
    light = mc.steady_state(machine.replace(shaft_inertia=inertia), rpm=rpm)
    heavy = mc.steady_state(machine.replace(shaft_inertia=inertia * factor), rpm=rpm)
    assert heavy.delta < light.delta


@settings(max_examples=15, deadline=None)
@given(level=st.floats(1e-3, 0.3), scale=st.floats(0.1, 10.0), rpm=st.floats(100.0, 3000.0))
def test_pure_flywheel_delta_depends_only_on_amplitude_over_inertia_omega_squared(level, scale, rpm):
    # ω² = ω₀² + 2K/I: δ is a function of a/(I ω_m²) alone. Scale I by s, or ω_m by √s, with a × s.
    amplitude = level * (rpm * math.pi / 30) ** 2  # a/(I ω_m²) = level, well clear of a stall

    def drive(amplitude):
        return lambda phi, omega: amplitude * np.sin(3 * phi)

    base = mc.steady_state(pure_flywheel(1.0), rpm=rpm, drive=drive(amplitude))
    heavier = mc.steady_state(pure_flywheel(scale), rpm=rpm, drive=drive(amplitude * scale))
    faster = mc.steady_state(pure_flywheel(1.0), rpm=rpm * math.sqrt(scale), drive=drive(amplitude * scale))
    assert heavier.delta == pytest.approx(base.delta, rel=1e-10)
    assert faster.delta == pytest.approx(base.delta, rel=1e-10)


# -- the result ----------------------------------------------------------------------------------


def test_the_result_is_a_frozen_closed_cycle_with_consistent_torques():
    machine = tabulated_machines()["four-stroke engine, PCHIP"]
    result = mc.steady_state(machine, rpm=2000, points=1441)
    assert result.phi.shape == (1441,) and result.phi[0] == 0 and result.phi[-1] == 4 * math.pi
    assert result.time[0] == 0 and result.time[-1] == result.period and np.all(np.diff(result.time) > 0)
    assert result.omega[-1] == pytest.approx(result.omega[0], rel=1e-12)
    assert result.omega_min <= result.omega.min() and result.omega.max() <= result.omega_max
    assert result.rpm == pytest.approx(2000, rel=1e-14)
    # Energy: ½Jω² grows by the work of the torques (trapezoid on the output grid, loosely).
    energy = 0.5 * result.reduced_inertia * result.omega**2
    net = result.gas_torque + result.gravity_torque + result.drive_torque - result.load_torque
    work = np.concatenate([[0], np.cumsum(0.5 * (net[1:] + net[:-1]) * np.diff(result.phi))])
    potential = machine.potential_energy(result.phi) - machine.potential_energy(0.0)
    assert np.max(np.abs(energy - energy[0] - work)) < 1e-3 * np.ptp(energy)
    assert np.max(np.abs(potential + result.gravity_torque * 0)) >= 0  # the gravity arrays are the machine's
    np.testing.assert_allclose(result.gravity_torque, machine.gravity_torque(result.phi))
    # J φ̈ = the sum of the torques, inertia included; φ̈ = ω dω/dφ.
    slope = np.gradient(result.omega, result.phi)
    assert np.max(np.abs(result.acceleration - result.omega * slope)) < 1e-2 * np.max(np.abs(result.acceleration))
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.omega_mean = 1.0
    with pytest.raises(ValueError, match="read-only"):
        result.omega[0] = 1.0
    frame = result.to_pandas()
    assert frame.index.name == "phi" and len(frame) == 1441
    assert {"omega", "time", "rpm", "gas_torque", "load_torque", "reduced_inertia"} <= set(frame.columns)
    text = repr(result)
    assert "δ" in text and "2000 rpm" in text and "midrange" in text


# -- bad inputs ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("keywords", "match"),
    [
        ({}, "rpm is required"),
        ({"rpm": 0.0}, "rpm = 0.0 is out of range"),
        ({"rpm": math.nan}, "rpm"),
        ({"rpm": -5}, "rpm"),
        ({"rpm": 100, "load": mc.PowerLawLoad(10.0, rpm=10.0 * 30 / math.pi)}, "rpm = 100 is not allowed"),
        ({"load": 5.0}, "load = 5.0 is a constant torque"),
        ({"load": None, "drive": 3.0}, "load = None is a constant torque"),
        ({"load": mc.PowerLawLoad(0.0, rpm=10.0 * 30 / math.pi)}, "load"),
        ({"load": mc.PowerLawLoad(10.0, rpm=10.0 * 30 / math.pi), "drive": -1e4}, "drive"),
        ({"rpm": 100, "load": "fast"}, "load = 'fast'"),
        ({"rpm": 100, "drive": "balance"}, "drive = 'balance'"),
        ({"rpm": 100, "min_speed_ratio": 0.0}, "min_speed_ratio"),
        ({"rpm": 100, "min_speed_ratio": 1.0}, "min_speed_ratio"),
        ({"rpm": 100, "min_speed_ratio": math.nan}, "min_speed_ratio"),
        ({"rpm": 100, "points": 1}, "points"),
        ({"rpm": 100, "gravity": "yes"}, "gravity"),
    ],
)
def test_bad_inputs_name_the_parameter(keywords, match):
    with pytest.raises(mc.MechanismError, match=match):
        mc.steady_state(SMOOTH_MACHINES["single, ΔI < 0"], **keywords)


@pytest.mark.parametrize(("delta", "match"), [(0.0, "delta = 0.0"), (-0.1, "delta"), (math.nan, "delta")])
def test_flywheel_refuses_bad_delta(delta, match):
    with pytest.raises(mc.MechanismError, match=match):
        mc.flywheel_inertia(SMOOTH_MACHINES["single, ΔI < 0"], delta=delta, rpm=100)


def test_the_speed_defaults_to_the_machines_own():
    compressor = mc.presets.MACHINES["slow-compressor"]
    running = compressor.replace(rpm=120.0)
    assert mc.steady_state(running).delta == mc.steady_state(compressor, rpm=120).delta
    sized = mc.flywheel_inertia(running, delta=1 / 40)
    assert sized.shaft_inertia == mc.flywheel_inertia(compressor, delta=1 / 40, rpm=120).shaft_inertia
    with pytest.raises(mc.MechanismError, match="rpm = 120 is not allowed with this load"):
        mc.steady_state(running, rpm=120, load=mc.PowerLawLoad(90.0, rpm=120))
    fixed = mc.steady_state(running, load=mc.PowerLawLoad(90.0, rpm=120), drive=1000.0)  # the load's speed
    assert fixed.method == "closed form" and fixed.rpm != 120


def test_results_share_their_names_and_keep_the_old_ones():
    state = mc.steady_state(mc.presets.MACHINES["slow-compressor"], rpm=120, points=37)
    assert isinstance(state, mc.motion.MotionResult) and state.solved == "balance load (energy method)"
    for old, new in [("J", "reduced_inertia"), ("dJ_dphi", "reduced_inertia_slope"), ("torque_gas", "gas_torque"),
                     ("torque_gravity", "gravity_torque"), ("torque_inertia", "inertia_torque"),
                     ("torque_drive", "drive_torque"), ("torque_load", "load_torque"),
                     ("delta_gravity_only", "delta_coasting")]:  # fmt: skip
        with pytest.warns(DeprecationWarning, match=f"SteadyState.{old} is deprecated .* use SteadyState.{new}"):
            assert getattr(state, old) is getattr(state, new)
    np.testing.assert_array_equal(state.inertia_torque, state.machine.inertia_torque(state.phi, state.omega))
    frame = state.to_pandas()
    assert frame.attrs["units"]["rpm"] == "1/min" and frame.attrs["solved"] == state.solved
    np.testing.assert_array_equal(frame["load_torque"], state.load_torque)
    np.testing.assert_allclose(frame["rpm"], state.omega * 30 / math.pi, rtol=1e-15)
    sized = mc.flywheel_inertia(mc.presets.MACHINES["slow-compressor"], delta=1 / 40, rpm=120)
    row = sized.to_pandas()
    assert len(row) == 1 and row["shaft_inertia"].iloc[0] == float(sized) and row.attrs["units"]["rpm"] == "1/min"
    assert "energy method" in sized.solved


def test_results_convert_to_xarray_with_units():
    pytest.importorskip("xarray")  # an extra: the dependency floors run without it
    state = mc.steady_state(mc.presets.MACHINES["slow-compressor"], rpm=120, points=37)
    dataset = state.to_xarray()
    assert dataset["gas_torque"].attrs["units"] == "N·m" and dataset.attrs["mean_load_torque"] == state.mean_load_torque
    sized = mc.flywheel_inertia(mc.presets.MACHINES["slow-compressor"], delta=1 / 40, rpm=120)
    assert sized.to_xarray()["shaft_inertia"].attrs["units"] == "kg·m²"


def test_machine_must_be_a_machine():
    with pytest.raises(mc.MechanismError, match=r"machine must be a multicrank\.Machine"):
        mc.steady_state("V8", rpm=100)
