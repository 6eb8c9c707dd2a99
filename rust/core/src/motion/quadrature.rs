//! Gauss–Legendre panels over one working cycle (docs/theory.md, "Steady running", "How the
//! integrals are taken"): the cycle [0, Φ] cut at the angles where an integrand may have a
//! kink, each piece into equal panels no wider than a maximum, every panel carrying the
//! nodes of one Gauss–Legendre rule. On such panels a smooth integrand converges spectrally.

use std::borrow::{Borrow, Cow};
use std::f64::consts::PI;
use std::sync::OnceLock;

/// The nodes (ascending) and weights of the `order`-point Gauss–Legendre rule on [−1, 1].
///
/// Newton's method on P_n from the classical first guesses cos(π(i + ¾)/(n + ½)), each root
/// to the last bit (the step is taken until it no longer changes x), the weights
/// 2/((1 − x²) P_n'(x)²) from the same evaluation. Symmetric by construction: the negative
/// nodes are the positive ones mirrored.
pub(crate) fn gauss_legendre(order: usize) -> (Vec<f64>, Vec<f64>) {
    let n = order;
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut slope = 0.0;
        // Newton converges quadratically from these guesses: 100 steps is never reached; it
        // only bounds the loop should rounding make x oscillate between two neighbours.
        for _ in 0..100 {
            let (p, dp) = legendre_and_slope(n, x);
            slope = dp;
            let step = p / dp;
            x -= step;
            if step.abs() <= 1e-16 * x.abs().max(1e-300) {
                break;
            }
        }
        let (_, dp) = legendre_and_slope(n, x);
        if dp.is_finite() {
            slope = dp;
        }
        let w = 2.0 / ((1.0 - x * x) * slope * slope);
        // The guesses run from the largest root down.
        nodes[n - 1 - i] = x;
        nodes[i] = -x;
        weights[n - 1 - i] = w;
        weights[i] = w;
    }
    if n % 2 == 1 {
        nodes[n / 2] = 0.0;
    }
    (nodes, weights)
}

/// What depends on a rule's order alone, made once per order in the process (`made`, one
/// slot an order; orders beyond it are made each time).
fn once_per_order<B: ToOwned + ?Sized + 'static>(
    made: &'static [OnceLock<B::Owned>],
    order: usize,
    make: impl FnOnce() -> B::Owned,
) -> Cow<'static, B> {
    match made.get(order) {
        Some(slot) => Cow::Borrowed(slot.get_or_init(make).borrow()),
        None => Cow::Owned(make()),
    }
}

/// Orders a rule's parts are kept for ([`once_per_order`]).
const KEPT_ORDERS: usize = 33;

/// [`gauss_legendre`] of `order`, made once per order (every new set of panels took it, its
/// Newton steps a few microseconds of a sweep's design).
fn rule_of(order: usize) -> Cow<'static, (Vec<f64>, Vec<f64>)> {
    static MADE: [OnceLock<(Vec<f64>, Vec<f64>)>; KEPT_ORDERS] =
        [const { OnceLock::new() }; KEPT_ORDERS];
    once_per_order(&MADE, order, || gauss_legendre(order))
}

/// P_n(x) and P_n'(x) by the three-term recurrence.
fn legendre_and_slope(n: usize, x: f64) -> (f64, f64) {
    let (mut previous, mut p) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let k = k as f64;
        let next = ((2.0 * k - 1.0) * x * p - (k - 1.0) * previous) / k;
        previous = p;
        p = next;
    }
    let n = n as f64;
    (p, n * (x * p - previous) / (x * x - 1.0))
}

/// Gauss–Legendre panels over [0, Φ].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Panels {
    /// The order of every panel's rule.
    pub order: usize,
    /// The widest panel (rad) a piece between breaks was cut to ([`Panels::refined`] cuts
    /// the same way).
    pub max_width: f64,
    /// Panel edges, from 0 to Φ (P + 1).
    pub edges: Vec<f64>,
    /// The nodes, panel after panel (P · order).
    pub phi: Vec<f64>,
    /// The weights: Σ weights·f ≈ ∫₀^Φ f dφ.
    pub weights: Vec<f64>,
    /// The rule on [−1, 1].
    pub unit_nodes: Vec<f64>,
    pub unit_weights: Vec<f64>,
}

impl Panels {
    /// Panels of `order` points whose edges include `breaks` (sorted, from 0 to Φ): each
    /// piece between breaks in equal panels no wider than `max_width`.
    pub fn new(breaks: &[f64], order: usize, max_width: f64) -> Self {
        let mut edges = Vec::with_capacity(breaks.len());
        for pair in breaks.windows(2) {
            let width = pair[1] - pair[0];
            let count = (width / max_width).ceil().max(1.0) as usize;
            let step = width / count as f64;
            edges.extend((0..count).map(|k| pair[0] + step * k as f64));
        }
        edges.extend(breaks.last());
        let (unit_nodes, unit_weights) = rule_of(order).into_owned();
        // Extended panel by panel from the rule's nodes (a length known: no check per value,
        // as a push has, nor zeroing first).
        let count = edges.len() - 1;
        let mut phi = Vec::with_capacity(count * order);
        let mut weights = Vec::with_capacity(count * order);
        for pair in edges.windows(2) {
            let half = 0.5 * (pair[1] - pair[0]);
            let middle = 0.5 * (pair[0] + pair[1]);
            phi.extend(unit_nodes.iter().map(|x| middle + half * x));
            weights.extend(unit_weights.iter().map(|w| half * w));
        }
        Self {
            order,
            max_width,
            edges,
            phi,
            weights,
            unit_nodes,
            unit_weights,
        }
    }

    /// The same rule with more edges (`extra`, angles in [0, Φ]): the union of the edges
    /// (exact duplicates dropped, as NumPy's `union1d`) cut again to `max_width`.
    pub fn refined(&self, extra: &[f64]) -> Self {
        let mut edges: Vec<f64> = self.edges.iter().chain(extra).copied().collect();
        edges.sort_by(f64::total_cmp);
        edges.dedup();
        Self::new(&edges, self.order, self.max_width)
    }

    /// The largest half-width of a panel (rad).
    pub fn widest_half(&self) -> f64 {
        self.edges
            .windows(2)
            .fold(0.0, |m, e| f64::max(m, 0.5 * (e[1] - e[0])))
    }

    /// The samples of a function given at the nodes then the edges (`values`), in angle
    /// order: edge p, the nodes of panel p, edge p + 1, … (the last edge, Φ ≡ 0, left out).
    pub fn in_angle_order(&self, values: &[f64]) -> Vec<(f64, f64)> {
        let (n, order) = (self.phi.len(), self.order);
        let mut samples = Vec::with_capacity(n + self.count());
        for p in 0..self.count() {
            samples.push((self.edges[p], values[n + p]));
            let nodes = p * order..(p + 1) * order;
            samples.extend(
                self.phi[nodes.clone()]
                    .iter()
                    .copied()
                    .zip(values[nodes].iter().copied()),
            );
        }
        samples
    }

    pub fn count(&self) -> usize {
        self.edges.len() - 1
    }

    /// Φ, the last edge.
    pub fn cycle(&self) -> f64 {
        self.edges[self.edges.len() - 1]
    }

    /// ∫₀^Φ f dφ from f at the nodes.
    pub fn integral(&self, values: &[f64]) -> f64 {
        self.weights.iter().zip(values).map(|(w, f)| w * f).sum()
    }

    /// The running integral F(φ) = ∫₀^φ f dφ at `phi` (rad, in [0, Φ]) from f at the nodes
    /// (`values`): see [`Antiderivative`].
    /// The interpolants in powers of x ([`MonomialRunning`]), eight angles at a time.
    pub fn running_at(&self, values: &[f64], phi: &[f64]) -> Vec<f64> {
        let running = MonomialRunning::through(self, values);
        let mut hint = 0;
        let mut out = Vec::with_capacity(phi.len());
        let mut lanes = phi.chunks_exact(8);
        for angles in &mut lanes {
            let angles: &[f64; 8] = angles.try_into().expect("chunks of eight");
            out.extend(running.at_lanes(self, angles, &mut hint));
        }
        out.extend(
            lanes
                .remainder()
                .iter()
                .map(|&angle| running.at_near(self, angle, &mut hint)),
        );
        out
    }

    /// (2k + 1)/2 · w_i · P_k(x_i) of the rule on [−1, 1], degree-major (row k): the
    /// interpolant's Legendre coefficient c_k is row k times f at the nodes.
    pub(super) fn legendre_basis(&self) -> Vec<f64> {
        let n = self.order;
        let mut basis = vec![0.0; n * n];
        for (i, (&x, &w)) in self.unit_nodes.iter().zip(&self.unit_weights).enumerate() {
            for (k, p) in legendre_all(n, x).into_iter().enumerate() {
                basis[k * n + i] = (2 * k + 1) as f64 * 0.5 * w * p;
            }
        }
        basis
    }

    /// The running integral of f, given at the nodes (`values`), everywhere: each panel's
    /// interpolant (degree order − 1) integrated exactly.
    ///
    /// The interpolant's Legendre coefficients come from the Gauss rule's discrete
    /// orthogonality, c_k = (2k + 1)/2 · Σ_i w_i f_i P_k(x_i) (exact: degree ≤ 2·order − 2).
    pub fn antiderivative(&self, values: &[f64]) -> Antiderivative<'_> {
        let n = self.order;
        let basis = self.legendre_basis();
        let mut at_edges = Vec::with_capacity(self.count() + 1);
        at_edges.push(0.0);
        let mut coefficients = Vec::with_capacity(values.len());
        for (p, panel) in values.chunks_exact(n).enumerate() {
            let half = 0.5 * (self.edges[p + 1] - self.edges[p]);
            let sum: f64 = panel
                .iter()
                .zip(&self.unit_weights)
                .map(|(f, w)| f * w)
                .sum();
            at_edges.push(at_edges[p] + half * sum);
            coefficients.extend(
                basis
                    .chunks_exact(n)
                    .map(|row| row.iter().zip(panel).map(|(b, f)| b * f).sum::<f64>()),
            );
        }
        Antiderivative {
            panels: self,
            at_edges,
            coefficients,
        }
    }

    /// f′ at the nodes of the polynomial through f at each panel's nodes: Σ_k c_k
    /// P_k′(x_i)/half.
    pub fn slope(&self, values: &[f64]) -> Vec<f64> {
        let n = self.order;
        let derivatives: Vec<Vec<f64>> = self
            .unit_nodes
            .iter()
            .map(|&x| {
                let p = legendre_all(n, x);
                // P_k′ = k(x P_k − P_{k−1})/(x² − 1): the nodes are inside (−1, 1).
                (0..n)
                    .map(|k| {
                        if k == 0 {
                            0.0
                        } else {
                            k as f64 * (x * p[k] - p[k - 1]) / (x * x - 1.0)
                        }
                    })
                    .collect()
            })
            .collect();
        let running = self.antiderivative(values);
        let mut slopes = Vec::with_capacity(values.len());
        for p in 0..self.count() {
            let half = 0.5 * (self.edges[p + 1] - self.edges[p]);
            let c = &running.coefficients[p * n..(p + 1) * n];
            slopes.extend(
                derivatives
                    .iter()
                    .map(|d| c.iter().zip(d).map(|(c, d)| c * d).sum::<f64>() / half),
            );
        }
        slopes
    }

    /// The largest |Legendre coefficient| of degrees order − 2 and order − 1 over the panels,
    /// of the polynomial through `values` at each panel's nodes: how well the panels resolve
    /// f. By the discrete orthogonality of the Gauss rule (exact to degree 2·order − 1),
    /// c_k = (2k + 1)/2 · Σ_i w_i f_i P_k(x_i).
    pub fn tail(&self, values: &[f64]) -> f64 {
        let n = self.order;
        let basis = tail_basis(n);
        let mut tail: f64 = 0.0;
        for panel in values.chunks_exact(n) {
            for (degree, column) in [(n - 2, 0), (n - 1, 1)] {
                let sum: f64 = panel
                    .iter()
                    .zip(&self.unit_weights)
                    .zip(basis.iter())
                    .map(|((f, w), b)| f * w * b[column])
                    .sum();
                tail = tail.max(((2 * degree + 1) as f64 * 0.5 * sum).abs());
            }
        }
        tail
    }
}

/// [P_{order−2}(x_i), P_{order−1}(x_i)] at the nodes x_i of the Gauss rule of `order`, made
/// once per order (a sweep's every design asked for them, n² divisions each time).
fn tail_basis(order: usize) -> Cow<'static, [[f64; 2]]> {
    static MADE: [OnceLock<Vec<[f64; 2]>>; KEPT_ORDERS] = [const { OnceLock::new() }; KEPT_ORDERS];
    once_per_order(&MADE, order, || {
        rule_of(order)
            .0
            .iter()
            .map(|&x| [legendre(order - 2, x), legendre(order - 1, x)])
            .collect()
    })
}

/// P_n(x).
fn legendre(n: usize, x: f64) -> f64 {
    if n == 0 {
        return 1.0;
    }
    let (mut previous, mut p) = (1.0, x);
    for k in 2..=n {
        let k = k as f64;
        let next = ((2.0 * k - 1.0) * x * p - (k - 1.0) * previous) / k;
        previous = p;
        p = next;
    }
    p
}

/// The running integral F(φ) = ∫₀^φ f dφ of a function given at the nodes of [`Panels`].
#[derive(Debug, Clone)]
pub(crate) struct Antiderivative<'p> {
    panels: &'p Panels,
    /// F at the edges: F(0) = 0, F(Φ) the whole integral.
    pub at_edges: Vec<f64>,
    /// Each panel's Legendre coefficients of f's interpolant (order per panel).
    coefficients: Vec<f64>,
}

impl Antiderivative<'_> {
    /// F(φ), φ (rad) in [0, Φ] ([`running_at`]).
    pub fn at(&self, angle: f64) -> f64 {
        running_at(self.panels, &self.at_edges, &self.coefficients, angle)
    }

    /// F at the nodes.
    pub fn at_nodes(&self) -> Vec<f64> {
        self.panels
            .phi
            .iter()
            .map(|&angle| self.at(angle))
            .collect()
    }
}

/// Coefficients the tables of Legendre polynomials hold (higher ones are computed).
pub(crate) const LEGENDRE_TABLE: usize = 24;

/// The three-term recurrence P_{k+1} = a_k x P_k − b_k P_{k−1} of the Legendre polynomials
/// and 1/(2k + 1), a_k = (2k + 1)/(k + 1), b_k = k/(k + 1), for k < [`LEGENDRE_TABLE`]: no
/// division per term.
pub(crate) const LEGENDRE: [(f64, f64, f64); LEGENDRE_TABLE] = {
    let mut table = [(0.0, 0.0, 0.0); LEGENDRE_TABLE];
    let mut k = 0;
    while k < LEGENDRE_TABLE {
        let j = k as f64;
        table[k] = (
            (2.0 * j + 1.0) / (j + 1.0),
            j / (j + 1.0),
            1.0 / (2.0 * j + 1.0),
        );
        k += 1;
    }
    table
};

/// (a_k, b_k, 1/(2k + 1)) of [`LEGENDRE`], computed where k is beyond the table.
#[inline]
pub(crate) fn legendre_step(k: usize) -> (f64, f64, f64) {
    match LEGENDRE.get(k) {
        Some(&step) => step,
        None => {
            let j = k as f64;
            (
                (2.0 * j + 1.0) / (j + 1.0),
                j / (j + 1.0),
                1.0 / (2.0 * j + 1.0),
            )
        }
    }
}

/// The panel of `angle` among `edges` (ascending, `count` + 1 of them): the last whose edge
/// is ≤ the angle, kept in 0..count (NumPy's `searchsorted(…, side="right") − 1`, clipped),
/// guessed as if the edges were uniform and walked a few steps; a binary search where they
/// are far from it. The same panel either way.
fn panel_of(edges: &[f64], angle: f64) -> usize {
    let count = edges.len() - 1;
    let (first, last) = (edges[0], edges[count]);
    let guess = ((angle - first) / (last - first) * count as f64).clamp(0.0, (count - 1) as f64);
    let mut p = guess as usize;
    for _ in 0..4 {
        if p > 0 && edges[p] > angle {
            p -= 1;
        } else if p + 1 < count && edges[p + 1] <= angle {
            p += 1;
        } else {
            return p;
        }
    }
    edges.partition_point(|&e| e <= angle).clamp(1, count) - 1
}

/// [`panel_of`] the angle, `hint` and the [`NEAR`] panels after it tried first.
#[inline]
fn panel_near(edges: &[f64], angle: f64, hint: usize) -> usize {
    let count = edges.len() - 1;
    // Panel p holds the angle where e_p ≤ angle < e_{p+1}, the first panel anything below
    // e_1 and the last anything from e_{count−1} on (panel_of's clipping).
    let holds =
        |p: usize| (p == 0 || edges[p] <= angle) && (p + 1 == count || angle < edges[p + 1]);
    (hint..(hint + 1 + NEAR).min(count))
        .find(|&p| holds(p))
        .unwrap_or_else(|| panel_of(edges, angle))
}

/// Panels after the hint [`panel_near`] tries before a search: angles in order a little
/// coarser than the panels (an indicator rule's ~10³ panels, a result's 1441 points over the
/// cycle) skip one or two.
const NEAR: usize = 3;

/// F(φ) = ∫₀^φ f dφ, φ (rad) in [0, Φ], from the tables of a running integral on `panels`
/// ([`Panels::antiderivative`]: F at the edges, each panel's Legendre coefficients of f's
/// interpolant): the panel sums up to φ's panel, then that panel's interpolant integrated
/// from its edge to φ, ∫_{−1}^x P_k = (P_{k+1}(x) − P_{k−1}(x))/(2k + 1) (x + 1 for k = 0);
/// F at the edge itself where φ is on it. φ's panel is [`panel_of`] it.
pub(crate) fn running_at(
    panels: &Panels,
    at_edges: &[f64],
    coefficients: &[f64],
    angle: f64,
) -> f64 {
    running_at_near(panels, at_edges, coefficients, angle, &mut 0)
}

/// [`running_at`] (the same doubles), φ's panel looked for first at `hint` and the one after
/// it, and left there: angles taken in increasing order walk the panels without a search.
#[inline]
pub(crate) fn running_at_near(
    panels: &Panels,
    at_edges: &[f64],
    coefficients: &[f64],
    angle: f64,
    hint: &mut usize,
) -> f64 {
    let (edges, n) = (&panels.edges, panels.order);
    let p = panel_near(edges, angle, *hint);
    *hint = p;
    let half = 0.5 * (edges[p + 1] - edges[p]);
    let x = (angle - 0.5 * (edges[p] + edges[p + 1])) / half;
    if x == -1.0 {
        // On the edge: F there, exactly (the tabled recurrence leaves ulps of P_k(−1)).
        return at_edges[p];
    }
    // P_{k−1}, P_k and P_{k+1} by the three-term recurrence as k runs.
    let coefficients = &coefficients[p * n..(p + 1) * n];
    let mut integral = coefficients[0] * (x + 1.0);
    let (mut previous, mut current) = (1.0, x);
    for (k, c) in coefficients.iter().enumerate().skip(1) {
        let (a, b, over) = legendre_step(k);
        let next = a * x * current - b * previous;
        integral += c * (next - previous) * over;
        previous = current;
        current = next;
    }
    at_edges[p] + half * integral
}

/// P_0(x) … P_{count − 1}(x) by the three-term recurrence.
fn legendre_all(count: usize, x: f64) -> Vec<f64> {
    let mut p = Vec::with_capacity(count);
    for k in 0..count {
        let value = match k {
            0 => 1.0,
            1 => x,
            _ => {
                let k = k as f64;
                ((2.0 * k - 1.0) * x * p[p.len() - 1] - (k - 1.0) * p[p.len() - 2]) / k
            }
        };
        p.push(value);
    }
    p
}

/// `angles` sorted and folded into [0, Φ] with 0 and Φ, breaks closer than 10⁻¹²·Φ merged
/// (a sliver panel would only cost nodes).
pub(crate) fn breaks(mut angles: Vec<f64>, cycle: f64) -> Vec<f64> {
    // Angles made in order within [0, Φ] (a rule's cuts) are not sorted again: a check is
    // one pass, and 0 and Φ go to their ends.
    let ordered = |a: &f64, b: &f64| a.total_cmp(b).is_le();
    if angles.is_sorted_by(ordered)
        && angles.first().is_none_or(|a| ordered(&0.0, a))
        && angles.last().is_none_or(|a| ordered(a, &cycle))
    {
        angles.insert(0, 0.0);
        angles.push(cycle);
    } else {
        angles.push(0.0);
        angles.push(cycle);
        angles.sort_by(f64::total_cmp);
    }
    let mut kept: Vec<f64> = Vec::with_capacity(angles.len());
    for a in angles {
        match kept.last() {
            Some(&last) if a - last <= 1e-12 * cycle => {}
            _ => kept.push(a),
        }
    }
    if let Some(last) = kept.last_mut() {
        *last = cycle;
    }
    kept
}

mod monomial;
pub(crate) use monomial::{MonomialRunning, PanelShift};

#[cfg(test)]
mod tests;
