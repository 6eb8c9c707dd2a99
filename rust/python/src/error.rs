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
