//! Shaker limits: what the controller and the plate allow a synthesized
//! motion to use.
//!
//! JSON form (the `shaker` object of a request; every key optional):
//!
//! ```json
//! {"period": 0.05, "linear": [10, 10, 0], "angular": [70, 70, 0],
//!  "harmonics": 1, "contact_margin": 0.1}
//! ```
//!
//! * `period` T (s): the fundamental period; the controller plays the
//!   harmonics 1..=`harmonics` of 2π/T.
//! * `linear` [a_x, a_y, a_z] (m/s²) and `angular` [α_x, α_y, α_z]
//!   (rad/s²): the largest |value| over the period of each **summed**
//!   plate-centre acceleration signal (not per harmonic). 0 forbids the axis.
//! * `contact_margin` m: the normal force per unit mass N must stay
//!   ≥ m·g everywhere in the region at every instant (0 ≤ m < 1).
//! * `velocity` and `stroke` (optional, [`TravelSpec`]): peak plate-centre
//!   velocity (m/s, rad/s) and displacement from the mean pose (m, rad)
//!   per axis. A term A sin(nωt + φ) moves at A/(nω) and travels A/(nω)²,
//!   so on an axis with velocity limit v and stroke limit s a harmonic-1
//!   term may have at most min(v ω, s ω²): [`ShakerLimits::axes`] lowers
//!   the acceleration limits to it, which is exact for one harmonic. Higher
//!   harmonics travel less per unit acceleration; a motion of several is
//!   held to the velocity and stroke of its summed signals by
//!   [`crate::synth::params::Coefficients::clamp`].
//!
//! Defaults ([`ShakerLimits::envelope`]): per axis, the larger of two
//! libraries of motions a 6-DOF plate has played, so that every motion of
//! either is within the default:
//!
//! * the paper's eight primitives with their default parameters
//!   ([`ShakerLimits::paper_envelope`]; ω = 209 rad/s, so T = 2π/209 ≈
//!   0.030063 s), which the sequenced designs play. Computed from the
//!   primitives' exact plate-centre accelerations, with x and y both taking
//!   the largest horizontal magnitude (designs turn the primitives about the
//!   vertical);
//! * the saved signal library of the PPOD, a 6-DOF vibrating plate driven
//!   through a measured transfer function ([`ShakerLimits::ppod_library`]:
//!   the desired plate accelerations of its saved cycles, repository
//!   `benbdon/PPOD2`, folders `*/SavedSignals_Pdd`, played at 20–30 Hz,
//!   the plate's accelerations within 10 % of them).
//!
//! | axis | default | from |
//! |------|---------|------|
//! | linear x, y | 45.28 m/s² | paper: Trans (sawtooth, d0 ω² · 2.07); the PPOD's 20 |
//! | linear z | 7 m/s² | PPOD: Trans and Circle (the paper's primitives only reach 0.109, the centripetal term of the Line/Skew rotations) |
//! | angular x, y | 218.4 rad/s² | paper: LineSink, ψ0 ω²; the PPOD's 100 |
//! | angular z | 9055 rad/s² | paper: Circle (sawtooth, 0.1 ω² · 2.07); the PPOD's 100 |
//!
//! The period, harmonics (2) and contact margin (0.1) are the paper
//! envelope's. The vertical limit lets a design move the plate up and down
//! where that helps; the contact margin keeps the normal force at least
//! m·g at every point of the region whatever the vertical acceleration.
//! A lab whose plate delivers less states its own `shaker` object: the
//! PPOD's library alone is `{"period": 0.05, "linear": [20, 20, 7],
//! "angular": [100, 100, 100]}`.
//!
//! `tests/unit/synth.rs` holds these numbers against the computation.

use serde::{Deserialize, Serialize};

use crate::basis::{Primitive, PrimitiveKind};
use crate::error::{Error, Result};
use crate::request::{ShakerSpec, TravelSpec};
use crate::schedule::export::centre_acceleration;
use crate::schedule::export::peaks::KinematicPeaks;

/// Peak accelerations, harmonics and contact margin a synthesized motion
/// must respect (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ShakerLimits {
    /// Fundamental period T (s).
    pub period: f64,
    /// Peak plate-centre translational acceleration per world axis (m/s²).
    pub linear: [f64; 3],
    /// Peak angular acceleration about each world axis (rad/s²).
    pub angular: [f64; 3],
    /// Harmonics 1..=H of 2π/T the controller may play.
    pub harmonics: u32,
    /// Least normal force to keep, as a fraction of g.
    pub contact_margin: f64,
    /// Peak plate-centre velocity per axis (m/s, rad/s), if limited.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub velocity: Option<TravelSpec>,
    /// Peak plate-centre displacement from the mean pose per axis (m,
    /// rad), if limited.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stroke: Option<TravelSpec>,
}

/// Samples per primitive period used to find the envelope's peaks.
const ENVELOPE_SAMPLES: usize = 4096;

impl Default for ShakerLimits {
    fn default() -> Self {
        ShakerLimits::envelope()
    }
}

impl ShakerLimits {
    /// Largest allowed number of harmonics.
    pub const MAX_HARMONICS: u32 = crate::request::MAX_HARMONICS;

    /// The limits a target's `shaker` object asks for: each key given
    /// replaces the default [`envelope`](Self::envelope) value (`None`:
    /// the envelope itself).
    pub fn from_spec(spec: Option<&ShakerSpec>) -> ShakerLimits {
        let mut l = ShakerLimits::envelope();
        if let Some(s) = spec {
            l.period = s.period.unwrap_or(l.period);
            l.linear = s.linear.unwrap_or(l.linear);
            l.angular = s.angular.unwrap_or(l.angular);
            l.harmonics = s.harmonics.unwrap_or(l.harmonics);
            l.contact_margin = s.contact_margin.unwrap_or(l.contact_margin);
            l.velocity = s.velocity;
            l.stroke = s.stroke;
        }
        l
    }

    /// The limits `schedule` is held to: those its design recorded
    /// (`played.limits`), else those its target states (keys left out the
    /// default [`envelope`](Self::envelope)); `None` for a schedule with
    /// neither.
    ///
    /// ```
    /// use platefield::schedule::Schedule;
    /// use platefield::synth::ShakerLimits;
    /// let s = Schedule::load(std::path::Path::new("results/sort_friction/schedule.json"))?;
    /// let held = ShakerLimits::stated(&s).unwrap();
    /// assert_eq!(held.linear, Some(ShakerLimits::envelope().linear));
    /// # Ok::<(), platefield::Error>(())
    /// ```
    pub fn stated(schedule: &crate::schedule::Schedule) -> Option<ShakerSpec> {
        schedule
            .played
            .as_ref()
            .and_then(|p| p.limits.clone())
            .or_else(|| {
                let target = schedule.target_spec.as_ref()?;
                Some(ShakerLimits::from_spec(target.shaker.as_ref()).to_spec())
            })
    }

    /// These limits as a fully given `shaker` object.
    pub(crate) fn to_spec(&self) -> ShakerSpec {
        ShakerSpec {
            period: Some(self.period),
            linear: Some(self.linear),
            angular: Some(self.angular),
            harmonics: Some(self.harmonics),
            contact_margin: Some(self.contact_margin),
            velocity: self.velocity,
            stroke: self.stroke,
            tolerance: None,
        }
    }

    /// The default limits (module documentation): per axis the larger of
    /// the [`paper_envelope`](Self::paper_envelope) and the
    /// `ppod_library`, with the paper envelope's
    /// period, harmonics and contact margin.
    ///
    /// ```
    /// use platefield::synth::ShakerLimits;
    /// let (env, paper) = (ShakerLimits::envelope(), ShakerLimits::paper_envelope());
    /// assert_eq!(env.linear[2], 7.0); // the PPOD's vertical
    /// assert_eq!(env.linear[0], paper.linear[0]); // the paper's Trans
    /// assert_eq!(env.period, paper.period);
    /// ```
    pub fn envelope() -> ShakerLimits {
        let (paper, ppod) = (ShakerLimits::paper_envelope(), ShakerLimits::ppod_library());
        let larger = |a: [f64; 3], b: [f64; 3]| std::array::from_fn(|k| a[k].max(b[k]));
        ShakerLimits {
            linear: larger(paper.linear, ppod.linear),
            angular: larger(paper.angular, ppod.angular),
            ..paper
        }
    }

    /// The per-channel peaks of the PPOD's saved desired plate
    /// accelerations (`benbdon/PPOD2`, `*/SavedSignals_Pdd/*.mat`, field
    /// `signalinfo.PddDesCyc`): linear x 20 (Trans), y 15 (TransY, LineSinkY)
    /// taken on both horizontal axes, z 7 m/s² (Trans, Circle); angular
    /// 100 rad/s² about every axis (Sink, LineSink, Circle). Its cycles are
    /// 0.05 s (20 Hz) and 0.0333 s; this takes T = 0.05 s, the most common,
    /// and harmonic 1, the only one its saved desired cycles use (each
    /// channel `A sin(ωt + φ)`).
    pub(crate) fn ppod_library() -> ShakerLimits {
        ShakerLimits {
            period: 0.05,
            linear: [20.0, 20.0, 7.0],
            angular: [100.0, 100.0, 100.0],
            harmonics: 1,
            contact_margin: 0.1,
            velocity: None,
            stroke: None,
        }
    }

    /// The envelope of the paper's eight primitives (default parameters):
    /// per axis, the largest |acceleration| any of them commands over
    /// `ENVELOPE_SAMPLES` samples of its period — on x and y the largest
    /// horizontal magnitude, since designs use the primitives turned about
    /// the vertical; 2 harmonics; margin 0.1.
    pub fn paper_envelope() -> ShakerLimits {
        let mut linear = [0.0_f64; 3];
        let mut angular = [0.0_f64; 3];
        let mut period = 0.0;
        for kind in PrimitiveKind::ALL {
            let p = Primitive::new(kind);
            period = p.period();
            let motion = p.motion();
            for i in 0..ENVELOPE_SAMPLES {
                let t = period * i as f64 / ENVELOPE_SAMPLES as f64;
                let (lin, ang) = centre_acceleration(&motion, t);
                // Designs turn primitives about the vertical, so any
                // horizontal peak can land on x or on y.
                for (env, v) in [(&mut linear, lin), (&mut angular, ang)] {
                    let horizontal = v.x.hypot(v.y);
                    env[0] = env[0].max(horizontal);
                    env[1] = env[1].max(horizontal);
                    env[2] = env[2].max(v.z.abs());
                }
            }
        }
        ShakerLimits {
            period,
            linear,
            angular,
            harmonics: 2,
            contact_margin: 0.1,
            velocity: None,
            stroke: None,
        }
    }

    /// The limits of a lab-class shaker: T = 0.05 s, linear ≤ 10 m/s² on x
    /// and y and 0 on z, angular ≤ 70 rad/s² about x and y and 0 about z,
    /// harmonic 1 only, margin 0.1.
    pub fn lab_class() -> ShakerLimits {
        ShakerLimits {
            period: 0.05,
            linear: [10.0, 10.0, 0.0],
            angular: [70.0, 70.0, 0.0],
            harmonics: 1,
            contact_margin: 0.1,
            velocity: None,
            stroke: None,
        }
    }

    /// The six per-axis acceleration limits in signal order (linear x, y,
    /// z, angular x, y, z), each lowered to what a harmonic-1 term may have
    /// under the axis's velocity and stroke limits, min(v ω, s ω²) with
    /// ω = 2π/T (see the module documentation).
    pub fn axes(&self) -> [f64; 6] {
        let w = std::f64::consts::TAU / self.period;
        let (accel, v, s) = (
            self.acceleration_axes(),
            self.velocity_axes(),
            self.stroke_axes(),
        );
        std::array::from_fn(|k| accel[k].min(v[k] * w).min(s[k] * w * w))
    }

    /// The six peak-acceleration limits as given (not lowered by the
    /// travel limits; compare [`axes`](Self::axes)).
    pub(crate) fn acceleration_axes(&self) -> [f64; 6] {
        let (l, a) = (self.linear, self.angular);
        [l[0], l[1], l[2], a[0], a[1], a[2]]
    }

    /// The first limit `peaks` exceed by more than a relative 1e-9
    /// ([`KinematicPeaks::excesses`]): the axis named as in a `signals`
    /// motion (`linear.x`, with ` velocity` or ` stroke` after it for
    /// those), the peak and the limit. `None`: within every limit.
    pub(crate) fn first_excess(&self, peaks: &KinematicPeaks) -> Option<(String, f64, f64)> {
        let e = peaks.excesses(&self.to_spec()).into_iter().next()?;
        Some((e.axis, e.peak, e.limit))
    }

    /// The six peak-velocity limits (`f64::INFINITY` where not limited).
    pub(crate) fn velocity_axes(&self) -> [f64; 6] {
        self.velocity.unwrap_or_default().axes()
    }

    /// The six stroke limits (`f64::INFINITY` where not limited).
    pub(crate) fn stroke_axes(&self) -> [f64; 6] {
        self.stroke.unwrap_or_default().axes()
    }

    /// Validates every value; errors name `{field}.period`,
    /// `{field}.linear[i]`, … (the target file's `field` is `shaker`) and
    /// the allowed range.
    pub(crate) fn validate(&self, field: &str) -> Result<()> {
        // The ranges live with the target file's `shaker` object.
        self.to_spec().validate(field).map_err(|e| {
            let (at, message) = e.located();
            Error::invalid(at, message)
        })
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `synth::limits::ShakerLimits::axes`.
    #[test]
    fn example_shakerlimits_axes() {
        use crate::request::TravelSpec;
        use crate::synth::ShakerLimits;
        let mut l = ShakerLimits::lab_class(); // T = 0.05 s, 10 m/s² on x
        assert_eq!(l.axes()[0], 10.0);
        // 1 mm of stroke at ω = 40π rad/s allows 1e-3 ω² ≈ 15.8 m/s²: no change.
        l.stroke = Some(TravelSpec {
            linear: Some([1e-3; 3]),
            angular: None,
        });
        assert_eq!(l.axes()[0], 10.0);
        // 0.25 mm allows 3.95 m/s².
        l.stroke = Some(TravelSpec {
            linear: Some([2.5e-4; 3]),
            angular: None,
        });
        let w = std::f64::consts::TAU / 0.05;
        assert!((l.axes()[0] - 2.5e-4 * w * w).abs() < 1e-12);
    }
}
