//! Played polish of a synthesized motion: a local search whose objective
//! is the *played* realised measure itself.
//!
//! **Why.** [`crate::synth::synthesize`] optimises the steady-state field on
//! a coarse grid of the region, every grid point weighted alike. The played
//! measure ([`super::judge::realised_error`]) weights the field where the parts
//! go: a part started at rest is measured over windows after a warm-up, at
//! its mean position. For an expanding target the parts spend the measured
//! windows outside the region (the saddle with its sequenced limits: parts
//! started inside the region are measured well outside it, and parts
//! started at its edge leave the plate during the warm-up where the tilts
//! swing N below zero — outside the region the contact margin covers, so
//! the measure leaves them out), and parts of a squeeze crowd near its
//! line; so the played strength can fall below the predicted one at the
//! same motion. The played measure is cheap (5 × 5 start points, 60
//! cycles), so it can be the objective of a last local refinement.
//!
//! **Cost** of a parameter vector (`synth::params::Layout`), with
//! ŝ and e the played realised strength and shape error at the given start
//! points, s₀ the starting motion's played strength:
//!
//! ```text
//! cost = −ŝ / s₀ + 20 · max(0, e − budget)          (shape first)
//!      + 20 · max(0, e_grid − grid budget)           (the region's shape kept)
//!      + Σ_axes max(0, peak/limit − 1)               (excess clamped away)
//!      + 100 · max(0, m + 0.01 − N_min/g)            (contact margin over the region, kept with the synthesis's safety)
//!      + 10 · (invalid coarse samples / samples)
//!      + 10 · max(0, lost − lost₀) / played          (no more parts lost inside the region than at the start)
//! ```
//!
//! e_grid is the shape error of the steady-state field on the coarse grid
//! over the whole region, its budget the larger of `grid_budget` and the
//! start's: without it the polish would trade the field where parts do
//! not go for the field where they do (on squeeze_trans it gains played
//! strength at the cost of the region's shape — parts are squeezed onto
//! the line during the warm-up and measured only there). N_min and the coarse
//! samples are those of the synthesis objective
//! (`Objective`: kinematic and steady-orbit least N on the coarse grid),
//! so the polish keeps every constraint the synthesis kept; parts lost
//! *outside* the region (as the saddle's above) may not become more.
//!
//! **Search**: Levenberg–Marquardt
//! ([`crate::synth::levenberg`], [`PolishOptions::lm`]) on the played
//! residuals — the cost above as a sum of squares: each part's
//! ω_i (R_i − ŝ P_i) rescaled to the norm 20 · max(0, e − b)
//! (`shape_block`; b the budget, or 0 for a start within it: below),
//! a strength row, 20 · max(0, e_grid − grid budget),
//! the excess, 10 · the margin violation, √(10 · invalid fraction) and
//! √(10 · extra lost fraction). The strength row is a − ŝ/s₀ with a =
//! [`STRENGTH_REACH`] (2), whose square has the cost's slope −1/s₀ at
//! ŝ = s₀: it asks for strength as the cost does (a row 1 − ŝ/(1.1 s₀)
//! asks for less once ŝ nears 1.1 s₀). For a start over the budget the
//! played shape block is
//! the cost's hinge (b = the budget). For a start within it the block
//! steers by the whole shape error (b = 0), as the synthesis's does
//! ([`crate::synth::objective`]): the hinge is zero there, so with it the
//! linearisation would see strength alone and its steps buy strength with
//! shape (on squeeze_trans they double its shape error); with the whole
//! shape error they gain both.
//!
//! **Shape first**, as the cost: when the start's played shape is over the budget, the first half of the steps
//! run with 1 − ŝ/([`POLISH_GOAL`] s₀), which asks for 10 % more and lets
//! the shape block lead (with the first row alone, a start just over the
//! budget, as the whirlpool's, stays over it). A start within the budget
//! runs the second half only: it has no shape to put first, and its steps
//! then cost what an over-budget start's strength steps do (more steps
//! still gain strength, at a cost of plays a design's polish is not meant
//! to spend). Each step's Jacobian is one parallel batch of n plays (recorded
//! in order: same bytes on one thread or two), so four steps are ≈ 4n + 9
//! plays where Nelder–Mead needs 300:
//! plays that confirm the synthesis and correct it, not a search. With
//! `lm` `None` it runs argmin's Nelder–Mead from the synthesized motion
//! (initial simplex `step`, restarts from the best point with a third of
//! that step, halving at each restart) until `max_plays` plays are spent
//! or the stall rule ([`PolishOptions::stall`], counted in plays) says the
//! played cost has stopped improving.
//!
//! **Never loses.** The cost steers; the played measure judges.
//! A played motion may replace the start only if `auto`'s rule between
//! candidates ([`crate::design::method::Rule`]: POOR, then realised shape errors within
//! one percentage point broken by the higher strength, else the lower
//! shape error) prefers its played measure to the start's — or, not
//! POOR, it plays a lower shape error than the start at a lower cost (a
//! gain of shape within a point, which the rule calls a tie) — and it
//! breaks none of the cost's constraint
//! terms more than the start (grid shape, margin, invalid samples, lost
//! parts). The peak excess is not one of them: a parameter vector is
//! played, checked and kept as its motion clamped onto the limits
//! (`Objective::motion`), which exceeds none; the excess term only
//! keeps the steps near the limits (squeeze_trans presses them, and its
//! steps that gain strength at a lower shape error go a few per cent past
//! them before the clamp). Of those, the one of
//! lowest cost is re-checked on the full grid (`Checked::of`) and kept
//! if the check is not POOR (unless the start was POOR too); otherwise the
//! start is returned unchanged. The polish stops when that measure stops
//! improving: after [`PolishOptions::patience`] steps' worth of plays
//! (n + 2 each) without a motion that replaces the best so far (a start
//! that no step beats by the rule, as the sink's synthesized motion, stops
//! after its first Jacobian and tries). `design` plays the polish exactly
//! as the judge plays the schedule — its cycles (10 warm-up, 10
//! measured), and the motion as a segment of
//! the judge's cycles, with the period played after
//! the windows in which a part that leaves the plate is left out — so the
//! polish's measure of a motion is the check's, bit for bit. Played in
//! one-cycle periods instead, the two measures disagree (on the saddle by
//! several points of shape error), and a polish on the one-cycle measure
//! can make the check's worse.
//!
//! **Overfitting check.** The polish sees only the start points it is given;
//! the study reports the kept motion on a second, disjoint set of start
//! points as well (`platefield_studies::synthesis`).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use rayon::prelude::*;

use super::judge::compare::{self, Promise};
use super::judge::{PointPlay, RealisedError};
use super::rule;
use crate::error::{positive, Error, Result};
use crate::field::{FieldSettings, Grid};
use crate::motion::Motion;
use crate::play::{PlayedSegment, ScheduleMotion};
use crate::request::{SampledTarget, Target};
use crate::scene::FrictionSpec;
use crate::synth::levenberg::{levenberg_marquardt, LmOptions};
use crate::synth::multistart::nelder_mead;
use crate::synth::objective::{
    shape_block, Objective, CONTACT_WEIGHT, INVALID_WEIGHT, LIMIT_WEIGHT,
};
use crate::synth::params::{Coefficients, Layout};
use crate::synth::progress::{ProgressMode, SynthesisProgress};
use crate::synth::stall::{StallRule, StallTracker};
use crate::synth::{Checked, ShakerLimits, Synthesis};
use crate::work::Stop;

/// Weight of the played shape error over budget (the synthesis objective's).
pub const SHAPE_WEIGHT: f64 = crate::synth::objective::SHAPE_WEIGHT;
/// Strength goal of the played residuals, relative to the start's played
/// strength, while the start's played shape is over budget (module
/// documentation): the strength row asks for 10 % more.
pub const POLISH_GOAL: f64 = 1.1;
/// The played strength row a − ŝ/s₀ asks for up to a = 2 times the
/// start's played strength (module documentation: the row's square then
/// has the cost's slope −1/s₀ at ŝ = s₀).
pub const STRENGTH_REACH: f64 = 2.0;
/// Cap on the played shape error inside the cost.
const SHAPE_CAP: f64 = 10.0;

/// Settings of the played polish.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolishOptions {
    /// Plays allowed (each also one coarse re-simulation for the contact
    /// check).
    pub max_plays: usize,
    /// Played shape-error budget (the cost's knee).
    pub shape_budget: f64,
    /// Shape-error budget of the steady-state field on the coarse grid
    /// over the whole region (the start's, if larger): the motion must keep
    /// the target's shape where the parts do not go as well.
    pub grid_budget: f64,
    /// Initial simplex step (fraction of each axis limit).
    pub step: f64,
    /// Coarse grid [nx, ny] of the contact check.
    pub coarse: [usize; 2],
    /// Stop once the played cost has stopped improving
    /// ([`crate::synth::stall`]); `None` spends `max_plays`.
    pub stall: Option<StallRule>,
    /// Progress display (default quiet): a bar on a terminal, a plain line
    /// otherwise ([`crate::progress::Progress`]); never part of the result.
    pub progress: ProgressMode,
    /// Play every candidate at the ends and middle of this friction range
    /// and score its worst case ([`crate::synth::robust`]); `None` (or an
    /// exact friction): the settings' friction only.
    pub robust: Option<FrictionSpec>,
    /// Levenberg–Marquardt on the played residuals with these settings
    /// (module documentation); `None`: Nelder–Mead with restarts.
    pub lm: Option<LmOptions>,
    /// With `lm`: stop once this many Levenberg–Marquardt steps' worth of
    /// plays (n + 2 each, n parameters) have found no motion the choice's
    /// rule prefers to the best so far (module documentation); `None`:
    /// the steps and `max_plays` alone end it.
    pub patience: Option<usize>,
}

/// Played shape error of the start above which the polish takes all its
/// steps whatever [`PolishOptions::patience`] says: patience stops the
/// whirlpool designed for μ 0.15 early just above this, where its further
/// steps reach well below it; a sink already below keeps its early
/// stop.
pub const PATIENT_BELOW: f64 = 0.06;

impl Default for PolishOptions {
    fn default() -> Self {
        PolishOptions {
            max_plays: 200,
            shape_budget: 0.045,
            grid_budget: 0.06,
            step: 0.03,
            coarse: [7, 7],
            stall: None,
            progress: ProgressMode::Quiet,
            robust: None,
            lm: Some(crate::synth::POLISH_LM),
            patience: Some(1),
        }
    }
}

impl PolishOptions {
    fn validate(&self) -> Result<()> {
        if self.max_plays == 0 {
            return Err(Error::invalid("polish.max_plays", "must be ≥ 1"));
        }
        positive("polish.shape_budget", self.shape_budget)?;
        positive("polish.grid_budget", self.grid_budget)?;
        positive("polish.step", self.step)?;
        if let Some(r) = &self.stall {
            if r.window == 0 {
                return Err(Error::invalid("polish.stall.window", "must be ≥ 1"));
            }
            if !(r.tol >= 0.0 && r.tol.is_finite()) {
                return Err(Error::invalid("polish.stall.tol", "must be finite and ≥ 0"));
            }
        }
        for (i, n) in self.coarse.iter().enumerate() {
            if !(2..=101).contains(n) {
                return Err(Error::invalid(
                    format!("polish.coarse[{i}]"),
                    format!("must be in 2..=101, got {n}"),
                ));
            }
        }
        Ok(())
    }
}

/// A polished synthesis, with the played measure before and after.
#[derive(Debug, Clone)]
pub struct Polished {
    /// The polished synthesis, or the given one when the polish did not
    /// help (`improved` false).
    pub synthesis: Synthesis,
    /// Played measure of the given motion.
    pub before: RealisedError,
    /// Played measure of the motion returned.
    pub after: RealisedError,
    /// Played cost of the given motion (see the module documentation).
    pub cost_before: f64,
    /// Played cost of the motion returned.
    pub cost_after: f64,
    /// Whether the polished motion was kept.
    pub improved: bool,
    /// Plays used.
    pub plays: usize,
    /// Why the search ended: the plays spent, no gain within patience or
    /// the stall rule, or the search's own stop (Levenberg–Marquardt's, or
    /// Nelder–Mead's simplex converged).
    pub stop: Stop,
    /// Wall time (s); not part of any data file.
    pub seconds: f64,
}

/// One played evaluation.
#[derive(Debug, Clone)]
struct Eval {
    params: Vec<f64>,
    cost: f64,
    played: RealisedError,
    residuals: Vec<f64>,
    /// The cost's constraint terms (grid shape over budget, excess, margin,
    /// invalid samples, extra lost parts).
    penalty: f64,
    /// The excess term of `penalty`, which the motion played (clamped onto
    /// the limits) does not break: a motion kept breaks none of the others
    /// more than the start ([`Played::beats_start`]).
    excess: f64,
}

impl Eval {
    /// The choice's key of the played measure ([`rule::Key`]): POOR (shape
    /// over [`crate::fit::POOR_ERROR`], not measured, or no strength), the
    /// realised shape error and strength.
    fn key(&self) -> rule::Key {
        let p = &self.played;
        let measured = p.shape_error.is_finite() && p.shape_error <= crate::fit::POOR_ERROR;
        let poor = !measured
            || p.realised_strength.is_nan()
            || p.realised_strength <= 0.0
            || p.valid < rule::MIN_MEASURED_POINTS;
        let shape = if p.shape_error.is_finite() {
            p.shape_error
        } else {
            f64::INFINITY
        };
        let strength = if p.realised_strength.is_finite() {
            p.realised_strength
        } else {
            f64::NEG_INFINITY
        };
        (poor, shape, strength)
    }
}

/// The played objective (see the module documentation).
struct Played<'a> {
    /// The target's promise, built once ([`Promise`]).
    promise: Promise<'a>,
    sampled: &'a SampledTarget,
    /// The target region: parts lost inside it count against a motion.
    region: &'a Grid,
    starts: &'a [usize],
    objective: Objective<'a>,
    options: &'a PolishOptions,
    strength_ref: f64,
    lost_ref: usize,
    grid_budget: f64,
    /// The budget b of the played shape block (module documentation): the
    /// played shape budget for a start over it, 0 for a start within it.
    steer_budget: f64,
    /// The strength row is `reach − ŝ/goal` (module documentation).
    goal: f64,
    /// See `goal`.
    reach: f64,
    plays: AtomicUsize,
    best: Mutex<Option<Eval>>,
    /// The start's evaluation, once made: what a motion kept must beat.
    start: Option<Eval>,
    /// The lowest-cost evaluation that beats the start by the choice's rule
    /// without breaking a constraint more ([`Played::beats_start`]).
    kept: Mutex<Option<Eval>>,
    /// Plays counted when `kept` last changed (the start's, at first).
    gained_at: AtomicUsize,
    /// Plays without a gain that end the polish ([`PolishOptions::patience`]).
    patience_plays: usize,
    stall: Mutex<StallTracker>,
    bar: crate::progress::Progress,
}

impl Played<'_> {
    /// The played measure of `c`: its worst case over the objective's
    /// physics ([`RealisedError::worst_of`]), the played residuals
    /// (module documentation) under each physics in turn, and the most
    /// parts lost inside the region under one physics ([`lost_inside`]).
    fn play(&self, c: &Coefficients) -> Result<(RealisedError, Vec<f64>, usize)> {
        let sm = ScheduleMotion::new(vec![PlayedSegment::moving(
            "synthesized",
            Motion::Signals(c.to_signals()),
            1,
        )])?;
        let mut residuals = Vec::new();
        let mut each = Vec::new();
        let mut lost = 0;
        for settings in self.objective.physics() {
            let plays = super::judge::play_motion(&sm, &self.sampled.points, self.starts, settings);
            let r = compare::realised_error_of(&self.promise, &self.sampled.weights, &plays, None);
            residuals.extend(self.part_residuals(&plays, &r));
            each.push(r);
            lost = lost.max(lost_inside(&plays, self.region));
        }
        let worst = RealisedError::worst_of(&each)
            .ok_or_else(|| Error::Internal("no physics to play the polish under".into()))?;
        Ok((worst, residuals, lost))
    }

    /// The shape block of the played residuals (module documentation):
    /// ω_i (R_i − ŝ P_i) for each part in start order (P_i the promise
    /// along its windows, 0 for a part that does not count), rescaled by
    /// [`shape_block`] to the cost's shape term.
    fn part_residuals(&self, plays: &[PointPlay], r: &RealisedError) -> Vec<f64> {
        let s = r.realised_strength;
        let raw: Vec<f64> = plays
            .iter()
            .flat_map(|p| {
                if !compare::counts(&self.sampled.weights, p) || !s.is_finite() {
                    return [0.0, 0.0];
                }
                let w = self.sampled.weights[p.index];
                let t = self.promise.along(&[p], s)[0];
                [w * (p.realised[0] - t[0]), w * (p.realised[1] - t[1])]
            })
            .collect();
        shape_block(&raw, r.shape_error, self.steer_budget)
    }

    /// The evaluation of `params`, not counted (callable from several
    /// threads).
    fn measure(&self, params: &[f64]) -> Result<Eval> {
        let (c, excess) = self.objective.motion(params);
        let coarse = self.objective.measure(params);
        let (played, mut residuals, lost) = self.play(&c)?;
        let margin = self.objective.margin_violation(coarse.least_normal);
        let shape = if played.shape_error.is_finite() && played.realised_strength > 0.0 {
            played.shape_error.min(SHAPE_CAP)
        } else {
            SHAPE_CAP
        };
        let strength = if played.realised_strength.is_finite() {
            played.realised_strength
        } else {
            0.0
        };
        let grid_over = (coarse.realised.shape_error.min(SHAPE_CAP) - self.grid_budget).max(0.0);
        let invalid = coarse.realised.invalid as f64 / self.objective_len() as f64;
        let lost_over = lost.saturating_sub(self.lost_ref) as f64 / self.starts.len().max(1) as f64;
        let penalty = SHAPE_WEIGHT * grid_over
            + LIMIT_WEIGHT * excess
            + CONTACT_WEIGHT * margin
            + INVALID_WEIGHT * invalid
            + INVALID_WEIGHT * lost_over;
        let cost = -strength / self.strength_ref
            + SHAPE_WEIGHT * (shape - self.options.shape_budget).max(0.0)
            + penalty;
        residuals.extend([
            self.reach - strength / self.goal,
            SHAPE_WEIGHT * grid_over,
            LIMIT_WEIGHT.sqrt() * excess,
            CONTACT_WEIGHT.sqrt() * margin,
            (INVALID_WEIGHT * invalid).sqrt(),
            (INVALID_WEIGHT * lost_over).sqrt(),
        ]);
        Ok(Eval {
            params: params.to_vec(),
            cost,
            played,
            residuals,
            penalty,
            excess: LIMIT_WEIGHT * excess,
        })
    }

    /// Counts `e`: plays, the stall rule, the best.
    fn record(&self, e: &Eval) {
        let n = self.plays.fetch_add(1, Ordering::Relaxed) + 1;
        if self.start.is_none() {
            self.gained_at.store(n, Ordering::Relaxed);
        }
        self.bar.set_position(n as u64);
        self.stall
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .record(e.cost, self.options.stall.as_ref());
        if self.beats_start(e) {
            let mut kept = self.kept.lock().unwrap_or_else(|p| p.into_inner());
            if kept.as_ref().is_none_or(|k| e.cost < k.cost) {
                *kept = Some(e.clone());
                self.gained_at.store(n, Ordering::Relaxed);
            }
        }
        let mut best = self.best.lock().unwrap_or_else(|p| p.into_inner());
        if best.as_ref().is_none_or(|b| e.cost < b.cost) {
            self.bar.set_message(format!(
                "best played: strength {:.4}, shape error {:.2} %",
                e.played.realised_strength,
                100.0 * e.played.shape_error
            ));
            *best = Some(e.clone());
        }
    }

    /// Whether `e` may replace the start (module documentation): the
    /// choice's rule prefers its played measure ([`rule::better`]), or it
    /// is not POOR and plays a lower shape error at a lower cost; and it
    /// breaks no constraint of the cost more than the start does (the peak
    /// excess aside: the motion played is clamped onto the limits).
    fn beats_start(&self, e: &Eval) -> bool {
        self.start.as_ref().is_some_and(|s| {
            let (a, b) = (s.key(), e.key());
            let preferred = rule::better(a, b).0 || (!b.0 && b.1 < a.1 && e.cost < s.cost);
            preferred && e.penalty - e.excess <= s.penalty - s.excess + 1e-12
        })
    }

    fn evaluate(&self, params: &[f64]) -> Result<Eval> {
        let e = self.measure(params)?;
        self.record(&e);
        Ok(e)
    }

    /// Evaluates `points` in parallel and records them in their order
    /// (same bytes on one thread or two); their residual vectors.
    fn evaluate_batch(&self, points: &[Vec<f64>]) -> Result<Vec<Vec<f64>>> {
        let all: Vec<Result<Eval>> = points.par_iter().map(|p| self.measure(p)).collect();
        let mut out = Vec::with_capacity(all.len());
        for e in all {
            let e = e?;
            self.record(&e);
            out.push(e.residuals);
        }
        Ok(out)
    }

    fn objective_len(&self) -> usize {
        self.options.coarse[0] * self.options.coarse[1]
    }

    fn spent(&self) -> bool {
        self.spent_stop().is_some()
    }

    /// Why the budget rules end the search, if they do: the plays are
    /// spent, or patience or the stall rule saw no gain.
    fn spent_stop(&self) -> Option<Stop> {
        let plays = self.plays.load(Ordering::Relaxed);
        if plays >= self.options.max_plays {
            Some(Stop::Spent)
        } else if plays.saturating_sub(self.gained_at.load(Ordering::Relaxed))
            >= self.patience_plays
            || self
                .stall
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .stalled(self.options.stall.as_ref())
        {
            Some(Stop::NoGain)
        } else {
            None
        }
    }

    fn best(&self) -> Option<Eval> {
        self.best.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }
}

/// Parts of `plays` that lost contact inside `region` ([`in_region`]):
/// the judge's failures. A part lost after it left the region
/// (an expanding target's) is left out of the measure, as the check
/// leaves it out, and is no failure.
fn lost_inside(plays: &[PointPlay], region: &Grid) -> usize {
    plays
        .iter()
        .filter(|p| p.note.is_some() && p.lost_at.is_none_or(|q| in_region(region, q)))
        .count()
}

/// Whether `q` lies in `region` (its edges widened by a relative 1e-9).
pub(crate) fn in_region(region: &Grid, q: [f64; 2]) -> bool {
    let (dx, dy) = (
        1e-9 * (region.x[1] - region.x[0]).abs(),
        1e-9 * (region.y[1] - region.y[0]).abs(),
    );
    q[0] >= region.x[0] - dx
        && q[0] <= region.x[1] + dx
        && q[1] >= region.y[0] - dy
        && q[1] <= region.y[1] + dy
}

/// Levenberg–Marquardt from `x0` on the played residuals, its Jacobian's
/// columns one parallel batch of plays.
fn run_lm(played: &Played<'_>, x0: &[f64], lm: &LmOptions) -> Result<Stop> {
    let report = levenberg_marquardt(
        x0,
        &|xs: &[Vec<f64>]| played.evaluate_batch(xs),
        || played.spent(),
        lm,
    )?;
    Ok(report.stop)
}

/// The least-squares polish from `x0` (module documentation): when the
/// start is `over` the played shape budget, the first half of the steps
/// shape first (strength row 1 − ŝ/([`POLISH_GOAL`] s₀)), then the rest
/// from the best point so far with the strength row a − ŝ/s₀; a start
/// within the budget runs that second half only.
fn run_lm_shape_first(
    played: &mut Played<'_>,
    x0: &[f64],
    over: bool,
    lm: &LmOptions,
) -> Result<Stop> {
    let mut from = x0.to_vec();
    let first = lm.max_iterations / 2;
    let left = lm.max_iterations - first;
    if over {
        (played.reach, played.goal) = (1.0, played.strength_ref * POLISH_GOAL);
        let stop = run_lm(
            played,
            x0,
            &LmOptions {
                max_iterations: first,
                ..*lm
            },
        )?;
        if let Some(best) = played.best() {
            from = best.params;
        }
        if played.spent() {
            // No play once the budget or the stall rule says stop.
            return Ok(stop);
        }
    }
    (played.reach, played.goal) = (STRENGTH_REACH, played.strength_ref);
    run_lm(
        played,
        &from,
        &LmOptions {
            max_iterations: left,
            ..*lm
        },
    )
}

/// One Nelder–Mead run from `x0` (simplex step `step`) until convergence or
/// the budget ([`nelder_mead`]).
fn run(played: &Played<'_>, x0: &[f64], step: f64) -> Result<()> {
    nelder_mead(
        x0,
        step,
        played
            .options
            .max_plays
            .saturating_sub(played.plays.load(Ordering::Relaxed)),
        |x| played.evaluate(x).map(|e| e.cost),
        || played.spent(),
        "played polish",
        None,
    )
}

/// Polishes `synthesis` (made for `target` over `region` within `limits`)
/// on the played measure at start points `starts` (indices into
/// `sampled.points`); see the module documentation.
///
/// # Errors
/// Invalid options (naming `polish.*`); the optimizer failing for a reason
/// other than the budget; a motion that cannot be played.
#[allow(clippy::too_many_arguments)]
pub fn polish(
    target: &Target,
    sampled: &SampledTarget,
    starts: &[usize],
    region: &Grid,
    limits: &ShakerLimits,
    settings: &FieldSettings,
    synthesis: &Synthesis,
    options: &PolishOptions,
) -> Result<Polished> {
    let clock = Instant::now();
    options.validate()?;
    let layout = Layout::new(limits);
    let coefficients = Coefficients::from_signals(&synthesis.checked.motion, limits.harmonics);
    let x0 = layout.to_vec(&coefficients);
    let progress = SynthesisProgress::new(ProgressMode::Quiet, options.max_plays);
    let coarse = Grid {
        n: options.coarse,
        ..*region
    };
    let objective = Objective::unbounded(
        &target.field,
        coarse,
        limits,
        settings,
        options.shape_budget,
        &progress,
    )
    .with_robust(options.robust);
    let mut played = Played {
        promise: Promise::of(target),
        sampled,
        region,
        starts,
        objective,
        options,
        strength_ref: 1.0,
        lost_ref: 0,
        grid_budget: f64::INFINITY,
        steer_budget: options.shape_budget,
        goal: 1.0,
        reach: 1.0,
        plays: AtomicUsize::new(0),
        best: Mutex::new(None),
        start: None,
        kept: Mutex::new(None),
        gained_at: AtomicUsize::new(0),
        patience_plays: match (options.lm, options.patience) {
            (Some(_), Some(k)) => k.max(1) * (layout.len() + 2),
            _ => usize::MAX,
        },
        stall: Mutex::new(StallTracker::default()),
        bar: crate::progress::Progress::new(
            "played polish",
            "plays",
            options.max_plays as u64,
            options.progress,
        ),
    };
    let (before, _, lost_before) = played.play(&coefficients)?;
    // Patience ends a polish that has little to gain; one whose start
    // plays worse than PATIENT_BELOW takes all its steps.
    if before.shape_error > PATIENT_BELOW {
        played.patience_plays = usize::MAX;
    }
    played.strength_ref = if before.realised_strength.is_finite() && before.realised_strength > 0.0
    {
        before.realised_strength
    } else {
        1.0
    };
    played.lost_ref = lost_before;
    let start_grid = played.objective.evaluate(&x0).realised.shape_error;
    played.grid_budget = options.grid_budget.max(start_grid.min(SHAPE_CAP));
    let start = played.evaluate(&x0)?;
    played.start = Some(start.clone());
    let mut lm_stop = None;
    if let Some(lm) = &options.lm {
        let over = before.shape_error.is_nan() || before.shape_error > options.shape_budget;
        if !over {
            played.steer_budget = 0.0;
        }
        lm_stop = Some(run_lm_shape_first(&mut played, &x0, over, lm)?);
    } else {
        run(&played, &x0, options.step)?;
    }
    let mut step = options.step / 3.0;
    while let Some(best) = played.best().filter(|_| options.lm.is_none()) {
        let n = played.plays.load(Ordering::Relaxed);
        if played.spent() || step < 1e-4 {
            break;
        }
        run(&played, &best.params, step)?;
        if played.plays.load(Ordering::Relaxed) == n {
            break;
        }
        step /= 2.0;
    }
    let plays = played.plays.load(Ordering::Relaxed);
    // Nelder–Mead ends, short of the budget rules, when its restarts'
    // simplex collapses: converged.
    let stop = played.spent_stop().or(lm_stop).unwrap_or(Stop::Converged);
    played.bar.finish();
    let kept = played
        .kept
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .clone();
    let keep = |checked: &Checked| !checked.poor || synthesis.checked.poor;
    let (synthesis, after, cost_after, improved) = if let Some(best) = kept {
        let c = played.objective.motion(&best.params).0;
        let checked = Checked::of(
            &target.field,
            region,
            limits,
            settings,
            &c,
            &synthesis.seed_notes,
        );
        if keep(&checked) {
            let s = synthesis.with_checked(checked, plays, clock.elapsed().as_secs_f64());
            (s, best.played, best.cost, true)
        } else {
            (synthesis.clone(), before, start.cost, false)
        }
    } else {
        (synthesis.clone(), before, start.cost, false)
    };
    Ok(Polished {
        synthesis,
        before,
        after,
        cost_before: start.cost,
        cost_after,
        improved,
        plays,
        stop,
        seconds: clock.elapsed().as_secs_f64(),
    })
}
