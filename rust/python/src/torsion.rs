//! The shaft's torsional chain: its natural modes (`chain_modes`), found by the core with the
//! GIL released.

use multicrank_core as core;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::error::to_py_err;

/// ω (count,) and the shapes (nodes, count).
type ModeArrays<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>);

/// chain_modes(stiffness, inertia, count) -> (omega, shapes): the lowest `count` elastic
/// modes of the free–free chain of node inertias `inertia` (J_i, kg·m², n ≥ 2) joined by
/// section stiffnesses `stiffness` (k_i, N·m/rad, n − 1): ω_m (rad/s, increasing, shape
/// (count,)) and the shapes (n, count), each scaled to a largest magnitude of 1, positive at
/// the first node within 1e-9 of it. 1 ≤ count ≤ n − 1; bad values refused by name.
#[pyfunction]
pub(crate) fn chain_modes<'py>(
    py: Python<'py>,
    stiffness: PyReadonlyArray1<'py, f64>,
    inertia: PyReadonlyArray1<'py, f64>,
    count: usize,
) -> PyResult<ModeArrays<'py>> {
    let (stiffness, inertia) = (stiffness.as_slice()?, inertia.as_slice()?);
    let modes = py
        .detach(|| core::Chain::new(inertia, stiffness)?.modes(count))
        .map_err(to_py_err)?;
    let nodes = modes.nodes();
    let (omega, shapes) = modes.into_parts();
    let shapes = shapes.into_pyarray(py).reshape([nodes, count])?;
    Ok((omega.into_pyarray(py), shapes))
}
