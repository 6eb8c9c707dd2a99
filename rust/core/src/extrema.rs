//! The exact extrema of U_w* over one revolution and the speed fluctuation due to gravity,
//! δ_g = max U_w* − min U_w* (docs/theory.md, "Speed fluctuation due to gravity").
//!
//! Everything is done on the machine-precision Fourier form of Q_u* (`series`) and its
//! antiderivative and derivative, not on the closed form: where the crank sum cancels all
//! but a tiny high harmonic (k = 7, say), the closed form's rounding noise (ε times the
//! single-crank terms) would swamp U_w*'s variation, while the series carries exactly the
//! surviving harmonics to full relative precision. The closed form fixes only the constant
//! (U_w* at φ = 0).
//!
//! Q_u* is sampled on a grid fine enough for its highest significant harmonic; every sign
//! change brackets an extremum of U_w*, which safeguarded Newton steps polish to full
//! precision. The grid values are candidates too, so the result is never below a sampled
//! maximum minus minimum on the same grid, and Q_u* ≡ 0 (U_w* constant, e.g. γ = 0 with
//! k ≥ 2) gives exactly 0.

use std::f64::consts::TAU;

use crate::angles::Run;
use crate::exact::{evaluate_units, Coefficients, Quantity};
use crate::mechanism::{Design, Phases};
use crate::parallel::{map_indices, Parallelism};
use crate::series::FourierSeries;
use crate::series_kernels::evaluate_series_one;

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

/// Grid points per revolution: 16 per period of the highest harmonic that matters
/// (amplitude ≥ 1e-9 of the largest), at least 128.
fn grid_size(series: &FourierSeries) -> usize {
    let largest = series
        .cos
        .iter()
        .zip(&series.sin)
        .map(|(a, b)| a.hypot(*b))
        .fold(series.a1.hypot(series.b1), f64::max);
    let mut highest = 1;
    for (nu, (a, b)) in series.cos.iter().zip(&series.sin).enumerate() {
        if a.hypot(*b) >= 1e-9 * largest {
            highest = (nu + 1) * series.step;
        }
    }
    (16 * highest).max(128)
}

/// What the extrema search needs of Q_u* and U_w*.
trait Curve {
    /// Q and U (up to a constant) on the grid.
    fn on_grid(&self, phi: &[f64], q: &mut [f64], u: &mut [f64]);
    /// (Q, dQ/dφ) at one angle.
    fn force_and_slope(&self, x: f64) -> (f64, f64);
    /// U (up to the same constant) at one angle.
    fn energy(&self, x: f64) -> f64;
}

/// The machine-precision series and its antiderivative (no constant term).
struct SeriesCurve<'a> {
    force: &'a FourierSeries,
    energy: FourierSeries,
}

impl Curve for SeriesCurve<'_> {
    fn on_grid(&self, phi: &[f64], q: &mut [f64], u: &mut [f64]) {
        evaluate_series_one(self.force, phi, q);
        evaluate_series_one(&self.energy, phi, u);
    }
    fn force_and_slope(&self, x: f64) -> (f64, f64) {
        self.force.value_and_slope_at(x)
    }
    fn energy(&self, x: f64) -> f64 {
        self.energy.value_at(x)
    }
}

/// The closed form, for series that cannot reach machine precision (λ → 1).
struct ClosedCurve<'a> {
    units: &'a [Coefficients],
    phases: &'a Phases,
}

impl ClosedCurve<'_> {
    fn at(&self, quantity: Quantity, x: f64) -> f64 {
        let mut out = [0.0];
        evaluate_units(
            quantity,
            self.units,
            self.phases,
            Run::points(&[x]),
            &mut out,
        );
        out[0]
    }
}

impl Curve for ClosedCurve<'_> {
    fn on_grid(&self, phi: &[f64], q: &mut [f64], u: &mut [f64]) {
        evaluate_units(
            Quantity::GeneralizedForce,
            self.units,
            self.phases,
            Run::points(phi),
            q,
        );
        evaluate_units(
            Quantity::PotentialEnergy,
            self.units,
            self.phases,
            Run::points(phi),
            u,
        );
    }
    fn force_and_slope(&self, x: f64) -> (f64, f64) {
        (
            self.at(Quantity::GeneralizedForce, x),
            self.at(Quantity::ForceDerivative, x),
        )
    }
    fn energy(&self, x: f64) -> f64 {
        self.at(Quantity::PotentialEnergy, x)
    }
}

/// The root of Q in [lo, hi], where Q(lo) = q_lo and Q(hi) = q_hi differ in sign: Newton
/// steps from the secant point, kept inside the shrinking bracket, bisection where Newton
/// would leave it.
fn polish_root(curve: &impl Curve, mut lo: f64, mut hi: f64, q_lo: f64, q_hi: f64) -> f64 {
    let mut x = lo + (hi - lo) * q_lo / (q_lo - q_hi);
    if !(x > lo && x < hi) {
        x = 0.5 * (lo + hi);
    }
    for _ in 0..100 {
        let (q, dq) = curve.force_and_slope(x);
        if q == 0.0 {
            return x;
        }
        if (q < 0.0) == (q_lo < 0.0) {
            lo = x;
        } else {
            hi = x;
        }
        let newton = x - q / dq;
        let next = if dq != 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - x).abs() <= 2.0 * f64::EPSILON * x.abs().max(1.0)
            || hi - lo <= 4.0 * f64::EPSILON * x.abs().max(1.0)
        {
            return next;
        }
        x = next;
    }
    x
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
    let closed = ClosedCurve { units, phases };
    let energy_at_zero = closed.at(Quantity::PotentialEnergy, 0.0);
    let m = grid_size(series);
    if series.complete {
        let curve = SeriesCurve {
            force: series,
            energy: series.integral(),
        };
        search(&curve, m, energy_at_zero)
    } else {
        search(&closed, m, energy_at_zero)
    }
}

/// Grid, sign changes, polished roots; the extrema levelled so that U(0) = energy_at_zero.
fn search(curve: &impl Curve, m: usize, energy_at_zero: f64) -> EnergyExtrema {
    let phi: Vec<f64> = (0..=m).map(|i| TAU * i as f64 / m as f64).collect();
    let (mut q, mut u) = (vec![0.0; m + 1], vec![0.0; m + 1]);
    curve.on_grid(&phi, &mut q, &mut u);
    // Extrema of U up to its constant first (δ_g keeps variations below the level's ulp),
    // then the level.
    let mut best = EnergyExtrema {
        min: u[0],
        min_at: 0.0,
        max: u[0],
        max_at: 0.0,
        range: 0.0,
    };
    let mut consider = |at: f64, value: f64| {
        if value < best.min {
            best.min = value;
            best.min_at = at;
        }
        if value > best.max {
            best.max = value;
            best.max_at = at;
        }
    };
    for i in 0..m {
        consider(phi[i], u[i]);
        let (qa, qb) = (q[i], q[i + 1]);
        // Q changes sign strictly inside the cell (a zero at a grid point is a candidate already).
        if (qa < 0.0 && qb > 0.0) || (qa > 0.0 && qb < 0.0) {
            let root = polish_root(curve, phi[i], phi[i + 1], qa, qb);
            consider(root, curve.energy(root));
        }
    }
    let level = energy_at_zero - u[0];
    best.range = best.max - best.min;
    best.min += level;
    best.max += level;
    best
}

/// The extrema of U_w* for every design (each with its own series for the grid size).
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
