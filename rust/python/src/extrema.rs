//! The extrema of U_w* over a revolution, per design.

use multicrank_core as core;
use numpy::PyReadonlyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::{designs, record_columns, DimensionlessDesigns};
use crate::error::to_py_err;
use crate::parallel::parallelism;

/// energy_extrema(design, phases, parallel_threshold=None) -> {"min", "min_at", "max",
/// "max_at", "range"}: the exact extrema of U_w* over one revolution, per design.
#[pyfunction]
#[pyo3(signature = (design, phases, parallel_threshold=None))]
pub(crate) fn energy_extrema<'py>(
    py: Python<'py>,
    design: DimensionlessDesigns<'py>,
    phases: PyReadonlyArray1<'py, f64>,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (columns, alphas) = (design.slices()?, phases.as_slice()?);
    let parallelism = parallelism(parallel_threshold);
    let extrema = py
        .detach(|| -> core::Result<Vec<core::EnergyExtrema>> {
            let (phases, designs) = (core::Phases::new(alphas)?, designs(columns)?);
            let series = core::build_series(core::SeriesKind::Exact, &designs, alphas, parallelism);
            Ok(core::all_energy_extrema(
                &designs,
                &phases,
                &series,
                parallelism,
            ))
        })
        .map_err(to_py_err)?;
    record_columns(
        py,
        &extrema,
        &core::EnergyExtrema::NAMES,
        core::EnergyExtrema::get,
    )
}
