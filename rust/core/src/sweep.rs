//! Design sweeps: many machines, each reduced on the fly to a handful of numbers, never a
//! designs × φ matrix. The grid outputs come from the closed form; the extrema and the
//! leading harmonic from the machine-precision Fourier series. Each design is processed independently (its own series, its own
//! grid buffer), so results are bit-identical for any thread count and chunking.

use crate::error::{MechanismError, Result};
use crate::exact::{evaluate_run, Quantity};
use crate::extrema::energy_extrema;
use crate::grid::{Run, TableAngles};
use crate::harmonics::{harmonic_reach, PhaseSums};
use crate::mechanism::{Design, Phases};
use crate::parallel::{map_indices_with, Parallelism};
use crate::series::FourierSeries;
use crate::trig::sincos_table;

/// What to compute for each design.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SweepOutputs {
    /// max|Q_u*| and rms(Q_u*) over the φ grid.
    pub force: bool,
    /// Exact min and max of U_w* (and so δ_g).
    pub energy: bool,
    /// The largest harmonic of Q_u* and its amplitude.
    pub harmonic: bool,
}

/// One design's reductions (NaN where not requested).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepRow {
    pub force_max_abs: f64,
    pub force_rms: f64,
    pub energy_min: f64,
    pub energy_max: f64,
    pub energy_range: f64,
    pub leading_harmonic: f64,
    pub leading_amplitude: f64,
}

/// The distinct crank phase sets of a sweep, each with its phase sums.
#[derive(Debug, Clone)]
pub struct PhaseSetTable {
    phases: Vec<Phases>,
    sums: Vec<PhaseSums>,
}

impl PhaseSetTable {
    /// `sets[i]` are the phases α_j of set i; `max_crank_ratio` bounds the harmonics needed.
    pub fn new(sets: &[Vec<f64>], max_crank_ratio: f64) -> Result<Self> {
        let reach = harmonic_reach(max_crank_ratio);
        Ok(Self {
            phases: sets.iter().map(|s| Phases::new(s)).collect::<Result<_>>()?,
            sums: sets.iter().map(|s| PhaseSums::new(s, reach)).collect(),
        })
    }

    pub fn len(&self) -> usize {
        self.phases.len()
    }

    pub fn is_empty(&self) -> bool {
        self.phases.is_empty()
    }
}

/// (max|q|, Σq²) with eight independent accumulators, so the loop is not bound by the
/// latency of one running sum; the combining order is fixed, so the result is too.
fn peak_and_sum_of_squares(values: &[f64]) -> (f64, f64) {
    const LANES: usize = 8;
    let (mut peak, mut squares) = ([0.0_f64; LANES], [0.0_f64; LANES]);
    let mut chunks = values.chunks_exact(LANES);
    for chunk in &mut chunks {
        for l in 0..LANES {
            let q = chunk[l];
            let magnitude = q.abs();
            peak[l] = if magnitude > peak[l] || magnitude.is_nan() {
                magnitude
            } else {
                peak[l]
            };
            squares[l] += q * q;
        }
    }
    for (l, &q) in chunks.remainder().iter().enumerate() {
        peak[l] = if q.abs() > peak[l] || q.is_nan() {
            q.abs()
        } else {
            peak[l]
        };
        squares[l] += q * q;
    }
    let peak = peak
        .iter()
        .fold(0.0_f64, |m, &p| if p > m || p.is_nan() { p } else { m });
    (peak, squares.iter().sum())
}

/// The largest harmonic of a series and its amplitude √(a_n² + b_n²).
fn leading_harmonic(series: &FourierSeries) -> (f64, f64) {
    let mut best = (1.0, series.a1.hypot(series.b1));
    for (nu, (a, b)) in series.cos.iter().zip(&series.sin).enumerate() {
        let amplitude = a.hypot(*b);
        if amplitude > best.1 {
            best = (((nu + 1) * series.step) as f64, amplitude);
        }
    }
    if best.1 == 0.0 {
        (0.0, 0.0) // Q ≡ 0: no harmonic leads
    } else {
        best
    }
}

fn sweep_one(
    design: &Design,
    phases: &Phases,
    sums: &PhaseSums,
    grid: TableAngles,
    outputs: SweepOutputs,
    buffer: &mut Vec<f64>,
) -> SweepRow {
    let mut row = SweepRow {
        force_max_abs: f64::NAN,
        force_rms: f64::NAN,
        energy_min: f64::NAN,
        energy_max: f64::NAN,
        energy_range: f64::NAN,
        leading_harmonic: f64::NAN,
        leading_amplitude: f64::NAN,
    };
    if outputs.force {
        // The closed form on the grid: k cheap crank terms per point from the shared sin/cos,
        // which beats building and summing a series for the short grids of a sweep.
        let n = grid.sin.len();
        buffer.resize(n, 0.0);
        evaluate_run(
            Quantity::GeneralizedForce,
            design,
            phases,
            Run::Table(grid),
            buffer,
        );
        let (peak, squares) = peak_and_sum_of_squares(buffer);
        row.force_max_abs = peak;
        row.force_rms = (squares / n as f64).sqrt();
    }
    if !(outputs.energy || outputs.harmonic) {
        return row;
    }
    let series = FourierSeries::exact(design, sums);
    if outputs.energy {
        let extrema = energy_extrema(design, phases, &series);
        row.energy_min = extrema.min;
        row.energy_max = extrema.max;
        row.energy_range = extrema.range;
    }
    if outputs.harmonic {
        (row.leading_harmonic, row.leading_amplitude) = leading_harmonic(&series);
    }
    row
}

/// Reduce every design: `phase_set[i]` indexes `table` for design i; `phi` is the grid for
/// the force outputs (the series path: exact to machine precision, nearly free of k).
pub fn sweep(
    designs: &[Design],
    phase_set: &[u32],
    table: &PhaseSetTable,
    phi: &[f64],
    outputs: SweepOutputs,
    parallelism: Parallelism,
) -> Result<Vec<SweepRow>> {
    if phase_set.len() != designs.len() {
        return Err(MechanismError::LengthMismatch {
            parameter: "phase_set",
            expected: designs.len(),
            found: phase_set.len(),
        });
    }
    if let Some(&bad) = phase_set.iter().find(|&&s| s as usize >= table.len()) {
        return Err(MechanismError::InvalidChoice {
            parameter: "phase_set",
            value: bad.to_string(),
            allowed: "an index into the phase-set table",
        });
    }
    if outputs.force && phi.is_empty() {
        return Err(MechanismError::Empty { parameter: "phi" });
    }
    let work = designs.len().saturating_mul(phi.len().max(64));
    // sin φ and cos φ of the grid, computed once and shared by every design: the same
    // values each design would compute itself, so results do not change.
    let (sin, cos) = sincos_table(if outputs.force { phi } else { &[] });
    let grid = TableAngles {
        sin: &sin,
        cos: &cos,
    };
    // A grid buffer per worker, overwritten by each design: results do not depend on it.
    Ok(map_indices_with(
        designs.len(),
        work,
        parallelism,
        Vec::new,
        |buffer, i| {
            let set = phase_set[i] as usize;
            sweep_one(
                &designs[i],
                &table.phases[set],
                &table.sums[set],
                grid,
                outputs,
                buffer,
            )
        },
    ))
}
