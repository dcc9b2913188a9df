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
//! [`ShakerSpec::validate`], so they are stated once): `period` in
//! [1e-4, 10] s (the shortest a scene or schedule motion may have,
//! [`crate::scene::PERIOD`]); each `linear` peak in [0, 1e4] m/s² and
//! `angular` peak in [0, 1e5] rad/s² (0 forbids the axis; the largest
//! amplitude a scene or schedule signal term may have,
//! [`crate::scene::LINEAR_ACCEL`] and [`crate::scene::ANGULAR_ACCEL`]: with
//! one harmonic a synthesized motion within these peaks can always be read
//! back; with more, one term's amplitude may exceed the summed signal's
//! peak (a square-like wave's first harmonic by up to 4/π), so a motion
//! synthesized at peaks above π/4 of these ranges — about 800 g — may be
//! refused when read back, naming the term); `harmonics` in
//! 1..=[`MAX_HARMONICS`]; `contact_margin` a fraction of g in [0, 1).

use serde::{Deserialize, Serialize};

use super::error::show;
use super::TargetError;

/// Largest number of harmonics of 2π/T a controller may be given.
pub const MAX_HARMONICS: u32 = 16;
/// Longest fundamental period (s).
pub const MAX_PERIOD_S: f64 = 10.0;
/// Shortest fundamental period (s): the scene and schedule minimum
/// ([`crate::scene::PERIOD`]). A period of 1e-300 s made the synthesis
/// run without end, and one below it wrote motions no command could read.
pub const MIN_PERIOD_S: f64 = *crate::scene::PERIOD.start();

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
            if !(p.is_finite() && (MIN_PERIOD_S..=MAX_PERIOD_S).contains(&p)) {
                return Err(TargetError::invalid(
                    format!("{field}.period"),
                    format!(
                        "must be a period in [{}, {MAX_PERIOD_S}] s, got {}",
                        show(MIN_PERIOD_S),
                        show(p)
                    ),
                ));
            }
        }
        for (name, values, max, unit) in [
            ("linear", self.linear, crate::scene::LINEAR_ACCEL, "m/s²"),
            (
                "angular",
                self.angular,
                crate::scene::ANGULAR_ACCEL,
                "rad/s²",
            ),
        ] {
            for (i, v) in values.iter().flatten().enumerate() {
                if !(v.is_finite() && (0.0..=max).contains(v)) {
                    return Err(TargetError::invalid(
                        format!("{field}.{name}[{i}]"),
                        format!(
                            "must be a peak acceleration in [0, {}] {unit}, got {}",
                            show(max),
                            show(*v)
                        ),
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
