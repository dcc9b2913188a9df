//! Refinement by least squares: Levenberg–Marquardt ([`super::levenberg`])
//! on the coarse objective's residuals ([`super::objective`]: the field
//! minus s_g times the target over the coarse grid, the peak excess and the
//! contact margin), its Jacobian's columns one parallel batch of coarse
//! re-simulations ([`Objective::evaluate_batch`], recorded in order: the
//! same bytes on one thread or two).
//!
//! It starts from the best start the synthesis has (the phase-calibrated
//! seed, or the transport start), where the averaged-friction analysis has
//! already put the motion near the target's shape, so a few steps suffice.
//! What is kept is the objective's best evaluation by its *cost* (the
//! shape budget first, then strength), not the residuals' least point: the
//! residuals steer, the cost judges. The run ends when a step improves the
//! residuals by less than [`super::levenberg::LmOptions::min_improvement`]
//! (the measure stopped improving), after its iterations, or once the
//! objective is spent.

use super::levenberg::{levenberg_marquardt, LmOptions};
use super::objective::{Evaluation, Objective};
use crate::error::{Error, Result};

/// Runs Levenberg–Marquardt on `objective` from `x0`; returns the
/// objective's best evaluation (by cost) so far.
///
/// # Errors
/// Never for a deterministic objective; a residual vector of changing
/// length (a bug) is reported.
pub(crate) fn least_squares(
    objective: &Objective<'_>,
    x0: &[f64],
    options: &LmOptions,
) -> Result<Evaluation> {
    let batch = |xs: &[Vec<f64>]| -> Result<Vec<Vec<f64>>> {
        Ok(objective
            .evaluate_batch(xs)
            .into_iter()
            .map(|e| e.residuals)
            .collect())
    };
    levenberg_marquardt(x0, &batch, || objective.spent(), options)?;
    objective
        .best()
        .ok_or_else(|| Error::Internal("least squares: nothing evaluated".into()))
}
