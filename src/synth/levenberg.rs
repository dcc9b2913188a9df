//! Levenberg–Marquardt on a residual vector, its Jacobian by forward
//! differences evaluated as one parallel batch.
//!
//! **Update rule.** With r(x) ∈ ℝᵐ the residuals, J = ∂r/∂x (m × n) and
//! D = diag(JᵀJ) (each entry floored at 10⁻² of the mean, so a column the
//! residuals barely feel cannot make the system singular), a step is
//!
//! ```text
//! (JᵀJ + λ D) δ = −Jᵀ r,      x ← x + δ  if ½‖r(x + δ)‖² < ½‖r(x)‖²
//! ```
//!
//! (Marquardt 1963: λ → 0 is Gauss–Newton, which solves a linear least
//! squares problem in one step; large λ a short gradient step scaled per
//! coordinate). Each iteration tries the steps of λ and 10λ as one batch;
//! the better of them, if it lowers the cost, is taken and λ becomes a third
//! of the λ that gave it; if neither does, λ grows a hundredfold and the same
//! Jacobian is tried again (at most [`LmOptions::max_rejections`] times).
//! With λ = 0 the first try is the Gauss–Newton step itself (then 10λ is
//! replaced by 10⁻³). A step longer than [`LmOptions::max_step`] (Euclidean
//! norm) is shortened to it, its direction kept: with fewer informative
//! residuals than parameters (a played polish whose shape is within
//! budget, strength the one residual left) the damped system is nearly
//! singular along the parameters the residuals barely feel, and the cap
//! keeps the step where the linearisation holds.
//!
//! **Jacobian.** Column j is (r(x + h eⱼ) − r(x))/h, h = [`LmOptions::step`]:
//! the n columns are one batch of evaluations. `parallel` evaluates a
//! batch with rayon and collects it in order, so the result is the same
//! bytes on one thread or many as long as each evaluation is deterministic.
//!
//! **Stop.** After [`LmOptions::max_iterations`] accepted steps; when an
//! accepted step lowers the cost by less than [`LmOptions::min_improvement`]
//! of it (the measure stopped improving) or the cost is at most
//! [`LmOptions::abs_cost`]; after the rejections; or once the caller's
//! `spent()` says its budget is gone (checked before every batch).

use nalgebra::{DMatrix, DVector};
#[cfg(test)]
use rayon::prelude::*;

use crate::error::{Error, Result};

/// Settings of one Levenberg–Marquardt run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LmOptions {
    /// Accepted steps at most.
    pub max_iterations: usize,
    /// Initial damping λ (0: the first try is the Gauss–Newton step).
    pub lambda0: f64,
    /// Forward-difference step h (in the parameters' units).
    pub step: f64,
    /// Stop when an accepted step lowers the cost by less than this fraction
    /// of it.
    pub min_improvement: f64,
    /// Stop when the cost ½‖r‖² is at most this.
    pub abs_cost: f64,
    /// Rejected tries in a row that end the run.
    pub max_rejections: usize,
    /// Longest step (Euclidean norm in the parameters' units).
    pub max_step: f64,
}

impl Default for LmOptions {
    fn default() -> Self {
        LmOptions {
            max_iterations: 4,
            lambda0: 1e-2,
            step: 0.01,
            min_improvement: 0.01,
            abs_cost: 0.0,
            max_rejections: 2,
            max_step: f64::INFINITY,
        }
    }
}

impl LmOptions {
    /// Residual evaluations of a run over `n` parameters that takes all
    /// its [`LmOptions::max_iterations`] steps, each accepted at its first
    /// batch: the start, then per step the n Jacobian columns and the two
    /// tries (the work estimate's count, [`crate::work`]; a rejected try
    /// adds two, a run that stops early takes fewer).
    pub(crate) fn evaluations(&self, n: usize) -> usize {
        1 + self.max_iterations * (n + 2)
    }
}

/// Why a run ended: [`Stop::Iterations`] after `max_iterations`
/// accepted steps; [`Stop::Converged`] when the last accepted step
/// improved the cost by less than `min_improvement` of it, or the cost
/// reached `abs_cost`; [`Stop::NoGain`] after `max_rejections` tries in a
/// row that did not lower the cost; [`Stop::Spent`] when the caller's
/// budget was spent.
pub use crate::work::Stop;

/// The result of one run.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LmReport {
    /// The best point found.
    pub x: Vec<f64>,
    /// Its cost ½‖r‖².
    pub cost: f64,
    /// Accepted steps.
    pub iterations: usize,
    /// Residual evaluations (start, Jacobian columns and tries).
    pub evaluations: usize,
    /// Why it ended.
    pub stop: Stop,
}

/// ½‖r‖².
pub(crate) fn half_squared(r: &[f64]) -> f64 {
    0.5 * r.iter().map(|v| v * v).sum::<f64>()
}

/// A batch evaluator from a residual function: the points evaluated in
/// parallel (rayon), the residual vectors returned in the points' order.
#[cfg(test)]
pub(crate) fn parallel<F>(f: F) -> impl Fn(&[Vec<f64>]) -> Result<Vec<Vec<f64>>>
where
    F: Fn(&[f64]) -> Vec<f64> + Sync,
{
    move |xs: &[Vec<f64>]| Ok(xs.par_iter().map(|x| f(x)).collect())
}

/// The forward-difference Jacobian of the residuals at `x` (residuals
/// `r0` there) with step `h`, its n columns evaluated as one batch by
/// `batch`.
///
/// # Errors
/// `batch` fails or returns residual vectors of another length.
pub(crate) fn jacobian<B>(x: &[f64], r0: &[f64], h: f64, batch: &B) -> Result<DMatrix<f64>>
where
    B: Fn(&[Vec<f64>]) -> Result<Vec<Vec<f64>>>,
{
    let points: Vec<Vec<f64>> = (0..x.len())
        .map(|j| {
            let mut p = x.to_vec();
            p[j] += h;
            p
        })
        .collect();
    let cols = batch(&points)?;
    let mut jac = DMatrix::zeros(r0.len(), x.len());
    for (j, r) in cols.iter().enumerate() {
        same_length(r, r0)?;
        for (i, (a, b)) in r.iter().zip(r0).enumerate() {
            jac[(i, j)] = (a - b) / h;
        }
    }
    Ok(jac)
}

fn same_length(r: &[f64], r0: &[f64]) -> Result<()> {
    if r.len() == r0.len() {
        Ok(())
    } else {
        Err(Error::Internal(format!(
            "Levenberg–Marquardt: residual length changed from {} to {}",
            r0.len(),
            r.len()
        )))
    }
}

/// The damped step δ solving (JᵀJ + λ D) δ = −Jᵀ r (module documentation);
/// a least-squares (SVD) solution when the system is singular.
pub(crate) fn damped_step(jtj: &DMatrix<f64>, jtr: &DVector<f64>, lambda: f64) -> Vec<f64> {
    let n = jtj.nrows();
    let largest = (0..n).map(|i| jtj[(i, i)]).fold(0.0, f64::max);
    let mean = (0..n).map(|i| jtj[(i, i)]).sum::<f64>() / n.max(1) as f64;
    let floor = (1e-2 * mean).max(f64::MIN_POSITIVE);
    let mut a = jtj.clone();
    for i in 0..n {
        a[(i, i)] += lambda * jtj[(i, i)].max(floor);
    }
    let rhs = -jtr;
    let delta = match a.clone().cholesky() {
        Some(c) => c.solve(&rhs),
        None => crate::linalg::svd(a)
            .and_then(|svd| svd.solve(&rhs, 1e-12 * largest.max(f64::MIN_POSITIVE)).ok())
            .unwrap_or_else(|| DVector::zeros(n)),
    };
    delta.iter().copied().collect()
}

/// `d` shortened to the norm `max` if longer (direction kept).
fn capped(d: Vec<f64>, max: f64) -> Vec<f64> {
    let norm = d.iter().map(|v| v * v).sum::<f64>().sqrt();
    if norm > max {
        d.iter().map(|v| v * max / norm).collect()
    } else {
        d
    }
}

/// Minimises ½‖r(x)‖² from `x0` (module documentation). `batch` evaluates
/// the residual vectors of several points in their order (e.g.
/// [`parallel`]); `spent` ends the run before any batch once the caller's
/// budget is gone. Returns the best point evaluated.
///
/// # Errors
/// `batch` fails, or returns residual vectors of changing length.
///
/// # Examples
pub(crate) fn levenberg_marquardt<B, S>(
    x0: &[f64],
    batch: &B,
    spent: S,
    options: &LmOptions,
) -> Result<LmReport>
where
    B: Fn(&[Vec<f64>]) -> Result<Vec<Vec<f64>>>,
    S: Fn() -> bool,
{
    let mut x = x0.to_vec();
    let mut r = batch(std::slice::from_ref(&x))?
        .pop()
        .ok_or_else(|| Error::Internal("Levenberg–Marquardt: no residuals".into()))?;
    let mut cost = half_squared(&r);
    let mut evaluations = 1;
    let mut iterations = 0;
    let mut lambda = options.lambda0.max(0.0);
    let report = |x: Vec<f64>, cost, iterations, evaluations, stop| LmReport {
        x,
        cost,
        iterations,
        evaluations,
        stop,
    };
    loop {
        if iterations >= options.max_iterations {
            return Ok(report(x, cost, iterations, evaluations, Stop::Iterations));
        }
        if cost <= options.abs_cost {
            return Ok(report(x, cost, iterations, evaluations, Stop::Converged));
        }
        if spent() {
            return Ok(report(x, cost, iterations, evaluations, Stop::Spent));
        }
        let jac = jacobian(&x, &r, options.step, batch)?;
        evaluations += x.len();
        let jtj = jac.tr_mul(&jac);
        let jtr = jac.tr_mul(&DVector::from_column_slice(&r));
        let mut rejections = 0;
        let accepted = loop {
            if spent() {
                return Ok(report(x, cost, iterations, evaluations, Stop::Spent));
            }
            let lambdas = [lambda, if lambda > 0.0 { 10.0 * lambda } else { 1e-3 }];
            let tries: Vec<Vec<f64>> = lambdas
                .iter()
                .map(|l| {
                    let d = capped(damped_step(&jtj, &jtr, *l), options.max_step);
                    x.iter().zip(&d).map(|(a, b)| a + b).collect()
                })
                .collect();
            let rs = batch(&tries)?;
            evaluations += tries.len();
            let best = rs
                .iter()
                .enumerate()
                .map(|(i, ri)| (i, half_squared(ri)))
                .filter(|(_, c)| c.is_finite())
                .fold(None, |b: Option<(usize, f64)>, (i, c)| match b {
                    Some((_, cb)) if cb <= c => b,
                    _ => Some((i, c)),
                });
            match best {
                Some((i, c)) if c < cost => {
                    same_length(&rs[i], &r)?;
                    lambda = lambdas[i] / 3.0;
                    break Some((tries[i].clone(), rs[i].clone(), c));
                }
                _ => {
                    rejections += 1;
                    lambda = if lambdas[1] > 0.0 {
                        100.0 * lambdas[1]
                    } else {
                        1e-2
                    };
                    if rejections >= options.max_rejections {
                        break None;
                    }
                }
            }
        };
        let Some((xn, rn, cn)) = accepted else {
            return Ok(report(x, cost, iterations, evaluations, Stop::NoGain));
        };
        let gain = cost - cn;
        x = xn;
        r = rn;
        cost = cn;
        iterations += 1;
        if gain < options.min_improvement * (cost + gain) {
            return Ok(report(x, cost, iterations, evaluations, Stop::Converged));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rosenbrock(p: &[f64]) -> Vec<f64> {
        vec![10.0 * (p[1] - p[0] * p[0]), 1.0 - p[0]]
    }

    #[test]
    fn rosenbrock_reaches_its_known_minimum() {
        let options = LmOptions {
            max_iterations: 200,
            step: 1e-7,
            abs_cost: 1e-20,
            min_improvement: 0.0,
            max_rejections: 20,
            ..LmOptions::default()
        };
        let fit = levenberg_marquardt(&[-1.2, 1.0], &parallel(rosenbrock), || false, &options)
            .expect("runs");
        assert!((fit.x[0] - 1.0).abs() < 1e-6, "{:?}", fit);
        assert!((fit.x[1] - 1.0).abs() < 1e-6, "{:?}", fit);
        assert!(fit.cost < 1e-12, "{:?}", fit);
        // Far fewer evaluations than a derivative-free search needs (each
        // iteration: 2 Jacobian columns and 2 tries).
        assert!(fit.evaluations < 400, "{}", fit.evaluations);
    }

    /// A linear least-squares problem A x ≈ b (3 unknowns, 5 equations):
    /// Gauss–Newton (λ = 0) must land on the normal equations' solution in
    /// one step, with forward differences exact up to round-off.
    #[test]
    fn linear_least_squares_converges_in_one_step() {
        let a = [
            [1.0, 2.0, 0.5],
            [0.0, 1.0, -1.0],
            [3.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [-2.0, 0.5, 0.0],
        ];
        let b = [1.0, -2.0, 0.5, 3.0, 1.5];
        let residual = |x: &[f64]| -> Vec<f64> {
            a.iter()
                .zip(b)
                .map(|(row, bi)| row.iter().zip(x).map(|(p, q)| p * q).sum::<f64>() - bi)
                .collect()
        };
        // Independent: the normal equations solved by nalgebra's LU.
        let am = DMatrix::from_fn(5, 3, |i, j| a[i][j]);
        let bm = DVector::from_column_slice(&b);
        let exact = (am.transpose() * &am)
            .lu()
            .solve(&(am.transpose() * bm))
            .expect("full rank");
        let options = LmOptions {
            max_iterations: 1,
            lambda0: 0.0,
            step: 1e-3,
            ..LmOptions::default()
        };
        let fit = levenberg_marquardt(&[5.0, -3.0, 2.0], &parallel(residual), || false, &options)
            .expect("runs");
        assert_eq!(fit.iterations, 1);
        for (got, want) in fit.x.iter().zip(exact.iter()) {
            assert!((got - want).abs() < 1e-9, "{got} vs {want}");
        }
    }

    #[test]
    fn jacobian_is_the_same_bytes_on_one_and_two_threads() {
        // A residual whose value depends on every bit of its input.
        let f = |p: &[f64]| -> Vec<f64> {
            (0..7)
                .map(|i| {
                    let t = i as f64;
                    (p[0] * t).sin() + p[1].exp() * t - (p[2] * p[3] + t).cos()
                })
                .collect()
        };
        let x = [0.3, -0.7, 1.1, 0.2];
        let r0 = f(&x);
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool")
                .install(|| jacobian(&x, &r0, 1e-4, &parallel(f)).expect("jacobian"))
        };
        let (one, two) = (on(1), on(2));
        let bits = |m: &DMatrix<f64>| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&one), bits(&two));
        // And it is the derivative: column 1 is e^{p1} t, to O(h).
        for i in 0..7 {
            let want = (-0.7f64).exp() * i as f64;
            assert!((one[(i, 1)] - want).abs() < 1e-3 * (1.0 + want), "{i}");
        }
    }

    #[test]
    fn spent_budget_returns_the_start() {
        let fit = levenberg_marquardt(
            &[-1.2, 1.0],
            &parallel(rosenbrock),
            || true,
            &LmOptions::default(),
        )
        .expect("runs");
        assert_eq!(fit.x, vec![-1.2, 1.0]);
        assert_eq!(fit.stop, Stop::Spent);
        assert_eq!(fit.evaluations, 1);
    }

    /// A worked example of `synth::levenberg::LmOptions::evaluations`.
    #[test]
    fn example_lmoptions_evaluations() {
        use crate::synth::levenberg::LmOptions;
        let lm = LmOptions {
            max_iterations: 4,
            ..LmOptions::default()
        };
        assert_eq!(lm.evaluations(10), 1 + 4 * 12);
    }
}
