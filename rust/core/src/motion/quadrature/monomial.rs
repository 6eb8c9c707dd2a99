//! A running integral in powers of x on each panel: the form of the indicator rules' G,
//! looked up once per unit and angle wherever W is asked for.

use std::borrow::Cow;
use std::sync::OnceLock;

use multiversion::multiversion;

use super::{once_per_order, panel_near, Panels, KEPT_ORDERS};

/// [`MonomialRunning::through`] for rules of order `N` compiled for the widest vectors the
/// machine has: its small matrix product a panel is a large part of a geometry sweep's
/// design (plain multiplies and adds, never fused: the same doubles at any width). One
/// function per order, so that each keeps its order a constant (compiled in one body, the
/// orders' code was merged and the panel's outputs stored one double at a time with the
/// order read from memory).
#[multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn through_widest<const N: usize, const W: usize>(
    panels: &Panels,
    values: &[f64],
) -> MonomialRunning {
    MonomialRunning::through_order::<N, W>(panels, values)
}

/// [`MonomialRunning::sum_of_shifts`] compiled for the widest vectors the machine has: each
/// run of panels is a run of memory, added by plain additions (the same doubles at any
/// width).
#[multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn sum_of_shifts_widest(own: &MonomialRunning, shifts: &[PanelShift]) -> MonomialRunning {
    // Panels summed a block at a time: the block's part of the sum stays in the first-level
    // cache while every copy is added to it (56 panels of order 7: 4 KiB).
    const BLOCK: usize = 56;
    let (n, count) = (own.order, own.at_edges.len() - 1);
    // The shifts in lists that do not overlap, each walked by a cursor: a new list wherever
    // a shift starts before the one before it ends (the next copy). Two copies in one list
    // never meet on a panel, so each panel still takes its terms in the copies' order.
    let mut lists: Vec<(&[PanelShift], usize)> = Vec::new();
    let mut start = 0;
    for k in 1..=shifts.len() {
        if k == shifts.len() || shifts[k].p < shifts[k - 1].p + shifts[k - 1].count {
            lists.push((&shifts[start..k], 0));
            start = k;
        }
    }
    // Each block's part of the sum zeroed just before its copies are added (in the
    // first-level cache, where writing the first copy in a pass of its own wrote the whole
    // sum to the second-level cache and read it back a block at a time): 0 + the first
    // copy's terms, 0 where no copy has any.
    let mut sum = MonomialRunning {
        at_edges: Vec::with_capacity(count + 1),
        running: Vec::with_capacity(own.running.len()),
        order: n,
    };
    for first in (0..count).step_by(BLOCK) {
        let end = (first + BLOCK).min(count);
        sum.running.resize(end * (n + 1), 0.0);
        sum.at_edges.resize(end, 0.0);
        for (list, cursor) in lists.iter_mut() {
            while let Some(shift) = list.get(*cursor) {
                if shift.p >= end {
                    break;
                }
                let (from, to) = (shift.p.max(first), (shift.p + shift.count).min(end));
                let q = shift.q + (from - shift.p);
                let q_to = q + (to - from);
                for (s, c) in sum.running[from * (n + 1)..to * (n + 1)]
                    .iter_mut()
                    .zip(&own.running[q * (n + 1)..q_to * (n + 1)])
                {
                    *s += *c;
                }
                for (s, c) in sum.at_edges[from..to]
                    .iter_mut()
                    .zip(&own.at_edges[q..q_to])
                {
                    *s = (*s + *c) + shift.at_edge;
                }
                if shift.p + shift.count > end {
                    break; // it goes on in the next block
                }
                *cursor += 1;
            }
        }
    }
    sum.at_edges.push(0.0);
    sum
}

/// Panels q… q + count − 1 of a table laid onto panels p… p + count − 1 of a sum, F at
/// their first edges raised by `at_edge` (whole cycles of the table's work): one run of a
/// unit of a group summed panel on panel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PanelShift {
    pub p: usize,
    pub q: usize,
    pub count: usize,
    pub at_edge: f64,
}

/// A running integral F(φ) = ∫₀^φ f dφ on `Panels` in monomials, for many look-ups: on each
/// panel F = F(e_p) + Σ_i q_i x^i, x ∈ [−1, 1] across it, and f′ = F″ = Σ_i i(i − 1) q_i
/// x^(i−2) / h² (h the half width), each by Horner's rule (a few multiply-adds where the
/// Legendre recurrence of [`running_at`](super::running_at) takes three times as many
/// operations). The same
/// interpolants as [`Antiderivative`](super::Antiderivative)'s, to rounding (their Legendre
/// coefficients turned into powers of x, |x| ≤ 1: each coefficient's error within a few ulps
/// of the largest).
#[derive(Debug, Clone)]
pub(crate) struct MonomialRunning {
    /// F at the edges (those of the Legendre form, exactly).
    pub at_edges: Vec<f64>,
    /// Per panel, half·∫₋₁^x of the interpolant: `order + 1` coefficients, highest power first.
    running: Vec<f64>,
    /// The panels' order.
    order: usize,
}

impl MonomialRunning {
    /// The running integral of f, given at the nodes of `panels` (`values`), in powers of x
    /// on each panel: each panel's interpolant (degree order − 1) integrated exactly. F at
    /// the edges is [`Panels::antiderivative`](super::Panels::antiderivative)'s (the same
    /// doubles); the powers come from f through a fixed matrix of the rule, made once
    /// (the interpolant's Legendre coefficients by the rule's discrete orthogonality, turned
    /// into powers and integrated), so a panel costs one small matrix product. The slope f′
    /// is the integral's second derivative ([`MonomialRunning::slope_at_panel`]): no
    /// coefficients of its own.
    pub fn through(panels: &Panels, values: &[f64]) -> Self {
        // The rules' orders N, each panel's N + 1 sums in registers (a length known when
        // compiled), each order compiled apart.
        macro_rules! order {
            ($($n:literal => $w:literal;)*) => {
                match panels.order {
                    $($n => through_widest::<$n, $w>(panels, values),)*
                    _ => through_widest::<0, 0>(panels, values),
                }
            };
        }
        order! {
            1 => 2; 2 => 3; 3 => 4; 4 => 5; 5 => 6; 6 => 7; 7 => 8; 8 => 9; 9 => 10; 10 => 11;
            11 => 12; 12 => 13;
        }
    }

    /// [`MonomialRunning::through`] for rules of order `N`, a panel's n + 1 integral
    /// coefficients summed in an array of `W` = N + 1 (0, 0: any order, the sums in memory),
    /// and Σ_j w_j f_j for F at the next edge in a chain of its own.
    #[inline(always)]
    fn through_order<const N: usize, const W: usize>(panels: &Panels, values: &[f64]) -> Self {
        // The order known when compiled wherever it can be: the panel's outputs are then
        // stored as whole vectors (with the order read at run time, one double at a time).
        let n = if N == 0 { panels.order } else { N };
        debug_assert!(N == 0 || (N == panels.order && W == n + 1));
        let count = panels.count();
        let weights = &panels.unit_weights[..n];
        // Column j: what f_j adds to each coefficient (the products summed in independent
        // lanes, not one chain).
        let columns = columns_of(panels);
        // The columns as N arrays of W (any order: none): every loop over them and over a
        // panel's nodes of a length known when compiled, so that the sums stay in registers
        // (a loop that may end early left them in memory, stored and read back a panel).
        let fixed: Vec<[f64; W]> = if N == 0 {
            Vec::new()
        } else {
            columns
                .chunks_exact(W)
                .map(|c| c.try_into().expect("columns of W lanes"))
                .collect()
        };
        let fixed: &[[f64; W]] = &fixed;
        let fixed: &[[f64; W]; N] = fixed.try_into().expect("N columns");
        let mut at_edges = vec![0.0; count + 1];
        // F at the panel's first edge kept where it is made, not read back from memory.
        let mut edge = 0.0;
        let mut running = vec![0.0; count * (n + 1)];
        let edges = panels.edges.windows(2);
        let out = running.chunks_exact_mut(n + 1).zip(&mut at_edges[1..]);
        if N == 0 {
            for ((f, e), (coefficients, at_edge)) in values.chunks_exact(n).zip(edges).zip(out) {
                let half = 0.5 * (e[1] - e[0]);
                // Σ_j w_j f_j from −0.0, as Iterator::sum does (its doubles); each sum
                // Σ_j column_j·f_j in the order of j.
                let mut weighted = -0.0;
                for ((column, f), w) in columns.chunks_exact(n + 1).zip(f).zip(weights) {
                    coefficients
                        .iter_mut()
                        .zip(column)
                        .for_each(|(s, c)| *s += c * f);
                    weighted += w * f;
                }
                coefficients.iter_mut().for_each(|s| *s *= half);
                edge += half * weighted;
                *at_edge = edge;
            }
        } else {
            // Written in place (zeroed first: a push or an extend may call the allocator,
            // and every vector live across that call went through the stack a panel).
            for ((f, e), (coefficients, at_edge)) in values.chunks_exact(N).zip(edges).zip(out) {
                let half = 0.5 * (e[1] - e[0]);
                let f: &[f64; N] = f.try_into().expect("N nodes a panel");
                let mut sums = [0.0; W];
                let mut weighted = -0.0;
                for j in 0..N {
                    for k in 0..W {
                        sums[k] += fixed[j][k] * f[j];
                    }
                    weighted += weights[j] * f[j];
                }
                for (c, s) in coefficients.iter_mut().zip(sums) {
                    *c = half * s;
                }
                edge += half * weighted;
                *at_edge = edge;
            }
        }
        Self {
            at_edges,
            running,
            order: n,
        }
    }

    /// The sum of copies of this table laid onto its own panels by `shifts`: each copy's
    /// shifts in increasing p, not overlapping (a shift may be empty), the copies one after
    /// another (a panel no shift reaches stays 0). Each panel's terms are added in the
    /// copies' order, so the doubles are those of adding the copies one by one; but the sum
    /// is made a block of
    /// panels at a time, which stays in the first-level cache while every copy is added,
    /// where adding copy after copy would read and write the whole sum once a copy (a
    /// V12's twelve units).
    pub fn sum_of_shifts(&self, shifts: &[PanelShift]) -> Self {
        sum_of_shifts_widest(self, shifts)
    }

    /// F(φ), φ (rad) in [0, Φ], on `panels` (those it was made on), φ's panel looked for
    /// first at `hint` and the one after it, and left there; F at the edge itself where φ is
    /// on one.
    #[inline]
    pub fn at_near(&self, panels: &Panels, angle: f64, hint: &mut usize) -> f64 {
        let (p, x) = Self::locate(panels, angle, hint);
        self.at_panel(p, x)
    }

    /// F on panel `p` at `x` ∈ [−1, 1] across it (F at its first edge where x = −1).
    #[inline]
    pub fn at_panel(&self, p: usize, x: f64) -> f64 {
        if x == -1.0 {
            return self.at_edges[p];
        }
        let n = self.order + 1;
        let value = self.running[p * n..(p + 1) * n]
            .iter()
            .fold(0.0, |sum, c| sum * x + c);
        self.at_edges[p] + value
    }

    /// f′ (per rad) on panel `p` of `panels` at `x` ∈ [−1, 1] across it: F″, from F's own
    /// coefficients, Σ_i i(i − 1) q_i x^(i−2) / h², h the panel's half width.
    #[inline]
    pub fn slope_at_panel(&self, panels: &Panels, p: usize, x: f64) -> f64 {
        self.slope_at_panels(panels, &[p], &[x])[0]
    }

    /// [`MonomialRunning::slope_at_panel`] in `L` lanes, their Horner chains side by side.
    #[inline]
    pub fn slope_at_panels<const L: usize>(
        &self,
        panels: &Panels,
        first: &[usize; L],
        x: &[f64; L],
    ) -> [f64; L] {
        let n = self.order;
        let rows: [&[f64]; L] = first.map(|p| &self.running[p * (n + 1)..(p + 1) * (n + 1)]);
        // q_n … q_2 times their powers' i(i − 1), highest first.
        let mut second = [0.0; L];
        for (k, power) in (2..=n).rev().enumerate() {
            let power = power as f64;
            let factor = power * (power - 1.0);
            for l in 0..L {
                second[l] = second[l] * x[l] + factor * rows[l][k];
            }
        }
        let mut out = [0.0; L];
        for l in 0..L {
            let width = panels.edges[first[l] + 1] - panels.edges[first[l]];
            out[l] = 4.0 * second[l] / (width * width);
        }
        out
    }

    /// F at `L` angles (rad, each in [0, Φ]) as [`MonomialRunning::at_near`] gives each (the
    /// same doubles): the look-ups one after another from `hint`, then the L Horner chains
    /// side by side (one chain's multiply-adds each wait on the last; L of them keep the
    /// arithmetic units busy).
    #[inline]
    pub fn at_lanes<const L: usize>(
        &self,
        panels: &Panels,
        angles: &[f64; L],
        hint: &mut usize,
    ) -> [f64; L] {
        let (first, x) = Self::locate_lanes(panels, angles, hint);
        self.at_panels(&first, &x)
    }

    /// [`MonomialRunning::locate`] of `L` angles, one after another from `hint` (the panels
    /// first, then the lanes' divisions side by side).
    #[inline]
    pub fn locate_lanes<const L: usize>(
        panels: &Panels,
        angles: &[f64; L],
        hint: &mut usize,
    ) -> ([usize; L], [f64; L]) {
        let edges = &panels.edges;
        let mut first = [0; L];
        for l in 0..L {
            *hint = panel_near(edges, angles[l], *hint);
            first[l] = *hint;
        }
        let mut x = [0.0; L];
        for l in 0..L {
            let (low, high) = (edges[first[l]], edges[first[l] + 1]);
            x[l] = (angles[l] - 0.5 * (low + high)) / (0.5 * (high - low));
        }
        (first, x)
    }

    /// [`MonomialRunning::at_panel`] in `L` lanes, their Horner chains side by side.
    #[inline]
    pub fn at_panels<const L: usize>(&self, first: &[usize; L], x: &[f64; L]) -> [f64; L] {
        // The common orders with their rows' length known when compiled: no bounds check
        // in the chains, and the L sums stay in registers (in a loop of any length they
        // went through the stack at every step; a few per cent of reading ω and t).
        let value = match self.order + 1 {
            2 => self.horner_lanes::<L, 2>(first, x),
            3 => self.horner_lanes::<L, 3>(first, x),
            4 => self.horner_lanes::<L, 4>(first, x),
            5 => self.horner_lanes::<L, 5>(first, x),
            6 => self.horner_lanes::<L, 6>(first, x),
            7 => self.horner_lanes::<L, 7>(first, x),
            8 => self.horner_lanes::<L, 8>(first, x),
            9 => self.horner_lanes::<L, 9>(first, x),
            10 => self.horner_lanes::<L, 10>(first, x),
            11 => self.horner_lanes::<L, 11>(first, x),
            12 => self.horner_lanes::<L, 12>(first, x),
            13 => self.horner_lanes::<L, 13>(first, x),
            n => {
                let mut value = [0.0; L];
                for k in 0..n {
                    for l in 0..L {
                        value[l] = value[l] * x[l] + self.running[first[l] * n + k];
                    }
                }
                value
            }
        };
        let mut out = [0.0; L];
        for l in 0..L {
            let at_edge = self.at_edges[first[l]];
            out[l] = if x[l] == -1.0 {
                at_edge
            } else {
                at_edge + value[l]
            };
        }
        out
    }

    /// Σ_k q_k x^k of each lane's panel by Horner's rule, rows of `W` coefficients (highest
    /// power first), the lanes' chains side by side.
    #[inline(always)]
    fn horner_lanes<const L: usize, const W: usize>(
        &self,
        first: &[usize; L],
        x: &[f64; L],
    ) -> [f64; L] {
        let rows: [&[f64; W]; L] = first.map(|p| {
            self.running[p * W..(p + 1) * W]
                .try_into()
                .expect("W coefficients a panel")
        });
        let mut value = [0.0; L];
        for k in 0..W {
            let coefficient = rows.map(|row| row[k]);
            for l in 0..L {
                value[l] = value[l] * x[l] + coefficient[l];
            }
        }
        value
    }

    /// F(φ) as [`MonomialRunning::at_near`], and f′(φ) (per rad) on the same panel (on an
    /// edge: the panel that starts there).
    #[inline]
    pub fn at_and_slope_near(&self, panels: &Panels, angle: f64, hint: &mut usize) -> (f64, f64) {
        let (p, x) = Self::locate(panels, angle, hint);
        (self.at_panel(p, x), self.slope_at_panel(panels, p, x))
    }

    /// φ's panel on `panels`, looked for from `hint` and left there, and x ∈ [−1, 1] across it.
    #[inline]
    pub fn locate(panels: &Panels, angle: f64, hint: &mut usize) -> (usize, f64) {
        let edges = &panels.edges;
        let p = panel_near(edges, angle, *hint);
        *hint = p;
        let half = 0.5 * (edges[p + 1] - edges[p]);
        (p, (angle - 0.5 * (edges[p] + edges[p + 1])) / half)
    }
}

/// [`rule_columns`] of the panels' order, made once per order in the process: they depend
/// on the order alone (the Gauss rule's nodes and weights, which `Panels::new` takes from it),
/// and a steady state's curves or a sweep's design made them again at every call (a sixth of
/// the time integral of `.omega`).
fn columns_of(panels: &Panels) -> Cow<'static, [f64]> {
    static MADE: [OnceLock<Vec<f64>>; KEPT_ORDERS] = [const { OnceLock::new() }; KEPT_ORDERS];
    once_per_order(&MADE, panels.order, || rule_columns(panels))
}

/// The matrix from f at a rule's nodes to, on [−1, 1], ∫₋₁^x of f's interpolant in powers
/// of x (`order` + 1 rows, highest power first, its value at −1 taken off in the last), one
/// column per node, column after column; the panel's half-width scales it. The
/// interpolant's powers a = L·B·f: B the Legendre coefficients by the Gauss rule's discrete
/// orthogonality, c_k = (2k + 1)/2 · Σ_i w_i f_i P_k(x_i), L the powers of x in each P_k.
fn rule_columns(panels: &Panels) -> Vec<f64> {
    let n = panels.order;
    // P_k in powers of x, row k: P_{k+1} = ((2k + 1) x P_k − k P_{k−1})/(k + 1).
    let mut legendre = vec![0.0; n * n];
    legendre[0] = 1.0;
    if n > 1 {
        legendre[n + 1] = 1.0;
    }
    for k in 1..n.saturating_sub(1) {
        for i in 0..n {
            let shifted = if i > 0 { legendre[k * n + i - 1] } else { 0.0 };
            legendre[(k + 1) * n + i] = ((2 * k + 1) as f64 * shifted
                - k as f64 * legendre[(k - 1) * n + i])
                / (k + 1) as f64;
        }
    }
    let basis = panels.legendre_basis();
    // powers[i][j]: the coefficient of x^i per f_j.
    let mut powers = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            powers[i * n + j] = (0..n).map(|k| legendre[k * n + i] * basis[k * n + j]).sum();
        }
    }
    // ∫₋₁^x a_i t^i dt = a_i (x^{i+1} − (−1)^{i+1})/(i + 1).
    let mut integrate = Vec::with_capacity((n + 1) * n);
    for i in (0..n).rev() {
        integrate.extend(
            powers[i * n..(i + 1) * n]
                .iter()
                .map(|a| a / (i + 1) as f64),
        );
    }
    integrate.extend((0..n).map(|j| {
        -(0..n)
            .map(|i| {
                let a = powers[i * n + j] / (i + 1) as f64;
                if i % 2 == 0 {
                    -a
                } else {
                    a
                }
            })
            .sum::<f64>()
    }));
    // Row-major (n + 1, n) to n columns of n + 1.
    let rows: Vec<&[f64]> = integrate.chunks_exact(n).collect();
    (0..n)
        .flat_map(|j| rows.iter().map(move |row| row[j]))
        .collect()
}

#[cfg(test)]
mod tests;
