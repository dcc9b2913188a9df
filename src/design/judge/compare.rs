//! The judge's comparison: a realised mean velocity field R against the
//! promise s·t (strength s times the target field t), with the target's
//! weights and mask.
//!
//! **Realised error.** With the target's weights ω_k of the played points
//! (0 where masked; masked points are not played), which multiply the
//! residual as in the design's own metrics (`crate::fit::metrics`):
//!
//! ```text
//! error(s)    = ‖R − P(s)‖ / ‖P(s)‖,   ‖v‖² = Σ_k ω_k² |v_k|²
//! ŝ           : ⟨R − P(ŝ), P(ŝ)⟩ = 0  (the least-squares scale: the realised strength)
//! shape error = error(ŝ)             (scale-free: cannot be gamed by the strength)
//! ```
//!
//! P(s) is the promise where the velocity was measured. For the judge's
//! held parts it is s·t(p) at the held point p, and ŝ = ⟨R, t⟩/⟨t, t⟩.
//! For parts that moved while measured (`crate::play::windowed`), it is the
//! mean velocity over the same windows of a part that follows s·t exactly
//! ([`PointPlay::expected`]), nearly linear in s; ŝ is then found by a
//! fixed-point iteration.
//!
//! **Decomposition** of the error field e = R − P(s) by weighted least squares
//! over the affine fields e(q) ≈ c + α q̃ + β J q̃ + S q̃ (q̃ = q minus the
//! weighted centroid, J the 90° rotation, S symmetric and traceless): the
//! offset c, the isotropic part α (for a sink target, a pure change of
//! strength), the rotational (whirlpool) part β, the anisotropic (shear)
//! part S and what the affine fit leaves, each as its norm relative to ‖P(s)‖,
//! over the points q where the velocity belongs.
//!
//! **Grid-less sampled targets.** The target wherever a part is measured
//! is the samples' interpolant ([`crate::request::SampledInterpolant`]: a
//! local linear fit on a node grid, weights computed once per point set,
//! exact for an affine field), one field for every part, so the flow of
//! the promise costs four node values per evaluation where an
//! inverse-distance interpolation would search every sample at every step.
//! (A moving part's own start sample's local model would be extrapolated
//! to wherever the part has gone — for a whirlpool, the centre, where a
//! few per cent of gradient error is the whole field: a sequenced schedule
//! realising a fraction of a 40-point whirlpool measures a shape error over
//! 100 % that way.) Gridded targets evaluate their field (`Promise::Field`).

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::request::{FieldSpec, SampledInterpolant, Target};

pub use crate::play::measure::PointPlay;

/// The promise s·t at each of `plays` as a part following it exactly would
/// realise it over the play's windows ([`PointPlay::expected`]).
pub(crate) fn promised(target: &Target, plays: &[&PointPlay], s: f64) -> Vec<[f64; 2]> {
    Promise::of(target).along(plays, s)
}

/// The target t a part follows, built once per target (see the module
/// documentation).
#[derive(Debug, Clone)]
pub(crate) enum Promise<'a> {
    /// The target's field, evaluated where the part is.
    Field(&'a FieldSpec),
    /// A grid-less sampled target: its samples' interpolant.
    Sampled(SampledInterpolant),
}

impl<'a> Promise<'a> {
    /// The promise of `target`: [`Promise::Sampled`] for a grid-less
    /// `sampled` target, else [`Promise::Field`].
    pub(crate) fn of(target: &'a Target) -> Promise<'a> {
        match (&target.grid, &target.field) {
            (None, FieldSpec::Sampled { .. }) => target
                .field
                .interpolant()
                .map_or(Promise::Field(&target.field), Promise::Sampled),
            _ => Promise::Field(&target.field),
        }
    }

    /// t at `p`.
    pub(crate) fn at(&self, p: [f64; 2]) -> [f64; 2] {
        match self {
            Promise::Field(f) => f.eval(p),
            Promise::Sampled(g) => g.eval(p),
        }
    }

    /// The promise s·t at each of `plays` ([`promised`]).
    pub(crate) fn along(&self, plays: &[&PointPlay], s: f64) -> Vec<[f64; 2]> {
        plays
            .iter()
            .map(|p| {
                let Ok(v) = p.expected::<std::convert::Infallible>(&mut |r| {
                    let v = self.at(r);
                    Ok([s * v[0], s * v[1]])
                });
                v
            })
            .collect()
    }
}

/// The realised error of a played schedule against a promised strength.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RealisedError {
    /// Promised strength s.
    pub strength: f64,
    /// ‖R − P(s)‖/‖P(s)‖.
    pub error: f64,
    /// The least-squares scale ŝ: the realised strength.
    pub realised_strength: f64,
    /// ‖R − P(ŝ)‖/‖P(ŝ)‖.
    pub shape_error: f64,
    /// Decomposition of R − s t.
    pub decomposition: Decomposition,
    /// Points used (valid, weight > 0).
    pub valid: usize,
}

impl RealisedError {
    /// The worst case of one motion's played measures under several
    /// physics (`crate::synth::robust`): the measure with the largest
    /// shape error (a non-finite one counts as largest), with the weakest
    /// realised strength and the fewest valid points of all. `None` for no
    /// measures.
    pub(crate) fn worst_of(all: &[RealisedError]) -> Option<RealisedError> {
        let key = |r: &RealisedError| {
            if r.shape_error.is_finite() {
                r.shape_error
            } else {
                f64::INFINITY
            }
        };
        let worst = all.iter().max_by(|a, b| key(a).total_cmp(&key(b)))?;
        Some(RealisedError {
            realised_strength: all
                .iter()
                .map(|r| r.realised_strength)
                .fold(worst.realised_strength, f64::min),
            valid: all.iter().map(|r| r.valid).min().unwrap_or(worst.valid),
            ..*worst
        })
    }
}

/// Affine decomposition of an error field, each part's norm relative to
/// ‖s t‖ (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Decomposition {
    /// Isotropic (divergence) part α q̃ (for a sink: a change of strength).
    pub isotropic: f64,
    /// Rotational (curl, whirlpool) part β J q̃.
    pub rotational: f64,
    /// Anisotropic (shear) part S q̃.
    pub anisotropic: f64,
    /// Uniform offset c.
    pub offset: f64,
    /// What the affine fit leaves.
    pub remainder: f64,
    /// α (1/s); for a sink target of strength k, the realised field is
    /// −(s k − α) q̃: α > 0 is a weaker sink.
    pub alpha: f64,
    /// β (1/s): the realised field turns counter-clockwise for β > 0.
    pub beta: f64,
}

/// Whether `play` counts in the realised measure: valid, with weight > 0.
pub fn counts(weights: &[f64], play: &PointPlay) -> bool {
    play.note.is_none() && weights[play.index] > 0.0
}

/// The points of `plays` that count ([`counts`]).
fn counted<'a>(weights: &[f64], plays: &'a [PointPlay]) -> Vec<&'a PointPlay> {
    plays.iter().filter(|p| counts(weights, p)).collect()
}

/// Realised error of `plays` against the promise `strength`·target (see
/// the module documentation; weights indexed by [`PointPlay::index`]). With `strength` `None`, the promise is the
/// realised strength ŝ (then `error` equals `shape_error`).
pub fn realised_error(
    target: &Target,
    weights: &[f64],
    plays: &[PointPlay],
    strength: Option<f64>,
) -> RealisedError {
    realised_error_of(&Promise::of(target), weights, plays, strength)
}

/// [`realised_error`] against a [`Promise`] built once (a grid-less
/// sampled target's interpolant costs a search of its samples per node:
/// a caller that measures many plays builds it once).
pub(crate) fn realised_error_of(
    promise: &Promise<'_>,
    weights: &[f64],
    plays: &[PointPlay],
    strength: Option<f64>,
) -> RealisedError {
    let ok = counted(weights, plays);
    let q: Vec<[f64; 2]> = ok.iter().map(|p| p.position).collect();
    // ω² (the target's weight multiplies the residual, as in the design's metrics).
    let w: Vec<f64> = ok.iter().map(|p| weights[p.index].powi(2)).collect();
    let r: Vec<[f64; 2]> = ok.iter().map(|p| p.realised).collect();
    let dot = |a: &[[f64; 2]], b: &[[f64; 2]]| -> f64 {
        a.iter()
            .zip(b)
            .zip(&w)
            .map(|((x, y), w)| w * (x[0] * y[0] + x[1] * y[1]))
            .sum()
    };
    // ŝ by fixed-point iteration s ← s⟨R, P(s)⟩/⟨P(s), P(s)⟩ from the
    // scale of R on t at the mean positions.
    let t: Vec<[f64; 2]> = ok.iter().map(|p| promise.at(p.position)).collect();
    let tt = dot(&t, &t);
    let mut s_hat = if tt > 0.0 { dot(&r, &t) / tt } else { 0.0 };
    for _ in 0..50 {
        let p = promise.along(&ok, s_hat);
        let pp = dot(&p, &p);
        if pp.is_nan() || pp <= 0.0 {
            break;
        }
        let next = s_hat * dot(&r, &p) / pp;
        let done = (next - s_hat).abs() <= 1e-13 * next.abs();
        s_hat = next;
        if done {
            break;
        }
    }
    let s = strength.unwrap_or(s_hat);
    let residual = |s: f64| -> (Vec<[f64; 2]>, f64) {
        let p = promise.along(&ok, s);
        let e: Vec<[f64; 2]> = r
            .iter()
            .zip(&p)
            .map(|(a, b)| [a[0] - b[0], a[1] - b[1]])
            .collect();
        (e, dot(&p, &p))
    };
    let rel = |s: f64| -> f64 {
        let (e, den) = residual(s);
        if den > 0.0 {
            (dot(&e, &e) / den).sqrt()
        } else {
            f64::INFINITY
        }
    };
    let (e, den) = residual(s);
    RealisedError {
        strength: s,
        error: rel(s),
        realised_strength: s_hat,
        shape_error: rel(s_hat),
        decomposition: decompose(&q, &e, &w, den.sqrt()),
        valid: ok.len(),
    }
}

/// Weighted least-squares affine decomposition of `e` over positions `q`,
/// norms relative to `scale`; every part NaN (not measured) without a
/// point.
fn decompose(q: &[[f64; 2]], e: &[[f64; 2]], w: &[f64], scale: f64) -> Decomposition {
    let n = q.len();
    if n == 0 {
        return Decomposition {
            isotropic: f64::NAN,
            rotational: f64::NAN,
            anisotropic: f64::NAN,
            offset: f64::NAN,
            remainder: f64::NAN,
            alpha: f64::NAN,
            beta: f64::NAN,
        };
    }
    let wsum: f64 = w.iter().sum();
    let mut c = [0.0; 2];
    if wsum > 0.0 {
        for (p, wi) in q.iter().zip(w) {
            c[0] += wi * p[0] / wsum;
            c[1] += wi * p[1] / wsum;
        }
    }
    // Unknowns: c_x, c_y, α, β, S = [[s1, s2], [s2, −s1]].
    let mut a = DMatrix::zeros(2 * n, 6);
    let mut b = DVector::zeros(2 * n);
    for i in 0..n {
        let sw = w[i].sqrt();
        let (x, y) = (q[i][0] - c[0], q[i][1] - c[1]);
        let f = [[1.0, 0.0], [0.0, 1.0], [x, y], [-y, x], [x, -y], [y, x]];
        for (k, fk) in f.iter().enumerate() {
            a[(2 * i, k)] = sw * fk[0];
            a[(2 * i + 1, k)] = sw * fk[1];
        }
        b[2 * i] = sw * e[i][0];
        b[2 * i + 1] = sw * e[i][1];
    }
    // A non-finite residual (a replayed file of huge accelerations)
    // leaves every part unmeasured rather than an SVD that never ends.
    let x = crate::linalg::svd(a.clone())
        .filter(|_| crate::linalg::all_finite(b.iter()))
        .and_then(|svd| svd.solve(&b, 1e-12).ok())
        .unwrap_or_else(|| DVector::from_element(6, f64::NAN));
    let scale = if scale > 0.0 { scale } else { f64::INFINITY };
    let part = |ks: &[usize]| -> f64 {
        let mut v = DVector::zeros(2 * n);
        for &k in ks {
            v += a.column(k) * x[k];
        }
        v.norm() / scale
    };
    Decomposition {
        isotropic: part(&[2]),
        rotational: part(&[3]),
        anisotropic: part(&[4, 5]),
        offset: part(&[0, 1]),
        remainder: (&b - &a * &x).norm() / scale,
        alpha: x[2],
        beta: x[3],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sink_target() -> Target {
        Target::from_json_str(
            r#"{"name": "s", "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [5, 5]},
                "field": {"kind": "sink", "center": [0.0, 0.0], "strength": 1.0}}"#,
        )
        .unwrap()
    }

    /// No valid point (every part lost contact): nothing is measured —
    /// zero valid points and NaN metrics, not a panic (the SVD of an empty
    /// system would panic).
    #[test]
    fn no_valid_point_measures_nothing() {
        let target = sink_target();
        let sampled = target.sample().unwrap();
        let plays: Vec<PointPlay> = sampled
            .points
            .iter()
            .enumerate()
            .map(|(i, p)| PointPlay {
                index: i,
                start: *p,
                position: *p,
                realised: [0.0, 0.0],
                window_starts: vec![],
                span: 0.0,
                periods: 0,
                moving: false,
                contributions: vec![],
                note: Some("contact lost".into()),
                lost_at: Some(*p),
                warmup_periods: 0,
                settled: true,
            })
            .collect();
        let e = realised_error(&target, &sampled.weights, &plays, Some(1.0));
        assert_eq!(e.valid, 0);
        assert!(e.decomposition.alpha.is_nan() && !e.shape_error.is_finite());
    }

    /// Synthetic realised fields with known parts: the metrics and the
    /// decomposition recover them exactly.
    #[test]
    fn error_and_decomposition_of_known_fields() {
        let target = sink_target();
        let sampled = target.sample().unwrap();
        let (s, alpha, beta, off) = (0.3, 0.06, 0.015, [0.0003, -0.0001]);
        let plays: Vec<PointPlay> = sampled
            .points
            .iter()
            .enumerate()
            .map(|(i, p)| {
                // R = −(s − α) q + β J q + c
                let r = [
                    -(s - alpha) * p[0] - beta * p[1] + off[0],
                    -(s - alpha) * p[1] + beta * p[0] + off[1],
                ];
                PointPlay {
                    index: i,
                    start: *p,
                    position: *p,
                    realised: r,
                    window_starts: vec![*p],
                    span: 1.0,
                    periods: 1,
                    moving: false,
                    contributions: vec![],
                    note: None,
                    lost_at: None,
                    warmup_periods: 0,
                    settled: true,
                }
            })
            .collect();
        let e = realised_error(&target, &sampled.weights, &plays, Some(s));
        let d = e.decomposition;
        assert!((d.alpha - alpha).abs() < 1e-12, "{d:?}");
        assert!((d.beta - beta).abs() < 1e-12, "{d:?}");
        assert!(d.anisotropic < 1e-12 && d.remainder < 1e-12, "{d:?}");
        // On a grid symmetric about the centre the parts are orthogonal:
        // error² = isotropic² + rotational² + offset².
        let sum = d.isotropic.powi(2) + d.rotational.powi(2) + d.offset.powi(2);
        assert!((e.error.powi(2) - sum).abs() < 1e-12, "{e:?}");
        // The isotropic part alone: α/s (a weaker sink).
        assert!((d.isotropic - alpha / s).abs() < 1e-12);
        // ŝ: the rotation and the offset are orthogonal to t on this grid.
        assert!((e.realised_strength - (s - alpha)).abs() < 1e-12);
        // Shape residual β J q + c against ŝ t = −(s − α) q.
        let q2: f64 = sampled
            .points
            .iter()
            .map(|p| p[0] * p[0] + p[1] * p[1])
            .sum();
        let off2 = sampled.len() as f64 * (off[0] * off[0] + off[1] * off[1]);
        let expect = (beta * beta * q2 + off2).sqrt() / ((s - alpha) * q2.sqrt());
        assert!(
            (e.shape_error - expect).abs() < 1e-12,
            "{} vs {expect}",
            e.shape_error
        );
        // Against the design's metric code, with uneven weights.
        let uneven: Vec<f64> = (0..sampled.len()).map(|i| 0.5 + (i % 3) as f64).collect();
        let e2 = realised_error(&target, &uneven, &plays, Some(s));
        let t: Vec<[f64; 2]> = plays
            .iter()
            .map(|p| target.field.eval(p.position))
            .collect();
        let r: Vec<[f64; 2]> = plays.iter().map(|p| p.realised).collect();
        let fm = crate::fit::field_metrics(&t, &r, s, Some(&uneven)).unwrap();
        assert!(
            (fm.relative_l2_error - e2.error).abs() < 1e-12,
            "{fm:?} {e2:?}"
        );
        // No promise given: the promise is ŝ.
        let own = realised_error(&target, &sampled.weights, &plays, None);
        assert_eq!(own.error, own.shape_error);
        assert!(own.error <= e.error);
    }

    /// A whirlpool (strength 1, rotation 1) sampled at `n` scattered points
    /// of ±4 cm with 5 % noise (proportional to |v|, a fixed sequence), as
    /// a grid-less target; the target's grid-free JSON text.
    fn noisy_whirlpool_json(n: usize) -> String {
        let (mut points, mut vectors) = (Vec::new(), Vec::new());
        for k in 0..n {
            let t = k as f64;
            let p = [
                0.04 * (2.0 * ((0.618_034 * t + 0.1) % 1.0) - 1.0),
                0.04 * (2.0 * ((0.754_878 * t + 0.3) % 1.0) - 1.0),
            ];
            let v = [-p[0] - p[1], -p[1] + p[0]];
            let m = 0.05 * v[0].hypot(v[1]);
            let (a, b) = ((7.3 * t).sin(), (4.1 * t + 1.0).cos());
            points.push(format!("[{}, {}]", p[0], p[1]));
            vectors.push(format!("[{}, {}]", v[0] + m * a, v[1] + m * b));
        }
        format!(
            r#"{{"name": "w", "field": {{"kind": "sampled", "points": [{}], "vectors": [{}]}}}}"#,
            points.join(", "),
            vectors.join(", ")
        )
    }

    /// Parts carried by the warm-up from their start samples to a fifth of
    /// the way out (as a whirlpool's schedule gathers them near the
    /// centre), realising exactly 0.4 × the whirlpool there: the measure
    /// of the noisy 40-point grid-less target finds strength 0.4 within
    /// 5 % and a shape error below 10 %. The promise is the samples'
    /// interpolant wherever the part is; the start sample's own local
    /// affine model would extrapolate its noisy gradient over the part's
    /// whole path to the centre, where the field is small (a sequenced
    /// schedule realising a fraction of it measures a shape error over
    /// 100 % that way).
    #[test]
    fn gathered_parts_measure_the_whirlpool_they_realise() {
        let target = Target::from_json_str(&noisy_whirlpool_json(40)).unwrap();
        let sampled = target.sample().unwrap();
        let s = 0.4;
        let exact = |p: [f64; 2]| -> Result<[f64; 2], std::convert::Infallible> {
            Ok([s * (-p[0] - p[1]), s * (-p[1] + p[0])])
        };
        let plays: Vec<PointPlay> = sampled
            .points
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let q = [0.2 * p[0], 0.2 * p[1]];
                let mut field = exact;
                let Ok(r) = crate::play::measure::flow_mean_velocity(&mut field, q, 1.0, 8);
                PointPlay {
                    index: i,
                    start: *p,
                    position: q,
                    realised: r,
                    window_starts: vec![q],
                    span: 1.0,
                    periods: 4,
                    moving: true,
                    contributions: vec![],
                    note: None,
                    lost_at: None,
                    warmup_periods: 1,
                    settled: true,
                }
            })
            .collect();
        let e = realised_error(&target, &sampled.weights, &plays, None);
        assert_eq!(e.valid, 40);
        assert!((e.realised_strength / s - 1.0).abs() < 0.05, "{e:?}");
        assert!(e.shape_error < 0.10, "{e:?}");
    }
}
