//! Q_u*(φ) from its Fourier form (mathematics.md §4): only the harmonics that survive the
//! crank sum, evaluated by rotation so that the cost per point hardly depends on k.
//!
//! A series is a₁ cos φ + b₁ sin φ + Σ_{ν=1}^{V} A_ν cos(νpφ) + B_ν sin(νpφ), where p is
//! the step of the surviving even harmonics (p = k for a two-stroke single-acting machine).
//! Per point: one sincos of φ, w = e^{ipφ} by binary powering, then one complex rotation
//! and one multiply-add pair per harmonic.

use multiversion::multiversion;
use multiversion::target::target_cfg_f;

use crate::error::{check_length, Result};
use crate::exact::{evaluate_units, store, Coefficients, Quantity};
use crate::grid::{AngleSource, GridAngles, Phi, PreparedPhi, Rotations, Run};
use crate::harmonics::{lambda_paper, ExactLambdas, PhaseSums, UnitAmplitudes, PAPER_MAX_HARMONIC};
use crate::mechanism::{Design, Phases};
use crate::parallel::{for_each_row_segment, map_indices, Parallelism};
use crate::trig::{Fused, MulAdd, Unfused};

/// Which Λ_n and which cut.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesKind {
    /// Exact Λ_n; harmonics up to where a rigorous bound on the rest is below ε·max|Q|/2.
    Exact,
    /// The paper's eq. (16): λ-series Λ_n through λ¹¹, harmonics n ≤ 12.
    Paper,
}

/// One design's Q_u* as a short trigonometric series (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct FourierSeries {
    pub a1: f64,
    pub b1: f64,
    /// Step p of the even harmonics (0 when there are none).
    pub step: usize,
    /// A_ν, B_ν for harmonic ν·step, ν = 1 … V.
    pub cos: Vec<f64>,
    pub sin: Vec<f64>,
    /// Whether the harmonics carried reach machine precision. As λ → 1 the harmonics decay
    /// ever more slowly; past MAX_HARMONIC (λ ≳ 0.9998) the series is incomplete, and the
    /// evaluation and extrema use the closed form instead of returning a truncation.
    pub complete: bool,
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

impl FourierSeries {
    /// a₁ cos φ + b₁ sin φ + Σ (a_n cos nφ + b_n sin nφ) over `even` = [(n, a_n, b_n)], n even ascending.
    pub fn from_terms(a1: f64, b1: f64, even: &[(usize, f64, f64)]) -> Self {
        let step = even.iter().fold(0, |g, &(n, _, _)| gcd(g, n));
        let count = even.last().map_or(0, |&(n, _, _)| n / step.max(1));
        let (mut cos, mut sin) = (vec![0.0; count], vec![0.0; count]);
        for &(n, a, b) in even {
            cos[n / step - 1] = a;
            sin[n / step - 1] = b;
        }
        Self {
            a1,
            b1,
            step,
            cos,
            sin,
            complete: true,
        }
    }

    /// The series with exact Λ_n, cut where the rest is provably below ε·max|Q|/2.
    ///
    /// Bound: |Λ_{2m}| ≤ t^{2m−1}/(1 − t⁴) (2m·|C(½, m)| ≤ 1 and the ₂F₁ terms are
    /// dominated by t^{4b}), and |S_n| ≤ k, so the harmonics above 2M add at most
    /// k·|N1|·t^{2M+1}/((1 − t²)(1 − t⁴)). By Parseval max|Q| ≥ rms(Q) =
    /// √(Σ (a_n² + b_n²)/2) over the harmonics kept so far.
    pub fn exact(design: &Design, sums: &PhaseSums) -> Self {
        let unit = UnitAmplitudes::new(design);
        let (a1, b1) = unit.first_harmonic(sums);
        let mut mean_square = 0.5 * (a1 * a1 + b1 * b1);
        let mut lambdas = ExactLambdas::new(design.crank_ratio);
        let t = lambdas.t();
        let (t2, t4) = (t * t, t * t * t * t);
        let tail_factor = sums.cranks as f64 * unit.n1.abs() / ((1.0 - t2) * (1.0 - t4));
        let mut even = Vec::new();
        let mut t_power = t; // t^{2M+1} after harmonic 2M
                             // N1 = 0 (γ = 0 or π, or U1 = 0): no even harmonics at all.
        let mut complete = tail_factor == 0.0;
        for n in (2..=sums.n_max()).step_by(2) {
            if complete {
                break;
            }
            let lambda_n = lambdas.next().unwrap_or(0.0);
            let (a, b) = unit.even_harmonic(lambda_n, n, sums);
            if a != 0.0 || b != 0.0 {
                even.push((n, a, b));
                mean_square += 0.5 * (a * a + b * b);
            }
            t_power *= t2;
            // Done when the rest is below ε·rms/2, or negligible outright (all cancelled).
            complete = tail_factor * t_power <= 0.5 * f64::EPSILON * mean_square.sqrt()
                || t_power <= 1e-30;
        }
        Self {
            complete,
            ..Self::from_terms(a1, b1, &even)
        }
    }

    /// The paper's eq. (16): Λ_n from the λ-series through λ¹¹, n ≤ 12, every harmonic
    /// whose phase sum survives.
    pub fn paper(design: &Design, sums: &PhaseSums) -> Self {
        let unit = UnitAmplitudes::new(design);
        let (a1, b1) = unit.first_harmonic(sums);
        let mut lambdas = [0.0; PAPER_MAX_HARMONIC + 1];
        lambda_paper(design.crank_ratio, &mut lambdas);
        let even: Vec<_> = (2..=PAPER_MAX_HARMONIC.min(sums.n_max()))
            .step_by(2)
            .map(|n| {
                let (a, b) = unit.even_harmonic(lambdas[n], n, sums);
                (n, a, b)
            })
            .filter(|&(_, a, b)| a != 0.0 || b != 0.0)
            .collect();
        Self::from_terms(a1, b1, &even)
    }

    pub fn new(kind: SeriesKind, design: &Design, sums: &PhaseSums) -> Self {
        match kind {
            SeriesKind::Exact => Self::exact(design, sums),
            SeriesKind::Paper => Self::paper(design, sums),
        }
    }

    /// Map every term a cos nφ + b sin nφ to new (cos, sin) coefficients.
    fn map_terms(&self, f: impl Fn(usize, f64, f64) -> (f64, f64)) -> Self {
        let (a1, b1) = f(1, self.a1, self.b1);
        let (cos, sin) = self
            .cos
            .iter()
            .zip(&self.sin)
            .enumerate()
            .map(|(nu, (&a, &b))| f((nu + 1) * self.step, a, b))
            .unzip();
        Self {
            a1,
            b1,
            step: self.step,
            cos,
            sin,
            complete: self.complete,
        }
    }

    /// The antiderivative with zero constant term: for Q_u*, U_w* up to a constant.
    pub fn integral(&self) -> Self {
        self.map_terms(|n, a, b| (-b / n as f64, a / n as f64))
    }

    /// The derivative: for Q_u*, dQ_u*/dφ.
    pub fn derivative(&self) -> Self {
        self.map_terms(|n, a, b| (n as f64 * b, -(n as f64) * a))
    }

    /// The series and its derivative at one angle (scalar: for root polishing, where a
    /// block kernel's set-up would cost more than the arithmetic).
    pub fn value_and_slope_at(&self, phi: f64) -> (f64, f64) {
        let (s, c) = phi.sin_cos();
        let mut value = self.a1 * c + self.b1 * s;
        let mut slope = self.b1 * c - self.a1 * s;
        if self.cos.is_empty() {
            return (value, slope);
        }
        let w = power(c, s, self.step);
        let mut z = w;
        for (nu, (&a, &b)) in self.cos.iter().zip(&self.sin).enumerate() {
            let n = ((nu + 1) * self.step) as f64;
            value += a * z.0 + b * z.1;
            slope += n * (b * z.0 - a * z.1);
            z = (z.0 * w.0 - z.1 * w.1, z.0 * w.1 + z.1 * w.0);
        }
        (value, slope)
    }

    /// The series at one angle.
    pub fn value_at(&self, phi: f64) -> f64 {
        self.value_and_slope_at(phi).0
    }

    /// The highest harmonic carried.
    pub fn highest_harmonic(&self) -> usize {
        (self.step * self.cos.len()).max(usize::from(self.a1 != 0.0 || self.b1 != 0.0))
    }
}

/// (re, im) of (c + i·s)^e by binary powering.
fn power(c: f64, s: f64, mut e: usize) -> (f64, f64) {
    let (mut w, mut z) = ((1.0, 0.0), (c, s));
    loop {
        if e & 1 == 1 {
            w = (w.0 * z.0 - w.1 * z.1, w.0 * z.1 + w.1 * z.0);
        }
        e >>= 1;
        if e == 0 {
            return w;
        }
        z = (z.0 * z.0 - z.1 * z.1, 2.0 * z.0 * z.1);
    }
}

/// (re, im) of w·z, lane by lane.
#[inline(always)]
fn multiply<M: MulAdd, const N: usize>(w: &mut ([f64; N], [f64; N]), z: &([f64; N], [f64; N])) {
    for l in 0..N {
        let re = M::mul_add(w.0[l], z.0[l], -(w.1[l] * z.1[l]));
        w.1[l] = M::mul_add(w.0[l], z.1[l], w.1[l] * z.0[l]);
        w.0[l] = re;
    }
}

/// (cos pφ, sin pφ) at N points from (cos φ, sin φ) by binary powering.
#[inline(always)]
fn power_lanes<M: MulAdd, const N: usize>(
    c: &[f64; N],
    s: &[f64; N],
    mut e: usize,
) -> ([f64; N], [f64; N]) {
    let mut w = ([1.0; N], [0.0; N]);
    let mut z = (*c, *s);
    loop {
        if e & 1 == 1 {
            multiply::<M, N>(&mut w, &z);
        }
        e >>= 1;
        if e == 0 {
            return w;
        }
        let square = z;
        multiply::<M, N>(&mut z, &square);
    }
}

/// The series at N points, entirely in registers, given (cos φ, sin φ) and
/// w = (cos pφ, sin pφ): a₁ cos φ + b₁ sin φ, then the harmonics of θ = pφ. Every point
/// sees the same operations in the same order.
#[inline(always)]
fn series_points<M: MulAdd, const N: usize>(
    series: &FourierSeries,
    c: &[f64; N],
    s: &[f64; N],
    w: &([f64; N], [f64; N]),
) -> [f64; N] {
    let mut sum = [0.0; N];
    for l in 0..N {
        sum[l] = M::mul_add(series.a1, c[l], series.b1 * s[l]);
    }
    if series.cos.is_empty() {
        return sum;
    }
    // Clenshaw's recurrence in θ = pφ, from the highest harmonic down:
    // b_ν = c_ν + 2 cos θ·b_{ν+1} − b_{ν+2}; then Σ A_ν cos νθ = b^A_1 cos θ − b^A_2 and
    // Σ B_ν sin νθ = b^B_1 sin θ. Three operations per harmonic and sequence, against ten
    // for rotating e^{iνθ}; with the geometrically decaying coefficients of Q its rounding
    // stays at a few ulps of the largest term.
    let two_cos = w.0.map(|c| 2.0 * c);
    let (mut a1, mut a2) = ([0.0; N], [0.0; N]);
    let (mut b1, mut b2) = ([0.0; N], [0.0; N]);
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

/// Points per register block (four AVX-512 vectors).
const LANES: usize = 32;

/// Where a series block gets e^{ipφ}.
trait HarmonicSource: Copy {
    fn block<M: MulAdd, const N: usize>(
        self,
        offset: usize,
        c: &[f64; N],
        s: &[f64; N],
        step: usize,
    ) -> ([f64; N], [f64; N]);
}

/// e^{ipφ} = (e^{iφ})^p by binary powering.
#[derive(Clone, Copy)]
struct Powering;

impl HarmonicSource for Powering {
    #[inline(always)]
    fn block<M: MulAdd, const N: usize>(
        self,
        _offset: usize,
        c: &[f64; N],
        s: &[f64; N],
        step: usize,
    ) -> ([f64; N], [f64; N]) {
        power_lanes::<M, N>(c, s, step)
    }
}

/// e^{ipφ} by rotation on a uniform grid, like e^{iφ}.
impl HarmonicSource for GridAngles<'_> {
    #[inline(always)]
    fn block<M: MulAdd, const N: usize>(
        self,
        offset: usize,
        _c: &[f64; N],
        _s: &[f64; N],
        _step: usize,
    ) -> ([f64; N], [f64; N]) {
        let (ws, wc) = AngleSource::block::<M, N>(self, offset, N);
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
            series_blocks::<M, _, _>(series, angles, GridAngles { rotations, first }, out)
        }
        (Run::Grid(angles), None) => series_blocks::<M, _, _>(series, angles, Powering, out),
        (Run::Points(angles), _) => series_blocks::<M, _, _>(series, angles, Powering, out),
        (Run::Table(angles), _) => series_blocks::<M, _, _>(series, angles, Powering, out),
    }
}

#[inline(always)]
fn series_blocks<M: MulAdd, A: AngleSource, H: HarmonicSource>(
    series: &FourierSeries,
    angles: A,
    harmonic: H,
    out: &mut [f64],
) {
    // Register blocks of LANES points — sin/cos, e^{ipφ} and the harmonic sum without a
    // pass over memory in between (several independent chains hide each step's latency);
    // the last block padded.
    for (b, o) in out.chunks_mut(LANES).enumerate() {
        let (s, c) = angles.block::<M, LANES>(b * LANES, o.len());
        let w = if series.cos.is_empty() {
            ([1.0; LANES], [0.0; LANES]) // unused
        } else {
            harmonic.block::<M, LANES>(b * LANES, &c, &s, series.step)
        };
        store(o, &series_points::<M, LANES>(series, &c, &s, &w));
    }
}

#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
fn series_run(series: &FourierSeries, run: Run, harmonic: Option<&Rotations>, out: &mut [f64]) {
    if target_cfg_f!(target_feature = "fma") {
        series_segment::<Fused>(series, run, harmonic, out)
    } else {
        series_segment::<Unfused>(series, run, harmonic, out)
    }
}

/// Evaluate a series at every φ of `phi` into `out`.
pub fn evaluate_series_one(series: &FourierSeries, phi: &[f64], out: &mut [f64]) {
    series_run(series, Run::points(phi), None, out)
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

/// The series of every design (parallel for many designs).
pub fn build_series(
    kind: SeriesKind,
    designs: &[Design],
    phases: &[f64],
    parallelism: Parallelism,
) -> Vec<FourierSeries> {
    let reach = match kind {
        SeriesKind::Exact => designs
            .iter()
            .map(|d| crate::harmonics::harmonic_reach(d.crank_ratio))
            .max()
            .unwrap_or(24),
        SeriesKind::Paper => PAPER_MAX_HARMONIC,
    };
    let sums = PhaseSums::new(phases, reach);
    map_indices(designs.len(), designs.len() * 64, parallelism, |i| {
        FourierSeries::new(kind, &designs[i], &sums)
    })
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
    let phi = SeriesPhi::new(phi.into(), series, parallelism);
    let n_phi = phi.len();
    check_length("designs", series.len(), designs.len())?;
    check_length("out", series.len() * n_phi, out.len())?;
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
    let phi = SeriesPhi::new(phi.into(), series, parallelism);
    let n_phi = phi.len();
    check_length("out", series.len() * n_phi, out.len())?;
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
