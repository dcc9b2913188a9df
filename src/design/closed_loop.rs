//! Closed-loop design (`platefield design --closed-loop`; see
//! [what combines under sequencing](crate#sequencing-what-combines)): what verification measures is fed back into the schedule, so
//! that short segments (fast switching, finer time-averaging) become usable.
//!
//! **The problem, measured.** The open-loop design promises the field s·t
//! (strength s times the target t) on the assumption that a schedule
//! realises the time-weighted combination of its segments' *steady-state*
//! fields. With few cycles per segment it does not: each segment starts
//! from the motion the previous one left. For the Sink target
//! (`targets/sink.json`: four LineSinks, full model, parts moving) the
//! realised error (below) is 38 % at one cycle per segment, 26 % at two,
//! 19 % at three. Decomposed ([`realised`]): mostly a pure change of scale
//! — the realised sink is weaker, 67 %, 79 % and 85 % of the promised
//! strength — plus, in the design's order 0°→180°→270°→90°, an offset (18 %
//! at one cycle) and an anisotropy (7 %); the cyclic order
//! 0°→90°→180°→270° has no offset but a swirl (2 %) from its rotation sense
//! (see [`super::order`]).
//!
//! **Realised error** ([`realised`]): the relative L2 error ‖R − s t‖/‖s t‖
//! of the realised mean velocity field R against the promise s·t, at the
//! parts' mean positions, with the target's weights and mask; s is the
//! strength the schedule's design claims. Reported with it: the realised
//! strength ŝ (the least-squares scale of R on t) and the shape-only error
//! ‖R − ŝ t‖/‖ŝ t‖, which no choice of strength can lower. A schedule whose
//! parts lose contact at more points than the open-loop schedule's is
//! rejected.
//!
//! **The loop.** Every candidate is played and judged by its measured
//! realised error, never by prediction alone; the best, including the
//! open-loop schedule itself, is kept, so "after" is never worse than
//! "before".
//! 1. *Design*: the open-loop schedule with its promise s (the "before").
//! 2. *Order* ([`super::order::candidates`]): the same segments and cycles in every cyclic
//!    order and every mirrored order (each segment twice per period, the
//!    second half reversed, which cancels the swirl of a rotation sense).
//!    The weights do not change, so the contextual model (3.) of the played
//!    schedule is the measurement itself and the promise it supports is the
//!    realised strength ŝ: an order is judged by its shape-only error.
//! 3. *Re-fit* (contextual basis): from the best schedule so far, each
//!    segment's realised velocity in its schedule context c_i
//!    ([`realised::play`]; R = Σ f_i c_i exactly) replaces its steady-state
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

pub mod realised;
pub(crate) mod refit;

use std::time::Instant;

use serde::Serialize;

pub use realised::{Decomposition, MeasureOptions, PointPlay, RealisedError};

use super::order::{self, arrange};
use super::Design;
use crate::dynamics::Model;
use crate::error::{Error, Result};
use crate::field::FieldSettings;
use crate::fit::{self, FitMetrics};
use crate::request::{SampledTarget, Target};
use crate::schedule::{Schedule, Segment};

/// Options of [`closed_loop`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LoopOptions {
    /// Play every `stride`-th target grid point along each axis (every
    /// `stride`-th point of a grid-less target); masked points are skipped.
    /// Default 2.
    pub stride: usize,
    /// Warm-up and measurement lengths.
    pub measure: MeasureOptions,
    /// Most contextual re-fit iterations (default 8).
    pub max_iterations: u32,
    /// Try other playing orders (default true).
    pub search_orders: bool,
    /// Model the schedules are played with (`None`, the default: the one
    /// the design's basis was built with, normally [`Model::FULL`]). With
    /// the frozen model (kinematics held at the start point) the measurement
    /// is the local field at each start point even when parts travel far
    /// during a long schedule period; it is not valid for the large-amplitude
    /// Circle (its frozen field has a spurious radial velocity, see
    /// [`crate::field`]), whose
    /// schedules must be played with moving parts.
    pub model: Option<Model>,
}

impl Default for LoopOptions {
    fn default() -> Self {
        LoopOptions {
            stride: 2,
            measure: MeasureOptions::default(),
            max_iterations: 8,
            search_orders: true,
            model: None,
        }
    }
}

impl LoopOptions {
    /// Validates ranges (errors name the option's path under
    /// [`DesignOptions::closed_loop`](super::DesignOptions::closed_loop)).
    pub fn validate(&self) -> Result<()> {
        if !(1..=100).contains(&self.stride) {
            return Err(Error::invalid(
                "closed_loop.stride",
                format!("must be in 1..=100, got {}", self.stride),
            ));
        }
        if self.max_iterations > 50 {
            return Err(Error::invalid(
                "closed_loop.max_iterations",
                format!("must be in 0..=50, got {}", self.max_iterations),
            ));
        }
        if !(1..=100_000).contains(&self.measure.measured_cycles)
            || self.measure.warmup_cycles > 100_000
        {
            return Err(Error::invalid(
                "closed_loop.measure",
                format!(
                    "measured cycles must be in 1..=100000 and warm-up cycles in 0..=100000, got {} and {}",
                    self.measure.measured_cycles, self.measure.warmup_cycles
                ),
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

/// One played schedule.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoopCandidate {
    /// The step that produced it.
    pub stage: Stage,
    /// Its segments in playing order, e.g. `LineSink@0°×1 LineSink@90°×1`.
    pub order: String,
    /// Where its promised strength comes from.
    pub promise: String,
    /// Realised error against its promise.
    pub error: RealisedError,
    /// ‖R − s₀ t‖/‖s₀ t‖ against the open-loop promise s₀.
    pub error_vs_design: f64,
    /// Why it was rejected (`None`: eligible).
    pub rejected: Option<String>,
    /// The schedule.
    #[serde(skip)]
    pub schedule: Schedule,
    /// What was measured.
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
    /// Start points played.
    pub points: usize,
    /// Schedules played (a candidate that repeats one is not played again).
    pub played: usize,
    /// Name of the model the schedules were played with.
    pub model: String,
    /// The options used.
    pub options: LoopOptions,
    /// The open-loop promise s₀.
    pub design_strength: f64,
    /// Why the re-fit stopped.
    pub stop: String,
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

    /// The best schedule, its `fit` and `fit_quantized` metrics replaced by
    /// the realised ones against its promise (the open-loop schedule is
    /// returned unchanged when it is the best).
    pub fn schedule(&self, target: &Target, weights: &[f64]) -> Schedule {
        let best = self.after();
        let mut s = best.schedule.clone();
        if self.best == 0 {
            return s;
        }
        if let Some(m) = realised_metrics(target, weights, &best.plays, best.error.strength) {
            s.fit = m;
            s.fit_quantized = m;
        }
        s.solver.status = format!(
            "closed loop ({}; realised over {} points, promise: {}); open loop: {}",
            best.stage.name(),
            best.error.valid,
            best.promise,
            s.solver.status
        );
        s
    }
}

/// `FitMetrics` of the realised field against the promise at `strength`
/// (`realised::promised`), by the design's own metric code (an independent
/// check of [`realised::realised_error`]).
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
    let t: Vec<[f64; 2]> = realised::promised(target, &ok, strength)
        .iter()
        .map(|v| [v[0] / strength, v[1] / strength])
        .collect();
    let r: Vec<[f64; 2]> = ok.iter().map(|p| p.realised).collect();
    let w: Vec<f64> = ok.iter().map(|p| weights[p.index]).collect();
    fit::field_metrics(&t, &r, strength, Some(&w)).ok()
}

/// The start points: every `stride`-th grid point along each axis (every
/// `stride`-th sample of a grid-less target), weight > 0 only.
pub fn loop_points(target: &Target, sampled: &SampledTarget, stride: usize) -> Vec<usize> {
    let stride = stride.max(1);
    (0..sampled.len())
        .filter(|&k| sampled.weights[k] > 0.0)
        .filter(|&k| match &target.grid {
            Some(g) => (k % g.n[0]) % stride == 0 && (k / g.n[0]) % stride == 0,
            None => k % stride == 0,
        })
        .collect()
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
struct Judge<'a> {
    target: &'a Target,
    sampled: &'a SampledTarget,
    starts: Vec<usize>,
    settings: FieldSettings,
    measure: MeasureOptions,
    design_strength: f64,
    valid_before: Option<usize>,
    played: std::cell::Cell<usize>,
}

impl Judge<'_> {
    fn judge(
        &self,
        stage: Stage,
        schedule: Schedule,
        plays: Vec<PointPlay>,
        strength: Option<f64>,
        promise: String,
    ) -> LoopCandidate {
        let w = &self.sampled.weights;
        let error = realised::realised_error(self.target, w, &plays, strength);
        let vs_design =
            realised::realised_error(self.target, w, &plays, Some(self.design_strength)).error;
        let rejected = match self.valid_before {
            Some(v) if error.valid < v => Some(format!(
                "parts lose contact at {} more points than open loop",
                v - error.valid
            )),
            _ if !error.error.is_finite() => Some("no realised field".into()),
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
        realised::play(
            schedule,
            &self.sampled.points,
            &self.starts,
            &self.settings,
            &self.measure,
        )
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
    judge: &Judge,
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
            judge.play(&schedule)?
        };
        let what = if same {
            "design order"
        } else if order.mirrored {
            "mirrored order"
        } else {
            "cyclic order"
        };
        cands.push(judge.judge(
            Stage::Order,
            schedule,
            plays,
            None,
            format!("{what}, weights unchanged: realised strength ŝ"),
        ));
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
    judge: &Judge,
    design: &Design,
    cands: &mut Vec<LoopCandidate>,
    mut pattern: Vec<usize>,
    max_iterations: u32,
) -> Result<String> {
    let open = &design.schedule;
    let mut current = best_of(cands);
    let mut base = open.segments.clone();
    let mut seen: Vec<Vec<u32>> = vec![base.iter().map(|g| g.cycles).collect()];
    let total: u32 = base.iter().map(|g| g.cycles).sum();
    let mut stale = 0;
    for _ in 0..max_iterations {
        let refitted = refit::refit(
            judge.target,
            &design.target.weights,
            open,
            &base,
            &pattern,
            &cands[current].plays,
            total,
        );
        let (new_base, new_pattern, strength) = match refitted {
            Ok(x) => x,
            Err(e) => return Ok(format!("re-fit failed: {e}")),
        };
        let cycles: Vec<u32> = new_base.iter().map(|g| g.cycles).collect();
        if seen.contains(&cycles) {
            return Ok("the re-fit returns a schedule already played (converged)".into());
        }
        seen.push(cycles);
        let schedule = play_in(open, &new_base, &new_pattern);
        let plays = judge.play(&schedule)?;
        let before_best = cands[best_of(cands)].error.error;
        cands.push(judge.judge(
            Stage::Refit,
            schedule,
            plays,
            Some(strength),
            "contextual re-fit".into(),
        ));
        current = cands.len() - 1;
        base = new_base;
        pattern = new_pattern;
        if cands[current].rejected.is_none() && cands[current].error.error < before_best {
            stale = 0;
        } else {
            stale += 1;
            if stale >= 2 {
                return Ok("two re-fits without improvement".into());
            }
        }
    }
    Ok("iteration cap".into())
}

/// Runs the closed loop on a finished open-loop design of `target`.
pub fn closed_loop(target: &Target, design: &Design, opts: &LoopOptions) -> Result<ClosedLoop> {
    opts.validate()?;
    let start = Instant::now();
    let open = &design.schedule;
    let mut settings: FieldSettings = open.settings;
    if let Some(m) = opts.model {
        settings.model = m;
    }
    let starts = loop_points(target, &design.target, opts.stride);
    if starts.is_empty() {
        return Err(Error::invalid(
            "closed_loop.stride",
            "leaves no target point with a positive weight",
        ));
    }
    let s0 = open.fit.strength;
    let mut judge = Judge {
        target,
        sampled: &design.target,
        starts,
        settings,
        measure: opts.measure,
        design_strength: s0,
        valid_before: None,
        played: std::cell::Cell::new(0),
    };

    // 1. The open-loop schedule.
    let plays = judge.play(open)?;
    let first = judge.judge(
        Stage::Design,
        open.clone(),
        plays,
        Some(s0),
        "open-loop design (steady-state fields)".into(),
    );
    judge.valid_before = Some(first.error.valid);
    let mut cands = vec![first];

    let pattern = order_stage(&judge, open, &mut cands, opts.search_orders)?;
    let mut stop = refit_stage(&judge, design, &mut cands, pattern, opts.max_iterations)?;
    if opts.max_iterations == 0 {
        stop = "no re-fit asked".into();
    }
    Ok(ClosedLoop {
        target: open.target.clone(),
        best: best_of(&cands),
        points: judge.starts.len(),
        played: judge.played.get(),
        model: judge.settings.model.name(),
        candidates: cands,
        options: *opts,
        design_strength: s0,
        stop,
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
            promise: String::new(),
            error: RealisedError {
                strength: 1.0,
                error,
                realised_strength: 1.0,
                shape_error: error,
                decomposition: d,
                valid: 1,
            },
            error_vs_design: error,
            rejected: rejected.then(|| "lost contact".to_string()),
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
