//! A part's own rotational symmetry and its principal axis.
//!
//! **Symmetry.** A part is symmetric under a turn by 360°/n about its
//! centre of mass when the turn maps it onto itself: its polygon's
//! vertices onto its vertices (a uniform or unknown support follows the
//! area), and for listed support points also each point onto a point of
//! the same weight, all within 1e-9 of the part's size. Every pose of such
//! a part is the same as the pose turned by 360°/n, so a pose is asked
//! for, and reached, modulo that turn.
//!
//! **Principal axis.** The angle φ of the major axis of the support's
//! second moments Σ c_j ρ_j ρ_jᵀ in the body frame: in a linear field
//! v = A p + b the torque on the part depends on these second moments only
//! (`crate::pose::LiftedField`), so an elliptic sink turns that axis to its
//! weaker contraction, up to 180°.

use super::{Part, Support};
use crate::dynamics::V2;

/// Largest symmetry order tried.
pub(crate) const MAX_ORDER: usize = 12;

/// `a` turned by `angle` (rad).
fn turned(a: &V2, angle: f64) -> V2 {
    let (s, c) = angle.sin_cos();
    V2::new(c * a.x - s * a.y, s * a.x + c * a.y)
}

/// Every point of `points` (with its weight) turned by `angle` lands on a
/// point of the set with the same weight (within `tol`).
fn maps_onto(points: &[V2], weights: &[f64], angle: f64, tol: f64) -> bool {
    points.iter().zip(weights).all(|(p, w)| {
        let q = turned(p, angle);
        points
            .iter()
            .zip(weights)
            .any(|(r, v)| (q - r).norm() <= tol && (w - v).abs() <= 1e-9 * w.abs().max(*v))
    })
}

impl Part {
    /// The order n of the part's rotational symmetry (module docs): 1 for
    /// none, 2 for a rectangle (symmetric under 180°).
    ///
    /// ```
    /// use platefield::part::Part;
    /// let load = |n: &str| Part::load(std::path::Path::new(&format!("targets/parts/{n}.json")));
    /// assert_eq!(load("rectangle")?.symmetry(), 2);
    /// assert_eq!(load("bracket")?.symmetry(), 1);
    /// # Ok::<(), platefield::Error>(())
    /// ```
    pub fn symmetry(&self) -> usize {
        let tol = 1e-9 * self.size();
        let ones = vec![1.0; self.polygon.len()];
        let listed = matches!(self.support, Support::Points { .. });
        (2..=MAX_ORDER)
            .rev()
            .find(|&n| {
                let angle = std::f64::consts::TAU / n as f64;
                maps_onto(&self.polygon, &ones, angle, tol)
                    && (!listed || maps_onto(self.body.points(), self.body.weights(), angle, tol))
            })
            .unwrap_or(1)
    }

    /// The angle φ (rad, in (−π/2, π/2]) of the major axis of the
    /// support's second moments in the body frame (module docs).
    #[cfg(test)]
    pub(crate) fn principal_angle(&self) -> f64 {
        let (mut xx, mut yy, mut xy) = (0.0, 0.0, 0.0);
        for (p, w) in self.body.points().iter().zip(self.body.weights()) {
            xx += w * p.x * p.x;
            yy += w * p.y * p.y;
            xy += w * p.x * p.y;
        }
        0.5 * (2.0 * xy).atan2(xx - yy)
    }
}
