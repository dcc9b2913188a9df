//! Errors. Every user-facing error names the offending field and, where one
//! exists, the allowed range.

use thiserror::Error;

/// Errors raised by platefield.
#[derive(Debug, Error)]
pub enum Error {
    /// A parameter is outside its allowed range, malformed, or not finite.
    #[error("{field}: {message}")]
    Invalid {
        /// Dotted path of the offending field (CLI argument or JSON path).
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A part leaves the plate (its normal force reaches zero) or finds no
    /// steady state where the computation needs it in contact: reduce the
    /// motion's amplitude or its vertical and tilt terms.
    #[error("{0}")]
    ContactLost(String),
    /// No motion the method can make meets the request: no usable basis,
    /// no axis that realises the target, no stable pose, a field the
    /// calibration's model cannot follow. The message says what is missing.
    #[error("{0}")]
    Unreachable(String),
    /// A step had nothing to work on or an internal invariant broke (a
    /// segment without the motion its stage made, a library that does not
    /// round-trip through JSON): a defect of platefield, to report.
    #[error("{0}")]
    Internal(String),
    /// An iterative solver did not converge.
    #[error("not converged: {0}")]
    NotConverged(String),
    /// The fit failed, with its kind ([`crate::fit::FitError`]: a dimension
    /// mismatch, invalid input, the conic solver's setup or status, a failed
    /// verification).
    #[error("fit: {0}")]
    Fit(#[from] crate::fit::FitError),
    /// I/O error with the path involved.
    #[error("{path}: {source}")]
    Io {
        /// The file involved.
        path: String,
        /// Underlying error.
        source: std::io::Error,
    },
}

/// Why an argmin run stopped early: the evaluation budget was spent.
/// Its cost functions return it as their error, and the runs recognise it
/// by type ([`BudgetSpent::is`]), not by message.
#[derive(Debug, Error)]
#[error("{0} budget spent")]
pub(crate) struct BudgetSpent(pub &'static str);

impl BudgetSpent {
    /// Whether `e` (an argmin error) is a spent budget.
    pub(crate) fn is(e: &anyhow::Error) -> bool {
        e.downcast_ref::<BudgetSpent>().is_some()
    }
}

/// Result alias.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// An [`Error::Invalid`] for `field` with `message`.
    pub fn invalid(field: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Invalid {
            field: field.into(),
            message: message.into(),
        }
    }

    /// The same error with `context` before the message of a
    /// [`Error::ContactLost`], [`Error::Unreachable`] or [`Error::Internal`]
    /// (e.g. the input file it is about); other kinds unchanged.
    pub(crate) fn within(self, context: impl std::fmt::Display) -> Self {
        match self {
            Error::ContactLost(m) => Error::ContactLost(format!("{context}: {m}")),
            Error::Unreachable(m) => Error::Unreachable(format!("{context}: {m}")),
            Error::Internal(m) => Error::Internal(format!("{context}: {m}")),
            e => e,
        }
    }
}

/// Checks that `value` is finite, naming `field` otherwise.
pub fn finite(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            format!("must be a finite number, got {value}"),
        ))
    }
}

/// Checks that `value` is finite and strictly positive.
pub fn positive(field: &str, value: f64) -> Result<f64> {
    finite(field, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            format!("must be > 0, got {}", crate::input::num(value)),
        ))
    }
}

/// Checks that `value` is finite and non-negative.
pub fn non_negative(field: &str, value: f64) -> Result<f64> {
    finite(field, value)?;
    if value >= 0.0 {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            format!("must be ≥ 0, got {}", crate::input::num(value)),
        ))
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `error::Error::within`.
    #[test]
    fn example_error_within() {
        use crate::Error;
        let e = Error::ContactLost("the part leaves the plate".into()).within("scene.json");
        assert_eq!(e.to_string(), "scene.json: the part leaves the plate");
    }
}
