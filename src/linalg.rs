//! Decompositions that always end. nalgebra's SVD iterates until its
//! off-diagonal entries vanish and, by default, without a bound on the
//! iterations: on a matrix holding an infinity or a NaN they never vanish
//! and the SVD never returns. Every SVD of the crate goes through [`svd`],
//! which refuses non-finite input and bounds the iterations. (LU, QR and
//! Cholesky are direct: they end on any input, with non-finite results
//! that their callers check.)

use nalgebra::{DMatrix, SVD};

/// Iterations an SVD may take per singular value before it is given up:
/// a converging bidiagonal QR takes 2-3 per value, so 1000 only stops one
/// that never converges.
const SVD_ITERATIONS_PER_VALUE: usize = 1000;

/// Convergence threshold of an off-diagonal entry, relative: nalgebra's
/// own `svd`'s (5 ε), so that a finite matrix decomposes to the same bits.
const SVD_EPS: f64 = 5.0 * f64::EPSILON;

/// Whether every entry of `m` is finite.
pub(crate) fn all_finite<'a>(m: impl IntoIterator<Item = &'a f64>) -> bool {
    m.into_iter().all(|x| x.is_finite())
}

/// The SVD of `m` (with U and Vᵀ), or `None` when an entry of `m` is not
/// finite or the iteration does not converge within
/// `SVD_ITERATIONS_PER_VALUE` per singular value.
pub(crate) fn svd(m: DMatrix<f64>) -> Option<SVD<f64, nalgebra::Dyn, nalgebra::Dyn>> {
    if !all_finite(m.iter()) {
        return None;
    }
    let max = SVD_ITERATIONS_PER_VALUE * m.nrows().min(m.ncols()).max(1);
    m.try_svd(true, true, SVD_EPS, max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A matrix with an infinity or a NaN gives `None` at once (nalgebra's
    /// own `svd` never returns on it); a finite one its exact singular
    /// values.
    #[test]
    fn svd_refuses_non_finite_input_and_solves_finite() {
        for bad in [f64::INFINITY, f64::NAN, f64::NEG_INFINITY] {
            let m = DMatrix::from_row_slice(2, 2, &[1.0, bad, 0.0, 1.0]);
            assert!(svd(m).is_none(), "{bad}");
        }
        let m = DMatrix::from_row_slice(2, 2, &[3.0, 0.0, 0.0, -2.0]);
        let s = svd(m).unwrap().singular_values;
        assert!((s[0] - 3.0).abs() < 1e-15 && (s[1] - 2.0).abs() < 1e-15);
        // 1e300 entries square to infinity inside a naive norm; the SVD
        // scales them and stays finite.
        let m = DMatrix::from_row_slice(2, 2, &[1e300, 0.0, 0.0, 1e300]);
        let s = svd(m).unwrap().singular_values;
        assert!((s[0] / 1e300 - 1.0).abs() < 1e-15);
    }
}
