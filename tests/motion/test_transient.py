"""mc.simulate (motion.md §4): the machine in time, against oracles that do not use its formulas.

- conservation of ½Jω² + U, with J and U recomputed from the returned angles, and once from the
  mass points of the mpmath oracle of tests/machine/test_machine_oracle.py (Σ ½ m v² + ½ I_w ω²);
- the periodic steady state under a square-law load, from the closed form of the linear equation
  for E = ½Jω² (motion.md §3) written out here with cumulative Simpson quadrature;
- a pure flywheel: φ(t) a parabola under a constant drive, and a stall at t = I ω₀ / M under a
  constant load; a machine that cannot climb over its top dead point stops where U(φ) = E₀;
- "balance": the constant load is the cycle mean (scipy.integrate.quad), and ½Jω² follows the
  energy integral at every sample.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from mpmath import mp, mpf
from scipy.integrate import cumulative_simpson, quad, simpson
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

import multicrank as mc
from tests.machine.test_machine_oracle import DPS, Spec, Unit, _x, unit_kinetic, unit_potential

TWO_PI = 2 * math.pi

# A heavy inclined unit on a light shaft: J varies by 30 % over a revolution and gravity
# changes the speed by a fifth (the unit of the mpmath oracle's "inclined-single-web-counterweight",
# on a shaft of 0.05 instead of 0.8 kg·m²).
SWING = Spec(
    (Unit(r=0.08, l=0.26, mt=2.2, mk=1.6, zk=0.18, ik=0.009, ms=3.1, rs=0.035, mp=2.4, rp=0.07, gamma=math.pi / 6),),
    iw=0.05,
)


def smooth_pressure(theta):
    """A smooth 2π-periodic gauge pressure [Pa]: the gas torque has no kink."""
    theta = np.asarray(theta, dtype=float)
    return 1e5 * (2.0 + np.sin(theta) + 0.3 * np.cos(2 * theta))


def gassed_machine(**machine):
    cylinder = mc.Cylinder(
        crank_radius=0.06,
        rod_length=0.21,
        piston_mass=1.3,
        rod_mass=0.85,
        rod_cg=0.145,
        bore=0.09,
        pressure=smooth_pressure,
        inclination=1.2,
        crank_mass=3.0,
        crank_cg_radius=0.04,
    )
    return mc.Machine([cylinder], **{"shaft_inertia": 0.25, **machine})


def flywheel(inertia):
    """A shaft with a massless unit: J ≡ I, U ≡ 0, no gas."""
    empty = mc.Cylinder(crank_radius=0.05, rod_length=0.2, piston_mass=0.0, rod_mass=0.0, rod_cg=0.0)
    return mc.Machine([empty], shaft_inertia=inertia)


def energy(machine, result):
    """½ J ω² + U from the returned φ and ω, J and U recomputed by the machine."""
    inertia, _ = machine.reduced_inertia(result.phi)
    return 0.5 * inertia * result.omega**2 + machine.potential_energy(result.phi)


# -- conservative runs --------------------------------------------------------------------------


def test_conservative_run_keeps_kinetic_plus_potential_energy():
    machine = SWING.machine()
    result = mc.simulate(machine, np.linspace(0.0, 2.0, 401), rpm0=20.0 * 30 / math.pi)
    assert not result.stalled
    assert result.phi[-1] > 5 * TWO_PI  # several revolutions
    inertia = result.reduced_inertia
    assert (inertia.max() - inertia.min()) / inertia.mean() > 0.2  # J really varies
    assert (result.omega.max() - result.omega.min()) / result.omega.mean() > 0.1  # and so does ω
    total = energy(machine, result)
    assert np.max(np.abs(total - total[0])) / total[0] <= 1e-8
    assert result.energy_drift <= 1e-8
    assert np.all(result.work == 0.0)
    # the returned torques are the machine's
    np.testing.assert_array_equal(result.gravity_torque, machine.gravity_torque(result.phi))
    np.testing.assert_array_equal(result.gas_torque, 0.0)


def test_conservative_run_against_the_mass_points_in_mpmath():
    """T = ½(I_w + Σ m_t|Ṗ|² + m_k|Ṙ|² + I_k β̇²)ω² and U = g Σ m y of the oracle's mass points."""
    machine = SWING.machine()
    result = mc.simulate(machine, np.linspace(0.0, 0.6, 13), rpm0=20.0 * 30 / math.pi)
    values = []
    with mp.workdps(DPS):
        g = _x(SWING.g)
        for phi, omega in zip(result.phi, result.omega, strict=True):
            kinetic = _x(SWING.iw)
            potential = mpf(0)
            for unit in SWING.units:
                psi = _x(phi) + _x(unit.alpha)
                kinetic += unit_kinetic(unit, psi)
                potential += unit_potential(unit, psi, g)
            values.append(float(kinetic * _x(omega) ** 2 / 2 + potential))
    values = np.array(values)
    assert np.max(np.abs(values - values[0])) / values[0] <= 1e-8


def test_a_machine_that_cannot_climb_its_top_dead_point_stops_where_its_energy_is_spent():
    """Gravity alone from the bottom of U with too little speed: it stops at the φ* where
    U(φ*) = ½J(φ₀)ω₀² + U(φ₀), short of the top."""
    machine = SWING.machine()
    grid = np.linspace(0.0, TWO_PI, 2001)
    bottom = grid[np.argmin(machine.potential_energy(grid))]
    ahead = bottom + grid
    top = ahead[np.argmax(machine.potential_energy(ahead))]
    climb = machine.potential_energy(top) - machine.potential_energy(bottom)
    omega0 = math.sqrt(climb / machine.reduced_inertia(bottom)[0])  # half the energy it needs
    start = 0.5 * machine.reduced_inertia(bottom)[0] * omega0**2 + machine.potential_energy(bottom)
    stop = brentq(lambda phi: machine.potential_energy(phi) - start, bottom, top, xtol=1e-15)
    result = mc.simulate(machine, np.linspace(0.0, 5.0, 51), rpm0=omega0 * 30 / math.pi, phi0=bottom)
    assert result.stalled
    assert result.phi[-1] == pytest.approx(stop, rel=1e-7)
    assert result.omega[-1] == 0.0 and result.time[-1] == result.stall_time


# -- the periodic steady state under a square-law load --------------------------------------------


def test_square_law_load_converges_to_the_closed_form_periodic_state():
    """dE/dφ = M(φ) − U'(φ) − (2c/J)E is linear in E = ½Jω²: its periodic solution (motion.md §3)
    E = e^{−A}[E₀ + ∫₀^φ e^{A}(M − U')], A = ∫₀^φ 2c/J, E₀ = ∫₀^Φ e^{A}(M − U') / (e^{A(Φ)} − 1)."""
    machine = gassed_machine(g=20 * 9.80665)  # strong gravity, so that it matters
    drive = 30.0
    load = mc.PowerLawLoad(torque=49.0, rpm=40.0 * 30 / math.pi)
    c = load.torque / load.omega**2
    grid = np.linspace(0.0, TWO_PI, 4001)
    inertia, _ = machine.reduced_inertia(grid)
    torque = machine.gas_torque(grid) + drive + machine.gravity_torque(grid)  # M − U'
    a = cumulative_simpson(2 * c / inertia, x=grid, initial=0.0)
    f = cumulative_simpson(np.exp(a) * torque, x=grid, initial=0.0)
    e = np.exp(-a) * (f[-1] / (np.exp(a[-1]) - 1) + f)
    omega = np.sqrt(2 * e / inertia)
    omega_mean = TWO_PI / simpson(1 / omega, x=grid)  # time mean
    delta = (omega.max() - omega.min()) / omega_mean
    periodic = CubicSpline(grid, omega, bc_type="periodic")

    result = mc.simulate(machine, np.linspace(0.0, 4.0, 4001), rpm0=30.0 * 30 / math.pi, drive=drive, load=load)
    assert not result.stalled
    last = result.phi >= result.phi[-1] - TWO_PI
    assert result.phi[-1] > 20 * TWO_PI
    # pointwise on the last cycle
    error = np.abs(result.omega[last] - periodic(np.mod(result.phi[last], TWO_PI)))
    assert np.max(error) / omega_mean <= 1e-8
    # its mean speed (time per cycle from the samples) and its speed fluctuation
    time_at = CubicSpline(result.phi, result.time)
    simulated_mean = TWO_PI / (time_at(result.phi[-1]) - time_at(result.phi[-1] - TWO_PI))
    assert simulated_mean == pytest.approx(omega_mean, rel=1e-9)
    simulated_delta = (result.omega[last].max() - result.omega[last].min()) / omega_mean
    assert simulated_delta == pytest.approx(delta, rel=1e-4)  # sampled extrema: 160 samples per cycle
    assert delta > 0.1
    assert result.energy_drift <= 1e-8
    # the power law at the samples
    np.testing.assert_allclose(result.load_torque, c * result.omega**2, rtol=1e-14)
    np.testing.assert_array_equal(result.drive_torque, drive)


# -- a pure flywheel --------------------------------------------------------------------------------


def test_flywheel_with_a_constant_drive_is_a_parabola_from_the_first_time():
    inertia, torque, phi0, omega0, t0 = 2.5, 40.0, -1.25, 3.0, 0.5
    times = np.linspace(t0, 3.0, 26)
    result = mc.simulate(flywheel(inertia), times, rpm0=omega0 * 30 / math.pi, phi0=phi0, drive=torque)
    dt = times - t0
    np.testing.assert_array_equal(result.time, times)
    np.testing.assert_allclose(result.phi, phi0 + omega0 * dt + 0.5 * torque / inertia * dt**2, rtol=1e-13)
    np.testing.assert_allclose(result.omega, omega0 + torque / inertia * dt, rtol=1e-13)
    np.testing.assert_allclose(result.acceleration, torque / inertia, rtol=1e-15)
    np.testing.assert_allclose(result.work, torque * (result.phi - phi0), rtol=1e-12)
    assert result.energy_drift <= 1e-12


def test_flywheel_against_a_constant_load_stalls_at_i_omega_over_m():
    inertia, torque, omega0 = 2.0, 12.0, 30.0
    times = np.linspace(0.0, 8.0, 71)  # none of them at the stall
    result = mc.simulate(flywheel(inertia), times, rpm0=omega0 * 30 / math.pi, load=torque, phi0=1.0)
    stall = inertia * omega0 / torque  # 5 s
    assert result.stalled
    assert result.stall_time == pytest.approx(stall, rel=1e-12)
    assert result.time[-1] == result.stall_time and result.omega[-1] == 0.0
    np.testing.assert_array_equal(result.time[:-1], times[times < stall])
    assert result.phi[-1] == pytest.approx(1.0 + inertia * omega0**2 / (2 * torque), rel=1e-12)
    assert result.energy_drift <= 1e-12
    assert "stalled" in repr(result)


def test_from_rest_a_drive_starts_it_and_a_load_does_not():
    machine = flywheel(1.0)
    moving = mc.simulate(machine, [0.0, 1.0], rpm0=0.0, drive=2.0)
    assert not moving.stalled and moving.omega[-1] == pytest.approx(2.0, rel=1e-13)
    stuck = mc.simulate(machine, [0.0, 1.0], rpm0=0.0, load=2.0)
    assert stuck.stalled and stuck.stall_time == 0.0


def test_a_run_continued_from_its_last_sample_is_the_same_run():
    machine = gassed_machine()
    load = mc.PowerLawLoad(torque=40.0, rpm=40.0 * 30 / math.pi)
    whole = mc.simulate(machine, np.linspace(0.0, 1.0, 21), rpm0=35.0 * 30 / math.pi, drive=25.0, load=load)
    first = mc.simulate(machine, np.linspace(0.0, 0.5, 11), rpm0=35.0 * 30 / math.pi, drive=25.0, load=load)
    second = mc.simulate(
        machine,
        np.linspace(0.5, 1.0, 11),
        rpm0=first.rpm_history[-1],
        phi0=first.phi[-1],
        drive=25.0,
        load=load,
    )
    np.testing.assert_allclose(second.phi[-1], whole.phi[-1], rtol=1e-9)
    np.testing.assert_allclose(second.omega[-1], whole.omega[-1], rtol=1e-8)


# -- "balance" --------------------------------------------------------------------------------


def test_balance_is_the_cycle_mean_and_the_speed_follows_the_energy_integral():
    machine = gassed_machine(strokes=4)
    drive = 12.0
    breaks = sorted({*np.arange(5) * math.pi})
    mean_gas = sum(quad(machine.gas_torque, a, b, epsabs=0, epsrel=1e-13)[0] for a, b in itertools.pairwise(breaks))
    load = mean_gas / (4 * math.pi) + drive
    result = mc.simulate(machine, np.linspace(0.0, 1.5, 301), rpm0=40.0 * 30 / math.pi, drive=drive, load="balance")
    np.testing.assert_allclose(result.load_torque, load, rtol=1e-12)
    # ½Jω² = ½J₀ω₀² + ∫_{φ₀}^{φ} (M_gas + M_drive − M_load) dφ − [U(φ) − U(φ₀)]
    grid = np.linspace(0.0, result.phi[-1], 20001)
    work = cumulative_simpson(machine.gas_torque(grid) + drive - load, x=grid, initial=0.0)
    inertia, _ = machine.reduced_inertia(result.phi)
    expected = 0.5 * inertia[0] * 40.0**2 + CubicSpline(grid, work)(result.phi)
    expected -= machine.potential_energy(result.phi) - machine.potential_energy(0.0)
    kinetic = 0.5 * inertia * result.omega**2
    assert np.max(np.abs(kinetic - expected)) / np.max(kinetic) <= 1e-9
    assert result.phi[-1] > 3 * 4 * math.pi


def test_balance_freezes_a_speed_dependent_drive_at_the_start_or_at_balance_speed():
    machine = flywheel(1.0)
    drive = mc.PowerLawLoad(torque=10.0, rpm=10.0 * 30 / math.pi, exponent=1)  # 10 N·m at 10 rad/s
    at_start = mc.simulate(machine, [0.0, 0.1], rpm0=20.0 * 30 / math.pi, drive=drive, load="balance")
    np.testing.assert_allclose(at_start.load_torque, 20.0, rtol=1e-13)
    with pytest.warns(DeprecationWarning, match=r"balance_speed=.* use balance_rpm"):
        frozen = mc.simulate(
            machine, [0.0, 0.1], rpm0=20.0 * 30 / math.pi, drive=drive, load="balance", balance_speed=5.0
        )
    np.testing.assert_allclose(frozen.load_torque, 5.0, rtol=1e-13)
    # balance_rpm: the same speed in 1/min (balance_speed, deprecated, is its rad/s alias)
    in_rpm = mc.simulate(
        machine, [0.0, 0.1], rpm0=20.0 * 30 / math.pi, drive=drive, load="balance", balance_rpm=150 / math.pi
    )
    np.testing.assert_allclose(in_rpm.load_torque, 5.0, rtol=1e-13)


def test_the_start_speed_in_rad_per_s_is_deprecated_and_the_same_run():
    """0.1's ``omega0=`` [rad/s] still works for one release, as ``rpm0`` = 30 ω₀/π."""
    machine = SWING.machine()
    in_rpm = mc.simulate(machine, np.linspace(0.0, 0.2, 5), rpm0=12.0 * 30 / math.pi)
    with pytest.warns(DeprecationWarning, match=r"simulate\(omega0=.* use rpm0="):
        in_rad = mc.simulate(machine, np.linspace(0.0, 0.2, 5), omega0=12.0)
    np.testing.assert_allclose(in_rpm.omega, in_rad.omega, rtol=1e-12)
    assert in_rpm.omega[0] == pytest.approx(12.0, rel=1e-15)
    assert in_rpm.solved == "time integration (DOP853)" and in_rpm.method == "DOP853"
    assert isinstance(in_rpm, mc.motion.MotionResult)


def test_tolerances_too_fine_to_compute_with_are_refused_up_front():
    """Hypothesis found atol = 3.7e-181 overflowing solve_ivp's error norm (a RuntimeWarning)."""
    machine = SWING.machine()
    with pytest.raises(mc.MechanismError, match=r"atol = 3.7\d*e-181 is out of range; allowed: atol >= 1e-100"):
        mc.simulate(machine, [0.0, 0.01], rpm0=60.0 * 30 / math.pi, atol=3.7096188882506045e-181)
    with pytest.raises(mc.MechanismError, match=r"rtol = 1\.0 is out of range"):
        mc.simulate(machine, [0.0, 0.01], rpm0=60.0 * 30 / math.pi, rtol=1.0)
    assert mc.simulate(machine, [0.0, 0.01], rpm0=60.0 * 30 / math.pi, atol=1e-100).omega[-1] > 0


def test_gravity_false_leaves_gravity_out():
    machine = SWING.machine()
    result = mc.simulate(machine, np.linspace(0.0, 0.5, 11), rpm0=20.0 * 30 / math.pi, gravity=False)
    assert np.all(result.gravity_torque == 0.0) and np.all(result.potential_energy == 0.0)
    inertia, _ = machine.reduced_inertia(result.phi)
    kinetic = 0.5 * inertia * result.omega**2
    assert np.max(np.abs(kinetic - kinetic[0])) / kinetic[0] <= 1e-8
    assert result.energy_drift <= 1e-8


def test_equation_of_motion_holds_at_the_samples():
    machine = gassed_machine()
    result = mc.simulate(machine, np.linspace(0.0, 0.3, 31), rpm0=30.0 * 30 / math.pi, drive=10.0, load=5.0)
    parts = result.gas_torque + result.gravity_torque + result.inertia_torque + result.drive_torque
    np.testing.assert_allclose(result.reduced_inertia * result.acceleration, parts - result.load_torque, atol=1e-9)
    # φ̈ also is the slope of ω (a fourth-order central difference, h = 1e-4 s)
    h = 1e-4
    fine = mc.simulate(machine, [0.0, *(0.1 + h * np.arange(-2, 3))], rpm0=30.0 * 30 / math.pi, drive=10.0, load=5.0)
    w = fine.omega[1:]
    slope = (w[0] - 8 * w[1] + 8 * w[3] - w[4]) / (12 * h)
    assert fine.acceleration[3] == pytest.approx(slope, rel=1e-6)


def test_progress_bar_changes_nothing(capsys):
    machine = gassed_machine()
    times = np.linspace(0.0, 0.2, 5)
    quiet = mc.simulate(machine, times, rpm0=30.0 * 30 / math.pi, drive=10.0)
    loud = mc.simulate(machine, times, rpm0=30.0 * 30 / math.pi, drive=10.0, progress=True)
    np.testing.assert_array_equal(quiet.phi, loud.phi)
    np.testing.assert_array_equal(quiet.omega, loud.omega)
    assert "simulate" in capsys.readouterr().err


# -- the result ---------------------------------------------------------------------------------


def test_result_is_frozen_and_converts_with_units():
    result = mc.simulate(SWING.machine(), np.linspace(0.0, 0.2, 11), rpm0=20.0 * 30 / math.pi, load=1.0)
    with pytest.raises(AttributeError):
        result.stalled = True  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        result.omega[0] = 0.0
    np.testing.assert_allclose(result.rpm_history, result.omega * 30 / math.pi, rtol=1e-15)
    # 0.1's name of the array, a number (the mean speed) on the steady state: deprecated
    with pytest.warns(DeprecationWarning, match=r"Transient.rpm is deprecated.* Transient.rpm_history"):
        np.testing.assert_array_equal(result.rpm, result.rpm_history)
    frame = result.to_pandas()
    assert frame.shape == (11, 12) and frame.index.name == "time"
    np.testing.assert_array_equal(frame.index.to_numpy(), result.time)
    np.testing.assert_array_equal(frame["omega"].to_numpy(), result.omega)
    units = frame.attrs["units"]
    assert units["time"] == "s" and units["omega"] == "rad/s" and units["gas_torque"] == "N·m"
    assert units["kinetic_energy"] == "J" and set(units) == {"time", *frame.columns}
    assert frame.attrs["stalled"] == 0 and math.isnan(frame.attrs["stall_time"])
    dataset = result.to_xarray()
    assert dict(dataset.sizes) == {"time": 11}
    assert set(dataset.data_vars) == set(frame.columns)
    assert dataset["load_torque"].attrs["units"] == "N·m" and dataset["time"].attrs["units"] == "s"
    np.testing.assert_array_equal(dataset["phi"].to_numpy(), result.phi)
    assert dataset.attrs["energy_drift"] == result.energy_drift


def test_to_xarray_names_the_extra_when_xarray_is_missing(monkeypatch):
    import multicrank._optional as optional

    def missing(name):
        raise ImportError(name)

    monkeypatch.setattr(optional.importlib, "import_module", missing)
    result = mc.simulate(flywheel(1.0), [0.0, 1.0], rpm0=1.0 * 30 / math.pi)
    with pytest.raises(ImportError, match=r"multicrank\[xarray\]"):
        result.to_xarray()


GOOD = {"rpm0": 100.0}
BAD = [
    ({"t_eval": [[0.0, 1.0]]}, "t_eval must be a 1-D"),
    ({"t_eval": [0.0]}, "t_eval must hold at least 2"),
    ({"t_eval": [0.0, math.nan]}, r"t_eval\[1\] = nan is not finite"),
    ({"t_eval": [0.0, 2.0, 1.0]}, "t_eval must increase strictly"),
    ({"t_eval": [0.0, 0.0]}, "t_eval must increase strictly"),
    ({"t_eval": [-1.0, 1.0]}, r"t_eval\[0\] = -1.0 is out of range"),
    ({"t_eval": ["a", "b"]}, "t_eval"),
    ({"rpm0": -1.0}, r"rpm0 = -1.0 is out of range; allowed: rpm0 >= 0 \[1/min\]"),
    ({"rpm0": math.inf}, "rpm0"),
    ({"rpm0": [1.0, 2.0]}, "rpm0 must be a single real number"),
    ({"phi0": math.nan}, "phi0"),
    ({"rtol": 0.0}, "rtol"),
    ({"rtol": 1e-20}, "rtol = 1e-20 is out of range"),
    ({"atol": -1.0}, "atol"),
    ({"method": "Euler"}, "method = 'Euler' is not allowed"),
    ({"max_step": 0.0}, "max_step"),
    ({"load": "fast"}, "load = 'fast' is not understood"),
    ({"drive": "balance"}, "drive = 'balance' is not understood"),
    ({"load": math.nan}, "load = nan is out of range"),
    ({"balance_speed": 3.0}, "balance_speed applies to load='balance' only"),
    ({"load": "balance", "balance_speed": math.nan}, "balance_speed"),
    ({"balance_rpm": 3.0}, "balance_rpm applies to load='balance' only"),
    ({"load": "balance", "balance_rpm": 3.0, "balance_speed": 3.0}, "give exactly one of balance_rpm and"),
    ({"omega0": 10.0}, "give exactly one of rpm0 and omega0, got both"),
    ({"rpm0": None}, "give exactly one of rpm0 and omega0, got neither"),
    # the deprecated omega0 [rad/s] is checked as before, in its own unit
    ({"rpm0": None, "omega0": -1.0}, r"omega0 = -1.0 is out of range; allowed: omega0 >= 0 \[rad/s\]"),
    # hypothesis found 4.13e-159 rad/s: neither rest nor a speed the integrator can step at
    ({"rpm0": None, "omega0": 4.13e-159}, r"omega0 = 4.13e-159 is out of range; allowed: omega0 = 0 \(from rest\) "),
    ({"rpm0": 1e9}, r"rpm0 = 1000000000.0 is out of range; allowed: rpm0 = 0 \(from rest\) or 1e-06"),
    ({"gravity": "yes"}, "gravity must be True or False"),
    ({"progress": 1}, "progress must be True or False"),
    ({"machine": "engine"}, "machine must be a multicrank.Machine"),
]


@pytest.mark.parametrize(("changes", "message"), BAD, ids=[repr(c) for c, _ in BAD])
def test_bad_input_names_the_parameter(changes, message):
    arguments = {"machine": flywheel(1.0), "t_eval": [0.0, 1.0], **GOOD, **changes}
    machine, times = arguments.pop("machine"), arguments.pop("t_eval")
    with pytest.raises(mc.MechanismError, match=message):
        mc.simulate(machine, times, **arguments)


def test_a_failing_load_callable_is_named():
    def broken(phi, omega):
        raise RuntimeError("no data")

    with pytest.raises(mc.MechanismError, match="load failed: RuntimeError: no data"):
        mc.simulate(flywheel(1.0), [0.0, 1.0], rpm0=1.0 * 30 / math.pi, load=broken)
