//! Conic formulations of the fit modes, solved with Clarabel.
//!
//! Clarabel solves
//!
//! ```text
//! min ½xᵀPx + qᵀx   s.t.  Ax + s = b,  s ∈ K,
//! ```
//!
//! with dual `z ∈ K*` and stationarity `Px + q + Aᵀz = 0`.  `K` is a
//! product of `ZeroConeT` (`s = 0`), `NonnegativeConeT` (`s ≥ 0`) and
//! `SecondOrderConeT` (`𝒬^p = {(s₀, s̄) : ‖s̄‖₂ ≤ s₀}`).
//!
//! The data passed in are already weighted and normalised (`‖t̂‖ = 1`, see
//! [`crate::fit::prepare`]), and for the least-squares modes compressed:
//! `‖Âw − s t̂‖² = ‖Rw − s c‖² + s² r₀²`.  The normal-equations matrix
//! `ÂᵀÂ` is never formed.
//!
//! | mode | function | form |
//! |------|----------|------|
//! | `Absolute`, `Shape` | [`solve_ls`] with [`ls_residual_qp`] (default) | QP, zero + non-negative cones |
//! | `Absolute`, `Shape` | [`solve_ls`] with [`ls_epigraph`] ([`LsFormulation::Epigraph`]) | SOCP |
//! | `Budget` | [`solve_budget`] | SOCP |
//! | `L1`, `LInf` | [`solve_l1_linear`], [`solve_linf`] | LP, zero + non-negative cones |
//!
//! # Settings
//!
//! [`fit_settings`]: `verbose = false`, `max_iter = 200`, gap and
//! feasibility tolerances per form ([`TOL_TIGHT`] = 1e-10 for the residual
//! QP and the LPs, [`TOL_BUDGET`] = 1e-9, [`TOL_EPIGRAPH`] = 1e-8; chosen
//! from 40 random problems per mode so that Clarabel ends `Solved` rather
//! than `AlmostSolved`), everything else Clarabel's default: QDLDL direct
//! solver, single-threaded, hence bit-for-bit deterministic.
//!
//! Equilibration is left **enabled**.  The failure of the normal-equations
//! QP `P = AᵀA` (ending `Solved` with weights far off on line sinks 0.1°
//! apart) reproduces with equilibration switched off too (the regression
//! test below prints both), so equilibration is not the cause: the
//! squared condition number and the absolute gap tolerance on an unscaled
//! objective are.  Both are removed here by the QR compression and the
//! normalisation `‖t̂‖ = 1`; see the regression test
//! `normal_equations_pitfall_vs_compressed_qr`.
//!
//! Interior-point weights of the least-squares modes are accurate only to
//! about the square root of the gap tolerance where the objective is flat
//! (the test `residual_qp_is_more_accurate_than_epigraph` prints the
//! epigraph form's); [`crate::fit::solve`]
//! therefore re-solves them on the identified active set before verifying.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
    SupportedConeT::{NonnegativeConeT, SecondOrderConeT, ZeroConeT},
};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::fit::FitError;

/// What an interior-point solve returned.
#[derive(Debug, Clone)]
pub(crate) struct ConicOutcome {
    /// Primal solution.
    pub x: Vec<f64>,
    /// Dual solution (in the dual cone).
    pub z: Vec<f64>,
    /// Termination status.
    pub status: SolverStatus,
    /// Iterations.
    pub iterations: u32,
    /// Clarabel's solve time in seconds.
    pub solve_time_s: f64,
    /// Primal objective as reported by Clarabel (normalised units).
    pub obj_val: f64,
    /// Least-squares modes: duals of the rows `wⱼ ≥ 0` (empty otherwise).
    pub bound_duals: Vec<f64>,
    /// Least-squares modes with the cap: dual of `1ᵀw ≤ 1`.
    pub sum_dual: Option<f64>,
    /// `L1`/`LInf`: the dual certificate `y = z₁ − z₂` (length `M`).
    pub lp_dual: Vec<f64>,
}

/// How the compressed least-squares modes (`Absolute`, `Shape`) are posed
/// to Clarabel.  Both work on the QR-compressed `R` (never on `AᵀA`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum LsFormulation {
    /// Residual variables with a zero cone and a quadratic objective
    /// (see `ls_residual_qp`).  Default: weight errors near round-off at
    /// the tolerances of `fit_settings`.
    #[default]
    ResidualQp,
    /// Second-order-cone epigraph `min τ, ‖Rw − c‖ ≤ τ` (see
    /// `ls_epigraph`).  Weight errors ~√tol
    /// whenever the optimal residual is non-zero, which can fail the 1e-6
    /// KKT verification; kept for comparison.
    Epigraph,
}

/// Gap/feasibility tolerance for the residual-QP least-squares form and
/// the LPs (every problem of the tests ends `Solved` at it, for an
/// iteration or two more than at 1e-8).
pub(crate) const TOL_TIGHT: f64 = 1e-10;
/// Tolerance for the `Budget` SOCP (at 1e-10, 6 of 40 random budget
/// problems ended `AlmostSolved`; at 1e-9 none did).
pub(crate) const TOL_BUDGET: f64 = 1e-9;
/// Tolerance for the epigraph least-squares form (at 1e-10 it often ends
/// `AlmostSolved`; the active-set re-solve supplies the accuracy anyway).
pub(crate) const TOL_EPIGRAPH: f64 = 1e-8;

/// Clarabel settings used for every fit, with gap/feasibility tolerance
/// `tol` (see module docs for the choices).
pub(crate) fn fit_settings(tol: f64) -> DefaultSettings<f64> {
    DefaultSettings {
        verbose: false,
        max_iter: 200,
        tol_gap_abs: tol,
        tol_gap_rel: tol,
        tol_feas: tol,
        equilibrate_enable: true,
        ..DefaultSettings::default()
    }
}

/// Sparse constraint matrix assembled row by row, with its cones (also
/// the stacked worst-case fit's, [`crate::fit::worst`]).
pub(crate) struct ConeBuilder {
    ncols: usize,
    nrows: usize,
    ri: Vec<usize>,
    ci: Vec<usize>,
    vals: Vec<f64>,
    b: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
}

impl ConeBuilder {
    pub(crate) fn new(ncols: usize) -> Self {
        Self {
            ncols,
            nrows: 0,
            ri: Vec::new(),
            ci: Vec::new(),
            vals: Vec::new(),
            b: Vec::new(),
            cones: Vec::new(),
        }
    }

    /// Add one row `Σ vals·x[cols] + s = b`; exact zeros are skipped.
    pub(crate) fn row(&mut self, entries: impl IntoIterator<Item = (usize, f64)>, b: f64) {
        for (j, v) in entries {
            if v != 0.0 {
                self.ri.push(self.nrows);
                self.ci.push(j);
                self.vals.push(v);
            }
        }
        self.b.push(b);
        self.nrows += 1;
    }

    /// Rows of the feasible set of time fractions, w ≥ 0 and (with
    /// `sum_cap`) Σw ≤ 1, over the first `m` variables; returns how many
    /// rows were added (the caller closes them with a non-negative cone).
    fn feasible_fractions(&mut self, m: usize, sum_cap: bool) -> usize {
        for j in 0..m {
            self.row([(j, -1.0)], 0.0);
        }
        if sum_cap {
            self.row((0..m).map(|j| (j, 1.0)), 1.0);
        }
        m + usize::from(sum_cap)
    }

    pub(crate) fn cone(&mut self, cone: SupportedConeT<f64>) {
        self.cones.push(cone);
    }

    /// Solves the linear program min qᵀx over the rows and cones built
    /// (`mode` names the fit in a set-up error).
    pub(crate) fn solve(
        self,
        q: Vec<f64>,
        tol: f64,
        mode: &'static str,
    ) -> Result<ConicOutcome, FitError> {
        let p = CscMatrix::zeros((self.ncols, self.ncols));
        self.solve_with(&p, q, tol, mode)
    }

    /// [`ConeBuilder::solve`] with the quadratic term ½xᵀPx.
    fn solve_with(
        self,
        p: &CscMatrix<f64>,
        q: Vec<f64>,
        tol: f64,
        mode: &'static str,
    ) -> Result<ConicOutcome, FitError> {
        let a = CscMatrix::new_from_triplets(self.nrows, self.ncols, self.ri, self.ci, self.vals);
        run(p, &q, &a, &self.b, &self.cones, fit_settings(tol), mode)
    }
}

fn run(
    p: &CscMatrix<f64>,
    q: &[f64],
    a: &CscMatrix<f64>,
    b: &[f64],
    cones: &[SupportedConeT<f64>],
    settings: DefaultSettings<f64>,
    mode: &'static str,
) -> Result<ConicOutcome, FitError> {
    let mut solver =
        DefaultSolver::new(p, q, a, b, cones, settings).map_err(|e| FitError::SolverSetup {
            mode,
            message: e.to_string(),
        })?;
    solver.solve();
    let sol = &solver.solution;
    Ok(ConicOutcome {
        x: sol.x.clone(),
        z: sol.z.clone(),
        status: sol.status,
        iterations: sol.iterations,
        solve_time_s: sol.solve_time,
        obj_val: sol.obj_val,
        bound_duals: Vec::new(),
        sum_dual: None,
        lp_dual: Vec::new(),
    })
}

/// Compressed least-squares fit (modes `Absolute` with `sum_cap`, `Shape`
/// without): min ‖Rw − c‖ over the time fractions w ≥ 0 [, 1ᵀw ≤ 1 if
/// `sum_cap`], posed as `form` ([`ls_residual_qp`] or [`ls_epigraph`]).
/// The outcome carries the duals of `w ≥ 0` and of the cap.
pub(crate) fn solve_ls(
    form: LsFormulation,
    r: &DMatrix<f64>,
    c: &DVector<f64>,
    sum_cap: bool,
) -> Result<ConicOutcome, FitError> {
    let LsForm { mut bld, p, q, tol } = match form {
        LsFormulation::ResidualQp => ls_residual_qp(r, c),
        LsFormulation::Epigraph => ls_epigraph(r, c),
    };
    let m = r.ncols();
    let first = bld.nrows;
    let rows = bld.feasible_fractions(m, sum_cap);
    bld.cone(NonnegativeConeT(rows));
    let out = bld.solve_with(&p, q, tol, if sum_cap { "absolute" } else { "shape" })?;
    Ok(with_ls_duals(out, first, m, sum_cap))
}

/// One posing of the compressed least-squares fit: its rows before those
/// of the feasible set of time fractions, its objective ½xᵀPx + qᵀx and
/// its tolerance.
struct LsForm {
    bld: ConeBuilder,
    p: CscMatrix<f64>,
    q: Vec<f64>,
    tol: f64,
}

/// Residual variables (the default).
///
/// Variables `x = (w, y) ∈ ℝ^{m+k}`, `P = diag(0_m, I_k)`, `q = 0`:
///
/// ```text
/// min ½‖y‖²   s.t.  Rw − y = c  (zero cone),  w ≥ 0,  [1ᵀw ≤ 1 if sum_cap]
/// ```
///
/// so `y* = Rw* − c` and the full squared residual is `‖y*‖² + r₀²`.  The
/// Hessian is the identity on `y` and `R` enters only the constraints, so
/// the KKT systems Clarabel factors have the conditioning of `R` (that of
/// `DA`), not of `RᵀR = AᵀD²A`.  Unlike the epigraph form, the objective is
/// smooth and strongly convex in `y`, and the interior-point iterates
/// converge to the weights at the rate of the duality gap rather than its
/// square root (see [`LsFormulation`]).
fn ls_residual_qp(r: &DMatrix<f64>, c: &DVector<f64>) -> LsForm {
    let (k, m) = r.shape();
    let mut bld = ConeBuilder::new(m + k);
    for i in 0..k {
        bld.row((0..m).map(|j| (j, r[(i, j)])).chain([(m + i, -1.0)]), c[i]);
    }
    bld.cone(ZeroConeT(k));
    let p = CscMatrix::new_from_triplets(
        m + k,
        m + k,
        (m..m + k).collect(),
        (m..m + k).collect(),
        vec![1.0; k],
    );
    let q = vec![0.0; m + k];
    LsForm {
        bld,
        p,
        q,
        tol: TOL_TIGHT,
    }
}

/// Attach the duals of `w ≥ 0` (rows `first..first+m`) and of the cap.
fn with_ls_duals(mut out: ConicOutcome, first: usize, m: usize, sum_cap: bool) -> ConicOutcome {
    if out.z.len() >= first + m + usize::from(sum_cap) {
        out.bound_duals = out.z[first..first + m].to_vec();
        out.sum_dual = sum_cap.then(|| out.z[first + m]);
    }
    out
}

/// Epigraph form (alternative, see [`LsFormulation::Epigraph`]).
///
/// Variables `x = (w, τ) ∈ ℝ^{m+1}`:
///
/// ```text
/// min τ   s.t.  (τ, c − Rw) ∈ 𝒬^{k+1},   w ≥ 0,   [1ᵀw ≤ 1 if sum_cap]
/// ```
///
/// so `τ* = min ‖Rw − c‖₂` and the full residual is `√(τ*² + r₀²)`.  With
/// `sum_cap` this is mode `Absolute` (minimising the norm or its square has
/// the same minimiser), without it mode `Shape`.
fn ls_epigraph(r: &DMatrix<f64>, c: &DVector<f64>) -> LsForm {
    let (k, m) = r.shape();
    let mut bld = ConeBuilder::new(m + 1);
    bld.row([(m, -1.0)], 0.0);
    for i in 0..k {
        bld.row((0..m).map(|j| (j, r[(i, j)])), c[i]);
    }
    bld.cone(SecondOrderConeT(k + 1));
    let mut q = vec![0.0; m + 1];
    q[m] = 1.0;
    let p = CscMatrix::zeros((m + 1, m + 1));
    LsForm {
        bld,
        p,
        q,
        tol: TOL_EPIGRAPH,
    }
}

/// Error-budget fit: variables `x = (w, s) ∈ ℝ^{m+1}`,
///
/// ```text
/// max s   s.t.  (ε s, s c − Rw, r₀ s) ∈ 𝒬^{k+2},  w ≥ 0,  s ≥ 0,  1ᵀw ≤ 1,
/// ```
///
/// i.e. `‖Âw − s t̂‖₂ = √(‖Rw − s c‖² + s²r₀²) ≤ ε s` with `‖t̂‖ = 1`.
pub(crate) fn solve_budget(
    r: &DMatrix<f64>,
    c: &DVector<f64>,
    r0: f64,
    eps: f64,
) -> Result<ConicOutcome, FitError> {
    let (k, m) = r.shape();
    let mut bld = ConeBuilder::new(m + 1);
    bld.row([(m, -eps)], 0.0);
    for i in 0..k {
        bld.row((0..m).map(|j| (j, r[(i, j)])).chain([(m, -c[i])]), 0.0);
    }
    bld.row([(m, -r0)], 0.0);
    bld.cone(SecondOrderConeT(k + 2));
    for j in 0..=m {
        bld.row([(j, -1.0)], 0.0);
    }
    bld.row((0..m).map(|j| (j, 1.0)), 1.0);
    bld.cone(NonnegativeConeT(m + 2));
    let mut q = vec![0.0; m + 1];
    q[m] = -1.0;
    bld.solve(q, TOL_BUDGET, "budget")
}

/// L1 fit as a linear program: variables `x = (w, r, u) ∈ ℝ^{m+2M}`,
///
/// ```text
/// min 1ᵀu   s.t.  Âw − r = t̂ (zero cone),  r − u ≤ 0,  −r − u ≤ 0,
///                 w ≥ 0,  1ᵀw ≤ 1.
/// ```
///
/// The explicit residual `r` means `Â` appears in `M` rows only (not `2M`),
/// which is several times faster than `−u ≤ Âw − t̂ ≤ u`.  With `z₁, z₂ ≥ 0` the
/// duals of the two bound blocks, stationarity in `u` gives `z₁ + z₂ = 1`,
/// so `y = z₁ − z₂ ∈ [−1, 1]^M` (stored in [`ConicOutcome::lp_dual`])
/// certifies optimality (see [`mod@crate::fit::certify`]).
///
/// With an extra linear term `gᵀw` in the objective (`min gᵀw + 1ᵀu`, same
/// constraints; `g` empty: none): the L1 fit in which the residual rows of
/// known sign are aggregated into `g` (see [`crate::fit::lp`]).  The dual
/// certificate of the rows passed is in [`ConicOutcome::lp_dual`].
pub(crate) fn solve_l1_linear(
    ad: &DMatrix<f64>,
    td: &DVector<f64>,
    g: &[f64],
) -> Result<ConicOutcome, FitError> {
    solve_lp(ad, td, true, g)
}

/// L∞ fit as a linear program: variables `x = (w, r, τ) ∈ ℝ^{m+M+1}`,
///
/// ```text
/// min τ   s.t.  Âw − r = t̂ (zero cone),  r − τ1 ≤ 0,  −r − τ1 ≤ 0,
///               w ≥ 0,  1ᵀw ≤ 1.
/// ```
///
/// At stationarity `1ᵀ(z₁ + z₂) = 1`, so `y = z₁ − z₂` has `‖y‖₁ ≤ 1`.
pub(crate) fn solve_linf(ad: &DMatrix<f64>, td: &DVector<f64>) -> Result<ConicOutcome, FitError> {
    solve_lp(ad, td, false, &[])
}

/// The L1 / L∞ LP; `g` (empty, or one entry per column) is added to the
/// objective as `gᵀw`.
fn solve_lp(
    ad: &DMatrix<f64>,
    td: &DVector<f64>,
    l1: bool,
    g: &[f64],
) -> Result<ConicOutcome, FitError> {
    let (mr, m) = ad.shape();
    // Column of the bound variable for row i.
    let nb = if l1 { mr } else { 1 };
    let bound_col = |i: usize| if l1 { m + mr + i } else { m + mr };
    let mut bld = ConeBuilder::new(m + mr + nb);
    for i in 0..mr {
        bld.row(
            (0..m).map(|j| (j, ad[(i, j)])).chain([(m + i, -1.0)]),
            td[i],
        );
    }
    bld.cone(ZeroConeT(mr));
    for i in 0..mr {
        bld.row([(m + i, 1.0), (bound_col(i), -1.0)], 0.0);
    }
    for i in 0..mr {
        bld.row([(m + i, -1.0), (bound_col(i), -1.0)], 0.0);
    }
    for j in 0..m {
        bld.row([(j, -1.0)], 0.0);
    }
    bld.row((0..m).map(|j| (j, 1.0)), 1.0);
    bld.cone(NonnegativeConeT(2 * mr + m + 1));
    let mut q = vec![0.0; m + mr + nb];
    q[m + mr..].iter_mut().for_each(|v| *v = 1.0);
    for (qj, gj) in q.iter_mut().zip(g) {
        *qj = *gj;
    }
    let mut out = bld.solve(q, TOL_TIGHT, if l1 { "l1" } else { "l_inf" })?;
    if out.z.len() >= 3 * mr {
        out.lp_dual = (0..mr).map(|i| out.z[mr + i] - out.z[2 * mr + i]).collect();
    }
    Ok(out)
}

/// The formulation this module deliberately does **not** use, kept for the
/// regression test that documents the pitfall: the normal-equations QP
///
/// ```text
/// min ½wᵀ(AᵀA)w − (Aᵀt)ᵀw   s.t.  w ≥ 0  [, 1ᵀw ≤ 1]
/// ```
///
/// on the raw (unnormalised, uncompressed) data with the given settings.
#[cfg(test)]
pub(crate) fn solve_normal_equations_qp(
    a: &DMatrix<f64>,
    t: &DVector<f64>,
    sum_cap: bool,
    settings: DefaultSettings<f64>,
) -> Result<ConicOutcome, FitError> {
    let m = a.ncols();
    let ata = a.tr_mul(a);
    let (mut pi, mut pj, mut pv) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..m {
        for i in 0..=j {
            pi.push(i);
            pj.push(j);
            pv.push(ata[(i, j)]);
        }
    }
    let p = CscMatrix::new_from_triplets(m, m, pi, pj, pv);
    let q: Vec<f64> = a.tr_mul(t).iter().map(|v| -v).collect();
    let mut bld = ConeBuilder::new(m);
    let rows = bld.feasible_fractions(m, sum_cap);
    bld.cone(NonnegativeConeT(rows));
    let ac = CscMatrix::new_from_triplets(bld.nrows, m, bld.ri, bld.ci, bld.vals);
    run(
        &p,
        &q,
        &ac,
        &bld.b,
        &bld.cones,
        settings,
        "normal-equations",
    )
}
