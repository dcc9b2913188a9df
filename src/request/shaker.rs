//! The optional `shaker` object of a target file: the limits a synthesized
//! motion must keep (peak accelerations per axis, period, harmonics,
//! contact margin). Every key is optional; a key left out takes the default
//! of [`crate::synth::ShakerLimits::paper_envelope`] (the envelope of the
//! paper's eight primitives), which `design` fills in.
//!
//! ```json
//! "shaker": {"period": 0.05, "linear": [10, 10, 0], "angular": [70, 70, 0],
//!            "harmonics": 1, "contact_margin": 0.1}
//! ```
//!
//! Ranges (checked here, and by `ShakerLimits::validate` through
//! [`ShakerSpec::validate`], so they are stated once): `period` in (0, 10] s;
//! each `linear` (m/s²) and `angular` (rad/s²) peak finite and ≥ 0 (0
//! forbids the axis); `harmonics` in 1..=[`MAX_HARMONICS`]; `contact_margin`
//! a fraction of g in [0, 1).

use serde::{Deserialize, Serialize};

use super::error::show;
use super::TargetError;

/// Largest number of harmonics of 2π/T a controller may be given.
pub const MAX_HARMONICS: u32 = 16;
/// Longest fundamental period (s).
pub const MAX_PERIOD_S: f64 = 10.0;

/// The `shaker` object of a target, as written (missing keys `None`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShakerSpec {
    /// Fundamental period T (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub period: Option<f64>,
    /// Peak plate-centre translational acceleration per world axis (m/s²).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linear: Option<[f64; 3]>,
    /// Peak angular acceleration about each world axis (rad/s²).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angular: Option<[f64; 3]>,
    /// Harmonics 1..=H of 2π/T the controller may play.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub harmonics: Option<u32>,
    /// Least normal force to keep everywhere in the region, as a fraction
    /// of g.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_margin: Option<f64>,
}

impl ShakerSpec {
    /// Checks every value given against its range (see the module docs);
    /// errors name `{field}.period`, `{field}.linear[i]`, ….
    pub fn validate(&self, field: &str) -> Result<(), TargetError> {
        if let Some(p) = self.period {
            if !(p.is_finite() && p > 0.0 && p <= MAX_PERIOD_S) {
                return Err(TargetError::invalid(
                    format!("{field}.period"),
                    format!("must be a period in (0, {MAX_PERIOD_S}] s, got {}", show(p)),
                ));
            }
        }
        for (name, values) in [("linear", self.linear), ("angular", self.angular)] {
            for (i, v) in values.iter().flatten().enumerate() {
                if !(v.is_finite() && *v >= 0.0) {
                    return Err(TargetError::invalid(
                        format!("{field}.{name}[{i}]"),
                        format!("must be a finite peak acceleration ≥ 0, got {}", show(*v)),
                    ));
                }
            }
        }
        if let Some(h) = self.harmonics {
            if !(1..=MAX_HARMONICS).contains(&h) {
                return Err(TargetError::invalid(
                    format!("{field}.harmonics"),
                    format!("must be in 1..={MAX_HARMONICS}, got {h}"),
                ));
            }
        }
        if let Some(m) = self.contact_margin {
            if !(m.is_finite() && (0.0..1.0).contains(&m)) {
                return Err(TargetError::invalid(
                    format!("{field}.contact_margin"),
                    format!("must be a fraction of g in [0, 1), got {}", show(m)),
                ));
            }
        }
        Ok(())
    }
}
