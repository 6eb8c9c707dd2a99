use super::*;

/// (sin, cos) of m·x exactly rounded-ish: m·x as an exact double-double, libm on hi
/// (exact range reduction at any size), lo rotated in full.
fn reference_sincos(x: f64, m: usize) -> (f64, f64) {
    let angle = DoubleDouble::product(x, m as f64);
    let (hs, hc) = angle.hi.sin_cos();
    let (ls, lc) = angle.lo.sin_cos();
    (hs * lc + hc * ls, hc * lc - hs * ls)
}

/// The worst error (units of ε) of the rotations against `reference_sincos` at the
/// grid's own points, over the first and the last tenth of the grid.
fn worst_errors<M: MulAdd>(grid: &UniformGrid, multiplier: usize) -> (f64, f64) {
    let rotations = Rotations::new(grid, multiplier, Parallelism::SERIAL);
    let (len, mut head, mut tail) = (grid.len, 0.0_f64, 0.0_f64);
    for first in (0..len).step_by(16) {
        let (s, c) = rotations.block::<M, 16>(first);
        for l in 0..16.min(len - first) {
            let i = first + l;
            let (es, ec) = reference_sincos(grid.point(i), multiplier);
            let error = (s[l] - es).abs().max((c[l] - ec).abs()) / f64::EPSILON;
            if i <= len / 10 {
                head = head.max(error);
            }
            if i >= len - len / 10 - 1 {
                tail = tail.max(error);
            }
        }
    }
    (head, tail)
}

#[test]
fn rotations_are_exact_at_the_exposed_points_without_drift() {
    // Long grids over many revolutions, grids that start anywhere — far out too, where
    // an ulp of φ is large (issue 13: 1.1e-4 off at start = 1e15) — and high harmonics:
    // the values are those at the doubles the grid exposes, the error at the far end no
    // larger than at the start.
    for &(start, step, len) in &[
        (0.0, std::f64::consts::TAU / 1_000_003.0, 1_000_003),
        (-3.7, 0.013, 200_000),
        (1234.5, 1.0e-3, 100_000),
        (1.0e6, 0.01, 3000),
        (-7.5e8, 0.37, 5000),
        (1.0e12, 0.01, 3000),
        (1.0e15, 0.01, 3000),
        (-3.0e17, 123.0, 3000),
    ] {
        let grid = UniformGrid::new(start, step, len).unwrap();
        for multiplier in [1, 6, 24, 2048] {
            for (head, tail) in [
                worst_errors::<Unfused>(&grid, multiplier),
                worst_errors::<Fused>(&grid, multiplier),
            ] {
                assert!(head < 5.0, "{start} {step} m={multiplier}: head {head}");
                assert!(tail < 5.0, "{start} {step} m={multiplier}: tail {tail}");
            }
        }
    }
}

#[test]
fn the_rounding_of_each_point_is_exact() {
    // d = x − (start + i·step) against the exact rational value, in i128 units of 2^-70
    // for grids whose doubles are all multiples of 2^-70 and below 2^50.
    let exact = |v: f64| (v * 2f64.powi(70)) as i128;
    for &(start, step) in &[(0.1, 0.3), (1.0e6 + 0.1, 1.0e-3), (3.0, 7.0e-5)] {
        for i in [0_u32, 1, 7, 1000, 12345] {
            let i = i as f64;
            let x = start + i * step;
            let expected = exact(x) - (exact(start) + exact(step) * i as i128);
            for (t, e) in [
                rounding::<Unfused>(start, step, i),
                rounding::<Fused>(start, step, i),
            ] {
                assert_eq!(exact(t) + exact(e), expected, "{start} {step} {i}");
            }
        }
    }
}

#[test]
fn a_point_does_not_depend_on_the_block_it_is_computed_in() {
    let grid = UniformGrid::new(0.25, 0.001, 5000).unwrap();
    let rotations = Rotations::new(&grid, 1, Parallelism::SERIAL);
    let (s16, c16) = (0..5000)
        .step_by(16)
        .map(|f| rotations.block::<Unfused, 16>(f))
        .fold((vec![], vec![]), |(mut s, mut c), (bs, bc)| {
            s.extend_from_slice(&bs);
            c.extend_from_slice(&bc);
            (s, c)
        });
    for first in [0, 1, 7, 1013, 1020, 4990] {
        let (s, c) = rotations.block::<Unfused, 8>(first);
        for l in 0..8.min(5000 - first) {
            assert_eq!(s[l].to_bits(), s16[first + l].to_bits());
            assert_eq!(c[l].to_bits(), c16[first + l].to_bits());
        }
    }
    // Index 0 is the exact sincos of start.
    let (s, c) = rotations.block::<Unfused, 1>(0);
    let (ts, tc) = sincos_table(&[0.25]);
    assert_eq!((s[0], c[0]), (ts[0], tc[0]));
}

#[test]
fn seeds_do_not_depend_on_the_thread_count() {
    let grid = UniformGrid::new(0.1, 1.0e-5, 3_000_001).unwrap();
    let serial = Rotations::new(&grid, 7, Parallelism::SERIAL);
    let parallel = Rotations::new(&grid, 7, Parallelism { threshold: 0 });
    assert_eq!(serial.seed_sin, parallel.seed_sin);
    assert_eq!(serial.seed_cos, parallel.seed_cos);
    assert_eq!(serial.seed_sin.len(), 3_000_001_usize.div_ceil(SPAN));
}

#[test]
fn rejects_non_finite_grids() {
    assert!(UniformGrid::new(f64::NAN, 0.1, 3).is_err());
    assert!(UniformGrid::new(0.0, f64::INFINITY, 3).is_err());
    assert!(UniformGrid::new(0.0, 1e308, 10).is_err());
    assert!(UniformGrid::new(0.0, 1e308, 1).is_ok());
    assert_eq!(
        UniformGrid::new(0.5, 0.25, 3).unwrap().points(),
        vec![0.5, 0.75, 1.0]
    );
}
