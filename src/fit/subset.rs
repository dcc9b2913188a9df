//! Fits with few primitives: best subsets of at most `k` basis columns.
//!
//! For a column subset `S` let `score(S)` be the optimum of the chosen mode
//! restricted to the columns in `S` (all other weights fixed at 0):
//!
//! * `Absolute`: `min_{w ≥ 0, 1ᵀw ≤ 1} ‖R_S w − c‖` (capped NNLS);
//! * `Shape`:    `min_{w ≥ 0} ‖R_S w − c‖` (NNLS);
//! * `Budget`:   `−s*(S)` (0 when the shape error of `S` already exceeds
//!   `ε`, i.e. the budget cannot be met with `S`);
//! * `L1`/`LInf`: the `Absolute` score (capped NNLS) as a proxy.
//!
//! (`R_S` are the columns of the compressed matrix of
//! [`crate::fit::prepare`], so the least-squares scores cost one small
//! active-set solve each; `Budget` costs one small cone program.)
//!
//! Why a proxy for the LP modes: the exact score is an LP on all `M`
//! residual rows (costly at `M ≈ 900`, whatever `k`: `lp_rows`), and an
//! exhaustive search over a 12-column support is 4096 of them — over a
//! minute, against microseconds for a capped NNLS on `R_S`.  The subset chosen for each `k` is
//! then solved
//! and verified exactly in the LP mode; its `exhaustive` flag is `false`,
//! since the search was exhaustive only over the proxy.
//!
//! The subset for each `k` is chosen by
//! * **exhaustive** search over all `C(m, k)` subsets when
//!   `C(m, k) ≤` [`EXHAUSTIVE_LIMIT`] (then it is optimal), otherwise
//! * **greedy forward selection** from the subset chosen for `k − 1` (add
//!   the column that lowers the score most), followed by **one swap pass**
//!   (for each chosen column in turn, replace it by the first unchosen column
//!   that strictly lowers the score).
//!
//! Because the set for `k` is a superset of the one for `k − 1` (or the
//! exhaustive optimum), the score is non-increasing in `k`; the *reported*
//! (verified) error is made exactly non-increasing by keeping the previous
//! subset whenever the verified solve of the new one comes out worse by
//! rounding.  Each reported subset fit is solved and verified with
//! [`crate::fit::solve`]'s machinery.  Ties are broken by the lowest index;
//! results are deterministic.

use serde::{Deserialize, Serialize};

use crate::fit::nnls::{nnls, nnls_capped};
use crate::fit::prepare::Prepared;
use crate::fit::{
    conic, solve_prepared, validate_options, FitError, FitMode, FitOptions, FitProblem, FitSolution,
};

/// Largest `C(m, k)` for which all subsets are tried.
pub(crate) const EXHAUSTIVE_LIMIT: u64 = 2000;

/// Relative improvement a candidate must bring to replace the incumbent
/// (guards against flip-flopping on rounding noise).
const IMPROVEMENT: f64 = 1e-12;

/// The best fit found with at most `k` columns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct SubsetFit {
    /// Column budget `k` this entry answers.
    pub k: usize,
    /// Chosen column indices (ascending, at most `k`).
    pub columns: Vec<usize>,
    /// Time fractions of the chosen columns (same order as `columns`).
    pub weights: Vec<f64>,
    /// Strength (see [`FitSolution::strength`]); 0 when infeasible.
    pub strength: f64,
    /// Relative L2 error of the verified fit (for an infeasible `Budget`
    /// entry: the best shape error of the chosen columns).
    pub relative_error: f64,
    /// Mode objective (see [`FitSolution::objective`]).
    pub objective: f64,
    /// Whether the subset was found by exhaustive search (hence optimal);
    /// always `false` in the `L1`/`LInf` modes, whose subsets are chosen by
    /// a least-squares proxy (see the module docs).
    pub exhaustive: bool,
    /// `false` only in `Budget` mode when no strength `s > 0` meets the
    /// budget with these columns.
    pub feasible: bool,
    /// See [`FitSolution::unreachable`].
    pub unreachable: bool,
}

/// For `k = 1..=min(k_max, m)`, the best fit found with at most `k`
/// columns (see module docs), using default verification settings.
///
/// # Errors
/// Invalid input, or a solver/verification failure of a reported fit.
pub(crate) fn sparsity_path(
    problem: &FitProblem,
    mode: &FitMode,
    k_max: usize,
) -> Result<Vec<SubsetFit>, FitError> {
    sparsity_path_with(
        problem,
        &FitOptions {
            mode: *mode,
            ..FitOptions::default()
        },
        k_max,
    )
}

/// [`sparsity_path`] with explicit options (`max_primitives` is ignored).
pub(crate) fn sparsity_path_with(
    problem: &FitProblem,
    options: &FitOptions,
    k_max: usize,
) -> Result<Vec<SubsetFit>, FitError> {
    validate_options(options)?;
    let prep = Prepared::new(problem)?;
    let m = prep.ncols();
    let kmax = k_max.min(m);
    let mode = options.mode;
    let tol = options.tolerance;
    let mut out: Vec<SubsetFit> = Vec::with_capacity(kmax);
    let mut current: Vec<usize> = Vec::new();
    for k in 1..=kmax {
        let (set, exhaustive) = choose_subset(&prep, &mode, k, &current)?;
        let exhaustive = exhaustive && !matches!(mode, FitMode::L1 | FitMode::LInf);
        current = set;
        let mut fit = fit_subset(
            &prep,
            &mode,
            tol,
            options.formulation,
            &current,
            k,
            exhaustive,
        )?;
        if let Some(prev) = out.last() {
            if worse(&fit, prev, &mode) {
                // The previous subset is at least as good as the one just
                // searched (an exhaustive search stays optimal this way).
                fit = SubsetFit {
                    k,
                    exhaustive,
                    ..prev.clone()
                };
                current = prev.columns.clone();
            }
        }
        out.push(fit);
    }
    Ok(out)
}

/// `a` is strictly worse than `b` in the mode's objective.
fn worse(a: &SubsetFit, b: &SubsetFit, mode: &FitMode) -> bool {
    match mode {
        FitMode::Absolute | FitMode::Shape => a.relative_error > b.relative_error,
        FitMode::Budget { .. } => a.strength < b.strength,
        FitMode::L1 | FitMode::LInf => a.objective > b.objective,
    }
}

/// Score of a column subset (lower is better); see module docs.
fn score(prep: &Prepared, mode: &FitMode, cols: &[usize]) -> Result<f64, FitError> {
    if cols.is_empty() {
        return Ok(f64::INFINITY);
    }
    match *mode {
        FitMode::Absolute | FitMode::Shape | FitMode::L1 | FitMode::LInf => {
            let rs = prep.r.select_columns(cols.iter());
            let w = if !matches!(mode, FitMode::Shape) {
                nnls_capped(&rs, &prep.c, 1.0)?
            } else {
                nnls(&rs, &prep.c)?
            };
            Ok((&rs * w - &prep.c).norm())
        }
        FitMode::Budget { rel_error } => {
            let rs = prep.r.select_columns(cols.iter());
            let w = nnls(&rs, &prep.c)?;
            let shape_err = (&rs * w - &prep.c).norm().hypot(prep.r0);
            if shape_err >= rel_error {
                return Ok(0.0);
            }
            let sub = prep.subset(cols);
            let out = conic::solve_budget(&sub.r, &sub.c, sub.r0, rel_error)?;
            Ok(if usable(&out) {
                -out.x[cols.len()]
            } else {
                f64::INFINITY
            })
        }
    }
}

fn usable(out: &conic::ConicOutcome) -> bool {
    use clarabel::solver::SolverStatus::{AlmostSolved, Solved};
    matches!(out.status, Solved | AlmostSolved)
}

fn improves(new: f64, best: f64) -> bool {
    if !best.is_finite() {
        return new < best;
    }
    new < best - IMPROVEMENT * best.abs().max(1e-300)
}

/// `C(m, k)` if it is at most `limit`, else `None`.
fn binomial_capped(m: usize, k: usize, limit: u64) -> Option<u64> {
    let k = k.min(m - k);
    let mut c: u128 = 1;
    for i in 0..k {
        // After this step c = C(m, i + 1), which is non-decreasing in i for
        // i + 1 ≤ m/2, so exceeding the limit early is final.
        c = c * (m - i) as u128 / (i as u128 + 1);
        if c > limit as u128 {
            return None;
        }
    }
    Some(c as u64)
}

/// Choose the subset for budget `k`, given the subset chosen for `k − 1`.
fn choose_subset(
    prep: &Prepared,
    mode: &FitMode,
    k: usize,
    previous: &[usize],
) -> Result<(Vec<usize>, bool), FitError> {
    let m = prep.ncols();
    if binomial_capped(m, k, EXHAUSTIVE_LIMIT).is_some() {
        return Ok((exhaustive_subset(prep, mode, k)?, true));
    }
    let (set, best) = greedy_forward(prep, mode, previous)?;
    Ok((swap_pass(prep, mode, set, best)?, false))
}

/// The best of all k-subsets, enumerated lexicographically.
fn exhaustive_subset(prep: &Prepared, mode: &FitMode, k: usize) -> Result<Vec<usize>, FitError> {
    let m = prep.ncols();
    let mut idx: Vec<usize> = (0..k).collect();
    let mut best = f64::INFINITY;
    let mut best_set = idx.clone();
    loop {
        let sc = score(prep, mode, &idx)?;
        if improves(sc, best) {
            best = sc;
            best_set = idx.clone();
        }
        // advance
        let mut i = k;
        while i > 0 && idx[i - 1] == m - k + i - 1 {
            i -= 1;
        }
        if i == 0 {
            break;
        }
        idx[i - 1] += 1;
        for j in i..k {
            idx[j] = idx[j - 1] + 1;
        }
    }
    Ok(best_set)
}

/// Greedy forward step: `previous` plus the column that lowers the score
/// most (or, when none does, the first one left, so the budget is still
/// used; its weight may be 0). Returns the set and its score.
fn greedy_forward(
    prep: &Prepared,
    mode: &FitMode,
    previous: &[usize],
) -> Result<(Vec<usize>, f64), FitError> {
    let m = prep.ncols();
    let mut set: Vec<usize> = previous.to_vec();
    let mut best = score(prep, mode, &set)?;
    let mut best_add: Option<usize> = None;
    for j in 0..m {
        if set.contains(&j) {
            continue;
        }
        let mut cand = set.clone();
        cand.push(j);
        cand.sort_unstable();
        let sc = score(prep, mode, &cand)?;
        if improves(sc, best) {
            best = sc;
            best_add = Some(j);
        }
    }
    if let Some(j) = best_add {
        set.push(j);
        set.sort_unstable();
    } else if let Some(j) = (0..m).find(|j| !set.contains(j)) {
        set.push(j);
        set.sort_unstable();
        best = score(prep, mode, &set)?;
    }
    Ok((set, best))
}

/// One swap-improvement pass over `set` (score `best`): each position's
/// column swapped for the first outside column that lowers the score.
fn swap_pass(
    prep: &Prepared,
    mode: &FitMode,
    mut set: Vec<usize>,
    mut best: f64,
) -> Result<Vec<usize>, FitError> {
    let m = prep.ncols();
    let mut pos = 0;
    while pos < set.len() {
        let mut swapped = false;
        for j in 0..m {
            if set.contains(&j) {
                continue;
            }
            let mut cand = set.clone();
            cand[pos] = j;
            cand.sort_unstable();
            let sc = score(prep, mode, &cand)?;
            if improves(sc, best) {
                best = sc;
                set = cand;
                swapped = true;
                break;
            }
        }
        if !swapped {
            pos += 1;
        }
        // After a swap the sorted order changed; continue scanning from the
        // same position (the pass is bounded because every swap strictly
        // lowers the score and positions only advance otherwise).
    }
    Ok(set)
}

/// Verified fit on the subset `cols`.
fn fit_subset(
    prep: &Prepared,
    mode: &FitMode,
    tol: f64,
    formulation: crate::fit::LsFormulation,
    cols: &[usize],
    k: usize,
    exhaustive: bool,
) -> Result<SubsetFit, FitError> {
    let sub = prep.subset(cols);
    match solve_prepared(&sub, mode, tol, formulation) {
        Ok(sol) => Ok(SubsetFit {
            k,
            columns: cols.to_vec(),
            weights: sol.fractions.clone(),
            strength: sol.strength,
            relative_error: sol.relative_error,
            objective: sol.objective,
            exhaustive,
            feasible: true,
            unreachable: sol.unreachable,
        }),
        Err(FitError::BudgetInfeasible { best_rel_error, .. }) => Ok(SubsetFit {
            k,
            columns: cols.to_vec(),
            weights: vec![0.0; cols.len()],
            strength: 0.0,
            relative_error: best_rel_error,
            objective: 0.0,
            exhaustive,
            feasible: false,
            unreachable: true,
        }),
        Err(e) => Err(e),
    }
}

/// [`crate::fit::solve`] with `max_primitives = Some(k)`, `1 ≤ k < m`.
///
/// Candidates: the subset chosen by the path procedure for `k`, and the
/// support of the unrestricted solution when it already has at most `k`
/// columns (fractions above `1e-8`).  The better-scoring candidate is
/// solved and verified; fractions are expanded to length `m`.
pub(crate) fn solve_max_primitives(
    prep: &Prepared,
    options: &FitOptions,
    k: usize,
) -> Result<FitSolution, FitError> {
    let mode = options.mode;
    let m = prep.ncols();
    let mut current: Vec<usize> = Vec::new();
    for kk in 1..=k {
        current = choose_subset(prep, &mode, kk, &current)?.0;
    }
    let mut best_set = current;
    let mut best_score = score(prep, &mode, &best_set)?;
    if let Ok(full) = solve_prepared(prep, &mode, options.tolerance, options.formulation) {
        let support: Vec<usize> = (0..m).filter(|&j| full.fractions[j] > 1e-8).collect();
        if !support.is_empty() && support.len() <= k {
            let sc = score(prep, &mode, &support)?;
            if improves(sc, best_score) {
                best_score = sc;
                best_set = support;
            }
        }
    }
    let _ = best_score;
    let sub = prep.subset(&best_set);
    let mut sol = solve_prepared(&sub, &mode, options.tolerance, options.formulation)?;
    let mut fractions = vec![0.0; m];
    for (pos, &j) in best_set.iter().enumerate() {
        fractions[j] = sol.fractions[pos];
    }
    sol.fractions = fractions;
    Ok(sol)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::solve;
    use crate::fit::testutil::{plate_like_basis, random_matrix, random_vector, SplitMix64};
    use nalgebra::{DMatrix, DVector};

    fn check_path(
        a: &DMatrix<f64>,
        mode: FitMode,
        cols: [usize; 2],
        k_max: usize,
    ) -> Vec<SubsetFit> {
        let t = a.column(cols[0]) * 0.3 + a.column(cols[1]) * 0.45;
        let path = sparsity_path(&FitProblem::new(a, &t), &mode, k_max).unwrap();
        assert_eq!(path.len(), k_max.min(a.ncols()));
        for (i, f) in path.iter().enumerate() {
            assert_eq!(f.k, i + 1);
            assert!(f.columns.len() <= f.k);
            assert_eq!(f.columns.len(), f.weights.len());
            assert!(f.columns.windows(2).all(|w| w[0] < w[1]));
            if i > 0 {
                assert!(
                    f.relative_error <= path[i - 1].relative_error,
                    "{mode:?}: error increased at k = {}: {} > {}",
                    f.k,
                    f.relative_error,
                    path[i - 1].relative_error
                );
            }
        }
        assert!(
            path[1].relative_error < 1e-6,
            "{mode:?}: k=2 error {}",
            path[1].relative_error
        );
        assert_eq!(path[1].columns, cols.to_vec(), "{mode:?}");
        path
    }

    /// Target = 0.3·A₃ + 0.45·A₈ on a 12-column plate-like basis (all
    /// k ≤ 4 exhaustive): relative error non-increasing in k, k = 2 picks
    /// exactly columns {3, 8} with error < 1e-6, weights (0.3, 0.45) to
    /// 1e-6 in Absolute mode.
    #[test]
    fn sparsity_path_exhaustive_finds_planted_pair() {
        let mut rng = SplitMix64::new(71);
        let a = plate_like_basis(&mut rng, 11, 12);
        for mode in [FitMode::Absolute, FitMode::Shape] {
            let path = check_path(&a, mode, [3, 8], 4);
            assert!(path.iter().all(|f| f.exhaustive));
            if mode == FitMode::Absolute {
                assert!((path[1].weights[0] - 0.3).abs() < 1e-6);
                assert!((path[1].weights[1] - 0.45).abs() < 1e-6);
            }
        }
    }

    /// Same with 70 columns (k = 1 exhaustive, k ≥ 2 greedy + swap pass):
    /// the planted pair {12, 57} is found at k = 2.
    #[test]
    fn sparsity_path_greedy_finds_planted_pair() {
        let mut rng = SplitMix64::new(72);
        let a = plate_like_basis(&mut rng, 11, 70);
        for mode in [FitMode::Absolute, FitMode::Shape] {
            let path = check_path(&a, mode, [12, 57], 3);
            assert!(path[0].exhaustive && !path[1].exhaustive);
        }
    }

    /// L1 path on 6 random columns (exhaustive): objective non-increasing,
    /// and k = m reproduces the unrestricted L1 optimum to 1e-7 relative.
    /// k_max above m is capped at m.
    #[test]
    fn sparsity_path_l1_reaches_full_optimum() {
        let mut rng = SplitMix64::new(73);
        let a = random_matrix(&mut rng, 30, 6);
        let t = &a * DVector::from_vec(vec![0.2, 0.1, 0.0, 0.3, 0.0, 0.1])
            + random_vector(&mut rng, 30) * 0.05;
        let p = FitProblem::new(&a, &t);
        let path = sparsity_path(&p, &FitMode::L1, 10).unwrap();
        assert_eq!(path.len(), 6);
        for i in 1..path.len() {
            assert!(path[i].objective <= path[i - 1].objective);
        }
        let full = solve(
            &p,
            &FitOptions {
                mode: FitMode::L1,
                ..FitOptions::default()
            },
        )
        .unwrap();
        assert!((path[5].objective - full.objective).abs() <= 1e-7 * full.objective);
    }

    /// Budget path: with one column the budget ε = 0.05 cannot be met
    /// (feasible = false, strength 0); with the planted pair it can, and
    /// the strength is non-decreasing in k.
    #[test]
    fn sparsity_path_budget_feasibility() {
        let mut rng = SplitMix64::new(74);
        let a = plate_like_basis(&mut rng, 11, 8);
        let t = a.column(1) * 0.3 + a.column(6) * 0.3;
        let p = FitProblem::new(&a, &t);
        let path = sparsity_path(&p, &FitMode::Budget { rel_error: 0.05 }, 3).unwrap();
        assert!(!path[0].feasible);
        assert_eq!(path[0].strength, 0.0);
        assert!(path[1].feasible && path[1].strength > 0.0);
        assert!(path[2].strength >= path[1].strength);
    }

    /// Binomial helper: exact values and the cap.
    #[test]
    fn binomial_cap() {
        assert_eq!(binomial_capped(12, 4, 2000), Some(495));
        assert_eq!(binomial_capped(70, 2, 2000), None);
        assert_eq!(binomial_capped(70, 69, 2000), Some(70));
        assert_eq!(binomial_capped(200, 1, 2000), Some(200));
    }
}
