//! A-posteriori verification of fit solutions.
//!
//! Every answer of the interior-point solver is re-checked here against the
//! **uncompressed** weighted data (`Â`, `t̂`, normalised so `‖t̂‖₂ = 1`, see
//! [`crate::fit::prepare`]) before it is returned.  With `w` the solver
//! variable (the un-normalised minimiser for `Shape`) and `tol` the
//! user's [`FitOptions::tolerance`](crate::fit::FitOptions::tolerance):
//!
//! 1. **Primal feasibility**: `minⱼ wⱼ ≥ −tol`; `1ᵀw ≤ 1 + tol` (all modes
//!    but `Shape`); for `Budget` also `‖Âw − s t̂‖ ≤ (ε + tol)·s`.
//!
//! 2. **KKT residual** (`Absolute`, `Shape`).  With the gradient
//!    `g = Âᵀ(Âw − t̂)` (i.e. `AᵀD²(Aw − t)/‖Dt‖²`) the optimality conditions
//!    of `min ½‖Âw − t̂‖²` s.t. `w ≥ 0, 1ᵀw ≤ 1` are
//!    `λ = g + μ1 ≥ 0, λ ⊙ w = 0, μ ≥ 0, μ(1 − 1ᵀw) = 0`.  The multiplier of
//!    the sum is recomputed from `w` alone as
//!    `μ̂ = max(0, −wᵀg / 1ᵀw)` (the `w`-weighted mean of `−gⱼ` over the
//!    support; `μ̂ = 0` for `Shape`), and
//!
//!    ```text
//!    kkt = max( maxⱼ max(0, −λⱼ)/‖Âⱼ‖,          (dual feasibility)
//!               Σⱼ wⱼ|λⱼ| + μ̂·|1 − 1ᵀw| )      (complementarity/stationarity)
//!    ```
//!
//!    Both terms are dimensionless (`‖t̂‖ = 1`); `kkt` is what a solution
//!    reports (`kkt_residual`). The check is `kkt_rel ≤ tol`, where
//!    `kkt_rel` divides the complementarity term by `max(1, Σⱼ wⱼ‖Âⱼ‖)`:
//!    the complementarity sum is relative to the problem's scale
//!    `Σⱼ wⱼ‖Âⱼ‖`, the total size of the fields the answer combines (in
//!    units of the target): each term is wⱼ‖Âⱼ‖ times |λⱼ|/‖Âⱼ‖, a
//!    column's share of the answer times its dimensionless gradient, so
//!    when the answer combines strong fields that nearly cancel into a
//!    weak one (`Shape` at a high friction: the parts mostly stick, the
//!    fields are weak, and w = f/s is large) the solver's relative
//!    accuracy on each term, not the absolute one, is what can be asked.
//!
//! 3. **Independent optimum.**
//!    * `Absolute`/`Shape`: the Lawson–Hanson solution `w_ref`
//!      ([`mod@crate::fit::nnls`], capped for `Absolute`) on the compressed
//!      data; `gap = ‖Âw − t̂‖ − ‖Âw_ref − t̂‖` (difference of relative L2
//!      errors, both evaluated on the full rows) must be `≤ tol`.
//!    * `Budget`: with `φ(s) = min_{w ≥ 0, 1ᵀw ≤ 1} ‖Âw − s t̂‖ − ε s`
//!      (capped NNLS; `φ` is convex with `φ(0) = 0`, so
//!      `{s : φ(s) ≤ 0} = [0, s*]`), the reported `s` must satisfy
//!      `φ(s(1 − tol)) ≤ 0 < φ(s(1 + tol))`; 20 bisection steps inside that
//!      bracket give `s_ref` and `gap = (s_ref − s)/s_ref`.
//!    * `L1`/`LInf`: weak duality.  For any `y` with `‖y‖_∞ ≤ 1` (L1) or
//!      `‖y‖₁ ≤ 1` (L∞) and any feasible `w`,
//!      `‖Âw − t̂‖_p ≥ yᵀ(Âw − t̂) ≥ min(0, minⱼ (Âᵀy)ⱼ) − yᵀt̂ =: LB(y)`.
//!      `y = z₁ − z₂` is taken from the solver's duals and projected onto
//!      the dual-norm ball, and `gap = (‖Âw − t̂‖_p − LB(y)) / ‖t̂‖_p` must be
//!      `≤ tol`.  The bound is computed here from the raw data, so a wrong
//!      dual can only make the check fail, never pass.
//!
//! Any failed check is a [`FitError::Verification`].

use nalgebra::{DMatrix, DVector};

use crate::fit::conic::ConicOutcome;
use crate::fit::lp::{dual_bound, project_dual, solve_lp_mode};
use crate::fit::nnls::{nnls_capped, nnls_detailed};
use crate::fit::prepare::Prepared;
#[cfg(test)]
use crate::fit::{validate_mode, FitProblem};
use crate::fit::{FitError, FitMode};

/// A field below this fraction of the (weighted) target norm counts as
/// zero when deciding that a `Shape` target is unreachable.
pub(crate) const ZERO_FIELD_TOL: f64 = 1e-9;

/// Bisection steps used to refine the independent `Budget` strength.
const BUDGET_BISECTION_STEPS: usize = 20;

/// Outcome of a successful verification (normalised units, `‖t̂‖ = 1`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub(crate) struct Verification {
    /// Largest primal infeasibility found (≤ tol).
    pub feasibility_violation: f64,
    /// KKT residual (`Absolute`, `Shape`), budget-constraint violation
    /// (`Budget`), or relative duality gap (`L1`, `LInf`).
    pub kkt_residual: f64,
    /// Gap to the independent reference (see module docs; negative means
    /// the checked answer is better than the reference).
    pub independent_gap: f64,
    /// Objective in normalised units: `‖Âw − t̂‖²` (`Absolute`, `Shape`),
    /// `s` (`Budget`), `‖Âw − t̂‖₁` / `‖Âw − t̂‖_∞` (`L1` / `LInf`).
    pub objective: f64,
    /// Relative L2 error `‖Âw − s t̂‖ / s` of the checked answer.
    pub relative_error: f64,
}

/// Independent reference data computed before the interior-point solve.
#[derive(Debug, Clone)]
pub(crate) struct Independent {
    /// Its relative L2 error (`Absolute`, `Shape`, and the shape error for
    /// `Budget`).
    pub rel_error: f64,
    /// `Shape`: the best non-negative mix produces a negligible field,
    /// `‖Âw_ref‖ ≤` [`ZERO_FIELD_TOL`]` ·‖t̂‖` (no column correlates
    /// positively with the target beyond rounding).
    pub zero_optimal: bool,
    /// Its weights (`Absolute`, `Shape`; `Shape` un-normalised like the
    /// solver's), which the fit keeps when the interior-point answer is
    /// worse by more than the tolerance and these pass every check.
    pub weights: Option<DVector<f64>>,
}

impl Independent {
    /// Compute the reference; for `Budget` this also decides feasibility
    /// exactly: a strength `s > 0` meets the budget iff the best shape fit
    /// has relative error `< ε` (for small `s` the cap `1ᵀw ≤ 1` is
    /// inactive and the constraint is scale-invariant).
    pub(crate) fn compute(prep: &Prepared, mode: &FitMode, _tol: f64) -> Result<Self, FitError> {
        match *mode {
            FitMode::Absolute => {
                let w = nnls_capped(&prep.r, &prep.c, 1.0)?;
                let rel_error = prep.residual_norm(&w, 1.0);
                Ok(Self {
                    rel_error,
                    zero_optimal: false,
                    weights: Some(w),
                })
            }
            FitMode::Shape | FitMode::Budget { .. } => {
                let out = nnls_detailed(&prep.r, &prep.c)?;
                let zero_optimal = (&prep.ad * &out.x).norm() <= ZERO_FIELD_TOL;
                let rel_error = prep.residual_norm(&out.x, 1.0);
                if let FitMode::Budget { rel_error: eps } = *mode {
                    if rel_error >= eps {
                        return Err(FitError::BudgetInfeasible {
                            rel_error: eps,
                            best_rel_error: rel_error,
                        });
                    }
                }
                let weights = matches!(mode, FitMode::Shape).then_some(out.x);
                Ok(Self {
                    rel_error,
                    zero_optimal,
                    weights,
                })
            }
            FitMode::L1 | FitMode::LInf => Ok(Self {
                rel_error: f64::NAN,
                zero_optimal: false,
                weights: None,
            }),
        }
    }
}

fn fail(mode: &FitMode, check: &'static str, residual: f64, tolerance: f64) -> FitError {
    FitError::Verification {
        mode: mode.name(),
        check,
        residual,
        tolerance,
        status: "n/a".into(),
    }
}

/// Verify a candidate answer on prepared data.  `w` is the solver variable
/// (un-normalised for `Shape`), `s` the strength (used by `Budget` only).
/// `outcome` supplies the dual certificate for `L1`/`LInf`; when absent a
/// reference LP is solved to obtain one.
pub(crate) fn verify_prepared(
    prep: &Prepared,
    mode: &FitMode,
    w: &DVector<f64>,
    s: f64,
    tol: f64,
    outcome: Option<&ConicOutcome>,
    independent: &Independent,
) -> Result<Verification, FitError> {
    let m = prep.ncols();
    if w.len() != m {
        return Err(FitError::DimensionMismatch {
            what: "fractions",
            expected: m,
            got: w.len(),
        });
    }
    if w.iter().any(|v| !v.is_finite()) || !s.is_finite() {
        return Err(FitError::InvalidInput(
            "candidate solution is not finite".into(),
        ));
    }
    let p = primal(prep, mode, w, s);
    if p.feas > tol {
        return Err(fail(mode, "feasibility", p.feas, tol));
    }
    match *mode {
        FitMode::Absolute | FitMode::Shape => verify_ls(prep, mode, w, tol, independent, &p),
        FitMode::Budget { rel_error } => verify_budget(prep, mode, (s, rel_error), tol, &p),
        FitMode::L1 | FitMode::LInf => verify_lp(prep, mode, tol, outcome, &p),
    }
}

/// A candidate's primal quantities: its residual, feasibility violation
/// (w ≥ 0, Σw ≤ 1 where capped, and `Budget`'s s ≥ 0 and error budget)
/// and relative error.
struct Primal {
    resid: DVector<f64>,
    res2: f64,
    feas: f64,
    budget_violation: f64,
    relative_error: f64,
}

/// 1. Primal feasibility of the candidate (`w`, `s`).
fn primal(prep: &Prepared, mode: &FitMode, w: &DVector<f64>, s: f64) -> Primal {
    let mut feas = (-w.min()).max(0.0);
    if mode.has_sum_constraint() {
        feas = feas.max(w.sum() - 1.0);
    }
    let resid = &prep.ad * w - &prep.td * s;
    let res2 = resid.norm();
    let mut budget_violation = 0.0;
    if let FitMode::Budget { rel_error: eps } = *mode {
        feas = feas.max(-s);
        budget_violation = if s > 0.0 {
            (res2 / s - eps).max(0.0)
        } else {
            f64::INFINITY
        };
        feas = feas.max(budget_violation);
    }
    let relative_error = if s > 0.0 { res2 / s } else { 1.0 };
    Primal {
        resid,
        res2,
        feas,
        budget_violation,
        relative_error,
    }
}

/// The least-squares modes: the KKT residual, and the objective against
/// the independent optimum.
fn verify_ls(
    prep: &Prepared,
    mode: &FitMode,
    w: &DVector<f64>,
    tol: f64,
    independent: &Independent,
    p: &Primal,
) -> Result<Verification, FitError> {
    let (dual_inf, comp, scale) = ls_kkt_terms(prep, w, mode.has_sum_constraint());
    let kkt = dual_inf.max(comp);
    let relative = dual_inf.max(comp / scale.max(1.0));
    if relative > tol {
        return Err(fail(mode, "kkt", relative, tol));
    }
    let reference = independent.rel_error;
    let gap = p.res2 - reference;
    if gap > tol {
        return Err(fail(mode, "independent", gap, tol));
    }
    Ok(Verification {
        feasibility_violation: p.feas,
        kkt_residual: kkt,
        independent_gap: gap,
        objective: p.res2 * p.res2,
        relative_error: p.relative_error,
    })
}

/// `Budget`: the strength `s` bracketed by an independent bisection on
/// φ(s) = ‖(R w*(s) − c s, s r₀)‖ − ε s (w*(s) by capped NNLS): a strictly
/// larger strength must be infeasible and `s` itself feasible.
fn verify_budget(
    prep: &Prepared,
    mode: &FitMode,
    (s, eps): (f64, f64),
    tol: f64,
    p: &Primal,
) -> Result<Verification, FitError> {
    let phi = |sv: f64| -> Result<f64, FitError> {
        let rhs = &prep.c * sv;
        let wr = nnls_capped(&prep.r, &rhs, 1.0)?;
        let inner = (&prep.r * &wr - &rhs).norm();
        Ok(inner.hypot(sv * prep.r0) - eps * sv)
    };
    let mut lo = s * (1.0 - tol);
    let mut hi = s * (1.0 + tol);
    if phi(hi)? <= 0.0 {
        // A strictly larger strength is feasible: not optimal.
        return Err(fail(mode, "independent", tol, tol));
    }
    if phi(lo)? > 0.0 {
        return Err(fail(mode, "independent", tol, tol));
    }
    for _ in 0..BUDGET_BISECTION_STEPS {
        let mid = 0.5 * (lo + hi);
        if phi(mid)? <= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let s_ref = 0.5 * (lo + hi);
    Ok(Verification {
        feasibility_violation: p.feas,
        kkt_residual: p.budget_violation,
        independent_gap: (s_ref - s) / s_ref,
        objective: s,
        relative_error: p.relative_error,
    })
}

/// `L1`/`LInf`: the duality gap against the lower bound of the dual
/// certificate (the solver's, or a reference LP's when absent).
fn verify_lp(
    prep: &Prepared,
    mode: &FitMode,
    tol: f64,
    outcome: Option<&ConicOutcome>,
    p: &Primal,
) -> Result<Verification, FitError> {
    let owned;
    let out = match outcome {
        Some(o) => o,
        None => {
            owned = solve_lp_mode(prep, matches!(mode, FitMode::L1), tol)?;
            &owned
        }
    };
    let l1 = matches!(mode, FitMode::L1);
    let (obj, obj0) = if l1 {
        (p.resid.lp_norm(1), prep.td.lp_norm(1))
    } else {
        (p.resid.amax(), prep.td.amax())
    };
    let lb = lp_lower_bound(&prep.ad, &prep.td, &out.lp_dual, l1);
    let gap = (obj - lb) / obj0;
    if gap > tol {
        return Err(fail(mode, "independent", gap, tol));
    }
    Ok(Verification {
        feasibility_violation: p.feas,
        kkt_residual: gap,
        independent_gap: gap,
        objective: obj,
        relative_error: p.relative_error,
    })
}

/// KKT residual of the least-squares modes (`kkt` of the module docs),
/// from the full rows.
pub(crate) fn ls_kkt_residual(prep: &Prepared, w: &DVector<f64>, sum_cap: bool) -> f64 {
    let (dual_inf, comp, _) = ls_kkt_terms(prep, w, sum_cap);
    dual_inf.max(comp)
}

/// The KKT residual's terms (module docs): the dual infeasibility, the
/// complementarity sum and the problem's scale Σⱼ wⱼ‖Âⱼ‖.
fn ls_kkt_terms(prep: &Prepared, w: &DVector<f64>, sum_cap: bool) -> (f64, f64, f64) {
    let resid = &prep.ad * w - &prep.td;
    let g = prep.ad.tr_mul(&resid);
    let sw = w.sum();
    let mu = if sum_cap && sw > 0.0 {
        (-w.dot(&g) / sw).max(0.0)
    } else {
        0.0
    };
    let mut dual_inf = 0.0_f64;
    let mut comp = mu * (1.0 - sw).abs();
    let mut scale = 0.0;
    for j in 0..w.len() {
        let lam = g[j] + mu;
        let cn = prep.col_norms[j];
        if cn > 0.0 {
            dual_inf = dual_inf.max((-lam).max(0.0) / cn);
        }
        comp += w[j] * lam.abs();
        scale += w[j].abs() * cn;
    }
    (dual_inf, comp, scale)
}

/// Weak-duality lower bound `LB(y)` for the L1 / L∞ fits, with the
/// solver's certificate `y` projected onto the dual-norm ball (`[−1,1]^M`
/// for L1, the unit ℓ₁ ball for L∞ by scaling).  Both `y` and `−y` are
/// valid; the larger bound is returned.
fn lp_lower_bound(ad: &DMatrix<f64>, td: &DVector<f64>, y: &[f64], l1: bool) -> f64 {
    if y.len() != ad.nrows() {
        return f64::NEG_INFINITY;
    }
    let y = project_dual(y, l1);
    let aty = ad.tr_mul(&y);
    let yt = y.dot(td);
    dual_bound(&aty, yt, None).max(dual_bound(&-aty, -yt, None))
}

/// Verify a candidate answer given in the caller's terms (time fractions
/// and strength, as in [`FitSolution`](crate::fit::FitSolution)) against
/// the problem, with the checks listed in the module docs.
///
/// For `Shape` the solver variable is recovered as `w = f / s` (`w = 0`
/// when `s = 0`); for `Budget` `w = f` and `s` is the strength; otherwise
/// `w = f` and the strength is ignored.  For `L1`/`LInf` a reference LP is
/// solved to obtain the dual certificate.
///
/// # Errors
/// [`FitError::Verification`] when a check fails (or `BudgetInfeasible`
/// when the budget cannot be met at all), input errors otherwise.
#[cfg(test)]
pub(crate) fn verify(
    problem: &FitProblem,
    mode: &FitMode,
    fractions: &[f64],
    strength: f64,
    tolerance: f64,
) -> Result<Verification, FitError> {
    validate_mode(mode)?;
    let prep = Prepared::new(problem)?;
    let f = DVector::from_column_slice(fractions);
    let (w, s) = match mode {
        FitMode::Shape => {
            if strength > 0.0 {
                (f / strength, 1.0)
            } else {
                (DVector::zeros(fractions.len()), 1.0)
            }
        }
        FitMode::Budget { .. } => (f, strength),
        _ => (f, 1.0),
    };
    let independent = Independent::compute(&prep, mode, tolerance)?;
    verify_prepared(&prep, mode, &w, s, tolerance, None, &independent)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::testutil::{random_matrix, SplitMix64};
    use crate::fit::{solve, FitOptions};

    fn problem_data(seed: u64) -> (DMatrix<f64>, DVector<f64>) {
        let mut rng = SplitMix64::new(seed);
        let a = random_matrix(&mut rng, 80, 6);
        let w_true = DVector::from_vec(vec![0.2, 0.0, 0.15, 0.1, 0.0, 0.25]);
        let noise = random_matrix(&mut rng, 80, 1).column(0).into_owned() * 0.05;
        let t = &a * w_true + noise;
        (a, t)
    }

    /// The verifier accepts the solver's answer and rejects the same answer
    /// perturbed by 1e-3 in one weight (failing check: "kkt"), in the
    /// least-squares modes.
    #[test]
    fn kkt_check_rejects_perturbed_solution() {
        let (a, t) = problem_data(11);
        let p = FitProblem::new(&a, &t);
        for mode in [FitMode::Absolute, FitMode::Shape] {
            let opts = FitOptions {
                mode,
                ..FitOptions::default()
            };
            let sol = solve(&p, &opts).unwrap();
            let ok = verify(&p, &mode, &sol.fractions, sol.strength, 1e-6).unwrap();
            assert!(ok.kkt_residual <= 1e-6);
            let mut bad = sol.fractions.clone();
            bad[0] += 1e-3;
            bad[2] -= 1e-3;
            match verify(&p, &mode, &bad, sol.strength, 1e-6) {
                Err(FitError::Verification {
                    check, residual, ..
                }) => {
                    assert_eq!(check, "kkt", "{mode:?}");
                    assert!(residual > 1e-6);
                }
                other => panic!("perturbed solution accepted in {mode:?}: {other:?}"),
            }
            // An infeasible candidate fails the feasibility check first.
            let mut neg = sol.fractions.clone();
            neg[1] = -1e-3;
            assert!(matches!(
                verify(&p, &mode, &neg, sol.strength, 1e-6),
                Err(FitError::Verification {
                    check: "feasibility",
                    ..
                })
            ));
        }
    }

    /// A sub-optimal but KKT-looking candidate is caught by the independent
    /// checks: Budget with a smaller strength, and L1/LInf with a perturbed
    /// weight.
    #[test]
    fn independent_checks_reject_suboptimal_answers() {
        let (a, t) = problem_data(12);
        let p = FitProblem::new(&a, &t);
        let budget = FitMode::Budget { rel_error: 0.2 };
        let sol = solve(
            &p,
            &FitOptions {
                mode: budget,
                ..FitOptions::default()
            },
        )
        .unwrap();
        verify(&p, &budget, &sol.fractions, sol.strength, 1e-6).unwrap();
        let smaller: Vec<f64> = sol.fractions.iter().map(|f| f * 0.99).collect();
        assert!(matches!(
            verify(&p, &budget, &smaller, sol.strength * 0.99, 1e-6),
            Err(FitError::Verification {
                check: "independent",
                ..
            })
        ));
        for mode in [FitMode::L1, FitMode::LInf] {
            let sol = solve(
                &p,
                &FitOptions {
                    mode,
                    ..FitOptions::default()
                },
            )
            .unwrap();
            verify(&p, &mode, &sol.fractions, 1.0, 1e-6).unwrap();
            let mut bad = sol.fractions.clone();
            bad[0] += 1e-2;
            assert!(
                matches!(
                    verify(&p, &mode, &bad, 1.0, 1e-6),
                    Err(FitError::Verification {
                        check: "independent",
                        ..
                    })
                ),
                "{mode:?}"
            );
        }
    }
}
