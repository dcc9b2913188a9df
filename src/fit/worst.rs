//! The stacked worst-case fit: one set of time fractions against several
//! bases of the same columns (the basis built at each friction sample of a
//! range), minimising the worst shape error over them.
//!
//! # Problem
//!
//! Bases `A₁ … A_K` (`2n×m` each, column j the same primitive simulated at
//! sample k), one target `t` and row weights `D`; `Â_k = DA_k/‖Dt‖`,
//! `t̂ = Dt/‖Dt‖` (unit norm). Time fractions `f ≥ 0`, `1ᵀf ≤ 1` give at
//! sample k the field `Â_k f`, whose strength and shape error are those of
//! the judge (`crate::verify`): the least-squares scale
//! `s_k = t̂ᵀÂ_k f` and `e_k = ‖Â_k f − s_k t̂‖ / s_k` (the tangent of the
//! angle between field and target; each sample has its own scale, so a
//! field that only grows or shrinks with friction costs no shape).
//! `e_k ≤ ε` is the second-order cone `(ε s_k, (I − t̂t̂ᵀ)Â_k f) ∈ 𝒬`,
//! linear in `f` for a fixed ε, so
//!
//! ```text
//! σ*(ε) = max σ   s.t.  s_k ≥ σ,  ‖(I − t̂t̂ᵀ)Â_k f‖ ≤ ε s_k  (k = 1 … K),
//!                       f ≥ 0,  1ᵀf ≤ 1   [σ ≥ s_min with a strength floor]
//! ```
//!
//! is a second-order cone program: the strongest weakest strength at worst
//! shape ε. Each sample is compressed by its own thin QR exactly as
//! `crate::fit::prepare` does (`Â_k = Q_k R_k`, `c_k = Q_kᵀt̂`, `r₀ₖ` the
//! unreachable part of `t̂`): with `g_k = R_kᵀc_k` (so `s_k = g_kᵀf`),
//! `‖(I − t̂t̂ᵀ)Â_k f‖² = ‖(R_k − c_k g_kᵀ) f‖² + r₀ₖ² (g_kᵀf)²`.
//! The worst shape is scale-free, so `σ*(ε)` is 0 below the least worst
//! error `τ*` and of the order of the field's strength above it:
//!
//! * stage 1 bisects ε for `τ*` (to `BISECTION_TOL`) between the
//!   independent bounds below, `σ*(ε) > 0` (or `≥ s_min`) meaning feasible;
//! * stage 2 solves `σ*(τ* + slack)`: as the single fit's `shape` mode
//!   (`strongest` in [`crate::design`]) takes the strongest field within
//!   a slack, since the minimiser is not unique where columns cancel.
//!
//! # Verification
//!
//! Bounds computed without the cone solver bracket `τ*`: each sample's own
//! best error (Lawson–Hanson NNLS on its compressed data; its residual is
//! the sine of the least angle, `e = sin/√(1 − sin²)`) is a lower bound
//! (the worst case is at least the best fit of any one sample), and the
//! worst error over all samples of each sample's own NNLS weights is an
//! upper bound (those weights are a feasible choice; without a floor,
//! which they may break). The returned fractions' errors and strengths are
//! recomputed from the uncompressed data and must meet ε and the floor.

use clarabel::solver::SolverStatus;
use clarabel::solver::SupportedConeT::{NonnegativeConeT, SecondOrderConeT};
use nalgebra::{DMatrix, DVector};

use super::conic::{ConeBuilder, ConicOutcome, TOL_BUDGET};
use super::nnls::nnls;
use super::prepare::Prepared;
use super::{FitError, FitProblem};

/// Mode name in errors.
const MODE: &str = "worst_case";

/// Stage 1 bisects the least worst error to this (absolute).
pub(crate) const BISECTION_TOL: f64 = 1e-6;

/// `σ*(ε)` above this (normalised strength units) counts as feasible.
const FEASIBLE_STRENGTH: f64 = 1e-7;

/// Options of [`solve_worst_case`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct WorstCaseOptions {
    /// Strength floor `s_min` (> 0) on every sample's strength, or none.
    pub min_strength: Option<f64>,
    /// Stage 2 takes the strongest field whose worst error is within
    /// `τ* + slack` (0 keeps stage 1's error; default 0.02, the single
    /// fit's `SHAPE_SLACK`).
    pub slack: f64,
    /// Tolerance of the checks (absolute, on errors and strengths);
    /// default 1e-5.
    pub tolerance: f64,
}

impl Default for WorstCaseOptions {
    fn default() -> Self {
        WorstCaseOptions {
            min_strength: None,
            slack: 0.02,
            tolerance: 1e-5,
        }
    }
}

/// A verified worst-case fit.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct WorstCaseFit {
    /// Time fractions `f ≥ 0`, `1ᵀf ≤ 1` (the plate rests for the rest).
    pub fractions: Vec<f64>,
    /// Least-squares strength `s_k` of the field at each sample (× the
    /// target's), recomputed from the uncompressed data.
    pub strengths: Vec<f64>,
    /// Shape error `e_k` at each sample, recomputed likewise.
    pub errors: Vec<f64>,
    /// Stage 1's least worst error `τ*` (at the strength floor, if any).
    pub best_worst: f64,
    /// The independent bounds on `τ*` (module docs).
    pub bounds: [f64; 2],
    /// Interior-point solves (bisection and stage 2).
    pub solves: u32,
    /// What was solved, e.g. `"Solved (worst case over 3 samples: best
    /// 0.0312, then strongest within 0.0512)"`.
    pub status: String,
}

impl WorstCaseFit {
    /// The worst of [`WorstCaseFit::errors`].
    pub(crate) fn worst(&self) -> f64 {
        self.errors.iter().copied().fold(0.0, f64::max)
    }

    /// The weakest of [`WorstCaseFit::strengths`].
    pub(crate) fn weakest(&self) -> f64 {
        self.strengths.iter().copied().fold(f64::INFINITY, f64::min)
    }
}

/// The judge's measures of fractions `f` against the
/// (row-weighted) target of `problem`: `(e, s)` with `s = ⟨DAf, Dt⟩/‖Dt‖²`
/// the least-squares strength and `e = ‖D(Af − s t)‖ / ‖D s t‖`.
pub(crate) fn shape_and_strength(problem: &FitProblem, fractions: &[f64]) -> (f64, f64) {
    let af = problem.a * DVector::from_column_slice(fractions);
    let (af, t) = match problem.row_weights {
        Some(d) => (af.component_mul(d), problem.t.component_mul(d)),
        None => (af, problem.t.clone()),
    };
    let s = af.dot(&t) / t.norm_squared();
    ((&af - &t * s).norm() / (s * t.norm()), s)
}

/// Solves the stacked worst-case fit of the target `t` (row weights `d`)
/// against the bases `a` (see the module docs), and verifies the answer.
///
/// # Errors
/// No sample, bases of different shapes, invalid data or options, a
/// target no non-negative mix points towards at every sample, a floor no
/// fractions reach, a solver failure, or a failed check.
pub(crate) fn solve_worst_case(
    a: &[DMatrix<f64>],
    t: &DVector<f64>,
    d: Option<&DVector<f64>>,
    options: &WorstCaseOptions,
) -> Result<WorstCaseFit, FitError> {
    let preps = prepare_all(a, t, d, options)?;
    let (lower, upper) = bounds(&preps)?;
    if !upper.is_finite() {
        return Err(FitError::InvalidInput(
            "no non-negative mix points towards the target at every friction sample".into(),
        ));
    }
    let floor = options.min_strength.unwrap_or(FEASIBLE_STRENGTH);
    // A solver failure during the bisection counts as infeasible.
    let feasible = |eps: f64| stage(&preps, eps, options.min_strength).is_ok_and(|o| o.1 >= floor);
    // Without a floor the upper bound is feasible; with one it may not be.
    let mut hi = if options.min_strength.is_some() {
        upper.max(1.0) * 4.0
    } else {
        upper
    };
    let mut lo = lower;
    if !feasible(hi) {
        return Err(FitError::InvalidInput(format!(
            "no fractions reach the strength floor {} at every friction sample",
            floor
        )));
    }
    let mut solves = 1;
    while hi - lo > BISECTION_TOL {
        let mid = 0.5 * (lo + hi);
        solves += 1;
        if feasible(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let tau = hi;
    let tol = options.tolerance;
    check("lower bound", lower - tau, tol)?;
    if options.min_strength.is_none() {
        check("upper bound", tau - upper, tol)?;
    }
    let eps = tau + options.slack;
    let (f, _) = stage(&preps, eps, options.min_strength)?;
    let (errors, strengths) = measures(&preps, &f);
    let fit = WorstCaseFit {
        fractions: f,
        strengths,
        errors,
        best_worst: tau,
        bounds: [lower, upper],
        solves: solves + 1,
        status: format!(
            "Solved (worst case over {} samples: best {tau:.4}, then strongest within {eps:.4})",
            a.len()
        ),
    };
    check("shape", fit.worst() - eps, tol)?;
    check("strength floor", floor - fit.weakest(), tol)?;
    check("time", fit.fractions.iter().sum::<f64>() - 1.0, tol)?;
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
    let positive = |what: &str, v: f64, zero_ok: bool| {
        if v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0)) {
            Ok(())
        } else {
            Err(FitError::InvalidInput(format!(
                "{what} must be finite and {} 0, got {v}",
                if zero_ok { ">=" } else { ">" }
            )))
        }
    };
    if let Some(s) = options.min_strength {
        positive("min_strength", s, false)?;
    }
    positive("slack", options.slack, true)?;
    positive("tolerance", options.tolerance, false)?;
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

/// `σ*(ε)` (module docs): the fractions and the weakest strength.
fn stage(preps: &[Prepared], eps: f64, floor: Option<f64>) -> Result<(Vec<f64>, f64), FitError> {
    let m = preps[0].ncols();
    let mut bld = ConeBuilder::new(m + 1);
    for p in preps {
        let kk = p.r.nrows();
        let g = p.r.tr_mul(&p.c);
        bld.row((0..m).map(|j| (j, -eps * g[j])), 0.0);
        for i in 0..kk {
            bld.row((0..m).map(|j| (j, p.c[i] * g[j] - p.r[(i, j)])), 0.0);
        }
        bld.row((0..m).map(|j| (j, -p.r0 * g[j])), 0.0);
        bld.cone(SecondOrderConeT(kk + 2));
    }
    for p in preps {
        let g = p.r.tr_mul(&p.c);
        bld.row((0..m).map(|j| (j, -g[j])).chain([(m, 1.0)]), 0.0);
    }
    for j in 0..m {
        bld.row([(j, -1.0)], 0.0);
    }
    bld.row((0..m).map(|j| (j, 1.0)), 1.0);
    let mut rows = preps.len() + m + 1;
    if let Some(s) = floor {
        bld.row([(m, -1.0)], -s);
        rows += 1;
    }
    bld.cone(NonnegativeConeT(rows));
    let mut q = vec![0.0; m + 1];
    q[m] = -1.0;
    let out = solved(bld.solve(q, TOL_BUDGET, MODE)?)?;
    let f = out.x[..m].iter().map(|v| v.max(0.0)).collect();
    Ok((f, out.x[m]))
}

fn solved(out: ConicOutcome) -> Result<ConicOutcome, FitError> {
    match out.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(out),
        s => Err(FitError::SolverStatus {
            mode: MODE,
            status: format!("{s:?}"),
        }),
    }
}

/// Each sample's shape error and strength of fractions `f`, from `Â_k`.
fn measures(preps: &[Prepared], f: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let f = DVector::from_column_slice(f);
    preps
        .iter()
        .map(|p| {
            let af = &p.ad * &f;
            let s = af.dot(&p.td);
            ((&af - &p.td * s).norm() / s, s)
        })
        .unzip()
}

/// The independent bounds on `τ*` (module docs): `(lower, upper)`.
fn bounds(preps: &[Prepared]) -> Result<(f64, f64), FitError> {
    let mut lower = 0.0_f64;
    let mut upper = f64::INFINITY;
    for p in preps {
        let w = nnls(&p.r, &p.c)?;
        let sin2 = ((&p.r * &w - &p.c).norm_squared() + p.r0 * p.r0).min(1.0);
        lower = lower.max((sin2 / (1.0 - sin2)).sqrt());
        let (errors, strengths) = measures(preps, w.as_slice());
        let worst = errors
            .iter()
            .zip(&strengths)
            .map(|(e, s)| if *s > 0.0 { *e } else { f64::INFINITY })
            .fold(0.0, f64::max);
        upper = upper.min(worst);
    }
    Ok((lower, upper))
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
    use crate::fit::{solve, FitOptions};

    fn perturbed(rng: &mut SplitMix64, a: &DMatrix<f64>, k: usize, size: f64) -> Vec<DMatrix<f64>> {
        (0..k)
            .map(|_| a + random_matrix(rng, a.nrows(), a.ncols()) * size)
            .collect()
    }

    fn exact() -> WorstCaseOptions {
        WorstCaseOptions {
            slack: 0.0,
            ..WorstCaseOptions::default()
        }
    }

    /// The single fit's error `sin` as the realised measure's `tan`.
    fn tan_of(sin: f64) -> f64 {
        sin / (1.0 - sin * sin).sqrt()
    }

    /// Identical bases at every sample: the worst case is the single
    /// `shape` fit's error (as the realised measure, tan of its angle;
    /// 1e-5) at every sample, with and without row weights; with the slack
    /// the field is at least as strong and within the slack.
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
            let single = tan_of(solve(&p, &FitOptions::default()).unwrap().relative_error);
            let bases = [a.clone(), a.clone(), a.clone()];
            let fit = solve_worst_case(&bases, &t, weights, &exact()).unwrap();
            assert!(
                (fit.best_worst - single).abs() < 1e-5,
                "{} vs {single}",
                fit.best_worst
            );
            for (e, s) in fit.errors.iter().zip(&fit.strengths) {
                assert!((e - single).abs() < 1e-5, "{e} vs {single}");
                let (e2, s2) = shape_and_strength(&p, &fit.fractions);
                assert!((e2 - e).abs() < 1e-9 && (s2 - s).abs() < 1e-9);
            }
            let slack =
                solve_worst_case(&bases, &t, weights, &WorstCaseOptions::default()).unwrap();
            assert!(slack.worst() <= single + 0.02 + 1e-5);
            assert!(slack.weakest() >= fit.weakest() - 1e-9);
        }
    }

    /// Perturbed samples: the worst case lies between bounds computed here
    /// from the single fits — at least each sample's own best error, at
    /// most the worst error over the samples of any one sample's own fit —
    /// and clearly beats the middle sample's fit (what a fit at the
    /// nominal friction gives).
    #[test]
    fn worst_case_is_between_the_independent_bounds() {
        let mut rng = SplitMix64::new(2602);
        let a = random_matrix(&mut rng, 40, 8);
        let t = &a * DVector::from_fn(8, |i, _| 0.05 + 0.02 * i as f64)
            + random_vector(&mut rng, 40) * 0.05;
        let bases = perturbed(&mut rng, &a, 3, 0.15);
        let fit = solve_worst_case(&bases, &t, None, &exact()).unwrap();
        let own: Vec<Vec<f64>> = bases
            .iter()
            .map(|b| {
                solve(&FitProblem::new(b, &t), &FitOptions::default())
                    .unwrap()
                    .fractions
            })
            .collect();
        let worst_of = |f: &[f64]| {
            bases
                .iter()
                .map(|b| shape_and_strength(&FitProblem::new(b, &t), f).0)
                .fold(0.0, f64::max)
        };
        let lower = bases
            .iter()
            .zip(&own)
            .map(|(b, f)| shape_and_strength(&FitProblem::new(b, &t), f).0)
            .fold(0.0, f64::max);
        let upper = own
            .iter()
            .map(|f| worst_of(f))
            .fold(f64::INFINITY, f64::min);
        println!(
            "worst case {:.4}; bounds [{lower:.4}, {upper:.4}]; middle fit's worst {:.4}",
            fit.best_worst,
            worst_of(&own[1])
        );
        assert!(
            fit.best_worst >= lower - 1e-5,
            "{} < {lower}",
            fit.best_worst
        );
        assert!(
            fit.best_worst <= upper + 1e-5,
            "{} > {upper}",
            fit.best_worst
        );
        assert!((fit.worst() - fit.best_worst).abs() < 1e-5);
        assert!(worst_of(&own[1]) > fit.best_worst + 1e-3);
    }

    /// Two columns, two samples: the worst error depends only on the
    /// direction of f, so stage 1 is checked against a brute-force scan of
    /// 20 000 directions: never above the scan's minimum, and within 1e-4
    /// of it.
    #[test]
    fn two_columns_match_a_brute_force_scan() {
        let mut rng = SplitMix64::new(2603);
        let a = random_matrix(&mut rng, 12, 2);
        let t = &a * DVector::from_vec(vec![0.4, 0.35]) + random_vector(&mut rng, 12) * 0.1;
        let bases = perturbed(&mut rng, &a, 2, 0.3);
        let fit = solve_worst_case(&bases, &t, None, &exact()).unwrap();
        let n = 20_000;
        let best = (0..=n)
            .map(|i| {
                let phi = std::f64::consts::FRAC_PI_2 * i as f64 / n as f64;
                let f = [phi.cos(), phi.sin()];
                bases
                    .iter()
                    .map(|b| {
                        let (e, s) = shape_and_strength(&FitProblem::new(b, &t), &f);
                        if s > 0.0 {
                            e
                        } else {
                            f64::INFINITY
                        }
                    })
                    .fold(0.0, f64::max)
            })
            .fold(f64::INFINITY, f64::min);
        assert!(fit.best_worst <= best + 1e-6, "{} > {best}", fit.best_worst);
        assert!(best - fit.best_worst < 1e-4, "{} vs {best}", fit.best_worst);
    }

    /// A strength floor that binds is met at every sample at a worse least
    /// worst error; one above any reachable strength is refused.
    #[test]
    fn strength_floor_is_met_or_refused() {
        let mut rng = SplitMix64::new(2605);
        let a = random_matrix(&mut rng, 20, 5).abs();
        let t = &a * DVector::from_element(5, 0.1) + random_vector(&mut rng, 20) * 0.05;
        let bases = perturbed(&mut rng, &a, 3, 0.1);
        let free = solve_worst_case(&bases, &t, None, &exact()).unwrap();
        // A floor between the strength at the least worst error and the
        // strength a loose error allows binds.
        let loose = WorstCaseOptions {
            slack: 1.0,
            ..exact()
        };
        let strongest = solve_worst_case(&bases, &t, None, &loose)
            .unwrap()
            .weakest();
        assert!(
            strongest > 1.01 * free.weakest(),
            "{strongest} vs {}",
            free.weakest()
        );
        let floor = 0.5 * (strongest + free.weakest());
        let opts = WorstCaseOptions {
            min_strength: Some(floor),
            ..exact()
        };
        let fit = solve_worst_case(&bases, &t, None, &opts).unwrap();
        assert!(fit.weakest() >= floor - 1e-6, "{} < {floor}", fit.weakest());
        assert!(
            fit.best_worst > free.best_worst + 1e-4,
            "{} vs {}",
            fit.best_worst,
            free.best_worst
        );
        let too_high = WorstCaseOptions {
            min_strength: Some(1e6),
            ..exact()
        };
        assert!(matches!(
            solve_worst_case(&bases, &t, None, &too_high),
            Err(FitError::InvalidInput(_))
        ));
    }

    /// Symmetry: the second sample is the first with its columns swapped in
    /// pairs (A₂ = A₁Π), so the problem is invariant under f → Πf and,
    /// being convex in each level set, has a symmetric minimiser: τ* equals
    /// the NNLS fit on the merged columns A₁(e_{2i} + e_{2i+1}) (as tan,
    /// 1e-5), and the errors at the two samples agree to 1e-4.
    #[test]
    fn mirrored_samples_have_a_symmetric_optimum() {
        let mut rng = SplitMix64::new(2604);
        let a1 = random_matrix(&mut rng, 24, 6);
        let t = random_vector(&mut rng, 24) + &a1 * DVector::from_element(6, 0.2);
        let a2 = DMatrix::from_fn(24, 6, |i, j| a1[(i, j ^ 1)]);
        let merged = DMatrix::from_fn(24, 3, |i, j| a1[(i, 2 * j)] + a1[(i, 2 * j + 1)]);
        let v = nnls(&merged, &t).unwrap();
        let closed = tan_of((&merged * &v - &t).norm() / t.norm());
        let fit = solve_worst_case(&[a1, a2], &t, None, &exact()).unwrap();
        assert!(
            (fit.best_worst - closed).abs() < 1e-5,
            "{} vs {closed}",
            fit.best_worst
        );
        assert!(
            (fit.errors[0] - fit.errors[1]).abs() < 1e-4,
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

    /// A worked example of `fit::worst`.
    #[test]
    fn example_worst() {
        use crate::fit::worst::{solve_worst_case, WorstCaseOptions};
        use nalgebra::{DMatrix, DVector};
        // Two samples of a two-column basis: the first column turns with the
        // sample, the second does not; only the second matches both.
        let a1 = DMatrix::from_column_slice(2, 2, &[1.0, 0.3, 1.0, 0.0]);
        let a2 = DMatrix::from_column_slice(2, 2, &[1.0, -0.3, 2.0, 0.0]);
        let t = DVector::from_vec(vec![1.0, 0.0]);
        let exact = WorstCaseOptions {
            slack: 0.0,
            ..WorstCaseOptions::default()
        };
        let fit = solve_worst_case(&[a1, a2], &t, None, &exact).unwrap();
        assert!(fit.best_worst < 1e-4);
        // Strength at each sample: 1 and 2 (the second column alone, all the time).
        assert!((fit.strengths[0] - 1.0).abs() < 1e-4 && (fit.strengths[1] - 2.0).abs() < 1e-4);
    }
}
