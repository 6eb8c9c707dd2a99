//! Design sweeps: many machines — in-line designs sharing phase sets, or engines of any
//! layout — each reduced on the fly to a handful of numbers, never a machines × φ matrix.
//! The grid outputs come from the closed form; the extrema and the leading harmonic from
//! the machine-precision Fourier series. Each machine is processed independently (its own
//! series, its own grid buffer), so results are bit-identical for any thread count and
//! chunking.

use crate::angles::{Run, TableAngles};
use crate::engine::Engine;
use crate::error::{MechanismError, Result};
use crate::exact::{evaluate_units, Coefficients, Quantity};
use crate::extrema::extrema_of_units;
use crate::harmonics::{harmonic_reach, PhaseSums};
use crate::mechanism::{Design, Phases};
use crate::parallel::{map_indices_with, Parallelism};
use crate::series::{FourierSeries, SeriesKind, UnitGroup};
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

impl SweepOutputs {
    /// The groups to compute for outputs named as `SweepRow::NAMES`.
    pub fn from_names<S: AsRef<str>>(names: &[S]) -> Result<Self> {
        let mut outputs = Self::default();
        for name in names {
            match name.as_ref() {
                "force_max_abs" | "force_rms" => outputs.force = true,
                "energy_min" | "energy_max" | "energy_range" => outputs.energy = true,
                "leading_harmonic" | "leading_amplitude" => outputs.harmonic = true,
                other => {
                    return Err(MechanismError::InvalidChoice {
                        parameter: "outputs",
                        value: format!("{other:?}"),
                        allowed: "force_max_abs, force_rms, energy_min, energy_max, \
                                  energy_range, leading_harmonic, leading_amplitude",
                    })
                }
            }
        }
        Ok(outputs)
    }
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

impl SweepRow {
    /// Every output a sweep can compute, in column order.
    pub const NAMES: [&'static str; 7] = [
        "force_max_abs",
        "force_rms",
        "energy_min",
        "energy_max",
        "energy_range",
        "leading_harmonic",
        "leading_amplitude",
    ];

    /// The output called `name` (one of `NAMES`).
    pub fn get(&self, name: &str) -> Option<f64> {
        Some(match name {
            "force_max_abs" => self.force_max_abs,
            "force_rms" => self.force_rms,
            "energy_min" => self.energy_min,
            "energy_max" => self.energy_max,
            "energy_range" => self.energy_range,
            "leading_harmonic" => self.leading_harmonic,
            "leading_amplitude" => self.leading_amplitude,
            _ => return None,
        })
    }
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
            sums: sets
                .iter()
                .map(|s| PhaseSums::within_reach(s, reach))
                .collect(),
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

/// The reductions of one machine: its kernel coefficients (shared or per unit), phases and
/// unit groups; `buffer` is scratch for the grid values.
fn sweep_one(
    coefficients: &[Coefficients],
    phases: &Phases,
    groups: &[UnitGroup],
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
        evaluate_units(
            Quantity::GeneralizedForce,
            coefficients,
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
    let series = FourierSeries::new(SeriesKind::Exact, groups);
    if outputs.energy {
        let extrema = extrema_of_units(coefficients, phases, &series);
        row.energy_min = extrema.min;
        row.energy_max = extrema.max;
        row.energy_range = extrema.range;
    }
    if outputs.harmonic {
        let (n, amplitude) = series.leading_harmonic();
        (row.leading_harmonic, row.leading_amplitude) = (n as f64, amplitude);
    }
    row
}

/// Reduce `count` machines, `reduce(i, grid, buffer)` each, in parallel when `work`
/// reaches the threshold. sin φ and cos φ of the force grid are computed once and shared by
/// every machine — the same values each would compute itself — and each worker keeps one
/// grid buffer, overwritten by each machine: results depend on neither.
fn reduce_each<F>(
    count: usize,
    work: usize,
    phi: &[f64],
    outputs: SweepOutputs,
    parallelism: Parallelism,
    reduce: F,
) -> Result<Vec<SweepRow>>
where
    F: Fn(usize, TableAngles, &mut Vec<f64>) -> SweepRow + Sync + Send,
{
    if outputs.force && phi.is_empty() {
        return Err(MechanismError::Empty { parameter: "phi" });
    }
    let (sin, cos) = sincos_table(if outputs.force { phi } else { &[] });
    let grid = TableAngles {
        sin: &sin,
        cos: &cos,
    };
    Ok(map_indices_with(
        count,
        work,
        parallelism,
        Vec::new,
        |buffer, i| reduce(i, grid, buffer),
    ))
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
    let work = designs.len().saturating_mul(phi.len().max(64));
    reduce_each(
        designs.len(),
        work,
        phi,
        outputs,
        parallelism,
        |i, grid, buffer| {
            let set = phase_set[i] as usize;
            let group = UnitGroup {
                design: &designs[i],
                sums: &table.sums[set],
            };
            let coefficients = [Coefficients::new(&designs[i])];
            sweep_one(
                &coefficients,
                &table.phases[set],
                &[group],
                grid,
                outputs,
                buffer,
            )
        },
    )
}

/// Reduce every engine (any layout, unequal cylinders, Monte-Carlo samples of tolerances)
/// as `sweep` reduces designs; `phi` is the grid for the force outputs.
pub fn sweep_engines(
    engines: &[Engine],
    phi: &[f64],
    outputs: SweepOutputs,
    parallelism: Parallelism,
) -> Result<Vec<SweepRow>> {
    let cylinders: usize = engines.iter().map(|e| e.cylinders().len()).sum();
    let work = cylinders.saturating_mul(phi.len().max(64));
    reduce_each(
        engines.len(),
        work,
        phi,
        outputs,
        parallelism,
        |i, grid, buffer| {
            let engine = &engines[i];
            engine.with_reach_groups(|groups| {
                sweep_one(
                    engine.coefficients(),
                    engine.phases(),
                    groups,
                    grid,
                    outputs,
                    buffer,
                )
            })
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::EngineUnit;
    use crate::mechanism::{crank_phases, Acting, Strokes};

    fn engines() -> Vec<Engine> {
        (0..40)
            .map(|i| {
                let x = i as f64;
                let alphas = crank_phases(1 + i % 7, Strokes::Four, Acting::Single).unwrap();
                Engine::new(
                    alphas
                        .iter()
                        .enumerate()
                        .map(|(j, &phase)| EngineUnit {
                            phase: phase + 1e-3 * (x + j as f64).sin(),
                            inclination: 0.3 + 0.1 * x - 0.2 * j as f64,
                            crank_ratio: 0.05 + 0.02 * x,
                            u1: 0.9 - 0.01 * x,
                            u2: -0.3 + 0.02 * j as f64,
                        })
                        .collect(),
                )
                .unwrap()
            })
            .collect()
    }

    #[test]
    fn engine_rows_are_each_engines_own_values() {
        let phi: Vec<f64> = (0..360)
            .map(|i| std::f64::consts::TAU * i as f64 / 360.0)
            .collect();
        let all = SweepOutputs {
            force: true,
            energy: true,
            harmonic: true,
        };
        let engines = engines();
        let rows = sweep_engines(&engines, &phi, all, Parallelism::SERIAL).unwrap();
        let parallel = sweep_engines(&engines, &phi, all, Parallelism { threshold: 0 }).unwrap();
        assert_eq!(rows, parallel);
        for (engine, row) in engines.iter().zip(&rows) {
            let extrema = engine.energy_extrema();
            assert_eq!(
                (row.energy_min, row.energy_max, row.energy_range),
                (extrema.min, extrema.max, extrema.range)
            );
            let (n, amplitude) = engine.leading_harmonic();
            assert_eq!(
                (row.leading_harmonic, row.leading_amplitude),
                (n as f64, amplitude)
            );
            let mut q = vec![0.0; phi.len()];
            engine
                .evaluate(
                    Quantity::GeneralizedForce,
                    &phi,
                    &mut q,
                    Parallelism::SERIAL,
                )
                .unwrap();
            let peak = q.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            let rms = (q.iter().map(|x| x * x).sum::<f64>() / q.len() as f64).sqrt();
            assert!((row.force_max_abs - peak).abs() <= 1e-14 * peak);
            assert!((row.force_rms - rms).abs() <= 1e-14 * rms);
        }
    }

    #[test]
    fn output_names() {
        let outputs = SweepOutputs::from_names(&["force_rms", "leading_amplitude"]).unwrap();
        assert_eq!(
            outputs,
            SweepOutputs {
                force: true,
                energy: false,
                harmonic: true
            }
        );
        let error = SweepOutputs::from_names(&["force"])
            .unwrap_err()
            .to_string();
        assert!(error.contains("outputs"), "{error}");
        let row = SweepRow {
            force_max_abs: 1.0,
            force_rms: 2.0,
            energy_min: 3.0,
            energy_max: 4.0,
            energy_range: 5.0,
            leading_harmonic: 6.0,
            leading_amplitude: 7.0,
        };
        let values: Vec<f64> = SweepRow::NAMES
            .iter()
            .map(|n| row.get(n).unwrap())
            .collect();
        assert_eq!(values, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        assert_eq!(row.get("cylinders"), None);
    }
}
