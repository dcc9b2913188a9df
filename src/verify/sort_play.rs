//! Every class of a sort played ([`crate::design::sort`]; here in
//! `verify`, the layer above the design's judge, beside its
//! swarm): the realised
//! field of each class at its own friction, and where a swarm of its parts
//! ends up.
//!
//! **Measures.** Per class, at the class's nominal friction:
//! * the realised strength and shape error: the design's one realised
//!   check (`crate::design::judge::realised_check`) against the class's
//!   own field;
//! * a swarm of point parts started on a grid over the target region
//!   (`SORT_STARTS` per axis, `crate::verify::swarm`) played for
//!   whole schedule periods, the same for every class (as on one plate):
//!   enough for the slowest class's predicted field to bring its farthest
//!   part within `SORT_TOL` twice over, at most `MAX_SORT_PERIODS`: the fraction of its parts that end within
//!   `SORT_TOL` of its own attractor, and the fraction that end within
//!   `SORT_TOL` of another class's attractor (the mix-up);
//! * the **time to sort**: the time by which at least [`SORT_SHARE`] of the
//!   class's swarm is within `SORT_TOL` of its own attractor and stays
//!   there to the end of the play (the ⌈0.95 n⌉-th smallest of the parts'
//!   times to converge, `crate::verify::swarm`; `None` when fewer
//!   converge within the play). A sort's time is its slowest class's.
//!
//! [`play_sort`] plays every candidate of a sort and keeps the one with
//! the shortest time to sort (one that does not sort within its play ranks
//! last; ties by the least share at the own attractor, higher first).
//! Every candidate is played for at least [`MIN_SORT_PLAY_S`] and
//! [`SORT_HOLD_S`] beyond, so a candidate sorted within
//! [`MIN_SORT_PLAY_S`] is seen to stay sorted for [`SORT_HOLD_S`] (a play
//! that ends just after the time judged cannot tell a sorted swarm from
//! one whose parts swing out of `SORT_TOL` once a period: such a play
//! reads the time of the parts' last swing out, just before its end); the
//! synthesized candidates are played first, and once one has sorted in T
//! the rest are played max(T, [`MIN_SORT_PLAY_S`]) + [`SORT_HOLD_S`] only
//! (a candidate not sorted by T cannot be the faster, so a slow one, as
//! the primitives' fit of `targets/sort_friction.json`, is not played to
//! its own sort).

use serde::Serialize;

use super::swarm::{run_swarm, SwarmOptions};
use crate::design::judge::realised_check;
use crate::design::replay::judge_replay;
use crate::design::sort::swarm::{first_exit, swarm_starts, time_to_share};
use crate::design::sort::SortDesign;
use crate::error::Result;
use crate::field::FieldSettings;
use crate::motion::sample_hold::HoldSamples;
use crate::play::replay::replay_motion;
use crate::play::{PlayOptions, ScheduleMotion};
use crate::progress::Progress;
use crate::request::{Attractor, Edge, SampledTarget, Target};
use crate::schedule::Schedule;
use crate::work::{Estimate, Runtime, Term};

/// Distance (m) to an attractor within which a part counts as there: 5 mm.
pub const SORT_TOL: f64 = 5e-3;
/// Most schedule periods a swarm is played.
pub(crate) const MAX_SORT_PERIODS: u32 = 40;
/// Share of a class that must be at its own attractor for it to be sorted.
pub const SORT_SHARE: f64 = 0.95;
/// Least time (s) a sort candidate is judged over: it is played this
/// long and [`SORT_HOLD_S`] beyond (whole periods).
pub const MIN_SORT_PLAY_S: f64 = 60.0;
/// Time (s) a sort candidate is played beyond the time it is judged
/// against, so that a class sorted by then is seen to stay sorted (module
/// docs).
pub const SORT_HOLD_S: f64 = 30.0;

/// One class played.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClassPlay {
    /// The class's name.
    pub name: String,
    /// Nominal static friction played.
    pub friction: f64,
    /// Realised strength ŝ against the class's field.
    pub realised_strength: f64,
    /// Realised shape error at ŝ.
    pub realised_shape_error: f64,
    /// Swarm parts.
    pub parts: usize,
    /// Time played (s).
    pub duration_s: f64,
    /// Fraction ending within `SORT_TOL` of the class's own attractor.
    pub at_own: Option<f64>,
    /// Fraction ending within `SORT_TOL` of another class's attractor.
    pub mixed_up: f64,
    /// Parts that lost contact.
    pub contact_lost: usize,
    /// Median distance (m) of the parts' ends from the own attractor.
    pub median_distance_m: Option<f64>,
    /// Time (s) by which [`SORT_SHARE`] of the swarm is within `SORT_TOL`
    /// of its own attractor and stays there (module docs).
    pub time_to_sort_s: Option<f64>,
    /// For a lane (a class with an `exit`): the edge and the mean exit
    /// time; `at_own` is then the fraction that left through its own
    /// edge, `mixed_up` through another, `time_to_sort_s` the time by
    /// which [`SORT_SHARE`] left through its own.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub exit: Option<LaneExit>,
    /// Per part, its time to converge to its own attractor (s) (for a
    /// lane: to leave through its own edge), `None` when it does not
    /// within the play: the fraction-against-time curve.
    #[serde(skip)]
    pub arrivals: Vec<Option<f64>>,
}

/// A lane class's swarm: which edge it should leave through and how.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LaneExit {
    /// The edge of the region the class should leave through.
    pub edge: Edge,
    /// Fraction of the swarm that left through it.
    pub through_own: f64,
    /// Fraction that left through another edge.
    pub through_other: f64,
    /// Mean time (s) of the exits through its own edge.
    pub mean_exit_time_s: Option<f64>,
}

/// Where each of a lane class's swarm `parts` (played by `sm`) first
/// leaves the target's region (the box of its grid; positions recorded
/// at segment ends, the crossing interpolated along the straight move
/// between two), against its own `edge`: the [`LaneExit`] and, per part,
/// its exit time through its own edge.
fn lane_exits(
    target: &Target,
    sm: &ScheduleMotion,
    parts: &[crate::verify::swarm::SwarmPart],
    edge: Edge,
) -> (LaneExit, Vec<Option<f64>>) {
    let g = target
        .grid
        .as_ref()
        .expect("a classes target has a grid (validated)");
    let durations: Vec<f64> = sm.segments().iter().map(|s| s.duration).collect();
    let mut own = Vec::new();
    let mut other = 0;
    for p in parts {
        match first_exit(&p.path, &durations, g.x, g.y) {
            Some((e, t)) if e == edge => own.push(Some(t)),
            Some(_) => {
                other += 1;
                own.push(None);
            }
            None => own.push(None),
        }
    }
    let n = parts.len().max(1) as f64;
    let times: Vec<f64> = own.iter().flatten().copied().collect();
    let lane = LaneExit {
        edge,
        through_own: times.len() as f64 / n,
        through_other: f64::from(other) / n,
        mean_exit_time_s: (!times.is_empty())
            .then(|| times.iter().sum::<f64>() / times.len() as f64),
    };
    (lane, own)
}

impl ClassPlay {
    /// The fraction of the swarm within `SORT_TOL` of its own attractor
    /// from time `t` (s) on.
    ///
    /// ```
    /// # use platefield::verify::sort_play::ClassPlay;
    /// # fn f(c: &ClassPlay) { let _ = c.sorted_at(30.0); }
    /// ```
    pub fn sorted_at(&self, t: f64) -> f64 {
        let n = self.arrivals.len().max(1) as f64;
        self.arrivals
            .iter()
            .filter(|a| a.is_some_and(|a| a <= t))
            .count() as f64
            / n
    }

    /// The time (s) by which `share` of the swarm is within `SORT_TOL` of
    /// its own attractor and stays there (the ⌈share·n⌉-th smallest of
    /// the parts' times to converge); `None` when fewer converge within
    /// the play. [`ClassPlay::time_to_sort_s`] is this at [`SORT_SHARE`].
    ///
    /// ```
    /// # use platefield::verify::sort_play::ClassPlay;
    /// # fn f(c: &ClassPlay) { let _ = c.time_to(0.9); }
    /// ```
    pub fn time_to(&self, share: f64) -> Option<f64> {
        time_to_share(&self.arrivals, share)
    }
}

/// One sort candidate played.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SortPlay {
    /// The candidate's method (`primitives`, `synthesized`).
    pub method: String,
    /// Its schedule's period (s).
    pub period_s: f64,
    /// Time played (s), the same for every class.
    pub played_s: f64,
    /// The slowest class's time to sort (s); `None` when a class is not
    /// sorted within the play.
    pub time_to_sort_s: Option<f64>,
    /// Per class.
    pub classes: Vec<ClassPlay>,
}

/// Every candidate played and the one kept.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SortOutcome {
    /// Index of the kept candidate.
    pub kept: usize,
    /// Per candidate, in the design's order.
    pub plays: Vec<SortPlay>,
}

impl SortOutcome {
    /// The kept candidate's play.
    pub fn kept(&self) -> &SortPlay {
        &self.plays[self.kept]
    }
}

/// Plays every candidate of a sort (`play_classes`, at least
/// [`MIN_SORT_PLAY_S`] + [`SORT_HOLD_S`]) and keeps the one that sorts soonest (module
/// docs).
///
/// ```no_run
/// use platefield::design::{sort::design_sort, DesignOptions};
/// use platefield::request::Target;
/// use platefield::verify::sort_play::play_sort;
/// let target = Target::load(std::path::Path::new("targets/sort_friction.json"))?;
/// let candidates = design_sort(&target, &DesignOptions::default())?;
/// let out = play_sort(&target, &candidates, &platefield::work::Runtime::QUIET)?;
/// println!("kept {}: sorted in {:?} s", out.kept().method, out.kept().time_to_sort_s);
/// # Ok::<(), platefield::Error>(())
/// ```
///
/// # Errors
/// No candidate; those of `play_classes`.
pub fn play_sort(
    target: &Target,
    candidates: &[SortDesign],
    runtime: &Runtime,
) -> Result<SortOutcome> {
    // The synthesized candidates first: once one has sorted in T, the
    // others are played max(T, MIN_SORT_PLAY_S) + SORT_HOLD_S only (whole
    // periods): one that has not sorted by T is not the faster.
    let mut order: Vec<usize> = (0..candidates.len()).collect();
    order.sort_by_key(|&i| candidates[i].motions.is_empty());
    let mut best: Option<f64> = None;
    let mut plays: Vec<Option<SortPlay>> = vec![None; candidates.len()];
    for i in order {
        let d = &candidates[i];
        let periods = best.map(|t| {
            let p = ((t.max(MIN_SORT_PLAY_S) + SORT_HOLD_S) / d.schedule.period_s).ceil();
            if p.is_finite() && p >= 1.0 {
                p as u32
            } else {
                1
            }
        });
        let classes = play_classes(target, d, periods, runtime)?;
        let time_to_sort_s = classes
            .iter()
            .map(|c| c.time_to_sort_s)
            .try_fold(0.0_f64, |a, t| t.map(|t| a.max(t)));
        if let Some(t) = time_to_sort_s {
            best = Some(best.map_or(t, |b: f64| b.min(t)));
        }
        plays[i] = Some(SortPlay {
            method: d.label(),
            period_s: d.schedule.period_s,
            played_s: classes.first().map_or(0.0, |c| c.duration_s),
            time_to_sort_s,
            classes,
        });
    }
    let plays: Vec<SortPlay> = plays.into_iter().flatten().collect();
    let rank = |p: &SortPlay| {
        let least = p
            .classes
            .iter()
            .map(|c| c.at_own.unwrap_or(0.0))
            .fold(f64::INFINITY, f64::min);
        (p.time_to_sort_s.unwrap_or(f64::INFINITY), -least)
    };
    let kept = (0..plays.len())
        .min_by(|&a, &b| {
            let (x, y) = (rank(&plays[a]), rank(&plays[b]));
            x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1))
        })
        .ok_or_else(|| crate::error::Error::invalid("candidates", "no sort candidate to play"))?;
    Ok(SortOutcome { kept, plays })
}

/// Plays every class of `design` (see the module docs). `periods`: the
/// swarms' schedule periods (`None`: from the predicted strengths).
pub(crate) fn play_classes(
    target: &Target,
    design: &SortDesign,
    periods: Option<u32>,
    runtime: &Runtime,
) -> Result<Vec<ClassPlay>> {
    let attractors = class_attractors(target);
    let sm = ScheduleMotion::from_schedule(&design.schedule)?;
    let starts = swarm_starts(target);
    // Every class for the same time, as on one plate: the slowest class's.
    let periods = periods.unwrap_or_else(|| {
        design
            .classes
            .iter()
            .zip(&attractors)
            .map(|(fit, own)| swarm_periods(*own, &starts, fit.strength, &sm))
            .max()
            .unwrap_or(1)
            .max(min_periods(&sm))
    });
    runtime.admit(&play_estimate(
        &design.schedule,
        target.classes.len(),
        starts.len(),
        periods,
        class_judge(target, &design.schedule)?,
    ))?;
    let strengths: Vec<f64> = design.classes.iter().map(|c| c.strength).collect();
    play_each_class(
        target,
        &ClassMotion {
            sm: &sm,
            label: "sort: plays",
            realised: &|ct, sampled, settings, strength| {
                let (_, r) =
                    realised_check(ct, sampled, &design.schedule, settings, Some(strength))?;
                Ok((r.realised_strength, r.shape_error))
            },
        },
        &design.schedule.settings,
        &strengths,
        periods,
        runtime,
    )
}

/// The classes' attractors, in the target's order.
fn class_attractors(target: &Target) -> Vec<Option<Attractor>> {
    target
        .classes
        .iter()
        .map(|c| Attractor::of(&c.field))
        .collect()
}

/// The judge's work of one class of `target` under `schedule`
/// (`crate::design::judge::judge_term`).
fn class_judge(target: &Target, schedule: &Schedule) -> Result<Term> {
    let ct = target.class_target(0);
    let sampled = ct.sample()?;
    Ok(crate::design::judge::judge_term(
        &ct,
        &sampled,
        crate::design::judge::judged_cycles(schedule),
        schedule.settings.numerics.steps_per_cycle,
    ))
}

/// The realised strength and shape error of a class (its target, sampled,
/// under its physics, against the strength its design predicts).
type Realised<'a> = dyn Fn(&Target, &SampledTarget, &FieldSettings, f64) -> Result<(f64, f64)> + 'a;

/// What the classes' swarms are played with: the plate's trajectory and
/// the realised check of each class under it.
struct ClassMotion<'a> {
    sm: &'a ScheduleMotion,
    /// The progress bar's label.
    label: &'static str,
    realised: &'a Realised<'a>,
}

/// Every class of `target` played by `motion` for `periods` periods at
/// its own friction (`base` with the class's physics): the realised check
/// and the swarm's measures (module docs). `strengths`: per class, the
/// strength the design predicts (the swarm's predicted times).
fn play_each_class(
    target: &Target,
    motion: &ClassMotion<'_>,
    base: &FieldSettings,
    strengths: &[f64],
    periods: u32,
    runtime: &Runtime,
) -> Result<Vec<ClassPlay>> {
    let attractors = class_attractors(target);
    let starts = swarm_starts(target);
    let progress = Progress::new(
        motion.label,
        "classes",
        target.classes.len() as u64,
        runtime.progress(),
    );
    let mut out = Vec::new();
    for (i, class) in target.classes.iter().enumerate() {
        progress.set_message(format!("class {}", class.name));
        let ct = target.class_target(i);
        let settings = ct.physics(base);
        let sampled = ct.sample()?;
        let strength = strengths.get(i).copied().unwrap_or(0.0);
        let (realised_strength, realised_shape_error) =
            (motion.realised)(&ct, &sampled, &settings, strength)?;
        let own = attractors[i];
        let swarm = run_swarm(
            motion.sm,
            &starts,
            own,
            &SwarmOptions {
                verify: PlayOptions::from_settings(&settings),
                periods,
                tol: SORT_TOL,
                strength,
            },
        );
        let others: Vec<Attractor> = attractors
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .filter_map(|(_, a)| *a)
            .collect();
        let (at_own, mixed_up) = arrivals(&swarm.parts, own, &others);
        let distances: Vec<f64> = swarm.parts.iter().map(|p| p.distance[1]).collect();
        let mut arrivals: Vec<Option<f64>> = swarm
            .parts
            .iter()
            .map(|p| p.time_to_converge_s.filter(|_| p.note.is_none()))
            .collect();
        let (mut at_own, mut mixed_up) = (at_own, mixed_up);
        let exit = class.exit.map(|edge| {
            let (lane, exits) = lane_exits(target, motion.sm, &swarm.parts, edge);
            at_own = Some(lane.through_own);
            mixed_up = lane.through_other;
            arrivals = exits;
            lane
        });
        out.push(ClassPlay {
            exit,
            name: class.name.clone(),
            friction: settings.friction.stat,
            realised_strength,
            realised_shape_error,
            parts: swarm.parts.len(),
            duration_s: swarm.duration_s,
            at_own,
            mixed_up,
            contact_lost: swarm.contact_lost,
            median_distance_m: own.and_then(|_| crate::verify::swarm::median(&distances)),
            time_to_sort_s: time_to_share(&arrivals, SORT_SHARE),
            arrivals,
        });
        progress.inc(1);
    }
    progress.finish();
    Ok(out)
}

/// A sort's schedule verified class by class (`platefield verify` of a
/// schedule whose target has classes): every class's swarm played by the
/// schedule's motions and, with an export, by the export's held samples
/// replayed (`crate::play::replay`), each at the class's own friction, by
/// the measures of the design's plays (module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SortVerify {
    /// Time played (s), the same for every class.
    pub played_s: f64,
    /// The schedule's motions played, per class.
    pub played: Vec<ClassPlay>,
    /// The export replayed: the file's name and, per class, its play.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub replayed: Option<(String, Vec<ClassPlay>)>,
}

impl SortVerify {
    /// The slowest class's time to sort (s) of `plays`; `None` when a
    /// class is not sorted within the play.
    ///
    /// ```
    /// use platefield::verify::sort_play::SortVerify;
    /// let v = SortVerify { played_s: 60.0, played: Vec::new(), replayed: None };
    /// assert_eq!(SortVerify::time_to_sort(&v.played), Some(0.0));
    /// ```
    pub fn time_to_sort(plays: &[ClassPlay]) -> Option<f64> {
        plays
            .iter()
            .map(|c| c.time_to_sort_s)
            .try_fold(0.0_f64, |a, t| t.map(|t| a.max(t)))
    }
}

/// Schedule periods a verification plays a sort's swarms: `asked`, else
/// at least [`MIN_SORT_PLAY_S`] + [`SORT_HOLD_S`] (the design's least
/// play) in whole periods of `schedule`.
///
/// # Errors
/// The schedule cannot be played.
pub fn verify_periods(schedule: &Schedule, asked: Option<u32>) -> Result<u32> {
    let sm = ScheduleMotion::from_schedule(schedule)?;
    Ok(asked.unwrap_or_else(|| min_periods(&sm)))
}

/// The work of [`verify_sort`] of `schedule` (its target's classes, the
/// swarms played `periods` periods, and replayed too when `replay_rate`
/// (samples/s) is given), `None` when its target has no classes.
///
/// # Errors
/// A class whose target cannot be sampled.
pub(crate) fn verify_estimate(
    schedule: &Schedule,
    periods: u32,
    replay_rate: Option<f64>,
) -> Result<Option<Estimate>> {
    let Some(target) = classes_target(schedule) else {
        return Ok(None);
    };
    let judge = class_judge(target, schedule)?;
    let n = target.classes.len();
    let parts = swarm_starts(target).len();
    let played = play_estimate(schedule, n, parts, periods, judge.clone());
    let Some(rate) = replay_rate else {
        return Ok(Some(played));
    };
    // The replay's part steps: at least one per held sample
    // (`crate::design::replay` counts its judge the same way).
    let steps = schedule.settings.numerics.steps_per_cycle as f64;
    let cycle = schedule
        .segments
        .iter()
        .find_map(|s| s.cycle_period())
        .unwrap_or(schedule.period_s);
    let per_step = (rate * cycle / steps).max(1.0);
    let mut e = played;
    for t in play_estimate(schedule, n, parts, periods, judge).terms {
        e = e.plus(t.named("replayed").times(per_step, "held samples per step"));
    }
    Ok(Some(e))
}

/// Whether `schedule` is a sort's: the target it records has classes.
pub(crate) fn is_sort(schedule: &Schedule) -> bool {
    classes_target(schedule).is_some()
}

/// The target `schedule` records when it has classes.
fn classes_target(schedule: &Schedule) -> Option<&Target> {
    schedule
        .target_spec
        .as_ref()
        .filter(|t| t.classes.len() >= 2)
}

/// Verifies a sort's `schedule` class by class ([`SortVerify`]) for
/// `periods` schedule periods ([`verify_periods`]): the schedule played
/// and, with `replay` (the export's held samples and the file's name),
/// the export replayed. `None` when the schedule's target has no classes.
///
/// ```no_run
/// use platefield::design::replay::exported;
/// use platefield::schedule::Schedule;
/// use platefield::verify::sort_play::{verify_periods, verify_sort};
/// let s = Schedule::load("results/sort_friction/schedule.json".as_ref())?;
/// let file = exported(&s)?;
/// let v = verify_sort(&s, Some((&file, "export")), verify_periods(&s, None)?, &platefield::work::Runtime::QUIET)?
///     .expect("a sort");
/// for c in &v.replayed.as_ref().unwrap().1 {
///     println!("{}: sorted in {:?} s", c.name, c.time_to_sort_s);
/// }
/// # Ok::<(), platefield::Error>(())
/// ```
///
/// # Errors
/// The schedule cannot be played; the file does not fit it (names the
/// file).
pub fn verify_sort(
    schedule: &Schedule,
    replay: Option<(&HoldSamples, &str)>,
    periods: u32,
    runtime: &Runtime,
) -> Result<Option<SortVerify>> {
    let Some(target) = classes_target(schedule) else {
        return Ok(None);
    };
    let sm = ScheduleMotion::from_schedule(schedule)?;
    // The design's per-class strengths are not in the schedule: its one
    // fitted strength stands for every class's predicted times.
    let strengths = vec![schedule.fit_quantized.strength; target.classes.len()];
    let played = play_each_class(
        target,
        &ClassMotion {
            sm: &sm,
            label: "sort: schedule played",
            realised: &|ct, sampled, settings, _| {
                let (_, r) = realised_check(ct, sampled, schedule, settings, None)?;
                Ok((r.realised_strength, r.shape_error))
            },
        },
        &schedule.settings,
        &strengths,
        periods,
        runtime,
    )?;
    let replayed = match replay {
        Some((file, source)) => {
            let rm = replay_motion(schedule, file, source)?;
            let plays = play_each_class(
                target,
                &ClassMotion {
                    sm: &rm,
                    label: "sort: export replayed",
                    realised: &|ct, sampled, settings, _| {
                        let j = judge_replay(ct, sampled, &rm, settings);
                        Ok((j.realised_strength, j.shape_error))
                    },
                },
                &schedule.settings,
                &strengths,
                periods,
                runtime,
            )?;
            Some((source.to_string(), plays))
        }
        None => None,
    };
    Ok(Some(SortVerify {
        played_s: f64::from(periods) * sm.period(),
        played,
        replayed,
    }))
}

/// The fractions of a class's swarm `parts` that end (without a note)
/// within [`SORT_TOL`] of its own attractor `own`, and of any of the
/// `others`: at its own, and mixed up.
fn arrivals(
    parts: &[crate::verify::swarm::SwarmPart],
    own: Option<Attractor>,
    others: &[Attractor],
) -> (Option<f64>, f64) {
    let n = parts.len().max(1) as f64;
    let near = |a: &Attractor, p: [f64; 2]| a.distance(p) <= SORT_TOL;
    let at_own = own.map(|a| {
        parts
            .iter()
            .filter(|p| p.note.is_none() && near(&a, p.end))
            .count() as f64
            / n
    });
    let mixed_up = parts
        .iter()
        .filter(|p| p.note.is_none() && others.iter().any(|a| near(a, p.end)))
        .count() as f64
        / n;
    (at_own, mixed_up)
}

/// Whole periods of `sm` that play at least [`MIN_SORT_PLAY_S`] +
/// [`SORT_HOLD_S`] (more than [`MAX_SORT_PERIODS`] for a schedule shorter
/// than 2.25 s).
fn min_periods(sm: &ScheduleMotion) -> u32 {
    let p = ((MIN_SORT_PLAY_S + SORT_HOLD_S) / sm.period()).ceil();
    if p.is_finite() && p >= 1.0 {
        p as u32
    } else {
        1
    }
}

/// The work of [`play_classes`] ([`crate::work`]): per class (of
/// `classes`) its swarm of `parts` parts played `periods` periods of
/// `schedule`, and its judge (`judge`, `crate::design::judge::judge_term`
/// of one class).
pub(crate) fn play_estimate(
    schedule: &Schedule,
    classes: usize,
    parts: usize,
    periods: u32,
    judge: Term,
) -> Estimate {
    let steps = schedule.settings.numerics.steps_per_cycle as f64;
    let cycles = f64::from(schedule.total_cycles);
    Estimate::new(
        "target",
        "playing the sort's classes",
        "fewer classes or a schedule of fewer cycles",
    )
    .plus(
        Term::new("swarms")
            .times(classes as f64, "classes")
            .times(parts as f64, "parts")
            .times(f64::from(periods), "periods")
            .times(cycles, "cycles")
            .times(steps, "steps"),
    )
    .plus(judge.named("judges").times(classes as f64, "classes"))
}

/// Whole periods for the predicted field to bring the farthest start
/// within [`SORT_TOL`] twice over, in 1..=[`MAX_SORT_PERIODS`].
fn swarm_periods(
    own: Option<Attractor>,
    starts: &[[f64; 2]],
    strength: f64,
    sm: &ScheduleMotion,
) -> u32 {
    let slowest = own.map_or(0.0, |a| {
        starts
            .iter()
            .map(|p| a.predicted_time(*p, strength, SORT_TOL))
            .fold(0.0, f64::max)
    });
    let periods = (2.0 * slowest / sm.period()).ceil();
    if periods.is_finite() {
        (periods as u32).clamp(1, MAX_SORT_PERIODS)
    } else {
        MAX_SORT_PERIODS
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lane's exits from hand-made paths (segment ends 1 s apart, the
    /// region x ±3 cm, y ±1 cm): through the left edge at 2.5 s (the
    /// crossing halfway between the ends at 2 s and 3 s), through the
    /// right edge, through the top, and not at all.
    #[test]
    fn lane_exits_find_the_first_edge_crossed_and_its_time() {
        use crate::play::PlayedSegment;
        use crate::verify::swarm::SwarmPart;
        let target = Target::from_json_str(
            r#"{"grid": {"x": [-0.03, 0.03], "y": [-0.01, 0.01], "n": [7, 3]},
                "classes": [
                  {"name": "a", "friction": 0.2, "exit": "left", "field": {"kind": "trans", "direction": 180}},
                  {"name": "b", "friction": 0.45, "exit": "right", "field": {"kind": "trans"}}]}"#,
        )
        .unwrap();
        let sm = ScheduleMotion::new(vec![PlayedSegment::rest(1.0)]).unwrap();
        let part = |path: Vec<[f64; 2]>| SwarmPart {
            start: path[0],
            end: path[path.len() - 1],
            distance: [f64::NAN; 2],
            converged: false,
            time_to_converge_s: None,
            predicted_time_s: None,
            note: None,
            path,
        };
        let parts = [
            part(vec![[0.0, 0.0], [-0.01, 0.0], [-0.02, 0.0], [-0.04, 0.0]]),
            part(vec![[0.0, 0.0], [0.025, 0.0], [0.035, 0.0]]),
            part(vec![[0.0, 0.0], [-0.01, 0.02]]),
            part(vec![[0.0, 0.0], [0.01, 0.005]]),
        ];
        let (lane, times) = lane_exits(&target, &sm, &parts, Edge::Left);
        assert_eq!(times, vec![Some(2.5), None, None, None]);
        assert_eq!(lane.through_own, 0.25);
        assert_eq!(lane.through_other, 0.5);
        assert_eq!(lane.mean_exit_time_s, Some(2.5));
    }

    /// The design aims by the sort's goal: its lanes' share, its largest
    /// swing within a period (half the distance a part may be from its
    /// attractor) and the farthest settled reach its cycle aim offers are
    /// this module's.
    #[test]
    fn the_design_aims_by_the_goal() {
        assert_eq!(crate::design::sort::LANE_SHARE, SORT_SHARE);
        assert_eq!(crate::design::sort::EXCURSION_MAX, 0.5 * SORT_TOL);
        assert_eq!(crate::design::sort::CYCLE_REACH_MAX, SORT_TOL);
    }

    /// The time to sort is the ⌈0.95 n⌉-th arrival: of 20 parts the 19th,
    /// of 45 the 43rd; one part short of the share, none.
    #[test]
    fn time_to_sort_is_the_share_s_order_statistic() {
        let twenty: Vec<Option<f64>> = (1..=20).map(|k| Some(f64::from(k))).collect();
        assert_eq!(time_to_share(&twenty, SORT_SHARE), Some(19.0));
        let mut forty_five: Vec<Option<f64>> = (1..=45).map(|k| Some(f64::from(k))).collect();
        assert_eq!(time_to_share(&forty_five, SORT_SHARE), Some(43.0));
        forty_five[0] = None;
        forty_five[1] = None;
        forty_five[2] = None;
        assert_eq!(time_to_share(&forty_five, SORT_SHARE), None);
        let c = ClassPlay {
            name: "a".into(),
            friction: 0.2,
            realised_strength: 0.0,
            realised_shape_error: 0.0,
            parts: 4,
            duration_s: 10.0,
            at_own: Some(0.75),
            mixed_up: 0.0,
            contact_lost: 0,
            median_distance_m: None,
            time_to_sort_s: None,
            exit: None,
            arrivals: vec![Some(1.0), Some(2.0), None, Some(8.0)],
        };
        assert_eq!(c.sorted_at(2.0), 0.5);
        assert_eq!(c.sorted_at(9.0), 0.75);
    }

    /// A worked example of `verify::sort_play::play_classes`.
    #[allow(dead_code)]
    fn example_play_classes() -> Result<(), crate::Error> {
        use crate::design::{sort::design_sort_primitives, DesignOptions};
        use crate::request::Target;
        use crate::verify::sort_play::play_classes;
        let target = Target::load(std::path::Path::new("targets/sort_friction.json"))?;
        let d = design_sort_primitives(&target, &DesignOptions::default())?;
        for c in play_classes(&target, &d, None, &crate::work::Runtime::QUIET)? {
            println!(
                "{}: {:?} at its own sink, {} mixed up",
                c.name, c.at_own, c.mixed_up
            );
        }
        Ok(())
    }

    /// A worked example of `verify::sort_play::is_sort`.
    #[test]
    fn example_is_sort() -> Result<(), crate::Error> {
        use crate::schedule::Schedule;
        let s = Schedule::load("results/sort_friction/schedule.json".as_ref())?;
        assert!(crate::verify::sort_play::is_sort(&s));
        Ok(())
    }
}
