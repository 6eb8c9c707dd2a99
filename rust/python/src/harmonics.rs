//! The coefficients Λ_n, which harmonics survive a crank set, and the Fourier
//! coefficients of Q_u*.

use multicrank_core as core;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::{designs, named, DimensionlessDesigns};
use crate::error::to_py_err;
use crate::parallel::parallelism;

/// lambda_coefficients(crank_ratio, n_max, method, parallel_threshold=None) -> flat
/// (len(crank_ratio) * (n_max + 1)), method "exact" or "paper".
#[pyfunction]
#[pyo3(signature = (crank_ratio, n_max, method, parallel_threshold=None))]
pub(crate) fn lambda_coefficients<'py>(
    py: Python<'py>,
    crank_ratio: PyReadonlyArray1<'py, f64>,
    n_max: usize,
    method: &str,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let paper = match method {
        "exact" => false,
        "paper" => true,
        other => {
            return Err(to_py_err(core::MechanismError::InvalidChoice {
                parameter: "method",
                value: format!("{other:?}"),
                allowed: "\"exact\", \"paper\"",
            }))
        }
    };
    let lambdas = crank_ratio.as_slice()?;
    let parallelism = parallelism(parallel_threshold);
    let table = py
        .detach(|| core::lambda_table(paper, lambdas, n_max, parallelism))
        .map_err(to_py_err)?;
    Ok(table.into_pyarray(py))
}

/// paper_coefficient(i, j) -> (numerator, denominator) of [λ^(2j+1)] Λ_(2i), exact.
#[pyfunction]
pub(crate) fn paper_coefficient(i: u32, j: u32) -> PyResult<(i128, u128)> {
    core::paper_coefficient(i, j).map_err(to_py_err)
}

/// surviving_harmonics(cranks, strokes, acting, n_max) -> the n <= n_max that survive,
/// as a uint64 array (its size checked in the core before it is made).
#[pyfunction]
pub(crate) fn surviving_harmonics<'py>(
    py: Python<'py>,
    cranks: u64,
    strokes: i64,
    acting: &str,
    n_max: u64,
) -> PyResult<Bound<'py, PyArray1<u64>>> {
    let strokes = core::Strokes::from_count(strokes).map_err(to_py_err)?;
    let acting = core::Acting::from_name(acting).map_err(to_py_err)?;
    let harmonics = py
        .detach(|| core::surviving_harmonics(cranks, strokes, acting, n_max))
        .map_err(to_py_err)?;
    Ok(harmonics.into_pyarray(py))
}

/// fourier_coefficients(design, phases, n_max, parallel_threshold=None) -> {"a", "b"},
/// each flat of len(design) * (n_max + 1).
#[pyfunction]
#[pyo3(signature = (design, phases, n_max, parallel_threshold=None))]
pub(crate) fn fourier_coefficients<'py>(
    py: Python<'py>,
    design: DimensionlessDesigns<'py>,
    phases: PyReadonlyArray1<'py, f64>,
    n_max: usize,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (columns, alphas) = (design.slices()?, phases.as_slice()?);
    let parallelism = parallelism(parallel_threshold);
    let (a, b) = py
        .detach(|| core::fourier_table(&designs(columns)?, alphas, n_max, parallelism))
        .map_err(to_py_err)?;
    named(py, [("a", a), ("b", b)])
}
