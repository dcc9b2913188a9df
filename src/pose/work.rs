//! The work of played drops ([`super::played_basins`]), estimated before
//! they play ([`crate::work`]): per drop, whole schedule periods covering
//! [`DropPlay::duration_s`], each segment at its own planar step (a rest
//! segment at the shortest moving segment's, as [`super::play_drop`]
//! plays it), each step of each support point of the played body at
//! [`PLANAR_POINT_STEP_COST`] point-part steps.

use super::drops::{rest_cycle, DropPlay};
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
