//! The judge: the realised field over the whole region the target asks for.
//!
//! Every design is judged by this one measure: each candidate `auto`
//! chooses between, the kept design's headline, `schedule.json`'s
//! `"played"`, the rows of its friction table, and the replay of its
//! exported file ([`super::replay`]).
//!
//! 1. **Points** ([`judge_points`]): a regular sub-grid of the target's
//!    grid with both edges of the region on it and at least
//!    [`JUDGE_MIN_PER_SIDE`] points per side (every point of a smaller
//!    grid); every sample of a grid-less sampled target. Points the
//!    target masks (weight 0) are not played.
//! 2. **Play** ([`play_motion`]): a point part at each point, its position
//!    frozen there — the plate's kinematics are those of that point
//!    ([`crate::dynamics::Model::moving`] off) — and its velocity state
//!    played from rest through whole schedule periods, segment joins and
//!    ramps included, until it runs periodic: until what the start-up
//!    transient still adds to the period's mean velocity is below
//!    `crate::play::settle`'s 10⁻⁴ of it (at least three periods). The
//!    last period's mean velocity is the realised field R(p). A schedule
//!    of one steady motion is played one motion cycle per period (the
//!    same periodic orbit, at a tenth of the work of a ten-cycle period).
//!    A held part that loses contact, or that has **no held steady
//!    state** — its velocity still changes at the warm-up cap by more
//!    than `crate::play::settle`'s `HELD_TOL` (1 %) of its mean — is
//!    invalid, with the reason, and not counted; either makes the design
//!    POOR. The second happens where the plate carries a part far within
//!    a cycle: 3 cm off the axis of the large-amplitude Circle primitive
//!    the held part's velocity keeps growing through the warm-up (the
//!    test `a_held_part_with_no_steady_state_is_invalid`), a mean with no
//!    meaning as a field.
//! 3. **Compare** ([`realised_error`], positions frozen so the
//!    promise at p is t(p) exactly): with the target's weights ω_k,
//!    ```text
//!    ŝ           = ⟨R, t⟩ / ⟨t, t⟩           realised strength   (⟨u, v⟩ = Σ_k ω_k² u_k·v_k)
//!    shape error = ‖R − ŝt‖ / ‖ŝt‖           realised shape error
//!    ```
//!
//! **Why frozen.** A part that moves drifts toward the target's attractor
//! before and while it is measured: on a long schedule it is measured far
//! from where it started, and the region's edge, where a field weakens
//! or saturates first, is hardly counted. A target asks for a velocity at
//! each point of its region; the realised field at a frozen point is that
//! velocity, whatever the schedule's period. (The moving parts' questions
//! — do they arrive, how fast, how many escape — are the swarm's, in
//! `verify`.)
//!
//! **Why these points.** The shape error is a weighted L2 norm over the
//! region; a regular grid with both edges on it is the trapezoid-like
//! sample of that norm, with an error of order h² (h the spacing) for a
//! smooth field. Eight intervals per side keep the edges and the centre
//! of a symmetric region on the grid and resolve a field that turns or
//! saturates once across it; the sub-grid keeps the target's own points,
//! so its weights and mask apply unchanged. The stride is the largest
//! that divides the grid's n − 1 intervals into at least eight; when no
//! divisor gives at most [`JUDGE_MAX_PER_SIDE`] points (n − 1 prime, say),
//! the stride ⌊(n − 1)/8⌋ is centred on the region instead, half a stride
//! from its edges at most.
//!
//! **Cost.** Frozen parts share one table of the plate's kinematics per
//! segment and need no contact search; 121 points of a 21 × 21 target
//! cost about three periods each.

pub(crate) mod compare;

use rayon::prelude::*;

pub use compare::counts;
pub use compare::realised_error;
#[cfg(test)]
pub(crate) use compare::Decomposition;
pub use compare::{PointPlay, RealisedError};

use crate::field::FieldSettings;
use crate::play::measure::{play_frozen_point, PlayOptions};
use crate::play::{PlayedSegment, ScheduleMotion};
use crate::request::{SampledTarget, Target};
use crate::schedule::Schedule;

/// Fewest periods the judge plays at a point: the first transient
/// estimate needs the means of three (`crate::play::settle`).
pub const JUDGE_MIN_PERIODS: u32 = 3;

/// Fewest judge points per side of a gridded target (every point of a
/// grid with fewer).
pub const JUDGE_MIN_PER_SIDE: usize = 9;

/// Most judge points per side a divisor of the grid's intervals may give
/// before the centred stride is taken instead (see the module
/// documentation).
pub const JUDGE_MAX_PER_SIDE: usize = 2 * JUDGE_MIN_PER_SIDE - 1;

/// The judge's point indices along one axis of `n` grid points.
fn axis_points(n: usize) -> Vec<usize> {
    let intervals = n.saturating_sub(1);
    let want = JUDGE_MIN_PER_SIDE - 1;
    if intervals <= want {
        return (0..n).collect();
    }
    let divisor = (1..=intervals / want)
        .rev()
        .find(|k| intervals.is_multiple_of(*k))
        .filter(|k| intervals / k < JUDGE_MAX_PER_SIDE);
    match divisor {
        Some(k) => (0..n).step_by(k).collect(),
        None => {
            let k = intervals / want;
            let count = intervals / k + 1;
            let offset = (intervals - (count - 1) * k) / 2;
            (0..count).map(|j| offset + j * k).collect()
        }
    }
}

/// The judge's points of `target` (indices into `sampled.points`; see the
/// [module documentation](self)): a regular sub-grid of its grid with both
/// edges on it, at least [`JUDGE_MIN_PER_SIDE`] per side, or every sample
/// of a grid-less target; masked points left out.
///
/// ```
/// use platefield::design::judge::judge_points;
/// use platefield::request::Target;
///
/// let target = Target::from_json_str(r#"{"name": "s", "field": {"kind": "sink"},
///     "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 21]}}"#).unwrap();
/// let sampled = target.sample().unwrap();
/// // Every other point of 21: 11 × 11, corners included.
/// let points = judge_points(&target, &sampled);
/// assert_eq!(points.len(), 121);
/// assert!(points.contains(&0) && points.contains(&440));
/// ```
pub fn judge_points(target: &Target, sampled: &SampledTarget) -> Vec<usize> {
    let counted = |k: &usize| sampled.weights[*k] > 0.0;
    match &target.grid {
        None => (0..sampled.len()).filter(counted).collect(),
        Some(g) => {
            let xs = axis_points(g.n[0]);
            axis_points(g.n[1])
                .into_iter()
                .flat_map(|j| xs.iter().map(move |i| j * g.n[0] + i))
                .filter(|k| *k < sampled.len())
                .filter(counted)
                .collect()
        }
    }
}

/// Every `stride`-th grid point along each axis (every `stride`-th sample
/// of a grid-less target), weight > 0 only: a coarser, cheaper set of
/// points than the judge's, for screening candidates before the judge
/// and for the model check's moving parts.
///
/// ```
/// use platefield::design::judge::strided_points;
/// use platefield::request::Target;
///
/// let target = Target::from_json_str(r#"{"name": "s", "field": {"kind": "sink"},
///     "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 21]}}"#).unwrap();
/// let sampled = target.sample().unwrap();
/// assert_eq!(strided_points(&target, &sampled, 4).len(), 36);
/// ```
pub fn strided_points(target: &Target, sampled: &SampledTarget, stride: usize) -> Vec<usize> {
    let stride = stride.max(1);
    (0..sampled.len())
        .filter(|&k| sampled.weights[k] > 0.0)
        .filter(|&k| match &target.grid {
            Some(g) => (k % g.n[0]) % stride == 0 && (k / g.n[0]) % stride == 0,
            None => k % stride == 0,
        })
        .collect()
}

/// `sm` as the judge plays it: one cycle per period when it is one steady
/// motion repeated (its periodic orbit is the same), else as it is.
fn one_period(sm: &ScheduleMotion) -> Option<ScheduleMotion> {
    let [seg] = sm.segments() else {
        return None;
    };
    let motion = seg.motion.as_ref()?;
    let cycle = motion.period();
    let whole = (seg.duration / cycle).round();
    if seg.cycles <= 1 || (whole * cycle - seg.duration).abs() > 1e-9 * seg.duration {
        return None;
    }
    ScheduleMotion::new(vec![PlayedSegment::moving(
        seg.label.clone(),
        motion.clone(),
        1,
    )])
    .ok()
}

/// The realised field of the trajectory `sm` at `points[i]` for each `i`
/// in `starts`, with the physics of `settings` (see the [module
/// documentation](self); in parallel, results in the order of `starts`,
/// [`PointPlay::index`] = i, positions frozen).
pub fn play_motion(
    sm: &ScheduleMotion,
    points: &[[f64; 2]],
    starts: &[usize],
    settings: &FieldSettings,
) -> Vec<PointPlay> {
    let shortened = one_period(sm);
    let sm = shortened.as_ref().unwrap_or(sm);
    let opts = PlayOptions::from_settings(settings);
    let frozen = opts.player(sm).frozen();
    // One kinematics table per segment, shared by every part (a memo).
    let tables = frozen.kinematics_tables();
    starts
        .par_iter()
        .map(|&i| play_frozen_point(sm, &frozen.clone().with_tables(&tables), i, points[i]))
        .collect()
}

/// The judge of the trajectory `sm` against `target` under `settings`:
/// the realised field at the judge's points ([`judge_points`],
/// [`play_motion`]) and what it realises against the target, with
/// `predicted` the strength the error against the prediction uses.
///
/// ```
/// use platefield::design::judge::judge;
/// use platefield::design::DesignOptions;
/// use platefield::inverse::run;
/// use platefield::play::ScheduleMotion;
/// use platefield::request::Target;
///
/// let target = Target::from_json_str(r#"{"name": "s", "field": {"kind": "sink"},
///     "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [9, 9]}}"#).unwrap();
/// let sampled = target.sample().unwrap();
/// let design = run(&target, &DesignOptions::default()).unwrap().into_method().unwrap();
/// let schedule = &design.kept().schedule;
/// let sm = ScheduleMotion::from_schedule(schedule).unwrap();
/// let (plays, r) = judge(&target, &sampled, &sm, &schedule.settings, None);
/// assert_eq!(plays.len(), 81);
/// // The headline is this number.
/// let played = schedule.played.as_ref().unwrap();
/// assert_eq!(played.realised_shape_error, Some(r.shape_error));
/// ```
pub fn judge(
    target: &Target,
    sampled: &SampledTarget,
    sm: &ScheduleMotion,
    settings: &FieldSettings,
    predicted: Option<f64>,
) -> (Vec<PointPlay>, RealisedError) {
    let plays = play_motion(
        sm,
        &sampled.points,
        &judge_points(target, sampled),
        settings,
    );
    let r = realised_error(target, &sampled.weights, &plays, predicted);
    (plays, r)
}

/// The judge's measure of `schedule` played under `settings` (its own or
/// other physics; see the [module documentation](self)): the plays at the judge's points and
/// what they realise against `target`, with `predicted` the strength the
/// error against the prediction uses.
pub(crate) fn realised_check(
    target: &Target,
    sampled: &SampledTarget,
    schedule: &Schedule,
    settings: &crate::field::FieldSettings,
    predicted: Option<f64>,
) -> crate::error::Result<(Vec<PointPlay>, RealisedError)> {
    let sm = crate::play::ScheduleMotion::from_schedule(schedule)?;
    Ok(judge(target, sampled, &sm, settings, predicted))
}

/// `realised_check` as a friction sweep's judge: the points played,
/// those that counted, the realised strength and shape error.
pub fn judge_check(
    target: &Target,
    sampled: &SampledTarget,
    schedule: &Schedule,
    settings: &crate::field::FieldSettings,
) -> crate::error::Result<crate::play::sensitivity::Judged> {
    let (plays, r) = realised_check(target, sampled, schedule, settings, None)?;
    Ok(crate::play::sensitivity::Judged {
        points: plays.len(),
        valid: r.valid,
        realised_strength: r.realised_strength,
        shape_error: r.shape_error,
    })
}

/// The work of one judge of a schedule of `per_period` primitive cycles
/// per period (1 for one steady motion, [`one_period`]) over `target`:
/// its points times [`JUDGE_MIN_PERIODS`] periods, at `steps` steps per
/// cycle (a slow transient asks for more periods, up to
/// `crate::play::settle::SETTLE_MAX_CYCLES` cycles).
pub(crate) fn judge_term(
    target: &Target,
    sampled: &SampledTarget,
    per_period: u32,
    steps: usize,
) -> crate::work::Term {
    crate::work::Term::new("judge")
        .times(judge_points(target, sampled).len() as f64, "points")
        .times(f64::from(JUDGE_MIN_PERIODS * per_period.max(1)), "cycles")
        .times(steps as f64, "steps")
}

/// The primitive cycles per period the judge plays `schedule` at: one for
/// one steady motion ([`one_period`]), else the schedule's.
pub(crate) fn judged_cycles(schedule: &crate::schedule::Schedule) -> u32 {
    match ScheduleMotion::from_schedule(schedule) {
        Ok(sm) if one_period(&sm).is_some() => 1,
        _ => schedule.total_cycles.max(1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::{Primitive, PrimitiveKind};

    /// One primitive's motion as a one-segment schedule of 10 cycles.
    fn primitive_schedule(kind: PrimitiveKind) -> ScheduleMotion {
        let motion = Primitive::new(kind).motion();
        ScheduleMotion::new(vec![PlayedSegment::moving("p", motion, 10)]).expect("a schedule")
    }

    /// A held part on the large-amplitude Circle's plate, 3 cm off the
    /// rotation axis, reaches no steady state (its velocity still grows at
    /// the warm-up cap) and the judge leaves it out with that reason; on a
    /// LineSink's plate the same held points all settle and count.
    #[test]
    fn a_held_part_with_no_steady_state_is_invalid() {
        let points = [[0.03, 0.0], [0.0, -0.03], [0.02, 0.02]];
        let starts = [0, 1, 2];
        let settings = FieldSettings::default();
        let played = |kind| play_motion(&primitive_schedule(kind), &points, &starts, &settings);
        for p in &played(PrimitiveKind::Circle) {
            let note = p.note.as_deref().unwrap_or("");
            assert!(
                note.starts_with("no held steady state"),
                "{:?}: {note:?}",
                p.start
            );
            assert!(p.lost_at.is_none() && !p.settled, "{p:?}");
            assert!(!counts(&[1.0; 3], p));
        }
        for p in &played(PrimitiveKind::LineSink) {
            assert!(p.note.is_none() && p.settled, "{p:?}");
            assert!(counts(&[1.0; 3], p));
        }
    }

    /// Both edges on the sub-grid, at least nine points per side, and the
    /// centred stride where n − 1 has no divisor that gives 9–17.
    #[test]
    fn axis_points_keep_the_edges() {
        assert_eq!(axis_points(5), vec![0, 1, 2, 3, 4]);
        assert_eq!(axis_points(13).len(), 13);
        assert_eq!(axis_points(17), (0..17).step_by(2).collect::<Vec<_>>());
        assert_eq!(axis_points(21), (0..21).step_by(2).collect::<Vec<_>>());
        // 1000 intervals: stride 125, the largest divisor giving ≥ 8 intervals.
        assert_eq!(axis_points(1001).len(), 9);
        for n in 2..400 {
            let a = axis_points(n);
            assert!(a.len() >= JUDGE_MIN_PER_SIDE.min(n), "{n}: {a:?}");
            let k = if a.len() > 1 { a[1] - a[0] } else { 1 };
            assert!(a.windows(2).all(|w| w[1] - w[0] == k), "{n}: regular");
            let (first, last) = (a[0], n - 1 - a[a.len() - 1]);
            assert!(
                first.max(last) <= k / 2,
                "{n}: centred within half a stride"
            );
        }
    }
}

#[cfg(test)]
#[path = "../../../tests/unit/judge.rs"]
mod judge_tests;
