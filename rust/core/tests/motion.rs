//! The energy method against an independent oracle: tests/data/oracle.py places every unit in
//! the plane, differentiates by the complex step, interpolates the pressure tables with SciPy
//! and finds the periodic solution with its own quadratures and brentq, sharing no code and
//! no formula with the core; tests/data/make_motion_fixtures.py wrote what it found for
//! built-in machines (tests/common reads them).
//!
//! The tolerances: the oracle is good to ~1e-13 in every speed and δ at the machines' own
//! speeds (its two runs with different rules agree to 5e-14: `oracle.agreement` in the
//! fixtures) and to ~1e-9 near stall. The core's time quadrature is less exact: at the
//! machines' own speeds its energy offset, and so every ω, is up to 3e-9 off (the slow
//! compressor; 1e-11 for the inline four), δ 3.5e-9 (δ about the midrange 6e-9), its t(φ)
//! 1.5e-8 of t_Φ; near stall, where ω_min rests on s ≪ E, ω_min is 1.2e-6 off (12 rpm); under
//! the square law δ is 1.4e-7 off (its extremes err in opposite senses). The tolerances sit a few times above what is
//! measured (each test prints it): well inside the accuracy promised for tabulated pressures
//! (ω_m to 1e-7, δ to 1e-3), and far below what a real error moves (a gas torque 1e-6 off
//! moves δ by ~1e-6).

mod common;

use common::{
    array, fixtures, machine_of, number, omega as omega_of, relative, rpm as rpm_of, solve,
    COASTING_KEY,
};
use multicrank_core::{
    flywheel_inertia, square_law_steady_state, steady_state, steady_state_curves, MachineView,
    MechanismError, SteadyCurves, SteadyState,
};
use serde_json::Value;
use std::f64::consts::PI;

/// At the machines' own speeds: ω_m and t_Φ are the speed asked for and the load the gas
/// torque's cycle mean (the core's is exact to rounding); ω's extremes and δ as the module's
/// note says.
#[test]
fn the_oracle_agrees_at_each_machines_speed() {
    for f in fixtures() {
        let state = solve(&f, f.rpm);
        agrees(&f.name, &state, &f.expected, 1e-13, 1e-8, 2e-8);
    }
}

/// Near stall (the slow compressor at 9 and 12 rpm; it stalls below 8.40 rpm) the dip of ω
/// is a few 1e-4 rad wide and ω_min ≈ √(2s/J) rests on s ≪ E, which t_Φ fixes only weakly:
/// the core's ω_min is 1.2e-6 off at 12 rpm, δ (which ω_max dominates) 1.3e-8, δ without
/// gravity 4e-8.
#[test]
fn near_stall_the_oracle_agrees() {
    let mut cases = 0;
    for f in fixtures() {
        for case in &f.near_stall {
            let rpm = number(case, "rpm");
            let state = solve(&f, rpm);
            let name = format!("{} at {rpm} rpm", f.name);
            agrees(&name, &state, &case["steady_state"], 1e-13, 5e-6, 2e-7);
            cases += 1;
        }
    }
    assert!(cases >= 2);
}

/// The worst relative difference of ω and of t (the latter in units of t_Φ) from the
/// oracle's arrays; t(0) = 0 and t(Φ) = t_Φ set.
fn curves_differ(found: &SteadyCurves, expected: &Value) -> (f64, f64) {
    let (omega, time) = (array(expected, "omega"), array(expected, "time"));
    assert_eq!(found.omega.len(), omega.len());
    let mut mine = found.time.clone();
    let last = mine.len() - 1;
    mine[0] = 0.0;
    mine[last] = found.state.period;
    let worst_omega = found
        .omega
        .iter()
        .zip(&omega)
        .fold(0.0_f64, |m, (a, b)| m.max(relative(*a, *b)));
    let worst_time = mine.iter().zip(&time).fold(0.0_f64, |m, (a, b)| {
        m.max((a - b).abs() / found.state.period)
    });
    (worst_omega, worst_time)
}

/// ω(φ) and t(φ) at 361 angles from 0 to Φ against the oracle's: ω as the extremes, t to
/// the core's time quadrature (1.5e-8 of t_Φ measured at speed, 1.6e-7 near stall).
#[test]
fn omega_and_time_at_angles_agree_with_the_oracle() {
    for f in fixtures() {
        let phi = array(&f.curves, "phi");
        let found =
            steady_state_curves(&machine_of(&f), omega_of(f.rpm), 1e-3, &phi).expect("runs");
        assert_eq!(found.state, solve(&f, f.rpm));
        assert_eq!(found.time[0], 0.0);
        assert!(relative(found.time[phi.len() - 1], found.state.period) < 1e-14);
        let (omega, time) = curves_differ(&found, &f.curves);
        println!("{:24} omega {omega:.2e} time {time:.2e}", f.name);
        assert!(omega <= 1e-8 && time <= 5e-8, "{}", f.name);
        for case in &f.near_stall {
            let rpm = number(case, "rpm");
            let phi = array(&case["curves"], "phi");
            let found =
                steady_state_curves(&machine_of(&f), omega_of(rpm), 1e-3, &phi).expect("runs");
            let (omega, time) = curves_differ(&found, &case["curves"]);
            println!(
                "{:24} at {rpm} rpm omega {omega:.2e} time {time:.2e}",
                f.name
            );
            assert!(omega <= 5e-6 && time <= 5e-7, "{} at {rpm}", f.name);
        }
    }
    let f = &fixtures()[0];
    let outside = steady_state_curves(&machine_of(f), omega_of(f.rpm), 1e-3, &[0.0, -1e-9]);
    assert!(matches!(
        outside,
        Err(MechanismError::OutOfRange {
            parameter: "phi",
            ..
        })
    ));
}

/// The square-law load c·ω² beside a constant drive (engines alone and with a drive,
/// compressors with a drive): the core's closed form against the oracle's propagator. The
/// mean speed is a result here: the core's is 1.1e-10 off (the boxer), its extremes 4.6e-9, δ
/// 1.4e-7 (the slow compressor with a drive of 3|T|).
#[test]
fn the_square_law_closed_form_agrees_with_the_oracle() {
    let mut cases = 0;
    for f in fixtures() {
        for case in &f.square_law {
            let name = format!("{} drive {}", f.name, number(case, "drive"));
            let phi = array(&case["curves"], "phi");
            let found = square_law_steady_state(
                &machine_of(&f),
                number(case, "coefficient"),
                number(case, "drive"),
                1e-3,
                &phi,
            )
            .expect("runs");
            let s = &found.state;
            let close = |key: &str, value: f64, tolerance: f64| {
                let error = relative(value, number(case, key));
                println!("{name:32} {key:24} {value:+.17e} {error:.2e}");
                assert!(error <= tolerance, "{name} {key}: {error:.2e}");
            };
            close("mean_load_torque", s.mean_load_torque, 1e-11);
            close("omega_mean", s.omega_mean, 1e-9);
            close("period", s.period, 1e-9);
            close("omega_max", s.omega_max, 2e-8);
            close("omega_min", s.omega_min, 2e-8);
            close("delta", s.delta, 5e-7);
            close("delta_without_gravity", s.delta_without_gravity, 5e-7);
            close(COASTING_KEY, s.delta_coasting, 5e-7);
            // Where: a machine whose speed peaks twice a cycle (the twin two-stroke, the
            // inline four) may name the other peak, where ω is the same.
            check_angles(&name, &found, case, |angles| {
                square_law_steady_state(
                    &machine_of(&f),
                    number(case, "coefficient"),
                    number(case, "drive"),
                    1e-3,
                    angles,
                )
                .expect("runs")
                .omega
            });
            let (omega, time) = curves_differ(&found, &case["curves"]);
            println!("{name:32} omega {omega:.2e} time {time:.2e}");
            assert!(omega <= 1e-8 && time <= 5e-8, "{name}");
            cases += 1;
        }
    }
    assert_eq!(cases, 8);
    // A compressor without a drive: nothing drives it against the load, which brings it to
    // rest — a stall (a sweep's row), with no speed asked and none that runs.
    let f = &fixtures()[0];
    match square_law_steady_state(&machine_of(f), 1.0, 0.0, 1e-3, &[]) {
        Err(MechanismError::Stall {
            angle,
            omega_mean,
            min_omega,
        }) => {
            assert!(
                (0.0..=2.0 * PI).contains(&angle) && omega_mean.is_nan() && min_omega.is_none()
            );
        }
        other => panic!("{other:?}"),
    }
    // No load at all: refused, naming it.
    let refused =
        |c: f64, drive: f64| match square_law_steady_state(&machine_of(f), c, drive, 1e-3, &[]) {
            Err(MechanismError::OutOfRange { parameter, .. }) => parameter,
            other => panic!("{other:?}"),
        };
    assert_eq!(refused(0.0, 1e4), "load");
}

/// φ_max and φ_min where the oracle found them (its bounded Brent finds an angle to ~1e-7
/// rad where ω is flat), or else at an angle where ω is the same (a second peak).
fn check_angles(
    name: &str,
    found: &SteadyCurves,
    expected: &Value,
    omega_at: impl Fn(&[f64]) -> Vec<f64>,
) {
    let s = &found.state;
    let oracle = [number(expected, "phi_max"), number(expected, "phi_min")];
    let there = omega_at(&oracle);
    for (k, (key, value, omega)) in [
        ("phi_max", s.phi_max, s.omega_max),
        ("phi_min", s.phi_min, s.omega_min),
    ]
    .into_iter()
    .enumerate()
    {
        let error = (value - oracle[k]).abs();
        println!("{name:32} {key:24} {value:+.17e} {error:.2e} rad");
        assert!(
            error <= 1e-5 || relative(there[k], omega) <= 1e-12,
            "{name} {key}"
        );
    }
}

/// Below the lowest running speed: a stall near the oracle's angle (K's minimum, where ω
/// would reach 0), with its min_rpm (the root of ω_min/ω_m = 1e-3; the core's is 3.1e-8
/// off: near stall t_Φ fixes ω_min only weakly).
#[test]
fn a_stall_names_the_lowest_speed_that_runs() {
    let mut cases = 0;
    for f in fixtures() {
        for case in &f.stalls {
            let rpm = number(case, "rpm");
            match steady_state(&machine_of(&f), omega_of(rpm), 1e-3) {
                Err(MechanismError::Stall {
                    angle,
                    omega_mean: at,
                    min_omega,
                }) => {
                    let min_rpm = rpm_of(min_omega.expect("min_omega found"));
                    let error = relative(min_rpm, number(case, "min_rpm"));
                    println!(
                        "{} at {rpm} rpm: min_rpm {min_rpm:.17e} ({error:.2e}), angle {angle} vs {}",
                        f.name,
                        number(case, "angle")
                    );
                    assert_eq!(at, omega_of(rpm));
                    assert!(error <= 2e-7, "{}: min_rpm {min_rpm}", f.name);
                    assert!(
                        (angle - number(case, "angle")).abs() < 1e-3,
                        "{}: angle {angle}",
                        f.name
                    );
                    let message = steady_state(&machine_of(&f), omega_of(rpm), 1e-3)
                        .unwrap_err()
                        .to_string();
                    assert!(message.contains("min_omega"), "{message}");
                }
                other => panic!("{} at {rpm} rpm: expected a stall, got {other:?}", f.name),
            }
            cases += 1;
        }
    }
    assert!(cases >= 1);
}

/// The flywheel for δ = 1/40, 1/100 and the machine's class value against the oracle's
/// (brentq on log I_w of its exact δ): I_w carries δ's error (7.2e-9 measured);
/// the textbook estimate and ΔE rest on K's extremes alone, exact in both (2e-16 measured).
#[test]
fn the_flywheel_agrees_with_the_oracle() {
    for f in fixtures() {
        let machine = machine_of(&f);
        for case in &f.flywheels {
            let delta = number(case, "delta");
            let found =
                flywheel_inertia(&machine, delta, omega_of(f.rpm), 1e-3).expect("a flywheel");
            for (key, value, tolerance) in [
                ("shaft_inertia", found.shaft_inertia, 2e-8),
                (
                    "shaft_inertia_without_gravity",
                    found.shaft_inertia_without_gravity,
                    2e-8,
                ),
                ("textbook", found.textbook, 1e-12),
                ("energy_swing", found.energy_swing, 1e-12),
            ] {
                let error = relative(value, number(case, key));
                println!(
                    "{:18} δ {delta:.4} {key:30} {value:.17e} {error:.2e}",
                    f.name
                );
                assert!(
                    error <= tolerance,
                    "{} δ {delta} {key}: {value} vs {}",
                    f.name,
                    number(case, key)
                );
            }
            // The steady state at that flywheel has the δ asked for.
            let sized = MachineView {
                shaft_inertia: found.shaft_inertia,
                ..machine
            };
            let state = steady_state(&sized, omega_of(f.rpm), 1e-3).expect("runs");
            assert!(relative(state.delta, delta) < 1e-11, "{}", state.delta);
        }
    }
}

/// `state` against the oracle's `e`: the cycle integrals to `integrals`, the extremes to
/// `extremes`, the δs to `deltas` (relative), the angles of the extremes as `check_angles`.
fn agrees(name: &str, state: &SteadyState, e: &Value, integrals: f64, extremes: f64, deltas: f64) {
    let mut worst: f64 = 0.0;
    let mut close = |key: &str, found: f64, tolerance: f64| {
        let error = relative(found, number(e, key));
        println!("{name:24} {key:24} {found:+.17e} {error:.2e}");
        assert!(
            error <= tolerance,
            "{name} {key}: {found} vs {} ({error:.2e})",
            number(e, key)
        );
        worst = worst.max(error);
    };
    close("omega_mean", state.omega_mean, integrals);
    close("period", state.period, integrals);
    close("mean_load_torque", state.mean_load_torque, integrals);
    close("omega_max", state.omega_max, extremes);
    close("omega_min", state.omega_min, extremes);
    close("delta", state.delta, deltas);
    close("delta_midrange", state.delta_midrange, deltas);
    close("delta_without_gravity", state.delta_without_gravity, deltas);
    close(COASTING_KEY, state.delta_coasting, deltas);
    println!("{name}: worst relative difference {worst:.2e}");
    for (key, found) in [("phi_max", state.phi_max), ("phi_min", state.phi_min)] {
        let error = (found - number(e, key)).abs();
        println!("{name:24} {key:24} {found:+.17e} {error:.2e} rad");
        assert!(error <= 1e-5, "{name} {key}: {found} vs {}", number(e, key));
    }
}
