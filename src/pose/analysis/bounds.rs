//! Equilibrium bounds for an unknown support distribution (the paper's
//! future work): the poses that are equilibria for SOME admissible support,
//! k contact points anywhere in the part with non-negative weights.
//!
//! **Condition.** In the lifted field's model (see `lifted`) a pose is an
//! equilibrium for contacts p_j with weights c_j exactly when the friction
//! drives balance: Σ_j c_j V(p_j) = 0 and Σ_j c_j a_j × V(p_j) = 0 (a_j the
//! lever arm from the part's origin; with zero net force the torque does
//! not depend on the reference point, so the unknown centre of mass does
//! not enter). With wrenches w(p) = (V(p), a × V(p)/R) ∈ R³ (R the part's
//! radius) that is 0 ∈ cone{w(p_j)}, so for any k:
//!
//! ```text
//! pose may rest  ⇒  0 ∈ conv{ w(p) : p in the part }
//! ```
//!
//! (for k ≥ 4 the converse holds too, by Carathéodory; for k ≤ 3 the true
//! set is smaller and this is an outer bound).
//!
//! **Test.** The part is covered by its uniform support samples s_i (every
//! point within h, half a cell diagonal, of one) and its vertices. The
//! distance from 0 to conv{w(s_i)} is found by Gilbert's algorithm (the
//! minimum-norm point of the hull); the continuum's hull lies within
//! δ = max_i max_d |w(s_i + h d) − w(s_i)| (d the two unit axes and
//! diagonals) of the samples' hull, so a pose is excluded only with a
//! separating plane of margin above δ, and kept when the distance is at
//! most δ or undecided after 2000 iterations (an outer bound throughout).

use super::lifted::{PointField, Pose};
use crate::dynamics::V2;
use crate::part::Part;
use nalgebra::Vector3;

/// Gilbert iterations before a pose counts as undecided (kept).
const ITERATIONS: usize = 2000;

/// The unknown-support test for one part in one field.
pub struct Bounds<'a> {
    field: &'a dyn PointField,
    /// Sample points (body frame, m): the support samples and vertices.
    samples: Vec<V2>,
    /// Covering radius h of the samples (m).
    cover: f64,
    /// The part's radius R (m).
    radius: f64,
}

impl<'a> Bounds<'a> {
    /// The test for `part` (its uniform samples, `part.body`, and
    /// vertices) in `field`.
    ///
    /// ```
    /// use platefield::dynamics::V2;
    /// use platefield::part::Part;
    /// use platefield::pose::{Bounds, Pose};
    /// let part = Part::from_json_str(
    ///     r#"{"name": "r", "polygon": [[-0.01, -0.0025], [0.01, -0.0025], [0.01, 0.0025], [-0.01, 0.0025]],
    ///         "support": {"unknown": {"contacts": 3}}}"#,
    /// )?;
    /// let sink = |p: V2| V2::new(-0.3 * p.x, -p.y);
    /// let b = Bounds::new(&part, &sink);
    /// assert!(b.may_rest(Pose::new(0.004, 0.001, 0.7))); // the sink's centre under the part
    /// assert!(!b.may_rest(Pose::new(0.02, 0.0, 0.7))); // every drive points one way
    /// # Ok::<(), platefield::Error>(())
    /// ```
    pub fn new(part: &Part, field: &'a dyn PointField) -> Bounds<'a> {
        let mut samples: Vec<V2> = part.body.points().to_vec();
        let area = crate::part::signed_area(&part.polygon).abs();
        let cell = (area / samples.len().max(1) as f64).sqrt();
        samples.extend(part.polygon.iter().copied());
        Bounds {
            field,
            samples,
            cover: cell * std::f64::consts::FRAC_1_SQRT_2,
            radius: part.radius(),
        }
    }

    /// The wrench w(p) of a contact at body point `rho` at `pose`.
    fn wrench(&self, pose: &Pose, rho: &V2) -> Vector3<f64> {
        let (s, c) = pose.theta.sin_cos();
        let a = V2::new(c * rho.x - s * rho.y, s * rho.x + c * rho.y);
        let v = self.field.velocity(pose.r + a);
        Vector3::new(v.x, v.y, a.perp(&v) / self.radius)
    }

    /// True when `pose` may be an equilibrium for some admissible support
    /// (module docs: an outer bound).
    pub fn may_rest(&self, pose: Pose) -> bool {
        let w: Vec<Vector3<f64>> = self.samples.iter().map(|s| self.wrench(&pose, s)).collect();
        let h = self.cover;
        let dirs = [
            V2::new(h, 0.0),
            V2::new(0.0, h),
            V2::new(h, h) * std::f64::consts::FRAC_1_SQRT_2,
            V2::new(h, -h) * std::f64::consts::FRAC_1_SQRT_2,
        ];
        let delta = self
            .samples
            .iter()
            .zip(&w)
            .flat_map(|(s, ws)| {
                dirs.iter()
                    .flat_map(move |d| [*s + d, *s - d])
                    .map(move |p| (self.wrench(&pose, &p) - ws).norm())
            })
            .fold(0.0, f64::max);
        hull_near_origin(&w, delta)
    }

    /// Every pose of an nx × ny × nθ grid over `region` (cell centres,
    /// θ from 0 in steps of 360°/nθ) that may be an equilibrium.
    pub fn scan(&self, region: &crate::pose::Region, n: [usize; 3]) -> Vec<Pose> {
        let mut out = Vec::new();
        for k in 0..n[2] {
            let theta = std::f64::consts::TAU * k as f64 / n[2] as f64;
            for j in 0..n[1] {
                for i in 0..n[0] {
                    let r = region.at(
                        (i as f64 + 0.5) / n[0] as f64,
                        (j as f64 + 0.5) / n[1] as f64,
                    );
                    let pose = Pose { r, theta };
                    if self.may_rest(pose) {
                        out.push(pose);
                    }
                }
            }
        }
        out
    }
}

/// Gilbert's minimum-norm point of conv(`w`): false only when a plane
/// separates the origin from every w_i by more than `delta`; true when the
/// hull comes within `delta` of the origin or the iterations run out.
fn hull_near_origin(w: &[Vector3<f64>], delta: f64) -> bool {
    let Some(first) = w.first() else {
        return true;
    };
    let mut x = *first;
    for _ in 0..ITERATIONS {
        let norm = x.norm();
        if norm <= delta {
            return true;
        }
        let u = x / norm;
        let (j, m) = w
            .iter()
            .map(|p| u.dot(p))
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, 0.0));
        if m > delta {
            return false;
        }
        let d = x - w[j];
        let dd = d.norm_squared();
        if dd == 0.0 {
            return true;
        }
        let t = (x.dot(&d) / dd).clamp(0.0, 1.0);
        x -= d * t;
    }
    true
}
