//! The work of played drops ([`crate::pose::played_basins`]) and of the
//! averaged field's check and refinement ([`averaged_estimate`]), estimated before
//! they play ([`crate::work`]): per drop, whole schedule periods covering
//! [`DropPlay::duration_s`], each segment at its own planar step (a rest
//! segment at the shortest moving segment's, as [`crate::pose::play_drop`]
//! plays it), each step of each support point of the played body at
//! [`PLANAR_POINT_STEP_COST`] point-part steps.

use super::averaged::CHECKED_POSES;
use super::continua::MAX_STEPS;
use super::drops::{rest_cycle, DropPlay};
use super::equilibria::{Region, SETTLE_STEP, SETTLE_STEPS, START_POSES};
use super::rests::MAX_RESTS;
use crate::part::Part;
use crate::play::ScheduleMotion;
use crate::work::{Estimate, Term, PLANAR_POINT_STEP_COST};

/// Support points of the body [`crate::pose::played_basins`] plays for `part`
/// (resampled as [`DropPlay::samples`] asks, else the part's own).
pub(crate) fn played_points(part: &Part, play: &DropPlay) -> usize {
    play.samples
        .and_then(|n| part.coarse_body(n))
        .map_or(part.body.points().len(), |(body, _)| body.points().len())
}

/// Nominal planar steps of one schedule period of `sm` at
/// `steps_per_cycle` (rest segments at the shortest moving segment's step).
pub(crate) fn steps_per_period(sm: &ScheduleMotion, steps_per_cycle: usize) -> f64 {
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

/// Cost of one lifted-twist evaluation per support point, in point-part
/// steps ([`crate::work`]'s unit): a slightly pessimistic rate, above the
/// measured ones (`docs/commands.md`, **The rates behind the
/// estimates**).
const LIFTED_POINT_COST: f64 = 0.08;

/// Newton iterations the estimate counts per start of the rest search
/// (at most 60; each 7 lifted twists: the twist and a central-difference
/// Jacobian).
const SEARCH_ITERATIONS: f64 = 20.0;

/// Continua the estimate counts, each traced over [`super::continua::MAX_STEPS`]
/// steps of 2 corrector iterations (a line sink gives four).
const TRACED: f64 = 4.0;

/// The work of the lifted analysis of `drops` drops of `part` in `region`
/// (`poses`' predicted rests and basins, [`crate::pose::rests`] and
/// `crate::pose::settle_on`), in [`crate::work`]'s unit: the rest search (the
/// start grid's 216 poses, `SEARCH_ITERATIONS` Newton iterations of 7
/// twists each), the continua traced (`TRACED`) and per drop the RK4
/// steps to cross half the region's diagonal at the largest step (2 % of
/// the part's radius), turn half a turn at 0.02 rad a step and close in
/// (100 steps), at most the 20000 steps a drop may take; each step 4
/// lifted-twist evaluations over the part's support points. A part of
/// 2e-8 m takes the 20000 steps per drop.
pub(crate) fn settle_estimate(part: &Part, region: &Region, drops: usize) -> Estimate {
    let half_diagonal = 0.5 * (region.x[1] - region.x[0]).hypot(region.y[1] - region.y[0]);
    let travel = half_diagonal / (SETTLE_STEP * part.radius());
    let turn = std::f64::consts::PI / SETTLE_STEP;
    let steps = (travel + turn + 100.0).min(SETTLE_STEPS as f64).round();
    let points = part.body.points().len() as f64;
    Estimate::new("--drops", "settling the drops", "--drops")
        .plus(
            Term::new("rest search")
                .times(START_POSES as f64, "starts")
                .times(SEARCH_ITERATIONS, "Newton iterations")
                .times(7.0, "evaluations")
                .times(points, "support points")
                .times(LIFTED_POINT_COST, "point steps per evaluation"),
        )
        .plus(
            Term::new("continua")
                .times(TRACED, "curves")
                .times(2.0 * MAX_STEPS as f64, "steps")
                .times(2.0 * 7.0, "evaluations")
                .times(points, "support points")
                .times(LIFTED_POINT_COST, "point steps per evaluation"),
        )
        .plus(
            Term::new("predicted drops")
                .times(drops as f64, "drops")
                .times(steps, "steps")
                .times(4.0, "evaluations")
                .times(points, "support points")
                .times(LIFTED_POINT_COST, "point steps per evaluation"),
        )
}

/// The work of scanning an unknown support's equilibrium bounds
/// ([`crate::pose::Bounds::scan`] over [`crate::pose::SCAN`]): per pose, the field
/// at every sample and vertex and at 8 neighbours of each (the covering
/// bound), each a point-field evaluation at [`LIFTED_POINT_COST`].
pub(crate) fn bounds_term(part: &Part) -> Term {
    Term::new("unknown-support bounds")
        .times(crate::pose::SCAN.iter().product::<usize>() as f64, "poses")
        .times(
            (part.body.points().len() + part.polygon.len()) as f64,
            "samples and vertices",
        )
        .times(9.0, "evaluations")
        .times(LIFTED_POINT_COST, "point steps per evaluation")
}

/// Expected schedule periods of one averaged twist from rest (this and
/// the next two: set from the measured counts, `docs/commands.md`,
/// **The rates behind the estimates**).
const PERIODS_FROM_REST: f64 = 4.0;
/// Expected periods of one warm-started averaged twist.
const PERIODS_WARM: f64 = 2.5;
/// Expected Newton steps per refined equilibrium.
const NEWTON_STEPS: f64 = 6.0;

/// The work of the `poses` averaged-field check ([`crate::pose::LiftCheck`] at
/// [`CHECKED_POSES`] poses from rest) and refinement ([`super::rests`]:
/// 7 warm-started averaged twists per Newton step) of `equilibria`
/// lifted equilibria of `part` on `sm`, played as
/// [`crate::pose::AveragedField::for_part`] plays.
pub(crate) fn averaged_estimate(part: &Part, sm: &ScheduleMotion, equilibria: usize) -> Estimate {
    // The drops' resampling (`DropPlay::new`'s samples), as `for_part` plays.
    let play = DropPlay::new(&crate::field::FieldSettings::default(), 0.0);
    let refined = equilibria.min(MAX_RESTS) as f64;
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
        Term::new("played rests")
            .times(refined, "equilibria")
            .times(NEWTON_STEPS * 7.0, "twists")
            .times(PERIODS_WARM, "periods")
            .times(per_period, "point steps per period"),
    )
}

#[cfg(test)]
mod tests {
    /// A worked example of `settle_estimate`.
    #[test]
    fn example_settle_estimate() -> Result<(), crate::Error> {
        use super::settle_estimate;
        use crate::part::Part;
        use crate::pose::Region;
        let part = Part::load(std::path::Path::new("targets/parts/rectangle.json"))?;
        let region = Region {
            x: [-0.04, 0.04],
            y: [-0.04, 0.04],
        };
        let e = settle_estimate(&part, &region, 200);
        let drops = e
            .terms
            .iter()
            .find(|t| t.label == "predicted drops")
            .unwrap()
            .steps();
        // 200 drops × 532 steps × 4 evaluations × 256 points × 0.08.
        assert!((drops / 8.72e6 - 1.0).abs() < 0.01, "{drops}");
        let more = settle_estimate(&part, &region, 100_000);
        assert_eq!(more.steps() - e.steps(), 499.0 * drops);
        Ok(())
    }
}
