//! The results of the native steady state and flywheel as Python sees them: typed, frozen,
//! SI units, built in one conversion place (`steady_result`, `FlywheelResult::from`).

use multicrank_core as core;

use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::error::motion_err;

type Array = Option<Py<PyArray1<f64>>>;

/// Whether two optional arrays hold the same doubles (or both are absent).
fn same_array(py: Python<'_>, a: &Array, b: &Array) -> PyResult<bool> {
    match (a, b) {
        (None, None) => Ok(true),
        (Some(a), Some(b)) => {
            Ok(a.bind(py).readonly().as_slice()? == b.bind(py).readonly().as_slice()?)
        }
        _ => Ok(false),
    }
}

/// A steady state as the core found it (SI units, immutable): its numbers, and the curves
/// and arrays at the angles asked for (None where none were asked); how the solve ended
/// (`status`: 0 converged, SciPy's success — a stall is an error, never a result), in words
/// (`message`), and its evaluation counts (`nfev`: of the function whose root is found, the
/// mean speed as a function of the energy margin; 0 for the square law's closed form; `nit`:
/// of those, Brent's method's). Equal to another with the same numbers and arrays.
#[pyclass(frozen, get_all, name = "SteadyResult", module = "multicrank._native")]
pub(crate) struct SteadyResult {
    omega_mean: f64,
    period: f64,
    omega_max: f64,
    omega_min: f64,
    phi_max: f64,
    phi_min: f64,
    energy_at_zero: f64,
    mean_load_torque: f64,
    delta: f64,
    delta_midrange: f64,
    delta_without_gravity: f64,
    delta_coasting: f64,
    status: i32,
    message: &'static str,
    nfev: usize,
    nit: usize,
    omega: Array,
    time: Array,
    reduced_inertia: Array,
    reduced_inertia_slope: Array,
    gas_torque: Array,
    gravity_torque: Array,
    /// The solve kept for its curves (the "balance" load's; None for other routes).
    solved: Option<Py<SolvedSteady>>,
}

/// A steady state's solve under the "balance" load, kept so that its curves can be asked
/// for later without solving again (`SteadyResult.solved`).
#[pyclass(frozen, name = "SolvedSteadyState", module = "multicrank._native")]
pub(crate) struct SolvedSteady {
    core: core::SolvedSteadyState,
}

#[pymethods]
impl SolvedSteady {
    /// curves(phi) -> (omega, time): ω (rad/s) and t (s from φ = 0) at `phi` (rad, each in
    /// [0, Φ]), the doubles steady_state gives with `phi`, without a second solve.
    fn curves<'py>(
        &self,
        py: Python<'py>,
        phi: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<[Bound<'py, PyArray1<f64>>; 2]> {
        let angles = phi.as_slice()?;
        let (omega, time) = py
            .detach(|| self.core.curves(angles))
            .map_err(|error| motion_err(py, error))?;
        Ok([omega.into_pyarray(py), time.into_pyarray(py)])
    }
}

impl SteadyResult {
    fn numbers(&self) -> [f64; 12] {
        [
            self.omega_mean,
            self.period,
            self.omega_max,
            self.omega_min,
            self.phi_max,
            self.phi_min,
            self.energy_at_zero,
            self.mean_load_torque,
            self.delta,
            self.delta_midrange,
            self.delta_without_gravity,
            self.delta_coasting,
        ]
    }

    fn arrays(&self) -> [&Array; 6] {
        [
            &self.omega,
            &self.time,
            &self.reduced_inertia,
            &self.reduced_inertia_slope,
            &self.gas_torque,
            &self.gravity_torque,
        ]
    }
}

#[pymethods]
impl SteadyResult {
    fn __eq__(&self, py: Python<'_>, other: PyRef<'_, Self>) -> PyResult<bool> {
        if self.numbers() != other.numbers() {
            return Ok(false);
        }
        for (a, b) in self.arrays().into_iter().zip(other.arrays()) {
            if !same_array(py, a, b)? {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// solution() -> dict: omega_mean, omega_max, omega_min (rad/s), phi_max, phi_min (rad),
    /// period (s), mean_load_torque (N·m), status, message, nfev and nit by name, in one
    /// call (eleven attribute reads were ~1.5 µs of a warm steady state's ~20).
    fn solution<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let found = PyDict::new(py);
        for (name, value) in [
            ("omega_mean", self.omega_mean),
            ("omega_max", self.omega_max),
            ("omega_min", self.omega_min),
            ("phi_max", self.phi_max),
            ("phi_min", self.phi_min),
            ("period", self.period),
            ("mean_load_torque", self.mean_load_torque),
        ] {
            found.set_item(name, value)?;
        }
        found.set_item("status", self.status)?;
        found.set_item("message", self.message)?;
        found.set_item("nfev", self.nfev)?;
        found.set_item("nit", self.nit)?;
        Ok(found)
    }

    fn __repr__(&self) -> String {
        format!(
            "SteadyResult(omega_mean={}, delta={}, delta_without_gravity={}, delta_coasting={})",
            self.omega_mean, self.delta, self.delta_without_gravity, self.delta_coasting
        )
    }
}

/// The shaft inertia sized for a coefficient of speed fluctuation (SI units, immutable);
/// equal to another with the same numbers.
#[pyclass(
    frozen,
    eq,
    get_all,
    name = "FlywheelResult",
    module = "multicrank._native"
)]
#[derive(PartialEq)]
pub(crate) struct FlywheelResult {
    shaft_inertia: f64,
    shaft_inertia_without_gravity: f64,
    textbook: f64,
    textbook_error: f64,
    energy_swing: f64,
    delta: f64,
    /// The mean speed ω_m (rad/s).
    omega_mean: f64,
}

#[pymethods]
impl FlywheelResult {
    fn __repr__(&self) -> String {
        format!(
            "FlywheelResult(shaft_inertia={}, shaft_inertia_without_gravity={}, textbook={}, delta={}, omega_mean={})",
            self.shaft_inertia, self.shaft_inertia_without_gravity, self.textbook, self.delta, self.omega_mean
        )
    }
}

/// The one conversion of the core's steady state (and its arrays, where asked) to Python.
pub(crate) fn steady_result(
    py: Python<'_>,
    found: core::SteadyCurves,
    curves: bool,
    arrays: Option<core::CycleArrays>,
    solved: Option<core::SolvedSteadyState>,
) -> PyResult<SteadyResult> {
    let s = found.state;
    let array = |values: Vec<f64>| Some(values.into_pyarray(py).unbind());
    let (omega, time) = if curves {
        (array(found.omega), array(found.time))
    } else {
        (None, None)
    };
    let (reduced_inertia, reduced_inertia_slope, gas_torque, gravity_torque) = match arrays {
        Some(a) => (
            array(a.reduced_inertia),
            array(a.reduced_inertia_slope),
            array(a.gas_torque),
            array(a.gravity_torque),
        ),
        None => (None, None, None, None),
    };
    let solved = solved
        .map(|core| Py::new(py, SolvedSteady { core }))
        .transpose()?;
    Ok(SteadyResult {
        omega_mean: s.omega_mean,
        period: s.period,
        omega_max: s.omega_max,
        omega_min: s.omega_min,
        phi_max: s.phi_max,
        phi_min: s.phi_min,
        energy_at_zero: s.energy_at_zero,
        mean_load_torque: s.mean_load_torque,
        delta: s.delta,
        delta_midrange: s.delta_midrange,
        delta_without_gravity: s.delta_without_gravity,
        delta_coasting: s.delta_coasting,
        status: found.status,
        message: found.message,
        nfev: found.nfev,
        nit: found.nit,
        omega,
        time,
        reduced_inertia,
        reduced_inertia_slope,
        gas_torque,
        gravity_torque,
        solved,
    })
}

impl From<core::FlywheelInertia> for FlywheelResult {
    fn from(f: core::FlywheelInertia) -> Self {
        Self {
            shaft_inertia: f.shaft_inertia,
            shaft_inertia_without_gravity: f.shaft_inertia_without_gravity,
            textbook: f.textbook,
            textbook_error: f.textbook_error,
            energy_swing: f.energy_swing,
            delta: f.delta,
            omega_mean: f.omega_mean,
        }
    }
}
