//! Where the kernels get sin φ and cos φ from: any points (one vectorised sincos per
//! point), a table computed once and shared (sweeps: one φ grid, many designs), or a
//! uniform grid by rotation from exact values.
//!
//! On a uniform grid φ_i = start + i·step, write i = q·SPAN + r. Then
//! e^{iφ_i} = e^{iφ_{q·SPAN}} · e^{i·r·step}: a seed per SPAN (1024) points and a table of SPAN
//! offsets, both from the exact sincos, so every point is *one* complex multiplication away
//! from exact values. The rounding does not accumulate along the grid (no drift): it is
//! bounded by a few ulps at every point, however long the grid. A point's value depends
//! only on (grid, i), never on the blocking or the thread count.

use crate::doubledouble::DoubleDouble;
use crate::error::{MechanismError, Result};
use crate::parallel::{map_indices, Parallelism};
#[cfg(test)]
use crate::trig::Unfused;
use crate::trig::{sincos_block, sincos_table, MulAdd};

/// The crank angles φ_i = start + i·step, i = 0 … len − 1 (as `start + i as f64 * step`
/// rounds them: numpy's `start + arange(len) * step`).
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

/// e^{i·m·φ_i} on a uniform grid, for a fixed integer multiplier m (1 for φ itself, p for
/// the step of a series' harmonics).
#[derive(Debug, Clone)]
pub(crate) struct Rotations {
    len: usize,
    seed_sin: Vec<f64>,
    seed_cos: Vec<f64>,
    offset_sin: Vec<f64>,
    offset_cos: Vec<f64>,
}

impl Rotations {
    pub(crate) fn new(grid: &UniformGrid, multiplier: usize, parallelism: Parallelism) -> Self {
        // Seed and offset angles in double-double, so that they are exact sums of the grid's
        // start and step: then their rounding is not relative to the (possibly large) offset
        // r·step but to the result, whatever the step and the multiplier.
        let m = multiplier as f64;
        let seed = |q: usize| {
            DoubleDouble::product((q * SPAN) as f64, grid.step)
                .add(DoubleDouble::new(grid.start))
                .mul_f64(m)
        };
        // The seeds are a serial prelude to the parallel kernels: compute them in parallel
        // too, in fixed batches (each seed's value does not depend on the batching).
        const BATCH: usize = 256;
        let n_seeds = grid.len.div_ceil(SPAN);
        let batches = map_indices(n_seeds.div_ceil(BATCH), grid.len, parallelism, |b| {
            let angles: Vec<DoubleDouble> = (b * BATCH..((b + 1) * BATCH).min(n_seeds))
                .map(seed)
                .collect();
            sincos_double_double(&angles)
        });
        let (mut seed_sin, mut seed_cos) =
            (Vec::with_capacity(n_seeds), Vec::with_capacity(n_seeds));
        for (s, c) in batches {
            seed_sin.extend_from_slice(&s);
            seed_cos.extend_from_slice(&c);
        }
        // Only as many offsets as a short grid reaches (rounded up to whole blocks).
        let offsets: Vec<DoubleDouble> = (0..SPAN.min(grid.len.next_multiple_of(64)))
            .map(|r| DoubleDouble::product(r as f64, grid.step).mul_f64(m))
            .collect();
        let (offset_sin, offset_cos) = sincos_double_double(&offsets);
        Self {
            len: grid.len,
            seed_sin,
            seed_cos,
            offset_sin,
            offset_cos,
        }
    }

    /// (sin, cos) of m·φ_i for i = first … first + N − 1; lanes past the grid's end repeat
    /// its last point (the caller drops them).
    #[inline(always)]
    pub(crate) fn block<M: MulAdd, const N: usize>(&self, first: usize) -> ([f64; N], [f64; N]) {
        let (mut s, mut c) = ([0.0; N], [0.0; N]);
        let (q, r) = (first / SPAN, first % SPAN);
        if r + N <= self.offset_sin.len() && first + N <= self.len {
            // One seed for the whole block: broadcast it against a run of offsets.
            let (ss, sc) = (self.seed_sin[q], self.seed_cos[q]);
            let (os, oc) = (&self.offset_sin[r..r + N], &self.offset_cos[r..r + N]);
            for l in 0..N {
                (s[l], c[l]) = rotate::<M>((ss, sc), (os[l], oc[l]));
            }
        } else {
            // A block across a seed boundary or the grid's end: the same arithmetic per lane.
            for l in 0..N {
                let i = (first + l).min(self.len.saturating_sub(1));
                let (q, r) = (i / SPAN, i % SPAN);
                let seed = (self.seed_sin[q], self.seed_cos[q]);
                (s[l], c[l]) = rotate::<M>(seed, (self.offset_sin[r], self.offset_cos[r]));
            }
        }
        (s, c)
    }
}

/// (sin, cos) of a + b from those of a and b: one complex multiplication, the same
/// operations for every point of a grid whichever path of `Rotations::block` it takes.
#[inline(always)]
fn rotate<M: MulAdd>((sa, ca): (f64, f64), (sb, cb): (f64, f64)) -> (f64, f64) {
    (M::mul_add(sa, cb, ca * sb), M::mul_add(ca, cb, -(sa * sb)))
}

/// (sin, cos) of angles hi + lo: sin(hi + lo) = sin hi + lo·cos hi to within lo², far
/// below an ulp.
fn sincos_double_double(angles: &[DoubleDouble]) -> (Vec<f64>, Vec<f64>) {
    let hi: Vec<f64> = angles.iter().map(|a| a.hi).collect();
    let (mut sin, mut cos) = sincos_table(&hi);
    for ((s, c), a) in sin.iter_mut().zip(cos.iter_mut()).zip(angles) {
        if a.lo != 0.0 {
            (*s, *c) = (*s + a.lo * *c, *c - a.lo * *s);
        }
    }
    (sin, cos)
}

/// Where a kernel's register block gets (sin φ, cos φ): one implementation per kind of
/// `Run`, so that each block loop is compiled for its source (no branch inside it).
pub(crate) trait AngleSource: Copy {
    /// Points offset … offset + len − 1 of the run (len ≤ N); the other lanes padded.
    fn block<M: MulAdd, const N: usize>(self, offset: usize, len: usize) -> ([f64; N], [f64; N]);
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
fn padded<const N: usize>(values: &[f64], offset: usize, len: usize) -> [f64; N] {
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
        let (mut s, mut c) = ([0.0; N], [0.0; N]);
        sincos_block::<M>(&padded::<N>(self.0, offset, len), &mut s, &mut c);
        (s, c)
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
    #[inline(always)]
    fn block<M: MulAdd, const N: usize>(self, offset: usize, _len: usize) -> ([f64; N], [f64; N]) {
        self.rotations.block::<M, N>(self.first + offset)
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
mod tests {
    use super::*;

    #[test]
    fn rotations_stay_within_two_ulps_of_exact_sincos_without_drift() {
        // Long grids over many revolutions, and grids that start anywhere: the error at the
        // far end is no larger than at the start (no accumulation along the grid).
        for &(start, step, len) in &[
            (0.0, std::f64::consts::TAU / 1_000_003.0, 1_000_003),
            (-3.7, 0.013, 200_000),
            (1234.5, 1.0e-3, 100_000),
        ] {
            let grid = UniformGrid::new(start, step, len).unwrap();
            for multiplier in [1, 6, 24] {
                let rotations = Rotations::new(&grid, multiplier, Parallelism::SERIAL);
                let mut worst_head: f64 = 0.0;
                let mut worst_tail: f64 = 0.0;
                for first in (0..len).step_by(16) {
                    let (s, c) = rotations.block::<Unfused, 16>(first);
                    for l in 0..16.min(len - first) {
                        let i = first + l;
                        // The rotation is of the exact angle m·(start + i·step); compare with
                        // libm there (the user's φ_i is that rounded, within ulp(φ_i)/2).
                        let angle = DoubleDouble::product(i as f64, step)
                            .add(DoubleDouble::new(start))
                            .mul_f64(multiplier as f64);
                        let (hs, hc) = angle.hi.sin_cos();
                        let (es, ec) = (hs + angle.lo * hc, hc - angle.lo * hs);
                        let error = (s[l] - es).abs().max((c[l] - ec).abs()) / f64::EPSILON;
                        if i < len / 10 {
                            worst_head = worst_head.max(error);
                        } else if i > len - len / 10 {
                            worst_tail = worst_tail.max(error);
                        }
                    }
                }
                assert!(
                    worst_head < 2.5,
                    "{start} {step} m={multiplier}: head {worst_head}"
                );
                assert!(
                    worst_tail < 2.5,
                    "{start} {step} m={multiplier}: tail {worst_tail}"
                );
            }
        }
    }

    #[test]
    fn a_point_does_not_depend_on_the_block_it_is_computed_in() {
        let grid = UniformGrid::new(0.25, 0.001, 5000).unwrap();
        let rotations = Rotations::new(&grid, 1, Parallelism::SERIAL);
        let (s16, c16) = (0..5000)
            .step_by(16)
            .map(|f| rotations.block::<Unfused, 16>(f))
            .fold((vec![], vec![]), |(mut s, mut c), (bs, bc)| {
                s.extend_from_slice(&bs);
                c.extend_from_slice(&bc);
                (s, c)
            });
        for first in [0, 1, 7, 1013, 1020, 4990] {
            let (s, c) = rotations.block::<Unfused, 8>(first);
            for l in 0..8.min(5000 - first) {
                assert_eq!(s[l].to_bits(), s16[first + l].to_bits());
                assert_eq!(c[l].to_bits(), c16[first + l].to_bits());
            }
        }
        // Index 0 is the exact sincos of start.
        let (s, c) = rotations.block::<Unfused, 1>(0);
        let (ts, tc) = sincos_table(&[0.25]);
        assert_eq!((s[0], c[0]), (ts[0], tc[0]));
    }

    #[test]
    fn seeds_do_not_depend_on_the_thread_count() {
        let grid = UniformGrid::new(0.1, 1.0e-5, 3_000_001).unwrap();
        let serial = Rotations::new(&grid, 7, Parallelism::SERIAL);
        let parallel = Rotations::new(&grid, 7, Parallelism { threshold: 0 });
        assert_eq!(serial.seed_sin, parallel.seed_sin);
        assert_eq!(serial.seed_cos, parallel.seed_cos);
        assert_eq!(serial.seed_sin.len(), 3_000_001_usize.div_ceil(SPAN));
    }

    #[test]
    fn rejects_non_finite_grids() {
        assert!(UniformGrid::new(f64::NAN, 0.1, 3).is_err());
        assert!(UniformGrid::new(0.0, f64::INFINITY, 3).is_err());
        assert!(UniformGrid::new(0.0, 1e308, 10).is_err());
        assert!(UniformGrid::new(0.0, 1e308, 1).is_ok());
        assert_eq!(
            UniformGrid::new(0.5, 0.25, 3).unwrap().points(),
            vec![0.5, 0.75, 1.0]
        );
    }
}
