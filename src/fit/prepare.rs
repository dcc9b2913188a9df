//! Input validation, row weighting, normalisation and QR compression.
//!
//! Given `A ∈ ℝ^{2n×m}`, `t ∈ ℝ^{2n}` and row weights `d ≥ 0`, rows with
//! `dᵢ = 0` are dropped and the remaining rows are scaled,
//!
//! ```text
//! Â = D A / ‖Dt‖₂,     t̂ = D t / ‖Dt‖₂     (so ‖t̂‖₂ = 1),
//! ```
//!
//! which leaves the time fractions `w` and the strength `s` of every mode
//! unchanged while making absolute solver tolerances meaningful.
//!
//! A thin Householder QR `Â = Q R` (`Q ∈ ℝ^{M×k}` orthonormal, `R ∈ ℝ^{k×m}`,
//! `k = min(M, m)`) then gives the exact identity
//!
//! ```text
//! ‖Âw − s t̂‖₂² = ‖Rw − s c‖₂² + s² r₀²,   c = Qᵀt̂,  r₀ = ‖(I − QQᵀ) t̂‖₂,
//! ```
//!
//! for every `w` and `s`, so the least-squares modes can be posed on the
//! small `k×m` matrix `R` without ever forming `ÂᵀÂ`.  `r₀` is taken from
//! the tail of `Hᵀt̂` (the full Householder product) rather than from
//! `1 − ‖c‖²`, which would cancel catastrophically for near-exact fits.

use nalgebra::{DMatrix, DVector};

use crate::fit::{FitError, FitProblem};

/// Weighted, normalised and compressed problem data (see module docs).
#[derive(Debug, Clone)]
pub(crate) struct Prepared {
    /// `Â = DA/‖Dt‖` with zero-weight rows removed (`M×m`).
    pub ad: DMatrix<f64>,
    /// `t̂ = Dt/‖Dt‖` (unit norm).
    pub td: DVector<f64>,
    /// `‖Dt‖₂` in the caller's units.
    pub tnorm: f64,
    /// `R` of the thin QR of `Â` (`k×m`).
    pub r: DMatrix<f64>,
    /// `c = Qᵀ t̂` (`k`).
    pub c: DVector<f64>,
    /// `r₀ = ‖(I − QQᵀ) t̂‖`, the part of the target no mix can reach.
    pub r0: f64,
    /// Column norms of `Â`.
    pub col_norms: Vec<f64>,
}

impl Prepared {
    /// Validate, weight, normalise and compress `problem`.
    pub(crate) fn new(problem: &FitProblem) -> Result<Self, FitError> {
        let a = problem.a;
        let t = problem.t;
        let (rows, m) = a.shape();
        if m == 0 {
            return Err(FitError::InvalidInput("basis has no columns".into()));
        }
        if rows == 0 {
            return Err(FitError::InvalidInput("basis has no rows".into()));
        }
        if t.len() != rows {
            return Err(FitError::DimensionMismatch {
                what: "target t",
                expected: rows,
                got: t.len(),
            });
        }
        if let Some(d) = problem.row_weights {
            if d.len() != rows {
                return Err(FitError::DimensionMismatch {
                    what: "row_weights",
                    expected: rows,
                    got: d.len(),
                });
            }
            if let Some(i) = d.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
                return Err(FitError::InvalidInput(format!(
                    "row weight {i} is {} (must be finite and >= 0)",
                    d[i]
                )));
            }
        }
        if a.iter().any(|v| !v.is_finite()) {
            return Err(FitError::InvalidInput(
                "basis matrix has non-finite entries".into(),
            ));
        }
        if t.iter().any(|v| !v.is_finite()) {
            return Err(FitError::InvalidInput(
                "target has non-finite entries".into(),
            ));
        }

        let keep: Vec<(usize, f64)> = match problem.row_weights {
            None => (0..rows).map(|i| (i, 1.0)).collect(),
            Some(d) => (0..rows)
                .filter(|&i| d[i] > 0.0)
                .map(|i| (i, d[i]))
                .collect(),
        };
        if keep.is_empty() {
            return Err(FitError::InvalidInput("all row weights are zero".into()));
        }
        let mr = keep.len();
        let td_raw = DVector::from_iterator(mr, keep.iter().map(|&(i, di)| di * t[i]));
        let tnorm = td_raw.norm();
        if !(tnorm > 0.0 && tnorm.is_finite()) {
            return Err(FitError::InvalidInput(
                "weighted target D·t is zero (or overflows): nothing to fit".into(),
            ));
        }
        let ad = DMatrix::from_fn(mr, m, |r, j| {
            let (i, di) = keep[r];
            di * a[(i, j)] / tnorm
        });
        let td = td_raw / tnorm;
        Ok(Self::from_weighted(ad, td, tnorm))
    }

    /// Build from already weighted and normalised data (`‖td‖ = 1`).
    pub(crate) fn from_weighted(ad: DMatrix<f64>, td: DVector<f64>, tnorm: f64) -> Self {
        let (r, c, r0) = compress(&ad, &td);
        let col_norms = ad.column_iter().map(|c| c.norm()).collect();
        Self {
            ad,
            td,
            tnorm,
            r,
            c,
            r0,
            col_norms,
        }
    }

    /// Number of basis columns `m`.
    pub(crate) fn ncols(&self) -> usize {
        self.ad.ncols()
    }

    /// Number of (kept) residual rows.
    pub(crate) fn nrows(&self) -> usize {
        self.ad.nrows()
    }

    /// The same problem restricted to the columns `cols` (in that order).
    ///
    /// The compressed form is obtained from the columns of `R` (a further
    /// QR of `R_S`, with `r₀` combined in quadrature), the full rows from
    /// the columns of `Â`.
    pub(crate) fn subset(&self, cols: &[usize]) -> Self {
        let ad = self.ad.select_columns(cols.iter());
        let rs = self.r.select_columns(cols.iter());
        let (r, c, r0_inner) = compress(&rs, &self.c);
        let col_norms = cols.iter().map(|&j| self.col_norms[j]).collect();
        Self {
            ad,
            td: self.td.clone(),
            tnorm: self.tnorm,
            r,
            c,
            r0: self.r0.hypot(r0_inner),
            col_norms,
        }
    }

    /// `‖Âw − s t̂‖₂` evaluated on the full rows.
    pub(crate) fn residual_norm(&self, w: &DVector<f64>, s: f64) -> f64 {
        (&self.ad * w - &self.td * s).norm()
    }
}

/// Thin QR compression: returns `(R, c, r₀)` with
/// `‖Ew − f‖² = ‖Rw − c‖² + r₀²` for all `w`.
pub(crate) fn compress(e: &DMatrix<f64>, f: &DVector<f64>) -> (DMatrix<f64>, DVector<f64>, f64) {
    let (rows, m) = e.shape();
    let k = rows.min(m);
    let qr = e.clone().qr();
    let r = qr.r();
    let mut qtf = f.clone();
    qr.q_tr_mul(&mut qtf);
    let c = qtf.rows(0, k).into_owned();
    let r0 = if rows > k {
        qtf.rows(k, rows - k).norm()
    } else {
        0.0
    };
    (r, c, r0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::testutil::{random_matrix, random_vector, SplitMix64};

    /// The compression identity ‖Ew − f‖² = ‖Rw − c‖² + r₀² holds to
    /// rounding for random w (relative 1e-12).
    #[test]
    fn compression_identity_holds() {
        let mut rng = SplitMix64::new(7);
        let e = random_matrix(&mut rng, 60, 8);
        let f = random_vector(&mut rng, 60);
        let (r, c, r0) = compress(&e, &f);
        assert_eq!(r.shape(), (8, 8));
        for _ in 0..5 {
            let w = random_vector(&mut rng, 8);
            let lhs = (&e * &w - &f).norm_squared();
            let rhs = (&r * &w - &c).norm_squared() + r0 * r0;
            assert!((lhs - rhs).abs() <= 1e-12 * lhs, "{lhs} vs {rhs}");
        }
    }

    /// Zero-weight rows are dropped and the target is normalised.
    #[test]
    fn weights_drop_rows_and_normalise() {
        let a = DMatrix::from_row_slice(3, 1, &[1.0, 2.0, 3.0]);
        let t = DVector::from_vec(vec![3.0, 4.0, 100.0]);
        let d = DVector::from_vec(vec![1.0, 1.0, 0.0]);
        let p = Prepared::new(&FitProblem {
            a: &a,
            t: &t,
            row_weights: Some(&d),
        })
        .unwrap();
        assert_eq!(p.nrows(), 2);
        assert!((p.tnorm - 5.0).abs() < 1e-15);
        assert!((p.td.norm() - 1.0).abs() < 1e-15);
        assert!((p.ad[(1, 0)] - 0.4).abs() < 1e-15);
    }

    /// Bad inputs are typed errors, not panics.
    #[test]
    fn invalid_inputs_are_rejected() {
        let a = DMatrix::from_element(4, 2, 1.0);
        let t = DVector::from_element(3, 1.0);
        assert!(matches!(
            Prepared::new(&FitProblem::new(&a, &t)),
            Err(FitError::DimensionMismatch { .. })
        ));
        let t0 = DVector::zeros(4);
        assert!(matches!(
            Prepared::new(&FitProblem::new(&a, &t0)),
            Err(FitError::InvalidInput(_))
        ));
        let t1 = DVector::from_element(4, 1.0);
        let dneg = DVector::from_vec(vec![1.0, -1.0, 1.0, 1.0]);
        assert!(matches!(
            Prepared::new(&FitProblem {
                a: &a,
                t: &t1,
                row_weights: Some(&dneg)
            }),
            Err(FitError::InvalidInput(_))
        ));
        let mut anan = a.clone();
        anan[(0, 0)] = f64::NAN;
        assert!(matches!(
            Prepared::new(&FitProblem::new(&anan, &t1)),
            Err(FitError::InvalidInput(_))
        ));
    }
}
