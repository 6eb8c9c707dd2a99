//! Q_u*(φ) as a short trigonometric series (docs/theory.md, "Fourier form and Λ_n"): the one series model of the
//! crate. Every machine is a list of *unit groups* — units that share one design, with the
//! sums of their phases: a regular in-line machine is one group of k identical units, an
//! engine of any layout one group per unit. One builder turns groups into harmonics, with
//! one rule for when a harmonic has cancelled and one cut-off rule for the tail; the series,
//! the Fourier coefficients, the extrema, the leading harmonic and the sweeps all use it.
//!
//! A series is a₁ cos φ + b₁ sin φ + Σ_{ν=1}^{V} A_ν cos(νpφ) + B_ν sin(νpφ), where p is
//! the step of the surviving even harmonics (p = k for a two-stroke single-acting machine).
//! Its SIMD evaluation lives in `series_kernels`.

use crate::error::{try_filled, Result};
use crate::harmonics::{
    gcd, harmonic_reach, harmonic_width, lambda_paper, ExactLambdas, PhaseSums, PAPER_MAX_HARMONIC,
};
use crate::mechanism::{Design, Phases};
use crate::parallel::{for_each_row_pair, map_indices, Parallelism};

/// Which Λ_n and which cut.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesKind {
    /// Exact Λ_n; harmonics up to where a rigorous bound on the rest is below ε·max|Q|/2.
    Exact,
    /// The paper's eq. (16): λ-series Λ_n through λ¹¹, harmonics n ≤ 12.
    Paper,
}

/// Units that share one design, with the sums of their phases: a whole regular in-line
/// machine, or one unit of an engine of any layout.
#[derive(Debug, Clone, Copy)]
pub struct UnitGroup<'a> {
    pub design: &'a Design,
    pub sums: &'a PhaseSums,
}

/// One design's Q_u* as a short trigonometric series (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct FourierSeries {
    pub(crate) a1: f64,
    pub(crate) b1: f64,
    /// Step p of the even harmonics (0 when there are none).
    pub(crate) step: usize,
    /// A_ν, B_ν for harmonic ν·step, ν = 1 … V.
    pub(crate) cos: Vec<f64>,
    pub(crate) sin: Vec<f64>,
    /// Whether the harmonics carried reach machine precision. As λ → 1 the harmonics decay
    /// ever more slowly; past MAX_HARMONIC (λ ≳ 0.9998) the series is incomplete, and the
    /// evaluation and extrema use the closed form instead of returning a truncation.
    pub(crate) complete: bool,
}

/// The per-unit amplitudes of eq. 14: N = U2 cos γ, W1 = N1 + N2, N1 = −U1 sin γ, so that
/// Q = N cos ψ + W1 sin ψ + Σ_{n even} N1 Λ_n sin nψ.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Amplitudes {
    pub n: f64,
    pub w1: f64,
    pub n1: f64,
}

impl Amplitudes {
    pub(crate) fn new(design: &Design) -> Self {
        let (sin_g, cos_g) = design.inclination_sin_cos();
        let n1 = -design.u1 * sin_g;
        Self {
            n: design.u2 * cos_g,
            w1: n1 - design.u2 * sin_g,
            n1,
        }
    }
}

/// Where a group's Λ_2, Λ_4, … come from.
enum Lambdas {
    Exact(ExactLambdas),
    /// The paper's λ-series; entries above n = 12 are 0, as the paper cuts there.
    Paper([f64; PAPER_MAX_HARMONIC + 1], usize),
}

impl Lambdas {
    fn new(kind: SeriesKind, crank_ratio: f64) -> Self {
        match kind {
            SeriesKind::Exact => Self::Exact(ExactLambdas::new(crank_ratio)),
            SeriesKind::Paper => {
                let mut values = [0.0; PAPER_MAX_HARMONIC + 1];
                lambda_paper(crank_ratio, &mut values);
                Self::Paper(values, 0)
            }
        }
    }

    /// Λ_n for the next even n.
    fn next_even(&mut self) -> f64 {
        match self {
            Self::Exact(lambdas) => lambdas.next().unwrap_or(0.0),
            Self::Paper(values, n) => {
                *n += 2;
                values.get(*n).copied().unwrap_or(0.0)
            }
        }
    }

    /// Past the next even n without its Λ_n (every group's phase sums cancel it).
    fn skip_even(&mut self) {
        match self {
            Self::Exact(lambdas) => lambdas.skip(),
            Self::Paper(_, n) => *n += 2,
        }
    }
}

/// A group while its harmonics are summed.
struct GroupState<'a> {
    amplitudes: Amplitudes,
    sums: &'a PhaseSums,
    lambdas: Lambdas,
    /// t = λ/(1 + √(1 − λ²)) and the tail's factor k·|N1|/((1 − t²)(1 − t⁴)).
    t: f64,
    tail_factor: f64,
    /// t^{2M+1} after harmonic 2M.
    t_power: f64,
}

/// Whether a harmonic sum stands above its own rounding noise: a sum of terms whose phase
/// factors cancel to below 8ε of their size has cancelled, and is exactly zero.
fn stands_out(a: f64, b: f64, noise: f64) -> bool {
    let threshold = 8.0 * f64::EPSILON * noise;
    // hypot(a, b) lies between max(|a|, |b|) and |a| + |b|: decide from those where they
    // settle it (nearly always), and take the (slow) hypot only in between.
    let (a, b) = (a.abs(), b.abs());
    if a.max(b) > threshold {
        true
    } else if a + b <= threshold {
        false
    } else {
        a.hypot(b) > threshold
    }
}

/// The harmonics of Q_u* of `groups`: (n, a_n, b_n) for n = 1 and the even n ≤ n_max that
/// do not cancel, and whether the rest is provably negligible.
///
/// Per group g with C_n + iS_n its phase sums, a_1 = N C_1 + W1 S_1, b_1 = W1 C_1 − N S_1,
/// and for even n a_n = W_n S_n, b_n = W_n C_n with W_n = N1 Λ_n; summed over the groups.
///
/// With `cut` (exact Λ_n only) the sum stops where a rigorous bound on the rest is below
/// ε·rms(Q)/2: |Λ_{2m}| ≤ t^{2m−1}/(1 − t⁴) (2m·|C(½, m)| ≤ 1 and the ₂F₁ terms are dominated
/// by t^{4b}) and |S_n| ≤ k, so the harmonics above 2M add at most
/// Σ_g k_g·|N1_g|·t_g^{2M+1}/((1 − t_g²)(1 − t_g⁴)); by Parseval max|Q| ≥ rms(Q) =
/// √(Σ (a_n² + b_n²)/2) over the harmonics kept so far. Without `cut` every harmonic up to
/// n_max is summed and the result counts as complete.
pub(crate) fn harmonic_terms(
    groups: &[UnitGroup],
    kind: SeriesKind,
    n_max: usize,
    cut: bool,
) -> (Vec<(usize, f64, f64)>, bool) {
    let reach = groups.iter().map(|g| g.sums.n_max()).min().unwrap_or(0);
    let mut n_max = n_max.min(reach);
    if kind == SeriesKind::Paper {
        n_max = n_max.min(PAPER_MAX_HARMONIC);
    }
    let cut = cut && kind == SeriesKind::Exact;
    let mut states: Vec<GroupState> = groups
        .iter()
        .map(|g| {
            let amplitudes = Amplitudes::new(g.design);
            let lambdas = Lambdas::new(kind, g.design.crank_ratio);
            let t = match &lambdas {
                Lambdas::Exact(exact) => exact.t(),
                Lambdas::Paper(..) => 0.0,
            };
            let (t2, t4) = (t * t, t * t * t * t);
            GroupState {
                amplitudes,
                sums: g.sums,
                lambdas,
                t,
                tail_factor: g.sums.cranks as f64 * amplitudes.n1.abs() / ((1.0 - t2) * (1.0 - t4)),
                t_power: t,
            }
        })
        .collect();

    let mut terms = Vec::new();
    let (mut a1, mut b1, mut noise) = (0.0, 0.0, 0.0);
    for s in &states {
        let (c, sn, u) = (s.sums.cos[1], s.sums.sin[1], &s.amplitudes);
        a1 += u.n * c + u.w1 * sn;
        b1 += u.w1 * c - u.n * sn;
        noise += (u.n.abs() + u.w1.abs()) * s.sums.noise(1);
    }
    let mut mean_square = 0.0;
    if n_max >= 1 && stands_out(a1, b1, noise) {
        terms.push((1, a1, b1));
        mean_square = 0.5 * (a1 * a1 + b1 * b1);
    }
    // N1 = 0 in every group (γ = 0 or π, or U1 = 0): no even harmonics at all.
    let mut complete = !cut || states.iter().all(|s| s.tail_factor == 0.0);
    for n in (2..=n_max).step_by(2) {
        if cut && complete {
            break;
        }
        let (mut a, mut b, mut noise) = (0.0, 0.0, 0.0);
        let cancelled = states
            .iter()
            .all(|s| s.sums.cos[n] == 0.0 && s.sums.sin[n] == 0.0);
        for s in states.iter_mut() {
            if cancelled {
                // Every group's phase sum is exactly 0 here (a regular crank set keeps
                // only multiples of its step): no Λ_n to compute, no term.
                s.lambdas.skip_even();
                continue;
            }
            let w = s.amplitudes.n1 * s.lambdas.next_even();
            a += w * s.sums.sin[n];
            b += w * s.sums.cos[n];
            noise += w.abs() * s.sums.noise(n);
        }
        if stands_out(a, b, noise) {
            terms.push((n, a, b));
            mean_square += 0.5 * (a * a + b * b);
        }
        if cut {
            let mut tail = 0.0;
            for s in states.iter_mut() {
                s.t_power *= s.t * s.t;
                tail += s.tail_factor * s.t_power;
            }
            // Done when the rest is below ε·rms/2, or negligible outright (all cancelled).
            complete = tail <= 0.5 * f64::EPSILON * mean_square.sqrt()
                || states.iter().all(|s| s.t_power <= 1e-30);
        }
    }
    (terms, complete)
}

/// Fourier coefficients a_n, b_n (n = 0 … a.len() − 1) of Q_u* of `groups`, exact Λ_n,
/// every harmonic; a cancelled harmonic is exactly 0. The groups' phase sums must reach
/// a.len() − 1.
pub(crate) fn fourier_coefficients(groups: &[UnitGroup], a: &mut [f64], b: &mut [f64]) {
    a.fill(0.0);
    b.fill(0.0);
    let (terms, _) = harmonic_terms(groups, SeriesKind::Exact, a.len().saturating_sub(1), false);
    for (n, an, bn) in terms {
        a[n] = an;
        b[n] = bn;
    }
}

impl FourierSeries {
    /// The series of `groups`: with exact Λ_n cut where the rest is provably below
    /// ε·max|Q|/2, or the paper's eq. (16) (λ-series Λ_n, n ≤ 12).
    pub(crate) fn new(kind: SeriesKind, groups: &[UnitGroup]) -> Self {
        let (terms, complete) = harmonic_terms(groups, kind, usize::MAX, true);
        let (a1, b1) = match terms.first() {
            Some(&(1, a, b)) => (a, b),
            _ => (0.0, 0.0),
        };
        let even: Vec<_> = terms.into_iter().filter(|&(n, _, _)| n > 1).collect();
        Self {
            complete,
            ..Self::from_terms(a1, b1, &even)
        }
    }

    /// a₁ cos φ + b₁ sin φ + Σ (a_n cos nφ + b_n sin nφ) over `even` = [(n, a_n, b_n)], n even ascending.
    fn from_terms(a1: f64, b1: f64, even: &[(usize, f64, f64)]) -> Self {
        let step = even
            .iter()
            .fold(0, |g, &(n, _, _)| gcd(g as u128, n as u128) as usize);
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

    /// (n, √(a_n² + b_n²)) of the largest harmonic; (0, 0) when Q ≡ 0 (no harmonic leads).
    pub(crate) fn leading_harmonic(&self) -> (usize, f64) {
        let mut best = (1, self.a1.hypot(self.b1));
        for (nu, (a, b)) in self.cos.iter().zip(&self.sin).enumerate() {
            let amplitude = a.hypot(*b);
            if amplitude > best.1 {
                best = ((nu + 1) * self.step, amplitude);
            }
        }
        if best.1 == 0.0 {
            (0, 0.0)
        } else {
            best
        }
    }
}

/// The series of every design of an in-line machine with crank phases `phases` (parallel
/// for many designs).
pub fn build_series(
    kind: SeriesKind,
    designs: &[Design],
    phases: &[f64],
    parallelism: Parallelism,
) -> Vec<FourierSeries> {
    let reach = match kind {
        SeriesKind::Exact => designs
            .iter()
            .map(|d| harmonic_reach(d.crank_ratio))
            .max()
            .unwrap_or(24),
        SeriesKind::Paper => PAPER_MAX_HARMONIC,
    };
    let sums = PhaseSums::within_reach(phases, reach);
    map_indices(
        designs.len(),
        designs.len().saturating_mul(64),
        parallelism,
        |i| {
            FourierSeries::new(
                kind,
                &[UnitGroup {
                    design: &designs[i],
                    sums: &sums,
                }],
            )
        },
    )
}

/// Fourier coefficients a_n, b_n (n = 0 … n_max) of every design of an in-line machine with
/// crank phases `phases`, design-major rows of n_max + 1; in parallel for many designs.
pub fn fourier_table(
    designs: &[Design],
    phases: &[f64],
    n_max: usize,
    parallelism: Parallelism,
) -> Result<(Vec<f64>, Vec<f64>)> {
    Phases::new(phases)?;
    let width = harmonic_width(n_max)?;
    let len = designs.len() as u128 * width as u128;
    let mut a = try_filled("n_max", n_max, len, 0.0)?;
    let mut b = try_filled("n_max", n_max, len, 0.0)?;
    let sums = PhaseSums::new(phases, n_max.max(1))?;
    let work = designs.len().saturating_mul(width).saturating_mul(64);
    for_each_row_pair(
        &mut a,
        &mut b,
        width,
        work,
        parallelism,
        |i, row_a, row_b| {
            let group = UnitGroup {
                design: &designs[i],
                sums: &sums,
            };
            fourier_coefficients(&[group], row_a, row_b);
        },
    );
    Ok((a, b))
}
