//! The free–free chain's natural modes to the precision its numbers hold.
//!
//! The modes solve K a = Ω² J a. A symmetric eigen solver — of the pencil (K, J) or of the
//! tridiagonal J^{−1/2} K J^{−1/2} — finds each Ω² to within a few ε of the largest: an
//! absolute accuracy. A mode far below the largest keeps only the digits left over (a light
//! node between stiff sections beside a soft one; a long chain's lowest modes), and the rigid
//! mode's 0 and a small elastic Ω² blur into each other. The chain's numbers themselves fix
//! every Ω² to a relative precision: ∂ ln Ω²/∂ ln k_i is section i's share of the mode's
//! strain energy and −∂ ln Ω²/∂ ln J_i node i's share of its kinetic energy, so changing
//! every k_i and J_i by a relative η moves every Ω² by at most 2η. This module keeps it.
//!
//! **Eigenvalues.** Holzer's recurrence for a trial Ω² = σ: q_0 = −σ J_0,
//!
//!   p_i = k_i + q_i,   q_{i+1} = k_i q_i / p_i − σ J_{i+1}   (i < n − 1),   p_{n−1} = q_{n−1},
//!
//! gives the pivots p_i of K − σJ = L D Lᵀ (K = L diag(k_0 … k_{n−2}, 0) Lᵀ with L unit lower
//! bidiagonal, its subdiagonal −1): q_i is the dynamic stiffness of nodes 0 … i, and
//! k_i q_i/p_i that of the same nodes seen through section i (k_i and q_i in series). It is
//! the differential form of the stationary qd transform (Dhillon & Parlett, "Orthogonal
//! eigenvectors and relative gaps", SIAM J. Matrix Anal. Appl. 25, 2004): it subtracts no two
//! large numbers, and what it computes is the exact transform of a chain whose numbers differ
//! from the given ones in their last digits. By Sylvester's law of inertia the number of
//! negative pivots is the number of modes with Ω² < σ, the rigid one included; a pivot smaller
//! in magnitude than `PIVMIN` is taken as −`PIVMIN` (LAPACK's rule), so the count is that of
//! a chain perturbed in its last digits and the next q stays finite. Bisection on the count
//! finds each Ω² from Gershgorin's bracket [0, ‖J^{−1/2} K J^{−1/2}‖∞]: in ln Ω² while the
//! bracket spans more than a factor of 2 (from its top × 2^−64 where it starts at 0), then
//! evenly, until no double lies between its ends. Each mode is bisected on its own — up to 32 at a
//! time, one to a vector lane, so that the divisions overlap — and its Ω² does not depend on
//! how many modes are asked.
//!
//! **Shapes.** At each Ω², the same recurrence from both ends: q_i from node 0 (pivots p_i)
//! and q′_i from node n − 1 (q′_{n−1} = −Ω² J_{n−1}, p′_i = k_{i−1} + q′_i,
//! q′_{i−1} = k_{i−1} q′_i / p′_i − Ω² J_{i−1}). Node r, where γ_r = q_r + q′_r + Ω² J_r (the
//! reciprocal of the (r, r) entry of (K − Ω² J)^{−1}) is smallest, is where the mode is large;
//! its shape is a_r = 1 and Holzer's amplitude ratios outwards, a_i = k_i a_{i+1}/p_i to the
//! left and a_i = k_{i−1} a_{i−1}/p′_i to the right (the twisted factorization's
//! eigenvector): products and quotients, each amplitude to a relative precision, a light
//! node's too. Each shape is then scaled to a largest magnitude of 1, positive at the first
//! node whose magnitude is within 1e-9 of the largest.
//!
//! Both recurrences run on the chain scaled to max k_i = max J_i = 1.

use multiversion::multiversion;

use crate::error::{try_filled, MechanismError, Result};

use super::Chain;

const EPS: f64 = f64::EPSILON;
/// A pivot smaller in magnitude than this is taken as −`PIVMIN` (LAPACK's rule). On the scaled
/// chain (k_i ≤ 1) a pivot that small follows a q of magnitude ≤ 1, so k q/p stays finite.
const PIVMIN: f64 = f64::MIN_POSITIVE / EPS;
/// The modes whose shapes are found together, one to a lane (a 512-bit vector holds eight).
const LANES: usize = 8;
/// The most modes bisected together, one to a lane: four 512-bit vectors of independent
/// divisions in flight hide the latency of each (on 1000 nodes, every mode: 32 lanes took
/// half the time of 16 and a third of 8; 64 no less than 32). Fewer modes take fewer lanes.
const BISECTED: usize = 32;
/// Bisection steps at most: about 60 close a bracket from its top × 2^−64 and each further
/// factor 2^−64 costs 6; a double's range is 2^−1074 … 2^1024.
const MAX_STEPS: usize = 1024;

/// The lowest elastic modes of a [`Chain`] ([`Chain::modes`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Modes {
    nodes: usize,
    omega: Vec<f64>,
    shapes: Vec<f64>,
}

impl Modes {
    /// The angular frequencies ω_m (rad/s) of elastic modes 1 … count, increasing.
    pub fn omega(&self) -> &[f64] {
        &self.omega
    }

    /// The number of modes.
    pub fn count(&self) -> usize {
        self.omega.len()
    }

    /// The number of nodes.
    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// The shapes, nodes × modes row by row (node i's amplitude in mode m at
    /// `i * count + m`): each scaled to a largest magnitude of 1, positive at the first node
    /// whose magnitude is within 1e-9 of it.
    pub fn shapes(&self) -> &[f64] {
        &self.shapes
    }

    /// Node i's amplitude in mode m (both from 0).
    pub fn amplitude(&self, node: usize, mode: usize) -> f64 {
        self.shapes[node * self.count() + mode]
    }

    /// (ω, shapes) as [`Modes::omega`] and [`Modes::shapes`] give them, without a copy.
    pub fn into_parts(self) -> (Vec<f64>, Vec<f64>) {
        (self.omega, self.shapes)
    }
}

impl Chain {
    /// The lowest `count` elastic modes (1 ≤ `count` ≤ n − 1): ω_m (rad/s), each from the
    /// chain's numbers to a few units in its last digit, and the shapes, each amplitude to a
    /// relative precision (module `modes`). A mode's ω and shape do not depend on `count`.
    /// Its cost is of the order of the nodes × `count`, with no n × n matrix.
    ///
    /// Errors: a `count` out of range (naming `count`); shapes too large to allocate.
    pub fn modes(&self, count: usize) -> Result<Modes> {
        let n = self.nodes();
        if count == 0 || count >= n {
            return Err(MechanismError::InvalidChoice {
                parameter: "count",
                value: count.to_string(),
                allowed: "1 <= count <= nodes - 1",
            });
        }
        let k_scale = self.stiffness.iter().copied().fold(0.0, f64::max);
        let j_scale = self.inertia.iter().copied().fold(0.0, f64::max);
        let k: Vec<f64> = self.stiffness.iter().map(|&v| v / k_scale).collect();
        let j: Vec<f64> = self.inertia.iter().map(|&v| v / j_scale).collect();
        let mut sigma = vec![0.0; count];
        eigenvalues(&k, &j, &mut sigma);
        let mut shapes = try_filled("count", count, n as u128 * count as u128, 0.0)?;
        let mut work = Work::new(n);
        for (group, values) in sigma.chunks(LANES).enumerate() {
            let mut lanes = [values[values.len() - 1]; LANES];
            lanes[..values.len()].copy_from_slice(values);
            work.shapes(&k, &j, &lanes);
            let first = group * LANES;
            for (node, row) in shapes.chunks_exact_mut(count).enumerate() {
                row[first..first + values.len()].copy_from_slice(&work.shape[node][..values.len()]);
            }
        }
        let scale = k_scale / j_scale;
        let omega = sigma.iter().map(|&s| (s * scale).sqrt()).collect();
        Ok(Modes {
            nodes: n,
            omega,
            shapes,
        })
    }
}

/// A pivot, one smaller in magnitude than `PIVMIN` taken as −`PIVMIN`.
#[inline(always)]
fn guard(pivot: f64) -> f64 {
    if pivot.abs() < PIVMIN {
        -PIVMIN
    } else {
        pivot
    }
}

/// The number of modes with Ω² < σ, the rigid one included, for each lane's trial σ > 0
/// (scaled chain).
#[inline(always)]
fn below<const L: usize>(k: &[f64], j: &[f64], sigma: &[f64; L]) -> [u64; L] {
    let mut q = [0.0; L];
    for (q, &s) in q.iter_mut().zip(sigma) {
        *q = -s * j[0];
    }
    let mut count = [0u64; L];
    for (&k_i, &j_next) in k.iter().zip(&j[1..]) {
        for lane in 0..L {
            let p = guard(q[lane] + k_i);
            count[lane] += u64::from(p < 0.0);
            q[lane] = q[lane] * k_i / p - sigma[lane] * j_next;
        }
    }
    for (count, &q) in count.iter_mut().zip(&q) {
        *count += u64::from(guard(q) < 0.0);
    }
    count
}

/// The next trial of a bracket [low, high]: its geometric middle while it spans more than a
/// factor of 2 (from high × 2^−64 where it starts at 0), its middle after.
#[inline(always)]
fn middle(low: f64, high: f64) -> f64 {
    let floor = if low > 0.0 {
        low
    } else {
        high * 2f64.powi(-64)
    };
    if high > 2.0 * floor {
        floor.sqrt() * high.sqrt()
    } else {
        low + (high - low) * 0.5
    }
}

/// Ω² of elastic modes 1 … `out.len()` of the scaled chain, each to a few units in its last
/// digit: up to `BISECTED` modes bisected at a time.
fn eigenvalues(k: &[f64], j: &[f64], out: &mut [f64]) {
    let n = j.len();
    // Gershgorin's bound on the tridiagonal J^{-1/2} K J^{-1/2}: every Ω² is below it.
    let off = |i: usize| k[i] / (j[i] * j[i + 1]).sqrt();
    let mut top = 0.0f64;
    for i in 0..n {
        let left = if i > 0 { k[i - 1] } else { 0.0 };
        let right = if i + 1 < n { k[i] } else { 0.0 };
        let mut row = (right + left) / j[i];
        if i + 1 < n {
            row += off(i);
        }
        if i > 0 {
            row += off(i - 1);
        }
        top = top.max(row);
    }
    let mut ceiling = top * (1.0 + 8.0 * EPS);
    // The count must find every mode below it (it is the count of a nearby chain).
    for _ in 0..64 {
        if below(k, j, &[ceiling])[0] >= n as u64 {
            break;
        }
        ceiling *= 2.0;
    }
    let mut first = 0;
    while first < out.len() {
        let left = out.len() - first;
        let block = &mut out[first..first + left.min(BISECTED)];
        // Each lane's bisection is its own: a mode's Ω² does not depend on its block.
        if left > 16 {
            bisect_block::<BISECTED>(k, j, first, ceiling, block);
        } else if left > 8 {
            bisect_block::<16>(k, j, first, ceiling, block);
        } else {
            bisect_block::<8>(k, j, first, ceiling, block);
        }
        first += block.len();
    }
}

/// Ω² of elastic modes `first` + 1 … `first` + `values.len()` (at most L) into `values`.
#[inline(always)]
fn bisect_block<const L: usize>(
    k: &[f64],
    j: &[f64],
    first: usize,
    ceiling: f64,
    values: &mut [f64],
) {
    let mut wanted = [0u64; L];
    for (lane, wanted) in wanted.iter_mut().enumerate() {
        // Mode m (from 1) has m modes below it, the rigid one included; spare lanes repeat
        // the block's last mode.
        *wanted = (first + lane.min(values.len() - 1) + 1) as u64;
    }
    let found = bisect(k, j, &wanted, ceiling);
    values.copy_from_slice(&found[..values.len()]);
}

/// Each lane's mode (`wanted` m: Ω²_m has m modes below it) bisected in [0, `ceiling`]
/// until no double lies between the ends of its bracket; the middle of each bracket.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
fn bisect<const L: usize>(k: &[f64], j: &[f64], wanted: &[u64; L], ceiling: f64) -> [f64; L] {
    let mut low = [0.0; L];
    let mut high = [ceiling; L];
    let mut open = [true; L];
    let mut trial = [ceiling; L];
    for _ in 0..MAX_STEPS {
        for lane in 0..L {
            if open[lane] {
                let mid = middle(low[lane], high[lane]);
                // No representable value between the ends: closed as it is.
                open[lane] = mid > low[lane] && mid < high[lane];
                trial[lane] = mid;
            }
        }
        if !open.contains(&true) {
            break;
        }
        let count = below(k, j, &trial);
        for lane in 0..L {
            if open[lane] {
                if count[lane] > wanted[lane] {
                    high[lane] = trial[lane];
                } else {
                    low[lane] = trial[lane];
                }
            }
        }
    }
    let mut middle = [0.0; L];
    for lane in 0..L {
        middle[lane] = 0.5 * (low[lane] + high[lane]);
    }
    middle
}

/// The buffers of the twisted recurrence, `LANES` modes at a time (one to a lane).
struct Work {
    /// q′_i from node n − 1, then the amplitude ratios a_i/a_{i+1} to the left.
    left: Vec<[f64; LANES]>,
    /// a_i/a_{i−1} to the right.
    right: Vec<[f64; LANES]>,
    /// The shapes found.
    shape: Vec<[f64; LANES]>,
}

impl Work {
    fn new(n: usize) -> Self {
        Self {
            left: vec![[0.0; LANES]; n],
            right: vec![[0.0; LANES]; n],
            shape: vec![[0.0; LANES]; n],
        }
    }

    /// The shapes at each lane's Ω² (scaled chain), by the twisted Holzer recurrence, each
    /// scaled to a largest magnitude of +1 at the first node that has it (to 1e-9).
    fn shapes(&mut self, k: &[f64], j: &[f64], sigma: &[f64; LANES]) {
        twisted(
            k,
            j,
            sigma,
            &mut self.left,
            &mut self.right,
            &mut self.shape,
        );
    }
}

/// [`Work::shapes`] into `shape`, with `left` and `right` its buffers.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq+avx2+fma", "x86_64+avx2+fma"))]
fn twisted(
    k: &[f64],
    j: &[f64],
    sigma: &[f64; LANES],
    left: &mut [[f64; LANES]],
    right: &mut [[f64; LANES]],
    shape: &mut [[f64; LANES]],
) {
    let n = j.len();
    let mut q = [0.0; LANES];
    for lane in 0..LANES {
        q[lane] = -sigma[lane] * j[n - 1];
    }
    for i in (1..n).rev() {
        for lane in 0..LANES {
            left[i][lane] = q[lane];
            right[i][lane] = k[i - 1] / guard(q[lane] + k[i - 1]);
            q[lane] = right[i][lane] * q[lane] - sigma[lane] * j[i - 1];
        }
    }
    left[0] = q;
    let mut smallest = [f64::INFINITY; LANES];
    let mut twist = [0usize; LANES];
    for lane in 0..LANES {
        q[lane] = -sigma[lane] * j[0];
    }
    for i in 0..n {
        for lane in 0..LANES {
            let gamma = (q[lane] + left[i][lane] + sigma[lane] * j[i]).abs();
            if gamma < smallest[lane] {
                smallest[lane] = gamma;
                twist[lane] = i;
            }
        }
        if i + 1 < n {
            for lane in 0..LANES {
                left[i][lane] = k[i] / guard(q[lane] + k[i]);
                q[lane] = left[i][lane] * q[lane] - sigma[lane] * j[i + 1];
            }
        }
    }
    // a_r = 1 at the twist r; a_i = a_{i+1} · (a_i/a_{i+1}) left of it, a_{i−1} · (a_i/a_{i−1})
    // right of it: the product of a 1 and the factor of each side.
    let mut factor = [1.0; LANES];
    for i in (0..n).rev() {
        for lane in 0..LANES {
            factor[lane] = if i >= twist[lane] {
                1.0
            } else {
                factor[lane] * left[i][lane]
            };
            shape[i][lane] = factor[lane];
        }
    }
    factor = [1.0; LANES];
    for i in 0..n {
        for lane in 0..LANES {
            factor[lane] = if i <= twist[lane] {
                1.0
            } else {
                factor[lane] * right[i][lane]
            };
            shape[i][lane] *= factor[lane];
        }
    }
    let mut size = [0.0f64; LANES];
    for a in shape.iter() {
        for lane in 0..LANES {
            size[lane] = size[lane].max(a[lane].abs());
        }
    }
    let mut divisor = [0.0; LANES];
    for lane in 0..LANES {
        let threshold = size[lane] * (1.0 - 1e-9);
        let first = shape
            .iter()
            .position(|a| a[lane] >= threshold || a[lane] <= -threshold)
            .unwrap_or(twist[lane]);
        divisor[lane] = size[lane] * shape[first][lane].signum();
    }
    for a in shape.iter_mut() {
        for lane in 0..LANES {
            a[lane] /= divisor[lane];
        }
    }
}
