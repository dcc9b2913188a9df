//! Aiming a sink sort's candidate by its segments' whole cycles (see the
//! parent module's **Cycle aim**): the columns and their order fixed, each
//! segment's cycles moved by a few in turn, the change kept that brings
//! the worst class's settled orbit nearest its attractor, as played.

use rayon::prelude::*;

use super::aim::{played_path, AIM_PLAY_S};
use super::SortDesign;
use crate::error::Result;
use crate::play::{PlayOptions, ScheduleMotion};
use crate::request::{Attractor, Target};
use crate::schedule::Schedule;

/// The changes of a segment's cycles tried at each step of the cycle aim.
pub const CYCLE_STEPS: [i32; 4] = [-2, -1, 1, 2];

/// Most steps of the cycle aim from each of its starts (each step plays
/// every segment's [`CYCLE_STEPS`] changes once).
pub const CYCLE_SWEEPS: usize = 4;

/// The cycle aim's starts: the candidate's period scaled by each (every
/// segment's cycles between its ramps scaled and rounded). A part swings
/// along its orbit by what each segment carries it, so a shorter period
/// swings less: on `targets/sort_three.json` an orbit can span more than
/// the 10 mm a class may span within 5 mm of its sink however it is
/// centred, and about half that at half the period.
pub const CYCLE_PERIOD_SCALES: [f64; 2] = [1.0, 0.5];

/// A schedule aimed by its cycles is offered only when its settled
/// orbits all stay within this (m) of their attractors, at every segment
/// end: the 5 mm a part may be from its attractor to count as there
/// (`crate::verify::sort_play::SORT_TOL`; its tests hold the two equal).
pub const CYCLE_REACH_MAX: f64 = 5e-3;

/// A candidate whose settled orbits all stay within this (m) of their
/// attractors, at every segment end, is not aimed by its cycles: half of
/// [`CYCLE_REACH_MAX`].
pub const CYCLE_REACH_OK: f64 = 0.5 * CYCLE_REACH_MAX;

/// The settled reach of `schedule`'s classes: per class with an
/// attractor, the largest distance (m) from it, at the segment ends of
/// the last period, of a part started at it and played [`AIM_PLAY_S`]
/// (whole periods, at least two) at the class's friction (every part of
/// a class settles on one orbit: on `targets/sort_three.json` parts
/// started at and around each sink end on it, far within the reach
/// asked for); infinite when the part loses contact. `None` for a class
/// without an attractor.
///
/// # Errors
/// The schedule cannot be played.
pub(crate) fn settled_reach(target: &Target, schedule: &Schedule) -> Result<Vec<Option<f64>>> {
    let sm = ScheduleMotion::from_schedule(schedule)?;
    let periods = ((AIM_PLAY_S / sm.period()).ceil() as u32).max(2);
    let segments = sm.segments().len();
    (0..target.classes.len())
        .into_par_iter()
        .map(|i| {
            let ct = target.class_target(i);
            let Some(a) = Attractor::of(&ct.field) else {
                return Ok(None);
            };
            let start = match a {
                Attractor::Point { center, .. } => center,
                Attractor::Line { point, .. } => point,
            };
            let v = PlayOptions::from_settings(&ct.physics(&schedule.settings));
            Ok(Some(match played_path(&sm, &v, start, periods) {
                Some(path) => path[path.len().saturating_sub(segments)..]
                    .iter()
                    .map(|(_, q)| a.distance(*q))
                    .fold(0.0, f64::max),
                None => f64::INFINITY,
            }))
        })
        .collect()
}

/// The worst class's settled reach ([`settled_reach`]); 0 when no class
/// has an attractor.
fn worst(reach: &[Option<f64>]) -> f64 {
    reach.iter().flatten().copied().fold(0.0, f64::max)
}

/// The least cycles of `schedule`'s segment `seg`: the schedule's
/// minimum (at least 1) and, for a ramped segment, its two ramps.
fn least_cycles(schedule: &Schedule, seg: &crate::schedule::Segment) -> u32 {
    schedule
        .min_cycles
        .max(1)
        .max(2 * seg.ramp_cycles.unwrap_or(0))
}

/// `schedule` with segment `i`'s cycles changed by `delta`; `None` when
/// that leaves it below its least cycles or it is a rest.
fn with_cycles(schedule: &Schedule, i: usize, delta: i32) -> Option<Schedule> {
    let seg = &schedule.segments[i];
    if !seg.is_moving() {
        return None;
    }
    let cycles = u32::try_from(i64::from(seg.cycles) + i64::from(delta)).ok()?;
    if cycles < least_cycles(schedule, seg) {
        return None;
    }
    let mut segments = schedule.segments.clone();
    segments[i].cycles = cycles;
    Some(schedule.with_segments(segments))
}

/// `schedule` with its period scaled by `k`: every moving segment's
/// cycles between its ramps scaled and rounded, at least its least
/// cycles.
fn scaled(schedule: &Schedule, k: f64) -> Schedule {
    let mut segments = schedule.segments.clone();
    for seg in segments.iter_mut().filter(|s| s.is_moving()) {
        let ramps = 2 * seg.ramp_cycles.unwrap_or(0);
        let steady = f64::from(seg.cycles.saturating_sub(ramps));
        let cycles = ramps.saturating_add((k * steady).round() as u32);
        seg.cycles = cycles.max(least_cycles(schedule, seg));
    }
    schedule.with_segments(segments)
}

/// The coordinate search of the cycle aim from `schedule` (its worst
/// settled reach `reach`): at most [`CYCLE_SWEEPS`] steps, each keeping
/// the one change of a segment's cycles by one of [`CYCLE_STEPS`] that
/// brings the worst reach least, while it is less than the current one
/// and more than [`CYCLE_REACH_OK`]. Returns the schedule reached and its
/// worst reach.
fn descend(target: &Target, mut schedule: Schedule, mut reach: f64) -> Result<(Schedule, f64)> {
    for _ in 0..CYCLE_SWEEPS {
        if reach <= CYCLE_REACH_OK {
            break;
        }
        let mut trials: Vec<Schedule> = (0..schedule.segments.len())
            .flat_map(|i| CYCLE_STEPS.iter().map(move |&k| (i, k)))
            .filter_map(|(i, k)| with_cycles(&schedule, i, k))
            .collect();
        let reached: Vec<Result<f64>> = trials
            .par_iter()
            .map(|s| settled_reach(target, s).map(|r| worst(&r)))
            .collect();
        let mut step: Option<(f64, usize)> = None;
        for (j, r) in reached.into_iter().enumerate() {
            let r = r?;
            if r < reach && step.is_none_or(|s| r < s.0) {
                step = Some((r, j));
            }
        }
        let Some((r, j)) = step else {
            break;
        };
        reach = r;
        schedule = trials.swap_remove(j);
    }
    Ok((schedule, reach))
}

/// `d` aimed by its segments' cycles (parent module docs, **Cycle aim**),
/// or `None` when it is not offered: a class without an attractor (a
/// lane), a worst settled reach already within [`CYCLE_REACH_OK`], or
/// none of the searches ([`descend`] from the candidate's period scaled
/// by each of [`CYCLE_PERIOD_SCALES`]) reaches a worst settled reach
/// below both the candidate's and [`CYCLE_REACH_MAX`] (farther, its
/// parts could not sort).
///
/// # Errors
/// The schedule cannot be played.
pub(super) fn cycle_aimed(target: &Target, d: &SortDesign) -> Result<Option<SortDesign>> {
    if target
        .classes
        .iter()
        .any(|c| c.exit.is_some() || Attractor::of(&c.field).is_none())
    {
        return Ok(None);
    }
    let own = worst(&settled_reach(target, &d.schedule)?);
    if own <= CYCLE_REACH_OK {
        return Ok(None);
    }
    let mut best: Option<(Schedule, f64)> = None;
    for k in CYCLE_PERIOD_SCALES {
        let start = scaled(&d.schedule, k);
        let reach = if start == d.schedule {
            own
        } else {
            worst(&settled_reach(target, &start)?)
        };
        let (s, r) = descend(target, start, reach)?;
        if best.as_ref().is_none_or(|b| r < b.1) {
            best = Some((s, r));
        }
        if r <= CYCLE_REACH_OK {
            break;
        }
    }
    Ok(best
        .filter(|b| b.1 < own.min(CYCLE_REACH_MAX) && b.0 != d.schedule)
        .map(|(schedule, _)| SortDesign {
            schedule,
            cycles_aimed: true,
            ..d.clone()
        }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shipped() -> Schedule {
        Schedule::load(std::path::Path::new("results/sort_three/schedule.json")).unwrap()
    }

    /// Scaling the period scales each segment's cycles between its ramps,
    /// rounded, at least its least cycles; scaled by 1 it is the same.
    #[test]
    fn scaled_keeps_ramps_and_least_cycles() {
        let s = shipped();
        assert_eq!(scaled(&s, 1.0), s);
        let half = scaled(&s, 0.5);
        for (a, b) in s.segments.iter().zip(&half.segments) {
            let ramps = 2 * a.ramp_cycles.unwrap_or(0);
            let steady = (0.5 * f64::from(a.cycles - ramps)).round() as u32;
            assert_eq!(b.cycles, (ramps + steady).max(least_cycles(&s, a)), "{a:?}");
            assert_eq!(b.ramp_cycles, a.ramp_cycles);
        }
        assert!(half.period_s < s.period_s);
    }

    /// A change of cycles keeps the segment at or above its least cycles
    /// (its two ramps for a ramped one) and derives the period.
    #[test]
    fn with_cycles_respects_the_least_cycles() {
        let s = shipped();
        for (i, seg) in s.segments.iter().enumerate() {
            for k in CYCLE_STEPS {
                let c = i64::from(seg.cycles) + i64::from(k);
                match with_cycles(&s, i, k) {
                    Some(t) => {
                        assert!(c >= i64::from(least_cycles(&s, seg)));
                        assert_eq!(i64::from(t.segments[i].cycles), c);
                        let cycle = seg.cycle_period().unwrap();
                        assert!((t.period_s - s.period_s - f64::from(k) * cycle).abs() < 1e-12);
                        t.validate().unwrap();
                    }
                    None => assert!(c < i64::from(least_cycles(&s, seg))),
                }
            }
        }
    }
}
