//! A vectorisable sin/cos for the kernels.
//!
//! `f64::sin_cos` is two scalar libm calls (~20 ns per point here), which would dominate
//! every kernel. This one is branch-free straight-line arithmetic that LLVM vectorises
//! across a block: Cody–Waite reduction by π/2 (π/2 split in three parts so that
//! q·part is exact for |q| < 2^20) and Taylor polynomials on |r| ≤ π/4 whose truncation
//! error (< 1e-19) is far below one ulp. Arguments beyond `REDUCTION_LIMIT` (where the
//! three-part reduction loses bits) fall back to libm element by element.
//!
//! Every multiply-add goes through [`MulAdd`]: the kernels' AVX2 and AVX-512 clones fuse
//! them (one rounding, one instruction: the polynomials and crank terms are chains of
//! them), the portable fallback does not (a software fma would be slow there). Within one
//! machine every point sees the same operations whatever the blocking or thread count.

use std::f64::consts::FRAC_2_PI;

use multiversion::multiversion;
use multiversion::target::target_cfg_f;

/// a·b + c, fused or not: the kernels are generic over it and pick one per instruction set.
pub(crate) trait MulAdd {
    fn mul_add(a: f64, b: f64, c: f64) -> f64;
    /// a·b − p exactly, for p = fl(a·b) (an error-free product: one FMA, or Dekker's
    /// splitting where there is none).
    fn product_error(a: f64, b: f64, p: f64) -> f64;
}

/// One rounding (an FMA instruction where the clone has one).
pub(crate) struct Fused;
/// Two roundings: for targets without FMA.
pub(crate) struct Unfused;

impl MulAdd for Fused {
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
    #[inline(always)]
    fn product_error(a: f64, b: f64, p: f64) -> f64 {
        a.mul_add(b, -p)
    }
}

impl MulAdd for Unfused {
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
    #[inline(always)]
    fn product_error(a: f64, b: f64, p: f64) -> f64 {
        // Dekker: a = ah + al, b = bh + bl with halves of ≤ 26 bits, products exact.
        let split = |x: f64| {
            let t = 134_217_729.0 * x; // 2^27 + 1
            let hi = t - (t - x);
            (hi, x - hi)
        };
        let ((ah, al), (bh, bl)) = (split(a), split(b));
        let error = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
        // The split overflows beyond 2^996: there an ulp of the product is far above any
        // angle's meaning, and the residual is taken as 0 rather than NaN.
        if error.is_finite() {
            error
        } else {
            0.0
        }
    }
}

/// π/2 = PIO2_HI + PIO2_MID + PIO2_LO; the first two carry 33 significant bits.
const PIO2_HI: f64 = 1.570_796_326_734_125_6; // 0x1.921fb544p+0
const PIO2_MID: f64 = 6.077_100_506_303_966e-11; // 0x1.0b4611a6p-34
const PIO2_LO: f64 = 2.022_266_248_795_950_6e-21; // 0x1.3198a2e037073p-69

/// Adding 1.5·2^52 rounds to the nearest integer and leaves it in the low mantissa bits.
const ROUND_MAGIC: f64 = 6_755_399_441_055_744.0;

/// Above this |x| the reduction is handed to libm.
pub(crate) const REDUCTION_LIMIT: f64 = 1.0e5;

// Taylor coefficients ±1/n!; every n! here (n ≤ 18) is exact in f64.
const S3: f64 = -1.0 / 6.0;
const S5: f64 = 1.0 / 120.0;
const S7: f64 = -1.0 / 5040.0;
const S9: f64 = 1.0 / 362_880.0;
const S11: f64 = -1.0 / 39_916_800.0;
const S13: f64 = 1.0 / 6_227_020_800.0;
const S15: f64 = -1.0 / 1_307_674_368_000.0;
const S17: f64 = 1.0 / 355_687_428_096_000.0;
const C2: f64 = -0.5;
const C4: f64 = 1.0 / 24.0;
const C6: f64 = -1.0 / 720.0;
const C8: f64 = 1.0 / 40320.0;
const C10: f64 = -1.0 / 3_628_800.0;
const C12: f64 = 1.0 / 479_001_600.0;
const C14: f64 = -1.0 / 87_178_291_200.0;
const C16: f64 = 1.0 / 20_922_789_888_000.0;
const C18: f64 = -1.0 / 6_402_373_705_728_000.0;

/// (sin x, cos x) for |x| ≤ `REDUCTION_LIMIT`; NaN for non-finite x (unfused arithmetic).
#[cfg(test)]
fn sincos_reduced(x: f64) -> (f64, f64) {
    sincos_with::<Unfused>(x)
}

/// Horner's rule Σ c_i z^i with multiply-adds.
#[inline(always)]
fn horner<M: MulAdd>(z: f64, coefficients: &[f64]) -> f64 {
    let (last, rest) = coefficients.split_last().expect("non-empty");
    rest.iter()
        .rev()
        .fold(*last, |acc, &c| M::mul_add(acc, z, c))
}

/// (sin x, cos x) for |x| ≤ `REDUCTION_LIMIT`; NaN for non-finite x.
#[inline(always)]
pub(crate) fn sincos_with<M: MulAdd>(x: f64) -> (f64, f64) {
    let shifted = x * FRAC_2_PI + ROUND_MAGIC;
    let quadrant = shifted.to_bits(); // q mod 2^51 in the low bits, two's complement
    let q = shifted - ROUND_MAGIC;
    // q·PIO2_HI and q·PIO2_MID are exact (33-bit parts, |q| < 2^20): fusing changes
    // nothing but the count of instructions (one fewer each). q·PIO2_LO is rounded, and
    // stays a product of its own.
    let r = M::mul_add(-q, PIO2_MID, M::mul_add(-q, PIO2_HI, x)) - q * PIO2_LO;
    let z = r * r;
    let sin_poly = horner::<M>(z, &[S3, S5, S7, S9, S11, S13, S15, S17]);
    let sin_r = M::mul_add(r * z, sin_poly, r);
    let cos_poly = horner::<M>(z, &[C2, C4, C6, C8, C10, C12, C14, C16, C18]);
    let cos_r = M::mul_add(z, cos_poly, 1.0);
    // sin(qπ/2 + r), cos(qπ/2 + r): swap for odd q, then flip signs by quadrant.
    let (s, c) = if quadrant & 1 == 0 {
        (sin_r, cos_r)
    } else {
        (cos_r, sin_r)
    };
    let s = f64::from_bits(s.to_bits() ^ ((quadrant & 2) << 62));
    let c = f64::from_bits(c.to_bits() ^ ((quadrant.wrapping_add(1) & 2) << 62));
    (s, c)
}

/// sin and cos of every element of `x` into `sin` and `cos` (all of one length).
#[inline(always)]
pub(crate) fn sincos_block<M: MulAdd>(x: &[f64], sin: &mut [f64], cos: &mut [f64]) {
    let n = x.len();
    let (sin, cos) = (&mut sin[..n], &mut cos[..n]);
    for i in 0..n {
        let (s, c) = sincos_with::<M>(x[i]);
        sin[i] = s;
        cos[i] = c;
    }
    // NaN and ±inf already give NaN; only large finite arguments need libm. Test the
    // block at once (a vectorised reduction), not element by element.
    let any_large = x
        .iter()
        .fold(false, |any, v| any | (v.abs() > REDUCTION_LIMIT));
    if any_large {
        for i in 0..n {
            if x[i].abs() > REDUCTION_LIMIT {
                (sin[i], cos[i]) = x[i].sin_cos();
            }
        }
    }
}

/// (sin x, cos x) of N lanes, as `sincos_block` computes them, returned by value: the
/// lanes stay in registers (results written through a slice are stored to the stack and
/// loaded back at once, a store-forwarding stall a block), and only the rare block with
/// a large finite argument takes libm's values, on a path of its own.
#[inline(always)]
pub(crate) fn sincos_lanes<M: MulAdd, const N: usize>(x: &[f64; N]) -> ([f64; N], [f64; N]) {
    let (mut sin, mut cos) = ([0.0; N], [0.0; N]);
    for l in 0..N {
        (sin[l], cos[l]) = sincos_with::<M>(x[l]);
    }
    let any_large = x
        .iter()
        .fold(false, |any, v| any | (v.abs() > REDUCTION_LIMIT));
    if any_large {
        (sin, cos) = large_by_libm(x, sin, cos);
    }
    (sin, cos)
}

/// The lanes of |x| > `REDUCTION_LIMIT` from libm, the others as given.
#[cold]
#[inline(never)]
fn large_by_libm<const N: usize>(
    x: &[f64; N],
    mut sin: [f64; N],
    mut cos: [f64; N],
) -> ([f64; N], [f64; N]) {
    for l in 0..N {
        if x[l].abs() > REDUCTION_LIMIT {
            (sin[l], cos[l]) = x[l].sin_cos();
        }
    }
    (sin, cos)
}

/// (sin x, cos x) of every element, as the kernels on this machine compute them (tables
/// shared across designs and the seeds of uniform grids).
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
pub(crate) fn sincos_table(x: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let (mut sin, mut cos) = (vec![0.0; x.len()], vec![0.0; x.len()]);
    if target_cfg_f!(target_feature = "fma") {
        sincos_block::<Fused>(x, &mut sin, &mut cos);
    } else {
        sincos_block::<Unfused>(x, &mut sin, &mut cos);
    }
    (sin, cos)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_libm() {
        // Absolute error against libm, in units of 2^-52: the kernels need accuracy
        // relative to the amplitude (|sin|, |cos| ≤ 1), not relative to tiny values.
        let mut worst: f64 = 0.0;
        let mut x = -2000.0;
        while x < 2000.0 {
            for (s, c) in [sincos_with::<Unfused>(x), sincos_with::<Fused>(x)] {
                worst = worst.max((s - x.sin()).abs()).max((c - x.cos()).abs());
            }
            x += 0.000_731_3;
        }
        assert!(
            worst <= 2.0 * f64::EPSILON,
            "worst absolute error {worst:e}"
        );
    }

    #[test]
    fn exact_points_and_non_finite() {
        assert_eq!(sincos_reduced(0.0), (0.0, 1.0));
        assert_eq!(sincos_with::<Fused>(0.0), (0.0, 1.0));
        let (table_sin, table_cos) = sincos_table(&[0.0, -0.0, 0.5]);
        assert_eq!((table_sin[0], table_cos[0]), (0.0, 1.0));
        assert_eq!((table_sin[1], table_cos[1]), (-0.0, 1.0));
        assert!((table_sin[2] - 0.5_f64.sin()).abs() <= 2.0 * f64::EPSILON);
        let (s, c) = sincos_reduced(-0.0);
        assert_eq!((s, c), (-0.0, 1.0));
        let mut s = [0.0; 4];
        let mut c = [0.0; 4];
        sincos_block::<Unfused>(
            &[f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1.0e9],
            &mut s,
            &mut c,
        );
        assert!(s[..3].iter().chain(&c[..3]).all(|v| v.is_nan()));
        assert_eq!((s[3], c[3]), 1.0e9_f64.sin_cos());
    }
}
