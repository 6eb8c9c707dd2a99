//! Every solver answers in one [`Solution`]: a stall with its status and angle, a converged
//! solve with the work its root finder did. Oracle: a constant inertia turned by gravity
//! alone, ½Iω² + U(φ) = E with U = g·m·e·sin(φ + α + π/2), whose speed minimum lies at the
//! top of U (φ = −α), and whose δ → 0 without gravity (a pure flywheel).

use std::f64::consts::{FRAC_PI_2, TAU};

use crate::mechanism::PhysicalCylinder;
use crate::mechanism::Strokes;

use super::super::square_law::SquareLaw;
use super::super::{GasCylinder, MachineView, SteadyTables};
use super::{PeriodicSolver, Status};

const PHASE: f64 = 0.3;

/// A crank web off-centre on a shaft of I_w = 2 kg·m², no reciprocating masses, no gas.
fn unit() -> PhysicalCylinder {
    PhysicalCylinder {
        crank_radius: 0.05,
        rod_length: 0.2,
        piston_mass: 0.0,
        rod_mass: 0.0,
        rod_cg: 0.1,
        rod_inertia: 0.0,
        crank_mass: 20.0,
        crank_cg_radius: 0.08,
        counterweight_mass: 0.0,
        counterweight_radius: 0.0,
        phase: PHASE,
        inclination: FRAC_PI_2,
    }
}

fn tables() -> SteadyTables {
    let units = [unit()];
    SteadyTables::new(&MachineView {
        units: &units,
        gas: &[GasCylinder::NONE],
        diagrams: &[],
        shaft_inertia: 2.0,
        strokes: Strokes::Two,
        g: 9.81,
    })
    .unwrap()
}

#[test]
fn a_stalled_solve_reports_its_status_and_the_top_of_the_potential() {
    // At a mean speed of 1 rad/s (½Iω² = 1 J) the barrier 2·g·m·e ≈ 31 J needs a swing of
    // ω from ~0 to ~5.6 rad/s: ω_min/ω_m = 0.5 cannot be kept.
    let found = tables().solve(2.0, 1.0, 0.5).unwrap();
    assert_eq!(found.status, Status::Stalled);
    assert_eq!(found.status.code(), 1);
    assert!(found.periodic.is_none() && found.curves.is_none());
    assert!(found.message.contains("stalls"), "{}", found.message);
    let angle = found.stall_angle.unwrap();
    let top = (-PHASE).rem_euclid(TAU);
    assert!((angle - top).abs() < 1e-9, "{angle} vs {top}");
}

#[test]
fn a_converged_solve_counts_fewer_evaluations_than_bisection_needs() {
    let tables = tables();
    let found = tables.solve(2.0, 30.0, 1e-3).unwrap();
    assert_eq!(found.status, Status::Converged);
    assert_eq!(found.status.code(), 0);
    assert!(found.stall_angle.is_none());
    let periodic = found.periodic.unwrap();
    assert!((periodic.omega_mean / 30.0 - 1.0).abs() < 1e-12);
    // Newton's method on a nearly linear excess from the estimate of the cycle means: a
    // few evaluations, one per step after the first, where bisection from the bracket
    // [s_low, s_high] to 1e-15 relative would take ~50.
    assert!(found.nit > 0, "{found:?}");
    assert_eq!(found.nfev, found.nit + 1, "{found:?}");
    assert!(found.nfev < 8, "{found:?}");
    // Curves when asked, none otherwise; the same numbers either way.
    assert!(found.curves.is_none());
    let phi = [0.0, 1.0, TAU];
    let with = tables.steady_state(2.0, 30.0, 1e-3, &phi, false).unwrap();
    assert_eq!(with.state.delta, periodic.delta());
    assert_eq!(with.omega.len(), 3);
    assert_eq!(
        (with.status, with.nfev, with.nit),
        (0, found.nfev, found.nit)
    );
}

#[test]
fn the_closed_form_finds_no_root_and_a_square_law_stall_is_a_status() {
    let tables = tables();
    // A drive of 5 N·m against c·ω²: runs at about √(5/c) (gravity's mean is zero).
    let law = SquareLaw::new(&tables.cycle, 5.0 / 900.0, 5.0);
    let found = law.solve(2.0, 1e-3, None).unwrap();
    assert_eq!(found.status, Status::Converged);
    assert_eq!((found.nfev, found.nit), (0, 0));
    assert!((found.periodic.unwrap().omega_mean / 30.0 - 1.0).abs() < 0.05);
    // A drive of 0.01 N·m: the square law holds it at ~1 rad/s, below the barrier.
    let weak = SquareLaw::new(&tables.cycle, 0.01, 0.01);
    let stalled = weak.solve(2.0, 1e-3, None).unwrap();
    assert_eq!(stalled.status, Status::Stalled);
    assert!(stalled.stall_angle.is_some() && stalled.periodic.is_none());
    assert_eq!(weak.delta_at(2.0, 1e-3).unwrap(), None);
}
