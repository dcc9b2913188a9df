//! Quality metrics of an achieved field against a (scaled) target field.
//!
//! For points `p` with target vectors `tₚ ∈ ℝ²`, achieved vectors `aₚ ∈ ℝ²`,
//! strength `s` and optional per-point weights `ωₚ ≥ 0` (multipliers on the
//! point's residual vector, exactly like the fit's row weights `d`; default
//! 1):
//!
//! * relative L2 error `√(Σ ωₚ²‖aₚ − s tₚ‖²) / √(Σ ωₚ²‖s tₚ‖²)`;
//! * magnitude-weighted mean angle error (degrees)
//!   `Σ ωₚ‖tₚ‖ θₚ / Σ ωₚ‖tₚ‖`, with `θₚ = ∠(aₚ, tₚ) ∈ [0°, 180°]` computed as
//!   `atan2(|aₚ × tₚ|, aₚ·tₚ)`; points with `‖tₚ‖ = 0` (or `ωₚ = 0`) are
//!   skipped, points with `aₚ = 0` count as 90° (no direction);
//! * worst-point error `maxₚ ‖aₚ − s tₚ‖` over points with `ωₚ > 0`
//!   (unweighted);
//! * the strength `s` itself.

use serde::{Deserialize, Serialize};

use crate::fit::FitError;

/// Field-quality summary of a fit (see module docs for definitions).
///
/// The angle and worst-point errors are NaN where they are not defined (a
/// synthesized motion of a grid-less `sampled` target, whose field is not
/// simulated at the sample points, or of no positive strength); JSON
/// writes NaN as `null`, and `null` reads back as NaN, so such a
/// `schedule.json` loads.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FitMetrics {
    /// `‖ω(a − s t)‖₂ / ‖ω s t‖₂`.
    pub relative_l2_error: f64,
    /// `|t|`-weighted mean angle between achieved and target vectors, deg.
    #[serde(deserialize_with = "number_or_null")]
    pub mean_angle_error_deg: f64,
    /// `maxₚ ‖aₚ − s tₚ‖`.
    #[serde(deserialize_with = "number_or_null")]
    pub max_error: f64,
    /// Strength `s` the target was scaled by (1 for absolute fits).
    pub strength: f64,
}

/// A number, or `null` (a metric not defined, written from NaN) as NaN.
fn number_or_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Metrics of `achieved` against `strength · target` (see module docs).
///
/// # Errors
/// Length mismatches, negative/non-finite weights or data, or a zero
/// weighted reference field `ω s t` (relative error undefined).
pub(crate) fn field_metrics(
    target: &[[f64; 2]],
    achieved: &[[f64; 2]],
    strength: f64,
    weights: Option<&[f64]>,
) -> Result<FitMetrics, FitError> {
    let n = target.len();
    if achieved.len() != n {
        return Err(FitError::DimensionMismatch {
            what: "achieved vectors",
            expected: n,
            got: achieved.len(),
        });
    }
    if let Some(w) = weights {
        if w.len() != n {
            return Err(FitError::DimensionMismatch {
                what: "point weights",
                expected: n,
                got: w.len(),
            });
        }
        if w.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(FitError::InvalidInput(
                "point weights must be finite and >= 0".into(),
            ));
        }
    }
    let finite = |v: &[f64; 2]| v[0].is_finite() && v[1].is_finite();
    if !strength.is_finite() || !target.iter().all(finite) || !achieved.iter().all(finite) {
        return Err(FitError::InvalidInput("metrics: non-finite data".into()));
    }
    let mut err2 = 0.0;
    let mut ref2 = 0.0;
    let mut angle_num = 0.0;
    let mut angle_den = 0.0;
    let mut max_error = 0.0_f64;
    for p in 0..n {
        let om = weights.map_or(1.0, |w| w[p]);
        if om == 0.0 {
            continue;
        }
        let t = target[p];
        let a = achieved[p];
        let st = [strength * t[0], strength * t[1]];
        let e = (a[0] - st[0]).hypot(a[1] - st[1]);
        err2 += om * om * e * e;
        ref2 += om * om * (st[0] * st[0] + st[1] * st[1]);
        max_error = max_error.max(e);
        let tm = t[0].hypot(t[1]);
        if tm > 0.0 {
            let theta = if a[0] == 0.0 && a[1] == 0.0 {
                90.0
            } else {
                let cross = a[0] * t[1] - a[1] * t[0];
                let dot = a[0] * t[0] + a[1] * t[1];
                cross.abs().atan2(dot).to_degrees()
            };
            angle_num += om * tm * theta;
            angle_den += om * tm;
        }
    }
    if ref2.is_nan() || ref2 <= 0.0 {
        return Err(FitError::InvalidInput(
            "metrics: the weighted reference field s·t is zero (strength 0 or zero target)".into(),
        ));
    }
    Ok(FitMetrics {
        relative_l2_error: (err2 / ref2).sqrt(),
        mean_angle_error_deg: if angle_den > 0.0 {
            angle_num / angle_den
        } else {
            0.0
        },
        max_error,
        strength,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-computed metrics: one point rotated by 90°, one exact point.
    #[test]
    fn metrics_hand_computed() {
        let target = [[1.0, 0.0], [0.0, 2.0], [0.0, 0.0]];
        let achieved = [[0.0, 1.0], [0.0, 2.0], [0.5, 0.0]];
        let m = field_metrics(&target, &achieved, 1.0, None).unwrap();
        // errors: √2, 0, 0.5; reference norms²: 1, 4, 0.
        let expect_rel = ((2.0 + 0.25) / 5.0_f64).sqrt();
        assert!((m.relative_l2_error - expect_rel).abs() < 1e-15);
        // angles 90° (|t|=1) and 0° (|t|=2); zero-target point skipped.
        assert!((m.mean_angle_error_deg - 30.0).abs() < 1e-12);
        assert!((m.max_error - 2f64.sqrt()).abs() < 1e-15);
        assert_eq!(m.strength, 1.0);
    }

    /// Strength scales the reference; opposite vectors give 180°; weights
    /// act as multipliers (a zero weight removes the point).
    #[test]
    fn metrics_strength_angle_and_weights() {
        let target = [[1.0, 0.0], [1.0, 0.0]];
        let achieved = [[2.0, 0.0], [-2.0, 0.0]];
        let m = field_metrics(&target, &achieved, 2.0, Some(&[1.0, 0.0])).unwrap();
        assert_eq!(m.relative_l2_error, 0.0);
        assert_eq!(m.mean_angle_error_deg, 0.0);
        assert_eq!(m.max_error, 0.0);
        let m = field_metrics(&target, &achieved, 2.0, None).unwrap();
        assert!((m.mean_angle_error_deg - 90.0).abs() < 1e-12);
        assert!((m.relative_l2_error - (16.0 / 8.0_f64).sqrt()).abs() < 1e-15);
        assert!(field_metrics(&target, &achieved, 0.0, None).is_err());
        assert_serialize(&m);
    }

    /// Compile-time check that the metrics struct is serde-serialisable.
    fn assert_serialize<T: Serialize>(_: &T) {}
}
