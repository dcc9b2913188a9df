//! Refinement of a sequenced design by re-simulation (argmin's
//! Nelder–Mead on the primitives' parameters): the continuous parameters of a schedule's
//! primitives are tuned so that the *played* schedule realises the target
//! better.
//!
//! **Solver: Nelder–Mead** (argmin's). Update rule first, as argmin states
//! it: each iteration replaces the worst vertex x_w of a simplex of n + 1
//! points by its reflection x_r = c + α(c − x_w) through the centroid c of
//! the others (α = 1), expanded to c + γ(x_r − c) (γ = 2) when x_r beats the
//! best vertex, contracted to c + ρ(x_w − c) (ρ = ½) when it does not beat
//! the second worst, and the whole simplex is shrunk towards the best
//! vertex (σ = ½) when the contraction fails too. Why: the objective is a
//! played simulation whose cycle counts are whole numbers (piecewise
//! constant in the cycle parameters) and whose stick–slip events make it
//! kinked elsewhere, so gradients (analytic or by finite differences, 2n
//! plays per step) are meaningless; the dimension is small (3 per moving
//! segment) and the budget is ≈ 10² plays, far below what a particle swarm
//! needs; Nelder–Mead needs only cost comparisons, one or two plays per
//! iteration, and is the solver [`crate::synth`] already uses.
//!
//! **Parameters**, per moving segment i (x ∈ ℝ^{3n}, all of order one):
//!
//! ```text
//! cycles_i   = max(min_cycles, round(c_i · e^{x_{3i}}))   time weight (whole cycles)
//! rotation_i = r_i + 10° · x_{3i+1}                        turn about the vertical
//! amplitude  = a_i · min(1, e^{x_{3i+2}})                  rotation and translation amplitudes scaled
//! ```
//!
//! (c_i, r_i, a_i the design's). The amplitude may only shrink, so every
//! refined schedule stays within the per-axis peaks of the design it
//! started from. Axis depth and shift are left as designed: a deeper axis or
//! a shifted one raises the peak linear acceleration (and the shift of a
//! centred target only breaks its symmetry).
//!
//! **Objective** (one play of the candidate schedule at a coarse set of
//! points, every [`RefineOptions::coarse_stride`]-th target grid point,
//! held there as the judge holds them, [`super::judge::play_motion`]):
//! with e the realised shape error and ŝ the realised strength against the
//! target,
//!
//! ```text
//! cost = e + max(0, 1 − ŝ / ŝ₀) + (points lost) / (points)
//! ```
//!
//! ŝ₀ the design's own realised strength: shape first, never bought by a
//! weaker field, and a schedule whose parts lose contact at more points is
//! penalised. The best candidate is then judged at the judge's points
//! ([`super::judge::judge_points`]) beside the design; if it is not better
//! there (lower cost) the design is kept and the result says so.

use std::sync::Mutex;
use std::time::Instant;

use crate::work::Stop;
use argmin::core::{CostFunction, Executor, State, TerminationReason, TerminationStatus};
use argmin::solver::neldermead::NelderMead;

use super::judge::{judge_points, play_motion};
use super::judge::{realised_error, strided_points, RealisedError};
use crate::error::{BudgetSpent, Error, Result};
use crate::request::{SampledTarget, Target};
use crate::schedule::Schedule;

/// Settings of [`refine_schedule`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefineOptions {
    /// Every `coarse_stride`-th grid point (each axis) is played inside the
    /// objective.
    pub coarse_stride: usize,
    /// Plays allowed inside the objective.
    pub max_evaluations: usize,
    /// Initial simplex step (parameter units, see the module docs).
    pub step: f64,
}

impl Default for RefineOptions {
    fn default() -> Self {
        RefineOptions {
            coarse_stride: 10,
            max_evaluations: 150,
            step: 0.3,
        }
    }
}

/// A schedule's realised field at held points: error, strength, points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scored {
    /// Realised shape error and strength against the target.
    pub error: RealisedError,
    /// Points played.
    pub played: usize,
    /// The objective's cost (see the module docs).
    pub cost: f64,
}

/// Before and after a refinement.
#[derive(Debug, Clone)]
pub struct Refined {
    /// The design as given, judged ([`super::judge`]'s points).
    pub before: Scored,
    /// The refined schedule, judged.
    pub after: Scored,
    /// The refined schedule (the design itself when refining did not help).
    pub schedule: Schedule,
    /// True when the refined schedule was kept.
    pub improved: bool,
    /// Plays inside the objective (coarse points).
    pub evaluations: usize,
    /// Why the search ended: Nelder–Mead's simplex converged, its play
    /// budget ([`RefineOptions::max_evaluations`]) was spent, or a schedule
    /// with nothing to refine was not searched.
    pub stop: Stop,
    /// Wall time (s); not part of any data file.
    pub seconds: f64,
}

/// The schedule for parameter vector `x` (see the module docs).
pub(crate) fn apply(schedule: &Schedule, x: &[f64]) -> Schedule {
    let min = schedule.min_cycles.max(1);
    let mut k = 0;
    let segments = schedule
        .segments
        .iter()
        .map(|seg| {
            let mut seg = seg.clone();
            if let Some(p) = &mut seg.primitive {
                let (lc, rot, la) = (
                    x.get(k).copied().unwrap_or(0.0),
                    x.get(k + 1).copied().unwrap_or(0.0),
                    x.get(k + 2).copied().unwrap_or(0.0),
                );
                k += 3;
                let c = (f64::from(seg.cycles) * lc.exp()).round();
                seg.cycles = if c.is_finite() {
                    c.clamp(f64::from(min), 100_000.0) as u32
                } else {
                    min
                };
                p.rotation_deg += 10.0 * rot;
                let scale = la.exp().min(1.0);
                let a = p
                    .amplitude
                    .unwrap_or_else(|| crate::basis::Primitive::default_amplitude(p.kind));
                p.amplitude = Some(a * scale);
                let t = p
                    .translation
                    .unwrap_or_else(|| crate::basis::Primitive::default_translation(p.kind));
                if t != 0.0 {
                    p.translation = Some(t * scale);
                }
            }
            seg
        })
        .collect();
    schedule.with_segments(segments)
}

/// Number of parameters of `schedule` (3 per moving segment).
pub(crate) fn dimension(schedule: &Schedule) -> usize {
    3 * schedule
        .segments
        .iter()
        .filter(|s| s.primitive.is_some())
        .count()
}

/// Plays `schedule` with a part held at each of `starts` (as the judge
/// plays) and judges it; `reference` is ŝ₀ (None: this play's own
/// strength).
fn judge(
    schedule: &Schedule,
    target: &Target,
    sampled: &SampledTarget,
    starts: &[usize],
    reference: Option<(f64, usize)>,
) -> Result<Scored> {
    let sm = crate::play::ScheduleMotion::from_schedule(schedule)?;
    let plays = play_motion(&sm, &sampled.points, starts, &schedule.settings);
    let error = realised_error(target, &sampled.weights, &plays, None);
    let (s0, valid0) = reference.unwrap_or((error.realised_strength, error.valid));
    let shape = if error.shape_error.is_finite() {
        error.shape_error
    } else {
        10.0
    };
    let lost = valid0.saturating_sub(error.valid) as f64 / starts.len().max(1) as f64;
    let weaker = if s0 > 0.0 {
        (1.0 - error.realised_strength / s0).max(0.0)
    } else {
        0.0
    };
    Ok(Scored {
        error,
        played: starts.len(),
        cost: shape + weaker.min(10.0) + lost,
    })
}

/// Why a run stopped early.
const BUDGET_SPENT: BudgetSpent = BudgetSpent("refinement");

struct Problem<'a> {
    schedule: &'a Schedule,
    target: &'a Target,
    sampled: &'a SampledTarget,
    starts: Vec<usize>,
    options: RefineOptions,
    reference: (f64, usize),
    tally: &'a Tally,
}

/// Plays so far and the best (cost, parameters).
type Tally = Mutex<(usize, Option<(f64, Vec<f64>)>)>;

impl CostFunction for Problem<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, x: &Vec<f64>) -> std::result::Result<f64, argmin::core::Error> {
        let n = self.tally.lock().map_or(usize::MAX, |t| t.0);
        // argmin's Nelder–Mead evaluates its first simplex unconditionally
        // (n + 1 plays, counted against the budget).
        if n >= self.options.max_evaluations.max(x.len() + 1) {
            return Err(BUDGET_SPENT.into());
        }
        let s = apply(self.schedule, x);
        let j = judge(
            &s,
            self.target,
            self.sampled,
            &self.starts,
            Some(self.reference),
        )
        .map_err(|e| argmin::core::Error::msg(e.to_string()))?;
        let mut t = self
            .tally
            .lock()
            .map_err(|_| argmin::core::Error::msg("poisoned"))?;
        t.0 += 1;
        if t.1.as_ref().is_none_or(|(c, _)| j.cost < *c) {
            t.1 = Some((j.cost, x.clone()));
        }
        Ok(j.cost)
    }
}

/// Refines `schedule` for `target` (see the module documentation).
///
/// # Errors
/// A target without samples, a schedule that cannot be played, or the
/// optimizer failing for a reason other than the budget.
pub fn refine_schedule(
    schedule: &Schedule,
    target: &Target,
    options: &RefineOptions,
) -> Result<Refined> {
    let start = Instant::now();
    let sampled = target.sample()?;
    let coarse = strided_points(target, &sampled, options.coarse_stride);
    let fine = judge_points(target, &sampled);
    if coarse.is_empty() || fine.is_empty() {
        return Err(Error::invalid(
            "target.grid",
            "no unmasked point at the refinement's stride",
        ));
    }
    let base = judge(schedule, target, &sampled, &coarse, None)?;
    let n = dimension(schedule);
    let tally: Tally = Mutex::new((0, Some((base.cost, vec![0.0; n]))));
    let problem = Problem {
        schedule,
        target,
        sampled: &sampled,
        starts: coarse,
        options: *options,
        reference: (base.error.realised_strength, base.error.valid),
        tally: &tally,
    };
    let simplex: Vec<Vec<f64>> = (0..=n)
        .map(|i| {
            let mut v = vec![0.0; n];
            if i > 0 {
                v[i - 1] = options.step;
            }
            v
        })
        .collect();
    let stop = if n > 0 {
        let solver = NelderMead::new(simplex)
            .with_sd_tolerance(1e-6)
            .map_err(|e| Error::NotConverged(format!("Nelder–Mead setup: {e}")))?;
        match Executor::new(problem, solver)
            .configure(|s| s.max_iters(1_000_000))
            .run()
        {
            Ok(result) => stop_of(result.state().get_termination_status()),
            Err(e) if BudgetSpent::is(&e) => Stop::Spent,
            Err(e) => return Err(Error::NotConverged(format!("Nelder–Mead: {e}"))),
        }
    } else {
        Stop::NotRun
    };
    let (evaluations, best) = tally
        .into_inner()
        .map_err(|_| Error::NotConverged("refinement: poisoned tally".into()))?;
    let x = best.map(|b| b.1).unwrap_or_else(|| vec![0.0; n]);
    let before = judge(schedule, target, &sampled, &fine, None)?;
    let candidate = apply(schedule, &x);
    let reference = Some((before.error.realised_strength, before.error.valid));
    let after = judge(&candidate, target, &sampled, &fine, reference)?;
    let improved = after.cost < before.cost;
    Ok(Refined {
        before,
        after: if improved { after } else { before },
        schedule: if improved {
            candidate
        } else {
            schedule.clone()
        },
        improved,
        evaluations,
        stop,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The loop's stop in the shared vocabulary ([`Stop`]) for argmin's
/// termination status.
fn stop_of(status: &TerminationStatus) -> Stop {
    match status {
        TerminationStatus::Terminated(
            TerminationReason::SolverConverged | TerminationReason::TargetCostReached,
        ) => Stop::Converged,
        TerminationStatus::Terminated(TerminationReason::MaxItersReached) => Stop::Iterations,
        TerminationStatus::Terminated(TerminationReason::Timeout) => Stop::Spent,
        TerminationStatus::Terminated(_) | TerminationStatus::NotTerminated => Stop::Failed,
    }
}

#[cfg(test)]
#[path = "../../tests/unit/refine.rs"]
mod refine_tests;
