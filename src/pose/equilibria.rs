//! Equilibrium poses of the lifted field and their stability, and basins
//! of the stable ones from random drops integrated along the lifted field.
//!
//! **Zeros.** Damped Newton on the twist (v_x, v_y, ω) = 0 in (x, y, θ),
//! started from every point of a grid of poses over the region (3 × 3
//! positions × 24 angles); each step is cut to a quarter of the part's
//! radius and 0.3 rad. A zero is accepted when |v| and |ω|·R fall below
//! 1e-9 of the field's speed scale (R the part's radius) inside the
//! region; zeros closer than 1e-6 R and 1e-4 rad (θ mod 360°) are one.
//!
//! **Stability.** The linearised flow q̇ = J (q − q*) is stable when every
//! eigenvalue of the Jacobian J has a negative real part, unstable when one
//! is positive (a degenerate zero, a real part within 1e-9 of the largest
//! magnitude, is reported as not stable).
//!
//! **Basins (predicted).** A drop at a random pose follows q̇ = twist by
//! RK4, each step moving at most 2 % of R or 0.02 rad and at most half the
//! inverse of the largest eigenvalue, until it is within 1e-3 R and 0.1°
//! of a stable equilibrium (then it counts for that one), leaves the
//! region, or runs 20000 steps (then it counts for none).

use nalgebra::{Matrix3, Vector3};

/// Most RK4 steps of one drop ([`settle`]).
pub(crate) const SETTLE_STEPS: usize = 20000;
/// Largest step of a drop as a fraction of the part's radius R (and in
/// radians of turn).
pub(crate) const SETTLE_STEP: f64 = 0.02;

use super::lifted::{LiftedField, Pose};
use crate::dynamics::V2;

/// A rectangular region of the plate the part's centre must stay in (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Region {
    /// [xmin, xmax].
    pub x: [f64; 2],
    /// [ymin, ymax].
    pub y: [f64; 2],
}

impl Region {
    /// True when `r` lies in the region (edges included).
    pub fn contains(&self, r: &V2) -> bool {
        (self.x[0]..=self.x[1]).contains(&r.x) && (self.y[0]..=self.y[1]).contains(&r.y)
    }

    /// The region shrunk by `margin` on every side (to its centre line
    /// along an axis narrower than 2 `margin`).
    pub fn inset(&self, margin: f64) -> Region {
        let shrink = |a: [f64; 2]| {
            let m = margin.min(0.5 * (a[1] - a[0]));
            [a[0] + m, a[1] - m]
        };
        Region {
            x: shrink(self.x),
            y: shrink(self.y),
        }
    }

    /// A point of the region from two numbers in [0, 1].
    pub fn at(&self, u: f64, v: f64) -> V2 {
        V2::new(
            self.x[0] + (self.x[1] - self.x[0]) * u,
            self.y[0] + (self.y[1] - self.y[0]) * v,
        )
    }
}

/// One equilibrium pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Equilibrium {
    /// The pose (θ in (−π, π]).
    pub pose: Pose,
    /// All eigenvalues of the Jacobian have negative real parts.
    pub stable: bool,
    /// The eigenvalues' real parts, largest first (1/s).
    pub rates: [f64; 3],
}

/// θ wrapped into (−π, π].
pub fn wrap(theta: f64) -> f64 {
    let t = theta.rem_euclid(std::f64::consts::TAU);
    if t > std::f64::consts::PI {
        t - std::f64::consts::TAU
    } else {
        t
    }
}

/// Speed scale of the lifted field over the region: the largest |v| + |ω|R
/// at the start grid's poses.
fn speed_scale(lifted: &LiftedField<'_>, starts: &[Pose]) -> f64 {
    starts
        .iter()
        .map(|p| {
            let t = lifted.twist(*p);
            t.v.norm() + t.omega.abs() * lifted.radius()
        })
        .fold(0.0, f64::max)
}

/// The grid of start poses: 3 × 3 positions at the quarters of the region
/// times 24 angles.
fn start_poses(region: &Region) -> Vec<Pose> {
    let mut out = Vec::new();
    for j in 1..=3 {
        for i in 1..=3 {
            let r = region.at(i as f64 / 4.0, j as f64 / 4.0);
            for k in 0..24 {
                out.push(Pose {
                    r,
                    theta: wrap((k as f64 * 15.0).to_radians()),
                });
            }
        }
    }
    out
}

/// Newton from `start`; the zero when it converged inside the region.
fn newton(lifted: &LiftedField<'_>, start: Pose, region: &Region, tol: f64) -> Option<Pose> {
    let r = lifted.radius();
    let mut q = Vector3::new(start.r.x, start.r.y, start.theta);
    for _ in 0..60 {
        let t = lifted.twist3(&q);
        if t.fixed_rows::<2>(0).norm() <= tol && t.z.abs() * r <= tol {
            let pose = Pose::new(q.x, q.y, wrap(q.z));
            return region.contains(&pose.r).then_some(pose);
        }
        let j = lifted.jacobian(Pose::new(q.x, q.y, q.z));
        let mut step = j.lu().solve(&(-t))?;
        let cut = (step.fixed_rows::<2>(0).norm() / (0.25 * r)).max(step.z.abs() / 0.3);
        if cut > 1.0 {
            step /= cut;
        }
        q += step;
        if !q.iter().all(|x| x.is_finite()) {
            return None;
        }
    }
    None
}

impl Equilibrium {
    /// The equilibrium at `pose` with the Jacobian `j` of its field there:
    /// stable when every eigenvalue's real part is below −1e-9 of the
    /// largest magnitude.
    pub fn of_jacobian(pose: Pose, j: &Matrix3<f64>) -> Equilibrium {
        let e = j.complex_eigenvalues();
        let mut rates = [e[0].re, e[1].re, e[2].re];
        rates.sort_by(|a, b| b.total_cmp(a));
        let scale = rates.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        Equilibrium {
            pose,
            stable: rates[0] < -1e-9 * scale,
            rates,
        }
    }
}

/// Every equilibrium of `lifted` found from the start grid over `region`,
/// sorted by θ then x then y.
///
/// ```
/// use platefield::dynamics::{PlanarBody, V2};
/// use platefield::pose::{equilibria, LiftedField, Region};
/// let (body, _) = PlanarBody::centred(
///     &[V2::new(-0.01, -0.002), V2::new(0.01, -0.002), V2::new(0.01, 0.002), V2::new(-0.01, 0.002)],
///     &[1.0; 4],
/// );
/// let sink = |p: V2| V2::new(-0.3 * p.x, -p.y);
/// let region = Region { x: [-0.03, 0.03], y: [-0.03, 0.03] };
/// let eq = equilibria(&LiftedField::new(&sink, &body), &region);
/// let stable: Vec<f64> = eq.iter().filter(|e| e.stable).map(|e| e.pose.theta.to_degrees()).collect();
/// assert_eq!(stable.len(), 2); // long side along x: 0° and 180°
/// assert!(stable.iter().all(|t| t.abs() < 1e-6 || (t.abs() - 180.0).abs() < 1e-6));
/// ```
pub fn equilibria(lifted: &LiftedField<'_>, region: &Region) -> Vec<Equilibrium> {
    let starts = start_poses(region);
    let tol = 1e-9 * speed_scale(lifted, &starts);
    let r = lifted.radius();
    let mut found: Vec<Pose> = Vec::new();
    for s in starts {
        let Some(p) = newton(lifted, s, region, tol) else {
            continue;
        };
        let same =
            |q: &Pose| (q.r - p.r).norm() <= 1e-6 * r && wrap(q.theta - p.theta).abs() <= 1e-4;
        if !found.iter().any(same) {
            found.push(p);
        }
    }
    found.sort_by(|a, b| {
        a.theta
            .total_cmp(&b.theta)
            .then(a.r.x.total_cmp(&b.r.x))
            .then(a.r.y.total_cmp(&b.r.y))
    });
    found
        .into_iter()
        .map(|pose| Equilibrium::of_jacobian(pose, &lifted.jacobian(pose)))
        .collect()
}

/// Where one drop ends: the index of the stable equilibrium it reached.
pub fn settle(
    lifted: &LiftedField<'_>,
    start: Pose,
    stable: &[Equilibrium],
    region: &Region,
) -> Option<usize> {
    let r = lifted.radius();
    let fastest = stable
        .iter()
        .map(|e| e.rates.iter().fold(0.0f64, |m, x| m.max(x.abs())))
        .fold(0.0f64, f64::max);
    let mut q = Vector3::new(start.r.x, start.r.y, start.theta);
    for _ in 0..SETTLE_STEPS {
        let near = stable.iter().position(|e| {
            (V2::new(q.x, q.y) - e.pose.r).norm() <= 1e-3 * r
                && wrap(q.z - e.pose.theta).abs() <= 0.1f64.to_radians()
        });
        if near.is_some() {
            return near;
        }
        if !region.contains(&V2::new(q.x, q.y)) {
            return None;
        }
        let f = |q: &Vector3<f64>| lifted.twist3(q);
        let k1 = f(&q);
        let speed =
            (k1.fixed_rows::<2>(0).norm() / (SETTLE_STEP * r)).max(k1.z.abs() / SETTLE_STEP);
        let mut h = if speed > 0.0 {
            1.0 / speed
        } else {
            f64::INFINITY
        };
        if fastest > 0.0 {
            h = h.min(0.5 / fastest);
        }
        if !h.is_finite() {
            return None;
        }
        let k2 = f(&(q + k1 * (0.5 * h)));
        let k3 = f(&(q + k2 * (0.5 * h)));
        let k4 = f(&(q + k3 * h));
        q += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
    }
    None
}
