//! Closed-form kernels (docs/theory.md, "Potential energy and generalised force"): U_w*(φ), Q_u*(φ) = dU_w*/dφ and dQ_u*/dφ,
//! summed over the cranks ψ_j = φ + α_j.
//!
//! Per point one sincos of φ (or, on a uniform grid, one rotation from exact values: see
//! `grid`); each crank angle follows by rotation with the precomputed (cos α_j, sin α_j).
//! Work is done in register blocks so the per-crank loop vectorises; `multiversion`
//! compiles it for AVX-512 and AVX2 with fused multiply-adds and picks at run time (a
//! portable clone without FMA otherwise), so a generic wheel is fast everywhere. Every
//! output element is computed by the same sequence of IEEE operations whatever the
//! blocking, chunking or thread count, so serial and parallel results are bit-identical.

use multiversion::multiversion;
use multiversion::target::target_cfg_f;

use crate::angles::{padded, AngleSource, Phi, PreparedPhi, Run};
use crate::error::{check_rows_length, Result};
use crate::mechanism::{Design, Phases};
use crate::parallel::{for_each_row_segment, Parallelism};
use crate::trig::{Fused, MulAdd, Unfused};

/// Which closed-form quantity to evaluate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// U_w*(φ), each unit measured from its own ψ = 0 configuration (eq. 3, 12).
    PotentialEnergy,
    /// Q_u*(φ) = +dU_w*/dφ (eq. 13).
    GeneralizedForce,
    /// dQ_u*/dφ, for Newton steps on the extrema of U_w*.
    ForceDerivative,
}

/// The contribution of one crank unit at angle ψ, given (sin ψ, cos ψ): gravity's U, Q and
/// dQ/dψ here, the reduced inertia and the piston's kinematics in `dynamics`.
pub(crate) trait CrankTerm {
    /// What the term needs to know of a unit.
    type Unit: Sync;
    fn term<M: MulAdd>(k: &Self::Unit, s: f64, c: f64) -> f64;
}

/// One crank unit's coefficients for the three quantities; λ² and the γ products precomputed.
///
/// The root √(1 − λ² sin²ψ) is taken as √((1 − λ²) + λ² cos²ψ), with 1 − λ² = (1 − λ)(1 + λ)
/// exact to an ulp: near ψ = π/2 and λ → 1 the first form subtracts two numbers close to 1
/// and keeps only their rounding (at λ = 1 − 2⁻⁵³ it is 2⁻⁵² ± 2⁻⁵³), the second adds two
/// accurate positive ones.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Coefficients {
    /// λ²
    l2: f64,
    /// 1 − λ²
    q2: f64,
    /// U2·cos γ
    p: f64,
    /// (U1 + U2)·sin γ
    w_plus: f64,
    /// U1·λ·sin γ
    wl: f64,
}

impl Coefficients {
    pub(crate) fn new(d: &Design) -> Self {
        let (sin_g, cos_g) = d.inclination_sin_cos();
        Self {
            l2: d.crank_ratio * d.crank_ratio,
            q2: (1.0 - d.crank_ratio) * (1.0 + d.crank_ratio),
            p: d.u2 * cos_g,
            w_plus: (d.u1 + d.u2) * sin_g,
            wl: d.u1 * d.crank_ratio * sin_g,
        }
    }
}

impl Coefficients {
    /// (U, Q, dQ/dψ) of the unit at one angle, given (sin ψ, cos ψ): the three terms of the
    /// kernels sharing one root (scalar: for root finding).
    #[inline]
    pub(crate) fn values(&self, s: f64, c: f64) -> (f64, f64, f64) {
        let (s2, d2) = (s * s, self.l2 * (c * c) + self.q2);
        let root = d2.sqrt();
        let energy = self.p * s + self.w_plus * (c - 1.0) - self.wl * s2 / (1.0 + root);
        let force = self.p * c - self.w_plus * s - self.wl * (s * c) / root;
        let numerator = c * c - s2 * d2;
        let slope = -self.p * s - self.w_plus * c - self.wl * numerator / (d2 * root);
        (energy, force, slope)
    }

    /// Over angles where D = 1 − λ² sin²ψ ≥ `d_min`: bounds on |Q|, |dQ/dψ| and |d²Q/dψ²| of
    /// the unit (its terms' sizes: what their rounding is relative to).
    ///
    /// Q = p cos ψ − w₊ sin ψ − w_λ·g(ψ), g = sin ψ cos ψ/√D. With D' = −λ² sin 2ψ,
    /// |cos ψ| ≤ √D (so |sin 2ψ| ≤ 2√D) and λ ≤ 1: |g| ≤ 1;
    /// g' = cos 2ψ/√D + (λ²/4) sin²2ψ/D^{3/2}, so |g'| ≤ 2/√D;
    /// g'' = −2 sin 2ψ/√D + (3λ²/2) sin 2ψ cos 2ψ/D^{3/2} + (3λ⁴/8) sin³2ψ/D^{5/2}, so
    /// |g''| ≤ 2/√D + 3/D + 3/D.
    pub(crate) fn bounds(&self, d_min: f64) -> [f64; 3] {
        let root = d_min.sqrt();
        let (p, w, wl) = (self.p.abs(), self.w_plus.abs(), self.wl.abs());
        [
            p + w + wl,
            p + w + wl * 2.0 / root,
            p + w + wl * (2.0 / root + 6.0 / d_min),
        ]
    }

    /// 1 − λ² sin²ψ where cos²ψ = `cos2` (as the kernels form it).
    pub(crate) fn root_argument(&self, cos2: f64) -> f64 {
        self.l2 * cos2 + self.q2
    }
}

/// The three quantities, as type-level selectors of the per-crank term.
struct Energy;
struct Force;
struct ForceDerivative;

impl CrankTerm for Energy {
    type Unit = Coefficients;

    /// U* = U2[sin(ψ+γ) − sin γ] − U1 sin γ [(1 − cos ψ) + λ sin²ψ / (1 + √(1 − λ² sin²ψ))]
    /// (the stable form of s(ψ)/r: no cancellation as λ → 0; exactly 0 at ψ = 0).
    #[inline(always)]
    fn term<M: MulAdd>(k: &Coefficients, s: f64, c: f64) -> f64 {
        let s2 = s * s;
        let root = M::mul_add(k.l2, c * c, k.q2).sqrt();
        M::mul_add(
            k.p,
            s,
            M::mul_add(k.w_plus, c - 1.0, -(k.wl * s2 / (1.0 + root))),
        )
    }
}

impl CrankTerm for Force {
    type Unit = Coefficients;

    /// Q = U2 cos(ψ+γ) − U1 sin γ [sin ψ + λ sin ψ cos ψ / √(1 − λ² sin²ψ)]
    #[inline(always)]
    fn term<M: MulAdd>(k: &Coefficients, s: f64, c: f64) -> f64 {
        let root = M::mul_add(k.l2, c * c, k.q2).sqrt();
        M::mul_add(k.p, c, M::mul_add(-k.w_plus, s, -(k.wl * (s * c) / root)))
    }
}

impl CrankTerm for ForceDerivative {
    type Unit = Coefficients;

    /// dQ/dψ = −U2 sin(ψ+γ) − U1 sin γ [cos ψ + λ (cos 2ψ + λ² sin⁴ψ) / (1 − λ² sin²ψ)^{3/2}]
    #[inline(always)]
    fn term<M: MulAdd>(k: &Coefficients, s: f64, c: f64) -> f64 {
        let s2 = s * s;
        let d2 = M::mul_add(k.l2, c * c, k.q2);
        // cos 2ψ + λ² sin⁴ψ = cos²ψ − sin²ψ·D: no cancellation of two terms near 1 as
        // λ → 1 at ψ → π/2, where the first form keeps only their rounding.
        let numerator = M::mul_add(-s2, d2, c * c);
        M::mul_add(
            -k.p,
            s,
            M::mul_add(-k.w_plus, c, -(k.wl * numerator / (d2 * d2.sqrt()))),
        )
    }
}

/// Σ_j term_j(φ_i + α_j) over a run of φ (each term times its weight, where `weights` has
/// them); `units` holds one set of coefficients shared by every crank (an in-line machine)
/// or one per crank (a general engine).
#[inline(always)]
fn sum_over_cranks<K: CrankTerm, M: MulAdd, W: CrankWeights>(
    units: &[K::Unit],
    phases: &Phases,
    run: Run,
    weights: W,
    out: &mut [f64],
) {
    match run {
        Run::Points(angles) => crank_blocks::<K, M, _, W>(units, phases, angles, weights, out),
        Run::Table(angles) => crank_blocks::<K, M, _, W>(units, phases, angles, weights, out),
        Run::Grid(angles) => crank_blocks::<K, M, _, W>(units, phases, angles, weights, out),
    }
}

#[inline(always)]
fn crank_blocks<K: CrankTerm, M: MulAdd, A: AngleSource, W: CrankWeights>(
    units: &[K::Unit],
    phases: &Phases,
    angles: A,
    weights: W,
    out: &mut [f64],
) {
    // LANES points at a time keep sin/cos and the running sum in registers through the
    // crank loop (several independent vectors hide the latency of sqrt and division). The
    // last block is padded; every lane sees the same operations, so a point's value does
    // not depend on the block it falls in. Whole blocks have a loop of their own, where
    // len = LANES is a constant (fixed-size loads and stores, no padded copies on the
    // stack; see `series_kernels::series_blocks`).
    // (A function, not a closure: a closure called twice is not inlined into the
    // multiversioned kernels, and outside them it is compiled without their features.)
    #[inline(always)]
    fn block<K: CrankTerm, M: MulAdd, A: AngleSource, W: CrankWeights, const N: usize>(
        units: &[K::Unit],
        phases: &Phases,
        angles: A,
        weights: W,
        offset: usize,
        len: usize,
    ) -> [f64; N] {
        let (s, c) = angles.block::<M, N>(offset, len);
        crank_sum::<K, M, W, N>(units, phases, &s, &c, weights, offset, len)
    }
    let mut whole = out.chunks_exact_mut(LANES);
    let mut offset = 0;
    for o in &mut whole {
        if let Ok(o) = <&mut [f64; LANES]>::try_from(o) {
            *o = block::<K, M, A, W, LANES>(units, phases, angles, weights, offset, LANES);
        }
        offset += LANES;
    }
    let tail = whole.into_remainder();
    if A::LANE_FREE {
        // A short tail (one angle at a time, as the steady state's extrema are refined) in
        // narrow blocks: a 16-lane block for one point is 16 times its work, and each lane's
        // value is the same in a block of any width.
        if let [one] = tail {
            [*one] = block::<K, M, A, W, 1>(units, phases, angles, weights, offset, 1);
        } else {
            for o in tail.chunks_mut(NARROW) {
                let len = o.len();
                let lanes =
                    block::<K, M, A, W, NARROW>(units, phases, angles, weights, offset, len);
                store(o, &lanes);
                offset += len;
            }
        }
    } else if !tail.is_empty() {
        let lanes = block::<K, M, A, W, LANES>(units, phases, angles, weights, offset, tail.len());
        store(tail, &lanes);
    }
}

/// Points per block of a short tail.
const NARROW: usize = 4;

/// The first `out.len()` ≤ N lanes into `out`: a fixed-size move for whole blocks (a
/// variable-length copy would be a call to memmove per block).
#[inline(always)]
pub(crate) fn store<const N: usize>(out: &mut [f64], lanes: &[f64; N]) {
    match <&mut [f64; N]>::try_from(&mut *out) {
        Ok(whole) => *whole = *lanes,
        Err(_) => out.copy_from_slice(&lanes[..out.len()]),
    }
}

/// What each crank's term is multiplied by before the sum over the cranks.
pub(crate) trait CrankWeights: Copy {
    /// `terms` (crank `crank`, points offset … offset + len − 1 of the run, the other lanes
    /// padding) weighted.
    fn weighted<const N: usize>(
        self,
        crank: usize,
        offset: usize,
        len: usize,
        terms: [f64; N],
    ) -> [f64; N];
}

/// The terms as they are.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Unweighted;

impl CrankWeights for Unweighted {
    #[inline(always)]
    fn weighted<const N: usize>(self, _: usize, _: usize, _: usize, terms: [f64; N]) -> [f64; N] {
        terms
    }
}

/// Weights of a crank-major table: crank j's weight at the run's point i is
/// `values[j * stride + first + i]` (a force per unit and angle, where the term is a
/// velocity ratio: the unit's torque).
#[derive(Debug, Clone, Copy)]
pub(crate) struct RowWeights<'a> {
    pub values: &'a [f64],
    pub stride: usize,
    pub first: usize,
}

impl CrankWeights for RowWeights<'_> {
    #[inline(always)]
    fn weighted<const N: usize>(
        self,
        crank: usize,
        offset: usize,
        len: usize,
        mut terms: [f64; N],
    ) -> [f64; N] {
        let weights = padded::<N>(self.values, crank * self.stride + self.first + offset, len);
        for l in 0..N {
            terms[l] *= weights[l];
        }
        terms
    }
}

/// Σ_j weight_j · term_j at N points given their (sin φ, cos φ) (points offset … offset +
/// len − 1 of the run).
#[inline(always)]
fn crank_sum<K: CrankTerm, M: MulAdd, W: CrankWeights, const N: usize>(
    units: &[K::Unit],
    phases: &Phases,
    s: &[f64; N],
    c: &[f64; N],
    weights: W,
    offset: usize,
    len: usize,
) -> [f64; N] {
    let mut sum = [0.0; N];
    for (j, (&cos_a, &sin_a)) in phases.cos.iter().zip(&phases.sin).enumerate() {
        let kernel = if units.len() == 1 {
            &units[0]
        } else {
            &units[j]
        };
        let mut terms = [0.0; N];
        for l in 0..N {
            let sin_psi = M::mul_add(s[l], cos_a, c[l] * sin_a);
            let cos_psi = M::mul_add(c[l], cos_a, -(s[l] * sin_a));
            terms[l] = K::term::<M>(kernel, sin_psi, cos_psi);
        }
        let terms = weights.weighted(j, offset, len, terms);
        for l in 0..N {
            sum[l] += terms[l];
        }
    }
    sum
}

/// Points per register block.
const LANES: usize = 16;

/// Σ_j K(unit_j, φ + α_j) at the points of `run`: one clone per instruction set of the
/// kernel for crank term K, with fused multiply-adds where the clone has FMA. `units` holds
/// one unit shared by every phase, or one per phase.
#[inline]
pub(crate) fn crank_run<K: CrankTerm>(
    units: &[K::Unit],
    phases: &Phases,
    run: Run,
    out: &mut [f64],
) {
    weighted_crank_run::<K, _>(units, phases, run, Unweighted, out)
}

/// Σ_j w_j(φ) K(unit_j, φ + α_j) at the points of `run`, as [`crank_run`] sums K, each
/// crank's term times its weight (`weights`); with [`RowWeights`] the same doubles as one
/// [`crank_run`] per crank and a running sum of the products, in crank order.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
pub(crate) fn weighted_crank_run<K: CrankTerm, W: CrankWeights>(
    units: &[K::Unit],
    phases: &Phases,
    run: Run,
    weights: W,
    out: &mut [f64],
) {
    if target_cfg_f!(target_feature = "fma") {
        sum_over_cranks::<K, Fused, W>(units, phases, run, weights, out)
    } else {
        sum_over_cranks::<K, Unfused, W>(units, phases, run, weights, out)
    }
}

pub(crate) fn evaluate_run(
    quantity: Quantity,
    design: &Design,
    phases: &Phases,
    run: Run,
    out: &mut [f64],
) {
    evaluate_units(quantity, &[Coefficients::new(design)], phases, run, out)
}

/// `quantity` of crank units with their own coefficients (one, shared, or one per phase)
/// at the `out.len()` points of `run`.
pub(crate) fn evaluate_units(
    quantity: Quantity,
    units: &[Coefficients],
    phases: &Phases,
    run: Run,
    out: &mut [f64],
) {
    match quantity {
        Quantity::PotentialEnergy => crank_run::<Energy>(units, phases, run, out),
        Quantity::GeneralizedForce => crank_run::<Force>(units, phases, run, out),
        Quantity::ForceDerivative => crank_run::<ForceDerivative>(units, phases, run, out),
    }
}

/// Evaluate `quantity` for every design at every φ into `out`, design-major
/// (`out[d * phi.len() + i]` belongs to design d at φ_i). NaN or ±inf in φ gives NaN there.
/// On a `Phi::Uniform` grid sin/cos come by rotation (see `grid`); on points each point's
/// value depends on that point alone.
pub fn evaluate<'a>(
    quantity: Quantity,
    designs: &[Design],
    phases: &Phases,
    phi: impl Into<Phi<'a>>,
    out: &mut [f64],
    parallelism: Parallelism,
) -> Result<()> {
    let phi = phi.into();
    let n_phi = phi.len();
    check_rows_length("out", designs.len(), n_phi, out.len())?;
    let expected = out.len();
    let phi = PreparedPhi::new(phi, parallelism);
    for_each_row_segment(
        out,
        n_phi,
        expected.saturating_mul(phases.len()),
        parallelism,
        |row, col, segment| {
            evaluate_run(
                quantity,
                &designs[row],
                phases,
                phi.run(col, segment.len()),
                segment,
            )
        },
    );
    Ok(())
}

/// Convenience for one design: a fresh vector of `quantity` over `phi`.
pub fn evaluate_one<'a>(
    quantity: Quantity,
    design: &Design,
    phases: &Phases,
    phi: impl Into<Phi<'a>>,
) -> Vec<f64> {
    let phi = PreparedPhi::new(phi.into(), Parallelism::SERIAL);
    let mut out = vec![0.0; phi.len()];
    evaluate_run(quantity, design, phases, phi.run(0, out.len()), &mut out);
    out
}

#[cfg(test)]
mod tests;
