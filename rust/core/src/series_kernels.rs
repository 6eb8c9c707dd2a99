//! The SIMD evaluation of a `FourierSeries` (the model is in `series`): only the harmonics
//! that survive the crank sum, so that the cost per point hardly depends on k.
//!
//! Per point: one sincos of φ (or a rotation on a uniform grid), w = e^{ipφ} by binary
//! powering (or by rotation), then Clenshaw's recurrence over the harmonics of θ = pφ.

use multiversion::multiversion;
use multiversion::target::target_cfg_f;

use crate::angles::{AngleSource, GridAngles, Phi, PreparedPhi, Rotations, Run};
use crate::error::{check_length, check_rows_length, Result};
use crate::exact::{evaluate_units, store, Coefficients, Quantity};
use crate::mechanism::{Design, Phases};
use crate::parallel::{for_each_row_segment, Parallelism};
use crate::series::FourierSeries;
use crate::trig::{Fused, MulAdd, Unfused};

/// (re, im) of w·z, lane by lane.
#[inline(always)]
fn multiply<M: MulAdd, const N: usize>(w: &mut ([f64; N], [f64; N]), z: &([f64; N], [f64; N])) {
    for l in 0..N {
        let re = M::mul_add(w.0[l], z.0[l], -(w.1[l] * z.1[l]));
        w.1[l] = M::mul_add(w.0[l], z.1[l], w.1[l] * z.0[l]);
        w.0[l] = re;
    }
}

/// z² in place.
#[inline(always)]
fn square<M: MulAdd, const N: usize>(z: &mut ([f64; N], [f64; N])) {
    let factor = *z;
    multiply::<M, N>(z, &factor);
}

/// (cos pφ, sin pφ) at N points from (cos φ, sin φ) by binary powering: the squarings
/// z = (e^{iφ})^{2^j}, and the product of those of p's set bits. The product starts
/// from the lowest set bit's power itself, not from 1 times it (one complex
/// multiplication a point fewer: 1·z is z to the value, only a zero's sign could differ).
#[inline(always)]
fn power_lanes<M: MulAdd, const N: usize>(
    c: &[f64; N],
    s: &[f64; N],
    mut e: usize,
) -> ([f64; N], [f64; N]) {
    if e == 0 {
        return ([1.0; N], [0.0; N]);
    }
    let mut z = (*c, *s);
    while e & 1 == 0 {
        square::<M, N>(&mut z);
        e >>= 1;
    }
    let mut w = z;
    e >>= 1;
    while e != 0 {
        square::<M, N>(&mut z);
        if e & 1 == 1 {
            multiply::<M, N>(&mut w, &z);
        }
        e >>= 1;
    }
    w
}

/// The series at N points, entirely in registers, given (cos φ, sin φ) and
/// w = (cos pφ, sin pφ): a₁ cos φ + b₁ sin φ, then the harmonics of θ = pφ. Every point
/// sees the same operations in the same order.
#[inline(always)]
fn series_points<M: MulAdd, const N: usize>(
    series: &FourierSeries,
    first: bool,
    c: &[f64; N],
    s: &[f64; N],
    w: &([f64; N], [f64; N]),
) -> [f64; N] {
    let mut sum = [0.0; N];
    if first {
        for l in 0..N {
            sum[l] = M::mul_add(series.a1, c[l], series.b1 * s[l]);
        }
    }
    if series.cos.is_empty() {
        return sum;
    }
    // Clenshaw's recurrence in θ = pφ, from the highest harmonic down:
    // b_ν = c_ν + 2 cos θ·b_{ν+1} − b_{ν+2}; then Σ A_ν cos νθ = b^A_1 cos θ − b^A_2 and
    // Σ B_ν sin νθ = b^B_1 sin θ. Three operations per harmonic and sequence, against ten
    // for rotating e^{iνθ}; with the geometrically decaying coefficients of Q its rounding
    // stays at a few ulps of the largest term.
    // A loop, not `w.0.map`: at 32 lanes `map` is not inlined, and its call (compiled
    // outside the multiversioned kernel, SSE2 only) sent every live vector through the stack.
    let mut two_cos = [0.0; N];
    for (twice, &cos) in two_cos.iter_mut().zip(&w.0) {
        *twice = 2.0 * cos;
    }
    let (mut a1, mut a2) = ([0.0; N], [0.0; N]);
    let (mut b1, mut b2) = ([0.0; N], [0.0; N]);
    if series.cos.iter().all(|&a| a == 0.0) {
        // A series of sines alone (a single crank, γ where its cosines vanish): the cosine
        // sequence would stay 0 throughout, and b^B_1 sin θ + 0 is b^B_1 sin θ.
        for &b in series.sin.iter().rev() {
            for l in 0..N {
                let next_b = M::mul_add(two_cos[l], b1[l], b - b2[l]);
                b2[l] = b1[l];
                b1[l] = next_b;
            }
        }
        for l in 0..N {
            sum[l] += b1[l] * w.1[l];
        }
        return sum;
    }
    for (&a, &b) in series.cos.iter().zip(&series.sin).rev() {
        for l in 0..N {
            let next_a = M::mul_add(two_cos[l], a1[l], a - a2[l]);
            a2[l] = a1[l];
            a1[l] = next_a;
            let next_b = M::mul_add(two_cos[l], b1[l], b - b2[l]);
            b2[l] = b1[l];
            b1[l] = next_b;
        }
    }
    // a₁·cos θ as (a₁/2)·(2 cos θ): the same value (halving is exact above the subnormals),
    // and cos θ need not stay in a register through the recurrence (fewer spills).
    for l in 0..N {
        sum[l] += M::mul_add(b1[l], w.1[l], M::mul_add(0.5 * a1[l], two_cos[l], -a2[l]));
    }
    sum
}

/// Points per register block where sin φ and cos φ come from a sincos of each point
/// (four AVX-512 vectors): the polynomials' chains need that many independent lanes.
const POINT_LANES: usize = 32;
/// Points per register block on a uniform grid (two AVX-512 vectors): its rotations are
/// short chains, and with e^{iφ}, e^{ipφ} and Clenshaw's four sequences a block of 16
/// stays in the 32 registers where one of 32 spilled (a third less time per point).
const GRID_LANES: usize = 16;

/// Where a series block gets e^{ipφ}: from e^{iφ} (cos and sin) or from the grid, given
/// the roundings d of the grid's points that e^{iφ} was found with.
trait HarmonicSource: Copy {
    /// Whether the kernel is compiled as two loops, with the first harmonic and without
    /// (measured: e^{ipφ} by rotation on a grid 20-30% faster so, e^{ipφ} by powering
    /// 10-15% slower, its powers shuffled between registers in the loop without).
    const OWN_LOOPS: bool;

    fn block<M: MulAdd, const N: usize>(
        self,
        offset: usize,
        c: &[f64; N],
        s: &[f64; N],
        d: &[f64; N],
        step: usize,
    ) -> ([f64; N], [f64; N]);
}

/// e^{ipφ} = (e^{iφ})^p by binary powering.
#[derive(Clone, Copy)]
struct Powering;

impl HarmonicSource for Powering {
    const OWN_LOOPS: bool = false;

    #[inline(always)]
    fn block<M: MulAdd, const N: usize>(
        self,
        _offset: usize,
        c: &[f64; N],
        s: &[f64; N],
        _d: &[f64; N],
        step: usize,
    ) -> ([f64; N], [f64; N]) {
        power_lanes::<M, N>(c, s, step)
    }
}

/// e^{ipφ} by rotation on a uniform grid, like e^{iφ}.
impl HarmonicSource for GridAngles<'_> {
    const OWN_LOOPS: bool = true;

    #[inline(always)]
    fn block<M: MulAdd, const N: usize>(
        self,
        offset: usize,
        _c: &[f64; N],
        _s: &[f64; N],
        d: &[f64; N],
        _step: usize,
    ) -> ([f64; N], [f64; N]) {
        let (ws, wc) = self.rotations.block_rounded::<M, N>(self.first + offset, d);
        (wc, ws)
    }
}

#[inline(always)]
fn series_segment<M: MulAdd>(
    series: &FourierSeries,
    run: Run,
    harmonic: Option<&Rotations>,
    out: &mut [f64],
) {
    match (run, harmonic) {
        (Run::Grid(angles), Some(rotations)) => {
            let first = angles.first;
            let harmonic = GridAngles { rotations, first };
            series_blocks::<M, _, _, GRID_LANES>(series, angles, harmonic, out)
        }
        (Run::Grid(angles), None) => {
            series_blocks::<M, _, _, GRID_LANES>(series, angles, Powering, out)
        }
        (Run::Points(angles), _) => {
            series_blocks::<M, _, _, POINT_LANES>(series, angles, Powering, out)
        }
        (Run::Table(angles), _) => {
            series_blocks::<M, _, _, POINT_LANES>(series, angles, Powering, out)
        }
    }
}

#[inline(always)]
fn series_blocks<M: MulAdd, A: AngleSource, H: HarmonicSource, const LANES: usize>(
    series: &FourierSeries,
    angles: A,
    harmonic: H,
    out: &mut [f64],
) {
    // a₁ = b₁ = 0 where the crank sum cancels the first harmonic (k ≥ 2): with harmonics
    // to follow, the sum then starts at 0, as a₁ cos φ + b₁ sin φ would have it to the
    // value (a NaN of φ reaches the sum through them). Without any, the first harmonic
    // is the sum, NaN where φ is.
    let first = series.cos.is_empty() || series.a1 != 0.0 || series.b1 != 0.0;
    if H::OWN_LOOPS {
        // A loop of its own for each case (`first` a constant in it): without the first
        // harmonic, sin φ and cos φ need not stay in registers through the harmonics.
        if first {
            series_blocks_of::<M, A, H, LANES>(series, true, angles, harmonic, out)
        } else {
            series_blocks_of::<M, A, H, LANES>(series, false, angles, harmonic, out)
        }
    } else {
        series_blocks_of::<M, A, H, LANES>(series, first, angles, harmonic, out)
    }
}

#[inline(always)]
fn series_blocks_of<M: MulAdd, A: AngleSource, H: HarmonicSource, const LANES: usize>(
    series: &FourierSeries,
    first: bool,
    angles: A,
    harmonic: H,
    out: &mut [f64],
) {
    // Register blocks of LANES points — sin/cos, e^{ipφ} and the harmonic sum without a
    // pass over memory in between (several independent chains hide each step's latency).
    // Whole blocks have a loop of their own, where len = LANES is a constant: their points
    // are loaded from the run and their lanes stored into `out` by fixed-size moves. One
    // loop for all blocks (len a variable) moved each block through padded copies on the
    // stack — zeroed, filled, reloaded, then a memmove into `out` — whose cost depends on
    // the alignment of the caller's stack: 10^6 points took 50% longer on a rayon worker's
    // stack than on Python's main thread. The last, partial block is padded.
    let mut whole = out.chunks_exact_mut(LANES);
    let mut offset = 0;
    for o in &mut whole {
        if let Ok(o) = <&mut [f64; LANES]>::try_from(o) {
            *o = series_block::<M, A, H, LANES>(series, first, angles, harmonic, offset, LANES);
        }
        offset += LANES;
    }
    let tail = whole.into_remainder();
    if !tail.is_empty() {
        let len = tail.len();
        let lanes = series_block::<M, A, H, LANES>(series, first, angles, harmonic, offset, len);
        store(tail, &lanes);
    }
}

/// The series at points offset … offset + len − 1 of `angles` (len ≤ LANES; the other
/// lanes padded).
#[inline(always)]
fn series_block<M: MulAdd, A: AngleSource, H: HarmonicSource, const LANES: usize>(
    series: &FourierSeries,
    first: bool,
    angles: A,
    harmonic: H,
    offset: usize,
    len: usize,
) -> [f64; LANES] {
    let (s, c, d) = angles.block_and_rounding::<M, LANES>(offset, len);
    let w = if series.cos.is_empty() {
        ([1.0; LANES], [0.0; LANES]) // unused
    } else {
        harmonic.block::<M, LANES>(offset, &c, &s, &d, series.step)
    };
    series_points::<M, LANES>(series, first, &c, &s, &w)
}

#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
fn series_run(series: &FourierSeries, run: Run, harmonic: Option<&Rotations>, out: &mut [f64]) {
    if target_cfg_f!(target_feature = "fma") {
        series_segment::<Fused>(series, run, harmonic, out)
    } else {
        series_segment::<Unfused>(series, run, harmonic, out)
    }
}

/// φ prepared for series: on a uniform grid, the rotations of φ and of pφ for every
/// harmonic step p among the series.
pub(crate) struct SeriesPhi<'a> {
    phi: PreparedPhi<'a>,
    harmonics: Vec<(usize, Rotations)>,
}

impl<'a> SeriesPhi<'a> {
    pub(crate) fn new(phi: Phi<'a>, series: &[FourierSeries], parallelism: Parallelism) -> Self {
        let mut harmonics: Vec<(usize, Rotations)> = Vec::new();
        if let Phi::Uniform(grid) = phi {
            let mut steps: Vec<usize> = series
                .iter()
                .filter(|s| s.complete && !s.cos.is_empty())
                .map(|s| s.step)
                .collect();
            steps.sort_unstable();
            steps.dedup();
            harmonics = steps
                .into_iter()
                .map(|p| (p, Rotations::new(&grid, p, parallelism)))
                .collect();
        }
        Self {
            phi: PreparedPhi::new(phi, parallelism),
            harmonics,
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.phi.len()
    }

    pub(crate) fn run(&self, first: usize, len: usize) -> Run<'_> {
        self.phi.run(first, len)
    }

    pub(crate) fn harmonic(&self, step: usize) -> Option<&Rotations> {
        self.harmonics
            .iter()
            .find(|(p, _)| *p == step)
            .map(|(_, r)| r)
    }
}

/// Q_u* from `series` where it is complete, else from the closed form of the same units,
/// at the `out.len()` points of `run`.
pub(crate) fn series_or_closed(
    series: &FourierSeries,
    units: &[Coefficients],
    phases: &Phases,
    run: Run,
    harmonic: Option<&Rotations>,
    out: &mut [f64],
) {
    if series.complete {
        series_run(series, run, harmonic, out)
    } else {
        evaluate_units(Quantity::GeneralizedForce, units, phases, run, out)
    }
}

/// Q_u* of each design at every φ from its series, or from the closed form where the
/// series is incomplete (λ too close to 1 for MAX_HARMONIC harmonics), design-major.
pub fn evaluate_series_or_exact<'a>(
    series: &[FourierSeries],
    designs: &[Design],
    phases: &Phases,
    phi: impl Into<Phi<'a>>,
    out: &mut [f64],
    parallelism: Parallelism,
) -> Result<()> {
    let phi = phi.into();
    let n_phi = phi.len();
    check_length("designs", series.len(), designs.len())?;
    check_rows_length("out", series.len(), n_phi, out.len())?;
    let phi = SeriesPhi::new(phi, series, parallelism);
    let work = out.len().saturating_mul(4);
    for_each_row_segment(out, n_phi, work, parallelism, |row, col, segment| {
        let units = [Coefficients::new(&designs[row])];
        series_or_closed(
            &series[row],
            &units,
            phases,
            phi.run(col, segment.len()),
            phi.harmonic(series[row].step),
            segment,
        )
    });
    Ok(())
}

/// Q_u* from the series of each design at every φ, design-major like `exact::evaluate`.
pub fn evaluate_series<'a>(
    series: &[FourierSeries],
    phi: impl Into<Phi<'a>>,
    out: &mut [f64],
    parallelism: Parallelism,
) -> Result<()> {
    let phi = phi.into();
    let n_phi = phi.len();
    check_rows_length("out", series.len(), n_phi, out.len())?;
    let phi = SeriesPhi::new(phi, series, parallelism);
    let work = out.len().saturating_mul(4);
    for_each_row_segment(out, n_phi, work, parallelism, |row, col, segment| {
        series_run(
            &series[row],
            phi.run(col, segment.len()),
            phi.harmonic(series[row].step),
            segment,
        )
    });
    Ok(())
}
