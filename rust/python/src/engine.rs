//! One engine of any layout: its U, Q and dQ/dφ over φ, its Fourier coefficients,
//! extrema, leading harmonic and sensitivity to unit errors.

use multicrank_core as core;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::conversion::{filled, named, EngineColumns, OutputSize, PhiArg};
use crate::error::to_py_err;
use crate::evaluation::{evaluation, Evaluation};
use crate::parallel::parallelism;

/// engine_evaluate(quantity, phi, engine, parallel_threshold=None) -> array like phi:
/// "potential_energy", "generalized_force", "force_derivative" (closed form) or
/// "series" (the machine-precision Fourier form) of an engine.
#[pyfunction]
#[pyo3(signature = (quantity, phi, engine, parallel_threshold=None))]
pub(crate) fn engine_evaluate<'py>(
    py: Python<'py>,
    quantity: &str,
    phi: PhiArg<'py>,
    engine: EngineColumns<'py>,
    parallel_threshold: Option<usize>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let evaluation = match evaluation(quantity)? {
        Evaluation::Series(core::SeriesKind::Paper) => {
            return Err(to_py_err(core::MechanismError::InvalidChoice {
                parameter: "quantity",
                value: "\"paper\"".into(),
                allowed: "\"potential_energy\", \"generalized_force\", \"force_derivative\", \
                          \"series\" (\"paper\" is not for an engine)",
            }))
        }
        other => other,
    };
    let (phi, engine) = (phi.slice()?, engine.engine()?);
    let parallelism = parallelism(parallel_threshold);
    filled(
        py,
        OutputSize::of("phi", phi.len()),
        |out| match evaluation {
            Evaluation::Closed(q) => engine.evaluate(q, phi.phi()?, out, parallelism),
            Evaluation::Series(_) => engine.evaluate_series(phi.phi()?, out, parallelism),
        },
    )
}

/// engine_fourier(engine, n_max) -> {"a", "b"}, each of length n_max + 1.
#[pyfunction]
pub(crate) fn engine_fourier<'py>(
    py: Python<'py>,
    engine: EngineColumns<'py>,
    n_max: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let engine = engine.engine()?;
    let (a, b) = py
        .detach(|| engine.fourier_coefficients(n_max))
        .map_err(to_py_err)?;
    named(py, [("a", a), ("b", b)])
}

/// engine_extrema(engine) -> {"min", "min_at", "max", "max_at", "range"} (floats).
#[pyfunction]
pub(crate) fn engine_extrema<'py>(
    py: Python<'py>,
    engine: EngineColumns<'py>,
) -> PyResult<Bound<'py, PyDict>> {
    let engine = engine.engine()?;
    let extrema = py.detach(|| engine.energy_extrema());
    let dict = PyDict::new(py);
    for name in core::EnergyExtrema::NAMES {
        dict.set_item(name, extrema.get(name))?;
    }
    Ok(dict)
}

/// engine_leading_harmonic(engine) -> {"n", "amplitude"}: the largest harmonic of
/// Q_u* (n = 0, amplitude 0 when Q ≡ 0).
#[pyfunction]
pub(crate) fn engine_leading_harmonic<'py>(
    py: Python<'py>,
    engine: EngineColumns<'py>,
) -> PyResult<Bound<'py, PyDict>> {
    let engine = engine.engine()?;
    let (n, amplitude) = py.detach(|| engine.leading_harmonic());
    let dict = PyDict::new(py);
    dict.set_item("n", n)?;
    dict.set_item("amplitude", amplitude)?;
    Ok(dict)
}

/// engine_sensitivity(engine, u1_rel, u2_rel, phase, n_max) -> {"n", "amplitude",
/// "scatter_rms"}: harmonics n = 1 and even n <= n_max, nominal amplitude and the rms
/// of their first-order scatter under independent unit errors.
#[pyfunction]
pub(crate) fn engine_sensitivity<'py>(
    py: Python<'py>,
    engine: EngineColumns<'py>,
    u1_rel: f64,
    u2_rel: f64,
    phase: f64,
    n_max: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let engine = engine.engine()?;
    let errors = core::UnitErrors {
        u1_rel,
        u2_rel,
        phase,
    };
    let rows = py
        .detach(|| engine.harmonic_sensitivity(errors, n_max))
        .map_err(to_py_err)?;
    named(
        py,
        [
            ("n", rows.iter().map(|r| r.n as f64).collect()),
            ("amplitude", rows.iter().map(|r| r.amplitude).collect()),
            ("scatter_rms", rows.iter().map(|r| r.scatter_rms).collect()),
        ],
    )
}
