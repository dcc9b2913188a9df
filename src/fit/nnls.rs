//! Active-set non-negative least squares (Lawson–Hanson), and its exact
//! extension to a capped sum.
//!
//! These solvers are the *independent* reference against which every
//! interior-point answer of [`crate::fit::solve`] is checked; they share no
//! code with the conic formulations.
//!
//! * [`nnls`] solves `min ‖Ax − b‖₂` s.t. `x ≥ 0`.
//! * [`nnls_capped`] solves `min ‖Ax − b‖₂` s.t. `x ≥ 0, 1ᵀx ≤ cap`.
//!
//! # Algorithm
//!
//! Lawson & Hanson (1974, ch. 23).  The passive set `P` (free variables) is
//! grown one column at a time (the one with the largest negative-gradient
//! component `wⱼ = Aⱼᵀ(b − Ax)`), the unconstrained least-squares problem
//! on `P` is solved, and variables that would turn negative are moved back
//! to the bound by an interpolation step.  The least-squares problem on
//! `P` is solved with an incrementally updated QR factorisation of `A_P`
//! (Gram–Schmidt with re-orthogonalisation when adding a column, Givens
//! rotations when removing one), so the normal equations are never formed.
//! A column that is numerically dependent on `A_P` (orthogonal part below
//! `1e-10·‖Aⱼ‖`) is never added, which makes the method robust to duplicate
//! columns.  Ties are broken by the lowest index; the result is
//! deterministic.
//!
//! # Capped sum: an exact reformulation
//!
//! Introduce a rest variable `x₀ = cap − 1ᵀx ≥ 0` with a zero column and
//! write `y = (x, x₀)/cap`, so that `y ≥ 0, 1ᵀy = 1` and
//! `Ax − b = Σⱼ yⱼ (cap·Aⱼ − b) + y₀(−b) = By`.  The problem becomes the
//! simplex-constrained least squares `min ‖By‖` s.t. `y ≥ 0, 1ᵀy = 1`.
//! That problem is solved *exactly* by one NNLS on an augmented system:
//!
//! ```text
//! u* = argmin_{u ≥ 0} ‖[B; γ1ᵀ] u − [0; γ]‖²,     y = u*/1ᵀu*   (γ > 0).
//! ```
//!
//! Proof: the KKT conditions of the NNLS are
//! `BᵀBu − γ²ρ1 = λ ≥ 0, λ ⊙ u = 0` with `ρ = 1 − 1ᵀu`.  `u = 0` is never
//! optimal (its gradient is `−γ²1 < 0`), so `1ᵀu > 0`, and dividing by it
//! gives `BᵀBy + ν1 = λ/1ᵀu ≥ 0`, `y ⊙ λ = 0`, `1ᵀy = 1` with
//! `ν = −γ²ρ/1ᵀu` — exactly the KKT conditions of the simplex problem (a
//! free multiplier `ν` for the equality).  No penalty weight has to be
//! "large enough".  The plain NNLS is tried first; when its solution already
//! satisfies `1ᵀx ≤ cap` it is optimal for the capped problem too.

use nalgebra::{DMatrix, DVector};

use crate::fit::FitError;

/// Relative threshold below which a column's component orthogonal to the
/// current passive columns counts as zero (column is dependent).
const DEPENDENCE_TOL: f64 = 1e-10;
/// Relative threshold on the gradient `Aⱼᵀr` (scaled by `‖Aⱼ‖‖b‖`) below
/// which a variable is considered optimal at its bound.
const GRADIENT_TOL: f64 = 1e-13;

/// Result of [`nnls_detailed`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct NnlsOutput {
    /// The minimiser `x ≥ 0`.
    pub x: DVector<f64>,
    /// `‖Ax − b‖₂`.
    pub residual_norm: f64,
    /// Inner (least-squares) iterations performed.
    pub iterations: usize,
}

/// Lawson–Hanson non-negative least squares: `argmin_{x ≥ 0} ‖Ax − b‖₂`.
///
/// # Errors
/// Dimension mismatch, non-finite data, or no convergence within
/// `3·ncols + 30` iterations.
pub(crate) fn nnls(a: &DMatrix<f64>, b: &DVector<f64>) -> Result<DVector<f64>, FitError> {
    nnls_detailed(a, b).map(|o| o.x)
}

/// [`nnls`] with residual norm and iteration count.
pub(crate) fn nnls_detailed(a: &DMatrix<f64>, b: &DVector<f64>) -> Result<NnlsOutput, FitError> {
    check_inputs(a, b)?;
    lawson_hanson(a, b)
}

/// `argmin ‖Ax − b‖₂` s.t. `x ≥ 0, 1ᵀx ≤ cap` (exact; see module docs).
///
/// # Errors
/// As [`nnls`], plus `cap` not finite and positive.
pub(crate) fn nnls_capped(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    cap: f64,
) -> Result<DVector<f64>, FitError> {
    check_inputs(a, b)?;
    if !(cap.is_finite() && cap > 0.0) {
        return Err(FitError::InvalidInput(format!(
            "nnls_capped: cap must be finite and > 0, got {cap}"
        )));
    }
    let free = lawson_hanson(a, b)?;
    if free.x.sum() <= cap {
        return Ok(free.x);
    }
    let (rows, n) = a.shape();
    // Augmented simplex system: columns cap·Aⱼ − b, the rest column −b, and
    // the row γ1ᵀ with right-hand side γ.
    let mut bm = DMatrix::zeros(rows + 1, n + 1);
    for j in 0..n {
        for i in 0..rows {
            bm[(i, j)] = cap * a[(i, j)] - b[i];
        }
    }
    for i in 0..rows {
        bm[(i, n)] = -b[i];
    }
    let gamma = (0..=n)
        .map(|j| bm.view((0, j), (rows, 1)).norm())
        .fold(0.0_f64, f64::max);
    let gamma = if gamma > 0.0 { gamma } else { 1.0 };
    for j in 0..=n {
        bm[(rows, j)] = gamma;
    }
    let mut rhs = DVector::zeros(rows + 1);
    rhs[rows] = gamma;
    let u = lawson_hanson(&bm, &rhs)?.x;
    let total = u.sum();
    if total.is_nan() || total <= 0.0 {
        // Cannot happen in exact arithmetic (see module docs).
        return Err(FitError::NnlsNoConvergence { iterations: 0 });
    }
    Ok(DVector::from_iterator(
        n,
        (0..n).map(|j| cap * u[j] / total),
    ))
}

fn check_inputs(a: &DMatrix<f64>, b: &DVector<f64>) -> Result<(), FitError> {
    if a.nrows() != b.len() {
        return Err(FitError::DimensionMismatch {
            what: "nnls right-hand side",
            expected: a.nrows(),
            got: b.len(),
        });
    }
    if a.iter().chain(b.iter()).any(|v| !v.is_finite()) {
        return Err(FitError::InvalidInput("nnls: non-finite data".into()));
    }
    Ok(())
}

/// Incrementally updated thin QR of the passive columns `A_P = Q R`,
/// together with `Qᵀb`.
struct IncrementalQr {
    /// Orthonormal columns of `Q`.
    q: Vec<DVector<f64>>,
    /// Columns of `R`; column `c` holds rows `0..=c`.
    r: Vec<Vec<f64>>,
    /// `Qᵀb`.
    qtb: Vec<f64>,
    /// Original column index of each passive column, in factor order.
    cols: Vec<usize>,
}

impl IncrementalQr {
    fn new() -> Self {
        Self {
            q: Vec::new(),
            r: Vec::new(),
            qtb: Vec::new(),
            cols: Vec::new(),
        }
    }

    fn len(&self) -> usize {
        self.cols.len()
    }

    /// Append column `j`; returns `false` (and changes nothing) when the
    /// column is numerically dependent on the current ones.
    fn push(&mut self, a: &DMatrix<f64>, b: &DVector<f64>, j: usize) -> bool {
        let aj = a.column(j);
        let norm = aj.norm();
        if norm == 0.0 {
            return false;
        }
        let mut v: DVector<f64> = aj.into_owned();
        let p = self.len();
        let mut h = vec![0.0; p + 1];
        for _pass in 0..2 {
            for (i, qi) in self.q.iter().enumerate() {
                let d = qi.dot(&v);
                h[i] += d;
                v.axpy(-d, qi, 1.0);
            }
        }
        let rho = v.norm();
        if rho <= DEPENDENCE_TOL * norm {
            return false;
        }
        v /= rho;
        h[p] = rho;
        self.qtb.push(v.dot(b));
        self.q.push(v);
        self.r.push(h);
        self.cols.push(j);
        true
    }

    /// Remove the passive column at factor position `k` and restore the
    /// triangular form with Givens rotations.
    fn remove(&mut self, k: usize) {
        let p = self.len();
        self.r.remove(k);
        self.cols.remove(k);
        // Columns k..p-2 now have one sub-diagonal entry at row c+1.
        for i in k..p - 1 {
            let a_ = self.r[i][i];
            let b_ = self.r[i][i + 1];
            let rr = a_.hypot(b_);
            let (cs, sn) = if rr == 0.0 {
                (1.0, 0.0)
            } else {
                (a_ / rr, b_ / rr)
            };
            for col in self.r.iter_mut().skip(i) {
                let x = col[i];
                let y = col[i + 1];
                col[i] = cs * x + sn * y;
                col[i + 1] = -sn * x + cs * y;
            }
            self.r[i].truncate(i + 1);
            self.r[i][i] = rr;
            let x = self.qtb[i];
            let y = self.qtb[i + 1];
            self.qtb[i] = cs * x + sn * y;
            self.qtb[i + 1] = -sn * x + cs * y;
            let (lo, hi) = self.q.split_at_mut(i + 1);
            let qi = &mut lo[i];
            let qn = &mut hi[0];
            for (u, v) in qi.iter_mut().zip(qn.iter_mut()) {
                let x = *u;
                let y = *v;
                *u = cs * x + sn * y;
                *v = -sn * x + cs * y;
            }
        }
        self.q.pop();
        self.qtb.pop();
    }

    /// Least-squares coefficients on the passive set: solve `R z = Qᵀb`.
    fn solve(&self) -> Vec<f64> {
        let p = self.len();
        let mut z = vec![0.0; p];
        for i in (0..p).rev() {
            let mut s = self.qtb[i];
            for (c, zc) in z.iter().enumerate().skip(i + 1) {
                s -= self.r[c][i] * zc;
            }
            z[i] = s / self.r[i][i];
        }
        z
    }

    fn position(&self, j: usize) -> Option<usize> {
        self.cols.iter().position(|&c| c == j)
    }
}

fn lawson_hanson(a: &DMatrix<f64>, b: &DVector<f64>) -> Result<NnlsOutput, FitError> {
    let n = a.ncols();
    let bnorm = b.norm();
    let col_norms: Vec<f64> = a.column_iter().map(|c| c.norm()).collect();
    let mut x = DVector::zeros(n);
    let mut passive = vec![false; n];
    let mut rejected = vec![false; n];
    let mut qr = IncrementalQr::new();
    let max_iter = 3 * n + 30;
    let mut iterations = 0usize;

    if bnorm == 0.0 {
        return Ok(NnlsOutput {
            x,
            residual_norm: 0.0,
            iterations,
        });
    }

    'outer: loop {
        let resid = b - a * &x;
        let grad = a.tr_mul(&resid); // negative gradient of ½‖Ax − b‖²
        let Some(j) = entering_column(&grad, (&passive, &rejected), &col_norms, bnorm) else {
            break;
        };
        if !qr.push(a, b, j) {
            rejected[j] = true;
            continue;
        }
        passive[j] = true;
        let mut first = true;
        loop {
            iterations += 1;
            if iterations > max_iter {
                return Err(FitError::NnlsNoConvergence { iterations });
            }
            let z = qr.solve();
            if first {
                first = false;
                let pos = qr.position(j).expect("just added");
                if z[pos].is_nan() || z[pos] <= 0.0 {
                    // Numerically the new column cannot enter: undo.
                    qr.remove(pos);
                    passive[j] = false;
                    rejected[j] = true;
                    continue 'outer;
                }
            }
            if z.iter().all(|&v| v > 0.0) {
                for (pos, &c) in qr.cols.iter().enumerate() {
                    x[c] = z[pos];
                }
                rejected.iter_mut().for_each(|r| *r = false);
                break;
            }
            step_to_first_bound(&mut x, &z, &qr.cols);
            release_bound(&mut x, &mut passive, &mut qr);
            if qr.len() == 0 {
                continue 'outer;
            }
        }
    }
    let residual_norm = (a * &x - b).norm();
    Ok(NnlsOutput {
        x,
        residual_norm,
        iterations,
    })
}

/// The column entering the passive set: the largest negative gradient
/// `grad` (of ½‖Ax − b‖²) among the columns neither passive nor rejected,
/// if it exceeds the tolerance relative to the column's and b's norms.
fn entering_column(
    grad: &DVector<f64>,
    (passive, rejected): (&[bool], &[bool]),
    col_norms: &[f64],
    bnorm: f64,
) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for j in 0..grad.len() {
        if passive[j] || rejected[j] || col_norms[j] == 0.0 {
            continue;
        }
        let gj = grad[j];
        if gj > GRADIENT_TOL * col_norms[j] * bnorm && best.is_none_or(|(_, g)| gj > g) {
            best = Some((j, gj));
        }
    }
    best.map(|(j, _)| j)
}

/// Interpolates the passive variables `x[cols]` towards the unconstrained
/// solution `z` until the first one hits zero (set exactly to zero).
fn step_to_first_bound(x: &mut DVector<f64>, z: &[f64], cols: &[usize]) {
    let mut alpha = f64::INFINITY;
    let mut hit = usize::MAX;
    for (pos, &c) in cols.iter().enumerate() {
        if z[pos] <= 0.0 {
            let ratio = x[c] / (x[c] - z[pos]);
            if ratio < alpha {
                alpha = ratio;
                hit = c;
            }
        }
    }
    for (pos, &c) in cols.iter().enumerate() {
        x[c] += alpha * (z[pos] - x[c]);
    }
    x[hit] = 0.0;
}

/// Moves every passive variable at (or below) zero to the bound: out of
/// the passive set and the factorisation.
fn release_bound(x: &mut DVector<f64>, passive: &mut [bool], qr: &mut IncrementalQr) {
    let mut pos = 0;
    while pos < qr.len() {
        let c = qr.cols[pos];
        if x[c] <= 0.0 {
            x[c] = 0.0;
            passive[c] = false;
            qr.remove(pos);
        } else {
            pos += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::testutil::{random_matrix, random_vector, SplitMix64};

    /// Checks the NNLS optimality conditions: x ≥ 0, g = Aᵀ(Ax − b) ≥ −tol,
    /// xⱼ gⱼ ≈ 0.
    fn assert_nnls_kkt(a: &DMatrix<f64>, b: &DVector<f64>, x: &DVector<f64>, tol: f64) {
        let g = a.tr_mul(&(a * x - b));
        let scale = b.norm() * a.column_iter().map(|c| c.norm()).fold(0.0, f64::max);
        for j in 0..x.len() {
            assert!(x[j] >= 0.0);
            assert!(g[j] >= -tol * scale, "g[{j}] = {}", g[j]);
            assert!(
                (x[j] * g[j]).abs() <= tol * scale * (1.0 + x[j]),
                "comp {j}"
            );
        }
    }

    /// Exact recovery of a non-negative solution of a consistent system.
    #[test]
    fn nnls_recovers_consistent_solution() {
        let mut rng = SplitMix64::new(1);
        let a = random_matrix(&mut rng, 40, 6);
        let x_true = DVector::from_vec(vec![0.5, 0.0, 1.5, 0.0, 0.25, 2.0]);
        let b = &a * &x_true;
        let x = nnls(&a, &b).unwrap();
        assert!((&x - &x_true).amax() < 1e-12, "{x}");
    }

    /// Random inconsistent problems satisfy the KKT conditions to 1e-12.
    #[test]
    fn nnls_satisfies_kkt_on_random_problems() {
        let mut rng = SplitMix64::new(2);
        for trial in 0..20 {
            let rows = 10 + trial * 3;
            let cols = 3 + trial % 9;
            let a = random_matrix(&mut rng, rows, cols);
            let b = random_vector(&mut rng, rows);
            let x = nnls(&a, &b).unwrap();
            assert_nnls_kkt(&a, &b, &x, 1e-12);
        }
    }

    /// Duplicate and zero columns, and more columns than rows, are handled.
    #[test]
    fn nnls_handles_rank_deficiency() {
        let mut rng = SplitMix64::new(3);
        let base = random_matrix(&mut rng, 5, 4);
        let mut a = DMatrix::zeros(5, 9);
        for j in 0..4 {
            a.set_column(j, &base.column(j));
            a.set_column(j + 4, &base.column(j)); // duplicates
        }
        // column 8 stays zero
        let b = random_vector(&mut rng, 5);
        let x = nnls(&a, &b).unwrap();
        assert_nnls_kkt(&a, &b, &x, 1e-12);
        let wide = random_matrix(&mut rng, 4, 12);
        let b2 = random_vector(&mut rng, 4);
        let x2 = nnls(&wide, &b2).unwrap();
        assert_nnls_kkt(&wide, &b2, &x2, 1e-12);
    }

    /// Capped NNLS: matches a brute-force scan of the one-dimensional
    /// problem and satisfies the capped KKT conditions.
    #[test]
    fn nnls_capped_matches_brute_force_and_kkt() {
        // One column: min (x a − b)² with 0 ≤ x ≤ cap has x = clamp(aᵀb/aᵀa).
        let a = DMatrix::from_column_slice(3, 1, &[1.0, 2.0, 2.0]);
        let b = DVector::from_vec(vec![3.0, 6.0, 6.0]); // unconstrained x = 3
        let x = nnls_capped(&a, &b, 1.0).unwrap();
        assert!((x[0] - 1.0).abs() < 1e-12);
        let x = nnls_capped(&a, &b, 5.0).unwrap();
        assert!((x[0] - 3.0).abs() < 1e-12);

        // Random: KKT with the multiplier of the sum recomputed.
        let mut rng = SplitMix64::new(4);
        for _ in 0..20 {
            let a = random_matrix(&mut rng, 30, 7);
            let b = random_vector(&mut rng, 30) * 3.0;
            let x = nnls_capped(&a, &b, 1.0).unwrap();
            assert!(x.min() >= 0.0 && x.sum() <= 1.0 + 1e-12);
            let g = a.tr_mul(&(&a * &x - &b));
            let mu = if x.sum() > 1.0 - 1e-12 {
                let supp: Vec<usize> = (0..7).filter(|&j| x[j] > 0.0).collect();
                -supp.iter().map(|&j| g[j]).sum::<f64>() / supp.len() as f64
            } else {
                0.0
            };
            assert!(mu >= -1e-10);
            for j in 0..7 {
                let lam = g[j] + mu;
                assert!(lam >= -1e-9, "lambda {j} = {lam}");
                assert!((x[j] * lam).abs() <= 1e-9);
            }
        }
    }

    /// Two-column capped problem checked against a fine grid search over
    /// the triangle {x ≥ 0, x₁ + x₂ ≤ 1} (objective within grid resolution).
    #[test]
    fn nnls_capped_beats_grid() {
        let mut rng = SplitMix64::new(5);
        let a = random_matrix(&mut rng, 12, 2);
        let b = &a * DVector::from_vec(vec![0.9, 0.7]) + random_vector(&mut rng, 12) * 0.1;
        let x = nnls_capped(&a, &b, 1.0).unwrap();
        let f = |x: &DVector<f64>| (&a * x - &b).norm_squared();
        let best = f(&x);
        let n = 400;
        let mut grid_best = f64::INFINITY;
        for i in 0..=n {
            for k in 0..=(n - i) {
                let xv = DVector::from_vec(vec![i as f64 / n as f64, k as f64 / n as f64]);
                grid_best = grid_best.min(f(&xv));
            }
        }
        assert!(best <= grid_best + 1e-12, "{best} > {grid_best}");
        assert!(grid_best - best < 1e-3 * grid_best.max(1.0));
    }

    /// Bad inputs are errors.
    #[test]
    fn nnls_rejects_bad_input() {
        let a = DMatrix::from_element(3, 2, 1.0);
        let b = DVector::from_element(2, 1.0);
        assert!(matches!(
            nnls(&a, &b),
            Err(FitError::DimensionMismatch { .. })
        ));
        let b = DVector::from_vec(vec![1.0, f64::NAN, 0.0]);
        assert!(matches!(nnls(&a, &b), Err(FitError::InvalidInput(_))));
    }
}
