//! The library's error type. Every variant carries the offending value so that the
//! message alone tells the user what to fix.

use thiserror::Error;

/// Errors of the physics and I/O layers.
#[derive(Debug, Error)]
pub enum Error {
    /// A parameter is out of its valid range. `field` is the scenario path or argument name.
    #[error("{field} = {value} {reason}")]
    InvalidParameter {
        field: String,
        value: String,
        reason: String,
    },
    /// A linear system could not be factorized (not positive definite, singular).
    #[error("factorization of {what} failed: {reason}")]
    Factorization { what: String, reason: String },
    /// A file could not be read or parsed.
    #[error("{path}: {reason}")]
    File { path: String, reason: String },
    /// The time integration produced a non-finite or runaway state.
    #[error("divergence at t = {time_s} s (step {step}): {quantity} = {value}; {hint}")]
    Divergence {
        time_s: f64,
        step: u64,
        quantity: String,
        value: f64,
        hint: String,
    },
    /// Output could not be written.
    #[error("writing {path}: {reason}")]
    Output { path: String, reason: String },
    /// A run whose estimated size exceeds the free space of its output's file system,
    /// refused before anything is written. The sizes are as printed (`95.3 GiB`).
    #[error(
        "refusing to write {out}: the run's estimated size, {estimated}, exceeds the {free} \
         free on the file system of the output folder {folder} (shorten the run or lower \
         its rates, free some space, or run it anyway with --skip-space-check; \
         skip_space_check=True in Python)"
    )]
    InsufficientSpace {
        out: String,
        folder: String,
        estimated: String,
        free: String,
    },
}

/// Shorthand used across the library.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// A parameter error; `value` is formatted with `Display`.
    pub fn invalid(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        reason: impl Into<String>,
    ) -> Self {
        Error::InvalidParameter {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

/// The path of item `index` of the scenario list `list`, with the item's id when it has
/// one: `sensors.2[A1]` (then `.rate_hz` and so on). The index is the TOML position (the
/// n-th `[[sensors]]` table, from 0), which the dotted path of a parse error also uses;
/// the id is what a user searches for in the file.
/// An id that is not a valid topic segment (letters, digits, `_`, `-`) is left out: it is
/// then the error itself, and the path must not repeat it.
pub fn item_path(list: &str, index: usize, id: Option<&str>) -> String {
    match id.filter(|id| is_segment(id)) {
        Some(id) => format!("{list}.{index}[{id}]"),
        None => format!("{list}.{index}"),
    }
}

/// Whether `id` is a valid id and topic segment: letters, digits, `_` and `-`.
pub fn is_segment(id: &str) -> bool {
    !id.is_empty()
        && id
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// `value` for a message: as `Display` (`0.001`, `-3`, `NaN`, `inf`), unless that takes
/// more than 24 characters (`1e-300` would print 302), then in exponent form (`1e-300`).
pub fn num(value: f64) -> String {
    let plain = value.to_string();
    if plain.len() > 24 {
        format!("{value:e}")
    } else {
        plain
    }
}

/// Checks that `value` is finite and strictly positive.
pub fn require_positive(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            num(value),
            "must be a finite number > 0",
        ))
    }
}

/// Checks that `value` is finite and >= 0.
pub fn require_non_negative(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            num(value),
            "must be a finite number >= 0",
        ))
    }
}

/// Checks that `value` is finite.
pub fn require_finite(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::invalid(field, num(value), "must be a finite number"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_stay_short_in_messages() {
        assert_eq!(num(0.001), "0.001");
        assert_eq!(num(-0.000001), "-0.000001");
        assert_eq!(num(f64::NAN), "NaN");
        assert_eq!(num(f64::NEG_INFINITY), "-inf");
        assert_eq!(num(1e-300), "1e-300");
        assert_eq!(num(-2.5e300), "-2.5e300");
        let e = require_positive("bridge.span_m", 1e300).map(|_| ());
        assert!(e.is_ok());
        let e = require_positive("bridge.span_m", -1e-300).unwrap_err();
        assert_eq!(
            e.to_string(),
            "bridge.span_m = -1e-300 must be a finite number > 0"
        );
    }
}
