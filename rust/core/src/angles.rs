//! Where the kernels get sin φ and cos φ from: any points (one vectorised sincos per
//! point), a table computed once and shared (sweeps: one φ grid, many designs), or a
//! uniform grid by rotation from exact values.
//!
//! A uniform grid's points are those its user sees: x_i = fl(start + fl(i·step)), as numpy's
//! `start + arange(len) * step` rounds them. Write i = q·SPAN + r and φ_i = start + i·step
//! exactly. Then e^{iφ_i} = e^{iφ_{q·SPAN}} · e^{i·r·step}: a seed per SPAN (1024) points and a
//! table of SPAN offsets, both from the exact sincos of double-double angles, so every point
//! is *one* complex multiplication away from exact values; and x_i = φ_i + d_i with the
//! rounding d_i found exactly per point (error-free transformations), so one more
//! rotation by d_i gives e^{ix_i}. The rounding does not accumulate along the grid (no
//! drift), and the values are those at the exposed points, at any start: a few ulps at
//! every point, however long the grid and wherever it starts. A point's value depends only
//! on (grid, i), never on the blocking or the thread count.

use crate::doubledouble::DoubleDouble;
use crate::error::{MechanismError, Result};
use crate::parallel::{map_indices, Parallelism};
#[cfg(test)]
use crate::trig::Fused;
use crate::trig::{sincos_block, sincos_lanes, sincos_table, MulAdd, Unfused};

/// The crank angles x_i = start + i·step, i = 0 … len − 1, rounded as `start + i as f64 *
/// step` rounds them (numpy's `start + arange(len) * step`): the kernels evaluate at
/// exactly these doubles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniformGrid {
    pub start: f64,
    pub step: f64,
    pub len: usize,
}

impl UniformGrid {
    pub fn new(start: f64, step: f64, len: usize) -> Result<Self> {
        for (parameter, value) in [("start", start), ("step", step)] {
            if !value.is_finite() {
                return Err(MechanismError::OutOfRange {
                    parameter,
                    value,
                    allowed: "a finite angle [rad]",
                });
            }
        }
        let grid = Self { start, step, len };
        let last = grid.point(len.saturating_sub(1));
        if !last.is_finite() {
            return Err(MechanismError::OutOfRange {
                parameter: "step",
                value: step,
                allowed: "a step whose grid stays finite",
            });
        }
        Ok(grid)
    }

    /// n points over one revolution, [0, 2π).
    pub fn revolution(len: usize) -> Self {
        Self {
            start: 0.0,
            step: std::f64::consts::TAU / len.max(1) as f64,
            len,
        }
    }

    /// φ_i as the grid's user sees it.
    #[inline(always)]
    pub fn point(&self, i: usize) -> f64 {
        self.start + i as f64 * self.step
    }

    pub fn points(&self) -> Vec<f64> {
        (0..self.len).map(|i| self.point(i)).collect()
    }
}

/// The crank angles of an evaluation.
#[derive(Debug, Clone, Copy)]
pub enum Phi<'a> {
    /// Any angles; each point's value depends on that point alone.
    Points(&'a [f64]),
    /// A uniform grid, evaluated by rotation (see the module docs).
    Uniform(UniformGrid),
}

impl Phi<'_> {
    pub fn len(&self) -> usize {
        match self {
            Phi::Points(points) => points.len(),
            Phi::Uniform(grid) => grid.len,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl<'a> From<&'a [f64]> for Phi<'a> {
    fn from(points: &'a [f64]) -> Self {
        Phi::Points(points)
    }
}

impl<'a> From<&'a Vec<f64>> for Phi<'a> {
    fn from(points: &'a Vec<f64>) -> Self {
        Phi::Points(points)
    }
}

impl<'a, const N: usize> From<&'a [f64; N]> for Phi<'a> {
    fn from(points: &'a [f64; N]) -> Self {
        Phi::Points(points)
    }
}

impl From<UniformGrid> for Phi<'_> {
    fn from(grid: UniformGrid) -> Self {
        Phi::Uniform(grid)
    }
}

/// Grid points per seed. A power of two (cheap q, r); the offset table (2·SPAN f64 = 16 KiB)
/// stays in L1, and the seeds — a serial prelude to the kernels when few threads compute
/// them — cost one double-double sincos per SPAN points. 256 and 1024 measured alike.
const SPAN: usize = 1024;

/// How the rotation to the exposed point, e^{i·m·d_i} with d_i = x_i − φ_i, is applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Correction {
    /// |m·d_i| ≤ 2^-27 on the whole grid: cos(m·d_i) rounds to 1 and sin(m·d_i) to m·d_i,
    /// so the rotation is two multiply-adds (every grid of moderate angles).
    FirstOrder,
    /// Larger angles (a grid that starts far out, a high harmonic): sincos of m·d_i.
    Full,
}

/// e^{i·m·x_i} on a uniform grid, for a fixed integer multiplier m (1 for φ itself, p for
/// the step of a series' harmonics).
#[derive(Debug, Clone)]
pub(crate) struct Rotations {
    len: usize,
    start: f64,
    /// start is +0.0 (see `block_and_rounding`).
    start_is_zero: bool,
    step: f64,
    multiplier: f64,
    correction: Correction,
    seed_sin: Vec<f64>,
    seed_cos: Vec<f64>,
    offset_sin: Vec<f64>,
    offset_cos: Vec<f64>,
}

impl Rotations {
    pub(crate) fn new(grid: &UniformGrid, multiplier: usize, parallelism: Parallelism) -> Self {
        // Every angle below is an exact product of doubles (an integer m·j < 2^53 times the
        // step, m times the start), carried as a double-double whose sincos is exact; the
        // seed e^{im(start + q·SPAN·step)} is then one rotation of two such values. Summing
        // the angles first would round them to ~2^-106 of their size: 1e-14 rad at
        // m·start = 2e18.
        let m = multiplier as f64;
        let start = sincos_double_double(&[DoubleDouble::product(m, grid.start)]);
        let start = (start.0[0], start.1[0]);
        let seed_angle =
            |q: usize| DoubleDouble::product((multiplier * q * SPAN) as f64, grid.step);
        // The seeds are a serial prelude to the parallel kernels: compute them in parallel
        // too, in fixed batches (each seed's value does not depend on the batching).
        const BATCH: usize = 256;
        let n_seeds = grid.len.div_ceil(SPAN);
        let batches = map_indices(n_seeds.div_ceil(BATCH), grid.len, parallelism, |b| {
            let angles: Vec<DoubleDouble> = (b * BATCH..((b + 1) * BATCH).min(n_seeds))
                .map(seed_angle)
                .collect();
            let (mut sin, mut cos) = sincos_double_double(&angles);
            for (s, c) in sin.iter_mut().zip(cos.iter_mut()) {
                (*s, *c) = rotate::<Unfused>(start, (*s, *c));
            }
            (sin, cos)
        });
        let (mut seed_sin, mut seed_cos) =
            (Vec::with_capacity(n_seeds), Vec::with_capacity(n_seeds));
        for (s, c) in batches {
            seed_sin.extend_from_slice(&s);
            seed_cos.extend_from_slice(&c);
        }
        // Only as many offsets as a short grid reaches (rounded up to whole blocks).
        let offsets: Vec<DoubleDouble> = (0..SPAN.min(grid.len.next_multiple_of(64)))
            .map(|r| DoubleDouble::product((multiplier * r) as f64, grid.step))
            .collect();
        let (offset_sin, offset_cos) = sincos_double_double(&offsets);
        // |d_i| ≤ ulp(x_i)/2 + ulp(i·step)/2 ≤ ε·(|start| + 2·len·|step|).
        let reach = grid.start.abs() + 2.0 * grid.len as f64 * grid.step.abs();
        let correction = if m * f64::EPSILON * reach <= FIRST_ORDER {
            Correction::FirstOrder
        } else {
            Correction::Full
        };
        Self {
            len: grid.len,
            start: grid.start,
            start_is_zero: grid.start.to_bits() == 0,
            step: grid.step,
            multiplier: m,
            correction,
            seed_sin,
            seed_cos,
            offset_sin,
            offset_cos,
        }
    }

    /// (sin, cos) of m·x_i for i = first … first + N − 1; lanes past the grid's end hold
    /// values of no meaning (the caller drops them).
    #[inline(always)]
    pub(crate) fn block<M: MulAdd, const N: usize>(&self, first: usize) -> ([f64; N], [f64; N]) {
        let (s, c, _) = self.block_and_rounding::<M, N>(first);
        (s, c)
    }

    /// As `block`, and the roundings d_i = x_i − φ_i of the lanes (for `block_rounded`
    /// of another multiplier on the same grid, which then need not find them again).
    #[inline(always)]
    pub(crate) fn block_and_rounding<M: MulAdd, const N: usize>(
        &self,
        first: usize,
    ) -> ([f64; N], [f64; N], [f64; N]) {
        let mut d = [0.0; N];
        // i as a float iota: vectorises without integer conversions. Not clamped to the
        // grid like the lanes of `progression`: lanes past the end are dropped by the
        // caller, and a clamp costs three instructions a vector.
        let base = first as f64;
        let index = |l: usize| base + l as f64;
        if self.start_is_zero {
            // x_i = fl(i·step): the sum's part of the rounding is exactly +0 and
            // (−0) + (−e) = −e bit for bit, so only the product's error is left to find
            // (the common grid over a revolution; 3 operations a lane instead of 9).
            for (l, d) in d.iter_mut().enumerate() {
                let i = index(l);
                *d = -M::product_error(i, self.step, i * self.step);
            }
        } else {
            for (l, d) in d.iter_mut().enumerate() {
                let (t, e) = rounding::<M>(self.start, self.step, index(l));
                *d = t + e;
            }
        }
        let (s, c) = self.block_rounded::<M, N>(first, &d);
        (s, c, d)
    }

    /// (sin, cos) of m·x_i given the lanes' roundings d_i (as `block_and_rounding` found
    /// them): the exact progression, then the rotation by m·d_i.
    #[inline(always)]
    pub(crate) fn block_rounded<M: MulAdd, const N: usize>(
        &self,
        first: usize,
        d: &[f64; N],
    ) -> ([f64; N], [f64; N]) {
        let (mut s, mut c) = self.progression::<M, N>(first);
        match self.correction {
            Correction::FirstOrder => {
                // One loop per result (see `rotated`).
                let (s0, c0) = (s, c);
                for l in 0..N {
                    s[l] = M::mul_add(self.multiplier * d[l], c0[l], s0[l]);
                }
                for l in 0..N {
                    c[l] = M::mul_add(-(self.multiplier * d[l]), s0[l], c0[l]);
                }
            }
            Correction::Full => {
                // m·d_i as hi + lo, d_i itself as an exact pair (a rounded d_i would be off
                // by m·ε·|d_i|: 60 ulps at m = 2048, start = 1e15): sincos of hi, lo (≤ an
                // ulp of hi) to first order.
                let (base, last) = (first as f64, self.len.saturating_sub(1) as f64);
                let (mut hi, mut lo) = ([0.0; N], [0.0; N]);
                for l in 0..N {
                    let i = (base + l as f64).min(last);
                    let (t, e) = rounding::<M>(self.start, self.step, i);
                    let (dh, dl) = two_sum(t, e);
                    hi[l] = self.multiplier * dh;
                    lo[l] = M::mul_add(
                        self.multiplier,
                        dl,
                        M::product_error(self.multiplier, dh, hi[l]),
                    );
                }
                let (mut ds, mut dc) = ([0.0; N], [0.0; N]);
                sincos_block::<M>(&hi, &mut ds, &mut dc);
                let (s0, c0) = (s, c);
                for l in 0..N {
                    let (ds, dc) = (
                        M::mul_add(lo[l], dc[l], ds[l]),
                        M::mul_add(-lo[l], ds[l], dc[l]),
                    );
                    s[l] = rotate::<M>((s0[l], c0[l]), (ds, dc)).0;
                    c[l] = rotate::<M>((s0[l], c0[l]), (ds, dc)).1;
                }
            }
        }
        (s, c)
    }

    /// (sin, cos) of m·φ_i on the exact progression φ_i = start + i·step.
    #[inline(always)]
    fn progression<M: MulAdd, const N: usize>(&self, first: usize) -> ([f64; N], [f64; N]) {
        let (q, r) = (first / SPAN, first % SPAN);
        if r + N <= self.offset_sin.len() && first + N <= self.len {
            // One seed for the whole block, against a run of offsets, read where they lie
            // (gathered into arrays first, they went through the stack: 24 moves a block).
            let (ss, sc) = (self.seed_sin[q], self.seed_cos[q]);
            let (os, oc) = (&self.offset_sin[r..r + N], &self.offset_cos[r..r + N]);
            rotated::<M, N>(|_| (ss, sc), |l| (os[l], oc[l]))
        } else {
            // A block across a seed boundary or the grid's end: each lane its own.
            let mut lanes = ([0.0; N], [0.0; N], [0.0; N], [0.0; N]);
            for l in 0..N {
                let i = (first + l).min(self.len.saturating_sub(1));
                let (q, r) = (i / SPAN, i % SPAN);
                lanes.0[l] = self.seed_sin[q];
                lanes.1[l] = self.seed_cos[q];
                lanes.2[l] = self.offset_sin[r];
                lanes.3[l] = self.offset_cos[r];
            }
            let (seed_s, seed_c, os, oc) = lanes;
            rotated::<M, N>(|l| (seed_s[l], seed_c[l]), |l| (os[l], oc[l]))
        }
    }
}

/// (sin, cos) of the sums of the angles of seed(l) and offset(l), given as (sin, cos), in
/// one loop per result: computed as a pair (s, c) per lane, the results are vectorised
/// across the pair, with shuffles between lanes (+40% of the instructions per point on a
/// uniform grid at k = 1).
#[inline(always)]
fn rotated<M: MulAdd, const N: usize>(
    seed: impl Fn(usize) -> (f64, f64),
    offset: impl Fn(usize) -> (f64, f64),
) -> ([f64; N], [f64; N]) {
    let (mut s, mut c) = ([0.0; N], [0.0; N]);
    for (l, s) in s.iter_mut().enumerate() {
        *s = rotate::<M>(seed(l), offset(l)).0;
    }
    for (l, c) in c.iter_mut().enumerate() {
        *c = rotate::<M>(seed(l), offset(l)).1;
    }
    (s, c)
}

/// Below this |angle|, cos rounds to 1 and sin to the angle itself (2^-27: angle²/2 ≤ ε/4).
const FIRST_ORDER: f64 = 1.0 / 134_217_728.0;

/// The rounding of a grid point, fl(start + fl(i·step)) − (start + i·step), as two
/// doubles whose sum it is exactly: i·step = p + e (an exact product), start + p = x + t (an
/// exact sum), so the rounding is (−t) + (−e).
#[inline(always)]
fn rounding<M: MulAdd>(start: f64, step: f64, i: f64) -> (f64, f64) {
    let p = i * step;
    let e = M::product_error(i, step, p);
    let x = start + p;
    let bb = x - start;
    let t = (start - (x - bb)) + (p - bb);
    (-t, -e)
}

/// (s, e) with s + e = a + b exactly.
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// (sin, cos) of a + b from those of a and b: one complex multiplication, the same
/// operations for every point of a grid whichever path of `Rotations::block` it takes.
#[inline(always)]
fn rotate<M: MulAdd>((sa, ca): (f64, f64), (sb, cb): (f64, f64)) -> (f64, f64) {
    (M::mul_add(sa, cb, ca * sb), M::mul_add(ca, cb, -(sa * sb)))
}

/// (sin, cos) of angles hi + lo, from the exact sincos of hi and of lo. lo may be as
/// large as half an ulp of hi (0.06 at hi = 10^15, more for a multiplied angle), so it is
/// rotated by in full; below 2^-27 (every angle of moderate size) cos lo = 1 and
/// sin lo = lo to within a quarter ulp.
fn sincos_double_double(angles: &[DoubleDouble]) -> (Vec<f64>, Vec<f64>) {
    let hi: Vec<f64> = angles.iter().map(|a| a.hi).collect();
    let (mut sin, mut cos) = sincos_table(&hi);
    for ((s, c), a) in sin.iter_mut().zip(cos.iter_mut()).zip(angles) {
        if a.lo == 0.0 {
            continue;
        }
        let (sl, cl) = if a.lo.abs() <= FIRST_ORDER {
            (a.lo, 1.0)
        } else {
            a.lo.sin_cos()
        };
        (*s, *c) = (*s * cl + *c * sl, *c * cl - *s * sl);
    }
    (sin, cos)
}

/// Where a kernel's register block gets (sin φ, cos φ): one implementation per kind of
/// `Run`, so that each block loop is compiled for its source (no branch inside it).
pub(crate) trait AngleSource: Copy {
    /// Whether a point's (sin, cos) are the same in a block of any width (computed from the
    /// point alone, or read): a run may then end in narrower blocks.
    const LANE_FREE: bool = true;

    /// Points offset … offset + len − 1 of the run (len ≤ N); the other lanes padded.
    fn block<M: MulAdd, const N: usize>(self, offset: usize, len: usize) -> ([f64; N], [f64; N]);

    /// As `block`, with the roundings d_i of a uniform grid's points (zero elsewhere: the
    /// points are the values themselves).
    #[inline(always)]
    fn block_and_rounding<M: MulAdd, const N: usize>(
        self,
        offset: usize,
        len: usize,
    ) -> ([f64; N], [f64; N], [f64; N]) {
        let (s, c) = self.block::<M, N>(offset, len);
        (s, c, [0.0; N])
    }
}

/// A vectorised sincos of each point.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PointAngles<'a>(pub &'a [f64]);

/// Precomputed sin φ and cos φ.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TableAngles<'a> {
    pub sin: &'a [f64],
    pub cos: &'a [f64],
}

/// Rotations on a uniform grid, from grid index `first` on.
#[derive(Debug, Clone, Copy)]
pub(crate) struct GridAngles<'a> {
    pub rotations: &'a Rotations,
    pub first: usize,
}

/// values[offset .. offset + len] in N lanes, zero-padded: a fixed-size load for whole
/// blocks (a variable-length copy would be a call to memcpy per block).
#[inline(always)]
pub(crate) fn padded<const N: usize>(values: &[f64], offset: usize, len: usize) -> [f64; N] {
    let mut x = [0.0; N];
    if len == N {
        x.copy_from_slice(&values[offset..offset + N]);
    } else {
        x[..len].copy_from_slice(&values[offset..offset + len]);
    }
    x
}

impl AngleSource for PointAngles<'_> {
    #[inline(always)]
    fn block<M: MulAdd, const N: usize>(self, offset: usize, len: usize) -> ([f64; N], [f64; N]) {
        // A whole block is read where its points lie: a padded copy went through the
        // stack (stored, then loaded again at once: a store-forwarding stall a block).
        match <&[f64; N]>::try_from(&self.0[offset..offset + len]) {
            Ok(x) => sincos_lanes::<M, N>(x),
            Err(_) => sincos_lanes::<M, N>(&padded::<N>(self.0, offset, len)),
        }
    }
}

impl AngleSource for TableAngles<'_> {
    #[inline(always)]
    fn block<M: MulAdd, const N: usize>(self, offset: usize, len: usize) -> ([f64; N], [f64; N]) {
        (
            padded::<N>(self.sin, offset, len),
            padded::<N>(self.cos, offset, len),
        )
    }
}

impl AngleSource for GridAngles<'_> {
    // A block's rotations start from its first index: its width is part of the rounding.
    const LANE_FREE: bool = false;

    #[inline(always)]
    fn block<M: MulAdd, const N: usize>(self, offset: usize, _len: usize) -> ([f64; N], [f64; N]) {
        self.rotations.block::<M, N>(self.first + offset)
    }

    #[inline(always)]
    fn block_and_rounding<M: MulAdd, const N: usize>(
        self,
        offset: usize,
        _len: usize,
    ) -> ([f64; N], [f64; N], [f64; N]) {
        self.rotations
            .block_and_rounding::<M, N>(self.first + offset)
    }
}

/// The kernels' unit of work: a run of points of φ and where their sin/cos come from.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Run<'a> {
    Points(PointAngles<'a>),
    Table(TableAngles<'a>),
    Grid(GridAngles<'a>),
}

impl<'a> Run<'a> {
    pub(crate) fn points(points: &'a [f64]) -> Self {
        Run::Points(PointAngles(points))
    }
}

/// Evaluation-wide preparation of `Phi`: the rotations of a uniform grid, built once and
/// shared by every thread and design.
pub(crate) enum PreparedPhi<'a> {
    Points(&'a [f64]),
    Uniform(Rotations),
}

impl<'a> PreparedPhi<'a> {
    pub(crate) fn new(phi: Phi<'a>, parallelism: Parallelism) -> Self {
        match phi {
            Phi::Points(points) => PreparedPhi::Points(points),
            Phi::Uniform(grid) => PreparedPhi::Uniform(Rotations::new(&grid, 1, parallelism)),
        }
    }

    pub(crate) fn len(&self) -> usize {
        match self {
            PreparedPhi::Points(points) => points.len(),
            PreparedPhi::Uniform(rotations) => rotations.len,
        }
    }

    /// The run of `len` points from index `first`.
    pub(crate) fn run(&self, first: usize, len: usize) -> Run<'_> {
        match self {
            PreparedPhi::Points(points) => Run::points(&points[first..first + len]),
            PreparedPhi::Uniform(rotations) => Run::Grid(GridAngles { rotations, first }),
        }
    }
}

#[cfg(test)]
mod tests;
