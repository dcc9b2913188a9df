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
    /// The requested computation is physically invalid for this input
    /// (for example the part leaves the plate).
    #[error("{0}")]
    Physical(String),
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
    pub fn is(e: &anyhow::Error) -> bool {
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
