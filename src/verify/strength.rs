//! The realised strength of a verification, measured against the target.
//!
//! A schedule's design claims a strength s: its field is to be s·t, t the
//! target's field. The realised field R (mean velocities of point parts,
//! [`crate::play::measure`]) is measured against t itself, by least
//! squares over the points that count,
//!
//! ŝ = ⟨R, t(q)⟩ / ⟨t(q), t(q)⟩,
//!
//! with t evaluated where each realised velocity belongs (q, the part's
//! mean position over the measured periods, or its start when positions
//! are frozen). A point counts when it is valid and outside every region
//! the target masks. Nothing here reads the schedule's stored
//! `fit.strength`: a schedule whose motions were edited after its design
//! reports the strength it realises, not the one it was designed for.

use crate::play::measure::RealisedField;
use crate::request::Target;

/// ŝ of `v` against `target`'s field (see the [module documentation](self));
/// `None` when no counted point has t ≠ 0 (nothing to measure against).
///
/// ```
/// use platefield::play::measure::{PointResult, RealisedField};
/// use platefield::request::Target;
/// use platefield::verify::strength::realised_strength;
///
/// let target = Target::from_json_str(
///     r#"{"grid": {"x": [-0.03, 0.03], "y": [-0.03, 0.03], "n": [5, 5]},
///         "field": {"kind": "sink", "center": [0, 0], "strength": 1}}"#,
/// )
/// .unwrap();
/// // Two parts moving at half the target's field: ŝ = 0.5.
/// let point = |q: [f64; 2]| PointResult {
///     start: q,
///     position: q,
///     realised: [-0.5 * q[0], -0.5 * q[1]],
///     predicted: [0.0; 2],
///     valid: true,
///     note: None,
///     warmup_periods: 1,
///     settled: true,
/// };
/// let v = RealisedField {
///     points: vec![point([0.01, 0.0]), point([0.0, -0.02])],
///     ..RealisedField::default()
/// };
/// let s = realised_strength(&target, &v).unwrap();
/// assert!((s - 0.5).abs() < 1e-12);
/// ```
pub fn realised_strength(target: &Target, v: &RealisedField) -> Option<f64> {
    let (mut rt, mut tt) = (0.0, 0.0);
    for p in v.points.iter().filter(|p| p.valid) {
        if target.mask.iter().any(|m| m.contains(p.position)) {
            continue;
        }
        let t = target.field.eval(p.position);
        rt += p.realised[0] * t[0] + p.realised[1] * t[1];
        tt += t[0] * t[0] + t[1] * t[1];
    }
    (tt > 0.0).then(|| rt / tt)
}
