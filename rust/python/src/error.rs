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
     and its allowed range."
);

/// A core error as a `MechanismError` with the core's message.
pub(crate) fn to_py_err(error: core::MechanismError) -> PyErr {
    MechanismError::new_err(error.to_string())
}
