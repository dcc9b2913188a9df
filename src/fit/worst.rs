//! The stacked worst-case fit: one set of time fractions against several
//! bases of the same columns (the basis built at each friction sample of a
//! range), minimising the worst shape error over them.
//!
//! # Problem
//!
//! Bases `A₁ … A_K` (`2n×m` each, column j the same primitive simulated at
//! sample k), one target `t` and row weights `D`. With `w ≥ 0` the time
//! fractions at strength 1 (`f = w/1ᵀw`, strength `s = 1/1ᵀw`), the shape
//! error at sample k is `‖D(A_k w − t)‖/‖Dt‖ = ‖D(A_k f − s t)‖/‖D s t‖`,
//! so the worst case is the second-order cone program
//!
//! ```text
//! stage 1:  τ* = min τ   s.t.  ‖Â_k w − t̂‖ ≤ τ  (k = 1 … K),  w ≥ 0,
//!                              [1ᵀw ≤ 1/s_min  with a strength floor]
//! ```
//!
//! (`Â_k = DA_k/‖Dt‖`, `t̂ = Dt/‖Dt‖`, each compressed by its own thin QR
//! exactly as [`crate::fit::prepare`] does: `‖Â_k w − t̂‖² = ‖R_k w −
//! c_k‖² + r₀ₖ²`, one cone `(τ, c_k − R_k w, r₀ₖ) ∈ 𝒬^{k+2}` per sample).
//! Like the single fit's `shape` mode ([`crate::design`]'s `strongest`),
//! the minimiser is not unique where columns cancel, so a second stage
//! takes the strongest field within `τ* + slack`:
//!
//! ```text
//! stage 2:  max s   s.t.  ‖Â_k f − s t̂‖ ≤ ε s  (all k),  f ≥ 0,  1ᵀf ≤ 1,
//!                         s ≥ s_min,   ε = τ* + slack
//! ```
//!
//! the stacked form of the `budget` mode. Stage 1's point, scaled to
//! `f = w/1ᵀw`, `s = 1/1ᵀw`, is feasible for stage 2, so stage 2 never
//! returns a weaker field; if it fails its checks, stage 1's point stands.
//!
//! # Verification
//!
//! Every answer is checked against bounds computed without the cone
//! solver: each sample's own best error (Lawson–Hanson NNLS on its
//! compressed data) is a lower bound on `τ*` (the worst case is at least
//! the best fit of any one sample), and the worst error of each sample's
//! own NNLS weights over all samples is an upper bound (those weights are
//! feasible; only used without a strength floor, which they may break).
//! The returned fractions' errors are recomputed from the uncompressed data
//! and must be within `ε` (stage 2) or `τ*` (stage 1).
//!
//! ```
//! use nalgebra::{DMatrix, DVector};
//! use platefield::fit::worst::{solve_worst_case, WorstCaseOptions};
//! // Two samples of a one-column basis: the target is between them.
//! let a1 = DMatrix::from_column_slice(2, 1, &[1.0, 0.0]);
//! let a2 = DMatrix::from_column_slice(2, 1, &[1.0, 0.2]);
//! let t = DVector::from_vec(vec![1.0, 0.1]);
//! let fit = solve_worst_case(&[a1, a2], &t, None, &WorstCaseOptions::default()).unwrap();
//! // w = 1 leaves an error of 0.1/‖t‖ at both samples: the worst case is balanced.
//! assert!((fit.best_worst - 0.1 / t.norm()).abs() < 1e-6);
//! ```

use clarabel::solver::SolverStatus;
use clarabel::solver::SupportedConeT::{NonnegativeConeT, SecondOrderConeT};
use nalgebra::{DMatrix, DVector};

use super::conic::{ConeBuilder, TOL_BUDGET};
use super::nnls::nnls;
use super::prepare::Prepared;
use super::{FitError, FitProblem};

/// Mode name in errors.
const MODE: &str = "worst_case";

/// Options of [`solve_worst_case`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorstCaseOptions {
    /// Strength floor `s_min` (> 0), or none.
    pub min_strength: Option<f64>,
    /// Stage 2 takes the strongest field whose worst error is within
    /// `τ* + slack` (0 keeps stage 1's error; default 0.02, the single
    /// fit's `SHAPE_SLACK`).
    pub slack: f64,
    /// Tolerance of the checks (absolute, on relative errors); default 1e-6.
    pub tolerance: f64,
}

impl Default for WorstCaseOptions {
    fn default() -> Self {
        WorstCaseOptions {
            min_strength: None,
            slack: 0.02,
            tolerance: 1e-6,
        }
    }
}

/// A verified worst-case fit.
#[derive(Debug, Clone, PartialEq)]
pub struct WorstCaseFit {
    /// Time fractions `f ≥ 0`, `1ᵀf ≤ 1` (the plate rests for the rest).
    pub fractions: Vec<f64>,
    /// Strength `s`: the field at every sample is about `s·t`.
    pub strength: f64,
    /// Relative error `‖D(A_k f − s t)‖/‖D s t‖` at each sample,
    /// recomputed from the uncompressed data.
    pub errors: Vec<f64>,
    /// Stage 1's optimum `τ*`: the least worst error any fractions reach
    /// (at the strength floor, if any).
    pub best_worst: f64,
    /// The independent lower bound on `τ*`: the largest of the samples'
    /// own best errors.
    pub lower_bound: f64,
    /// Interior-point iterations of both stages.
    pub iterations: u32,
    /// What was solved, e.g. `"Solved (worst case over 3 samples: best
    /// 0.0312, then strongest within 0.0512)"`.
    pub status: String,
}

impl WorstCaseFit {
    /// The worst of [`WorstCaseFit::errors`].
    pub fn worst(&self) -> f64 {
        self.errors.iter().copied().fold(0.0, f64::max)
    }
}

/// `‖D(A f − s t)‖ / ‖D s t‖`: the shape error of fractions `f` at
/// strength `s` against the (row-weighted) target.
pub fn relative_error(problem: &FitProblem, fractions: &[f64], strength: f64) -> f64 {
    let f = DVector::from_column_slice(fractions);
    let r = problem.a * f - problem.t * strength;
    let (num, den) = match problem.row_weights {
        Some(d) => (r.component_mul(d).norm(), problem.t.component_mul(d).norm()),
        None => (r.norm(), problem.t.norm()),
    };
    num / (strength * den)
}

/// Solves the stacked worst-case fit of the target `t` (row weights `d`)
/// against the bases `a` (see the module docs), and verifies the answer.
///
/// # Errors
/// No sample, bases of different shapes, invalid data or options, a
/// target no non-negative mix points towards at some sample (worst error
/// 1), a solver failure, or a failed check.
pub fn solve_worst_case(
    a: &[DMatrix<f64>],
    t: &DVector<f64>,
    d: Option<&DVector<f64>>,
    options: &WorstCaseOptions,
) -> Result<WorstCaseFit, FitError> {
    let preps = prepare_all(a, t, d, options)?;
    let m = preps[0].ncols();
    let (tau, w, it1) = stage_one(&preps, options.min_strength)?;
    let lower_bound = lower_bound(&preps)?;
    let tol = options.tolerance;
    check("lower bound", lower_bound - tau, tol)?;
    if options.min_strength.is_none() {
        check("upper bound", tau - upper_bound(&preps)?, tol)?;
    }
    let sum: f64 = w.iter().sum();
    if tau >= 1.0 - tol || sum <= 0.0 {
        return Err(FitError::InvalidInput(format!(
            "no non-negative mix points towards the target at every sample (worst error {tau:.4})"
        )));
    }
    let fit = WorstCaseFit {
        fractions: w.iter().map(|v| v / sum).collect(),
        strength: 1.0 / sum,
        errors: Vec::new(),
        best_worst: tau,
        lower_bound,
        iterations: it1,
        status: format!(
            "Solved (worst case over {} samples: best {tau:.4})",
            a.len()
        ),
    };
    let head = format!("Solved (worst case over {} samples: best {tau:.4}", a.len());
    let mut fit = WorstCaseFit {
        status: format!("{head})"),
        ..fit
    };
    fit.errors = errors_of(&preps, &fit.fractions, fit.strength);
    check("stage 1 feasibility", fit.worst() - tau, tol)?;
    if options.slack > 0.0 {
        let eps = (tau + options.slack).min(0.99);
        if let Ok((f, s, it2)) = stage_two(&preps, eps, options.min_strength) {
            let errors = errors_of(&preps, &f, s);
            let worst = errors.iter().copied().fold(0.0, f64::max);
            if s >= fit.strength && worst <= eps + tol && f.iter().sum::<f64>() <= 1.0 + tol {
                fit.status = format!("{head}, then strongest within {eps:.4})");
                fit.fractions = f;
                fit.strength = s;
                fit.errors = errors;
                fit.iterations += it2;
            }
        }
    }
    debug_assert_eq!(fit.fractions.len(), m);
    Ok(fit)
}

/// Validates the options and the bases' shapes, and prepares each sample.
fn prepare_all(
    a: &[DMatrix<f64>],
    t: &DVector<f64>,
    d: Option<&DVector<f64>>,
    options: &WorstCaseOptions,
) -> Result<Vec<Prepared>, FitError> {
    if a.is_empty() {
        return Err(FitError::InvalidInput("no friction sample to fit".into()));
    }
    if let Some(s) = options.min_strength {
        if !(s.is_finite() && s > 0.0) {
            return Err(FitError::InvalidInput(format!(
                "min_strength must be finite and > 0, got {s}"
            )));
        }
    }
    if !(options.slack.is_finite() && options.slack >= 0.0) {
        return Err(FitError::InvalidInput(format!(
            "slack must be finite and >= 0, got {}",
            options.slack
        )));
    }
    if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
        return Err(FitError::InvalidInput(format!(
            "tolerance must be finite and > 0, got {}",
            options.tolerance
        )));
    }
    a.iter()
        .map(|ak| {
            if ak.shape() != a[0].shape() {
                return Err(FitError::DimensionMismatch {
                    what: "basis of a friction sample",
                    expected: a[0].ncols(),
                    got: ak.ncols(),
                });
            }
            Prepared::new(&FitProblem {
                a: ak,
                t,
                row_weights: d,
            })
        })
        .collect()
}

/// The cone `(scale·x_τ, ±(c_k·x_s − R_k w), r₀ₖ·x_s)` of one sample, where
/// `x_τ` and `x_s` are variable `m` (stage 1: `x_s` the constant 1).
fn sample_cone(bld: &mut ConeBuilder, p: &Prepared, first: (usize, f64), stage_two: bool) {
    let m = p.ncols();
    let kk = p.r.nrows();
    bld.row([first], 0.0);
    for i in 0..kk {
        let w = (0..m).map(|j| (j, p.r[(i, j)]));
        if stage_two {
            bld.row(w.chain([(m, -p.c[i])]), 0.0);
        } else {
            bld.row(w, p.c[i]);
        }
    }
    if stage_two {
        bld.row([(m, -p.r0)], 0.0);
    } else {
        bld.row(std::iter::empty(), p.r0);
    }
    bld.cone(SecondOrderConeT(kk + 2));
}

/// Stage 1 (module docs): `(τ*, w*, iterations)`.
fn stage_one(preps: &[Prepared], floor: Option<f64>) -> Result<(f64, Vec<f64>, u32), FitError> {
    let m = preps[0].ncols();
    let mut bld = ConeBuilder::new(m + 1);
    for p in preps {
        sample_cone(&mut bld, p, (m, -1.0), false);
    }
    for j in 0..m {
        bld.row([(j, -1.0)], 0.0);
    }
    if let Some(s) = floor {
        bld.row((0..m).map(|j| (j, 1.0)), 1.0 / s);
    }
    bld.cone(NonnegativeConeT(m + usize::from(floor.is_some())));
    let mut q = vec![0.0; m + 1];
    q[m] = 1.0;
    let out = solved(bld.solve(q, TOL_BUDGET, MODE)?)?;
    let w = out.x[..m].iter().map(|v| v.max(0.0)).collect();
    Ok((out.x[m], w, out.iterations))
}

/// Stage 2 (module docs): `(f, s, iterations)`.
fn stage_two(
    preps: &[Prepared],
    eps: f64,
    floor: Option<f64>,
) -> Result<(Vec<f64>, f64, u32), FitError> {
    let m = preps[0].ncols();
    let mut bld = ConeBuilder::new(m + 1);
    for p in preps {
        sample_cone(&mut bld, p, (m, -eps), true);
    }
    for j in 0..m {
        bld.row([(j, -1.0)], 0.0);
    }
    bld.row([(m, -1.0)], -floor.unwrap_or(0.0));
    bld.row((0..m).map(|j| (j, 1.0)), 1.0);
    bld.cone(NonnegativeConeT(m + 2));
    let mut q = vec![0.0; m + 1];
    q[m] = -1.0;
    let out = solved(bld.solve(q, TOL_BUDGET, MODE)?)?;
    let f = out.x[..m].iter().map(|v| v.max(0.0)).collect();
    Ok((f, out.x[m], out.iterations))
}

fn solved(out: super::conic::ConicOutcome) -> Result<super::conic::ConicOutcome, FitError> {
    match out.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(out),
        s => Err(FitError::SolverStatus {
            mode: MODE,
            status: format!("{s:?}"),
        }),
    }
}

/// Each sample's error of fractions `f` at strength `s`, from `Â_k`.
fn errors_of(preps: &[Prepared], f: &[f64], s: f64) -> Vec<f64> {
    let f = DVector::from_column_slice(f);
    preps
        .iter()
        .map(|p| (&p.ad * &f - &p.td * s).norm() / s)
        .collect()
}

/// Each sample's own NNLS weights (at strength 1) and best error.
fn own_fits(preps: &[Prepared]) -> Result<Vec<(DVector<f64>, f64)>, FitError> {
    preps
        .iter()
        .map(|p| {
            let w = nnls(&p.r, &p.c)?;
            let e = ((&p.r * &w - &p.c).norm_squared() + p.r0 * p.r0).sqrt();
            Ok((w, e))
        })
        .collect()
}

/// The largest of the samples' own best errors: `τ*` is at least this.
fn lower_bound(preps: &[Prepared]) -> Result<f64, FitError> {
    Ok(own_fits(preps)?.iter().map(|(_, e)| *e).fold(0.0, f64::max))
}

/// The least, over the samples' own NNLS weights, of their worst error
/// over all samples: `τ*` (without a floor) is at most this.
fn upper_bound(preps: &[Prepared]) -> Result<f64, FitError> {
    Ok(own_fits(preps)?
        .iter()
        .map(|(w, _)| {
            preps
                .iter()
                .map(|p| (&p.ad * w - &p.td).norm())
                .fold(0.0, f64::max)
        })
        .fold(f64::INFINITY, f64::min))
}

/// A check passes when `excess ≤ tol`.
fn check(what: &'static str, excess: f64, tol: f64) -> Result<(), FitError> {
    if excess <= tol {
        return Ok(());
    }
    Err(FitError::Verification {
        mode: MODE,
        check: what,
        residual: excess,
        tolerance: tol,
        status: "Solved".into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::testutil::{random_matrix, random_vector, SplitMix64};
    use crate::fit::{solve, FitMode, FitOptions, FitSolution};

    fn perturbed(rng: &mut SplitMix64, a: &DMatrix<f64>, k: usize, size: f64) -> Vec<DMatrix<f64>> {
        (0..k)
            .map(|_| a + random_matrix(rng, a.nrows(), a.ncols()) * size)
            .collect()
    }

    /// Identical bases at every sample: stage 1 equals the single `shape`
    /// fit's relative error (1e-6) and stage 2 the single `budget` fit's
    /// strength at that error plus the slack (1e-6 relative), with and
    /// without row weights.
    #[test]
    fn identical_samples_give_the_single_fit() {
        let mut rng = SplitMix64::new(2601);
        let a = random_matrix(&mut rng, 30, 6);
        let t = &a * DVector::from_vec(vec![0.3, 0.0, 0.2, 0.1, 0.0, 0.25])
            + random_vector(&mut rng, 30) * 0.1;
        let d = DVector::from_fn(30, |i, _| {
            if i % 7 == 0 {
                0.0
            } else {
                1.0 + 0.1 * (i % 3) as f64
            }
        });
        for weights in [None, Some(&d)] {
            let p = FitProblem {
                a: &a,
                t: &t,
                row_weights: weights,
            };
            let shape = solve(&p, &FitOptions::default()).unwrap();
            let eps = shape.relative_error + 0.02;
            let budget = solve(
                &p,
                &FitOptions {
                    mode: FitMode::Budget { rel_error: eps },
                    ..FitOptions::default()
                },
            )
            .unwrap();
            let fit = solve_worst_case(
                &[a.clone(), a.clone(), a.clone()],
                &t,
                weights,
                &WorstCaseOptions::default(),
            )
            .unwrap();
            assert!(
                (fit.best_worst - shape.relative_error).abs() < 1e-6,
                "{} vs {}",
                fit.best_worst,
                shape.relative_error
            );
            assert!(
                (fit.strength - budget.strength).abs() < 1e-6 * budget.strength,
                "{} vs {}",
                fit.strength,
                budget.strength
            );
            for e in &fit.errors {
                assert!((e - fit.errors[0]).abs() < 1e-12);
                assert!((relative_error(&p, &fit.fractions, fit.strength) - e).abs() < 1e-9);
            }
        }
    }

    /// Perturbed samples: the worst case lies between the independent
    /// bounds — at least each sample's own best error, at most the worst
    /// error over the samples of any one sample's own fit (and of the
    /// middle sample's `shape` fit, what a fit at the nominal friction
    /// gives) — and it beats the nominal fit's worst case.
    #[test]
    fn worst_case_is_between_the_independent_bounds() {
        let mut rng = SplitMix64::new(2602);
        let a = random_matrix(&mut rng, 40, 8);
        let t = &a * DVector::from_fn(8, |i, _| 0.05 + 0.02 * i as f64)
            + random_vector(&mut rng, 40) * 0.05;
        let bases = perturbed(&mut rng, &a, 3, 0.15);
        let opts = WorstCaseOptions {
            slack: 0.0,
            ..WorstCaseOptions::default()
        };
        let fit = solve_worst_case(&bases, &t, None, &opts).unwrap();
        let own: Vec<FitSolution> = bases
            .iter()
            .map(|b| solve(&FitProblem::new(b, &t), &FitOptions::default()).unwrap())
            .collect();
        let lower = own.iter().map(|s| s.relative_error).fold(0.0, f64::max);
        let worst_of = |s: &FitSolution| {
            bases
                .iter()
                .map(|b| relative_error(&FitProblem::new(b, &t), &s.fractions, s.strength))
                .fold(0.0, f64::max)
        };
        let upper = own.iter().map(worst_of).fold(f64::INFINITY, f64::min);
        assert!(
            fit.best_worst >= lower - 1e-6,
            "{} < {lower}",
            fit.best_worst
        );
        assert!(
            fit.best_worst <= upper + 1e-6,
            "{} > {upper}",
            fit.best_worst
        );
        assert!(fit.worst() <= fit.best_worst + 1e-6);
        // The nominal (middle) fit is strictly worse here: the test can fail.
        assert!(
            worst_of(&own[1]) > fit.best_worst + 1e-3,
            "{} vs {}",
            worst_of(&own[1]),
            fit.best_worst
        );
        eprintln!(
            "worst case {:.4}; bounds [{lower:.4}, {upper:.4}]; nominal fit's worst {:.4}",
            fit.best_worst,
            worst_of(&own[1])
        );
    }

    /// Two columns, two samples, strength floor 1 (Σw ≤ 1): stage 1 against
    /// a brute-force grid over the triangle (step 1/400): never above the
    /// grid's minimum and within its resolution (Lipschitz bound).
    #[test]
    fn two_columns_match_a_brute_force_grid() {
        let mut rng = SplitMix64::new(2603);
        let a = random_matrix(&mut rng, 12, 2);
        let t = &a * DVector::from_vec(vec![0.4, 0.35]) + random_vector(&mut rng, 12) * 0.1;
        let bases = perturbed(&mut rng, &a, 2, 0.3);
        let opts = WorstCaseOptions {
            min_strength: Some(1.0),
            slack: 0.0,
            ..WorstCaseOptions::default()
        };
        let fit = solve_worst_case(&bases, &t, None, &opts).unwrap();
        assert!(fit.strength >= 1.0 - 1e-9);
        let tn = t.norm();
        let f = |w: &DVector<f64>| {
            bases
                .iter()
                .map(|b| (b * w - &t).norm() / tn)
                .fold(0.0, f64::max)
        };
        let n = 400;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for k in 0..=(n - i) {
                best = best.min(f(&DVector::from_vec(vec![
                    i as f64 / n as f64,
                    k as f64 / n as f64,
                ])));
            }
        }
        let lip = bases
            .iter()
            .map(|b| b.column(0).norm().max(b.column(1).norm()))
            .fold(0.0, f64::max)
            / tn;
        assert!(fit.best_worst <= best + 1e-7, "{} > {best}", fit.best_worst);
        assert!(
            best - fit.best_worst <= lip / n as f64,
            "{} vs {best}",
            fit.best_worst
        );
    }

    /// Symmetry: the second sample is the first with its columns swapped in
    /// pairs (A₂ = A₁Π), so the problem is invariant under w → Πw and, being
    /// convex, has a symmetric minimiser: τ* equals the NNLS fit on the
    /// merged columns A₁(e_{2i} + e_{2i+1}) (1e-6), and the errors at the
    /// two samples of the returned fractions agree to 1e-5.
    #[test]
    fn mirrored_samples_have_a_symmetric_optimum() {
        let mut rng = SplitMix64::new(2604);
        let a1 = random_matrix(&mut rng, 24, 6);
        let t = random_vector(&mut rng, 24) + &a1 * DVector::from_element(6, 0.2);
        let a2 = DMatrix::from_fn(24, 6, |i, j| a1[(i, j ^ 1)]);
        let merged = DMatrix::from_fn(24, 3, |i, j| a1[(i, 2 * j)] + a1[(i, 2 * j + 1)]);
        let v = nnls(&merged, &t).unwrap();
        let closed = (&merged * &v - &t).norm() / t.norm();
        let fit = solve_worst_case(
            &[a1, a2],
            &t,
            None,
            &WorstCaseOptions {
                slack: 0.0,
                ..WorstCaseOptions::default()
            },
        )
        .unwrap();
        assert!(
            (fit.best_worst - closed).abs() < 1e-6,
            "{} vs {closed}",
            fit.best_worst
        );
        assert!(
            (fit.errors[0] - fit.errors[1]).abs() < 1e-5,
            "{:?}",
            fit.errors
        );
    }

    /// Bad input is refused: no sample, bases of different shapes, a
    /// non-positive floor.
    #[test]
    fn bad_input_is_refused() {
        let a = DMatrix::from_element(4, 2, 1.0);
        let t = DVector::from_element(4, 1.0);
        let opts = WorstCaseOptions::default();
        assert!(matches!(
            solve_worst_case(&[], &t, None, &opts),
            Err(FitError::InvalidInput(_))
        ));
        let b = DMatrix::from_element(4, 3, 1.0);
        assert!(matches!(
            solve_worst_case(&[a.clone(), b], &t, None, &opts),
            Err(FitError::DimensionMismatch { .. })
        ));
        let floor = WorstCaseOptions {
            min_strength: Some(0.0),
            ..opts
        };
        assert!(matches!(
            solve_worst_case(&[a], &t, None, &floor),
            Err(FitError::InvalidInput(_))
        ));
    }
}
