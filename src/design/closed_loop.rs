//! Closed-loop design (`platefield design --closed-loop`; see
//! [what combines under sequencing](crate#sequencing-what-combines)): what verification measures is fed back into the schedule, so
//! that short segments (fast switching, finer time-averaging) become usable.
//!
//! **The problem.** The open-loop design promises the field s·t
//! (strength s times the target t) on the assumption that a schedule
//! realises the time-weighted combination of its segments' *steady-state*
//! fields. With few cycles per segment it does not: each segment starts
//! from the motion the previous one left, and its field in that context
//! differs from its steady state. The loop's numbers for the Sink target
//! at 1, 2 and 3 cycles per segment are in `results/closed_loop/`.
//!
//! **The measure** is the judge's ([`super::judge`]): the realised field R
//! at the judge's held points over the whole region, whole schedule
//! periods, against the promise s·t with the target's weights and mask
//! (`judge::compare`): the **realised error** ‖R − s t‖/‖s t‖ at
//! the strength s the schedule's design claims, the **realised strength**
//! ŝ (the least-squares scale of R on t) and the **realised shape error**
//! ‖R − ŝ t‖/‖ŝ t‖, which no choice of strength can lower. So the kept
//! schedule's numbers are the ones `design` reports for it. A schedule
//! whose held parts lose contact at more points than the open-loop
//! schedule's is rejected.
//!
//! **The loop.** Every candidate is played and judged by its measured
//! realised error, never by prediction alone; the best, including the
//! open-loop schedule itself, is kept, so "after" is never worse than
//! "before".
//! 1. *Design*: the open-loop schedule with its promise s (the "before").
//! 2. *Order* (`super::order::candidates`): the same segments and cycles in every cyclic
//!    order and every mirrored order (each segment twice per period, the
//!    second half reversed, which cancels the swirl of a rotation sense).
//!    The weights do not change, so the contextual model (3.) of the played
//!    schedule is the measurement itself and the promise it supports is the
//!    realised strength ŝ: an order is judged by its shape-only error.
//! 3. *Re-fit* (contextual basis): from the best schedule so far, each
//!    segment's realised velocity in its schedule context c_i (over the
//!    judge's last period; R = Σ f_i c_i exactly) replaces its steady-state
//!    field as a basis column; the time fractions are re-fitted to the
//!    target with the design's conic fit (shape mode, strongest within its
//!    slack), requantised to whole cycles with the same minimum per segment
//!    at the open-loop schedule's total length (so the segments keep the
//!    length the user asked for, and their context changes little), played
//!    in the same order pattern, and judged against the re-fit's strength. Repeated from the latest schedule until the
//!    re-fit returns a schedule already played, two iterations bring no
//!    improvement, or [`LoopOptions::max_iterations`].
//!
//! What it cannot do: make the field stronger. Time fractions already sum to
//! one in a `shape` design, and the weakening at short segments is common to
//! the segments, so no re-weighting recovers it (iterative target correction
//! t ← t + γ(s t − R) is not built, for this reason: a
//! scale error gives a correction parallel to t, which the scale-free
//! `shape` fit ignores). The loop states the strength the schedule realises
//! and fixes the shape; the report gives both errors and both strengths.

pub(crate) mod refit;

use std::time::Instant;

use serde::Serialize;

#[cfg(test)]
pub(crate) use judge::Decomposition;
pub(crate) use judge::{PointPlay, RealisedError};

use super::judge;
use super::order::{self, arrange};
use super::Design;
use crate::error::{Error, Result};
use crate::field::FieldSettings;
use crate::fit::{self, FitMetrics};
use crate::play::ScheduleMotion;
use crate::request::{SampledTarget, Target};
use crate::schedule::{Schedule, Segment};
use crate::work::Stop;

/// Options of [`closed_loop`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LoopOptions {
    /// Most contextual re-fit iterations (default 8).
    pub max_iterations: u32,
    /// Try other playing orders (default true).
    pub search_orders: bool,
}

impl Default for LoopOptions {
    fn default() -> Self {
        LoopOptions {
            max_iterations: 8,
            search_orders: true,
        }
    }
}

impl LoopOptions {
    /// Validates ranges (errors name the option's path under
    /// [`DesignOptions::closed_loop`](super::DesignOptions::closed_loop)).
    pub fn validate(&self) -> Result<()> {
        if self.max_iterations > 50 {
            return Err(Error::invalid(
                "closed_loop.max_iterations",
                format!("must be in 0..=50, got {}", self.max_iterations),
            ));
        }
        Ok(())
    }
}

/// Which step of the loop produced a candidate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// The open-loop schedule with the open-loop promise.
    Design,
    /// A playing order of the open-loop segments, promise ŝ.
    Order,
    /// A contextual re-fit, promise from the re-fit.
    Refit,
}

impl Stage {
    /// Short name.
    pub fn name(&self) -> &'static str {
        match self {
            Stage::Design => "design",
            Stage::Order => "order",
            Stage::Refit => "re-fit",
        }
    }
}

/// Where a candidate's promised strength comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Promise {
    /// The open-loop design's fit of the segments' steady-state fields.
    OpenLoop,
    /// A playing order with the weights unchanged: the promise is the
    /// schedule's own realised strength ŝ.
    Order(OrderKind),
    /// The contextual re-fit's strength.
    Refit,
}

/// Which playing order an [`Promise::Order`] candidate plays.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum OrderKind {
    /// The open-loop design's own order.
    Design,
    /// Another cyclic order.
    Cyclic,
    /// A mirrored order: each segment twice per period, the second half
    /// reversed.
    Mirrored,
}

impl std::fmt::Display for Promise {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let order = |k: &OrderKind| match k {
            OrderKind::Design => "design",
            OrderKind::Cyclic => "cyclic",
            OrderKind::Mirrored => "mirrored",
        };
        match self {
            Promise::OpenLoop => f.write_str("open-loop design (steady-state fields)"),
            Promise::Order(k) => write!(
                f,
                "{} order, weights unchanged: realised strength ŝ",
                order(k)
            ),
            Promise::Refit => f.write_str("contextual re-fit"),
        }
    }
}

/// Why a candidate cannot be kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Rejection {
    /// Held parts lose contact at more points than under the open-loop
    /// schedule.
    LostContact {
        /// How many more points than the open-loop schedule.
        more_points: usize,
    },
    /// No realised field: no point counted, or a non-finite error.
    NoRealisedField,
}

impl std::fmt::Display for Rejection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Rejection::LostContact { more_points } => write!(
                f,
                "parts lose contact at {more_points} more points than open loop"
            ),
            Rejection::NoRealisedField => f.write_str("no realised field"),
        }
    }
}

/// One played schedule.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoopCandidate {
    /// The step that produced it.
    pub stage: Stage,
    /// Its segments in playing order, e.g. `LineSink@0°×1 LineSink@90°×1`.
    pub order: String,
    /// Where its promised strength comes from.
    pub promise: Promise,
    /// The judge's realised field against its promise.
    pub error: RealisedError,
    /// ‖R − s₀ t‖/‖s₀ t‖ against the open-loop promise s₀.
    pub error_vs_design: f64,
    /// Why it was rejected (`None`: eligible).
    pub rejected: Option<Rejection>,
    /// The schedule.
    #[serde(skip)]
    pub schedule: Schedule,
    /// The judge's plays.
    #[serde(skip)]
    pub plays: Vec<PointPlay>,
}

/// The outcome of [`closed_loop`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClosedLoop {
    /// Target name.
    pub target: String,
    /// Every played schedule, in the order played; the first is the
    /// open-loop schedule.
    pub candidates: Vec<LoopCandidate>,
    /// Index of the best candidate (lowest realised error among the eligible).
    pub best: usize,
    /// The judge's points played.
    pub points: usize,
    /// Schedules played (a candidate that repeats one is not played again).
    pub played: usize,
    /// The options used.
    pub options: LoopOptions,
    /// The open-loop promise s₀.
    pub design_strength: f64,
    /// Why the re-fit stopped: [`Stop::Converged`] when a re-fit returns
    /// a schedule already played, [`Stop::NoGain`] after two re-fits
    /// without improvement, [`Stop::Iterations`] at
    /// [`LoopOptions::max_iterations`], [`Stop::NotRun`] when none was
    /// asked, [`Stop::Failed`] when the re-fit could not be computed.
    pub stop: Stop,
    /// Why the re-fit could not be computed ([`Stop::Failed`]).
    pub refit_failure: Option<String>,
    /// Wall time (s): for the terminal summary, not written to files.
    #[serde(skip)]
    pub seconds: f64,
}

impl ClosedLoop {
    /// The open-loop schedule's measurement.
    pub fn before(&self) -> &LoopCandidate {
        &self.candidates[0]
    }

    /// The best candidate's measurement.
    pub fn after(&self) -> &LoopCandidate {
        &self.candidates[self.best]
    }

    /// The best schedule with the judge's record (`played`), its `fit` and
    /// `fit_quantized` metrics replaced by the realised ones against its
    /// promise (the open-loop schedule keeps its own when it is the best).
    pub fn schedule(&self, target: &Target, weights: &[f64]) -> Schedule {
        let best = self.after();
        let mut s = best.schedule.clone();
        let mut played = super::method::played_of(
            &best.plays,
            &best.error,
            &s,
            best.error.strength,
            super::Method::Sequence,
            None,
        );
        played.choice = format!(
            "closed loop: the best of {} schedules judged ({}, {})",
            self.candidates.len(),
            best.stage.name(),
            best.promise
        );
        s.played = Some(played);
        if self.best == 0 {
            return s;
        }
        if let Some(m) = realised_metrics(target, weights, &best.plays, best.error.strength) {
            s.fit = m;
            s.fit_quantized = m;
        }
        s.solver.status = format!(
            "closed loop ({}; judged over {} points, promise: {}); open loop: {}",
            best.stage.name(),
            best.error.valid,
            best.promise,
            s.solver.status
        );
        s
    }
}

/// `FitMetrics` of the realised field against the promise at `strength`
/// (`compare::promised`), by the design's own metric code (an independent
/// check of [`judge::realised_error`]).
pub fn realised_metrics(
    target: &Target,
    weights: &[f64],
    plays: &[PointPlay],
    strength: f64,
) -> Option<FitMetrics> {
    let ok: Vec<&PointPlay> = plays
        .iter()
        .filter(|p| p.note.is_none() && weights[p.index] > 0.0)
        .collect();
    if strength == 0.0 {
        return None;
    }
    let t: Vec<[f64; 2]> = judge::compare::promised(target, &ok, strength)
        .iter()
        .map(|v| [v[0] / strength, v[1] / strength])
        .collect();
    let r: Vec<[f64; 2]> = ok.iter().map(|p| p.realised).collect();
    let w: Vec<f64> = ok.iter().map(|p| weights[p.index]).collect();
    fit::field_metrics(&t, &r, strength, Some(&w)).ok()
}

/// `base` segments played in `sequence` (indices into `base`; a segment
/// listed twice is played twice, its weight split between the plays).
fn play_in(template: &Schedule, base: &[Segment], sequence: &[usize]) -> Schedule {
    let mut count = vec![0usize; base.len()];
    for &i in sequence {
        count[i] += 1;
    }
    let split: Vec<Segment> = base
        .iter()
        .zip(&count)
        .map(|(g, &c)| Segment {
            weight: g.weight / c.max(1) as f64,
            ..g.clone()
        })
        .collect();
    template.with_segments(arrange(&split, sequence, |_| None))
}

fn order_text(s: &Schedule) -> String {
    s.segments
        .iter()
        .map(|g| format!("{}×{}", g.label, g.cycles))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Everything a step needs to play and judge a schedule.
struct Trial<'a> {
    target: &'a Target,
    sampled: &'a SampledTarget,
    points: Vec<usize>,
    settings: FieldSettings,
    design_strength: f64,
    valid_before: Option<usize>,
    played: std::cell::Cell<usize>,
}

impl Trial<'_> {
    fn judge(
        &self,
        stage: Stage,
        schedule: Schedule,
        plays: Vec<PointPlay>,
        strength: Option<f64>,
        promise: Promise,
    ) -> LoopCandidate {
        let w = &self.sampled.weights;
        let error = judge::realised_error(self.target, w, &plays, strength);
        let vs_design =
            judge::realised_error(self.target, w, &plays, Some(self.design_strength)).error;
        let rejected = match self.valid_before {
            Some(v) if error.valid < v => Some(Rejection::LostContact {
                more_points: v - error.valid,
            }),
            _ if !error.error.is_finite() => Some(Rejection::NoRealisedField),
            _ => None,
        };
        LoopCandidate {
            stage,
            order: order_text(&schedule),
            promise,
            error,
            error_vs_design: vs_design,
            rejected,
            schedule,
            plays,
        }
    }

    fn play(&self, schedule: &Schedule) -> Result<Vec<PointPlay>> {
        self.played.set(self.played.get() + 1);
        let sm = ScheduleMotion::from_schedule(schedule)?;
        Ok(judge::play_motion(
            &sm,
            &self.sampled.points,
            &self.points,
            &self.settings,
        ))
    }
}

/// Index of the best eligible candidate (lowest realised error, earliest on ties).
fn best_of(c: &[LoopCandidate]) -> usize {
    let mut best = 0;
    for (i, x) in c.iter().enumerate() {
        if x.rejected.is_none()
            && (c[best].rejected.is_some() || x.error.error < c[best].error.error)
        {
            best = i;
        }
    }
    best
}

/// Stage 2: every segment order played with the weights unchanged
/// (when `search`); returns the best order's pattern (the design's own
/// order when none is better or none is searched).
fn order_stage(
    trial: &Trial,
    open: &Schedule,
    cands: &mut Vec<LoopCandidate>,
    search: bool,
) -> Result<Vec<usize>> {
    let base = &open.segments;
    let pattern: Vec<usize> = (0..base.len()).collect();
    if !search {
        return Ok(pattern);
    }
    for order in order::candidates(base.len()) {
        let same = order.sequence == pattern;
        let schedule = play_in(open, base, &order.sequence);
        let plays = if same {
            cands[0].plays.clone()
        } else {
            trial.play(&schedule)?
        };
        let kind = if same {
            OrderKind::Design
        } else if order.mirrored {
            OrderKind::Mirrored
        } else {
            OrderKind::Cyclic
        };
        cands.push(trial.judge(Stage::Order, schedule, plays, None, Promise::Order(kind)));
    }
    let b = best_of(cands);
    Ok(if cands[b].stage == Stage::Order {
        order::candidates(base.len())[b - 1].sequence.clone()
    } else {
        pattern
    })
}

/// Stage 3: contextual re-fits from the best candidate so far, at most
/// `max_iterations`, stopping at a schedule already played or after two
/// re-fits without improvement; returns why it stopped.
fn refit_stage(
    trial: &Trial,
    design: &Design,
    cands: &mut Vec<LoopCandidate>,
    mut pattern: Vec<usize>,
    max_iterations: u32,
) -> Result<(Stop, Option<String>)> {
    let open = &design.schedule;
    let mut current = best_of(cands);
    let mut base = open.segments.clone();
    let mut seen: Vec<Vec<u32>> = vec![base.iter().map(|g| g.cycles).collect()];
    let total: u32 = base.iter().map(|g| g.cycles).sum();
    let mut stale = 0;
    for _ in 0..max_iterations {
        let refitted = refit::refit(
            trial.target,
            &design.target.weights,
            open,
            &base,
            &pattern,
            &cands[current].plays,
            total,
        );
        let (new_base, new_pattern, strength) = match refitted {
            Ok(x) => x,
            Err(e) => return Ok((Stop::Failed, Some(e.to_string()))),
        };
        let cycles: Vec<u32> = new_base.iter().map(|g| g.cycles).collect();
        if seen.contains(&cycles) {
            return Ok((Stop::Converged, None));
        }
        seen.push(cycles);
        let schedule = play_in(open, &new_base, &new_pattern);
        let plays = trial.play(&schedule)?;
        let before_best = cands[best_of(cands)].error.error;
        cands.push(trial.judge(
            Stage::Refit,
            schedule,
            plays,
            Some(strength),
            Promise::Refit,
        ));
        current = cands.len() - 1;
        base = new_base;
        pattern = new_pattern;
        if cands[current].rejected.is_none() && cands[current].error.error < before_best {
            stale = 0;
        } else {
            stale += 1;
            if stale >= 2 {
                return Ok((Stop::NoGain, None));
            }
        }
    }
    Ok((Stop::Iterations, None))
}

/// Runs the closed loop on a finished open-loop design of `target`.
pub fn closed_loop(target: &Target, design: &Design, opts: &LoopOptions) -> Result<ClosedLoop> {
    opts.validate()?;
    let start = Instant::now();
    let open = &design.schedule;
    let points = judge::judge_points(target, &design.target);
    if points.is_empty() {
        return Err(Error::Unreachable(
            "the target has no point with a positive weight to judge".into(),
        ));
    }
    let s0 = open.fit.strength;
    let mut trial = Trial {
        target,
        sampled: &design.target,
        points,
        settings: open.settings,
        design_strength: s0,
        valid_before: None,
        played: std::cell::Cell::new(0),
    };

    // 1. The open-loop schedule.
    let plays = trial.play(open)?;
    let first = trial.judge(
        Stage::Design,
        open.clone(),
        plays,
        Some(s0),
        Promise::OpenLoop,
    );
    trial.valid_before = Some(first.error.valid);
    let mut cands = vec![first];

    let pattern = order_stage(&trial, open, &mut cands, opts.search_orders)?;
    let (stop, refit_failure) = if opts.max_iterations == 0 {
        (Stop::NotRun, None)
    } else {
        refit_stage(&trial, design, &mut cands, pattern, opts.max_iterations)?
    };
    Ok(ClosedLoop {
        target: open.target.clone(),
        best: best_of(&cands),
        points: trial.points.len(),
        played: trial.played.get(),
        candidates: cands,
        options: *opts,
        design_strength: s0,
        stop,
        refit_failure,
        seconds: start.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn candidate(error: f64, rejected: bool) -> LoopCandidate {
        let d = Decomposition {
            isotropic: 0.0,
            rotational: 0.0,
            anisotropic: 0.0,
            offset: 0.0,
            remainder: 0.0,
            alpha: 0.0,
            beta: 0.0,
        };
        let none = FitMetrics {
            relative_l2_error: 0.0,
            mean_angle_error_deg: 0.0,
            max_error: 0.0,
            strength: 1.0,
        };
        let schedule = Schedule::of_segments("t", Vec::new(), FieldSettings::default(), none);
        LoopCandidate {
            stage: Stage::Order,
            order: String::new(),
            promise: Promise::Refit,
            error: RealisedError {
                strength: 1.0,
                error,
                realised_strength: 1.0,
                shape_error: error,
                decomposition: d,
                valid: 1,
            },
            error_vs_design: error,
            rejected: rejected.then_some(Rejection::NoRealisedField),
            schedule,
            plays: Vec::new(),
        }
    }

    #[test]
    fn best_is_the_lowest_eligible_error_earliest_on_ties() {
        let c = |v: &[(f64, bool)]| v.iter().map(|&(e, r)| candidate(e, r)).collect::<Vec<_>>();
        assert_eq!(
            best_of(&c(&[(0.3, false), (0.1, true), (0.2, false), (0.2, false)])),
            2
        );
        assert_eq!(best_of(&c(&[(0.3, false), (0.4, false)])), 0);
        // A rejected open-loop schedule gives way to any eligible one.
        assert_eq!(best_of(&c(&[(0.1, true), (0.4, false)])), 1);
        assert_eq!(
            best_of(&c(&[(0.3, false), (f64::NAN, false), (0.2, false)])),
            2
        );
    }
}
