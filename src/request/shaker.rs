//! The optional `shaker` object of a target file: the limits a synthesized
//! motion must keep (peak accelerations per axis, period, harmonics,
//! contact margin). Every key is optional; a key left out takes the default
//! of [`crate::synth::ShakerLimits::envelope`] (the paper's eight primitives
//! and a 6-DOF plate's saved signals, per axis the larger), which `design`
//! fills in.
//!
//! ```json
//! "shaker": {"period": 0.05, "linear": [10, 10, 0], "angular": [70, 70, 0],
//!            "harmonics": 1, "contact_margin": 0.1,
//!            "velocity": {"linear": [0.1, 0.1, 0.05]},
//!            "stroke": {"linear": [2e-3, 2e-3, 1e-3], "angular": [0.01, 0.01, 0.01]}}
//! ```
//!
//! `velocity` and `stroke` are optional travel limits of the plate centre:
//! peak |velocity| (m/s, rad/s) and peak displacement from its mean pose
//! (m, rad) per world axis, each group (`linear`, `angular`) optional; an
//! axis not given is not limited by them. A shaker's stroke and velocity
//! are what its actuators' travel and speed allow.
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
//! 1..=[`MAX_HARMONICS`]; `contact_margin` a fraction of g in [0, 1);
//! `velocity.linear` in [0, [`MAX_LINEAR_VELOCITY`]] m/s,
//! `velocity.angular` in [0, [`MAX_ANGULAR_VELOCITY`]] rad/s,
//! `stroke.linear` in [0, [`MAX_LINEAR_STROKE`]] m and `stroke.angular` in
//! [0, [`MAX_ANGULAR_STROKE`]] rad (0 forbids the axis, as for the peaks).

use serde::{Deserialize, Serialize};

use super::error::show;
use super::TargetError;

/// Largest number of harmonics of 2π/T a controller may be given.
pub const MAX_HARMONICS: u32 = 16;
/// Longest fundamental period (s).
pub const MAX_PERIOD_S: f64 = 10.0;
/// Shortest fundamental period (s): the scene and schedule minimum
/// (`crate::scene::PERIOD`). A period as short as 1e-300 s makes the
/// synthesis run without end, and shorter ones write motions no command
/// can read.
pub const MIN_PERIOD_S: f64 = *crate::scene::PERIOD.start();

/// Largest linear velocity limit (m/s).
pub(crate) const MAX_LINEAR_VELOCITY: f64 = 100.0;
/// Largest angular velocity limit (rad/s).
pub(crate) const MAX_ANGULAR_VELOCITY: f64 = 1e3;
/// Largest linear stroke limit (m).
pub(crate) const MAX_LINEAR_STROKE: f64 = 1.0;
/// Largest angular stroke limit (rad): the small-angle model of a
/// six-signal motion means nothing near a half turn.
pub(crate) const MAX_ANGULAR_STROKE: f64 = 1.0;

/// A travel limit per world axis (`velocity` or `stroke` of a `shaker`
/// object): `linear` x, y, z and `angular` about x, y, z; a group left out
/// is not limited.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TravelSpec {
    /// Linear x, y, z (m/s or m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linear: Option<[f64; 3]>,
    /// Angular about x, y, z (rad/s or rad).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angular: Option<[f64; 3]>,
}

impl TravelSpec {
    /// The six limits in signal order (linear x, y, z, angular x, y, z);
    /// an axis not limited is `f64::INFINITY`.
    pub(crate) fn axes(&self) -> [f64; 6] {
        let inf = [f64::INFINITY; 3];
        let (l, a) = (self.linear.unwrap_or(inf), self.angular.unwrap_or(inf));
        [l[0], l[1], l[2], a[0], a[1], a[2]]
    }

    /// Checks every value against `[0, max]` of its group; errors name
    /// `{field}.linear[i]` or `{field}.angular[i]`.
    fn validate(&self, field: &str, what: &str, max: [(f64, &str); 2]) -> Result<(), TargetError> {
        for ((name, values), (max, unit)) in [("linear", self.linear), ("angular", self.angular)]
            .into_iter()
            .zip(max)
        {
            in_range(
                field,
                name,
                values,
                max,
                &format!("{what} in [0, {}] {unit}", show(max)),
            )?;
        }
        Ok(())
    }
}

/// Checks `values` (one group of three axes) against [0, max]; errors name
/// `{field}.{name}[i]` and say it must be `expected`.
fn in_range(
    field: &str,
    name: &str,
    values: Option<[f64; 3]>,
    max: f64,
    expected: &str,
) -> Result<(), TargetError> {
    for (i, v) in values.iter().flatten().enumerate() {
        if !(v.is_finite() && (0.0..=max).contains(v)) {
            return Err(TargetError::invalid(
                format!("{field}.{name}[{i}]"),
                format!("must be a {expected}, got {}", show(*v)),
            ));
        }
    }
    Ok(())
}

/// Largest delivery error of a channel's amplitude a `tolerance` may state
/// (a fraction).
pub const MAX_TOLERANCE_AMPLITUDE: f64 = 0.5;
/// Largest delivery error of a channel's phase a `tolerance` may state
/// (degrees).
pub const MAX_TOLERANCE_PHASE_DEG: f64 = 45.0;

/// How closely the shaker's controller delivers each channel's harmonics:
/// within ±`amplitude` (a fraction) of the amplitude and ±`phase_deg`
/// degrees of the phase asked for (`"tolerance": {"amplitude": 0.05,
/// "phase_deg": 5}`). A design is not changed by it; `verify --tolerance`
/// and `report.md` judge the design under seeded random errors within it
/// (`platefield::design::tolerance`).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tolerance {
    /// Relative amplitude error bound, in [0, 0.5].
    #[serde(default)]
    pub amplitude: f64,
    /// Phase error bound (degrees), in [0, 45].
    #[serde(default)]
    pub phase_deg: f64,
}

impl Tolerance {
    /// Checks both bounds; errors name `{field}.amplitude` or
    /// `{field}.phase_deg`.
    ///
    /// ```
    /// use platefield::request::Tolerance;
    /// assert!(Tolerance { amplitude: 0.05, phase_deg: 5.0 }.validate("shaker.tolerance").is_ok());
    /// let e = Tolerance { amplitude: 0.8, phase_deg: 5.0 }.validate("shaker.tolerance");
    /// assert!(e.unwrap_err().to_string().contains("shaker.tolerance.amplitude"));
    /// ```
    pub fn validate(&self, field: &str) -> Result<(), TargetError> {
        for (name, v, max, what) in [
            (
                "amplitude",
                self.amplitude,
                MAX_TOLERANCE_AMPLITUDE,
                "a fraction",
            ),
            (
                "phase_deg",
                self.phase_deg,
                MAX_TOLERANCE_PHASE_DEG,
                "degrees",
            ),
        ] {
            if !(v.is_finite() && (0.0..=max).contains(&v)) {
                return Err(TargetError::invalid(
                    format!("{field}.{name}"),
                    format!("must be in [0, {}] ({what}), got {}", show(max), show(v)),
                ));
            }
        }
        Ok(())
    }
}

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
    /// Peak plate-centre velocity per world axis (m/s, rad/s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<TravelSpec>,
    /// Peak plate-centre displacement from its mean pose per world axis
    /// (m, rad).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stroke: Option<TravelSpec>,
    /// How closely the controller delivers each channel ([`Tolerance`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<Tolerance>,
}

impl ShakerSpec {
    /// Checks every value given against its range (see the module docs);
    /// errors name `{field}.period`, `{field}.linear[i]`, ….
    pub(crate) fn validate(&self, field: &str) -> Result<(), TargetError> {
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
            let expected = format!("peak acceleration in [0, {}] {unit}", show(max));
            in_range(field, name, values, max, &expected)?;
        }
        if let Some(v) = &self.velocity {
            let max = [
                (MAX_LINEAR_VELOCITY, "m/s"),
                (MAX_ANGULAR_VELOCITY, "rad/s"),
            ];
            v.validate(&format!("{field}.velocity"), "peak velocity", max)?;
        }
        if let Some(v) = &self.stroke {
            let max = [(MAX_LINEAR_STROKE, "m"), (MAX_ANGULAR_STROKE, "rad")];
            v.validate(&format!("{field}.stroke"), "stroke", max)?;
        }
        if let Some(t) = &self.tolerance {
            t.validate(&format!("{field}.tolerance"))?;
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

#[cfg(test)]
mod tests {
    /// A worked example of `request::shaker::TravelSpec::axes`.
    #[test]
    fn example_travelspec_axes() {
        use crate::request::TravelSpec;
        let t = TravelSpec {
            linear: Some([1e-3, 2e-3, 0.0]),
            angular: None,
        };
        assert_eq!(
            t.axes(),
            [1e-3, 2e-3, 0.0, f64::INFINITY, f64::INFINITY, f64::INFINITY]
        );
    }
}
