//! Realised from the file: a design's exported signals played on its
//! parts, beside the schedule's own play.
//!
//! A design is judged by what parts do when its signals are played
//! (`super::method::realised_check`: moving point parts from about 5 × 5
//! start points over the target, `super::method::CHECK_WARMUP_CYCLES`
//! warm-up and `super::method::CHECK_MEASURED_CYCLES` measured cycles
//! rounded up to whole schedule periods, one window starting at each
//! segment join; realised strength ŝ = the least-squares scale against the
//! target and realised shape error ‖R − ŝt‖/‖ŝt‖). Here that same measure
//! is taken twice under the same physics: of the schedule's motions
//! (**played**) and of the file a controller plays (**replayed**: its held
//! samples integrated exactly from rest at home and cut into the
//! schedule's segments, [`crate::play::replay`]). Only the plate's
//! trajectory differs, so the two agree to what holding the samples
//! changes — second order in ωΔt ([`crate::motion::Held`]) — and a file
//! that is not the schedule's (a channel's sign flipped, another design's
//! export) does not agree.

use super::method::{
    judge_check, realised_check_of, CHECK_MEASURED_CYCLES, CHECK_POINTS, CHECK_WARMUP_CYCLES,
};
use crate::dynamics::Friction;
use crate::error::{Error, Result};
use crate::field::FieldSettings;
use crate::motion::held_csv;
use crate::motion::sample_hold::HoldSamples;
use crate::play::replay::{replay_motion, ReplayCheck};
use crate::play::sensitivity::{friction_sweep, Judged};
use crate::play::ScheduleMotion;
use crate::request::{SampledTarget, Target};
use crate::schedule::export::{export, DEFAULT_STEADY_CYCLES};
use crate::schedule::Schedule;
use crate::work::{Estimate, Term};

/// The rate `platefield export` samples at by default (Hz).
pub(crate) const EXPORT_RATE: f64 = 10_000.0;

/// The design's realised check of the replayed trajectory `sm` (one
/// period `per_period` primitive cycles) under `settings`, as a judge.
pub fn judge_replay(
    target: &Target,
    sampled: &SampledTarget,
    (sm, per_period): (&ScheduleMotion, u32),
    settings: &FieldSettings,
) -> Judged {
    let (plays, r) = realised_check_of(target, sampled, (sm, per_period), settings, None);
    Judged {
        points: plays.len(),
        valid: r.valid,
        realised_strength: r.realised_strength,
        shape_error: r.shape_error,
    }
}

/// `schedule`'s export as `platefield export` writes it (at
/// `EXPORT_RATE`, [`DEFAULT_STEADY_CYCLES`] steady cycles), read back
/// from its CSV text.
///
/// # Errors
/// The schedule cannot be exported.
pub fn exported(schedule: &Schedule) -> Result<HoldSamples> {
    let e = export(schedule, EXPORT_RATE, DEFAULT_STEADY_CYCLES)?;
    held_csv::parse(&e.to_csv(), "export")
}

/// The target `schedule` records, sampled (a replay is judged against it).
fn recorded_target(schedule: &Schedule) -> Result<(&Target, SampledTarget)> {
    let target = schedule.target_spec.as_ref().ok_or_else(|| {
        Error::invalid(
            "--replay",
            "a replay is judged against the schedule's target, and this schedule records none (\"target_spec\")",
        )
    })?;
    Ok((target, target.sample()?))
}

/// Checks, before anything is played, that [`replay_check`] can judge
/// `file` against `schedule`: the schedule records a target and the file's
/// rows fit its segments.
///
/// # Errors
/// As [`replay_check`]'s, without playing.
pub(crate) fn check_replay(schedule: &Schedule, file: &HoldSamples, source: &str) -> Result<()> {
    recorded_target(schedule)?;
    replay_motion(schedule, file, source).map(|_| ())
}

/// Plays `schedule` and replays `file` (its export; `source` names it)
/// at `friction` (default: the schedule's), by the design's realised
/// check (see the [module documentation](self)).
///
/// ```no_run
/// use platefield::design::replay::{exported, replay_check};
/// use platefield::schedule::Schedule;
///
/// let schedule = Schedule::load("results/sequenced/sink/schedule.json".as_ref()).unwrap();
/// let check = replay_check(&schedule, &exported(&schedule).unwrap(), "export", None).unwrap();
/// assert!(check.strength_gap() < 0.01);
/// ```
///
/// # Errors
/// The schedule records no target or cannot be played; the file does not
/// fit it (names `source`).
pub fn replay_check(
    schedule: &Schedule,
    file: &HoldSamples,
    source: &str,
    friction: Option<Friction>,
) -> Result<ReplayCheck> {
    let (target, sampled) = recorded_target(schedule)?;
    let sm = replay_motion(schedule, file, source)?;
    let friction = [friction.unwrap_or(schedule.settings.friction)];
    let base = &schedule.settings;
    let played = friction_sweep(base, &friction, &|settings| {
        judge_check(target, &sampled, schedule, settings)
    })?;
    let replayed = friction_sweep(base, &friction, &|settings| {
        Ok(judge_replay(
            target,
            &sampled,
            (&sm, schedule.total_cycles),
            settings,
        ))
    })?;
    Ok(ReplayCheck {
        file: source.into(),
        played: played[0].clone(),
        replayed: replayed[0].clone(),
    })
}

/// The work of [`replay_check`] of a file sampled at `rate`: the realised
/// check's parts and cycles, played at `steps_per_cycle` steps per cycle
/// and replayed at one step (at least) per held sample (a 10 kHz file of a
/// 0.03 s primitive: about 5 times as many).
pub(crate) fn replay_estimate(schedule: &Schedule, rate: f64) -> Estimate {
    let per_period = schedule.total_cycles.max(1);
    let periods =
        CHECK_WARMUP_CYCLES.div_ceil(per_period) + CHECK_MEASURED_CYCLES.div_ceil(per_period);
    let cycle = schedule
        .segments
        .iter()
        .find_map(|s| s.cycle_period())
        .unwrap_or(schedule.period_s);
    let steps = schedule.settings.numerics.steps_per_cycle as f64;
    Estimate::new(
        "--replay",
        "playing the schedule and replaying its export",
        "an export at a lower --rate",
    )
    .plus(
        Term::new("played and replayed")
            .times((CHECK_POINTS * CHECK_POINTS) as f64, "parts")
            .times(f64::from(periods * per_period), "cycles")
            .times(steps + (rate * cycle).max(steps), "steps"),
    )
}
