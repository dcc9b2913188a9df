//! A design judged under the shaker's delivery error: what the parts do
//! when each channel's harmonics come out within the controller's
//! tolerance instead of exactly as exported.
//!
//! A real 6-DOF controller corrects its drive against measured transfer
//! functions and still leaves each channel's response at each frequency a
//! few percent and a few degrees off. Model: for each of the six channels
//! c and each harmonic h, one gain 1 + a·u and one phase shift p·u′ with
//! u, u′ uniform in [−1, 1] ([`crate::request::Tolerance`]: a and p), the
//! same for every segment the schedule plays (the error belongs to the
//! channel at that frequency, not to the segment). Each draw's motions are
//! judged ([`super::judge`]) under the physics given; [`Spread`] holds the
//! draws' shape errors and strengths and their median, 90th percentile and
//! worst. Segments of screw primitives are played as designed (their
//! channels are not Fourier terms); the spread says how many.

use serde::Serialize;

use crate::error::Result;
use crate::field::FieldSettings;
use crate::request::{SampledTarget, Target, Tolerance, MAX_HARMONICS};
use crate::rng::SplitMix64;
use crate::schedule::Schedule;

/// Draws a spread is made of unless asked otherwise.
pub const DEFAULT_DRAWS: usize = 64;

/// The generator's seed: every spread of the same schedule, tolerance and
/// draws is the same.
const SEED: u64 = 0x746f_6c65_7261_6e63;

/// One draw's errors: gain and phase shift (rad) per channel and harmonic.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Draw {
    /// `[channel][harmonic − 1]` = (gain, shift).
    pub errors: Vec<[(f64, f64); 6]>,
}

impl Draw {
    /// (gain, shift) of channel `c` at harmonic `h` (1 and 0 outside the
    /// drawn harmonics).
    pub(crate) fn at(&self, c: usize, h: u32) -> (f64, f64) {
        (h as usize)
            .checked_sub(1)
            .and_then(|i| self.errors.get(i))
            .map_or((1.0, 0.0), |row| row[c.min(5)])
    }
}

/// `count` seeded draws within `tol` ([module documentation](self)).
pub(crate) fn draws(tol: &Tolerance, count: usize) -> Vec<Draw> {
    let mut rng = SplitMix64::new(SEED);
    let phase = tol.phase_deg.to_radians();
    (0..count)
        .map(|_| Draw {
            errors: (0..MAX_HARMONICS)
                .map(|_| {
                    std::array::from_fn(|_| {
                        let gain = 1.0 + tol.amplitude * rng.symmetric();
                        (gain, phase * rng.symmetric())
                    })
                })
                .collect(),
        })
        .collect()
}

/// `schedule` as the controller delivers it under `draw`: every six-signal
/// segment's motion with the draw's errors ([`crate::motion::Signals::delivered`]).
pub(crate) fn delivered(schedule: &Schedule, draw: &Draw) -> Schedule {
    let mut s = schedule.clone();
    for seg in &mut s.segments {
        if let Some(m) = seg.motion.as_mut() {
            *m = m.delivered(&|c, h| draw.at(c, h));
        }
    }
    s
}

/// The judge of a design over delivery errors.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Spread {
    /// The tolerance drawn within.
    pub tolerance: Tolerance,
    /// The parts' kinetic friction judged at.
    pub friction: f64,
    /// Each draw's realised shape error, in draw order.
    pub shape_errors: Vec<f64>,
    /// Each draw's realised strength, in draw order.
    pub strengths: Vec<f64>,
    /// Segments whose channels were perturbed (six-signal motions).
    pub perturbed_segments: usize,
    /// Segments played as designed (screw primitives).
    pub primitive_segments: usize,
}

impl Spread {
    /// (median, 90th percentile, worst) of the shape errors (NaN counts as
    /// worst).
    pub fn shape(&self) -> [f64; 3] {
        [0.5, 0.9, 1.0].map(|q| quantile(&self.shape_errors, q))
    }

    /// (median, 10th percentile, weakest) of the strengths.
    pub fn strength(&self) -> [f64; 3] {
        let neg: Vec<f64> = self.strengths.iter().map(|s| -s).collect();
        [0.5, 0.9, 1.0].map(|q| -quantile(&neg, q))
    }
}

/// The value at quantile `q` of `xs` by nearest rank (NaN sorts last:
/// a draw not measured counts as the worst).
///
/// ```
/// use platefield::design::tolerance::quantile;
/// let xs = [3.0, 1.0, f64::NAN, 2.0];
/// assert_eq!(quantile(&xs, 0.5), 2.0);
/// assert!(quantile(&xs, 1.0).is_infinite());
/// ```
pub fn quantile(xs: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = xs
        .iter()
        .map(|x| if x.is_nan() { f64::INFINITY } else { *x })
        .collect();
    v.sort_by(f64::total_cmp);
    let k = ((q * v.len() as f64).ceil() as usize).clamp(1, v.len().max(1)) - 1;
    v.get(k).copied().unwrap_or(f64::NAN)
}

/// The work of [`spread`]: `count` judges of `schedule` (one when no
/// segment of it is a six-signal motion a draw perturbs).
pub(crate) fn spread_estimate(
    target: &Target,
    sampled: &SampledTarget,
    schedule: &Schedule,
    count: usize,
) -> crate::work::Estimate {
    let term = super::judge::judge_term(
        target,
        sampled,
        super::judge::judged_cycles(schedule),
        schedule.settings.numerics.steps_per_cycle,
    )
    .times(
        if schedule.segments.iter().any(|s| s.motion.is_some()) {
            count as f64
        } else {
            1.0
        },
        "draws",
    )
    .named("delivery-error draws");
    crate::work::Estimate::new(
        "schedule",
        "judging it under the shaker's tolerance",
        "fewer --draws",
    )
    .plus(term)
}

/// The physics a spread of `schedule` is judged under: `settings` at the
/// friction `asked`, else where the design's worst case over its friction
/// range falls (`played.worst_friction`), else the settings' own.
pub(crate) fn judged_at(
    schedule: &Schedule,
    settings: &FieldSettings,
    asked: Option<crate::dynamics::Friction>,
) -> FieldSettings {
    let friction = asked
        .or_else(|| schedule.played.as_ref().and_then(|p| p.worst_friction))
        .unwrap_or(settings.friction);
    FieldSettings {
        friction,
        ..*settings
    }
}

/// The judge of `schedule` against `target` under `settings` over `count`
/// draws within `tol` ([module documentation](self)).
///
/// # Errors
/// A draw's schedule cannot be played.
pub(crate) fn spread(
    target: &Target,
    sampled: &SampledTarget,
    schedule: &Schedule,
    settings: &FieldSettings,
    (tol, count): (&Tolerance, usize),
) -> Result<Spread> {
    let perturbed = schedule
        .segments
        .iter()
        .filter(|s| s.motion.is_some())
        .count();
    let mut shape_errors = Vec::with_capacity(count);
    let mut strengths = Vec::with_capacity(count);
    if perturbed == 0 {
        // Nothing a draw perturbs: every draw is the design as designed.
        let j = super::judge::judge_check(target, sampled, schedule, settings)?;
        shape_errors.resize(count, j.shape_error);
        strengths.resize(count, j.realised_strength);
    }
    for draw in draws(tol, count).iter().filter(|_| perturbed > 0) {
        let s = delivered(schedule, draw);
        let j = super::judge::judge_check(target, sampled, &s, settings)?;
        shape_errors.push(j.shape_error);
        strengths.push(j.realised_strength);
    }
    Ok(Spread {
        tolerance: *tol,
        friction: settings.friction.kinetic,
        shape_errors,
        strengths,
        perturbed_segments: perturbed,
        primitive_segments: schedule
            .segments
            .iter()
            .filter(|s| s.primitive.is_some())
            .count(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The draws fill the tolerance's box uniformly: every gain within
    /// 1 ± a and shift within ±p, and over 64 draws × 6 channels × 16
    /// harmonics the means of u and u′ are 0 within 4 standard errors
    /// (1/√(3n)) and their extremes within 2 % of the bounds.
    #[test]
    fn draws_fill_the_tolerance_box() {
        let tol = Tolerance {
            amplitude: 0.05,
            phase_deg: 5.0,
        };
        let p = 5f64.to_radians();
        let all: Vec<(f64, f64)> = draws(&tol, 64)
            .iter()
            .flat_map(|d| d.errors.iter().flatten().copied().collect::<Vec<_>>())
            .collect();
        let n = all.len() as f64;
        let u: Vec<f64> = all.iter().map(|(g, _)| (g - 1.0) / 0.05).collect();
        let w: Vec<f64> = all.iter().map(|(_, s)| s / p).collect();
        for xs in [&u, &w] {
            assert!(xs.iter().all(|x| (-1.0..=1.0).contains(x)));
            let mean = xs.iter().sum::<f64>() / n;
            assert!(mean.abs() < 4.0 / (3.0 * n).sqrt(), "mean {mean}");
            let (lo, hi) = xs
                .iter()
                .fold((1.0_f64, -1.0_f64), |(l, h), x| (l.min(*x), h.max(*x)));
            assert!(lo < -0.98 && hi > 0.98, "{lo} {hi}");
        }
    }

    /// A worked example of `design::tolerance::draws`.
    #[test]
    fn example_draws() {
        use crate::design::tolerance::draws;
        use crate::request::Tolerance;

        let tol = Tolerance {
            amplitude: 0.05,
            phase_deg: 5.0,
        };
        let d = draws(&tol, 64);
        assert_eq!(d.len(), 64);
        assert_eq!(d, draws(&tol, 64));
        let (g, s) = d[3].at(2, 1);
        assert!((g - 1.0).abs() <= 0.05 && s.abs() <= 5f64.to_radians());
    }

    /// A worked example of `design::tolerance::judged_at`.
    #[test]
    fn example_judged_at() -> Result<(), crate::Error> {
        use crate::design::tolerance::judged_at;
        use crate::dynamics::Friction;
        use crate::schedule::Schedule;

        let schedule = Schedule::load(std::path::Path::new("results/sink/schedule.json"))?;
        let asked = Friction {
            stat: 0.4,
            kinetic: 0.4,
        };
        assert_eq!(
            judged_at(&schedule, &schedule.settings, Some(asked)).friction,
            asked
        );
        assert_eq!(
            judged_at(&schedule, &schedule.settings, None).friction,
            schedule.settings.friction
        );
        Ok(())
    }
}

#[cfg(test)]
#[path = "../../tests/unit/tolerance.rs"]
mod tolerance_tests;
