//! Multi-start Nelder–Mead refinement (why Nelder–Mead: see the
//! [module documentation](super)).
//!
//! Start 0 is the (phase-calibrated) seed; then come the caller's explicit
//! starts (the uncalibrated seed); the remaining starts rotate every (c, s) pair of the seed's
//! parameter vector by an angle uniform in ±0.5 rad (a phase shift of that
//! harmonic) and scale it by a factor uniform in [0.85, 1], drawn from a
//! SplitMix64 generator seeded by the caller. Each start runs Nelder–Mead
//! (initial simplex: the start plus `step` along each coordinate) for an
//! equal share of 60 % of the evaluation budget; the best point found then
//! gets the rest, restarting with a simplex a third the size and halving it
//! at each restart (Nelder–Mead stops when its simplex's costs agree to
//! 1e-7). Every run also ends once the objective is spent: its evaluation
//! budget, its deadline, or its stall rule ([`super::stall`]: the best cost
//! has stopped improving). A run starts only if its initial simplex fits in the budget; a
//! time budget can overrun by one simplex (n + 1 evaluations). Everything is
//! sequential and the field engine is deterministic, so the same seed gives
//! the same bytes; a time budget (if given) cuts the run wherever the clock
//! says and is then the only source of variation.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use argmin::core::observers::ObserverMode;
use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;

use super::objective::{Evaluation, Objective};
use super::progress::{Observer, SynthesisProgress};
use crate::error::{BudgetSpent, Error, Result};

/// Settings of the refinement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultistartOptions {
    /// Number of starts (≥ 1; the first is the seed).
    pub starts: usize,
    /// RNG seed of the perturbed starts.
    pub seed: u64,
    /// Initial simplex step in normalised parameters (fraction of the axis
    /// limit).
    pub step: f64,
}

impl Default for MultistartOptions {
    fn default() -> Self {
        MultistartOptions {
            starts: 3,
            seed: 1,
            step: 0.1,
        }
    }
}

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny, portable, seeded RNG.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [a, b).
    fn uniform(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Why a run stopped early.
const BUDGET_SPENT: BudgetSpent = BudgetSpent("synthesis");

/// The argmin problem: `cost`, refusing evaluations once `spent()` says
/// the budget is gone — but never during the simplex's first n + 1
/// evaluations, which argmin's Nelder–Mead cannot interrupt
/// ([`nelder_mead`] starts only when they fit in the budget).
struct Budgeted<F, S> {
    cost: F,
    spent: S,
    init_left: AtomicUsize,
}

impl<F, S> CostFunction for Budgeted<F, S>
where
    F: Fn(&[f64]) -> Result<f64>,
    S: Fn() -> bool,
{
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, param: &Vec<f64>) -> std::result::Result<f64, argmin::core::Error> {
        let init = self
            .init_left
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |n| n.checked_sub(1))
            .is_ok();
        if !init && (self.spent)() {
            return Err(BUDGET_SPENT.into());
        }
        (self.cost)(param).map_err(|e| argmin::core::Error::msg(e.to_string()))
    }
}

/// One argmin Nelder–Mead run of `cost` from `x0` (initial simplex: `x0`
/// plus `step` along each coordinate) until its simplex's costs agree to
/// 1e-7 or `spent()`; it starts only if `room` evaluations hold the
/// simplex (n + 1). `label` names the run in errors; `progress`, if given,
/// observes every iteration.
///
/// # Errors
/// The optimizer (or `cost`) fails for a reason other than the budget.
pub(crate) fn nelder_mead<F, S>(
    x0: &[f64],
    step: f64,
    room: usize,
    cost: F,
    spent: S,
    label: &str,
    progress: Option<&Arc<SynthesisProgress>>,
) -> Result<()>
where
    F: Fn(&[f64]) -> Result<f64>,
    S: Fn() -> bool,
{
    let simplex: Vec<Vec<f64>> = (0..=x0.len())
        .map(|i| {
            let mut v = x0.to_vec();
            if i > 0 {
                v[i - 1] += step;
            }
            v
        })
        .collect();
    if spent() || simplex.len() > room {
        return Ok(());
    }
    let problem = Budgeted {
        cost,
        spent,
        init_left: AtomicUsize::new(simplex.len()),
    };
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(1e-7)
        .map_err(|e| Error::NotConverged(format!("{label} setup: {e}")))?;
    let mut executor = Executor::new(problem, solver).configure(|s| s.max_iters(1_000_000));
    if let Some(p) = progress {
        executor = executor.add_observer(Observer(p.clone()), ObserverMode::Always);
    }
    match executor.run() {
        Ok(_) => Ok(()),
        Err(e) if BudgetSpent::is(&e) => Ok(()),
        Err(e) => Err(Error::NotConverged(format!("{label}: {e}"))),
    }
}

/// One Nelder–Mead run from `x0` until convergence or `cap` evaluations.
fn run(
    objective: &Objective<'_>,
    x0: &[f64],
    step: f64,
    cap: usize,
    progress: &Arc<SynthesisProgress>,
) -> Result<()> {
    nelder_mead(
        x0,
        step,
        cap.saturating_sub(objective.evaluations()),
        |x| Ok(objective.evaluate(x).cost),
        || objective.spent() || objective.evaluations() >= cap,
        "Nelder–Mead",
        Some(progress),
    )
}

/// Searches from the seed vector `x0` and the explicit starts `extra`
/// (runs 1..=extra.len(); the random perturbations of `x0` fill the
/// remaining runs up to `options.starts`); returns the best evaluation.
///
/// # Errors
/// The optimizer fails for a reason other than the budget.
pub(crate) fn search(
    objective: &Objective<'_>,
    x0: &[f64],
    extra: &[Vec<f64>],
    budget: usize,
    options: &MultistartOptions,
    progress: &Arc<SynthesisProgress>,
) -> Result<Evaluation> {
    let mut rng = SplitMix64(options.seed);
    let starts = options.starts.max(1 + extra.len());
    let explore = (budget * 3 / 5) / starts;
    for i in 0..starts {
        let x: Vec<f64> = if i == 0 {
            x0.to_vec()
        } else if i <= extra.len() {
            extra[i - 1].clone()
        } else {
            x0.chunks(2)
                .flat_map(|cs| {
                    let (s, c) = rng.uniform(-0.5, 0.5).sin_cos();
                    let k = rng.uniform(0.85, 1.0);
                    let (a, b) = (cs[0], cs.get(1).copied().unwrap_or(0.0));
                    [k * (c * a - s * b), k * (s * a + c * b)]
                })
                .collect()
        };
        let cap = (objective.evaluations() + explore).min(budget);
        run(objective, &x, options.step, cap, progress)?;
    }
    // Polish the best point with shrinking simplices until the budget is
    // spent or the simplex is below 1e-4 of the limits.
    let mut step = options.step / 3.0;
    while let Some(best) = objective.best() {
        let before = objective.evaluations();
        if objective.spent() || before >= budget || step < 1e-4 {
            break;
        }
        run(objective, &best.params, step, budget, progress)?;
        if objective.evaluations() == before {
            break;
        }
        step /= 2.0;
    }
    objective
        .best()
        .ok_or_else(|| Error::NotConverged("synthesis: no evaluation within the budget".into()))
}
