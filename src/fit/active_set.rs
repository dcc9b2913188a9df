//! Active-set re-solve of interior-point least-squares solutions.
//!
//! An interior-point method stops when the duality gap is below its
//! tolerance; for least squares that pins the *objective* to the tolerance,
//! but the weights only to roughly its square root wherever the objective is
//! flat — at an exactly reachable target for `min ½‖Rw − c‖²`, and at a
//! non-zero optimal residual for the epigraph `min τ, ‖Rw − c‖ ≤ τ` (both
//! seen in the tests of `conic`).  The
//! interior-point answer does, however, identify the optimal active set
//! reliably.  The re-solve (OSQP's "polishing") solves the problem restricted to
//! that active set exactly:
//!
//! * support `S = {j : wⱼ > λⱼ}` (primal value vs. the dual of `wⱼ ≥ 0`,
//!   both from the solver);
//! * the sum constraint is taken as active iff `1 − 1ᵀw < μ` (its dual);
//! * then `min ‖R_S v − c‖₂` (sum inactive), or
//!   `min ‖R_S v − c‖₂ s.t. 1ᵀv = 1` (sum active) solved by writing
//!   `v = 1/p + Z u` with `Z` an orthonormal basis of `1^⊥` (the last `p − 1`
//!   columns of the Householder reflector that maps `1/√p` to `e₁`), so
//!   `min ‖R_S Z u − (c − R_S 1/p)‖` is unconstrained;
//! * the least-squares problems are solved by SVD (minimum-norm solution,
//!   singular values below `1e-12·σ_max` dropped) so duplicate columns in
//!   `S` are harmless.
//!
//! If the guessed active set is not optimal (a negative entry, a violated
//! sum, a wrong-signed sum multiplier or a negative bound multiplier
//! `λⱼ = gⱼ + μ` off the support, with `g = Rᵀ(Rv − c)`), it is corrected
//! primal-dual-active-set style and the equality problem re-solved (at most
//! `2m + 5` rounds; an interior-point guess is usually right at once).
//! The caller keeps the re-solved point only if its KKT residual is not
//! larger than the interior-point one.  Everything is then verified as
//! usual.

use nalgebra::{DMatrix, DVector};

/// Relative singular-value cut-off of the re-solve's least squares.
const SVD_RCOND: f64 = 1e-12;
/// Tolerated negativity / sum excess of a re-solved point before clipping.
const ACTIVE_SET_FEAS: f64 = 1e-12;

/// Re-solves `w` on its active set (see module docs).  `bound_duals[j]` is the dual of `wⱼ ≥ 0`,
/// `sum_dual` the dual of `1ᵀw ≤ 1` (`None` without the constraint),
/// `col_norms` the column norms of `R`.
pub(crate) fn resolve_on_active_set(
    r: &DMatrix<f64>,
    c: &DVector<f64>,
    col_norms: &[f64],
    w: &DVector<f64>,
    bound_duals: &[f64],
    sum_dual: Option<f64>,
) -> Option<DVector<f64>> {
    let m = w.len();
    if bound_duals.len() != m || col_norms.len() != m {
        return None;
    }
    let capped = sum_dual.is_some();
    let mut in_s: Vec<bool> = (0..m).map(|j| w[j] > bound_duals[j]).collect();
    let mut sum_active = match sum_dual {
        Some(mu) => 1.0 - w.sum() < mu,
        None => false,
    };
    for _round in 0..(2 * m + 5) {
        let support: Vec<usize> = (0..m).filter(|&j| in_s[j]).collect();
        let v = if support.is_empty() {
            if sum_active {
                sum_active = false;
                continue;
            }
            DVector::zeros(0)
        } else {
            solve_on_support(r, c, &support, sum_active)?
        };
        if v.iter().any(|x| !x.is_finite()) {
            return None;
        }
        if capped && !sum_active && v.sum() > 1.0 + ACTIVE_SET_FEAS {
            sum_active = true;
            continue;
        }
        if drop_negative(&support, &v, &mut in_s) {
            continue;
        }
        let mut full = DVector::zeros(m);
        for (pos, &j) in support.iter().enumerate() {
            full[j] = v[pos].max(0.0);
        }
        let g = r.tr_mul(&(r * &full - c));
        let total = full.sum();
        let mu = if sum_active && total > 0.0 {
            -full.dot(&g) / total
        } else {
            0.0
        };
        if sum_active && mu < -ACTIVE_SET_FEAS {
            sum_active = false;
            continue;
        }
        if let Some(j) = most_violated_bound(&g, mu, &in_s, col_norms) {
            in_s[j] = true;
            continue;
        }
        if capped {
            let s = full.sum();
            if s > 1.0 {
                full /= s;
            }
        }
        return Some(full);
    }
    None
}

/// Drops from the support `in_s` the columns whose weight in `v` (on
/// `support`) is negative beyond the tolerance; whether any was.
fn drop_negative(support: &[usize], v: &DVector<f64>, in_s: &mut [bool]) -> bool {
    let scale = v.amax().max(1.0);
    let negative: Vec<usize> = support
        .iter()
        .zip(v.iter())
        .filter(|&(_, &x)| x < -ACTIVE_SET_FEAS * scale)
        .map(|(&j, _)| j)
        .collect();
    negative.iter().for_each(|&j| in_s[j] = false);
    !negative.is_empty()
}

/// The bound column with the most negative scaled multiplier
/// λⱼ = (gⱼ + max(μ, 0))/‖aⱼ‖ below −tolerance, if any: the KKT condition
/// it violates says it should enter the support.
fn most_violated_bound(
    g: &DVector<f64>,
    mu: f64,
    in_s: &[bool],
    col_norms: &[f64],
) -> Option<usize> {
    let mut worst: Option<(usize, f64)> = None;
    for j in 0..in_s.len() {
        if in_s[j] || col_norms[j] == 0.0 {
            continue;
        }
        let lam = (g[j] + mu.max(0.0)) / col_norms[j];
        if lam < -ACTIVE_SET_FEAS && worst.is_none_or(|(_, l)| lam < l) {
            worst = Some((j, lam));
        }
    }
    worst.map(|(j, _)| j)
}

/// `min ‖R_S v − c‖` (optionally with `1ᵀv = 1`) on the support `S`.
fn solve_on_support(
    r: &DMatrix<f64>,
    c: &DVector<f64>,
    support: &[usize],
    sum_active: bool,
) -> Option<DVector<f64>> {
    let rs = r.select_columns(support.iter());
    let p = support.len();
    if !sum_active {
        return lstsq(rs, c);
    }
    // v = 1/p + Z u, Z = columns 1.. of H = I − 2 h hᵀ/(hᵀh),
    // h = 1/√p − e₁ (H maps 1/√p to e₁ and back).
    let v0 = DVector::from_element(p, 1.0 / p as f64);
    let mut h = DVector::from_element(p, 1.0 / (p as f64).sqrt());
    h[0] -= 1.0;
    let hh = h.norm_squared();
    if p == 1 || hh == 0.0 {
        return Some(v0);
    }
    // R_S H = R_S − 2 (R_S h) hᵀ / hᵀh
    let rsh = &rs * &h;
    let rs_h = &rs - (&rsh * h.transpose()) * (2.0 / hh);
    let rz = rs_h.columns(1, p - 1).into_owned();
    let rhs = c - &rs * &v0;
    let u = lstsq(rz, &rhs)?;
    // Z u = H [0; u]
    let mut y = DVector::zeros(p);
    y.rows_mut(1, p - 1).copy_from(&u);
    let hy = h.dot(&y);
    Some(v0 + (&y - &h * (2.0 * hy / hh)))
}

/// Minimum-norm least squares by SVD.
fn lstsq(a: DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    let svd = crate::linalg::svd(a)?;
    let smax = svd.singular_values.max();
    if smax.is_nan() || smax <= 0.0 {
        return Some(DVector::zeros(svd.v_t.as_ref()?.nrows()));
    }
    svd.solve(b, SVD_RCOND * smax).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::testutil::{random_matrix, SplitMix64};

    /// With the correct support the re-solved point is the exact minimiser
    /// (unconstrained on the support) to 1e-13, and with the sum active it
    /// satisfies 1ᵀv = 1 and the equality-constrained normal equations.
    #[test]
    fn active_set_recovers_exact_minimiser() {
        let mut rng = SplitMix64::new(5);
        let r = random_matrix(&mut rng, 6, 4);
        let w_true = DVector::from_vec(vec![0.2, 0.0, 0.3, 0.1]);
        let c = &r * &w_true;
        // Perturbed "interior-point" answer with a clear support.
        let w = DVector::from_vec(vec![0.2 + 1e-6, 1e-9, 0.3 - 1e-6, 0.1 + 1e-6]);
        let duals = [1e-9, 1e-2, 1e-9, 1e-9];
        let cn: Vec<f64> = r.column_iter().map(|c| c.norm()).collect();
        let v = resolve_on_active_set(&r, &c, &cn, &w, &duals, None).unwrap();
        assert!((&v - &w_true).amax() < 1e-13, "{v}");

        // Sum active: target needs Σ = 1.2.
        let c2 = &r * DVector::from_vec(vec![0.5, 0.0, 0.4, 0.3]);
        let w2 = DVector::from_vec(vec![0.4, 1e-9, 0.35, 0.25]);
        let v2 = resolve_on_active_set(&r, &c2, &cn, &w2, &duals, Some(1.0)).unwrap();
        assert!((v2.sum() - 1.0).abs() < 1e-14);
        // Stationarity on the support: gradients equal (= −μ).
        let g = r.tr_mul(&(&r * &v2 - &c2));
        assert!((g[0] - g[2]).abs() < 1e-12 && (g[0] - g[3]).abs() < 1e-12);
    }
}
