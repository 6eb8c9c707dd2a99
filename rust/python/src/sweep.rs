//! Sweeps: many designs × phase sets, or many engines, to one row of outputs each.

use multicrank_core as core;
use numpy::PyReadonlyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::{designs, record_columns, DimensionlessDesigns, EngineColumns};
use crate::error::to_py_err;
use crate::parallel::parallelism;

/// The output names a sweep was asked for, as the core knows them.
pub(crate) fn sweep_names(outputs: &[String]) -> PyResult<(core::SweepOutputs, Vec<&'static str>)> {
    let groups = core::SweepOutputs::from_names(outputs).map_err(to_py_err)?;
    let names = core::SweepRow::NAMES
        .into_iter()
        .filter(|name| outputs.iter().any(|o| o == name))
        .collect();
    Ok((groups, names))
}

/// sweep(design, phase_set, phase_sets, phi, outputs, parallel_threshold=None) ->
/// {output: array}, one value per design: design i has the crank phases
/// phase_sets[phase_set[i]]; `outputs` are names from SWEEP_OUTPUTS.
#[pyfunction]
#[pyo3(signature = (design, phase_set, phase_sets, phi, outputs, parallel_threshold=None))]
pub(crate) fn sweep<'py>(
    py: Python<'py>,
    design: DimensionlessDesigns<'py>,
    phase_set: PyReadonlyArray1<'py, u32>,
    phase_sets: Vec<PyReadonlyArray1<'py, f64>>,
    phi: PyReadonlyArray1<'py, f64>,
    outputs: Vec<String>,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (groups, names) = sweep_names(&outputs)?;
    let (columns, phase_set, phi) = (design.slices()?, phase_set.as_slice()?, phi.as_slice()?);
    let sets = phase_sets
        .iter()
        .map(|set| Ok(set.as_slice()?.to_vec()))
        .collect::<PyResult<Vec<_>>>()?;
    let parallelism = parallelism(parallel_threshold);
    let rows = py
        .detach(|| -> core::Result<Vec<core::SweepRow>> {
            let designs = designs(columns)?;
            let max_ratio = designs.iter().map(|d| d.crank_ratio).fold(0.0, f64::max);
            let table = core::PhaseSetTable::new(&sets, max_ratio)?;
            core::sweep(&designs, phase_set, &table, phi, groups, parallelism)
        })
        .map_err(to_py_err)?;
    record_columns(py, &rows, &names, core::SweepRow::get)
}

/// sweep_engines(engines, phi, outputs, parallel_threshold=None) -> {output: array},
/// one value per engine (a list of engine dicts).
#[pyfunction]
#[pyo3(signature = (engines, phi, outputs, parallel_threshold=None))]
pub(crate) fn sweep_engines<'py>(
    py: Python<'py>,
    engines: Vec<EngineColumns<'py>>,
    phi: PyReadonlyArray1<'py, f64>,
    outputs: Vec<String>,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (groups, names) = sweep_names(&outputs)?;
    let engines = engines
        .iter()
        .map(EngineColumns::engine)
        .collect::<PyResult<Vec<_>>>()?;
    let phi = phi.as_slice()?;
    let parallelism = parallelism(parallel_threshold);
    let rows = py
        .detach(|| core::sweep_engines(&engines, phi, groups, parallelism))
        .map_err(to_py_err)?;
    record_columns(py, &rows, &names, core::SweepRow::get)
}
