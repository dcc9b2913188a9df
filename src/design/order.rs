//! Segment order and rest insertion: which playing order of a schedule's
//! segments, and how much rest at the joins, best realises the design's
//! prediction (the paper's section V).
//!
//! **Why order matters.** Every segment starts off its own periodic orbit:
//! the part arrives with the slip velocity the previous segment left it
//! (or none, after rest), and the transient until it settles displaces it
//! by a fraction of a millimetre, once per segment and always the same way
//! for the same pair of neighbours (`platefield study squeeze-order` measures
//! this for SqueezeTrans). So the realised field depends on which segment follows
//! which, and on rest at the joins; the time-weighted prediction does not.
//!
//! **Candidates.**
//! * *Orders up to rotation*: a periodic schedule played for whole periods
//!   after a warm-up is unchanged by a cyclic rotation of its segments, so
//!   the first moving segment is kept first and the others are permuted:
//!   (n − 1)! orders for n segments (an existing rest segment of the
//!   schedule is one of the n and takes part in the ordering), all of them
//!   for n ≤ `EXHAUSTIVE_MAX`, in lexicographic order of the permutation.
//! * *Beyond that, a heuristic*: steepest descent over pairwise swaps of
//!   the segments after the first, starting from the given order, with no
//!   rest inserted; every round evaluates all swaps of the current order
//!   (scanned in lexicographic order of the swapped positions, orders seen
//!   before skipped) and moves to the best one if it lowers the error;
//!   it stops at a local minimum or after `max_evaluations` evaluations.
//!   The rest insertions are then tried on the order it ends on.
//! * *Rest*: `k` primitive cycles of rest (the plate at rest in the home
//!   pose) at **every** join between two moving segments, the cyclic join
//!   from the last segment to the first included, for each k of
//!   `rest_cycles` (default 0, 1, 2). A join that already touches a rest
//!   segment gets none. A "primitive cycle" of rest is the period of the
//!   first moving segment.
//! * *Mirrored orders* (the closed loop's candidates, `candidates`): a
//!   cyclic order σ followed by (σ₀, σ_{n−1}, …, σ₁), every segment played
//!   twice per period with its own cycles, so that every join a→b of the
//!   first half is matched by b→a in the second. On the Sink from four
//!   LineSinks at one cycle each (`design --closed-loop`, error parts
//!   relative to the promised field): the design's order 0°→180°→270°→90°
//!   plays each axis's two LineSinks (whose mean tilts are opposite) one
//!   after the other and has an offset and an anisotropy; the cyclic
//!   order 0°→90°→180°→270°, in which every segment follows a perpendicular
//!   one, has the target's four-fold symmetry and no offset, but its
//!   rotation sense gives a swirl; the mirrored order
//!   0°→90°→180°→270°→0°→270°→180°→90° has both symmetries, and the
//!   lowest shape-only error of the three by far.
//!
//! **Evaluation.** Each candidate is played by [`verify_points`] on the
//! given points, the model check: the moving parts' mean velocity against the time-weighted
//! steady-state prediction, in which rest counts as the zero field, so a
//! candidate with rest is compared with its own (weaker) prediction and the
//! comparison is fair about the field's shape. What rest costs is strength:
//! every field is scaled by the moving fraction (moving time / period),
//! reported with each candidate. Warm-up: at least one schedule period and
//! at least `warmup_cycles` primitive cycles; measured: `verify.periods`
//! (at least one) whole periods.
//!
//! **Choice.** Among the candidates with the most valid points, the
//! smallest relative error e*; among those within `tie_tolerance` of e*
//! (absolute, default half a percentage point: differences below that do
//! not matter for design and rest costs strength), the one with the least
//! inserted rest, then the smallest error, then the first in the table.

use std::path::Path;

use serde::Serialize;

use crate::dynamics::Model;
use crate::error::{Error, Result};
use crate::play::measure::{grid_points, verify_points, PlayOptions};
use crate::play::{periods_for, PlayedSegment, ScheduleMotion};
use crate::progress::{Progress, ProgressMode};
use crate::schedule::{Schedule, Segment};
use crate::work::{Estimate, Term};

/// Segments up to which every order (up to rotation) is tried.
pub(crate) const EXHAUSTIVE_MAX: usize = 4;
/// Default rest insertions tried (primitive cycles at every join).
pub const DEFAULT_REST_CYCLES: [u32; 3] = [0, 1, 2];
/// Default minimum warm-up in primitive cycles.
pub(crate) const DEFAULT_WARMUP_CYCLES: u32 = 40;
/// Default tie tolerance on the relative error (absolute).
pub(crate) const DEFAULT_TIE_TOLERANCE: f64 = 0.005;
/// Default budget of schedule evaluations of the heuristic.
pub(crate) const DEFAULT_MAX_EVALUATIONS: usize = 60;

/// Settings of an order search.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct OrderOptions {
    /// Physics and model; its `warmup_periods` and `periods` are minimums
    /// (see `warmup_cycles`).
    pub verify: PlayOptions,
    /// Start points of the parts (m).
    pub points: Vec<[f64; 2]>,
    /// Rest cycles inserted at every join, one candidate set per value.
    pub rest_cycles: Vec<u32>,
    /// Minimum warm-up in primitive cycles (the warm-up is also at least
    /// one schedule period).
    pub warmup_cycles: u32,
    /// Up to this many segments every order is tried.
    pub exhaustive_max: usize,
    /// Evaluation budget of the heuristic beyond `exhaustive_max`.
    pub max_evaluations: usize,
    /// Errors within this (absolute) of the smallest count as ties, which
    /// go to the candidate with less rest.
    pub tie_tolerance: f64,
    /// Progress display of the search (default: quiet).
    pub progress: ProgressMode,
}

impl OrderOptions {
    /// Defaults for `verify` physics on `points`.
    pub fn new(verify: PlayOptions, points: Vec<[f64; 2]>) -> OrderOptions {
        OrderOptions {
            verify,
            points,
            rest_cycles: DEFAULT_REST_CYCLES.to_vec(),
            warmup_cycles: DEFAULT_WARMUP_CYCLES,
            exhaustive_max: EXHAUSTIVE_MAX,
            max_evaluations: DEFAULT_MAX_EVALUATIONS,
            tie_tolerance: DEFAULT_TIE_TOLERANCE,
            progress: ProgressMode::Quiet,
        }
    }
}

/// One candidate schedule and how well it realises its prediction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrderCandidate {
    /// Playing order: indices into the searched segments.
    pub order: Vec<usize>,
    /// The order as labels, e.g. `LineSink@90° → Trans@0°`.
    pub sequence: String,
    /// Rest cycles inserted at each join between moving segments.
    pub rest_cycles: u32,
    /// Joins that received rest.
    pub rest_joins: usize,
    /// Inserted rest time per period (s).
    pub inserted_rest_s: f64,
    /// Moving time / period: the factor every field is scaled by.
    pub moving_fraction: f64,
    /// The model check's relative L2 error, measured against predicted
    /// (NaN: no valid point).
    pub relative_error: f64,
    /// Largest |measured − predicted| (m/s).
    pub max_abs_error: f64,
    /// Valid points.
    pub valid: usize,
    /// Schedule period (s).
    pub period_s: f64,
    /// Warm-up periods played.
    pub warmup_periods: u32,
    /// Periods measured.
    pub periods: u32,
}

/// The result of an order search.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrderSearch {
    /// Labels of the searched segments (input order).
    pub segments: Vec<String>,
    /// How the orders were enumerated.
    pub method: String,
    /// All candidates evaluated, in evaluation order.
    pub candidates: Vec<OrderCandidate>,
    /// Index of the chosen candidate.
    pub best: usize,
    /// Start points.
    pub points: usize,
    /// Model name.
    pub model: String,
    /// Duration of one rest cycle (s).
    pub rest_period_s: f64,
    /// Tie tolerance used.
    pub tie_tolerance: f64,
    /// Minimum warm-up in primitive cycles.
    pub warmup_cycles: u32,
}

impl OrderSearch {
    /// The chosen candidate.
    pub fn chosen(&self) -> &OrderCandidate {
        &self.candidates[self.best]
    }
}

/// (n − 1)! orders of `n` segments up to rotation: `first` leads, the
/// others in every permutation, lexicographic. Empty for n = 0.
pub(crate) fn orders_up_to_rotation(n: usize, first: usize) -> Vec<Vec<usize>> {
    if n == 0 || first >= n {
        return Vec::new();
    }
    let mut rest: Vec<usize> = (0..n).filter(|&i| i != first).collect();
    let mut out = Vec::new();
    loop {
        let mut o = vec![first];
        o.extend_from_slice(&rest);
        out.push(o);
        if !next_permutation(&mut rest) {
            return out;
        }
    }
}

/// Advances `v` to its next lexicographic permutation; false at the last.
fn next_permutation(v: &mut [usize]) -> bool {
    let n = v.len();
    if n < 2 {
        return false;
    }
    let Some(i) = (0..n - 1).rev().find(|&i| v[i] < v[i + 1]) else {
        return false;
    };
    let j = (i + 1..n).rev().find(|&j| v[j] > v[i]).unwrap_or(i + 1);
    v.swap(i, j);
    v[i + 1..].reverse();
    true
}

/// `items` in the playing order `sequence` (indices into `items`; an item
/// may appear more than once), with `after(k)` inserted after position k
/// when it returns one.
pub(crate) fn arrange<T: Clone>(
    items: &[T],
    sequence: &[usize],
    mut after: impl FnMut(usize) -> Option<T>,
) -> Vec<T> {
    let mut out = Vec::with_capacity(2 * sequence.len());
    for (k, &i) in sequence.iter().enumerate() {
        out.push(items[i].clone());
        out.extend(after(k));
    }
    out
}

/// The played segments of `order` with `rest_cycles` × `rest_period` of
/// rest after every segment whose (cyclic) successor is also moving.
pub(crate) fn arrange_with_rest(
    segments: &[PlayedSegment],
    order: &[usize],
    rest_cycles: u32,
    rest_period: f64,
) -> Vec<PlayedSegment> {
    arrange(segments, order, |k| {
        (rest_cycles > 0 && rest_after(segments, order, k))
            .then(|| PlayedSegment::rest(f64::from(rest_cycles) * rest_period))
    })
}

/// True when position `k` of `order` and its cyclic successor both move.
fn rest_after(segments: &[PlayedSegment], order: &[usize], k: usize) -> bool {
    let next = order[(k + 1) % order.len()];
    segments[order[k]].motion.is_some() && segments[next].motion.is_some()
}

/// The period of one rest cycle: that of the first moving segment.
fn rest_period(segments: &[PlayedSegment]) -> Result<f64> {
    segments
        .iter()
        .find_map(|s| s.motion.as_ref().map(|m| m.period()))
        .ok_or_else(|| {
            Error::invalid(
                "schedule.segments",
                "must hold at least one moving segment to order",
            )
        })
}

fn evaluate(
    segments: &[PlayedSegment],
    order: &[usize],
    rest_cycles: u32,
    t_rest: f64,
    opts: &OrderOptions,
) -> Result<OrderCandidate> {
    let played = arrange_with_rest(segments, order, rest_cycles, t_rest);
    let sm = ScheduleMotion::new(played)?;
    let p = sm.period();
    let moving = sm.moving_time();
    let rest_joins = (0..order.len())
        .filter(|&k| rest_after(segments, order, k))
        .count();
    let verify = PlayOptions {
        warmup_periods: opts
            .verify
            .warmup_periods
            .max(periods_for(opts.warmup_cycles, t_rest, p)),
        periods: opts.verify.periods.max(1),
        ..opts.verify
    };
    let v = verify_points(&sm, &opts.points, &verify);
    Ok(OrderCandidate {
        order: order.to_vec(),
        sequence: order
            .iter()
            .map(|&i| segments[i].label.as_str())
            .collect::<Vec<_>>()
            .join(" → "),
        rest_cycles,
        rest_joins: if rest_cycles > 0 { rest_joins } else { 0 },
        inserted_rest_s: if rest_cycles > 0 {
            rest_joins as f64 * f64::from(rest_cycles) * t_rest
        } else {
            0.0
        },
        moving_fraction: moving / p,
        relative_error: v.relative_error,
        max_abs_error: v.max_abs_error,
        valid: v.valid,
        period_s: p,
        warmup_periods: verify.warmup_periods,
        periods: verify.periods,
    })
}

/// Most segments whose cyclic orders are all tried ((n − 1)! ≤ 24).
pub(crate) const MAX_PERMUTED: usize = 5;

/// One candidate order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Order {
    /// Indices into the segments, in playing order (a segment may appear
    /// twice in a mirrored order).
    pub sequence: Vec<usize>,
    /// True for a mirrored order.
    pub mirrored: bool,
}

/// The mirrored order of a cyclic order σ: σ, then σ₀ and the rest of σ reversed.
pub(crate) fn mirrored(sigma: &[usize]) -> Vec<usize> {
    let mut out = sigma.to_vec();
    if let Some((&first, rest)) = sigma.split_first() {
        out.push(first);
        out.extend(rest.iter().rev());
    }
    out
}

/// The closed loop's candidate orders of `n` segments: every cyclic order
/// (`orders_up_to_rotation` with segment 0 first) when n ≤
/// `MAX_PERMUTED`, else the given order and its reverse; then the
/// mirrored order of each cyclic order up to reversal (n ≥ 3; for n ≤ 2 it
/// would repeat σ). The first candidate is the given order.
pub(crate) fn candidates(n: usize) -> Vec<Order> {
    if n == 0 {
        return Vec::new();
    }
    let identity: Vec<usize> = (0..n).collect();
    let cyclic: Vec<Vec<usize>> = if n <= MAX_PERMUTED {
        orders_up_to_rotation(n, 0)
    } else {
        let rev = mirrored(&identity)[n..].to_vec();
        vec![identity.clone(), rev]
    };
    let mut out: Vec<Order> = cyclic
        .iter()
        .map(|s| Order {
            sequence: s.clone(),
            mirrored: false,
        })
        .collect();
    if n >= 3 {
        for s in &cyclic {
            // σ and its reverse give the same mirrored order, shifted.
            if s[1] > s[n - 1] {
                continue;
            }
            out.push(Order {
                sequence: mirrored(s),
                mirrored: true,
            });
        }
    }
    out
}

/// Error as a sort key (no valid point = worst).
fn key(c: &OrderCandidate) -> f64 {
    if c.relative_error.is_finite() {
        c.relative_error
    } else {
        f64::INFINITY
    }
}

/// The chosen candidate (see the module docs); `None` if no candidate has
/// a valid point.
pub(crate) fn choose(candidates: &[OrderCandidate], tie_tolerance: f64) -> Option<usize> {
    let most = candidates.iter().map(|c| c.valid).max()?;
    let eligible: Vec<usize> = (0..candidates.len())
        .filter(|&i| candidates[i].valid == most && key(&candidates[i]).is_finite())
        .collect();
    let emin = eligible
        .iter()
        .map(|&i| key(&candidates[i]))
        .fold(f64::INFINITY, f64::min);
    eligible
        .into_iter()
        .filter(|&i| key(&candidates[i]) <= emin + tie_tolerance)
        .min_by(|&i, &j| {
            let (a, b) = (&candidates[i], &candidates[j]);
            a.inserted_rest_s
                .total_cmp(&b.inserted_rest_s)
                .then(key(a).total_cmp(&key(b)))
                .then(i.cmp(&j))
        })
}

/// Refuses a search over no points, a bad tie tolerance or segments
/// without a positive duration.
fn check_search(segments: &[PlayedSegment], opts: &OrderOptions) -> Result<()> {
    if opts.points.is_empty() {
        return Err(Error::invalid("points", "must hold at least one point"));
    }
    if !(opts.tie_tolerance.is_finite() && opts.tie_tolerance >= 0.0) {
        return Err(Error::invalid(
            "tie_tolerance",
            format!("must be a finite number ≥ 0, got {}", opts.tie_tolerance),
        ));
    }
    // Validates the segments (durations, motions) once.
    ScheduleMotion::new(segments.to_vec())?;
    if segments
        .iter()
        .any(|s| s.duration.is_nan() || s.duration <= 0.0)
    {
        return Err(Error::invalid(
            "schedule.segments",
            "every segment to order must have a positive duration",
        ));
    }
    Ok(())
}

/// One order and rest evaluated: the candidate, or why it could not be.
type Evaluate<'a> = dyn Fn(&[usize], u32) -> Result<OrderCandidate> + 'a;

/// The heuristic search for many segments: steepest descent over pairwise
/// swaps from `start` at rest `k0`, within `budget` evaluations, pushing
/// every candidate onto `candidates`; returns the number of orders seen.
fn descend(
    start: Vec<usize>,
    k0: u32,
    budget: usize,
    evaluate: &Evaluate,
    candidates: &mut Vec<OrderCandidate>,
) -> Result<usize> {
    let n = start.len();
    let mut current = start;
    candidates.push(evaluate(&current, k0)?);
    let mut current_err = key(&candidates[0]);
    let mut seen = vec![current.clone()];
    'descent: loop {
        let mut step: Option<(Vec<usize>, f64)> = None;
        for i in 1..n {
            for j in i + 1..n {
                if candidates.len() >= budget {
                    break 'descent;
                }
                let mut o = current.clone();
                o.swap(i, j);
                if seen.contains(&o) {
                    continue;
                }
                seen.push(o.clone());
                let c = evaluate(&o, k0)?;
                let e = key(&c);
                candidates.push(c);
                if step.as_ref().is_none_or(|s| e < s.1) {
                    step = Some((o, e));
                }
            }
        }
        match step {
            Some((o, e)) if e < current_err => {
                current = o;
                current_err = e;
            }
            _ => break,
        }
    }
    Ok(seen.len())
}

/// The rest insertions to try, in cycles: sorted, without repeats, and
/// no rest when none is given.
fn rest_choices(asked: &[u32]) -> Vec<u32> {
    let mut rests = asked.to_vec();
    rests.sort_unstable();
    rests.dedup();
    if rests.is_empty() {
        rests.push(0);
    }
    rests
}

/// Searches orders and rest insertions of `segments` (see the module docs).
fn search_orders(segments: &[PlayedSegment], opts: &OrderOptions) -> Result<OrderSearch> {
    check_search(segments, opts)?;
    let t_rest = rest_period(segments)?;
    let first = segments
        .iter()
        .position(|s| s.motion.is_some())
        .unwrap_or(0);
    let rests = rest_choices(&opts.rest_cycles);
    let n = segments.len();
    let mut candidates = Vec::new();
    let method;
    let orders = if n <= opts.exhaustive_max {
        orders_up_to_rotation(n, first)
    } else {
        Vec::new()
    };
    let total = if n <= opts.exhaustive_max {
        orders.len() * rests.len()
    } else {
        opts.max_evaluations.max(1) + rests.len() - 1
    };
    let progress = Progress::new("order search", "candidates", total as u64, opts.progress);
    let evaluate = |o: &[usize], k: u32| {
        let c = evaluate(segments, o, k, t_rest, opts);
        progress.inc(1);
        c
    };
    if n <= opts.exhaustive_max {
        method = format!(
            "exhaustive: all {} orders of {n} segments up to rotation ({} first), × rest {:?} cycles at every join",
            orders.len(),
            segments[first].label,
            rests
        );
        for o in &orders {
            for &k in &rests {
                candidates.push(evaluate(o, k)?);
            }
        }
    } else {
        let k0 = rests[0];
        let start: Vec<usize> = (first..n).chain(0..first).collect();
        let budget = opts.max_evaluations.max(1);
        let seen = descend(start.clone(), k0, budget, &evaluate, &mut candidates)?;
        // Whatever the budget, the rest insertions go on the best order found.
        let best_order = candidates
            .iter()
            .min_by(|a, b| key(a).total_cmp(&key(b)))
            .map_or(start, |c| c.order.clone());
        for &k in &rests[1..] {
            candidates.push(evaluate(&best_order, k)?);
        }
        method = format!(
            "heuristic ({n} segments > {}): steepest descent over pairwise swaps from the given order ({} first), rest {k0} cycles, {seen} orders evaluated (budget {}); then rest {:?} cycles on the best order",
            opts.exhaustive_max,
            segments[first].label,
            opts.max_evaluations,
            &rests[1..]
        );
    }
    progress.finish();
    let best = choose(&candidates, opts.tie_tolerance).ok_or_else(|| {
        Error::ContactLost(
            "order search: no candidate has a valid point (parts leave the plate everywhere)"
                .into(),
        )
    })?;
    Ok(OrderSearch {
        segments: segments.iter().map(|s| s.label.clone()).collect(),
        method,
        candidates,
        best,
        points: opts.points.len(),
        model: opts.verify.model.name(),
        rest_period_s: t_rest,
        tie_tolerance: opts.tie_tolerance,
        warmup_cycles: opts.warmup_cycles,
    })
}

/// `n × n` points over the bounding box of `points` (the target region).
pub(crate) fn region_grid(points: &[[f64; 2]], n: usize) -> Vec<[f64; 2]> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if !(lo[0].is_finite() && hi[0].is_finite()) {
        return Vec::new();
    }
    crate::field::Grid {
        x: [lo[0], hi[0]],
        y: [lo[1], hi[1]],
        n: [n, n],
    }
    .points()
}

/// Reorders a designed schedule: searches its segments' orders and rest
/// insertions ([`search_orders`]) and returns the schedule of the chosen
/// candidate with the search. The schedule keeps its format: segments in
/// the chosen order, inserted rest segments (no primitive, weight 0 — the
/// fit gave them none — `cycles` rest cycles of the first moving segment's
/// period), `total_cycles` and `period_s` recomputed. `fit` and
/// `fit_quantized` still describe the design's time fractions without the
/// inserted rest: inserted rest scales the realised field by the chosen
/// candidate's moving fraction over the original one. Segments of zero
/// duration are dropped, as when the schedule is played.
pub(crate) fn choose_order(
    schedule: &Schedule,
    opts: &OrderOptions,
) -> Result<(Schedule, OrderSearch)> {
    let mut items: Vec<&Segment> = Vec::with_capacity(schedule.segments.len());
    let mut played = Vec::with_capacity(schedule.segments.len());
    for (i, seg) in schedule.segments.iter().enumerate() {
        let p = PlayedSegment::from_segment(seg, i)?;
        if p.duration > 0.0 {
            items.push(seg);
            played.push(p);
        }
    }
    let search = search_orders(&played, opts)?;
    let best = search.chosen();
    let items: Vec<Segment> = items.into_iter().cloned().collect();
    let segments = arrange(&items, &best.order, |k| {
        (best.rest_cycles > 0 && rest_after(&played, &best.order, k)).then(|| Segment {
            label: "Rest".into(),
            primitive: None,
            motion: None,
            ramp_cycles: None,
            weight: 0.0,
            cycles: best.rest_cycles,
            duration_s: f64::from(best.rest_cycles) * search.rest_period_s,
        })
    });
    let out = schedule.with_segments(segments);
    Ok((out, search))
}

/// What `platefield order` is asked to do.
#[derive(Debug, Clone, PartialEq)]
pub struct OrderRequest {
    /// Points per side of the grid over ±3 cm.
    pub n: usize,
    /// Rest cycles tried at every join.
    pub rest_cycles: Vec<u32>,
    /// Warm-up periods (a minimum).
    pub warmup: u32,
    /// Measured periods (a minimum).
    pub periods: u32,
    /// Model override (default: the schedule's own).
    pub model: Option<Model>,
    /// Progress output and the long-run guard.
    pub runtime: crate::work::Runtime,
}

/// The work of an order search of `schedule` with `opts`
/// ([`crate::work`]): candidates × parts × periods (warm-up, at least
/// `warmup_cycles` primitive cycles, and measured) × cycles per period
/// (with the most rest inserted at every join) × steps.
pub(crate) fn work_estimate(schedule: &Schedule, opts: &OrderOptions) -> Estimate {
    let moving = schedule.segments.iter().filter(|s| s.cycles > 0).count();
    let rests = {
        let mut r = opts.rest_cycles.clone();
        r.sort_unstable();
        r.dedup();
        r.len().max(1)
    };
    let candidates = if moving <= opts.exhaustive_max {
        (1..moving).product::<usize>() * rests
    } else {
        opts.max_evaluations.max(1) + rests - 1
    };
    let max_rest = opts.rest_cycles.iter().copied().max().unwrap_or(0);
    let cycles = f64::from(schedule.total_cycles) + (f64::from(max_rest) * moving as f64);
    let warmup = f64::from(opts.verify.warmup_periods)
        .max((f64::from(opts.warmup_cycles) / cycles.max(1.0)).ceil());
    let periods = warmup + f64::from(opts.verify.periods.max(1));
    Estimate::new(
        "schedule",
        "searching the segment order",
        "fewer segments, --points, --rest, --warmup or --periods",
    )
    .plus(
        Term::new("order search")
            .times(candidates as f64, "candidates")
            .times(opts.points.len() as f64, "parts")
            .times(periods, "periods")
            .times(cycles, "cycles")
            .times(opts.verify.numerics.steps_per_cycle as f64, "steps"),
    )
}

/// What `platefield order` found (written by `crate::report::order`).
#[derive(Debug, Clone)]
pub struct OrderOutcome {
    /// The schedule searched, as read.
    pub schedule: Schedule,
    /// Every order and rest insertion judged, and the one chosen.
    pub search: OrderSearch,
}

/// `platefield order`: searches the orders and rest insertions of the
/// schedule at `path` on `n × n` points over ±3 cm with the schedule's own
/// physics (the model overridden by `model` when given; `warmup` and
/// `periods` are minimums); returns the schedule and the search. The work
/// is estimated first and refused above `crate::work::LIMIT_S` unless
/// `runtime.allow_long`.
///
/// ```no_run
/// use platefield::design::order::{order_schedule_file, OrderRequest};
/// use platefield::work::Runtime;
/// let req = OrderRequest {
///     n: 5,
///     rest_cycles: vec![0, 2],
///     warmup: 1,
///     periods: 1,
///     model: None,
///     runtime: Runtime::QUIET,
/// };
/// let outcome = order_schedule_file(std::path::Path::new("results/synthesized/sink/schedule.json"), &req)?;
/// println!("{} orders judged", outcome.search.candidates.len());
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn order_schedule_file(path: &Path, req: &OrderRequest) -> Result<OrderOutcome> {
    let OrderRequest {
        n,
        ref rest_cycles,
        warmup,
        periods,
        model,
        runtime,
    } = *req;
    if !(2..=41).contains(&n) {
        return Err(Error::invalid(
            "--points",
            format!("must be in 2..=41, got {n}: each order is measured by its model check (moving parts against the prediction) over the N×N grid of points, and N = 1 is the region's centre alone (usually the attractor, where the field is zero)"),
        ));
    }
    if let Some(k) = rest_cycles.iter().find(|&&k| k > 100) {
        return Err(Error::invalid(
            "--rest",
            format!("rest cycles must be in 0..=100, got {k}"),
        ));
    }
    if !(1..=100).contains(&periods) {
        return Err(Error::invalid(
            "--periods",
            format!("must be in 1..=100, got {periods}"),
        ));
    }
    if warmup > 100 {
        return Err(Error::invalid(
            "--warmup",
            format!("must be in 0..=100, got {warmup}"),
        ));
    }
    let schedule = Schedule::load(path)?;
    let settings = schedule.settings;
    schedule.target_folder()?;
    let mut verify = PlayOptions {
        warmup_periods: warmup,
        periods,
        ..PlayOptions::from_settings(&settings)
    };
    if let Some(m) = model {
        verify.model = m;
    }
    let opts = OrderOptions {
        rest_cycles: rest_cycles.to_vec(),
        progress: runtime.progress(),
        ..OrderOptions::new(verify, grid_points(n, 0.03))
    };
    runtime.admit(&work_estimate(&schedule, &opts))?;
    let (_, search) = choose_order(&schedule, &opts)?;
    Ok(OrderOutcome { schedule, search })
}

#[cfg(test)]
#[path = "../../tests/unit/order.rs"]
mod order_tests;

#[cfg(test)]
mod tests {
    use super::*;

    /// (n − 1)! distinct orders, each a permutation with `first` leading,
    /// and no two of them cyclic rotations of each other.
    #[test]
    fn orders_are_permutations_up_to_rotation() {
        for n in 1..=6 {
            let orders = orders_up_to_rotation(n, n / 2);
            let fact: usize = (1..n).product();
            assert_eq!(orders.len(), fact.max(1), "n = {n}");
            for o in &orders {
                assert_eq!(o[0], n / 2);
                let mut s = o.clone();
                s.sort_unstable();
                assert_eq!(s, (0..n).collect::<Vec<_>>());
            }
            let canon = |o: &Vec<usize>| {
                (0..n)
                    .map(|r| {
                        let mut v = o.clone();
                        v.rotate_left(r);
                        v
                    })
                    .min()
                    .unwrap()
            };
            let mut c: Vec<Vec<usize>> = orders.iter().map(canon).collect();
            c.sort();
            c.dedup();
            assert_eq!(c.len(), orders.len(), "n = {n}: two orders are rotations");
        }
        assert!(orders_up_to_rotation(0, 0).is_empty());
    }

    #[test]
    fn counts_and_first_candidate() {
        // n = 4: 3! = 6 cyclic orders, 3 mirrored ones.
        let c = candidates(4);
        assert_eq!(c.len(), 9);
        assert_eq!(c[0].sequence, vec![0, 1, 2, 3]);
        assert_eq!(c.iter().filter(|o| o.mirrored).count(), 3);
        assert!(c.contains(&Order {
            sequence: vec![0, 1, 2, 3, 0, 3, 2, 1],
            mirrored: true
        }));
        // Distinct, and every cyclic order starts with segment 0.
        for (i, a) in c.iter().enumerate() {
            assert_eq!(a.sequence[0], 0);
            for b in &c[i + 1..] {
                assert_ne!(a, b);
            }
        }
        // n ≤ 2: one cyclic order, and mirroring only repeats it.
        assert_eq!(candidates(1).len(), 1);
        assert_eq!(candidates(2).len(), 1);
        assert_eq!(candidates(3).len(), 2 + 1);
        assert_eq!(candidates(5).len(), 24 + 12);
        // Beyond MAX_PERMUTED: the design's order, its reverse, their mirror.
        let big = candidates(7);
        assert_eq!(big.len(), 3);
        assert_eq!(big[1].sequence, vec![0, 6, 5, 4, 3, 2, 1]);
    }

    #[test]
    fn mirrored_order_has_both_turn_senses() {
        // Every segment appears twice, and the joins of the second half are
        // those of the first, reversed: (a→b) in the first half pairs with
        // (b→a) in the second.
        let m = mirrored(&[0, 1, 2, 3]);
        let n = m.len();
        let joins: Vec<(usize, usize)> = (0..n).map(|i| (m[i], m[(i + 1) % n])).collect();
        for &(a, b) in &joins {
            assert!(joins.contains(&(b, a)), "{joins:?}");
        }
    }
}
