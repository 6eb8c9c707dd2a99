//! The flywheel's root search over a δ(I_w) given from outside ([`size_shaft_inertia`]).
//! Oracle: δ(I_w) = a/(I_w + b), the usual flywheel's law (δ ≈ ΔE/(ω_m²·J̄), J̄ = I_w +
//! mean(J − I_w)), whose root a/δ − b, stall limit and massless limit a/b are known in
//! closed form.

use crate::error::{MechanismError, Reach, Result};

use super::size_shaft_inertia;

/// δ(I_w) = a/(I_w + b), `None` (a stall) below `stall`, every I_w asked recorded.
fn law(
    a: f64,
    b: f64,
    stall: f64,
    asked: &mut Vec<f64>,
) -> impl FnMut(f64) -> Result<Option<f64>> + '_ {
    move |inertia| {
        asked.push(inertia);
        Ok((inertia >= stall).then(|| a / (inertia + b)))
    }
}

fn unreachable(found: Result<f64>) -> (Reach, f64) {
    match found {
        Err(MechanismError::Unreachable { reach, closest, .. }) => (reach, closest),
        other => panic!("expected Unreachable, got {other:?}"),
    }
}

#[test]
fn the_root_is_the_laws_from_near_and_far_starts_each_inertia_asked_once() {
    let (a, b, delta) = (2.0, 0.3, 0.01);
    let exact = a / delta - b;
    for start in [0.75 * exact, 1e-3, 1e6] {
        let mut asked = Vec::new();
        let found = size_shaft_inertia(law(a, b, 0.0, &mut asked), b, delta, start).unwrap();
        assert!(((found - exact) / exact).abs() < 1e-11, "{start}: {found}");
        let mut sorted = asked.clone();
        sorted.sort_by(f64::total_cmp);
        sorted.dedup();
        assert_eq!(sorted.len(), asked.len(), "{start}: an inertia asked twice");
    }
}

#[test]
fn a_stall_counts_as_infinite_delta_and_limits_the_reach() {
    // Below I_w = 1 the machine stalls, where δ = a/(1 + b): a target under it is found, one
    // above it is unreachable, and the largest δ that runs is reported.
    let (a, b) = (2.0, 0.3);
    let mut asked = Vec::new();
    let found = size_shaft_inertia(law(a, b, 1.0, &mut asked), b, 1.0, 100.0).unwrap();
    assert!((found - (a - b)).abs() < 1e-11 * (a - b));
    let mut asked = Vec::new();
    let (reach, closest) = unreachable(size_shaft_inertia(
        law(a, b, 1.0, &mut asked),
        b,
        5.0,
        100.0,
    ));
    assert_eq!(reach, Reach::Stalls);
    assert!((closest - a / (1.0 + b)).abs() < 1e-9);
}

#[test]
fn a_target_above_the_massless_shafts_delta_is_unreachable() {
    // δ(0) = a/b = 0.3: the rods' and pistons' inertia b alone keeps δ below 0.5.
    let (a, b) = (0.3, 1.0);
    let mut asked = Vec::new();
    let (reach, closest) = unreachable(size_shaft_inertia(law(a, b, 0.0, &mut asked), b, 0.5, 2.0));
    assert_eq!(reach, Reach::Massless);
    assert!((closest - a / b).abs() < 1e-8);
}

#[test]
fn a_target_below_deltas_floor_is_never_reached() {
    let mut asked = Vec::new();
    let mut floored = law(2.0, 0.3, 0.0, &mut asked);
    let found = size_shaft_inertia(|i| Ok(floored(i)?.map(|d| d + 0.1)), 0.3, 0.05, 10.0);
    assert_eq!(unreachable(found).0, Reach::NeverFalls);
}

#[test]
fn an_error_of_delta_at_ends_the_search_unchanged() {
    let failure = MechanismError::Empty { parameter: "load" };
    let mut calls = 0;
    let found = size_shaft_inertia(
        |inertia| {
            calls += 1;
            if calls == 3 {
                return Err(failure.clone());
            }
            Ok(Some(2.0 / (inertia + 0.3)))
        },
        0.3,
        0.01,
        150.0,
    );
    assert_eq!(found, Err(failure));
    assert_eq!(calls, 3);
}

#[test]
fn bad_input_is_refused_naming_the_parameter_before_any_solve() {
    let cases = [
        (0.3, 0.0, 1.0, "delta"),
        (0.3, 1e-10, 1.0, "delta"),
        (f64::NAN, 0.01, 1.0, "rest"),
        (0.3, 0.01, 0.0, "start"),
        (0.3, 0.01, f64::INFINITY, "start"),
    ];
    for (rest, delta, start, parameter) in cases {
        let found = size_shaft_inertia(|_| panic!("solved on bad input"), rest, delta, start);
        assert_eq!(found.unwrap_err().parameter(), Some(parameter));
    }
}
