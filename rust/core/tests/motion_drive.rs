//! A driving torque of φ alone beside the gas under the "balance" load, and the square-law
//! flywheel, against the independent oracle (tests/data/oracle.py, whose fixtures
//! make_motion_fixtures.py writes): the drive is the same SciPy `PPoly` on both sides, which
//! the oracle integrates by Gauss–Legendre rules on panels between its breakpoints and the
//! core by each piece's antiderivative.

mod common;

use common::{diagram, fixtures, machine_json, machine_of, number, omega, relative, COASTING_KEY};
use multicrank_core::{
    square_law_flywheel_inertia, square_law_steady_state, MachineView, MechanismError, SteadyTables,
};

/// The steady state at each machine's speed beside the oracle's drive: ω_m, t_Φ and the
/// load (gas and drive's cycle mean) exact to rounding; δ, δ without gravity and of gravity
/// alone as without a drive (the module note of tests/motion.rs: 2e-8).
#[test]
fn a_drive_of_phi_agrees_with_the_oracle() {
    for f in fixtures() {
        let json = machine_json(&f.name);
        let case = &json["drive"];
        let cycle = f.strokes.cycle_angle();
        let drive = diagram(case, cycle, 1.0);
        let tables = SteadyTables::new(&machine_of(&f)).expect("tables");
        let driven = tables.with_drive(&drive).expect("a drive");
        let found = driven
            .steady_state(f.shaft_inertia, omega(f.rpm), 1e-3, &[], true)
            .expect("runs")
            .state;
        let expected = &case["steady_state"];
        for (key, value, tolerance) in [
            ("omega_mean", found.omega_mean, 1e-13),
            ("period", found.period, 1e-13),
            ("mean_load_torque", found.mean_load_torque, 1e-12),
            ("omega_max", found.omega_max, 1e-8),
            ("omega_min", found.omega_min, 1e-8),
            ("delta", found.delta, 2e-8),
            ("delta_without_gravity", found.delta_without_gravity, 2e-8),
            (COASTING_KEY, found.delta_coasting, 2e-8),
        ] {
            let error = relative(value, number(expected, key));
            println!("{:18} {key:24} {value:+.17e} {error:.2e}", f.name);
            assert!(
                error <= tolerance,
                "{} {key}: {value} vs {}",
                f.name,
                number(expected, key)
            );
        }
        // The drive changes the motion (else the test could not fail on it).
        let plain = tables
            .steady_state(f.shaft_inertia, omega(f.rpm), 1e-3, &[], false)
            .expect("runs")
            .state;
        assert!(relative(plain.delta, found.delta) > 1e-3, "{}", f.name);
        // The flywheel for δ = 1/40 beside the drive.
        let sized = &case["flywheel"];
        let delta = number(sized, "delta");
        let flywheel = driven
            .flywheel_inertia(delta, omega(f.rpm), 1e-3, f.shaft_inertia, false)
            .expect("a flywheel");
        for (key, value, tolerance) in [
            ("shaft_inertia", flywheel.shaft_inertia, 2e-8),
            ("textbook", flywheel.textbook, 1e-12),
            ("energy_swing", flywheel.energy_swing, 1e-12),
        ] {
            let error = relative(value, number(sized, key));
            println!("{:18} {key:24} {value:+.17e} {error:.2e}", f.name);
            assert!(
                error <= tolerance,
                "{} {key}: {value} vs {}",
                f.name,
                number(sized, key)
            );
        }
    }
}

/// A drive table over the wrong span, or a second drive, is refused naming `drive`.
#[test]
fn a_bad_drive_names_the_parameter() {
    let f = &fixtures()[0];
    let tables = SteadyTables::new(&machine_of(f)).expect("tables");
    let cycle = f.strokes.cycle_angle();
    let short = multicrank_core::PiecewisePolynomial::new(vec![0.0, 1.0], vec![1.0], 1.0)
        .expect("a polynomial");
    let refused = tables.with_drive(&short).expect_err("the wrong span");
    assert!(matches!(
        refused,
        MechanismError::OutOfRange {
            parameter: "drive",
            ..
        }
    ));
    let drive = multicrank_core::PiecewisePolynomial::new(vec![0.0, cycle], vec![1.0], cycle)
        .expect("a polynomial");
    let twice = tables.with_drive(&drive).expect("a drive");
    assert!(twice.with_drive(&drive).is_err());
}

/// The square-law flywheel (the fixtures' square-law cases, each load and drive): the shaft
/// found gives the δ asked for in the closed-form steady state the oracle checks
/// (tests/motion.rs), at the mean speed it reports.
#[test]
fn the_square_law_flywheel_gives_the_delta_asked_for() {
    for f in fixtures() {
        let json = machine_json(&f.name);
        let machine = machine_of(&f);
        for case in json["square_law"].as_array().expect("square law") {
            let (coefficient, drive) = (number(case, "coefficient"), number(case, "drive"));
            for delta in [1.0 / 40.0, 1.0 / 100.0] {
                let found = square_law_flywheel_inertia(&machine, coefficient, drive, delta, 1e-3)
                    .expect("a flywheel");
                let sized = MachineView {
                    shaft_inertia: found.shaft_inertia,
                    ..machine
                };
                let state = square_law_steady_state(&sized, coefficient, drive, 1e-3, &[])
                    .expect("runs")
                    .state;
                println!(
                    "{:18} δ {delta:.4} I_w {:.10e} textbook {:+.2e}",
                    f.name, found.shaft_inertia, found.textbook_error
                );
                assert!(relative(state.delta, delta) < 1e-11, "{}", state.delta);
                assert!(relative(found.omega_mean, state.omega_mean) < 1e-14);
                // The textbook estimate is exact to first order in δ.
                assert!(
                    found.textbook_error.abs() < 10.0 * delta,
                    "{}",
                    found.textbook_error
                );
            }
        }
    }
}
