//! `L1` and `LInf` fits by column generation over small Clarabel LPs.
//!
//! The LPs of [`crate::fit::conic::solve_l1_linear`] / [`crate::fit::conic::solve_linf`] carry one
//! residual row per weighted sample (`M ≈ 900` on a 21×21 target) and the
//! dense `M×m` block `Â`; an interior-point iteration factors a KKT system
//! whose elimination costs `O(M·m²)`, so the full basis (`m ≈ 190`) costs
//! of the order of a second per solve.  The optimal weights
//! are sparse (a dozen columns or fewer), so the same optimum is reached by
//! solving the LP on a *working set* `S` of columns and adding the columns
//! that price out:
//!
//! * **Dual bound.**  For any `y` with `‖y‖_∞ ≤ 1` (L1) or `‖y‖₁ ≤ 1` (L∞)
//!   and any feasible `w` (`w ≥ 0`, `1ᵀw ≤ 1`),
//!   `‖Âw − t̂‖_p ≥ yᵀ(Âw − t̂) ≥ min(0, minⱼ (Âᵀy)ⱼ) − yᵀt̂ =: LB(y)`
//!   (the weak-duality bound of [`mod@crate::fit::certify`]).
//! * **Round.**  Solve the LP on `S` (by [`mod@crate::fit::lp_rows`], which
//!   passes only the residual rows that matter; weights outside `S` are 0, so its
//!   optimum `UB` is attained by a feasible point of the full problem) and
//!   take the certificate `y = z₁ − z₂` of its duals, projected onto the
//!   dual-norm ball.  Over `S`, strong duality gives
//!   `min(0, min_{j∈S} (Âᵀy)ⱼ) − yᵀt̂ ≈ UB`.  If `LB(y)` over **all**
//!   columns is within [`GAP_FACTOR`]`·tol·‖t̂‖_p` of `UB`, the working-set
//!   optimum is optimal for the full problem; otherwise the columns with
//!   `(Âᵀy)ⱼ < min(0, min_{j∈S} (Âᵀy)ⱼ)` (negative reduced cost) are added,
//!   most negative first, at most [`ADD_PER_ROUND`] per round.
//! * **Start.**  `S` = the support of the capped least-squares fit
//!   (`Absolute`, Lawson–Hanson on the compressed data, microseconds), or
//!   the column best correlated with `t̂` when that support is empty.
//!
//! The working set only grows, so the loop ends after at most `m` rounds
//! (all columns); in practice 2–4 rounds of LPs with ~10–30 columns.  The
//! returned certificate is checked again, independently, by
//! [`crate::fit::verify()`] over all columns; column generation changes how
//! fast the optimum is found, not how it is certified.

use nalgebra::DVector;

use crate::fit::conic::ConicOutcome;
use crate::fit::lp_rows::solve_on_rows;
use crate::fit::nnls::nnls_capped;
use crate::fit::prepare::Prepared;
use crate::fit::FitError;

/// Columns added per round at most.
pub(crate) const ADD_PER_ROUND: usize = 12;

/// The working set is optimal when `UB − LB(y) ≤ GAP_FACTOR · tol · ‖t̂‖_p`
/// (a hundredth of the verification tolerance, so that verification of the
/// final answer has room to spare).
pub(crate) const GAP_FACTOR: f64 = 0.01;

/// The solver's certificate `y` projected onto the dual-norm ball:
/// `[−1, 1]^M` for L1 (clipping), the unit ℓ₁ ball for L∞ (scaling).
pub(crate) fn project_dual(y: &[f64], l1: bool) -> DVector<f64> {
    let mut y = DVector::from_column_slice(y);
    if l1 {
        y.apply(|v| *v = v.clamp(-1.0, 1.0));
    } else {
        let n1 = y.lp_norm(1);
        if n1 > 1.0 {
            y /= n1;
        }
    }
    y
}

/// `LB(y) = min(0, minⱼ (Âᵀy)ⱼ) − yᵀt̂` over the columns `cols` (all when
/// `None`), given `aty = Âᵀy`.
pub(crate) fn dual_bound(aty: &DVector<f64>, yt: f64, cols: Option<&[usize]>) -> f64 {
    let min = match cols {
        Some(c) => c.iter().map(|&j| aty[j]).fold(0.0, f64::min),
        None => aty.iter().copied().fold(0.0, f64::min),
    };
    min - yt
}

/// The `L1` (`l1 = true`) or `LInf` fit of the prepared data by column
/// generation (see the module docs).  The outcome's `x` holds the `m`
/// weights (zero outside the final working set), `lp_dual` the certificate
/// of the last LP, `iterations` and `solve_time_s` the totals over rounds;
/// `obj_val` the last LP's objective.
///
/// # Errors
/// Clarabel setup failures and Lawson–Hanson non-convergence.  A status
/// other than `Solved`/`AlmostSolved` is returned in the outcome for the
/// caller to report.
pub(crate) fn solve_lp_mode(prep: &Prepared, l1: bool, tol: f64) -> Result<ConicOutcome, FitError> {
    column_generation(prep, l1, tol).map(|(out, _)| out)
}

/// [`solve_lp_mode`], also returning the number of LPs solved (rounds).
pub(crate) fn column_generation(
    prep: &Prepared,
    l1: bool,
    tol: f64,
) -> Result<(ConicOutcome, usize), FitError> {
    let m = prep.ncols();
    let (mut set, mut w) = start_set(prep)?;
    let obj0 = if l1 {
        prep.td.lp_norm(1)
    } else {
        prep.td.amax()
    };
    let (mut iterations, mut solve_time_s, mut round) = (0u32, 0.0, 0usize);
    loop {
        round += 1;
        let ad = prep.ad.select_columns(set.iter());
        let w0 = DVector::from_iterator(set.len(), set.iter().map(|&j| w[j]));
        let mut out = solve_on_rows(&ad, &prep.td, l1, &w0)?;
        iterations += out.iterations;
        solve_time_s += out.solve_time_s;
        w = vec![0.0; m];
        for (k, &j) in set.iter().enumerate() {
            w[j] = out.x.get(k).copied().unwrap_or(0.0);
        }
        out.x = w.clone();
        out.iterations = iterations;
        out.solve_time_s = solve_time_s;
        let usable = matches!(
            out.status,
            clarabel::solver::SolverStatus::Solved | clarabel::solver::SolverStatus::AlmostSolved
        );
        if !usable || set.len() == m || out.lp_dual.len() != prep.nrows() {
            return Ok((out, round));
        }
        let wv = DVector::from_column_slice(&out.x);
        let resid = &prep.ad * &wv - &prep.td;
        let ub = if l1 { resid.lp_norm(1) } else { resid.amax() };
        let y = project_dual(&out.lp_dual, l1);
        let aty = prep.ad.tr_mul(&y);
        let yt = y.dot(&prep.td);
        if ub - dual_bound(&aty, yt, None) <= GAP_FACTOR * tol * obj0 {
            return Ok((out, round));
        }
        let floor = set.iter().map(|&j| aty[j]).fold(0.0, f64::min);
        let mut cands: Vec<usize> = (0..m)
            .filter(|&j| aty[j] < floor && set.binary_search(&j).is_err())
            .collect();
        if cands.is_empty() {
            // The gap is the working-set LP's own; verification judges it.
            return Ok((out, round));
        }
        cands.sort_by(|&a, &b| aty[a].total_cmp(&aty[b]).then(a.cmp(&b)));
        set.extend(cands.into_iter().take(ADD_PER_ROUND));
        set.sort_unstable();
    }
}

/// The starting working set (sorted): the support of the capped
/// least-squares fit, or the column best correlated with `t̂`; and the
/// starting weights (that fit's, length `m`).
fn start_set(prep: &Prepared) -> Result<(Vec<usize>, Vec<f64>), FitError> {
    let w = nnls_capped(&prep.r, &prep.c, 1.0)?;
    let set: Vec<usize> = (0..prep.ncols()).filter(|&j| w[j] > 0.0).collect();
    let w: Vec<f64> = w.iter().copied().collect();
    if !set.is_empty() {
        return Ok((set, w));
    }
    let corr = prep.ad.tr_mul(&prep.td);
    let best = (0..prep.ncols())
        .max_by(|&a, &b| corr[a].total_cmp(&corr[b]).then(b.cmp(&a)))
        .unwrap_or(0);
    Ok((vec![best], w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::testutil::{
        assert_matches_full_lp, plate_like_basis, random_vector, SplitMix64,
    };
    use crate::fit::FitProblem;
    use clarabel::solver::SolverStatus;

    /// Column generation against the LP on all columns, on a plate-like
    /// basis of 60 columns over 21×21 points (882 rows) with a target of 4
    /// planted columns plus noise: both end `Solved`, the objectives agree
    /// to 1e-9 of ‖t̂‖_p, the weights to 1e-6, the working set stays below
    /// half the columns and more than one round was needed for L1 (the
    /// capped least-squares support is not the L1 support).
    #[test]
    fn column_generation_matches_the_full_lp() {
        let mut rng = SplitMix64::new(4242);
        let a = plate_like_basis(&mut rng, 21, 60);
        let w = nalgebra::DVector::from_fn(60, |i, _| if i % 17 == 3 { 0.1 } else { 0.0 });
        let t = &a * w + random_vector(&mut rng, a.nrows()) * 0.1;
        let prep = Prepared::new(&FitProblem::new(&a, &t)).unwrap();
        for l1 in [true, false] {
            let (cg, rounds) = column_generation(&prep, l1, 1e-6).unwrap();
            assert_eq!(cg.status, SolverStatus::Solved);
            assert_matches_full_lp(&prep.ad, &prep.td, &cg.x, l1);
            let support = (0..60).filter(|&j| cg.x[j] > 1e-9).count();
            assert!(support < 30, "l1={l1}: {support}");
            if l1 {
                assert!(rounds >= 2, "{rounds}");
            }
            println!(
                "l1={l1}: {rounds} rounds, {} iterations, support {support}",
                cg.iterations
            );
        }
    }
}
