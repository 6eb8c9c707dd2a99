//! The one error type of the core. Messages use the public parameter names of the
//! Python API (`crank_ratio`, `inclination`, ...) so that a user sees the name they typed.

use std::fmt;

/// Why a mechanism description or an evaluation request was rejected.
#[derive(Debug, Clone, PartialEq)]
pub enum MechanismError {
    /// A value lies outside its allowed range (NaN and ±inf included).
    OutOfRange {
        parameter: &'static str,
        value: f64,
        allowed: &'static str,
    },
    /// An integer count or a choice outside its allowed set.
    InvalidChoice {
        parameter: &'static str,
        value: String,
        allowed: &'static str,
    },
    /// A list that must not be empty was empty.
    Empty { parameter: &'static str },
    /// Two buffers that must agree in length do not.
    LengthMismatch {
        parameter: &'static str,
        expected: usize,
        found: usize,
    },
}

impl fmt::Display for MechanismError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::OutOfRange {
                parameter,
                value,
                allowed,
            } => write!(
                f,
                "{parameter} = {value} is out of range; allowed: {allowed}"
            ),
            Self::InvalidChoice {
                parameter,
                value,
                allowed,
            } => write!(
                f,
                "{parameter} = {value} is not allowed; allowed: {allowed}"
            ),
            Self::Empty { parameter } => write!(f, "{parameter} must not be empty"),
            Self::LengthMismatch {
                parameter,
                expected,
                found,
            } => write!(f, "{parameter} has length {found}, expected {expected}"),
        }
    }
}

impl std::error::Error for MechanismError {}

pub type Result<T> = std::result::Result<T, MechanismError>;

/// `Ok(value)` if `value` is finite and `ok(value)`, else an `OutOfRange` error.
pub(crate) fn check(
    parameter: &'static str,
    value: f64,
    allowed: &'static str,
    ok: impl Fn(f64) -> bool,
) -> Result<f64> {
    if value.is_finite() && ok(value) {
        Ok(value)
    } else {
        Err(MechanismError::OutOfRange {
            parameter,
            value,
            allowed,
        })
    }
}

/// `Ok(())` if a buffer has the length it must have, else a `LengthMismatch` naming it.
pub(crate) fn check_length(parameter: &'static str, expected: usize, found: usize) -> Result<()> {
    if expected == found {
        Ok(())
    } else {
        Err(MechanismError::LengthMismatch {
            parameter,
            expected,
            found,
        })
    }
}
