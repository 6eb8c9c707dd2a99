//! The exact extrema of U_w* over one revolution and the speed fluctuation due to gravity,
//! δ_g = max U_w* − min U_w* (docs/theory.md, "Speed fluctuation due to gravity").
//!
//! The extrema of U are at the roots of Q = dU/dφ, and the search for them is rigorous: no
//! root can hide between samples. The revolution is cut into cells; over a cell of width
//! h a bound M2 ≥ |Q''| gives, from each end e, |Q(e ± t)| ≥ |Q(e)| ± Q'(e)·t − M2·t²/2.
//! A cell is dropped when that stays clear of zero over each half of it; it holds at most
//! one root when Q' provably keeps its sign over it (|Q'(e)| > M2·h/2 from both ends, same
//! sign), which a sign change of Q then brackets and safeguarded Newton steps polish to
//! full precision; any other cell is halved. Three roots crowded into one cell (an upright
//! unit with u2 ≈ −(1 − λ)·u1 and a slight tilt puts them within 1e-4 of bottom dead
//! centre) are separated this way, where a sign-change scan on a grid saw one or none and
//! under-reported δ_g (issue 13, item 3). Cells where Q cannot be told from its rounding
//! noise are not split further (U is flat there to that noise times their width). Every
//! sampled U is a candidate as well, so the result is never below a sampled max − min.
//!
//! The search runs on the machine-precision Fourier form of Q (`series`), with its
//! antiderivative and derivative from the same harmonics: M2 = Σ n²·|c_n|. Where the crank
//! sum leaves only harmonics of step p (no first harmonic), Q has period 2π/p and the
//! search runs in θ = pφ over one such period. Where the series cannot reach machine
//! precision (λ → 1, beyond MAX_HARMONIC harmonics), it runs on the closed form, with M2
//! bounded per cell from the smallest 1 − λ² sin²ψ there (`Coefficients::bounds`): the
//! cells crossing the narrow features near ψ = π/2 are halved until they resolve them.
//! Where the crank sum cancels all but a tiny high harmonic (k = 7, say), the closed form's
//! rounding noise (ε times the single-crank terms) would swamp U_w*'s variation, while the
//! series carries exactly the surviving harmonics to full relative precision. The closed
//! form fixes only the constant (U_w* at φ = 0). Q_u* ≡ 0 (U_w* constant, e.g. γ = 0 with
//! k ≥ 2) gives exactly 0.

use std::f64::consts::TAU;

use crate::exact::Coefficients;
use crate::mechanism::{Design, Phases};
use crate::parallel::{map_indices, Parallelism};
use crate::series::FourierSeries;
use crate::trig::{sincos_with, Unfused};

/// min and max of U_w* over one revolution, the angles where they occur, and their
/// difference δ_g.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyExtrema {
    pub min: f64,
    pub min_at: f64,
    pub max: f64,
    pub max_at: f64,
    /// max − min, taken before the constant level is added: a variation below one ulp of
    /// the level (a crank set that cancels all but a tiny harmonic) survives in it.
    pub range: f64,
}

impl EnergyExtrema {
    pub fn range(&self) -> f64 {
        self.range
    }

    /// The field names, in order.
    pub const NAMES: [&'static str; 5] = ["min", "min_at", "max", "max_at", "range"];

    /// The field called `name` (one of `NAMES`).
    pub fn get(&self, name: &str) -> Option<f64> {
        Some(match name {
            "min" => self.min,
            "min_at" => self.min_at,
            "max" => self.max,
            "max_at" => self.max_at,
            "range" => self.range,
            _ => return None,
        })
    }
}

/// Q, dQ/dy and U (up to the curve's constant) at one point y of the search variable.
#[derive(Debug, Clone, Copy)]
struct Sample {
    y: f64,
    q: f64,
    dq: f64,
}

/// Over a cell: a bound on |d²Q/dy²|, and how far rounding may move Q and dQ/dy.
#[derive(Debug, Clone, Copy)]
struct Bounds {
    curvature: f64,
    noise_q: f64,
    noise_dq: f64,
}

/// What the search needs of Q_u* and U_w*, in a variable y = scale·φ with period 2π.
trait Curve {
    /// y per radian of φ.
    fn scale(&self) -> f64;
    /// (Q, dQ/dy, U) at y.
    fn at(&self, y: f64) -> (f64, f64, f64);
    /// The bounds over [a, b].
    fn bounds(&self, a: f64, b: f64) -> Bounds;
    /// Cells of the first grid over one period.
    fn cells(&self) -> usize;
}

/// Rounding of a sum of terms, relative to their sizes (8ε: a few operations each), plus a
/// shift of the angle by a few ulps of 2π times the next derivative's size.
fn noise(terms: f64, next: f64) -> f64 {
    8.0 * f64::EPSILON * (terms + 8.0 * next)
}

/// First-grid cells for a curve whose derivatives are bounded by `s1` and `s2` against its
/// size `s0`: ~6 per 2π/ω with ω = √(s2/s0), so that M2·h²/8 is a few percent of |Q|.
fn cells_for(s0: f64, s2: f64) -> usize {
    if s0 > 0.0 && s2 > 0.0 {
        ((6.0 * (s2 / s0).sqrt()).ceil() as usize).clamp(8, 4096)
    } else {
        8
    }
}

/// The machine-precision series, its derivative and antiderivative, from the same powers
/// e^{iny}.
struct SeriesCurve {
    scale: f64,
    /// The first harmonic (in φ; zero where the search runs in θ = pφ).
    a1: f64,
    b1: f64,
    /// The harmonics' step in y: each term's e^{iνy·step}.
    step: usize,
    /// Per harmonic ν: A, B, n·A, n·B, A/n, B/n, n the harmonic number in φ.
    terms: Vec<[f64; 6]>,
    bounds: Bounds,
    cells: usize,
}

impl SeriesCurve {
    fn new(series: &FourierSeries) -> Self {
        let reduced = series.a1 == 0.0 && series.b1 == 0.0 && series.step > 0;
        let scale = if reduced { series.step as f64 } else { 1.0 };
        // Sizes |a| + |b| ≥ √(a² + b²): bounds stay bounds, without a hypot per term.
        let first = series.a1.abs() + series.b1.abs();
        let (mut s0, mut s1, mut s2) = (first, first, first);
        let terms: Vec<[f64; 6]> = series
            .cos
            .iter()
            .zip(&series.sin)
            .enumerate()
            .map(|(nu, (&a, &b))| {
                let n = ((nu + 1) * series.step) as f64;
                let size = a.abs() + b.abs();
                s0 += size;
                s1 += n * size;
                s2 += n * n * size;
                [a, b, n * a, n * b, a / n, b / n]
            })
            .collect();
        let (s1, s2) = (s1 / scale, s2 / (scale * scale));
        let count = terms.len() as f64 + 2.0;
        Self {
            scale,
            a1: series.a1,
            b1: series.b1,
            step: if reduced { 1 } else { series.step },
            terms,
            bounds: Bounds {
                curvature: s2,
                noise_q: noise(count * s0, s1),
                noise_dq: noise(count * s1, s2),
            },
            cells: cells_for(s0, s2),
        }
    }
}

impl Curve for SeriesCurve {
    fn scale(&self) -> f64 {
        self.scale
    }

    fn at(&self, y: f64) -> (f64, f64, f64) {
        let (s, c) = sincos_with::<Unfused>(y);
        let mut q = self.a1 * c + self.b1 * s;
        let mut dq = self.b1 * c - self.a1 * s;
        let mut u = self.a1 * s - self.b1 * c;
        if !self.terms.is_empty() {
            let w = power(c, s, self.step);
            let mut z = w;
            for [a, b, na, nb, ad, bd] in &self.terms {
                q += a * z.0 + b * z.1;
                dq += nb * z.0 - na * z.1;
                u += ad * z.1 - bd * z.0;
                z = (z.0 * w.0 - z.1 * w.1, z.0 * w.1 + z.1 * w.0);
            }
        }
        (q, dq / self.scale, u)
    }

    fn bounds(&self, _a: f64, _b: f64) -> Bounds {
        self.bounds
    }

    fn cells(&self) -> usize {
        self.cells
    }
}

/// (re, im) of (c + i·s)^e by binary powering (e ≥ 1).
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

/// The closed form, for series that cannot reach machine precision (λ → 1).
struct ClosedCurve<'a> {
    units: &'a [Coefficients],
    phases: &'a Phases,
    cells: usize,
}

impl ClosedCurve<'_> {
    fn unit(&self, j: usize) -> &Coefficients {
        if self.units.len() == 1 {
            &self.units[0]
        } else {
            &self.units[j]
        }
    }

    /// (sin, cos) of ψ_j = y + α_j.
    fn crank(&self, j: usize, s: f64, c: f64) -> (f64, f64) {
        let (sa, ca) = (self.phases.sin[j], self.phases.cos[j]);
        (s * ca + c * sa, c * ca - s * sa)
    }
}

impl Curve for ClosedCurve<'_> {
    fn scale(&self) -> f64 {
        1.0
    }

    fn at(&self, y: f64) -> (f64, f64, f64) {
        let (s, c) = sincos_with::<Unfused>(y);
        let (mut u, mut q, mut dq) = (0.0, 0.0, 0.0);
        for j in 0..self.phases.len() {
            let (sj, cj) = self.crank(j, s, c);
            let (uj, qj, dqj) = self.unit(j).values(sj, cj);
            (u, q, dq) = (u + uj, q + qj, dq + dqj);
        }
        (q, dq, u)
    }

    fn bounds(&self, a: f64, b: f64) -> Bounds {
        let ((sa, ca), (sb, cb)) = (sincos_with::<Unfused>(a), sincos_with::<Unfused>(b));
        let mut sizes = [0.0; 3];
        for j in 0..self.phases.len() {
            // cos ψ_j at both ends: a cell (shorter than π) crosses a zero of it — where
            // 1 − λ² sin²ψ is smallest — exactly when the signs differ.
            let (ea, eb) = (self.crank(j, sa, ca).1, self.crank(j, sb, cb).1);
            let cos2_min = if ea * eb <= 0.0 {
                0.0
            } else {
                (ea * ea).min(eb * eb)
            };
            let unit = self.unit(j);
            for (total, size) in sizes
                .iter_mut()
                .zip(unit.bounds(unit.root_argument(cos2_min)))
            {
                *total += size;
            }
        }
        Bounds {
            curvature: sizes[2],
            noise_q: noise(sizes[0], sizes[1]),
            noise_dq: noise(sizes[1], sizes[2]),
        }
    }

    fn cells(&self) -> usize {
        self.cells
    }
}

/// The exact extrema of U_w* over φ ∈ [0, 2π) for one design.
pub fn energy_extrema(design: &Design, phases: &Phases, series: &FourierSeries) -> EnergyExtrema {
    extrema_of_units(&[Coefficients::new(design)], phases, series)
}

/// The exact extrema of U_w* of crank units (shared or per-unit coefficients), searched on
/// their series where it is complete and on the closed form where it is not.
pub(crate) fn extrema_of_units(
    units: &[Coefficients],
    phases: &Phases,
    series: &FourierSeries,
) -> EnergyExtrema {
    let closed = ClosedCurve {
        units,
        phases,
        cells: 0,
    };
    let energy_at_zero = closed.at(0.0).2;
    let curve = SeriesCurve::new(series);
    if series.complete {
        if curve.terms.is_empty() && curve.a1 == 0.0 && curve.b1 == 0.0 {
            // Q ≡ 0: U is its value at 0 everywhere.
            return EnergyExtrema {
                min: energy_at_zero,
                min_at: 0.0,
                max: energy_at_zero,
                max_at: 0.0,
                range: 0.0,
            };
        }
        search(&curve, energy_at_zero)
    } else {
        // The closed form: a coarse grid, its cells halved where the bounds ask (across the
        // narrow features near ψ = π/2 of each unit), not a grid fine enough everywhere.
        search(
            &ClosedCurve {
                cells: 64,
                ..closed
            },
            energy_at_zero,
        )
    }
}

/// The extremes of the U values offered, with where they were.
struct Extremes {
    min: (f64, f64),
    max: (f64, f64),
}

impl Extremes {
    fn consider(&mut self, y: f64, u: f64) {
        if u < self.min.1 {
            self.min = (y, u);
        }
        if u > self.max.1 {
            self.max = (y, u);
        }
    }
}

/// Cells narrower than this (relative to the angle) are not split: they are at rounding
/// level, and U varies over one by at most its width times |Q|.
const NARROWEST: f64 = 64.0 * f64::EPSILON;

/// Where the cubic Hermite interpolant of Q over the cell [l, r] (values and slopes at both
/// ends) crosses zero, by Newton steps on the cubic itself from the secant point: a start
/// within ~h⁴·max|Q⁗|/384 of the root, so that one or two steps on Q finish the job.
fn hermite_root(l: &Sample, r: &Sample) -> f64 {
    let h = r.y - l.y;
    let (q0, q1, m0, m1) = (l.q, r.q, l.dq * h, r.dq * h);
    // H(s) = q0 + m0 s + (3(q1 − q0) − 2m0 − m1) s² + (2(q0 − q1) + m0 + m1) s³, s ∈ [0, 1]
    let (c2, c3) = (3.0 * (q1 - q0) - 2.0 * m0 - m1, 2.0 * (q0 - q1) + m0 + m1);
    let mut s = q0 / (q0 - q1);
    for _ in 0..4 {
        let value = q0 + s * (m0 + s * (c2 + s * c3));
        let slope = m0 + s * (2.0 * c2 + 3.0 * s * c3);
        let next = s - value / slope;
        if !(next > 0.0 && next < 1.0) {
            break;
        }
        s = next;
    }
    let y = l.y + s * h;
    if y > l.y && y < r.y {
        y
    } else {
        0.5 * (l.y + r.y)
    }
}

/// Newton steps smaller than this (relative to the angle) end the polishing: the root is
/// then within ~step² of the point stepped to, and U at the point stepped from is within
/// |Q'|·step²/2 of its extremum — below an ulp of it.
const CONVERGED: f64 = 1.0 / (1u64 << 30) as f64;

/// The root of Q in (l, r), where Q(l) and Q(r) have strictly opposite signs and Q' keeps
/// its sign, or which the cell is too narrow to split further: Newton steps from the
/// Hermite estimate, kept inside the shrinking bracket; where Newton would leave it, a
/// secant step across the bracket (which also closes in on a root at one of its ends, as
/// Newton's step overshoots there). Returns the root and U there.
fn polish_root(curve: &impl Curve, l: Sample, r: Sample) -> (f64, f64) {
    let (mut lo, mut hi) = ((l.y, l.q), (r.y, r.q));
    let negative_at_lo = l.q < 0.0;
    let mut y = hermite_root(&l, &r);
    let mut u = 0.0;
    for _ in 0..100 {
        let (q, dq, value) = curve.at(y);
        u = value;
        if q == 0.0 {
            break;
        }
        if (q < 0.0) == negative_at_lo {
            lo = (y, q);
        } else {
            hi = (y, q);
        }
        let size = y.abs().max(1.0);
        let newton = y - q / dq;
        if (newton - y).abs() <= CONVERGED * size {
            // Within ~step² of the root: done (kept inside the bracket).
            return (newton.max(lo.0).min(hi.0), u);
        }
        if hi.0 - lo.0 <= 4.0 * f64::EPSILON * size {
            break;
        }
        let secant = lo.0 + (hi.0 - lo.0) * lo.1 / (lo.1 - hi.1);
        y = if dq != 0.0 && newton > lo.0 && newton < hi.0 {
            newton
        } else if secant > lo.0 && secant < hi.0 {
            secant
        } else {
            0.5 * (lo.0 + hi.0)
        };
    }
    (y, u)
}

/// Whether Q provably has no zero within half a cell (h/2) of the end `e`, moving in
/// `direction` (+1 from the left end, −1 from the right): from Q(e + σt) = Q(e) + σQ'(e)t
/// + R, |R| ≤ M2·t²/2.
fn clear_of_zero(e: &Sample, direction: f64, h: f64, bounds: &Bounds) -> bool {
    let rest = bounds.curvature * h * h / 8.0;
    if e.q == 0.0 {
        // |Q'(e)|·t > M2·t²/2 for every t ≤ h/2.
        e.dq.abs() > bounds.curvature * h / 4.0 + bounds.noise_dq
    } else {
        let toward_zero = (-e.q.signum() * direction * e.dq).max(0.0);
        e.q.abs() - toward_zero * h / 2.0 - rest > bounds.noise_q
    }
}

/// Search for the extrema over one period of the curve; the result levelled so that U(0)
/// = energy_at_zero, the angles in φ.
fn search(curve: &impl Curve, energy_at_zero: f64) -> EnergyExtrema {
    let cells = curve.cells();
    let sample = |y: f64, extremes: &mut Extremes| {
        let (q, dq, u) = curve.at(y);
        extremes.consider(y, u);
        Sample { y, q, dq }
    };
    let (q0, dq0, u0) = curve.at(0.0);
    let mut extremes = Extremes {
        min: (0.0, u0),
        max: (0.0, u0),
    };
    // Samples allowed beyond the first grid (a guard for pathological curves, far above
    // anything seen: a near-degenerate cell takes a few dozen).
    let mut budget = 64 * cells + 100_000;
    // Cells still to look at: each split replaces a cell by its two halves, so the stack
    // holds at most one cell per halving (≤ ~46 from 2π/8 down to NARROWEST).
    let mut stack: Vec<(Sample, Sample)> = Vec::with_capacity(16);
    let mut left = Sample {
        y: 0.0,
        q: q0,
        dq: dq0,
    };
    for i in 1..=cells {
        let y = if i == cells {
            TAU
        } else {
            TAU * i as f64 / cells as f64
        };
        let right = sample(y, &mut extremes);
        stack.push((left, right));
        while let Some((l, r)) = stack.pop() {
            let h = r.y - l.y;
            let bounds = curve.bounds(l.y, r.y);
            if clear_of_zero(&l, 1.0, h, &bounds) && clear_of_zero(&r, -1.0, h, &bounds) {
                continue; // no root inside
            }
            let opposite = (l.q < 0.0 && r.q > 0.0) || (l.q > 0.0 && r.q < 0.0);
            let slope_margin = bounds.curvature * h / 2.0 + bounds.noise_dq;
            let monotone = l.dq.abs() > slope_margin
                && r.dq.abs() > slope_margin
                && (l.dq > 0.0) == (r.dq > 0.0);
            if monotone {
                // At most one root: inside when Q changes sign strictly.
                if opposite {
                    let (y, u) = polish_root(curve, l, r);
                    extremes.consider(y, u);
                }
                continue;
            }
            // Q indistinguishable from its noise over the cell: U is flat there.
            let reach = |e: &Sample| e.q.abs() + e.dq.abs() * h / 2.0;
            let flat =
                reach(&l).max(reach(&r)) + bounds.curvature * h * h / 8.0 <= 2.0 * bounds.noise_q;
            let narrow = h <= NARROWEST * r.y.abs().max(1.0);
            if flat || narrow || budget == 0 {
                if opposite {
                    let (y, u) = polish_root(curve, l, r);
                    extremes.consider(y, u);
                }
                continue;
            }
            budget -= 1;
            let middle = sample(0.5 * (l.y + r.y), &mut extremes);
            stack.push((middle, r));
            stack.push((l, middle));
        }
        left = right;
    }
    let level = energy_at_zero - u0;
    let scale = curve.scale();
    EnergyExtrema {
        min: extremes.min.1 + level,
        min_at: extremes.min.0 / scale,
        max: extremes.max.1 + level,
        max_at: extremes.max.0 / scale,
        range: extremes.max.1 - extremes.min.1,
    }
}

/// The extrema of U_w* for every design (each with its own series).
pub fn all_energy_extrema(
    designs: &[Design],
    phases: &Phases,
    series: &[FourierSeries],
    parallelism: Parallelism,
) -> Vec<EnergyExtrema> {
    map_indices(
        designs.len(),
        designs.len().saturating_mul(4096),
        parallelism,
        |i| energy_extrema(&designs[i], phases, &series[i]),
    )
}

#[cfg(test)]
mod tests;
