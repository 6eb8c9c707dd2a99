//! Tests of the closed-form kernels.

use super::*;
use crate::angles::{GridAngles, Rotations, UniformGrid};
use crate::mechanism::{crank_phases, Acting, Strokes};

#[test]
fn unit_bounds_hold() {
    // |Q|, |dQ/dψ| and |d²Q/dψ²| of a unit against `Coefficients::bounds` at D there
    // (the last from central differences of dQ/dψ), λ up to the last double below 1,
    // with ψ close to π/2 where D is smallest; and `values` against the kernels.
    let phases = Phases::single();
    for lambda in [
        0.0,
        0.3,
        0.9,
        0.999,
        1.0 - 1e-8,
        1.0 - 1e-12,
        1.0 - 2f64.powi(-53),
    ] {
        for gamma in [0.4, std::f64::consts::FRAC_PI_2, -2.5] {
            let design = Design::new(lambda, gamma, 1.3, -0.7).unwrap();
            let unit = Coefficients::new(&design);
            let root = ((1.0 - lambda) * (1.0 + lambda)).sqrt();
            for offset in [
                0.7,
                0.1,
                1e-3,
                30.0 * root,
                3.0 * root,
                root,
                0.3 * root,
                0.0,
            ] {
                for psi in [
                    std::f64::consts::FRAC_PI_2 + offset,
                    -std::f64::consts::FRAC_PI_2 - offset,
                ] {
                    let (s, c) = psi.sin_cos();
                    let (u, q, dq) = unit.values(s, c);
                    let kernels = |quantity| evaluate_one(quantity, &design, &phases, &[psi])[0];
                    let [size_q, size_dq, curvature] = unit.bounds(unit.root_argument(c * c));
                    assert!(q.abs() <= size_q * (1.0 + 1e-12), "{lambda} {psi}");
                    assert!(dq.abs() <= size_dq * (1.0 + 1e-12), "{lambda} {psi}");
                    // The kernels' sin/cos differ from libm's by ulps: allow that shift
                    // of ψ times the next derivative (large near π/2 as λ → 1).
                    let shift = 8.0 * f64::EPSILON * (1.0 + psi.abs());
                    let near = |a: f64, b: f64, size: f64, next: f64| {
                        (a - b).abs() <= 1e-12 * size + shift * next
                    };
                    assert!(near(
                        q,
                        kernels(Quantity::GeneralizedForce),
                        size_q,
                        size_dq
                    ));
                    let kernel_dq = kernels(Quantity::ForceDerivative);
                    assert!(
                        near(dq, kernel_dq, size_dq, curvature),
                        "λ = {lambda}, γ = {gamma}, ψ = {psi}: {dq} vs {kernel_dq} (sizes {size_dq} {curvature})"
                    );
                    assert!(near(u, kernels(Quantity::PotentialEnergy), size_q, size_q));
                    // d²Q/dψ² by central differences on a step small against the feature
                    let h = 1e-4 * root.max(1e-4);
                    let slope = |x: f64| {
                        let (s, c) = x.sin_cos();
                        unit.values(s, c).2
                    };
                    let second = (slope(psi + h) - slope(psi - h)) / (2.0 * h);
                    let (smin, cmin) = (psi - h, psi + h);
                    let d_min = unit
                        .root_argument(smin.cos().powi(2))
                        .min(unit.root_argument(cmin.cos().powi(2)))
                        .min(unit.root_argument(c * c));
                    assert!(
                        second.abs() <= unit.bounds(d_min)[2] * 1.01,
                        "λ = {lambda}, ψ = {psi}: {second} > {}",
                        unit.bounds(d_min)[2]
                    );
                }
            }
        }
    }
}

#[test]
fn output_sizes_are_checked_before_any_preparation() {
    // A grid far longer than the buffer: refused before its seeds (len/1024 of them)
    // are computed; designs × points past usize: refused, not wrapped into a match.
    let design = [Design::new(0.3, 1.0, 1.0, 0.0).unwrap()];
    let phases = Phases::single();
    let huge = UniformGrid::new(0.0, 1e-9, usize::MAX / 2).unwrap();
    let mut out = [0.0; 4];
    let force = Quantity::GeneralizedForce;
    let error = evaluate(force, &design, &phases, huge, &mut out, Parallelism::SERIAL);
    assert!(matches!(
        error,
        Err(crate::MechanismError::LengthMismatch { .. })
    ));
    let three = [design[0]; 3];
    let error = evaluate(force, &three, &phases, huge, &mut out, Parallelism::SERIAL);
    assert!(matches!(error, Err(crate::MechanismError::TooLarge { .. })));
}

/// The portable clone (no FMA) cannot be reached through dispatch on a machine with
/// FMA: run both arithmetics directly, on points and on a uniform grid.
#[test]
fn fused_and_unfused_arithmetic_agree() {
    let grid = UniformGrid::new(-1.0, 0.0123, 3001).unwrap();
    let points = grid.points();
    let rotations = Rotations::new(&grid, 1, Parallelism::SERIAL);
    for cranks in [1, 3, 8] {
        let phases =
            Phases::new(&crank_phases(cranks, Strokes::Four, Acting::Double).unwrap()).unwrap();
        for design in [
            Design::new(0.0, 1.2, 0.7, -0.3).unwrap(),
            Design::new(0.9, -0.4, 1.5, 0.2).unwrap(),
        ] {
            let units = [Coefficients::new(&design)];
            let scale = 2.0 * cranks as f64 * 10.0 * (design.u1.abs() + design.u2.abs());
            for run in [
                Run::points(&points),
                Run::Grid(GridAngles {
                    rotations: &rotations,
                    first: 0,
                }),
            ] {
                let (mut fused, mut unfused) = (vec![0.0; 3001], vec![0.0; 3001]);
                sum_over_cranks::<Force, Fused, _>(&units, &phases, run, Unweighted, &mut fused);
                sum_over_cranks::<Force, Unfused, _>(
                    &units,
                    &phases,
                    run,
                    Unweighted,
                    &mut unfused,
                );
                let (mut energy_fused, mut energy_unfused) = (vec![0.0; 3001], vec![0.0; 3001]);
                sum_over_cranks::<Energy, Fused, _>(
                    &units,
                    &phases,
                    run,
                    Unweighted,
                    &mut energy_fused,
                );
                sum_over_cranks::<Energy, Unfused, _>(
                    &units,
                    &phases,
                    run,
                    Unweighted,
                    &mut energy_unfused,
                );
                let pairs = fused.iter().zip(&unfused);
                for (f, u) in pairs.chain(energy_fused.iter().zip(&energy_unfused)) {
                    assert!((f - u).abs() <= 64.0 * f64::EPSILON * scale, "{f} {u}");
                }
                assert_ne!(
                    fused, unfused,
                    "the two arithmetics should differ somewhere"
                );
            }
        }
    }
}

/// Six cranks, each its own unit: a general engine's sum.
fn six_units() -> (Vec<Coefficients>, Phases) {
    let phases = Phases::new(&[0.0, 2.1, 4.2, 1.05, 3.15, 5.25]).unwrap();
    let units = (0..6)
        .map(|j| {
            let j = j as f64;
            Coefficients::new(
                &Design::new(0.2 + 0.1 * j, 0.3 * j - 0.7, 1.0 + j, 0.5 - 0.2 * j).unwrap(),
            )
        })
        .collect();
    (units, phases)
}

/// Angles of no pattern, some far out (the reduction's long path) and some negative.
fn scattered(count: usize) -> Vec<f64> {
    (0..count)
        .map(|i| {
            let i = i as f64;
            (i * 2.399_963).sin() * 40.0 + if i as usize % 7 == 3 { 3e6 } else { 0.0 }
        })
        .collect()
}

#[test]
fn a_point_has_the_same_value_in_a_run_of_any_length() {
    // A run's tail is taken in narrower blocks than its whole blocks (one point alone in a
    // block of one): each point's value must be the one it has alone, bit for bit.
    let (units, phases) = six_units();
    let points = scattered(53);
    let alone = |p: &f64| {
        let mut out = [0.0];
        sum_over_cranks::<Force, Fused, _>(
            &units,
            &phases,
            Run::points(std::slice::from_ref(p)),
            Unweighted,
            &mut out,
        );
        out[0]
    };
    let expected: Vec<f64> = points.iter().map(alone).collect();
    for start in [0, 1, 5] {
        for len in (1..=points.len() - start).step_by(3) {
            let run = &points[start..start + len];
            let mut out = vec![0.0; len];
            sum_over_cranks::<Force, Fused, _>(
                &units,
                &phases,
                Run::points(run),
                Unweighted,
                &mut out,
            );
            for (i, value) in out.iter().enumerate() {
                assert_eq!(
                    value.to_bits(),
                    expected[start + i].to_bits(),
                    "point {} of a run of {len}",
                    start + i
                );
            }
        }
    }
}

#[test]
fn a_weighted_run_is_each_cranks_products_summed_in_crank_order() {
    // The gas torque Σ_j F_j(φ) v_j(φ) in one pass: the same doubles as one run per crank and
    // a running sum of the products, on points and on a uniform grid, in runs of any length.
    let (units, phases) = six_units();
    let points = scattered(41);
    let grid = UniformGrid::new(-1.0, 0.0123, 41).unwrap();
    let rotations = Rotations::new(&grid, 1, Parallelism::SERIAL);
    let n = points.len();
    let weights: Vec<f64> = (0..units.len() * n)
        .map(|i| (i as f64 * 0.77).cos() * 1e4)
        .collect();
    for len in [1, 3, 4, 16, 17, 41] {
        for first in [0, n - len] {
            let runs = [
                Run::points(&points[first..first + len]),
                Run::Grid(GridAngles {
                    rotations: &rotations,
                    first,
                }),
            ];
            for run in runs {
                let mut expected = vec![0.0; len];
                let mut term = vec![0.0; len];
                for (j, unit) in units.iter().enumerate() {
                    sum_over_cranks::<Force, Fused, _>(
                        std::slice::from_ref(unit),
                        &phases.one(j),
                        run,
                        Unweighted,
                        &mut term,
                    );
                    for (i, (e, t)) in expected.iter_mut().zip(&term).enumerate() {
                        *e += weights[j * n + first + i] * t;
                    }
                }
                let mut found = vec![0.0; len];
                let rows = RowWeights {
                    values: &weights,
                    stride: n,
                    first,
                };
                sum_over_cranks::<Force, Fused, _>(&units, &phases, run, rows, &mut found);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&found), bits(&expected), "a run of {len} from {first}");
            }
        }
    }
}
