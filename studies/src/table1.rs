//! Least-squares fits of simulated primitive fields to the forms of the
//! paper's Table I.
//!
//! Each form is linear in its coefficients: f(p) ≈ Σ c_i φ_i(p). The fit
//! minimises Σ_p |f(p) − Σ c_i φ_i(p)|² over the valid samples (and, for
//! Circle, outside 1 cm of its axis, where a(−y, x)/r is singular). Because
//! the forms have no constant term, R² is the uncentred one:
//! R² = 1 − Σ|f − f̂|² / Σ|f|².

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use platefield::basis::PrimitiveKind;
use platefield::field::{Field, Validity};

/// A fitted Table I form.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct FormFit {
    /// The form, as in Table I.
    pub form: &'static str,
    /// Coefficients (a, or a and b for DivCircle).
    pub coefficients: Vec<f64>,
    /// Uncentred coefficient of determination.
    pub r2: f64,
    /// Samples used.
    pub samples: usize,
    /// True when the form's leading coefficient a has Table I's sign
    /// (positive; DivCircle's second coefficient b is reported, not
    /// checked).
    pub signs_ok: bool,
}

type Basis = fn(f64, f64) -> [f64; 2];

/// The form's text and basis vector fields for `kind`.
pub fn form(kind: PrimitiveKind) -> (&'static str, Vec<Basis>) {
    match kind {
        PrimitiveKind::Trans => ("a(1, 0)", vec![|_, _| [1.0, 0.0]]),
        PrimitiveKind::ScaledCircle => ("a(-y, x)", vec![|x, y| [-y, x]]),
        PrimitiveKind::Circle => (
            "a(-y, x)/r",
            vec![|x, y| {
                let r = x.hypot(y);
                [-y / r, x / r]
            }],
        ),
        PrimitiveKind::DivCircle => (
            "(a x y, b x^2)",
            vec![|x, y| [x * y, 0.0], |x, _| [0.0, x * x]],
        ),
        PrimitiveKind::LineSink => ("a(-x, 0)", vec![|x, _| [-x, 0.0]]),
        PrimitiveKind::LineSource => ("a(x, 0)", vec![|x, _| [x, 0.0]]),
        PrimitiveKind::SkewSink => ("a(-x, x)", vec![|x, _| [-x, x]]),
        PrimitiveKind::SkewSource => ("a(x, -x)", vec![|x, _| [x, -x]]),
    }
}

/// Fits `field` to the Table I form of `kind`.
pub fn fit(kind: PrimitiveKind, field: &Field) -> FormFit {
    let (text, basis) = form(kind);
    let rows: Vec<([f64; 2], [f64; 2])> = field
        .grid
        .points()
        .into_iter()
        .zip(field.vectors.iter().zip(&field.validity))
        .filter(|(p, (_, v))| {
            **v == Validity::Ok && (kind != PrimitiveKind::Circle || p[0].hypot(p[1]) >= 0.01)
        })
        .map(|(p, (f, _))| (p, *f))
        .collect();
    let m = basis.len();
    let mut a = DMatrix::zeros(2 * rows.len(), m);
    let mut b = DVector::zeros(2 * rows.len());
    for (i, (p, f)) in rows.iter().enumerate() {
        for (j, phi) in basis.iter().enumerate() {
            let v = phi(p[0], p[1]);
            a[(2 * i, j)] = v[0];
            a[(2 * i + 1, j)] = v[1];
        }
        b[2 * i] = f[0];
        b[2 * i + 1] = f[1];
    }
    let coefficients: Vec<f64> = a
        .clone()
        .svd(true, true)
        .solve(&b, 1e-14)
        .map(|c| c.iter().copied().collect())
        .unwrap_or_else(|_| vec![0.0; m]);
    let fitted = &a * DVector::from_column_slice(&coefficients);
    let ss_res = (&b - fitted).norm_squared();
    let ss_tot = b.norm_squared();
    FormFit {
        form: text,
        signs_ok: coefficients.first().is_some_and(|a| *a > 0.0),
        coefficients,
        r2: if ss_tot > 0.0 {
            1.0 - ss_res / ss_tot
        } else {
            0.0
        },
        samples: rows.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use platefield::field::{FieldKind, Grid};

    /// A field that is exactly Σ c_i φ_i of `kind`'s form, plus `extra`(p).
    fn synthetic(kind: PrimitiveKind, c: &[f64], extra: fn(f64, f64) -> [f64; 2]) -> Field {
        let grid = Grid {
            x: [-0.04, 0.04],
            y: [-0.04, 0.04],
            n: [9, 9],
        };
        let (_, basis) = form(kind);
        let vectors = grid
            .points()
            .iter()
            .map(|p| {
                let mut v = extra(p[0], p[1]);
                for (ci, phi) in c.iter().zip(&basis) {
                    let f = phi(p[0], p[1]);
                    v[0] += ci * f[0];
                    v[1] += ci * f[1];
                }
                v
            })
            .collect();
        Field {
            validity: vec![Validity::Ok; grid.len()],
            grid,
            kind: FieldKind::Force,
            vectors,
        }
    }

    /// A field that is exactly the form gives back its coefficients (to
    /// 1e-12) at R² = 1, and the sign check reads the leading one; a
    /// component no form holds (a uniform (0, 0.05)) lowers R².
    #[test]
    fn exact_forms_are_recovered() {
        for kind in PrimitiveKind::ALL {
            let n = form(kind).1.len();
            for c in [vec![0.7, -1.3], vec![-0.7, 1.3]] {
                let c = &c[..n];
                let f = fit(kind, &synthetic(kind, c, |_, _| [0.0, 0.0]));
                for (got, want) in f.coefficients.iter().zip(c) {
                    assert!(
                        (got - want).abs() <= 1e-12 * want.abs(),
                        "{kind:?}: {got} vs {want}"
                    );
                }
                assert!((f.r2 - 1.0).abs() < 1e-12, "{kind:?}: R² {}", f.r2);
                assert_eq!(f.signs_ok, c[0] > 0.0, "{kind:?}");
            }
            let off = fit(
                kind,
                &synthetic(kind, &[0.7, -1.3][..n], |_, _| [0.0, 0.05]),
            );
            assert!(off.r2 < 1.0 - 1e-6, "{kind:?}: R² {}", off.r2);
        }
    }
}
