//! The work of played drops ([`super::played_basins`]) and of the
//! averaged field's check and refinement ([`averaged_estimate`]), estimated before
//! they play ([`crate::work`]): per drop, whole schedule periods covering
//! [`DropPlay::duration_s`], each segment at its own planar step (a rest
//! segment at the shortest moving segment's, as [`super::play_drop`]
//! plays it), each step of each support point of the played body at
//! [`PLANAR_POINT_STEP_COST`] point-part steps.

use super::averaged::CHECKED_POSES;
use super::drops::{rest_cycle, DropPlay};
use super::refine::MAX_REFINED;
use crate::part::Part;
use crate::play::ScheduleMotion;
use crate::work::{Estimate, Term, PLANAR_POINT_STEP_COST};

/// Support points of the body [`super::played_basins`] plays for `part`
/// (resampled as [`DropPlay::samples`] asks, else the part's own).
pub fn played_points(part: &Part, play: &DropPlay) -> usize {
    play.samples
        .and_then(|n| part.coarse_body(n))
        .map_or(part.body.points().len(), |(body, _)| body.points().len())
}

/// Nominal planar steps of one schedule period of `sm` at
/// `steps_per_cycle` (rest segments at the shortest moving segment's step).
pub fn steps_per_period(sm: &ScheduleMotion, steps_per_cycle: usize) -> f64 {
    let rest = rest_cycle(sm);
    sm.segments()
        .iter()
        .map(|s| {
            let cycle = s.motion.as_ref().map_or(rest, |m| m.period());
            (s.duration / cycle * steps_per_cycle.max(1) as f64).ceil()
        })
        .sum()
}

/// The work of playing `drops` drops of `part` through `sm` as `play`
/// says, in [`crate::work`]'s unit (module docs).
///
/// ```
/// use platefield::pose::{drops_estimate, DropPlay};
/// use platefield::part::Part;
/// use platefield::schedule::Schedule;
/// let part = Part::load(std::path::Path::new("targets/parts/rectangle.json"))?;
/// let schedule = Schedule::load(std::path::Path::new("results/ellipse/schedule.json"))?;
/// let sm = platefield::play::ScheduleMotion::from_schedule(&schedule)?;
/// let play = DropPlay::new(&schedule.settings, 20.0);
/// let one = drops_estimate(&part, &sm, 1, &play).steps();
/// assert_eq!(drops_estimate(&part, &sm, 100, &play).steps(), 100.0 * one);
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn drops_estimate(part: &Part, sm: &ScheduleMotion, drops: usize, play: &DropPlay) -> Estimate {
    let periods = (play.duration_s / sm.period()).ceil().max(1.0);
    Estimate::new("--play", "playing the drops", "--drops or --play").plus(
        Term::new("played drops")
            .times(drops as f64, "drops")
            .times(periods, "periods")
            .times(steps_per_period(sm, play.steps_per_cycle), "steps")
            .times(played_points(part, play) as f64, "support points")
            .times(PLANAR_POINT_STEP_COST, "point steps per support-point step"),
    )
}

/// Expected schedule periods of one averaged twist from rest (measured: 3
/// on the designed ellipse, 4 on a pose design's cycle).
const PERIODS_FROM_REST: f64 = 4.0;
/// Expected periods of one warm-started averaged twist (measured: 2–3).
const PERIODS_WARM: f64 = 2.5;
/// Expected Newton steps per refined equilibrium (measured: 3–12).
const NEWTON_STEPS: f64 = 6.0;

/// The work of the `poses` averaged-field check ([`super::LiftCheck`] at
/// [`CHECKED_POSES`] poses from rest) and refinement ([`super::refine`]:
/// 7 warm-started averaged twists per Newton step) of `equilibria`
/// lifted equilibria of `part` on `sm`, played as
/// [`super::AveragedField::for_part`] plays.
pub fn averaged_estimate(part: &Part, sm: &ScheduleMotion, equilibria: usize) -> Estimate {
    // The drops' resampling (`DropPlay::new`'s samples), as `for_part` plays.
    let play = DropPlay::new(&crate::field::FieldSettings::default(), 0.0);
    let refined = equilibria.min(MAX_REFINED) as f64;
    let per_period = steps_per_period(sm, super::averaged::AVERAGING_STEPS)
        * played_points(part, &play) as f64
        * PLANAR_POINT_STEP_COST;
    Estimate::new(
        "poses",
        "checking and refining on the averaged field",
        "a shorter schedule period",
    )
    .plus(
        Term::new("check")
            .times(CHECKED_POSES as f64, "poses")
            .times(PERIODS_FROM_REST, "periods")
            .times(per_period, "point steps per period"),
    )
    .plus(
        Term::new("refinement")
            .times(refined, "equilibria")
            .times(NEWTON_STEPS * 7.0, "twists")
            .times(PERIODS_WARM, "periods")
            .times(per_period, "point steps per period"),
    )
}
