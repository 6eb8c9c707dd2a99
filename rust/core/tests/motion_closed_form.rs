//! The energy method against closed forms: a constant inertia turned by gravity alone, a
//! constant-pressure stroke on a constant inertia; and its errors (a stall, bad input).

mod common;

use common::{fixtures, omega, relative};
use multicrank_core::{
    steady_state, GasCylinder, MachineView, MechanismError, PhysicalCylinder, PiecewisePolynomial,
    Strokes,
};

/// A unit without reciprocating masses (J = I_w, constant), its crank web off-centre.
fn flywheel_unit(crank_mass: f64, phase: f64) -> PhysicalCylinder {
    PhysicalCylinder {
        crank_radius: 0.05,
        rod_length: 0.2,
        piston_mass: 0.0,
        rod_mass: 0.0,
        rod_cg: 0.1,
        rod_inertia: 0.0,
        crank_mass,
        crank_cg_radius: 0.08,
        counterweight_mass: 0.0,
        counterweight_radius: 0.0,
        phase,
        inclination: std::f64::consts::FRAC_PI_2,
    }
}

/// The root of an increasing `f` in [low, high] by bisection to the last bit.
fn bisect(f: impl Fn(f64) -> f64, mut low: f64, mut high: f64) -> f64 {
    for _ in 0..200 {
        let middle = 0.5 * (low + high);
        if middle <= low || middle >= high {
            break;
        }
        if f(middle) < 0.0 {
            low = middle;
        } else {
            high = middle;
        }
    }
    0.5 * (low + high)
}

/// Constant J, no gas, gravity alone: ½Iω² + U = E with U = g·m·e·(sin(φ + α + γ) − sin γ),
/// E from t_Φ = ∫dφ/ω by the trapezoid rule (spectral for a smooth periodic integrand) and
/// bisection; without gravity it is a pure flywheel, δ = 0.
#[test]
fn gravity_alone_on_a_constant_inertia_is_the_energy_integral() {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    let (g, inertia, rpm, phase) = (9.81, 2.0, 120.0, 0.3);
    let units = [flywheel_unit(20.0, phase)];
    let machine = MachineView {
        units: &units,
        gas: &[GasCylinder::NONE],
        diagrams: &[],
        shaft_inertia: inertia,
        strokes: Strokes::Two,
        g,
    };
    let state = steady_state(&machine, omega(rpm), 1e-3).unwrap();
    let amplitude = g * 20.0 * 0.08;
    let energy = |phi: f64| amplitude * ((phi + phase + FRAC_PI_2).sin() - FRAC_PI_2.sin());
    let omega_mean = PI * rpm / 30.0;
    let points = 20_000;
    let period = |e: f64| {
        let h = TAU / points as f64;
        (0..points)
            .map(|i| h / (2.0 * (e - energy(i as f64 * h)) / inertia).sqrt())
            .sum::<f64>()
    };
    let (u_min, u_max) = (-amplitude - amplitude, amplitude - amplitude);
    let e = bisect(|e| TAU / omega_mean - period(e), u_max + 1e-9, 1e6);
    let omega_max = (2.0 * (e - u_min) / inertia).sqrt();
    let omega_min = (2.0 * (e - u_max) / inertia).sqrt();
    let delta = (omega_max - omega_min) / omega_mean;
    assert!(delta > 0.05, "a fluctuation worth testing: {delta}");
    assert!(relative(state.omega_mean, omega_mean) < 1e-14);
    assert!(
        relative(state.omega_max, omega_max) < 1e-14,
        "{} {omega_max}",
        state.omega_max
    );
    assert!(
        relative(state.omega_min, omega_min) < 1e-14,
        "{} {omega_min}",
        state.omega_min
    );
    assert!(
        relative(state.delta, delta) < 1e-12,
        "{} vs {delta}",
        state.delta
    );
    // Fastest where U is lowest (sin = −1), slowest where it is highest.
    let phi_max = (1.5 * PI - phase - FRAC_PI_2).rem_euclid(TAU);
    let phi_min = (0.5 * PI - phase - FRAC_PI_2).rem_euclid(TAU);
    assert!(
        (state.phi_max - phi_max).abs() < 1e-7,
        "{} {phi_max}",
        state.phi_max
    );
    assert!(
        (state.phi_min - phi_min).abs() < 1e-7,
        "{} {phi_min}",
        state.phi_min
    );
    assert_eq!(state.mean_load_torque, 0.0);
    assert!(relative(state.delta_coasting, delta) < 1e-12);
    // g = 0: a pure flywheel.
    assert!(
        state.delta_without_gravity.abs() < 1e-15,
        "{}",
        state.delta_without_gravity
    );
    let still = steady_state(&MachineView { g: 0.0, ..machine }, omega(rpm), 1e-3).unwrap();
    assert!(still.delta.abs() < 1e-15 && still.delta_coasting.abs() < 1e-15);
    assert!(relative(still.omega_max, omega_mean) < 1e-15);
}

/// A constant pressure p over the power stroke [0, π) and none over the return: the gas
/// torque is pA·s'(φ) on [0, π] (a half sine with the crank ratio's correction), its work
/// pA·s(φ) exactly, the load pA·2r/2π; on a constant inertia ω² = 2(E₀ + K)/I, with E₀ from
/// t_Φ by Simpson's rule on each half and bisection, and the extremes where pA·s' equals the
/// load. The textbook δ ≈ ΔE/(Iω_m²) agrees to first order in δ.
#[test]
fn a_constant_pressure_stroke_on_a_constant_inertia_is_the_textbook_machine() {
    use std::f64::consts::{PI, TAU};
    let (pressure, bore, inertia, rpm) = (2e5, 0.1, 2.0, 300.0);
    let units = [flywheel_unit(0.0, 0.0)];
    let gas = [GasCylinder {
        bore,
        piston_rod_diameter: 0.0,
        head: Some(0),
        crank_end: None,
    }];
    // PPoly of order 1: c[0] = [p, 0] on [0, π), [π, 2π).
    let diagrams =
        [PiecewisePolynomial::new(vec![0.0, PI, TAU], vec![pressure, 0.0], TAU).unwrap()];
    let machine = MachineView {
        units: &units,
        gas: &gas,
        diagrams: &diagrams,
        shaft_inertia: inertia,
        strokes: Strokes::Two,
        g: 9.81,
    };
    let state = steady_state(&machine, omega(rpm), 1e-3).unwrap();
    let (r, l) = (0.05, 0.2);
    let lambda = r / l;
    let force = pressure * PI * bore * bore / 4.0;
    let travel = |phi: f64| {
        let phi = phi.min(PI);
        r * (1.0 - phi.cos()) + l * (1.0 - (1.0 - (lambda * phi.sin()).powi(2)).sqrt())
    };
    let velocity = |phi: f64| {
        let w = (1.0 - (lambda * phi.sin()).powi(2)).sqrt();
        r * phi.sin() * (1.0 + lambda * phi.cos() / w)
    };
    let load = force * 2.0 * r / TAU;
    let work = |phi: f64| force * travel(phi) - load * phi;
    assert!(relative(state.mean_load_torque, load) < 1e-14);
    let omega_mean = PI * rpm / 30.0;
    let simpson = |f: &dyn Fn(f64) -> f64, a: f64, b: f64| {
        let n = 20_000;
        let h = (b - a) / n as f64;
        let inner: f64 = (1..n)
            .map(|i| f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
            .sum();
        h / 3.0 * (f(a) + inner + f(b))
    };
    let period = |e: f64| {
        let inverse = |phi: f64| 1.0 / (2.0 * (e + work(phi)) / inertia).sqrt();
        simpson(&inverse, 0.0, PI) + simpson(&inverse, PI, TAU)
    };
    // K's extremes: pA·s' = load, rising through it at φ₁ (K's minimum) and falling at φ₂.
    let peak = bisect(
        |phi| {
            let h = 1e-6;
            velocity(phi + h) - velocity(phi - h)
        },
        0.5,
        2.5,
    );
    let peak = peak.clamp(0.5, 2.5);
    let phi_1 = bisect(|phi| force * velocity(phi) - load, 0.0, peak);
    let phi_2 = bisect(|phi| load - force * velocity(phi), peak, PI);
    let k_min = work(phi_1);
    let e = bisect(|e| TAU / omega_mean - period(e), -k_min + 1e-9, 1e7);
    let omega_max = (2.0 * (e + work(phi_2)) / inertia).sqrt();
    let omega_min = (2.0 * (e + k_min) / inertia).sqrt();
    let delta = (omega_max - omega_min) / omega_mean;
    assert!(
        relative(state.delta, delta) < 1e-11,
        "{} vs {delta}",
        state.delta
    );
    assert!(relative(state.omega_max, omega_max) < 1e-13);
    assert!(relative(state.omega_min, omega_min) < 1e-13);
    assert!(
        (state.phi_max - phi_2).abs() < 1e-7,
        "{} {phi_2}",
        state.phi_max
    );
    assert!(
        (state.phi_min - phi_1).abs() < 1e-7,
        "{} {phi_1}",
        state.phi_min
    );
    // No moving mass leaves gravity nothing to do.
    assert!(relative(state.delta_without_gravity, state.delta) < 1e-14);
    assert!(state.delta_coasting.abs() < 1e-15);
    let textbook = (work(phi_2) - k_min) / (inertia * omega_mean * omega_mean);
    assert!(
        relative(textbook, delta) < 2.0 * delta,
        "textbook {textbook} vs {delta}"
    );
}

/// Too slow a mean speed is a stall, named with the angle; bad input names the parameter.
#[test]
fn a_stall_and_bad_input_are_errors() {
    let all = fixtures();
    let f = &all[0];
    let machine = MachineView {
        units: &f.units,
        gas: &f.gas,
        diagrams: &f.diagrams,
        shaft_inertia: f.shaft_inertia,
        strokes: f.strokes,
        g: f.g,
    };
    // Below its lowest running speed (8.4 rpm, the oracle's min_rpm in the fixtures): a stall.
    assert!(matches!(
        steady_state(&machine, omega(5.0), 1e-3),
        Err(MechanismError::Stall { .. })
    ));
    // A stall the base panels decide: gravity alone turning a light shaft slowly, with the
    // limit at half the mean speed; it is slowest where U is highest.
    let units = [flywheel_unit(20.0, 0.3)];
    let heavy = MachineView {
        units: &units,
        gas: &[GasCylinder::NONE],
        diagrams: &[],
        shaft_inertia: 2.0,
        strokes: Strokes::Two,
        g: 9.81,
    };
    let top = (0.5 * std::f64::consts::PI - 0.3 - std::f64::consts::FRAC_PI_2)
        .rem_euclid(std::f64::consts::TAU);
    match steady_state(&heavy, omega(20.0), 0.5) {
        Err(MechanismError::Stall {
            angle, omega_mean, ..
        }) => {
            assert!((angle - top).abs() < 0.1, "{angle} vs {top}");
            assert_eq!(omega_mean, omega(20.0));
            let message = MechanismError::Stall {
                angle,
                omega_mean,
                min_omega: None,
            }
            .to_string();
            assert!(message.contains("stalls"), "{message}");
        }
        other => panic!("expected a stall, got {other:?}"),
    }
    assert!(steady_state(&machine, omega(9.0), 1e-3).is_ok());
    for (rpm, ratio, name) in [
        (-1.0, 1e-3, "omega_mean"),
        (f64::NAN, 1e-3, "omega_mean"),
        (100.0, 1.0, "min_speed_ratio"),
    ] {
        let message = steady_state(&machine, omega(rpm), ratio)
            .unwrap_err()
            .to_string();
        assert!(message.contains(name), "{message}");
    }
    let gas = [GasCylinder {
        head: Some(7),
        ..f.gas[0]
    }];
    let message = steady_state(
        &MachineView {
            gas: &gas,
            ..machine
        },
        omega(100.0),
        1e-3,
    )
    .unwrap_err()
    .to_string();
    assert!(message.contains("pressure"), "{message}");
}
