//! Q_u*(φ) from its Fourier form (mathematics.md §4): only the harmonics that survive the
//! crank sum, evaluated by rotation so that the cost per point hardly depends on k.
//!
//! A series is a₁ cos φ + b₁ sin φ + Σ_{ν=1}^{V} A_ν cos(νpφ) + B_ν sin(νpφ), where p is
//! the step of the surviving even harmonics (p = k for a two-stroke single-acting machine).
//! Per point: one sincos of φ, w = e^{ipφ} by binary powering, then one complex rotation
//! and one multiply-add pair per harmonic.

use multiversion::multiversion;

use crate::error::{check_length, Result};
use crate::exact::{evaluate_run, Quantity};
use crate::harmonics::{lambda_paper, ExactLambdas, PhaseSums, UnitAmplitudes, PAPER_MAX_HARMONIC};
use crate::mechanism::{Design, Phases};
use crate::parallel::{for_each_row_segment, map_indices, Parallelism};
use crate::trig::sincos_block;

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

/// Points per block: the block's arrays stay in L1 through the harmonic loop.
const BLOCK: usize = 128;

#[inline(always)]
fn series_segment(series: &FourierSeries, phi: &[f64], out: &mut [f64]) {
    let mut sin_phi = [0.0; BLOCK];
    let mut cos_phi = [0.0; BLOCK];
    let (mut w_re, mut w_im) = ([0.0; BLOCK], [0.0; BLOCK]);
    let (mut z_re, mut z_im) = ([0.0; BLOCK], [0.0; BLOCK]);
    for (phi_b, out_b) in phi.chunks(BLOCK).zip(out.chunks_mut(BLOCK)) {
        let n = phi_b.len();
        let (s, c) = (&mut sin_phi[..n], &mut cos_phi[..n]);
        sincos_block(phi_b, s, c);
        for i in 0..n {
            out_b[i] = series.a1 * c[i] + series.b1 * s[i];
        }
        if series.cos.is_empty() {
            continue;
        }
        // w = e^{ipφ} by binary powering of z = e^{iφ}.
        let (w_re, w_im) = (&mut w_re[..n], &mut w_im[..n]);
        let (z_re, z_im) = (&mut z_re[..n], &mut z_im[..n]);
        w_re.fill(1.0);
        w_im.fill(0.0);
        z_re.copy_from_slice(c);
        z_im.copy_from_slice(s);
        let mut e = series.step;
        loop {
            if e & 1 == 1 {
                for i in 0..n {
                    let re = w_re[i] * z_re[i] - w_im[i] * z_im[i];
                    w_im[i] = w_re[i] * z_im[i] + w_im[i] * z_re[i];
                    w_re[i] = re;
                }
            }
            e >>= 1;
            if e == 0 {
                break;
            }
            for i in 0..n {
                let re = z_re[i] * z_re[i] - z_im[i] * z_im[i];
                z_im[i] = 2.0 * z_re[i] * z_im[i];
                z_re[i] = re;
            }
        }
        // v walks e^{iνpφ}, ν = 1, 2, …, and the sum takes a·Re v + b·Im v per harmonic.
        // Register-blocked: LANES points keep v and their sum in vector registers across all
        // harmonics (one pass over memory per harmonic was load/store-bound), as several
        // independent chains so that the latency of each step is hidden. Every point sees
        // the same operations in the same order as in the remainder loop below.
        let mut i = 0;
        while i + LANES <= n {
            let range = i..i + LANES;
            let mut sum: Lanes = [0.0; LANES];
            let (mut v_re, mut v_im): (Lanes, Lanes) = ([0.0; LANES], [0.0; LANES]);
            let (mut r_re, mut r_im): (Lanes, Lanes) = ([0.0; LANES], [0.0; LANES]);
            sum.copy_from_slice(&out_b[range.clone()]);
            v_re.copy_from_slice(&w_re[range.clone()]);
            v_im.copy_from_slice(&w_im[range.clone()]);
            r_re.copy_from_slice(&w_re[range.clone()]);
            r_im.copy_from_slice(&w_im[range.clone()]);
            for (&a, &b) in series.cos.iter().zip(&series.sin) {
                for l in 0..LANES {
                    sum[l] += a * v_re[l] + b * v_im[l];
                    let re = v_re[l] * r_re[l] - v_im[l] * r_im[l];
                    v_im[l] = v_re[l] * r_im[l] + v_im[l] * r_re[l];
                    v_re[l] = re;
                }
            }
            out_b[range].copy_from_slice(&sum);
            i += LANES;
        }
        z_re[i..].copy_from_slice(&w_re[i..]);
        z_im[i..].copy_from_slice(&w_im[i..]);
        for (&a, &b) in series.cos.iter().zip(&series.sin) {
            for j in i..n {
                out_b[j] += a * z_re[j] + b * z_im[j];
                let re = z_re[j] * w_re[j] - z_im[j] * w_im[j];
                z_im[j] = z_re[j] * w_im[j] + z_im[j] * w_re[j];
                z_re[j] = re;
            }
        }
    }
}

/// Points per register block of the harmonic loop (four AVX-512 vectors).
const LANES: usize = 32;
type Lanes = [f64; LANES];

#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq", "x86_64+avx2+fma"))]
fn series_run(series: &FourierSeries, phi: &[f64], out: &mut [f64]) {
    series_segment(series, phi, out)
}

/// Evaluate a series at every φ into `out`.
pub fn evaluate_series_one(series: &FourierSeries, phi: &[f64], out: &mut [f64]) {
    series_run(series, phi, out)
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

/// Q_u* of each design at every φ from its series, or from the closed form where the
/// series is incomplete (λ too close to 1 for MAX_HARMONIC harmonics), design-major.
pub fn evaluate_series_or_exact(
    series: &[FourierSeries],
    designs: &[Design],
    phases: &Phases,
    phi: &[f64],
    out: &mut [f64],
    parallelism: Parallelism,
) -> Result<()> {
    let expected = series.len() * phi.len();
    check_length("designs", series.len(), designs.len())?;
    check_length("out", expected, out.len())?;
    let work = out.len().saturating_mul(4);
    for_each_row_segment(out, phi.len(), work, parallelism, |row, col, segment| {
        let phi = &phi[col..col + segment.len()];
        if series[row].complete {
            series_run(&series[row], phi, segment)
        } else {
            evaluate_run(
                Quantity::GeneralizedForce,
                &designs[row],
                phases,
                phi,
                segment,
            )
        }
    });
    Ok(())
}

/// Q_u* from the series of each design at every φ, design-major like `exact::evaluate`.
pub fn evaluate_series(
    series: &[FourierSeries],
    phi: &[f64],
    out: &mut [f64],
    parallelism: Parallelism,
) -> Result<()> {
    let expected = series.len() * phi.len();
    check_length("out", expected, out.len())?;
    let work = out.len().saturating_mul(4);
    for_each_row_segment(out, phi.len(), work, parallelism, |row, col, segment| {
        series_run(&series[row], &phi[col..col + segment.len()], segment)
    });
    Ok(())
}
