//! Identities the closed-form kernels must satisfy, independent of how they are computed:
//! Q = dU/dφ and dQ/dφ by central differences, periodicity, crank-set symmetry, the λ → 0
//! limit, the zero level, and serial == parallel bit for bit.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use multicrank_core::{
    crank_phases, evaluate, evaluate_one, Acting, Design, Parallelism, Phases, Quantity, Strokes,
};

fn grid(n: usize, from: f64, to: f64) -> Vec<f64> {
    (0..n)
        .map(|i| from + (to - from) * i as f64 / n as f64)
        .collect()
}

fn designs() -> Vec<Design> {
    let mut out = Vec::new();
    for &lambda in &[0.0, 1e-7, 0.25, 0.45, 0.8, 0.95] {
        for &gamma in &[0.0, FRAC_PI_2, -FRAC_PI_2, PI, 0.7, -2.3] {
            out.push(Design::new(lambda, gamma, 0.9, -0.35).expect("valid design"));
        }
    }
    out
}

/// The natural size of U*, Q* and dQ*/dφ for a design: sums over k cranks of terms that
/// are O(|U1| + |U2|) (times 1/(1 − λ²)^{3/2} at most). Tolerances are relative to it, so a
/// quantity that cancels to zero over the cranks is judged by its rounding noise.
fn natural_scale(d: &Design, cranks: usize) -> f64 {
    cranks as f64 * (d.u1.abs() + d.u2.abs()) / (1.0 - d.crank_ratio * d.crank_ratio).powf(1.5)
}

#[test]
fn force_is_the_derivative_of_energy_and_derivative_of_force() {
    let h = 1e-5;
    let phi = grid(97, -7.0, 7.0);
    let plus: Vec<f64> = phi.iter().map(|p| p + h).collect();
    let minus: Vec<f64> = phi.iter().map(|p| p - h).collect();
    for cranks in [1, 3, 8] {
        let phases =
            Phases::new(&crank_phases(cranks, Strokes::Four, Acting::Single).unwrap()).unwrap();
        for d in designs() {
            for (integral, derivative) in [
                (Quantity::PotentialEnergy, Quantity::GeneralizedForce),
                (Quantity::GeneralizedForce, Quantity::ForceDerivative),
            ] {
                let up = evaluate_one(integral, &d, &phases, &plus);
                let down = evaluate_one(integral, &d, &phases, &minus);
                let exact = evaluate_one(derivative, &d, &phases, &phi);
                let scale = natural_scale(&d, cranks as usize);
                for i in 0..phi.len() {
                    let numeric = (up[i] - down[i]) / (2.0 * h);
                    // Central-difference truncation (h² f'''/6) and rounding (ε/h) bound this.
                    assert!(
                        (numeric - exact[i]).abs() <= 1e-7 * scale,
                        "{derivative:?} k={cranks} {d:?} phi={}: {numeric} vs {}",
                        phi[i],
                        exact[i]
                    );
                }
            }
        }
    }
}

#[test]
fn periodic_and_symmetric_under_crank_shift() {
    let phi = grid(211, -3.0, 3.0);
    for cranks in 1..=12 {
        let alphas = crank_phases(cranks, Strokes::Two, Acting::Single).unwrap();
        let phases = Phases::new(&alphas).unwrap();
        let step = TAU / cranks as f64;
        for d in designs() {
            for quantity in [Quantity::PotentialEnergy, Quantity::GeneralizedForce] {
                let base = evaluate_one(quantity, &d, &phases, &phi);
                let scale = natural_scale(&d, cranks as usize);
                for shift in [TAU, step] {
                    let moved: Vec<f64> = phi.iter().map(|p| p + shift).collect();
                    let shifted = evaluate_one(quantity, &d, &phases, &moved);
                    for (a, b) in base.iter().zip(&shifted) {
                        assert!((a - b).abs() <= 1e-13 * scale, "k={cranks} shift={shift}");
                    }
                }
            }
        }
    }
}

#[test]
fn zero_level_and_infinite_rod_limit() {
    let phases = Phases::single();
    for d in designs() {
        let at_zero = evaluate_one(Quantity::PotentialEnergy, &d, &phases, &[0.0]);
        assert_eq!(at_zero[0], 0.0);
    }
    // λ = 0: the piston moves harmonically, s/r = 1 − cos φ, so
    // U* = U2[sin(φ+γ) − sin γ] − U1(1 − cos φ) sin γ and Q = U2 cos(φ+γ) − U1 sin φ sin γ.
    let (u1, u2, gamma) = (0.7, 0.2, 1.1);
    let d = Design::new(0.0, gamma, u1, u2).unwrap();
    let phi = grid(50, -4.0, 4.0);
    let energy = evaluate_one(Quantity::PotentialEnergy, &d, &phases, &phi);
    let force = evaluate_one(Quantity::GeneralizedForce, &d, &phases, &phi);
    for (i, p) in phi.iter().enumerate() {
        let u = u2 * ((p + gamma).sin() - gamma.sin()) - u1 * (1.0 - p.cos()) * gamma.sin();
        let q = u2 * (p + gamma).cos() - u1 * p.sin() * gamma.sin();
        assert!((energy[i] - u).abs() < 1e-15, "{} vs {u}", energy[i]);
        assert!((force[i] - q).abs() < 1e-15, "{} vs {q}", force[i]);
    }
}

#[test]
fn horizontal_cylinders_feel_only_the_rotating_unbalance() {
    // γ = 0 and γ = π: the piston moves horizontally, so U1 drops out (eq. 19, 21).
    let phi = grid(64, 0.0, TAU);
    let phases = Phases::new(&crank_phases(3, Strokes::Two, Acting::Single).unwrap()).unwrap();
    for gamma in [0.0, PI] {
        let with = evaluate_one(
            Quantity::GeneralizedForce,
            &Design::new(0.4, gamma, 5.0, 0.3).unwrap(),
            &phases,
            &phi,
        );
        let without = evaluate_one(
            Quantity::GeneralizedForce,
            &Design::new(0.4, gamma, 0.0, 0.3).unwrap(),
            &phases,
            &phi,
        );
        for (a, b) in with.iter().zip(&without) {
            assert!((a - b).abs() < 1e-14);
        }
    }
}

#[test]
fn serial_equals_parallel_bit_for_bit() {
    let phases = Phases::new(&crank_phases(7, Strokes::Four, Acting::Double).unwrap()).unwrap();
    let designs = designs();
    for n_phi in [1, 255, 257, 4099, 50_001] {
        let phi = grid(n_phi, -20.0, 20.0);
        let mut serial = vec![0.0; designs.len() * n_phi];
        let mut parallel = vec![1.0; designs.len() * n_phi];
        for quantity in [
            Quantity::PotentialEnergy,
            Quantity::GeneralizedForce,
            Quantity::ForceDerivative,
        ] {
            evaluate(
                quantity,
                &designs,
                &phases,
                &phi,
                &mut serial,
                Parallelism::SERIAL,
            )
            .unwrap();
            evaluate(
                quantity,
                &designs,
                &phases,
                &phi,
                &mut parallel,
                Parallelism { threshold: 0 },
            )
            .unwrap();
            assert!(serial
                .iter()
                .zip(&parallel)
                .all(|(a, b)| a.to_bits() == b.to_bits()));
            // And each row equals the one-design evaluation.
            for (row, d) in designs.iter().enumerate().step_by(7) {
                let alone = evaluate_one(quantity, d, &phases, &phi);
                assert_eq!(&serial[row * n_phi..(row + 1) * n_phi], &alone[..]);
            }
        }
    }
}

#[test]
fn rejects_bad_requests() {
    let phases = Phases::single();
    let d = [Design::new(0.3, 0.0, 1.0, 1.0).unwrap()];
    let mut out = vec![0.0; 3];
    let err = evaluate(
        Quantity::GeneralizedForce,
        &d,
        &phases,
        &[0.0; 4],
        &mut out,
        Parallelism::SERIAL,
    )
    .unwrap_err();
    assert!(err.to_string().contains("out"));
    assert!(Phases::new(&[]).is_err());
    assert!(Phases::new(&[0.0, f64::NAN])
        .unwrap_err()
        .to_string()
        .contains("phases"));
}
