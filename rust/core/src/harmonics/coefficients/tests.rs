use super::*;

#[test]
fn paper_coefficients_of_lambda_2() {
    // Λ_2 = λ/2 + λ³/8 + 15λ⁵/256 + 35λ⁷/1024 + 735λ⁹/32768 + 2079λ¹¹/131072
    let expected = [
        (1, 2),
        (1, 8),
        (15, 256),
        (35, 1024),
        (735, 32768),
        (2079, 131072),
    ];
    for (j, &(p, q)) in expected.iter().enumerate() {
        assert_eq!(paper_coefficient(1, j as u32), Ok((p, q)));
    }
    assert_eq!(paper_coefficient(2, 1), Ok((-1, 16)));
    assert_eq!(paper_coefficient(6, 5), Ok((-63, 524288)));
    assert_eq!(paper_coefficient(3, 1), Ok((0, 1)));
    assert!(paper_coefficient(1, 21).is_err());
}

/// λ from 0 to the largest double below 1, and t, w at each.
const RATIOS: [f64; 13] = [
    0.0,
    1e-8,
    0.3,
    0.7,
    0.9,
    0.986,
    0.99,
    0.9999,
    0.99999,
    1.0 - 1e-8,
    1.0 - 1e-12,
    1.0 - 1.0 / (1u64 << 52) as f64,
    1.0 - 1.0 / (1u64 << 53) as f64,
];

#[test]
fn lambda_work_is_bounded_for_every_crank_ratio() {
    // Issue 13, item 4: at λ = 1 − 2⁻⁵³ the ₂F₁ power series ran to its 10⁷-term cap for
    // each of ~1000 harmonics (40 s per series). Every regime now takes a bounded
    // number of terms or recurrence steps per harmonic.
    for &lambda in &RATIOS {
        let mut lambdas = ExactLambdas::new(lambda);
        let t = lambdas.t();
        let bound = |m: f64| t.powf(2.0 * m - 1.0) / (1.0 - t.powi(4)).max(f64::MIN_POSITIVE);
        for m in 1..=(MAX_HARMONIC / 2) {
            let value = lambdas.next().unwrap();
            assert!(value.is_finite(), "λ = {lambda}, m = {m}");
            assert!(
                value.abs() <= bound(m as f64) * (1.0 + 1e-12),
                "λ = {lambda}, m = {m}"
            );
        }
        assert!(
            lambdas.work() <= 64 * MAX_HARMONIC as u64,
            "λ = {lambda}: {} terms for {} harmonics",
            lambdas.work(),
            MAX_HARMONIC / 2
        );
    }
    // A table far beyond any series, near 1: still O(1) per entry.
    for &lambda in &RATIOS[7..] {
        let mut lambdas = ExactLambdas::with_reach(lambda, 200_000);
        for _ in 0..100_000 {
            lambdas.next();
        }
        assert!(
            lambdas.work() <= 200 * 100_000,
            "λ = {lambda}: {}",
            lambdas.work()
        );
    }
}

/// F_m after `m` steps, then by the power series for the same m (forced, for a check).
fn regimes(lambda: f64, m: u64) -> (f64, f64) {
    let mut lambdas = ExactLambdas::with_reach(lambda, 4096);
    for _ in 0..m {
        lambdas.next();
    }
    let found = lambdas.previous;
    (found, lambdas.power_series())
}

#[test]
fn the_three_regimes_agree_where_they_meet() {
    // z > ½ with the power series still affordable (≤ 10⁴ terms): the expansion about
    // z = 1 (m·w ≤ 2) and Miller's blocks (m·w > 2) against it, across the switch.
    for lambda in [0.987, 0.99, 0.995, 0.999, 0.9995] {
        let w = 1.0 - ExactLambdas::new(lambda).z.hi;
        let switch = (2.0 / w) as u64;
        for m in [
            1,
            2,
            switch.saturating_sub(1).max(1),
            switch,
            switch + 1,
            switch + 2,
            300,
            1000,
        ] {
            let (found, series) = regimes(lambda, m);
            assert!(
                (found - series).abs() <= 8.0 * f64::EPSILON * series,
                "λ = {lambda}, m = {m} (switch {switch}): {found} vs {series}"
            );
        }
    }
}

#[test]
fn exact_matches_paper_series_for_small_lambda() {
    // The first omitted term, λ¹³, is λ^{14−n} relative to Λ_n: negligible at λ = 1e-8.
    let lambda = 1e-8;
    let (mut exact, mut paper) = ([0.0; 13], [0.0; 13]);
    lambda_exact(lambda, &mut exact);
    lambda_paper(lambda, &mut paper);
    for n in (2..=12).step_by(2) {
        let scale = lambda.powi(n as i32 - 1);
        assert!((exact[n] - paper[n]).abs() <= 1e-14 * scale, "n={n}");
    }
}

#[test]
fn lambda_table_rows_across_chunks() {
    // Rows of 10001 entries span the parallel chunks of 8192: each must still be whole.
    let ratios = [0.2, 0.6, 0.95];
    for paper in [false, true] {
        let serial = lambda_table(paper, &ratios, 10_000, Parallelism::SERIAL).unwrap();
        let parallel = lambda_table(paper, &ratios, 10_000, Parallelism { threshold: 0 }).unwrap();
        assert_eq!(serial, parallel);
        for (row, &lambda) in serial.chunks(10_001).zip(&ratios) {
            let mut direct = vec![0.0; 10_001];
            if paper {
                lambda_paper(lambda, &mut direct)
            } else {
                lambda_exact(lambda, &mut direct)
            }
            assert_eq!(row, direct.as_slice());
        }
    }
    assert!(lambda_table(false, &[1.0], 4, Parallelism::SERIAL).is_err());
    assert!(lambda_table(false, &[0.1], usize::MAX, Parallelism::SERIAL).is_err());
}

#[test]
fn tables_too_large_to_allocate_are_refused_by_name() {
    for n_max in [usize::MAX, usize::MAX / 2, 1 << 62] {
        let error = lambda_table(false, &[0.3], n_max, Parallelism::SERIAL).unwrap_err();
        assert!(error.to_string().starts_with("n_max = "), "{error}");
        assert!(crate::harmonics::PhaseSums::new(&[0.0, 1.0], n_max).is_err());
    }
    // Many rows of a moderate width overflow only as a product.
    let ratios = vec![0.3; 1 << 20];
    assert!(lambda_table(true, &ratios, 1 << 50, Parallelism::SERIAL).is_err());
}
