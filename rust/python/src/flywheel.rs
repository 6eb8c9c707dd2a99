//! The flywheel's one root search (the core's `size_shaft_inertia`) over steady states solved
//! in Python: the shooting for loads given as callables, which the core cannot call itself.

use multicrank_core as core;
use pyo3::prelude::*;

use crate::error::motion_err;
use crate::error::refused;

/// size_shaft_inertia(delta_at, rest, delta, start) -> float
///
/// The shaft inertia I_w (kg·m²) whose steady state has the coefficient of speed fluctuation
/// `delta` (≥ 1e-9): the core's flywheel search, the one its own flywheels use, over
/// `delta_at(I_w)`, a Python callable that gives δ of the steady state on a shaft of inertia
/// I_w as a finite float ≥ 0, or None where the machine stalls (δ = ∞ to the search). δ must
/// fall as I_w grows. `rest`: mean(J − I_w) (kg·m²); `start` (kg·m², > 0): the estimate to
/// bracket from (the textbook I_w).
///
/// Raises MechanismError for bad input (naming it) or for a `delta` no shaft inertia gives
/// (`parameter` "delta", with the attributes `delta`, `reach` and `closest` as every flywheel
/// of the core sets them); any exception `delta_at` raises, unchanged (it ends the search);
/// MechanismError naming "delta_at" where it returns a NaN, infinite or negative δ.
#[pyfunction]
pub(crate) fn size_shaft_inertia(
    py: Python<'_>,
    delta_at: &Bound<'_, PyAny>,
    rest: f64,
    delta: f64,
    start: f64,
) -> PyResult<f64> {
    // Unlike every other call into the core, this one holds the GIL throughout: each step of
    // the search calls `delta_at`, Python code that needs it, and the search's own arithmetic
    // between those calls (each a whole steady state) is too little to gain from releasing it.
    let mut raised = None;
    let found = core::size_shaft_inertia(
        |inertia| {
            answer(delta_at, inertia).map_err(|error| {
                raised = Some(error);
                // Only a marker that ends the search: `raised` is what reaches the caller.
                core::MechanismError::Empty {
                    parameter: "delta_at",
                }
            })
        },
        rest,
        delta,
        start,
    );
    match raised {
        Some(error) => Err(error),
        None => found.map_err(|error| motion_err(py, error)),
    }
}

/// δ of `delta_at`'s steady state with I_w = `inertia` (kg·m²), `None` for a stall.
fn answer(delta_at: &Bound<'_, PyAny>, inertia: f64) -> PyResult<Option<f64>> {
    let value = delta_at.call1((inertia,))?;
    if value.is_none() {
        return Ok(None);
    }
    let delta: f64 = value.extract()?;
    if delta.is_finite() && delta >= 0.0 {
        Ok(Some(delta))
    } else {
        Err(refused(
            "delta_at",
            format!(
                "delta_at({inertia}) = {delta}: a steady state's δ is a finite float >= 0 \
                 (None where the machine stalls)"
            ),
        ))
    }
}
