//! The one way work is spread over threads: the flat, design-major output is cut into
//! fixed chunks, and each chunk is walked row segment by row segment. Each output
//! element is computed independently of the chunking, so results are bit-identical for
//! any thread count.

use rayon::prelude::*;

/// When to spread work over rayon's thread pool.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Parallelism {
    /// Smallest amount of work (output points × cranks) worth going parallel for;
    /// `usize::MAX` means always serial.
    pub threshold: usize,
}

impl Parallelism {
    pub const SERIAL: Self = Self {
        threshold: usize::MAX,
    };
    pub const DEFAULT_THRESHOLD: usize = 1 << 15;

    pub fn runs_parallel(self, work: usize) -> bool {
        work >= self.threshold
    }
}

impl Default for Parallelism {
    fn default() -> Self {
        Self {
            threshold: Self::DEFAULT_THRESHOLD,
        }
    }
}

/// Output elements per parallel task.
const CHUNK: usize = 8 * 1024;

/// Call `fill(row, first_column, segment)` for every row segment of `out`, viewed as rows
/// of `n_cols`, in parallel when `work` reaches the threshold.
pub(crate) fn for_each_row_segment<F>(
    out: &mut [f64],
    n_cols: usize,
    work: usize,
    parallelism: Parallelism,
    fill: F,
) where
    F: Fn(usize, usize, &mut [f64]) + Sync,
{
    if out.is_empty() || n_cols == 0 {
        return;
    }
    // A chunk of the flat output may span several rows: walk it segment by segment.
    let fill_chunk = |(index, chunk): (usize, &mut [f64])| {
        let mut flat = index * CHUNK;
        let mut done = 0;
        while done < chunk.len() {
            let (row, col) = (flat / n_cols, flat % n_cols);
            let len = (n_cols - col).min(chunk.len() - done);
            fill(row, col, &mut chunk[done..done + len]);
            flat += len;
            done += len;
        }
    };
    if parallelism.runs_parallel(work) {
        out.par_chunks_mut(CHUNK).enumerate().for_each(fill_chunk);
    } else {
        out.chunks_mut(CHUNK).enumerate().for_each(fill_chunk);
    }
}

/// Call `fill(row, values)` for every whole row of `out` (rows of `n_cols`), one task per
/// row, in parallel when `work` reaches the threshold: for rows that must be computed
/// whole (a recurrence along the row).
pub(crate) fn for_each_row<F>(
    out: &mut [f64],
    n_cols: usize,
    work: usize,
    parallelism: Parallelism,
    fill: F,
) where
    F: Fn(usize, &mut [f64]) + Sync,
{
    if out.is_empty() || n_cols == 0 {
        return;
    }
    let fill_row = |(row, values): (usize, &mut [f64])| fill(row, values);
    if parallelism.runs_parallel(work) {
        out.par_chunks_mut(n_cols).enumerate().for_each(fill_row);
    } else {
        out.chunks_mut(n_cols).enumerate().for_each(fill_row);
    }
}

/// As `for_each_row`, for two outputs of the same shape filled together.
pub(crate) fn for_each_row_pair<F>(
    a: &mut [f64],
    b: &mut [f64],
    n_cols: usize,
    work: usize,
    parallelism: Parallelism,
    fill: F,
) where
    F: Fn(usize, &mut [f64], &mut [f64]) + Sync,
{
    if a.is_empty() || n_cols == 0 {
        return;
    }
    let fill_rows = |(row, (x, y)): (usize, (&mut [f64], &mut [f64]))| fill(row, x, y);
    if parallelism.runs_parallel(work) {
        a.par_chunks_mut(n_cols)
            .zip(b.par_chunks_mut(n_cols))
            .enumerate()
            .for_each(fill_rows);
    } else {
        a.chunks_mut(n_cols)
            .zip(b.chunks_mut(n_cols))
            .enumerate()
            .for_each(fill_rows);
    }
}

/// `f(i)` for i in 0..n into a vector, in parallel when `work` reaches the threshold.
pub(crate) fn map_indices<T, F>(n: usize, work: usize, parallelism: Parallelism, f: F) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync + Send,
{
    if parallelism.runs_parallel(work) {
        (0..n).into_par_iter().map(f).collect()
    } else {
        (0..n).map(f).collect()
    }
}

/// As `map_indices`, with a scratch value per worker (`init`) that `f` may reuse: it must
/// not influence the result, which then stays independent of the scheduling.
pub(crate) fn map_indices_with<T, S, I, F>(
    n: usize,
    work: usize,
    parallelism: Parallelism,
    init: I,
    f: F,
) -> Vec<T>
where
    T: Send,
    I: Fn() -> S + Sync + Send,
    F: Fn(&mut S, usize) -> T + Sync + Send,
{
    if parallelism.runs_parallel(work) {
        (0..n).into_par_iter().map_init(init, f).collect()
    } else {
        let mut scratch = init();
        (0..n).map(|i| f(&mut scratch, i)).collect()
    }
}
