//! The one Python exception of the module, and the core's errors as it.

use multicrank_core as core;
use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

create_exception!(
    multicrank,
    MechanismError,
    PyValueError,
    "Invalid mechanism description or evaluation request; the message names the parameter \
     and its allowed range, and the attribute ``parameter`` names it as data (the public \
     name of the parameter the error is about, e.g. ``\"crank_ratio\"``; None where the \
     error names none)."
);

/// A core error as a `MechanismError` with the core's message and its parameter's name as
/// the exception's `parameter` attribute; a design row's error also carries its `row`
/// (from 0) and `reason`, its own error's message without the row.
pub(crate) fn to_py_err(error: core::MechanismError) -> PyErr {
    let parameter = error.parameter();
    let row = match &error {
        core::MechanismError::InRow { row, error } => Some((*row, error.to_string())),
        _ => None,
    };
    let err = MechanismError::new_err(error.to_string());
    Python::attach(|py| {
        let value = err.value(py);
        let mut set = value.setattr("parameter", parameter);
        if let Some((row, reason)) = row {
            set = set
                .and_then(|()| value.setattr("row", row))
                .and_then(|()| value.setattr("reason", reason));
        }
        match set {
            Ok(()) => err,
            Err(failed) => failed,
        }
    })
}

/// A `MechanismError` with `message`, about `parameter` (its `parameter` attribute): a
/// refusal of this module's own, or a core error re-worded with its context.
pub(crate) fn refused(parameter: &'static str, message: String) -> PyErr {
    let err = MechanismError::new_err(message);
    Python::attach(|py| match err.value(py).setattr("parameter", parameter) {
        Ok(()) => err,
        Err(failed) => failed,
    })
}

/// The exception class's own `parameter` (None), so that every instance has the attribute,
/// those made in Python without one included.
pub(crate) fn add_default_parameter(py: Python<'_>) -> PyResult<()> {
    py.get_type::<MechanismError>()
        .setattr("parameter", py.None())
}

/// The core's error as a `MechanismError`, carrying what Python words it from as attributes
/// of the exception: a stall its `angle` (rad), `omega_mean` and `min_omega` (rad/s, None
/// where no speed runs); an unreachable flywheel target its `delta`, `reach` ("never_falls",
/// "massless" or "stalls") and `closest` (the δ nearest to it that the machine reaches, NaN
/// where none is known); a bad design its `row` (from 0) and `reason` (as `to_py_err` sets
/// them), with the attributes of its own error beside. Every one carries its `parameter`.
pub(crate) fn motion_err(py: Python<'_>, error: core::MechanismError) -> PyErr {
    let mut inner = &error;
    if let core::MechanismError::InRow { error, .. } = &error {
        inner = error;
    }
    let stall = match *inner {
        core::MechanismError::Stall {
            angle,
            omega_mean,
            min_omega,
        } => Some((angle, omega_mean, min_omega)),
        _ => None,
    };
    let unreachable = match *inner {
        core::MechanismError::Unreachable {
            delta,
            reach,
            closest,
        } => Some((delta, reach.name(), closest)),
        _ => None,
    };
    let err = to_py_err(error);
    let value = err.value(py);
    let mut set = Ok(());
    if let Some((angle, omega_mean, min_omega)) = stall {
        set = set
            .and_then(|()| value.setattr("angle", angle))
            .and_then(|()| value.setattr("omega_mean", omega_mean))
            .and_then(|()| value.setattr("min_omega", min_omega));
    }
    if let Some((delta, reach, closest)) = unreachable {
        set = set
            .and_then(|()| value.setattr("delta", delta))
            .and_then(|()| value.setattr("reach", reach))
            .and_then(|()| value.setattr("closest", closest));
    }
    match set {
        Ok(()) => err,
        Err(failed) => failed,
    }
}
