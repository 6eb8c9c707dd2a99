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
    /// A size asked for (through `parameter`, whose value was `value`) would need more
    /// memory than can be allocated: `elements` items of `item_bytes` bytes each.
    TooLarge {
        parameter: &'static str,
        value: String,
        elements: u128,
        item_bytes: usize,
    },
    /// The machine cannot keep the mean speed `omega_mean` (rad/s) asked for: its speed
    /// would fall below the stall limit (or to zero) near the crank angle `angle` (rad);
    /// `min_omega`, where found, is the lowest mean speed (rad/s) that runs.
    Stall {
        angle: f64,
        omega_mean: f64,
        min_omega: Option<f64>,
    },
    /// No shaft inertia gives the coefficient of speed fluctuation `delta` asked for:
    /// `reach` says why, and `closest` is the δ nearest to it that the machine reaches (the
    /// largest δ that runs, or δ of a massless shaft; NaN where none is known).
    Unreachable {
        delta: f64,
        reach: Reach,
        closest: f64,
    },
    /// A value that breaks a rule about several values at once (a bearing at a throw, a
    /// throw outside the bearings): `message` says which values and why.
    Refused {
        parameter: &'static str,
        message: String,
    },
    /// Design `row` of a batch has a bad value: `error` names the parameter.
    InRow {
        row: usize,
        error: Box<MechanismError>,
    },
}

/// Why no shaft inertia gives a coefficient of speed fluctuation
/// ([`MechanismError::Unreachable`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reach {
    /// δ never falls that low, however heavy the shaft.
    NeverFalls,
    /// Even a massless shaft keeps δ below it: the rods' and pistons' own inertia limits
    /// the fluctuation.
    Massless,
    /// The machine stalls (ω_min < min_speed_ratio·ω_m) before its fluctuation grows that
    /// large.
    Stalls,
}

impl Reach {
    /// Its name, as the Python exception's `reach` attribute carries it.
    pub fn name(self) -> &'static str {
        match self {
            Self::NeverFalls => "never_falls",
            Self::Massless => "massless",
            Self::Stalls => "stalls",
        }
    }
}

impl MechanismError {
    /// The public name of the parameter the error is about, as its message names it: the
    /// speed `omega_mean` of a stall, `delta` of an unreachable flywheel target, and for a
    /// design row its own error's parameter. None for an error that names no parameter
    /// (no variant today).
    pub fn parameter(&self) -> Option<&'static str> {
        match self {
            Self::OutOfRange { parameter, .. }
            | Self::InvalidChoice { parameter, .. }
            | Self::Empty { parameter }
            | Self::LengthMismatch { parameter, .. }
            | Self::TooLarge { parameter, .. }
            | Self::Refused { parameter, .. } => Some(parameter),
            Self::Stall { .. } => Some("omega_mean"),
            Self::Unreachable { .. } => Some("delta"),
            Self::InRow { error, .. } => error.parameter(),
        }
    }
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
            Self::TooLarge {
                parameter,
                value,
                elements,
                item_bytes,
            } => write!(
                f,
                "{parameter} = {value} asks for {elements} values ({} bytes), more than can \
                 be allocated",
                elements.saturating_mul(*item_bytes as u128)
            ),
            Self::Stall {
                angle,
                omega_mean,
                min_omega,
            } => {
                write!(
                    f,
                    "the machine stalls at omega_mean = {omega_mean} rad/s: it would crawl over \
                     its dead point near phi = {angle} rad ({:.4} deg)",
                    angle.to_degrees()
                )?;
                match min_omega {
                    Some(min_omega) => {
                        write!(
                            f,
                            "; the lowest mean speed that runs is min_omega = {min_omega} rad/s"
                        )
                    }
                    None => Ok(()),
                }
            }
            Self::Unreachable {
                delta,
                reach,
                closest,
            } => match reach {
                Reach::NeverFalls => write!(
                    f,
                    "delta = {delta} is not reached by any shaft_inertia (δ never falls that low)"
                ),
                Reach::Massless => write!(
                    f,
                    "delta = {delta} is unreachable: even a massless shaft keeps δ below it \
                     (about {closest:.4e}: the rods' and pistons' own inertia limits the \
                     fluctuation)"
                ),
                Reach::Stalls => write!(
                    f,
                    "delta = {delta} is unreachable at this speed: the machine stalls \
                     (ω_min < min_speed_ratio·ω_m) before its fluctuation grows that large; the \
                     largest δ that runs is about {closest:.4e}"
                ),
            },
            Self::Refused { message, .. } => f.write_str(message),
            Self::InRow { row, error } => write!(f, "design {row}: {error}"),
        }
    }
}

impl std::error::Error for MechanismError {}

pub type Result<T> = std::result::Result<T, MechanismError>;

/// `x` as a message shows a length or a position: six significant digits, trailing zeros
/// dropped, exponent form beyond 10⁶ and below 10⁻⁴ (`0.3`, `1e+30`, `nan`): the form of the
/// Python API's own messages (its `:g`), so that one rule words the same number alike
/// wherever it is checked.
pub(crate) fn short(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "nan".into()
        } else if x > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    if x == 0.0 {
        return if x.is_sign_negative() {
            "-0".into()
        } else {
            "0".into()
        };
    }
    // Rounded to six significant digits first: the exponent is that of the rounded value.
    let scientific = format!("{x:.5e}");
    let (mantissa, exponent) = scientific.split_once('e').unwrap_or((&scientific, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let trim = |digits: String| {
        if digits.contains('.') {
            digits
                .trim_end_matches('0')
                .trim_end_matches('.')
                .to_string()
        } else {
            digits
        }
    };
    if (-4..6).contains(&exponent) {
        let decimals = (5 - exponent).max(0) as usize;
        trim(format!("{x:.decimals$}"))
    } else {
        let sign = if exponent < 0 { '-' } else { '+' };
        format!("{}e{sign}{:02}", trim(mantissa.to_string()), exponent.abs())
    }
}

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

/// `Ok(())` if every value is finite, else the [`check`] error of the first that is not:
/// all tested in one pass without a branch a value (a check a value, its branch and its
/// error's making, was half of a V12's new native machine on its 6·10³ pressure
/// coefficients), each checked alone only to name the one.
pub(crate) fn check_finite(
    parameter: &'static str,
    values: &[f64],
    allowed: &'static str,
) -> Result<()> {
    if values.iter().fold(true, |all, v| all & v.is_finite()) {
        return Ok(());
    }
    for &value in values {
        check(parameter, value, allowed, |_| true)?;
    }
    Ok(())
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

/// `Ok(())` if a buffer holds `rows` × `cols` values, else a `LengthMismatch` naming it (the
/// product formed without overflow: a wrapped product could match a wrong buffer).
pub(crate) fn check_rows_length(
    parameter: &'static str,
    rows: usize,
    cols: usize,
    found: usize,
) -> Result<()> {
    match rows.checked_mul(cols) {
        Some(expected) => check_length(parameter, expected, found),
        None => Err(MechanismError::TooLarge {
            parameter,
            value: format!("{rows} x {cols}"),
            elements: rows as u128 * cols as u128,
            item_bytes: std::mem::size_of::<f64>(),
        }),
    }
}

/// An empty vector with room for `len` items, or `TooLarge` naming `parameter` (whose value
/// was `value`) when that much memory cannot be had. `len` is a `u128` so that a size made
/// of user integers is formed without overflow and refused here, not wrapped or aborted on.
pub(crate) fn try_with_capacity<T>(
    parameter: &'static str,
    value: impl fmt::Display,
    len: u128,
) -> Result<Vec<T>> {
    let item_bytes = std::mem::size_of::<T>().max(1);
    let too_large = || MechanismError::TooLarge {
        parameter,
        value: value.to_string(),
        elements: len,
        item_bytes,
    };
    // A Rust allocation holds at most isize::MAX bytes.
    if len > (isize::MAX as u128) / item_bytes as u128 {
        return Err(too_large());
    }
    let mut vec = Vec::new();
    vec.try_reserve_exact(len as usize)
        .map_err(|_| too_large())?;
    Ok(vec)
}

/// `len` copies of `item`, or `TooLarge` as `try_with_capacity`.
pub(crate) fn try_filled<T: Clone>(
    parameter: &'static str,
    value: impl fmt::Display,
    len: u128,
    item: T,
) -> Result<Vec<T>> {
    let mut vec = try_with_capacity(parameter, value, len)?;
    vec.resize(len as usize, item);
    Ok(vec)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_error_names_its_parameter() {
        let range = MechanismError::OutOfRange {
            parameter: "crank_ratio",
            value: 2.0,
            allowed: "0 <= crank_ratio < 1",
        };
        assert_eq!(range.parameter(), Some("crank_ratio"));
        let choice = MechanismError::InvalidChoice {
            parameter: "acting",
            value: "triple".into(),
            allowed: "single, double",
        };
        assert_eq!(choice.parameter(), Some("acting"));
        assert_eq!(
            MechanismError::Empty {
                parameter: "phases"
            }
            .parameter(),
            Some("phases")
        );
        let length = MechanismError::LengthMismatch {
            parameter: "bore",
            expected: 2,
            found: 3,
        };
        assert_eq!(length.parameter(), Some("bore"));
        let large = MechanismError::TooLarge {
            parameter: "phi",
            value: "1e20".into(),
            elements: 1 << 70,
            item_bytes: 8,
        };
        assert_eq!(large.parameter(), Some("phi"));
        let stall = MechanismError::Stall {
            angle: 1.0,
            omega_mean: 2.0,
            min_omega: None,
        };
        assert_eq!(stall.parameter(), Some("omega_mean"));
        let unreachable = MechanismError::Unreachable {
            delta: 1e-9,
            reach: Reach::NeverFalls,
            closest: f64::NAN,
        };
        assert_eq!(unreachable.parameter(), Some("delta"));
        // A design row's error is its own error's, however deep.
        let row = MechanismError::InRow {
            row: 3,
            error: Box::new(MechanismError::InRow {
                row: 1,
                error: Box::new(length),
            }),
        };
        assert_eq!(row.parameter(), Some("bore"));
        let refused = MechanismError::Refused {
            parameter: "main_bearings",
            message: "main_bearings: a throw is overhung".into(),
        };
        assert_eq!(refused.parameter(), Some("main_bearings"));
        assert_eq!(refused.to_string(), "main_bearings: a throw is overhung");
    }

    #[test]
    fn short_numbers_read_as_the_python_api_writes_them() {
        for (x, words) in [
            (0.1, "0.1"),
            (0.3 + 1e-15, "0.3"),
            (0.0, "0"),
            (-2.5, "-2.5"),
            (1e30, "1e+30"),
            (123456.0, "123456"),
            (1234567.0, "1.23457e+06"),
            (0.0001, "0.0001"),
            (0.00001234, "1.234e-05"),
            (999999.5, "1e+06"),
            (f64::NAN, "nan"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(short(x), words, "{x}");
        }
    }

    #[test]
    fn check_finite_names_the_first_value_that_is_not() {
        assert!(check_finite("phi", &[], "finite").is_ok());
        assert!(check_finite("phi", &[1.0, -2.0, 0.0], "finite").is_ok());
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let values = [1.0, bad, 3.0, f64::NAN];
            match check_finite("phi", &values, "finite") {
                Err(MechanismError::OutOfRange {
                    parameter, value, ..
                }) => {
                    assert_eq!(parameter, "phi");
                    assert_eq!(value.to_bits(), bad.to_bits());
                }
                other => panic!("{other:?}"),
            }
        }
    }
}
