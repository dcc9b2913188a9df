//! Poses modulo a part's symmetry and the field family a pose design
//! places.
//!
//! **Family** ([`Family`]): the elliptic sink, line sinks of strengths
//! `ratio` and 1 whose weaker contraction runs along the angle. A linear
//! field v = A p + b turns a part by its second moments only, so the
//! part's major axis (the principal axis of its support's second moments) aligns with
//! the weaker contraction up to 180°: one pose for a part symmetric under
//! 180° (the rectangle), two 180° apart for the others. (A unique pose
//! for those needs a nonlinear field, e.g. a radial sink plus a small
//! uniform field (Böhringer et al.); one synthesized six-signal motion
//! makes affine fields only, [`crate::synth`].)
//!
//! Equilibria are compared modulo the part's symmetry ([`pose_error`],
//! [`nearest_stable`], [`distinct_stable`]).

use crate::dynamics::V2;
use crate::pose::{wrap, Equilibrium, Pose};
use crate::request::{FieldSpec, SumTerm};

/// Stable equilibria closer than this (m) and [`SAME_RAD`] modulo the
/// part's symmetry are one pose.
const SAME_M: f64 = 5e-4;
const SAME_RAD: f64 = 0.0175;

/// A family of requested point fields, placed by a centre and an angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Family {
    /// Elliptic sink: contraction `ratio` along the angle, 1 across it.
    Ellipse {
        /// Weaker / stronger contraction, in (0, 1).
        ratio: f64,
    },
}

impl Family {
    /// A short name.
    pub fn label(&self) -> String {
        match self {
            Family::Ellipse { ratio } => format!("elliptic sink (ratio {ratio})"),
        }
    }

    /// The requested field centred at `c` (m), its weaker contraction
    /// along `angle` (degrees).
    pub(crate) fn field(&self, c: V2, angle: f64) -> FieldSpec {
        let line = |strength: f64, angle: f64| SumTerm {
            weight: 1.0,
            field: FieldSpec::LineSink {
                center: [c.x, c.y],
                strength,
                angle,
                offset: 0.0,
            },
        };
        match *self {
            Family::Ellipse { ratio } => FieldSpec::Sum {
                terms: vec![line(ratio, angle + 90.0), line(1.0, angle)],
            },
        }
    }
}

/// θ reduced modulo the symmetry turn 2π/`n`, into (−π/n, π/n].
pub(crate) fn wrap_symmetric(theta: f64, n: usize) -> f64 {
    let n = n.max(1) as f64;
    wrap(theta * n) / n
}

/// How far `pose` is from `asked` modulo the symmetry `n`: (|Δr| m, Δθ rad).
pub fn pose_error(pose: &Pose, asked: &Pose, n: usize) -> (f64, f64) {
    (
        (pose.r - asked.r).norm(),
        wrap_symmetric(pose.theta - asked.theta, n),
    )
}

/// The stable equilibrium nearest `asked` modulo `n` in the metric
/// |Δr|/`radius` + |Δθ|.
pub fn nearest_stable(
    eqs: &[Equilibrium],
    asked: &Pose,
    n: usize,
    radius: f64,
) -> Option<Equilibrium> {
    let metric = |e: &Equilibrium| {
        let (d, t) = pose_error(&e.pose, asked, n);
        d / radius + t.abs()
    };
    eqs.iter()
        .filter(|e| e.stable)
        .min_by(|a, b| metric(a).total_cmp(&metric(b)))
        .copied()
}

/// The stable equilibria, one per pose modulo the symmetry `n`.
pub fn distinct_stable(eqs: &[Equilibrium], n: usize) -> Vec<Equilibrium> {
    let mut out: Vec<Equilibrium> = Vec::new();
    for e in eqs.iter().filter(|e| e.stable) {
        let same = |f: &Equilibrium| {
            let (d, t) = pose_error(&e.pose, &f.pose, n);
            d <= SAME_M && t.abs() <= SAME_RAD
        };
        if !out.iter().any(same) {
            out.push(*e);
        }
    }
    out
}
