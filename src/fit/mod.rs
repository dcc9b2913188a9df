//! Fitting a target vector field with a time-weighted mix of basis fields.
//!
//! # Problem data
//!
//! A target 2-D field sampled at `n` points is stacked into a vector
//! `t ∈ ℝ^{2n}`; the `m` basis fields (primitive plate motions) are the
//! columns of a dense matrix `A ∈ ℝ^{2n×m}` (stacked or interleaved layout,
//! as long as `A` and `t` agree).  Optional non-negative row weights
//! `d ∈ ℝ^{2n}` act as multipliers on the residual rows, `D = diag(d)`.
//!
//! The decision variable is the vector of *time fractions*
//! `w ∈ ℝ^m` with `w ≥ 0` and `Σw ≤ 1`; the plate at rest (the zero field)
//! fills the remaining `1 − Σw`.
//!
//! # Modes ([`FitMode`])
//!
//! | mode | problem solved |
//! |------|----------------|
//! | `Absolute` | `min ‖D(Aw − t)‖₂²` s.t. `w ≥ 0, 1ᵀw ≤ 1` |
//! | `Shape` (default) | `w* = argmin ‖D(Aw − t)‖₂` s.t. `w ≥ 0`; report `f = w*/1ᵀw*`, strength `s = 1/1ᵀw*` |
//! | `Budget{ε}` | `max s` s.t. `‖D(Aw − s t)‖₂ ≤ ε s ‖Dt‖₂, w ≥ 0, 1ᵀw ≤ 1` |
//! | `L1` | `min ‖D(Aw − t)‖₁` s.t. `w ≥ 0, 1ᵀw ≤ 1` |
//! | `LInf` | `min ‖D(Aw − t)‖_∞` s.t. `w ≥ 0, 1ᵀw ≤ 1` |
//!
//! # How the problems are solved
//!
//! All modes are solved with the Clarabel interior-point solver, whose
//! standard form is
//!
//! ```text
//! min ½xᵀPx + qᵀx   s.t.  Ax + s = b,  s ∈ K
//! ```
//!
//! with `K` a product of zero, non-negative and second-order cones.
//!
//! * The least-squares modes (`Absolute`, `Shape`, `Budget`) never form the
//!   normal equations `AᵀD²A` (a normal-equations QP on nearly collinear
//!   columns ends `Solved` with weights far off — see `conic` and its
//!   regression test).  Instead the weighted matrix is compressed by a thin
//!   Householder QR, `DA = QR` with `R ∈ ℝ^{k×m}`, `k = min(2n, m)`, so that
//!   `‖D(Aw − t)‖² = ‖Rw − c‖² + r₀²` with `c = QᵀDt` and
//!   `r₀ = ‖(I − QQᵀ)Dt‖`, and the problem is posed on the small matrix `R`:
//!   by default as `min ½‖y‖²` s.t. `Rw − y = c` (residual variables in a
//!   zero cone), optionally in epigraph form `min τ` s.t.
//!   `(τ, Rw − c) ∈ 𝒬^{k+1}` (`FitOptions::formulation`); `Budget` is a
//!   second-order cone program on `R`.
//! * The interior-point weights of `Absolute`/`Shape` are then *re-solved on their active set*:
//!   the problem restricted to the active set the solver identified (support
//!   of `w`, and whether `Σw ≤ 1` binds) is solved exactly by an SVD least
//!   squares, with primal-dual active-set corrections if the guess was off;
//!   the re-solved point replaces the interior-point one only if its KKT
//!   residual is not larger ([`FitSolution::active_set`]).
//! * Where that point is still worse than the independent optimum (below)
//!   by more than the tolerance — a nearly collinear basis lets a KKT
//!   residual under the tolerance coexist with an objective 1e-6 off — the
//!   independent active-set solution is kept instead, provided it passes
//!   every check itself ([`FitSolution::independent_kept`]); otherwise the
//!   fit fails as below.
//! * `L1` and `LInf` are linear programs on the full rows with explicit
//!   residual variables, solved by column generation (`mod@lp`): LPs on
//!   a small working set of columns, grown by the columns whose reduced
//!   cost under the LP's dual certificate is negative, until the
//!   weak-duality bound over all columns meets the working-set optimum.
//!
//! # Verification
//!
//! Every solution is checked before it is returned (`mod@certify`): primal
//! feasibility, a KKT / duality residual recomputed from the *uncompressed*
//! data, and an independent optimum (Lawson–Hanson active-set NNLS in
//! `mod@nnls` for the least-squares modes, a bracketing of the optimal strength
//! for `Budget`, and a weak-duality lower bound for `L1`/`LInf`).  A failed
//! check is an error ([`FitError::Verification`]), never a result.
//!
//! # Fewer primitives
//!
//! `subset::sparsity_path` gives the best fit found with at most `k`
//! columns for `k = 1..=k_max`, and `FitOptions::max_primitives` restricts
//! `solve` the same way.
//!
//! # Scaling and units
//!
//! Internally rows with `dᵢ = 0` are dropped and the weighted data are
//! divided by `‖Dt‖₂` (this leaves `w` and the strength unchanged); all
//! reported objectives are converted back to the caller's units.

pub(crate) mod active_set;
pub(crate) mod certify;
pub(crate) mod conic;
pub(crate) mod lp;
pub(crate) mod lp_rows;
pub(crate) mod metrics;
pub(crate) mod nnls;
pub(crate) mod prepare;
pub(crate) mod subset;
pub mod worst;

#[cfg(test)]
pub(crate) mod testutil;

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

#[cfg(test)]
pub(crate) use certify::verify;
pub(crate) use certify::Verification;
pub(crate) use conic::LsFormulation;
pub(crate) use metrics::{field_metrics, FitMetrics};
pub(crate) use subset::sparsity_path;

use prepare::Prepared;

/// The one POOR threshold of the product: a relative error above it — a
/// fit's relative L2 error, a synthesized motion's shape error, a played
/// design's realised shape error — is reported as POOR. 20 % (the shape
/// error of a field turned by atan 0.2 = 11.3° from the target's).
pub const POOR_ERROR: f64 = 0.2;

/// A fit whose relative L2 error exceeds this value is flagged
/// [`FitSolution::unreachable`]: [`POOR_ERROR`] (one threshold).
pub(crate) const UNREACHABLE_REL_ERROR: f64 = POOR_ERROR;

/// Which optimisation problem `solve` solves (see the module docs for the
/// maths).  Serialised with snake_case tags: `"absolute"`, `"shape"`,
/// `{"budget": {"rel_error": 0.1}}`, `"l1"`, `"l_inf"` (alias `"linf"`).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FitMode {
    /// `min ‖D(Aw − t)‖₂²` s.t. `w ≥ 0, 1ᵀw ≤ 1`; strength is 1.
    Absolute,
    /// `w* = argmin_{w ≥ 0} ‖D(Aw − t)‖₂` (no sum constraint); fractions
    /// `w*/1ᵀw*`, strength `1/1ᵀw*`.  The achieved field is `≈ s·t`.
    #[default]
    Shape,
    /// `max s` s.t. `‖D(Aw − s t)‖₂ ≤ ε s ‖Dt‖₂, w ≥ 0, 1ᵀw ≤ 1`, with
    /// `ε = rel_error ∈ (0, 1)`.
    Budget {
        /// The relative L2 error budget `ε`.
        rel_error: f64,
    },
    /// `min ‖D(Aw − t)‖₁` s.t. `w ≥ 0, 1ᵀw ≤ 1`.
    L1,
    /// `min ‖D(Aw − t)‖_∞` s.t. `w ≥ 0, 1ᵀw ≤ 1`.
    #[serde(alias = "linf")]
    LInf,
}

impl FitMode {
    /// Short name used in messages.
    pub fn name(&self) -> &'static str {
        match self {
            FitMode::Absolute => "absolute",
            FitMode::Shape => "shape",
            FitMode::Budget { .. } => "budget",
            FitMode::L1 => "l1",
            FitMode::LInf => "l_inf",
        }
    }

    /// Whether the mode imposes `1ᵀw ≤ 1` on the solver variable.
    pub(crate) fn has_sum_constraint(&self) -> bool {
        !matches!(self, FitMode::Shape)
    }
}

/// Options of [`solve`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub(crate) struct FitOptions {
    /// The problem to solve.
    pub mode: FitMode,
    /// Use at most this many basis columns (see `subset`); `None` = all.
    pub max_primitives: Option<usize>,
    /// Tolerance of the a-posteriori verification (feasibility, KKT
    /// residual, gap to the independent solver), dimensionless; see
    /// `mod@certify` for the exact scaling of each check.  Default `1e-6`.
    pub tolerance: f64,
    /// Print a one-line summary of each solve to stderr.
    pub verbose: bool,
    /// Conic formulation of the least-squares modes (default: residual
    /// QP on the QR-compressed data; see [`LsFormulation`]).
    pub formulation: LsFormulation,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            mode: FitMode::Shape,
            max_primitives: None,
            tolerance: 1e-6,
            verbose: false,
            formulation: LsFormulation::ResidualQp,
        }
    }
}

/// Problem data: `A` (`2n×m`), target `t` (`2n`), optional row weights `d`
/// (`2n`, non-negative multipliers on the residual rows).
#[derive(Debug, Clone, Copy)]
pub(crate) struct FitProblem<'a> {
    /// Basis fields as columns.
    pub a: &'a DMatrix<f64>,
    /// Target field.
    pub t: &'a DVector<f64>,
    /// Row weights `d`; the fit minimises norms of `diag(d)(Aw − t)`.
    pub row_weights: Option<&'a DVector<f64>>,
}

impl<'a> FitProblem<'a> {
    /// Unweighted problem.
    #[cfg(test)]
    pub(crate) fn new(a: &'a DMatrix<f64>, t: &'a DVector<f64>) -> Self {
        Self {
            a,
            t,
            row_weights: None,
        }
    }
}

/// A verified solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitSolution {
    /// Time fractions `f` (length `m`, `f ≥ 0`, `Σf ≤ 1`); the plate rests
    /// for `1 − Σf`.  The achieved field is `A f ≈ strength · t`.
    pub fractions: Vec<f64>,
    /// Achieved strength `s`: 1 for `Absolute`, `L1`, `LInf`; `1/1ᵀw*` for
    /// `Shape` (0 when the target is unreachable); the maximal `s` for
    /// `Budget`.
    pub strength: f64,
    /// Objective in the caller's units: `‖D(Aw − t)‖₂²` for `Absolute` and
    /// `Shape` (with `w` the un-normalised minimiser `w*` for `Shape`), the
    /// strength `s` for `Budget`, `‖D(Aw − t)‖₁` for `L1`,
    /// `‖D(Aw − t)‖_∞` for `LInf`.
    pub objective: f64,
    /// Relative L2 error `‖D(Af − s t)‖₂ / ‖D s t‖₂` of the returned
    /// fractions (all modes; 1 when the target is unreachable in `Shape`).
    pub relative_error: f64,
    /// Clarabel's termination status (`"Solved"`, or `"AlmostSolved"` when
    /// the independent verification passed).
    pub status: String,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Clarabel's own solve time, seconds.
    pub solve_time_s: f64,
    /// Wall time of the whole fit (weighting, QR, solve, verification), s.
    pub total_time_s: f64,
    /// Verification residual (see `Verification::kkt_residual`).
    pub kkt_residual: f64,
    /// Gap to the independent solution (see
    /// `Verification::independent_gap`).
    pub independent_gap: f64,
    /// The best achievable fit is poor: relative error above
    /// `UNREACHABLE_REL_ERROR`, or (in `Shape`) no non-negative mix
    /// correlates positively with the target at all (then `fractions` are
    /// all zero and `strength` is 0).
    pub unreachable: bool,
    /// The interior-point weights were replaced by their active-set re-solve
    /// (least-squares modes only; see the module docs).
    pub active_set: bool,
    /// The interior-point (and re-solved) weights were worse than the
    /// independent Lawson–Hanson optimum by more than the tolerance and were
    /// replaced by it, which passed every check (least-squares modes only;
    /// see the module docs).
    pub independent_kept: bool,
}

/// Errors of the fitting module.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// Sizes of `A`, `t` and the row weights disagree.
    #[error("dimension mismatch: {what} has {got}, expected {expected}")]
    DimensionMismatch {
        /// Which input.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        got: usize,
    },
    /// Any other invalid input (non-finite data, negative weights, zero
    /// target, bad option).
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// Clarabel rejected the problem data or settings.
    #[error("clarabel setup failed in {mode} mode: {message}")]
    SolverSetup {
        /// Fit mode.
        mode: &'static str,
        /// Clarabel's message.
        message: String,
    },
    /// Clarabel terminated with a status other than `Solved` (and, for
    /// `AlmostSolved`, the independent verification failed too).
    #[error("clarabel returned status {status} in {mode} mode")]
    SolverStatus {
        /// Fit mode.
        mode: &'static str,
        /// Clarabel's status text.
        status: String,
    },
    /// An a-posteriori check of the solver's answer failed.
    #[error(
        "verification of the {mode} solution failed: {check} residual {residual:.3e} exceeds tolerance {tolerance:.3e} (solver status {status})"
    )]
    Verification {
        /// Fit mode.
        mode: &'static str,
        /// Which check failed (`"feasibility"`, `"kkt"`, `"independent"`).
        check: &'static str,
        /// The measured residual.
        residual: f64,
        /// The tolerance it had to meet.
        tolerance: f64,
        /// Clarabel's status for the rejected answer.
        status: String,
    },
    /// `Budget`: no strength `s > 0` meets the error budget.
    #[error(
        "error budget rel_error = {rel_error} cannot be met at any strength > 0: the best achievable relative error (shape fit) is {best_rel_error:.6}"
    )]
    BudgetInfeasible {
        /// The requested budget `ε`.
        rel_error: f64,
        /// The best relative L2 error any non-negative mix reaches.
        best_rel_error: f64,
    },
    /// The Lawson–Hanson iteration did not terminate.
    #[error("NNLS did not converge within {iterations} iterations")]
    NnlsNoConvergence {
        /// Iterations performed.
        iterations: usize,
    },
}

/// Solve the fit described by `options.mode` (see the module docs), verify
/// the answer, and return it.
///
/// With `options.max_primitives = Some(k)`, `k < m`, at most `k` columns
/// are used (best subset found by `subset`; the returned `fractions`
/// still have length `m`, with zeros outside the chosen subset).
///
/// # Errors
/// Invalid input, a Clarabel status other than `Solved` (`AlmostSolved` is
/// accepted only when verification passes), a failed verification, or an
/// infeasible `Budget`.
pub(crate) fn solve(problem: &FitProblem, options: &FitOptions) -> Result<FitSolution, FitError> {
    let start = std::time::Instant::now();
    validate_options(options)?;
    let prep = Prepared::new(problem)?;
    let m = prep.ncols();
    let mut sol = match options.max_primitives {
        Some(k) if k < m => {
            if k == 0 {
                return Err(FitError::InvalidInput(
                    "max_primitives must be at least 1".into(),
                ));
            }
            subset::solve_max_primitives(&prep, options, k)?
        }
        _ => solve_prepared(&prep, &options.mode, options.tolerance, options.formulation)?,
    };
    sol.total_time_s = start.elapsed().as_secs_f64();
    if options.verbose {
        crate::progress::say(&format!(
            "platefield::fit [{}] m={} rows={} status={} iters={} solve={:.3}ms total={:.3}ms rel_err={:.3e} strength={:.6} kkt={:.2e} gap={:.2e}{}",
            options.mode.name(),
            m,
            prep.nrows(),
            sol.status,
            sol.iterations,
            sol.solve_time_s * 1e3,
            sol.total_time_s * 1e3,
            sol.relative_error,
            sol.strength,
            sol.kkt_residual,
            sol.independent_gap,
            if sol.unreachable { " UNREACHABLE" } else { "" }
        ));
    }
    Ok(sol)
}

pub(crate) fn validate_options(options: &FitOptions) -> Result<(), FitError> {
    if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
        return Err(FitError::InvalidInput(format!(
            "tolerance must be finite and > 0, got {}",
            options.tolerance
        )));
    }
    validate_mode(&options.mode)
}

pub(crate) fn validate_mode(mode: &FitMode) -> Result<(), FitError> {
    if let FitMode::Budget { rel_error } = *mode {
        if !(rel_error > 0.0 && rel_error < 1.0) {
            return Err(FitError::InvalidInput(format!(
                "budget rel_error must lie in (0, 1), got {rel_error} (ε ≥ 1 makes the strength unbounded; ε = 0 leaves the cone without interior)"
            )));
        }
    }
    Ok(())
}

/// Solve on prepared (weighted, normalised, compressed) data using all its
/// columns, and verify.  Fractions have length `prep.ncols()`.
///
/// The steps: the independent reference ([`certify::Independent`]), the
/// conic solve ([`solve_conic`]), the raw weights cleaned onto the
/// constraints ([`cleaned_weights`]), the least-squares modes' active-set
/// active-set re-solve ([`active_set_weights`]), verification ([`verified`]), and the
/// reported quantities ([`reported`]).
pub(crate) fn solve_prepared(
    prep: &Prepared,
    mode: &FitMode,
    tol: f64,
    formulation: LsFormulation,
) -> Result<FitSolution, FitError> {
    let start = std::time::Instant::now();
    // Independent reference (also decides reachability / budget feasibility
    // exactly, before any interior-point answer is looked at).
    let independent = certify::Independent::compute(prep, mode, tol)?;
    let outcome = solve_conic(prep, mode, tol, formulation)?;
    let status = outcome.status.to_string();
    let w = cleaned_weights(prep, mode, tol, &outcome, &status)?;
    let (w, active_set) = active_set_weights(prep, mode, w, &outcome);
    let s_budget = match mode {
        FitMode::Budget { .. } => outcome.x[prep.ncols()].max(0.0),
        _ => 1.0,
    };
    let (w, check, independent_kept) =
        verified(prep, mode, w, s_budget, tol, &outcome, &independent)?;
    let r = reported(prep, mode, &w, s_budget, &check, independent.zero_optimal);
    Ok(FitSolution {
        fractions: r.fractions,
        strength: r.strength,
        objective: r.objective,
        relative_error: r.relative_error,
        status,
        iterations: outcome.iterations,
        solve_time_s: outcome.solve_time_s,
        total_time_s: start.elapsed().as_secs_f64(),
        kkt_residual: check.kkt_residual,
        independent_gap: check.independent_gap,
        unreachable: r.zero_solution || r.relative_error > UNREACHABLE_REL_ERROR,
        active_set,
        independent_kept,
    })
}

/// The conic program of `mode` solved by Clarabel; an error unless it is
/// solved or almost solved.
fn solve_conic(
    prep: &Prepared,
    mode: &FitMode,
    tol: f64,
    formulation: LsFormulation,
) -> Result<conic::ConicOutcome, FitError> {
    let outcome = match *mode {
        FitMode::Absolute | FitMode::Shape => {
            let cap = matches!(mode, FitMode::Absolute);
            conic::solve_ls(formulation, &prep.r, &prep.c, cap)?
        }
        FitMode::Budget { rel_error } => conic::solve_budget(&prep.r, &prep.c, prep.r0, rel_error)?,
        FitMode::L1 => lp::solve_lp_mode(prep, true, tol)?,
        FitMode::LInf => lp::solve_lp_mode(prep, false, tol)?,
    };
    let solved = outcome.status == clarabel::solver::SolverStatus::Solved;
    let almost = outcome.status == clarabel::solver::SolverStatus::AlmostSolved;
    if !(solved || almost) {
        return Err(FitError::SolverStatus {
            mode: mode.name(),
            status: outcome.status.to_string(),
        });
    }
    Ok(outcome)
}

/// The raw solver variables cleaned: an error if they violate w ≥ 0 or
/// Σw ≤ 1 by more than `tol`; else negatives clipped and the weights
/// rescaled onto Σw ≤ 1.
fn cleaned_weights(
    prep: &Prepared,
    mode: &FitMode,
    tol: f64,
    outcome: &conic::ConicOutcome,
    status: &str,
) -> Result<DVector<f64>, FitError> {
    let m = prep.ncols();
    let mut w = DVector::from_iterator(m, outcome.x[..m].iter().copied());
    let raw_min = w.min();
    let raw_sum = w.sum();
    if raw_min < -tol || (mode.has_sum_constraint() && raw_sum > 1.0 + tol) {
        return Err(FitError::Verification {
            mode: mode.name(),
            check: "feasibility",
            residual: (-raw_min).max(raw_sum - 1.0),
            tolerance: tol,
            status: status.to_string(),
        });
    }
    w.apply(|v| *v = v.max(0.0));
    if mode.has_sum_constraint() {
        let s = w.sum();
        if s > 1.0 {
            w /= s;
        }
    }
    Ok(w)
}

/// Active-set re-solve of the least-squares modes (see `active_set`): kept
/// only when feasible and not worse in the KKT residual. Returns the
/// weights and whether the re-solved ones were kept.
fn active_set_weights(
    prep: &Prepared,
    mode: &FitMode,
    w: DVector<f64>,
    outcome: &conic::ConicOutcome,
) -> (DVector<f64>, bool) {
    if !matches!(mode, FitMode::Absolute | FitMode::Shape) {
        return (w, false);
    }
    let Some(wp) = active_set::resolve_on_active_set(
        &prep.r,
        &prep.c,
        &prep.col_norms,
        &w,
        &outcome.bound_duals,
        outcome.sum_dual,
    ) else {
        return (w, false);
    };
    let cap = mode.has_sum_constraint();
    if certify::ls_kkt_residual(prep, &wp, cap) <= certify::ls_kkt_residual(prep, &w, cap) {
        (wp, true)
    } else {
        (w, false)
    }
}

/// The weights verified ([`certify::verify_prepared`]). The interior-point
/// answer worse than the independent optimum by more than the tolerance
/// (an ill-conditioned basis: its KKT residual can pass while its
/// objective is 1e-6 off) is replaced by the independent active-set
/// solution when that passes every check itself. Returns the weights, the
/// verification and whether the independent solution was kept; a failed
/// verification carries the solver's status.
fn verified(
    prep: &Prepared,
    mode: &FitMode,
    mut w: DVector<f64>,
    s_budget: f64,
    tol: f64,
    outcome: &conic::ConicOutcome,
    independent: &certify::Independent,
) -> Result<(DVector<f64>, Verification, bool), FitError> {
    let mut check =
        certify::verify_prepared(prep, mode, &w, s_budget, tol, Some(outcome), independent);
    let mut independent_kept = false;
    if let (
        Err(FitError::Verification {
            check: "independent",
            ..
        }),
        Some(wi),
    ) = (&check, &independent.weights)
    {
        if let Ok(c) =
            certify::verify_prepared(prep, mode, wi, s_budget, tol, Some(outcome), independent)
        {
            w = wi.clone();
            check = Ok(c);
            independent_kept = true;
        }
    }
    let status = outcome.status.to_string();
    let check = check.map_err(|e| match e {
        FitError::Verification {
            mode,
            check,
            residual,
            tolerance,
            ..
        } => FitError::Verification {
            mode,
            check,
            residual,
            tolerance,
            status,
        },
        other => other,
    })?;
    Ok((w, check, independent_kept))
}

/// What a fit reports, in the target's units.
struct Reported {
    fractions: Vec<f64>,
    strength: f64,
    objective: f64,
    relative_error: f64,
    zero_solution: bool,
}

/// The verified weights converted to the reported quantities: `Shape`'s
/// weights normalised to fractions with strength 1/Σw (the zero solution
/// when no field is achieved), the objective in the target's units.
fn reported(
    prep: &Prepared,
    mode: &FitMode,
    w: &DVector<f64>,
    s_budget: f64,
    check: &Verification,
    zero_optimal: bool,
) -> Reported {
    let direct = |strength: f64, objective: f64| Reported {
        fractions: w.iter().copied().collect(),
        strength,
        objective,
        relative_error: check.relative_error,
        zero_solution: false,
    };
    match *mode {
        FitMode::Shape => {
            let sum = w.sum();
            let achieved = (&prep.ad * w).norm();
            if sum.is_nan() || sum <= 0.0 || achieved <= certify::ZERO_FIELD_TOL || zero_optimal {
                Reported {
                    fractions: vec![0.0; prep.ncols()],
                    strength: 0.0,
                    objective: prep.tnorm * prep.tnorm,
                    relative_error: 1.0,
                    zero_solution: true,
                }
            } else {
                Reported {
                    fractions: w.iter().map(|v| v / sum).collect(),
                    strength: 1.0 / sum,
                    objective: check.objective * prep.tnorm * prep.tnorm,
                    relative_error: check.relative_error,
                    zero_solution: false,
                }
            }
        }
        FitMode::Absolute => direct(1.0, check.objective * prep.tnorm * prep.tnorm),
        FitMode::Budget { .. } => direct(s_budget, s_budget),
        FitMode::L1 | FitMode::LInf => direct(1.0, check.objective * prep.tnorm),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::nnls::{nnls, nnls_capped};
    use crate::fit::testutil::*;
    use nalgebra::{DMatrix, DVector};

    fn opts(mode: FitMode) -> FitOptions {
        FitOptions {
            mode,
            ..FitOptions::default()
        }
    }

    fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    }

    /// Random well-conditioned bases, target = A·w_true with w_true ≥ 0
    /// (one zero entry), Σw_true = 0.7: every mode returns status Solved and
    /// recovers w_true to 1e-6 (Shape: fractions w_true/Σ and strength 1/Σ;
    /// Budget with ε = 1e-8: fractions w_true/Σ, strength 1/Σ to 1e-6).
    /// One of the three seeds uses random row weights.
    #[test]
    fn every_mode_recovers_planted_weights() {
        for seed in [101u64, 202, 303] {
            let mut rng = SplitMix64::new(seed);
            let (rows, m) = (120, 7);
            let a = random_matrix(&mut rng, rows, m);
            let mut w_true = DVector::from_fn(m, |_, _| 0.2 + rng.uniform());
            w_true[3] = 0.0;
            w_true *= 0.7 / w_true.sum();
            let t = &a * &w_true;
            let d = DVector::from_fn(rows, |_, _| 0.5 + rng.uniform());
            let problem = FitProblem {
                a: &a,
                t: &t,
                row_weights: if seed == 202 { Some(&d) } else { None },
            };
            let wt: Vec<f64> = w_true.iter().copied().collect();
            let shape: Vec<f64> = wt.iter().map(|v| v / 0.7).collect();
            for mode in [
                FitMode::Absolute,
                FitMode::Shape,
                FitMode::Budget { rel_error: 1e-8 },
                FitMode::L1,
                FitMode::LInf,
            ] {
                let sol = solve(&problem, &opts(mode)).unwrap();
                assert_eq!(sol.status, "Solved", "{mode:?} seed {seed}");
                let (expect, strength) = match mode {
                    FitMode::Shape | FitMode::Budget { .. } => (&shape, 1.0 / 0.7),
                    _ => (&wt, 1.0),
                };
                let err = max_abs_diff(&sol.fractions, expect);
                assert!(err < 1e-6, "{mode:?} seed {seed}: weight error {err:.2e}");
                assert!(
                    (sol.strength - strength).abs() < 1e-6 * strength,
                    "{mode:?} seed {seed}: strength {} vs {strength}",
                    sol.strength
                );
                assert!(
                    sol.relative_error < 1e-6,
                    "{mode:?}: {}",
                    sol.relative_error
                );
                assert!(!sol.unreachable);
            }
        }
    }

    /// Basis on the 21×21 grid with two line sinks 0.1° apart, a duplicated
    /// point-sink column and three other fields.
    fn collinear_basis() -> (DMatrix<f64>, Vec<[f64; 2]>) {
        let pts = grid_points(21);
        let deg = std::f64::consts::PI / 180.0;
        let cols = vec![
            line_sink(&pts, 30.0 * deg),
            line_sink(&pts, 30.1 * deg),
            point_sink(&pts, [0.2, -0.1]),
            point_sink(&pts, [0.2, -0.1]), // exact duplicate of column 2
            uniform_field(&pts, [1.0, 0.0]),
            rotation_field(&pts, 1.0),
            line_sink(&pts, 100.0 * deg),
        ];
        (from_columns(&cols), pts)
    }

    /// Columns whose weights are unique (the duplicate pair 2/3 is compared
    /// through its sum).
    fn unique_parts(w: &[f64]) -> Vec<f64> {
        vec![w[0], w[1], w[2] + w[3], w[4], w[5], w[6]]
    }

    /// Nearly collinear basis (line sinks 0.1° apart + an exact duplicate
    /// column), both least-squares formulations: Absolute and Shape agree
    /// with the independent Lawson–Hanson
    /// solution — objective within 1e-8 relative, unique weights (and the
    /// sum of the duplicated pair) within 1e-6 — for an exactly reachable
    /// target, an unreachable-in-span target, and one where Σw ≤ 1 is
    /// active.
    #[test]
    fn collinear_basis_matches_nnls() {
        let (a, pts) = collinear_basis();
        let deg = std::f64::consts::PI / 180.0;
        let mut rng = SplitMix64::new(9);
        let exact = &a * DVector::from_vec(vec![0.3, 0.2, 0.05, 0.05, 0.1, 0.0, 0.15]);
        let off_span = line_sink(&pts, 30.05 * deg) * 0.5
            + rotation_field(&pts, 0.1)
            + DVector::from_fn(a.nrows(), |_, _| 0.02 * rng.symmetric());
        let too_strong = &exact * 1.6; // needs Σw = 1.36 > 1
        for (name, t) in [
            ("exact", exact),
            ("off_span", off_span),
            ("too_strong", too_strong),
        ] {
            let p = FitProblem::new(&a, &t);
            for (mode, formulation) in [
                (FitMode::Absolute, LsFormulation::ResidualQp),
                (FitMode::Shape, LsFormulation::ResidualQp),
                (FitMode::Absolute, LsFormulation::Epigraph),
                (FitMode::Shape, LsFormulation::Epigraph),
            ] {
                let sol = solve(
                    &p,
                    &FitOptions {
                        mode,
                        formulation,
                        ..FitOptions::default()
                    },
                )
                .unwrap();
                // Independent reference on the raw data.
                let w_ref = match mode {
                    FitMode::Absolute => nnls_capped(&a, &t, 1.0).unwrap(),
                    _ => nnls(&a, &t).unwrap(),
                };
                let obj_ref = (&a * &w_ref - &t).norm_squared();
                let w_sol: Vec<f64> = match mode {
                    FitMode::Shape => sol.fractions.iter().map(|f| f / sol.strength).collect(),
                    _ => sol.fractions.clone(),
                };
                let obj_sol = (&a * DVector::from_column_slice(&w_sol) - &t).norm_squared();
                let scale = t.norm_squared();
                assert!(
                    obj_sol - obj_ref <= 1e-8 * obj_ref.max(1e-8 * scale),
                    "{name} {mode:?}: objective {obj_sol:e} vs NNLS {obj_ref:e}"
                );
                assert!((sol.objective - obj_sol).abs() <= 1e-9 * scale);
                let ws: Vec<f64> = w_ref.iter().copied().collect();
                let err = max_abs_diff(&unique_parts(&w_sol), &unique_parts(&ws));
                assert!(err < 1e-6, "{name} {mode:?}: weight error {err:.2e}");
                if name == "too_strong" && mode == FitMode::Absolute {
                    let s: f64 = sol.fractions.iter().sum();
                    assert!(
                        (s - 1.0).abs() < 1e-9,
                        "sum constraint should be active: {s}"
                    );
                }
            }
        }
    }

    /// The pitfall: the normal-equations QP (P = AᵀA, default Clarabel
    /// settings, equilibration on) on the nearly collinear basis.  Its
    /// deviation from the planted weights is recorded (printed) for several
    /// data scalings, with and without equilibration (status `Solved`
    /// with weights far off at some scalings, with or without it).  The
    /// verifier must reject the naive answer whenever it is off by > 1e-4
    /// (and accept it otherwise), and the compressed-QR path must match the
    /// planted weights to 1e-6 on the same data.
    #[test]
    fn normal_equations_pitfall_vs_compressed_qr() {
        let (a0, _) = collinear_basis();
        // Drop the exact duplicate so the reference weights are unique.
        let a0 = a0.remove_column(3);
        let w_true = DVector::from_vec(vec![0.5, 0.0, 0.1, 0.05, 0.0, 0.2]);
        for scale in [1e-3, 1.0, 1e3] {
            let a = &a0 * scale;
            let t = &a * &w_true;
            let naive = conic::solve_normal_equations_qp(
                &a,
                &t,
                true,
                clarabel::solver::DefaultSettings {
                    verbose: false,
                    ..Default::default()
                },
            )
            .unwrap();
            let naive_err = (0..w_true.len())
                .map(|j| (naive.x[j] - w_true[j]).abs())
                .fold(0.0, f64::max);
            let naive_noeq = conic::solve_normal_equations_qp(
                &a,
                &t,
                true,
                clarabel::solver::DefaultSettings {
                    verbose: false,
                    equilibrate_enable: false,
                    ..Default::default()
                },
            )
            .unwrap();
            let noeq_err = (0..w_true.len())
                .map(|j| (naive_noeq.x[j] - w_true[j]).abs())
                .fold(0.0, f64::max);
            println!(
                "normal-equations QP, scale {scale:e}: equilibrated: status {:?}, max weight error {naive_err:.3e}; \
                 no equilibration: status {:?}, max weight error {noeq_err:.3e}",
                naive.status, naive_noeq.status
            );
            // Whatever the naive answer is, the verifier must judge it
            // correctly: rejected when it is off by more than 1e-4.
            let naive_w: Vec<f64> = naive.x.iter().map(|v| v.max(0.0)).collect();
            let verdict = verify(
                &FitProblem::new(&a, &t),
                &FitMode::Absolute,
                &naive_w,
                1.0,
                1e-6,
            );
            if naive_err > 1e-4 {
                assert!(
                    verdict.is_err(),
                    "verifier accepted a naive answer off by {naive_err:e}"
                );
            } else {
                assert!(verdict.is_ok(), "{verdict:?}");
            }
            let sol = solve(&FitProblem::new(&a, &t), &opts(FitMode::Absolute)).unwrap();
            let err = max_abs_diff(&sol.fractions, w_true.as_slice());
            assert_eq!(sol.status, "Solved");
            assert!(
                err < 1e-6,
                "compressed QR path, scale {scale:e}: error {err:.2e}"
            );
        }
    }

    /// The two conic forms of the compressed least-squares problem on a
    /// random 6×6 Absolute problem whose optimum has a non-zero residual and
    /// an active sum constraint: the residual-variable QP (default) matches
    /// the Lawson–Hanson weights to 1e-9; the SOC epigraph's error is
    /// recorded (printed; of order √tol).
    #[test]
    fn residual_qp_is_more_accurate_than_epigraph() {
        let mut rng = SplitMix64::new(613355);
        let a = random_matrix(&mut rng, 6, 6);
        let t = random_vector(&mut rng, 6);
        let prep = prepare::Prepared::new(&FitProblem::new(&a, &t)).unwrap();
        let w_ref = nnls_capped(&prep.r, &prep.c, 1.0).unwrap();
        let err = |x: &[f64]| (0..6).map(|j| (x[j] - w_ref[j]).abs()).fold(0.0, f64::max);
        let qp = conic::solve_ls(LsFormulation::ResidualQp, &prep.r, &prep.c, true).unwrap();
        let epi = conic::solve_ls(LsFormulation::Epigraph, &prep.r, &prep.c, true).unwrap();
        println!(
            "residual QP: {:?} {} it, weight error {:.2e}; epigraph: {:?} {} it, weight error {:.2e}",
            qp.status,
            qp.iterations,
            err(&qp.x),
            epi.status,
            epi.iterations,
            err(&epi.x)
        );
        assert_eq!(qp.status, clarabel::solver::SolverStatus::Solved);
        assert!(err(&qp.x) < 1e-9, "{}", err(&qp.x));
        assert!(
            (w_ref.sum() - 1.0).abs() < 1e-12,
            "sum constraint should be active"
        );
    }

    /// Budget with orthonormal basis columns and t = A·w_true: the optimum
    /// is analytic, s* = 1/(Σw_true − √m·ε·‖w_true‖), w* = s*·w_true − δ1
    /// with δ = (s*Σw_true − 1)/m.  Strength to 1e-7 relative, weights to
    /// 1e-6; the same with random positive row weights applied to a
    /// D-orthonormal basis.
    #[test]
    fn budget_matches_analytic_strength() {
        let mut rng = SplitMix64::new(31);
        let (rows, m) = (60, 5);
        let q = random_matrix(&mut rng, rows, m).qr().q();
        let w_true = DVector::from_vec(vec![0.24, 0.2, 0.16, 0.12, 0.08]);
        let eps = 0.05;
        let sum: f64 = w_true.sum();
        let s_star = 1.0 / (sum - (m as f64).sqrt() * eps * w_true.norm());
        let delta = (s_star * sum - 1.0) / m as f64;
        let w_star: Vec<f64> = w_true.iter().map(|v| s_star * v - delta).collect();
        assert!(w_star.iter().all(|&v| v > 0.0));
        // Unweighted, and weighted with A = D⁻¹Q so that DA is orthonormal.
        let d = DVector::from_fn(rows, |_, _| 0.5 + rng.uniform());
        let a_w = DMatrix::from_fn(rows, m, |i, j| q[(i, j)] / d[i]);
        for (a, weights) in [(q.clone(), None), (a_w, Some(&d))] {
            let t = &a * &w_true;
            let p = FitProblem {
                a: &a,
                t: &t,
                row_weights: weights,
            };
            let sol = solve(&p, &opts(FitMode::Budget { rel_error: eps })).unwrap();
            assert!(
                (sol.strength - s_star).abs() < 1e-7 * s_star,
                "strength {} vs analytic {s_star}",
                sol.strength
            );
            assert!(max_abs_diff(&sol.fractions, &w_star) < 1e-6);
            assert!((sol.relative_error - eps).abs() < 1e-6);
            assert!(sol.independent_gap.abs() < 1e-7);
        }
    }

    /// Budget that no strength can meet: the target has 30% of its norm
    /// outside the span, so the best shape error is 0.3 > ε = 0.1: a typed
    /// error naming the budget and the best achievable error (0.3 to 1e-9).
    #[test]
    fn budget_infeasible_is_reported() {
        let mut rng = SplitMix64::new(32);
        let (rows, m) = (40, 4);
        let qfull = random_matrix(&mut rng, rows, m + 1).qr().q();
        let a = qfull.columns(0, m).into_owned();
        let inside = &a * DVector::from_vec(vec![0.4, 0.3, 0.2, 0.1]);
        let t = &inside / inside.norm() * 0.91f64.sqrt() + qfull.column(m) * 0.3;
        let err = solve(
            &FitProblem::new(&a, &t),
            &opts(FitMode::Budget { rel_error: 0.1 }),
        )
        .unwrap_err();
        match &err {
            FitError::BudgetInfeasible {
                rel_error,
                best_rel_error,
            } => {
                assert_eq!(*rel_error, 0.1);
                assert!((best_rel_error - 0.3).abs() < 1e-9, "{best_rel_error}");
            }
            other => panic!("expected BudgetInfeasible, got {other:?}"),
        }
        assert!(err.to_string().contains("rel_error = 0.1"));
        // Invalid budgets are rejected up front.
        for bad in [0.0, 1.0, -0.5, f64::NAN] {
            assert!(matches!(
                solve(
                    &FitProblem::new(&a, &t),
                    &opts(FitMode::Budget { rel_error: bad })
                ),
                Err(FitError::InvalidInput(_))
            ));
        }
    }

    /// L1 / L∞ against exact answers: one column of ones, t = (0, 0.5, 0.6):
    /// L1 optimum is the median (w = 0.5, objective 0.6), L∞ the mid-range
    /// (w = 0.3, objective 0.3); with t = (0, 3, 4) both hit the cap w = 1.
    #[test]
    fn l1_linf_exact_one_column() {
        let a = DMatrix::from_element(3, 1, 1.0);
        let cases = [
            (vec![0.0, 0.5, 0.6], 0.5, 0.6, 0.3, 0.3),
            (vec![0.0, 3.0, 4.0], 1.0, 1.0 + 2.0 + 3.0, 1.0, 3.0),
        ];
        for (tv, w1, o1, winf, oinf) in cases {
            let t = DVector::from_vec(tv);
            let p = FitProblem::new(&a, &t);
            let s1 = solve(&p, &opts(FitMode::L1)).unwrap();
            assert!((s1.fractions[0] - w1).abs() < 1e-7, "{}", s1.fractions[0]);
            assert!((s1.objective - o1).abs() < 1e-7);
            let si = solve(&p, &opts(FitMode::LInf)).unwrap();
            assert!((si.fractions[0] - winf).abs() < 1e-7, "{}", si.fractions[0]);
            assert!((si.objective - oinf).abs() < 1e-7);
        }
    }

    /// L1 / L∞ with two random columns against a brute-force grid over the
    /// triangle {w ≥ 0, w₁ + w₂ ≤ 1} (step 1/600): the solver's objective is
    /// never above the grid minimum (+1e-9) and within the grid's
    /// resolution of it.
    #[test]
    fn l1_linf_match_brute_force_grid() {
        let mut rng = SplitMix64::new(41);
        let a = random_matrix(&mut rng, 10, 2);
        let t = &a * DVector::from_vec(vec![0.5, 0.3]) + random_vector(&mut rng, 10) * 0.2;
        let p = FitProblem::new(&a, &t);
        let lip = a.column(0).lp_norm(1).max(a.column(1).lp_norm(1));
        for mode in [FitMode::L1, FitMode::LInf] {
            let sol = solve(&p, &opts(mode)).unwrap();
            let f = |w: &DVector<f64>| {
                let r = &a * w - &t;
                if mode == FitMode::L1 {
                    r.lp_norm(1)
                } else {
                    r.amax()
                }
            };
            let n = 600;
            let mut best = f64::INFINITY;
            for i in 0..=n {
                for k in 0..=(n - i) {
                    best = best.min(f(&DVector::from_vec(vec![
                        i as f64 / n as f64,
                        k as f64 / n as f64,
                    ])));
                }
            }
            assert!(
                sol.objective <= best + 1e-9,
                "{mode:?}: {} > {best}",
                sol.objective
            );
            assert!(best - sol.objective <= lip / n as f64, "{mode:?}");
            assert!((f(&DVector::from_column_slice(&sol.fractions)) - sol.objective).abs() < 1e-12);
        }
    }

    /// Targets no non-negative mix of line sinks can produce: a line source
    /// (negatively correlated with every column) and a rotation (orthogonal
    /// to every column).  Shape flags unreachable with zero fractions,
    /// strength 0 and relative error 1; Absolute returns w ≈ 0 (Σw < 1e-8)
    /// with relative error 1 ± 1e-8, flagged; L1/L∞ (whose optimum need not
    /// be w = 0) are flagged with relative error > 0.5; Budget reports
    /// BudgetInfeasible.  No panics.
    #[test]
    fn unreachable_target_is_flagged() {
        let pts = grid_points(21);
        let deg = std::f64::consts::PI / 180.0;
        let a = from_columns(&[
            line_sink(&pts, 0.0),
            line_sink(&pts, 45.0 * deg),
            line_sink(&pts, 90.0 * deg),
        ]);
        let source = -line_sink(&pts, 20.0 * deg);
        let rotation = rotation_field(&pts, 1.0);
        for t in [source, rotation] {
            let p = FitProblem::new(&a, &t);
            let shape = solve(&p, &opts(FitMode::Shape)).unwrap();
            assert!(shape.unreachable);
            assert_eq!(shape.strength, 0.0);
            assert!(shape.fractions.iter().all(|&f| f == 0.0));
            assert_eq!(shape.relative_error, 1.0);
            let abs = solve(&p, &opts(FitMode::Absolute)).unwrap();
            assert!(abs.unreachable);
            assert!(abs.fractions.iter().sum::<f64>() < 1e-8);
            assert!((abs.relative_error - 1.0).abs() < 1e-8);
            for mode in [FitMode::L1, FitMode::LInf] {
                let sol = solve(&p, &opts(mode)).unwrap();
                assert!(sol.unreachable, "{mode:?}");
                assert!(sol.relative_error > UNREACHABLE_REL_ERROR, "{mode:?}");
            }
            assert!(matches!(
                solve(&p, &opts(FitMode::Budget { rel_error: 0.5 })),
                Err(FitError::BudgetInfeasible { .. })
            ));
        }
    }

    /// Identical input gives bit-identical output (timings excluded).
    #[test]
    fn solve_is_deterministic() {
        let mut rng = SplitMix64::new(55);
        let a = plate_like_basis(&mut rng, 11, 20);
        let t = &a * DVector::from_fn(20, |i, _| if i % 3 == 0 { 0.05 } else { 0.0 })
            + random_vector(&mut rng, a.nrows()) * 0.05;
        let p = FitProblem::new(&a, &t);
        for mode in [
            FitMode::Shape,
            FitMode::Budget { rel_error: 0.3 },
            FitMode::L1,
        ] {
            let s1 = solve(&p, &opts(mode)).unwrap();
            let s2 = solve(&p, &opts(mode)).unwrap();
            let bits = |s: &FitSolution| {
                let mut v: Vec<u64> = s.fractions.iter().map(|f| f.to_bits()).collect();
                v.extend(
                    [s.strength, s.objective, s.relative_error, s.kkt_residual].map(f64::to_bits),
                );
                v
            };
            assert_eq!(bits(&s1), bits(&s2), "{mode:?}");
            assert_eq!(s1.iterations, s2.iterations);
        }
    }

    /// max_primitives = 2 on a target made of 2 of 30 columns: at most 2
    /// non-zero fractions and relative error below 1e-6.
    #[test]
    fn max_primitives_limits_support() {
        let mut rng = SplitMix64::new(61);
        let a = plate_like_basis(&mut rng, 11, 30);
        let t = a.column(4) * 0.3 + a.column(17) * 0.5;
        let p = FitProblem::new(&a, &t);
        for mode in [FitMode::Absolute, FitMode::Shape] {
            let sol = solve(
                &p,
                &FitOptions {
                    mode,
                    max_primitives: Some(2),
                    ..FitOptions::default()
                },
            )
            .unwrap();
            let nz: Vec<usize> = (0..30).filter(|&j| sol.fractions[j] != 0.0).collect();
            assert!(nz.len() <= 2, "{mode:?}: {nz:?}");
            assert!(
                sol.relative_error < 1e-6,
                "{mode:?}: {}",
                sol.relative_error
            );
        }
        let sol = solve(
            &p,
            &FitOptions {
                mode: FitMode::Absolute,
                max_primitives: Some(1),
                ..FitOptions::default()
            },
        )
        .unwrap();
        assert!(sol.fractions.iter().filter(|&&f| f != 0.0).count() <= 1);
    }

    /// Timing for the reference size m = 100, n = 441 points (882 rows);
    /// prints Clarabel's and the total time per mode, asserts only a
    /// generous bound (5 s per fit) so that the test is about gross
    /// regressions.
    #[test]
    fn timing_m100_n441() {
        let mut rng = SplitMix64::new(77);
        let a = plate_like_basis(&mut rng, 21, 100);
        let w = DVector::from_fn(100, |i, _| if i % 7 == 0 { 0.04 } else { 0.0 });
        let t = &a * w + random_vector(&mut rng, a.nrows()) * 0.1;
        let p = FitProblem::new(&a, &t);
        for mode in [
            FitMode::Absolute,
            FitMode::Shape,
            FitMode::Budget { rel_error: 0.45 },
            FitMode::L1,
            FitMode::LInf,
        ] {
            let sol = solve(
                &p,
                &FitOptions {
                    mode,
                    verbose: true,
                    ..FitOptions::default()
                },
            )
            .unwrap();
            println!(
                "timing m=100 n=441 {:>8}: clarabel {:7.2} ms, total {:7.2} ms, {} iterations, rel err {:.4}",
                mode.name(),
                sol.solve_time_s * 1e3,
                sol.total_time_s * 1e3,
                sol.iterations,
                sol.relative_error
            );
            assert!(sol.total_time_s < 5.0);
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
        /// Property: for random small problems, Absolute and Shape objectives
        /// never exceed the Lawson–Hanson reference by more than 1e-8
        /// (relative to ‖t‖²) and verification passes.
        #[test]
        fn prop_ls_modes_match_nnls(seed in 0u64..1_000_000, rows in 4usize..40, m in 1usize..8) {
            let mut rng = SplitMix64::new(seed);
            let a = random_matrix(&mut rng, rows, m);
            let t = random_vector(&mut rng, rows);
            let p = FitProblem::new(&a, &t);
            for mode in [FitMode::Absolute, FitMode::Shape] {
                let sol = solve(&p, &opts(mode)).unwrap();
                let w_ref = if mode == FitMode::Absolute {
                    nnls_capped(&a, &t, 1.0).unwrap()
                } else {
                    nnls(&a, &t).unwrap()
                };
                let obj_ref = (&a * &w_ref - &t).norm_squared();
                let scale = t.norm_squared();
                if mode == FitMode::Shape && sol.unreachable && sol.strength == 0.0 {
                    proptest::prop_assert!(w_ref.iter().all(|&v| v == 0.0));
                } else {
                    proptest::prop_assert!(sol.objective <= obj_ref + 1e-8 * scale,
                        "{:?}: {} vs {}", mode, sol.objective, obj_ref);
                }
            }
        }
    }
}
