//! The margin s of the energy method (docs/theory.md, "Steady running"): the period
//! t_Φ(s) = ∫₀^Φ √(J/2(s + K̃)) dφ on a time mesh, and the s that gives the mean speed asked
//! for — the root of (Φ/(t_Φ(s)·ω_m))² − 1, increasing and nearly linear in s, by Newton's
//! method from the estimate of the cycle means.

use multiversion::multiversion;

use super::quadrature::Panels;

/// The rule on which t_Φ = ∫₀^Φ √(J/2E) dφ is taken: the base panels graded towards E's
/// near-zeros, and there K̃ (J) and J − I_w (kg·m²), nodes then edges.
#[derive(Debug, Clone)]
pub(super) struct Graded {
    pub panels: Panels,
    pub lifted: Vec<f64>,
    pub rest: Vec<f64>,
}

impl Graded {
    pub fn view(&self) -> Mesh<'_> {
        Mesh {
            panels: &self.panels,
            lifted: &self.lifted,
            rest: &self.rest,
        }
    }
}

/// A time mesh: the base panels and tables or a graded one.
#[derive(Clone, Copy)]
pub(super) struct Mesh<'m> {
    pub panels: &'m Panels,
    pub lifted: &'m [f64],
    pub rest: &'m [f64],
}

/// Newton's steps on the margin before the root is left to Brent's method.
const NEWTON_STEPS: usize = 8;

/// s to this (relative) is the root: the tolerance of Brent's method on it (rtol 1e-15).
const MARGIN_RTOL: f64 = 1e-15;

/// How far (|Δs|/E at any node) a period is taken from the terms at another margin by the
/// series of (1 + u)^(−1/2) to u³: its first term left out, 35u⁴/128, is then below 3e-21.
const SERIES_REACH: f64 = 1e-5;

/// What Newton's method on the margin found: the root and t_Φ there, where it settled, and
/// the periods it took.
pub(super) struct Newton {
    pub root: Option<(f64, f64)>,
    pub evaluations: usize,
}

impl Mesh<'_> {
    pub fn nodes(&self) -> usize {
        self.panels.phi.len()
    }

    /// The node columns: weights, J − I_w and K̃.
    fn columns(&self) -> (&[f64], &[f64], &[f64]) {
        let n = self.nodes();
        (
            &self.panels.weights[..n],
            &self.rest[..n],
            &self.lifted[..n],
        )
    }

    /// t_Φ(s) (s) with I_w = `inertia` (kg·m²).
    pub fn period(&self, inertia: f64, s: f64) -> f64 {
        let (w, rest, k) = self.columns();
        period_sum(w, rest, k, inertia, s)
    }

    /// The margin s (J) whose period is `target` (s) with I_w = `inertia` (kg·m²): Newton's
    /// method on (target/t_Φ(s))² − 1 from the s of the cycle means, ½J̄ω_m² − K̃̄ (exact
    /// where J and K̃ do not vary; its error is of the order of δ²), to the tolerance of
    /// Brent's method (1e-15 of s). The slope dt_Φ/ds is the one at the last margin where
    /// the terms w√(J/2E) were taken exactly; a period within [`SERIES_REACH`] of it is
    /// taken from those terms by a series, without a division or a root. `root`: `None`
    /// where a step falls to `s_low` or below, the excess or its slope is not finite, or
    /// [`NEWTON_STEPS`] do not settle (the caller then brackets the root from s_low).
    pub fn newton(&self, inertia: f64, target: f64, s_low: f64) -> Newton {
        let (w, rest, k) = self.columns();
        let [length, inertia_sum, lifted_sum, lowest] = means(w, rest, k, inertia);
        let omega = length / target;
        let mut s = 0.5 * inertia_sum / length * omega * omega - lifted_sum / length;
        let mut found = Newton {
            root: None,
            evaluations: 0,
        };
        if s.is_nan() || s <= s_low {
            return found;
        }
        let (mut term, mut over) = (vec![0.0; w.len()], vec![0.0; w.len()]);
        let mut base = s;
        let mut period = exact_terms(w, rest, k, inertia, s, &mut term, &mut over);
        let mut slope = -0.5 * product_sum(&term, &over);
        for _ in 0..NEWTON_STEPS {
            found.evaluations += 1;
            let ratio = target / period;
            let excess = ratio * ratio - 1.0;
            let rate = -2.0 * ratio * ratio * slope / period;
            if !(excess.is_finite() && rate.is_finite() && rate > 0.0) {
                return found;
            }
            let step = -excess / rate;
            if step.abs() <= 0.5 * MARGIN_RTOL * s {
                found.root = Some((s, period));
                return found;
            }
            s += step;
            if s.is_nan() || s <= s_low {
                return found;
            }
            let shift = s - base;
            if shift.abs() <= SERIES_REACH * (base + lowest) {
                period = shifted_period(&term, &over, shift);
            } else {
                base = s;
                period = exact_terms(w, rest, k, inertia, s, &mut term, &mut over);
                slope = -0.5 * product_sum(&term, &over);
            }
        }
        found
    }
}

// The sums over the nodes, in LANES running sums added at the end: the same sum in the same
// order every time, and one the compiler keeps in vector registers (a single running sum of
// doubles it may not reorder; two in one loop it does not vectorise). One clone per
// instruction set (the same IEEE operations in each: no multiply-add is fused), picked at
// run time.

/// The running sums of the period's quadrature.
const LANES: usize = 8;

/// t_Φ(s) = Σ w√(J/2E) over the nodes (weights `w`, J − I_w `rest`, K̃ `k`), I_w =
/// `inertia`, E = s + K̃.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
fn period_sum(w: &[f64], rest: &[f64], k: &[f64], inertia: f64, s: f64) -> f64 {
    let term = |w: f64, rest: f64, k: f64| w * (0.5 * (inertia + rest) / (s + k)).sqrt();
    let mut lanes = [0.0; LANES];
    let whole = w.len() / LANES * LANES;
    for ((w, rest), k) in w[..whole]
        .chunks_exact(LANES)
        .zip(rest[..whole].chunks_exact(LANES))
        .zip(k[..whole].chunks_exact(LANES))
    {
        for lane in 0..LANES {
            lanes[lane] += term(w[lane], rest[lane], k[lane]);
        }
    }
    let tail: f64 = (whole..w.len()).map(|i| term(w[i], rest[i], k[i])).sum();
    lanes.iter().sum::<f64>() + tail
}

/// t_Φ(s) as [`period_sum`] takes it, each node's term w√(J/2E) into `term` and 1/E into
/// `over`.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
fn exact_terms(
    w: &[f64],
    rest: &[f64],
    k: &[f64],
    inertia: f64,
    s: f64,
    term: &mut [f64],
    over: &mut [f64],
) -> f64 {
    let mut lanes = [0.0; LANES];
    let whole = w.len() / LANES * LANES;
    for ((((w, rest), k), term), over) in w[..whole]
        .chunks_exact(LANES)
        .zip(rest[..whole].chunks_exact(LANES))
        .zip(k[..whole].chunks_exact(LANES))
        .zip(term[..whole].chunks_exact_mut(LANES))
        .zip(over[..whole].chunks_exact_mut(LANES))
    {
        for lane in 0..LANES {
            over[lane] = 1.0 / (s + k[lane]);
            term[lane] = w[lane] * (0.5 * (inertia + rest[lane]) * over[lane]).sqrt();
            lanes[lane] += term[lane];
        }
    }
    let mut tail = 0.0;
    for i in whole..w.len() {
        over[i] = 1.0 / (s + k[i]);
        term[i] = w[i] * (0.5 * (inertia + rest[i]) * over[i]).sqrt();
        tail += term[i];
    }
    lanes.iter().sum::<f64>() + tail
}

/// Σ a·b.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
fn product_sum(a: &[f64], b: &[f64]) -> f64 {
    let mut lanes = [0.0; LANES];
    let whole = a.len() / LANES * LANES;
    for (a, b) in a[..whole]
        .chunks_exact(LANES)
        .zip(b[..whole].chunks_exact(LANES))
    {
        for lane in 0..LANES {
            lanes[lane] += a[lane] * b[lane];
        }
    }
    let tail: f64 = (whole..a.len()).map(|i| a[i] * b[i]).sum();
    lanes.iter().sum::<f64>() + tail
}

/// t_Φ at the margin `shift` from the one whose terms w√(J/2E) and 1/E are `term` and
/// `over`: each term times (1 + u)^(−1/2), u = shift/E, by its series to u³ (|u| ≤
/// [`SERIES_REACH`]).
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
fn shifted_period(term: &[f64], over: &[f64], shift: f64) -> f64 {
    let factor = |over: f64| {
        let u = shift * over;
        1.0 + u * (-0.5 + u * (0.375 - 0.3125 * u))
    };
    let mut lanes = [0.0; LANES];
    let whole = term.len() / LANES * LANES;
    for (term, over) in term[..whole]
        .chunks_exact(LANES)
        .zip(over[..whole].chunks_exact(LANES))
    {
        for lane in 0..LANES {
            lanes[lane] += term[lane] * factor(over[lane]);
        }
    }
    let tail: f64 = (whole..term.len()).map(|i| term[i] * factor(over[i])).sum();
    lanes.iter().sum::<f64>() + tail
}

/// (Σw, Σw·J, Σw·K̃, min K̃) over the nodes, I_w = `inertia`: Φ, the integrals of J and K̃,
/// and the least K̃.
fn means(w: &[f64], rest: &[f64], k: &[f64], inertia: f64) -> [f64; 4] {
    let mut sums = [[0.0; LANES]; 3];
    let whole = w.len() / LANES * LANES;
    for ((w, rest), k) in w[..whole]
        .chunks_exact(LANES)
        .zip(rest[..whole].chunks_exact(LANES))
        .zip(k[..whole].chunks_exact(LANES))
    {
        for lane in 0..LANES {
            sums[0][lane] += w[lane];
            sums[1][lane] += w[lane] * (inertia + rest[lane]);
            sums[2][lane] += w[lane] * k[lane];
        }
    }
    let [mut length, mut inertia_sum, mut lifted_sum] = sums.map(|lanes| lanes.iter().sum());
    for i in whole..w.len() {
        length += w[i];
        inertia_sum += w[i] * (inertia + rest[i]);
        lifted_sum += w[i] * k[i];
    }
    // The least in lanes too: a chain of minima through every node costs their latency.
    let mut least = [f64::INFINITY; LANES];
    for k in k[..whole].chunks_exact(LANES) {
        for lane in 0..LANES {
            least[lane] = least[lane].min(k[lane]);
        }
    }
    let lowest = k[whole..]
        .iter()
        .chain(&least)
        .fold(f64::INFINITY, |a, &b| a.min(b));
    [length, inertia_sum, lifted_sum, lowest]
}
