//! A schedule's exported signal file, played: the trajectory a shaker
//! controller gives the plate when it holds the file's samples
//! (`crate::motion::Held`, integrated exactly from rest in the home pose),
//! cut into the schedule's segments so that every measure of a
//! [`ScheduleMotion`] — the judge's windows starting at each
//! segment join above all — applies to it unchanged.
//!
//! The cuts follow the export's layout ([`crate::schedule::export`]), with
//! Δt the file's:
//!
//! * **A looped schedule period** (primitives, rests, ramped six-signal
//!   segments of a mixed schedule): segment i holds round(T_i/Δt) samples
//!   (a rest at least one, a rest of 0 s none), in order; their sum must be
//!   the file's rows. Every segment is played from the file, rests
//!   included, from the state the file has reached there (rest at home, to
//!   round-off: every such segment is rest-to-rest).
//! * **A steady six-signal motion** (a synthesized design), exported as
//!   [`RAMP_CYCLES`] cycles of ramp-in from rest, the steady cycles and the
//!   ramp-out: the ramp-in is integrated from rest at home, and the
//!   segment's cycles are the file's first steady cycles, from the state
//!   the ramp-in left (the steady state the schedule's own play starts
//!   in, to O(Δt²)). The steady cycles of the file are identical sample for
//!   sample, so looping them is what the controller plays in the middle of
//!   the file. Rest segments beside it (the export leaves them out) are
//!   rest.
//!
//! The file's own Δt, not the schedule's, times everything: a file that
//! does not fit the schedule (another schedule's export, a rate the
//! segments are not whole samples of) is refused, naming the file.

use std::fmt::Write as _;

use serde::Serialize;

use super::sensitivity::FrictionRow;
use super::{PlayedSegment, ScheduleMotion};
use crate::error::{Error, Result};
use crate::motion::sample_hold::HoldSamples;
use crate::motion::{Held, Motion};
use crate::schedule::export::RAMP_CYCLES;
use crate::schedule::Schedule;

/// How close to a whole number of the file's samples a moving segment
/// must be. The file's Δt is known from its times, printed to 1 ns: at
/// 1e5 rows of 10 µs that is a few 1e-9 relative, a few 1e-4 samples over
/// a segment of 1e5; a rate the segments are not whole samples of is off
/// by a sizeable fraction of one.
const WHOLE: f64 = 1e-2;

/// The trajectory of `file` (the export of `schedule`, named `source` in
/// errors) cut into `schedule`'s segments (see the module documentation).
///
/// # Errors
/// The schedule is invalid or all rest; the file's rows or Δt do not fit
/// the schedule's layout (names `source`).
pub fn replay_motion(
    schedule: &Schedule,
    file: &HoldSamples,
    source: &str,
) -> Result<ScheduleMotion> {
    schedule.validate()?;
    let schedule = &schedule.with_segments(schedule.segments.clone());
    let first = schedule
        .segments
        .iter()
        .find_map(|s| s.cycle_period())
        .ok_or_else(|| {
            Error::invalid(
                "schedule.segments",
                "every segment is rest: nothing was exported",
            )
        })?;
    let per_period = (first / file.dt).round().max(1.0) as usize;
    let held = Held::new(&HoldSamples {
        samples_per_period: per_period,
        ..file.clone()
    })?;
    let steady = schedule
        .segments
        .iter()
        .position(|s| s.motion.is_some() && s.ramp_cycles.is_none());
    let segments = match steady {
        Some(i) => steady_segments(schedule, &held, i, source)?,
        None => looped_segments(schedule, &held, source)?,
    };
    ScheduleMotion::new(segments)
}

/// A moving segment of `held`'s samples `range`.
fn held_segment(
    label: &str,
    held: &Held,
    range: std::ops::Range<usize>,
    cycles: u32,
) -> PlayedSegment {
    let part = held.slice(range);
    PlayedSegment {
        label: format!("{label} (replayed)"),
        duration: part.span(),
        motion: Some(Motion::Held(part)),
        cycles,
    }
}

/// The file's rows do not fit: the error naming `source`.
fn misfit(source: &str, why: String) -> Error {
    Error::invalid(
        source,
        format!("{why}: is this file the schedule's export (`platefield export` of the same schedule.json)?"),
    )
}

/// Cuts of a looped schedule period, in the schedule's order.
fn looped_segments(schedule: &Schedule, held: &Held, source: &str) -> Result<Vec<PlayedSegment>> {
    let dt = held.dt();
    let mut out = Vec::new();
    let mut at = 0;
    for (i, seg) in schedule.segments.iter().enumerate() {
        if !seg.is_moving() && seg.duration_s == 0.0 {
            continue;
        }
        let exact = seg.duration_s / dt;
        let k = exact.round().max(1.0) as usize;
        if seg.is_moving() && (exact - k as f64).abs() > WHOLE {
            return Err(misfit(
                source,
                format!(
                    "segments[{i}] lasts {} s, {exact:.6} of the file's Δt = {dt:.9e} s, not a whole number",
                    seg.duration_s
                ),
            ));
        }
        if at + k > held.len() {
            return Err(misfit(
                source,
                format!(
                    "{} rows, fewer than the schedule's segments take at its Δt",
                    held.len()
                ),
            ));
        }
        out.push(held_segment(&seg.label, held, at..at + k, seg.cycles));
        at += k;
    }
    if at != held.len() {
        return Err(misfit(
            source,
            format!(
                "{} rows, the schedule's segments take {at} at its Δt",
                held.len()
            ),
        ));
    }
    Ok(out)
}

/// The steady six-signal segment `steady` as the file's first steady
/// cycles after its ramp-in; rests as rests.
fn steady_segments(
    schedule: &Schedule,
    held: &Held,
    steady: usize,
    source: &str,
) -> Result<Vec<PlayedSegment>> {
    let n = (held.period() / held.dt()).round() as usize;
    let seg = &schedule.segments[steady];
    let (ramp, cycles) = (RAMP_CYCLES as usize, seg.cycles as usize);
    if !held.len().is_multiple_of(n) || held.len() / n < 2 * ramp + cycles {
        return Err(misfit(
            source,
            format!(
                "{} rows: a six-signal export holds whole cycles of {n} samples, {ramp} of ramp-in, at least the segment's {cycles} steady cycles and {ramp} of ramp-out",
                held.len()
            ),
        ));
    }
    Ok(schedule
        .segments
        .iter()
        .enumerate()
        .filter(|(i, s)| *i == steady || s.duration_s > 0.0)
        .map(|(i, s)| {
            if i == steady {
                held_segment(&s.label, held, ramp * n..(ramp + cycles) * n, s.cycles)
            } else {
                PlayedSegment::rest(s.duration_s)
            }
        })
        .collect())
}

/// The schedule played and its export replayed, by the one realised
/// measure, at one friction (`design::replay::replay_check` measures it).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReplayCheck {
    /// The file replayed.
    pub file: String,
    /// The schedule's motions played.
    pub played: FrictionRow,
    /// The exported file replayed.
    pub replayed: FrictionRow,
}

impl ReplayCheck {
    /// |ŝ_replayed/ŝ_played − 1| (infinite when either is not measured).
    pub fn strength_gap(&self) -> f64 {
        match (
            self.played.realised_strength,
            self.replayed.realised_strength,
        ) {
            (Some(p), Some(r)) if p != 0.0 => (r / p - 1.0).abs(),
            _ => f64::INFINITY,
        }
    }

    /// |shape error replayed − shape error played| (a fraction; infinite
    /// when either is not measured).
    pub fn shape_gap(&self) -> f64 {
        match (
            self.played.realised_shape_error,
            self.replayed.realised_shape_error,
        ) {
            (Some(p), Some(r)) => (r - p).abs(),
            _ => f64::INFINITY,
        }
    }

    /// Both numbers, as `verify --replay` prints them.
    pub fn text(&self) -> String {
        let row = |r: &FrictionRow| {
            format!(
                "realised strength {}, shape error {} ({} of {} points)",
                r.realised_strength
                    .map_or_else(|| "n/a".into(), |s| format!("{s:.4}")),
                crate::output::percent(r.realised_shape_error.unwrap_or(f64::NAN), 2),
                r.valid,
                r.points
            )
        };
        let mut t = format!(
            "replay of {} (the judge at μ_s = {}, μ_k = {}: the realised field at the design's judge points, parts held at their points):\n",
            self.file, self.played.friction.stat, self.played.friction.kinetic
        );
        let _ = writeln!(t, "  schedule played: {}", row(&self.played));
        let _ = writeln!(t, "  export replayed: {}", row(&self.replayed));
        let _ = writeln!(
            t,
            "  strength differs by {}, shape error by {} pp",
            crate::output::percent(self.strength_gap(), 2),
            format_pp(self.shape_gap())
        );
        t
    }
}

fn format_pp(x: f64) -> String {
    if x.is_finite() {
        format!("{:.2}", 100.0 * x)
    } else {
        "n/a".into()
    }
}
