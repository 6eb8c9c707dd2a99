//! The closed form and the Fourier form over φ for designs of an in-line machine, and
//! the machine's own description (crank phases, dimensionless moments).

use multicrank_core as core;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::{
    designs, filled, named, DimensionlessDesigns, OutputSize, PhiArg, PhysicalArrays,
};
use crate::error::to_py_err;
use crate::parallel::parallelism;

pub(crate) fn series_kind(method: &str) -> PyResult<core::SeriesKind> {
    match method {
        "exact" | "series" => Ok(core::SeriesKind::Exact),
        "paper" => Ok(core::SeriesKind::Paper),
        other => Err(to_py_err(core::MechanismError::InvalidChoice {
            parameter: "method",
            value: format!("{other:?}"),
            allowed: "\"exact\", \"series\", \"paper\"",
        })),
    }
}

/// What `evaluate` and `engine_evaluate` compute: a closed-form quantity, or Q_u* from a
/// Fourier form.
pub(crate) enum Evaluation {
    Closed(core::Quantity),
    Series(core::SeriesKind),
}

pub(crate) fn evaluation(quantity: &str) -> PyResult<Evaluation> {
    Ok(match quantity {
        "potential_energy" => Evaluation::Closed(core::Quantity::PotentialEnergy),
        "generalized_force" => Evaluation::Closed(core::Quantity::GeneralizedForce),
        "force_derivative" => Evaluation::Closed(core::Quantity::ForceDerivative),
        "series" | "paper" => Evaluation::Series(series_kind(quantity)?),
        other => {
            return Err(to_py_err(core::MechanismError::InvalidChoice {
                parameter: "quantity",
                value: format!("{other:?}"),
                allowed: "\"potential_energy\", \"generalized_force\", \"force_derivative\", \
                          \"series\", \"paper\"",
            }))
        }
    })
}

/// crank_phases(cranks, strokes, acting) -> the phases α_j (rad) of a regular machine.
#[pyfunction]
pub(crate) fn crank_phases<'py>(
    py: Python<'py>,
    cranks: i64,
    strokes: i64,
    acting: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let strokes = core::Strokes::from_count(strokes).map_err(to_py_err)?;
    let acting = core::Acting::from_name(acting).map_err(to_py_err)?;
    let phases = core::crank_phases(cranks, strokes, acting).map_err(to_py_err)?;
    Ok(phases.into_pyarray(py))
}

/// evaluate(quantity, phi, design, phases, parallel_threshold=None) -> flat array of
/// len(design) * len(phi), design-major: "potential_energy", "generalized_force",
/// "force_derivative" (closed form), "series" (the machine-precision Fourier form) or
/// "paper" (eq. 16).
#[pyfunction]
#[pyo3(signature = (quantity, phi, design, phases, parallel_threshold=None))]
pub(crate) fn evaluate<'py>(
    py: Python<'py>,
    quantity: &str,
    phi: PhiArg<'py>,
    design: DimensionlessDesigns<'py>,
    phases: PyReadonlyArray1<'py, f64>,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let evaluation = evaluation(quantity)?;
    let (phi, columns, alphas) = (phi.slice()?, design.slices()?, phases.as_slice()?);
    let parallelism = parallelism(parallel_threshold);
    let size = OutputSize::of("phi", phi.len()).times(columns[0].len());
    filled(py, size, |out| {
        let (phi, phases, designs) = (phi.phi()?, core::Phases::new(alphas)?, designs(columns)?);
        match evaluation {
            Evaluation::Closed(q) => core::evaluate(q, &designs, &phases, phi, out, parallelism),
            Evaluation::Series(kind) => {
                let series = core::build_series(kind, &designs, alphas, parallelism);
                core::evaluate_series_or_exact(&series, &designs, &phases, phi, out, parallelism)
            }
        }
    })
}

/// dimensionless_moments(units) -> {"u1", "u2"}: `units` holds equal-length arrays of
/// every `PhysicalColumns` field (see `multicrank_core::PhysicalUnit::dimensionless_moments`).
#[pyfunction]
pub(crate) fn dimensionless_moments<'py>(
    py: Python<'py>,
    units: PhysicalArrays<'py>,
) -> PyResult<Bound<'py, PyDict>> {
    let columns = units.columns()?;
    let (u1, u2) = py
        .detach(|| core::dimensionless_moments(&columns))
        .map_err(to_py_err)?;
    named(py, [("u1", u1), ("u2", u2)])
}
