//! A function known at the nodes of Gauss–Legendre panels between them: each panel's
//! interpolant through its nodes (degree order − 1) with its slope and curvature, and an
//! extremum next to a sample located on it and polished by Newton's steps on the exact slope
//! (docs/theory.md, "How the integrals are taken"): one or two exact evaluations where Brent's
//! method on the exact slope takes a dozen.

use crate::error::Result;

use super::quadrature::{Panels, LEGENDRE};

/// The most points per panel whose interpolants [`Panels::interpolant`] holds.
pub(crate) const MAX_ORDER: usize = super::quadrature::LEGENDRE_TABLE;

/// The polynomial through a function's values at one panel's nodes (degree order − 1), in
/// Legendre coefficients on the panel's own x ∈ [−1, 1], φ = middle + half·x.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Interpolant {
    coefficients: [f64; MAX_ORDER],
    order: usize,
    middle: f64,
    half: f64,
}

impl Interpolant {
    /// φ (rad) at x.
    pub fn angle(&self, x: f64) -> f64 {
        self.middle + self.half * x
    }

    /// The half-width (rad): dφ/dx.
    pub fn half_width(&self) -> f64 {
        self.half
    }

    /// x at φ (rad).
    pub fn unit(&self, angle: f64) -> f64 {
        (angle - self.middle) / self.half
    }

    /// (f, df/dφ, d²f/dφ²) at x: P_k by the three-term recurrence, P_k′ and P_k″ by
    /// P_{k+1}′ = P_{k−1}′ + (2k + 1)P_k and P_{k+1}″ = P_{k−1}″ + (2k + 1)P_k′.
    pub fn at(&self, x: f64) -> [f64; 3] {
        let c = &self.coefficients[..self.order];
        let (mut value, mut slope, mut bend) = (c[0], 0.0, 0.0);
        // P_{k−1} and P_k, with their first and second derivatives, at k = 1.
        let (mut p0, mut p1) = (1.0, x);
        let (mut d0, mut d1) = (0.0, 1.0);
        let (mut b0, mut b1) = (0.0, 0.0);
        for (k, (c, &(a, b, _))) in c.iter().zip(&LEGENDRE).enumerate().skip(1) {
            value += c * p1;
            slope += c * d1;
            bend += c * b1;
            let odd = (2 * k + 1) as f64;
            let p2 = a * x * p1 - b * p0;
            let d2 = d0 + odd * p1;
            let b2 = b0 + odd * d1;
            (p0, p1, d0, d1, b0, b1) = (p1, p2, d1, d2, b1, b2);
        }
        [value, slope / self.half, bend / (self.half * self.half)]
    }
}

impl Panels {
    /// The interpolant on panel `p` of a function given at the nodes (`values`, panel after
    /// panel; edges after them are not read): c_k = (2k + 1)/2 · Σ_i w_i f_i P_k(x_i), exact
    /// by the Gauss rule's discrete orthogonality. `None` for a rule of more than
    /// [`MAX_ORDER`] points.
    pub fn interpolant(&self, p: usize, values: &[f64]) -> Option<Interpolant> {
        let n = self.order;
        if n > MAX_ORDER || n == 0 {
            return None;
        }
        let panel = &values[p * n..(p + 1) * n];
        let mut coefficients = [0.0; MAX_ORDER];
        for ((f, w), &x) in panel.iter().zip(&self.unit_weights).zip(&self.unit_nodes) {
            let fw = f * w;
            let (mut previous, mut current) = (1.0, x);
            coefficients[0] += fw;
            for (c, &(a, b, _)) in coefficients[1..n].iter_mut().zip(&LEGENDRE[1..]) {
                *c += fw * current;
                let next = a * x * current - b * previous;
                (previous, current) = (current, next);
            }
        }
        for (k, c) in coefficients[..n].iter_mut().enumerate() {
            *c *= (2 * k + 1) as f64 * 0.5;
        }
        let (a, b) = (self.edges[p], self.edges[p + 1]);
        Some(Interpolant {
            coefficients,
            order: n,
            middle: 0.5 * (a + b),
            half: 0.5 * (b - a),
        })
    }
}

/// Exact evaluations [`polish`] makes at most.
const POLISH_STEPS: usize = 4;

/// The extremum next to sample `index` (angle order) of `values` (nodes then edges) from
/// the panels' interpolants: the root of the interpolant's slope between the sample's
/// neighbours (Newton's method, kept in the bracket by bisection), then Newton's steps on
/// the exact slope with the interpolant's curvature, each point evaluated exactly
/// (`exact`), until the step's gain ½f′²/|f″| is below 1/16 of an ulp of `scale` (the
/// largest |sample|): the value there is the extremum's to rounding, and the angle is
/// moved by that last step. `None` where the interpolant's slope does not change sign
/// between the neighbours (a kink, an edge whose panels disagree), its curvature has the
/// wrong sign, or the steps do not settle within [`POLISH_STEPS`] evaluations.
pub(crate) fn polish(
    panels: &Panels,
    values: &[f64],
    index: usize,
    largest: bool,
    scale: f64,
    exact: &mut impl FnMut(f64) -> Result<(f64, f64)>,
) -> Result<Option<(f64, f64)>> {
    let sign = if largest { 1.0 } else { -1.0 };
    let (order, count) = (panels.order, panels.count());
    let (p, r) = (index / (order + 1), index % (order + 1));
    let nodes = &panels.unit_nodes;
    // (panel, bracket in its x, the start): the sample's own panel, or the two beside an
    // edge (the one before edge 0 is the last: `exact` takes any angle).
    let mut candidates = [(p, -1.0, 1.0, 0.0); 2];
    let tried = if r == 0 {
        candidates[0] = (p, -1.0, nodes[0], -1.0);
        let before = if p == 0 { count - 1 } else { p - 1 };
        candidates[1] = (before, nodes[order - 1], 1.0, 1.0);
        2
    } else {
        let k = r - 1;
        let low = if k == 0 { -1.0 } else { nodes[k - 1] };
        let high = if k + 1 == order { 1.0 } else { nodes[k + 1] };
        candidates[0] = (p, low, high, nodes[k]);
        1
    };
    for &(panel, low, high, start) in &candidates[..tried] {
        let Some(interpolant) = panels.interpolant(panel, values) else {
            return Ok(None);
        };
        let rate = |x: f64| sign * interpolant.at(x)[1];
        if !(rate(low) >= 0.0 && rate(high) <= 0.0) {
            continue;
        }
        let x = interpolated_root(&interpolant, sign, low, high, start);
        let (from, to) = (interpolant.angle(low), interpolant.angle(high));
        let mut phi = interpolant.angle(x);
        for _ in 0..POLISH_STEPS {
            let (value, slope) = exact(phi)?;
            let bend = interpolant.at(interpolant.unit(phi))[2];
            if !(value.is_finite() && slope.is_finite() && sign * bend < 0.0) {
                return Ok(None);
            }
            let step = -slope / bend;
            if 0.5 * (slope * step).abs() <= scale * f64::EPSILON / 16.0 {
                return Ok(Some((phi + step, value)));
            }
            phi += step;
            if !(from <= phi && phi <= to) {
                return Ok(None);
            }
        }
        return Ok(None);
    }
    Ok(None)
}

/// Where Newton's method on an interpolant's slope stops (panel units): far below what the
/// interpolant resolves (its root is ~1e-7 of a panel off the function's), above the
/// rounding of its slope, which would keep the steps from settling.
const INTERPOLATED_ROOT: f64 = 1e-12;

/// The root in [low, high] (panel units) of the slope of `interpolant` (times `sign`,
/// falling from ≥ 0 at `low` to ≤ 0 at `high`): Newton's method from `start`, a bisection
/// where a step leaves the bracket.
fn interpolated_root(interpolant: &Interpolant, sign: f64, low: f64, high: f64, start: f64) -> f64 {
    let (mut low, mut high) = (low, high);
    let mut x = start;
    // Bisection alone would take ~40 steps to the tolerance.
    for _ in 0..60 {
        let [_, slope, bend] = interpolant.at(x);
        let rate = sign * slope;
        if rate > 0.0 {
            low = x;
        } else if rate < 0.0 {
            high = x;
        } else {
            return x;
        }
        let newton = x - slope / (bend * interpolant.half_width());
        let next = if low < newton && newton < high {
            newton
        } else {
            0.5 * (low + high)
        };
        if (next - x).abs() <= INTERPOLATED_ROOT || high - low <= INTERPOLATED_ROOT {
            return next;
        }
        x = next;
    }
    x
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::super::quadrature::breaks;
    use super::*;

    #[test]
    fn a_panels_interpolant_is_the_polynomial_with_its_derivatives() {
        let panels = Panels::new(&breaks(vec![1.0], 2.0 * PI), 12, PI / 8.0);
        let f = |p: f64| p.powi(11) - 3.0 * p * p;
        let values: Vec<f64> = panels.phi.iter().map(|&p| f(p)).collect();
        let p = 5;
        let interpolant = panels.interpolant(p, &values).unwrap();
        for x in [-1.0, -0.3, 0.0, 0.7, 1.0] {
            let phi = interpolant.angle(x);
            assert!((interpolant.unit(phi) - x).abs() < 1e-15);
            let [v, d, b] = interpolant.at(x);
            let exact = [
                f(phi),
                11.0 * phi.powi(10) - 6.0 * phi,
                110.0 * phi.powi(9) - 6.0,
            ];
            for (found, exact) in [v, d, b].iter().zip(exact) {
                assert!(
                    (found - exact).abs() <= 1e-11 * (1.0 + exact.abs()),
                    "{x}: {found} {exact}"
                );
            }
        }
    }

    #[test]
    fn an_extremum_is_polished_to_rounding_in_an_exact_evaluation_or_two() {
        // f = 10 + cos(3(φ − c)) + 0.2 sin(7φ): smooth, its extremes between the samples;
        // on an edge (the largest, at c) and inside a panel (the smallest).
        let cycle = 2.0 * PI;
        let c = PI / 4.0;
        let panels = Panels::new(&breaks(vec![c], cycle), 12, PI / 8.0);
        let f = |p: f64| 10.0 + (3.0 * (p - c)).cos() + 0.2 * (7.0 * p).sin();
        let slope = |p: f64| -3.0 * (3.0 * (p - c)).sin() + 1.4 * (7.0 * p).cos();
        let everywhere: Vec<f64> = panels.phi.iter().chain(&panels.edges).copied().collect();
        let values: Vec<f64> = everywhere.iter().map(|&p| f(p)).collect();
        let samples = panels.in_angle_order(&values);
        for largest in [true, false] {
            let sign = if largest { 1.0 } else { -1.0 };
            let best = (0..samples.len())
                .max_by(|&a, &b| (sign * samples[a].1).total_cmp(&(sign * samples[b].1)))
                .unwrap();
            let mut calls = 0;
            let mut exact = |p: f64| {
                calls += 1;
                Ok((f(p), slope(p)))
            };
            let (angle, value) = polish(&panels, &values, best, largest, 11.2, &mut exact)
                .unwrap()
                .unwrap();
            assert!(calls <= 2, "{calls} exact evaluations");
            // The root of the slope next to the sample, to rounding, by bisection.
            let (mut low, mut high) = (samples[best].0 - 0.05, samples[best].0 + 0.05);
            for _ in 0..200 {
                let middle = 0.5 * (low + high);
                if sign * slope(middle) > 0.0 {
                    low = middle;
                } else {
                    high = middle;
                }
            }
            assert!((angle - low).abs() < 1e-9, "{angle} vs {low}");
            assert!(
                (value - f(low)).abs() <= 2.0 * f64::EPSILON * 11.2,
                "{value}"
            );
            assert!(sign * value > sign * samples[best].1);
        }
    }
}
