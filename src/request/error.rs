//! Error type for loading, validating and sampling targets.

use std::path::PathBuf;

/// Everything that can go wrong when reading, validating or sampling a
/// [`Target`](crate::request::Target).
///
/// The `Display` text is meant to be shown to users as-is: validation errors
/// start with the JSON path of the offending value (e.g.
/// `target.grid.n[0]: must be ≥ 2, got 0`), and errors produced by
/// [`Target::load`](crate::request::Target::load) are prefixed with the file
/// path.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TargetError {
    /// The target file could not be read.
    #[error("{}: cannot read target file: {error}", file.display())]
    Io {
        /// Path of the file that failed to read.
        file: PathBuf,
        /// Underlying I/O error.
        error: std::io::Error,
    },
    /// A value is missing, has the wrong type, or is outside its allowed
    /// range.
    #[error("{path}: {message}")]
    Invalid {
        /// JSON path of the offending value, e.g. `target.field.strength`.
        path: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// An error found while loading a particular file.
    #[error("{}: {error}", file.display())]
    InFile {
        /// Path of the target file.
        file: PathBuf,
        /// The error found in that file.
        error: Box<TargetError>,
    },
}

impl TargetError {
    /// Builds a [`TargetError::Invalid`] for the JSON path `path`.
    pub(crate) fn invalid(path: impl Into<String>, message: impl Into<String>) -> Self {
        TargetError::Invalid {
            path: path.into(),
            message: message.into(),
        }
    }

    /// The error as (where, what): the JSON path, prefixed with the file
    /// for [`TargetError::InFile`], and the message without it, so that a
    /// caller can report it without repeating the path.
    pub(crate) fn located(&self) -> (String, String) {
        match self {
            TargetError::Invalid { path, message } => (path.clone(), message.clone()),
            TargetError::InFile { file, error } => {
                let (path, message) = error.located();
                (format!("{}: {path}", file.display()), message)
            }
            TargetError::Io { file, error } => (
                file.display().to_string(),
                format!("cannot read target file: {error}"),
            ),
        }
    }

    /// The JSON path of the offending value, if the error is about one
    /// particular value (looks through [`TargetError::InFile`]).
    #[cfg(test)]
    pub(crate) fn field_path(&self) -> Option<&str> {
        match self {
            TargetError::Invalid { path, .. } => Some(path),
            TargetError::InFile { error, .. } => error.field_path(),
            _ => None,
        }
    }
}

/// Formats a number for an error message, short (see
/// [`crate::input::num`]).
pub(crate) fn show(v: f64) -> String {
    crate::input::num(v)
}

/// Errors unless `lo ≤ v ≤ hi`; `unit` follows the range in the message.
pub(crate) fn check_range(
    path: &str,
    v: f64,
    lo: f64,
    hi: f64,
    unit: &str,
) -> Result<(), TargetError> {
    if (lo..=hi).contains(&v) {
        return Ok(());
    }
    Err(TargetError::invalid(
        path,
        format!(
            "must be in [{}, {}]{unit}, got {}",
            show(lo),
            show(hi),
            show(v)
        ),
    ))
}

/// Errors unless `v` is non-zero with `scale[0] ≤ |v| ≤ scale[1]`.
pub(crate) fn check_scale(
    path: &str,
    v: f64,
    scale: [f64; 2],
    unit: &str,
) -> Result<(), TargetError> {
    if (scale[0]..=scale[1]).contains(&v.abs()) {
        return Ok(());
    }
    Err(TargetError::invalid(
        path,
        format!(
            "must be non-zero, with |value| in [{}, {}]{unit}, got {}",
            show(scale[0]),
            show(scale[1]),
            show(v)
        ),
    ))
}

/// Formats a pair for an error message, e.g. `[0.04, -0.04]`.
pub(crate) fn show2(v: [f64; 2]) -> String {
    format!("[{}, {}]", show(v[0]), show(v[1]))
}

/// Errors unless `v` is finite.
pub(crate) fn check_finite(path: &str, v: f64) -> Result<(), TargetError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(TargetError::invalid(
            path,
            format!("must be finite, got {}", show(v)),
        ))
    }
}

/// Errors unless both components of `v` are finite.
pub(crate) fn check_finite2(path: &str, v: [f64; 2]) -> Result<(), TargetError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(TargetError::invalid(
            path,
            format!("must be finite, got {}", show2(v)),
        ))
    }
}

/// Errors unless `r` is an interval `[min, max]` of finite numbers with
/// `min < max`; `axis` is `"x"` or `"y"`.
pub(crate) fn check_interval(path: &str, axis: &str, r: [f64; 2]) -> Result<(), TargetError> {
    check_finite2(path, r)?;
    if r[0] < r[1] {
        Ok(())
    } else {
        Err(TargetError::invalid(
            path,
            format!("{axis}min must be < {axis}max, got {}", show2(r)),
        ))
    }
}
