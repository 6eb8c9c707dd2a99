//! The Fourier path against the closed form, the harmonic rules against phase sums,
//! and serial == parallel for the series and the extrema.

use std::f64::consts::{FRAC_PI_2, TAU};

use multicrank_core::{
    all_energy_extrema, build_series, crank_phases, evaluate, evaluate_series, harmonic_survives,
    Acting, Design, Parallelism, PhaseSums, Phases, Quantity, SeriesKind, Strokes,
};

fn grid(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| -TAU + 2.0 * TAU * i as f64 / n as f64)
        .collect()
}

fn machines() -> Vec<Vec<f64>> {
    let mut sets = Vec::new();
    for k in 1..=12 {
        for strokes in [Strokes::Two, Strokes::Four] {
            for acting in [Acting::Single, Acting::Double] {
                sets.push(crank_phases(k, strokes, acting).expect("k >= 1"));
            }
        }
    }
    sets.push(vec![0.0, 0.4, 2.9, 4.0]); // irregular
    sets
}

#[test]
fn series_matches_closed_form() {
    let phi = grid(501);
    let designs: Vec<Design> = [0.0, 0.2, 0.5, 0.8, 0.95]
        .iter()
        .flat_map(|&l| {
            [0.0, 0.6, FRAC_PI_2, 2.0, -1.2].map(|g| Design::new(l, g, 0.8, -0.4).unwrap())
        })
        .collect();
    for alphas in machines() {
        let phases = Phases::new(&alphas).unwrap();
        let series = build_series(SeriesKind::Exact, &designs, &alphas, Parallelism::SERIAL);
        let mut exact = vec![0.0; designs.len() * phi.len()];
        let mut fourier = vec![0.0; designs.len() * phi.len()];
        evaluate(
            Quantity::GeneralizedForce,
            &designs,
            &phases,
            &phi,
            &mut exact,
            Parallelism::SERIAL,
        )
        .unwrap();
        evaluate_series(&series, &phi, &mut fourier, Parallelism::SERIAL).unwrap();
        for (row, d) in designs.iter().enumerate() {
            let range = row * phi.len()..(row + 1) * phi.len();
            let peak = exact[range.clone()]
                .iter()
                .fold(0.0_f64, |m, x| m.max(x.abs()));
            // The closed form's own rounding is ε times the single-crank terms.
            let noise = alphas.len() as f64 * (d.u1.abs() + d.u2.abs())
                / (1.0 - d.crank_ratio.powi(2)).powf(1.5);
            let tolerance = 4e-15 * peak + 2e-15 * noise;
            for i in range {
                assert!(
                    (exact[i] - fourier[i]).abs() <= tolerance,
                    "{alphas:?} {d:?}: {} vs {}",
                    exact[i],
                    fourier[i]
                );
            }
        }
    }
}

#[test]
fn harmonic_rule_agrees_with_phase_sums() {
    for k in 1..=12u64 {
        for strokes in [Strokes::Two, Strokes::Four] {
            for acting in [Acting::Single, Acting::Double] {
                let alphas = crank_phases(k as i64, strokes, acting).unwrap();
                let sums = PhaseSums::new(&alphas, 60).unwrap();
                for n in 1..=60u64 {
                    let carried = n == 1 || n % 2 == 0;
                    let nonzero = sums.cos[n as usize] != 0.0 || sums.sin[n as usize] != 0.0;
                    assert_eq!(
                        harmonic_survives(n, k, strokes, acting),
                        carried && nonzero,
                        "k={k} n={n} {strokes:?} {acting:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn series_and_extrema_serial_equals_parallel() {
    let alphas = crank_phases(5, Strokes::Four, Acting::Single).unwrap();
    let phases = Phases::new(&alphas).unwrap();
    let designs: Vec<Design> = (0..300)
        .map(|i| {
            Design::new(
                0.003 * i as f64,
                0.1 * i as f64,
                0.5,
                0.2 - 0.001 * i as f64,
            )
            .unwrap()
        })
        .collect();
    let phi = grid(3001);
    let serial_series = build_series(SeriesKind::Exact, &designs, &alphas, Parallelism::SERIAL);
    let parallel_series = build_series(
        SeriesKind::Exact,
        &designs,
        &alphas,
        Parallelism { threshold: 0 },
    );
    assert_eq!(serial_series, parallel_series);
    let mut a = vec![0.0; designs.len() * phi.len()];
    let mut b = vec![1.0; designs.len() * phi.len()];
    evaluate_series(&serial_series, &phi, &mut a, Parallelism::SERIAL).unwrap();
    evaluate_series(&serial_series, &phi, &mut b, Parallelism { threshold: 0 }).unwrap();
    assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
    let e1 = all_energy_extrema(&designs, &phases, &serial_series, Parallelism::SERIAL);
    let e2 = all_energy_extrema(
        &designs,
        &phases,
        &serial_series,
        Parallelism { threshold: 0 },
    );
    assert_eq!(e1, e2);
}

#[test]
fn extrema_are_never_below_the_grid() {
    let alphas = crank_phases(3, Strokes::Two, Acting::Single).unwrap();
    let phases = Phases::new(&alphas).unwrap();
    let designs: Vec<Design> = [0.0, 0.3, 0.9]
        .iter()
        .flat_map(|&l| [0.0, 0.9, FRAC_PI_2].map(|g| Design::new(l, g, 1.0, 0.3).unwrap()))
        .collect();
    let series = build_series(SeriesKind::Exact, &designs, &alphas, Parallelism::SERIAL);
    let extrema = all_energy_extrema(&designs, &phases, &series, Parallelism::SERIAL);
    let phi: Vec<f64> = (0..100_000).map(|i| TAU * i as f64 / 100_000.0).collect();
    for (d, e) in designs.iter().zip(&extrema) {
        let mut u = vec![0.0; phi.len()];
        evaluate(
            Quantity::PotentialEnergy,
            std::slice::from_ref(d),
            &phases,
            &phi,
            &mut u,
            Parallelism::SERIAL,
        )
        .unwrap();
        let (lo, hi) = u
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(
            e.min <= lo + 1e-14 && e.max >= hi - 1e-14,
            "{d:?}: {e:?} vs [{lo}, {hi}]"
        );
        assert!(
            e.range() - (hi - lo) <= 1e-9,
            "{d:?}: the grid is dense, so it is close"
        );
    }
}
