//! The lifted field: a planar part's mean twist at a pose (x, y, θ),
//! predicted from the point-part velocity field V(p) integrated over its
//! support.
//!
//! **Model (quasi-static, viscous averaging).** A part on a vibrating plate
//! slips back and forth every cycle by far more than it drifts; averaged
//! over a cycle, the friction on support point j is then close to linear in
//! its mean velocity relative to the point-part steady state,
//! f̄_j ≈ −c_j b (ṗ_j − V(p_j)), with one damping rate b for every point
//! (the same μ and normal load per unit mass). The body's mean motion
//! balances these forces and their torques about the centre of mass (the
//! inertia of the slow drift is negligible), which makes its twist
//! (v, ω) the weighted least-squares rigid fit to the support's velocities:
//!
//! ```text
//! v = Σ_j c_j V(p_j) / Σ_j c_j
//! ω = Σ_j c_j a_j × V(p_j) / Σ_j c_j |a_j|²,      a_j = R(θ) ρ_j,  p_j = r + a_j
//! ```
//!
//! (b cancels). Assumptions: the field varies little over one cycle's
//! excursion of the part; each support point's mean slip response is the
//! point part's (no coupling through the rigid body's oscillating spin);
//! the centre of mass is the support's weighted centroid. Where a whole
//! part sticks (the field's stick region) the prediction is the mean of
//! the points' (zero) velocities, exact too.
//!
//! **Against the planar simulation** (LineSink primitive, 2 × 0.5 cm
//! rectangle, 20 poses; measured: `tests/poses.rs` `lifted_field_against_simulation`): the
//! translation
//! agrees closely. The spin has the right sign everywhere but is a few
//! times the simulated rate: the cycle-averaged Coulomb friction
//! of a slip oscillating along one direction damps a drift across it more
//! than along it, and by how much V(p) does not record
//! ([`crate::pose::AveragedField`], which sums the friction over the support
//! before averaging over the cycle, agrees closely in both).
//! [`LiftedField::with_damping`] takes that anisotropy as a fitted tensor
//! B, which brings the spin within several per cent. Where every V(p_j) is
//! parallel to one direction B leaves the equilibria unchanged.

use nalgebra::{Matrix2, Matrix3, Vector3};

use crate::dynamics::{PlanarBody, V2};
use crate::field::{Field, Grid};
use crate::request::FieldSpec;

/// A point part's velocity field V(p) (m/s) at any plate point (m).
pub trait PointField: Sync {
    /// V at `p`.
    fn velocity(&self, p: V2) -> V2;
}

impl<F: Fn(V2) -> V2 + Sync> PointField for F {
    fn velocity(&self, p: V2) -> V2 {
        self(p)
    }
}

impl PointField for FieldSpec {
    /// A target's requested field, as the field a part would see.
    fn velocity(&self, p: V2) -> V2 {
        let v = self.eval([p.x, p.y]);
        V2::new(v[0], v[1])
    }
}

/// A computed velocity field on a grid, bilinear between its samples and
/// held at the edge value outside the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct GridField {
    grid: Grid,
    vectors: Vec<[f64; 2]>,
}

impl GridField {
    /// The velocity samples of `field` (row-major over its grid).
    pub fn new(field: &Field) -> GridField {
        GridField {
            grid: field.grid,
            vectors: field.vectors.clone(),
        }
    }

    /// Samples `vectors` (row-major, y outer) on `grid`.
    pub(crate) fn from_samples(grid: Grid, vectors: Vec<[f64; 2]>) -> GridField {
        GridField { grid, vectors }
    }
}

/// Cell index and fraction of `v` on an axis of `n` points over `range`.
fn locate(v: f64, range: [f64; 2], n: usize) -> (usize, f64) {
    if n < 2 {
        return (0, 0.0);
    }
    let s = ((v - range[0]) / (range[1] - range[0]) * (n - 1) as f64).clamp(0.0, (n - 1) as f64);
    let i = (s.floor() as usize).min(n - 2);
    (i, s - i as f64)
}

impl PointField for GridField {
    fn velocity(&self, p: V2) -> V2 {
        let [nx, ny] = self.grid.n;
        let (i, fx) = locate(p.x, self.grid.x, nx);
        let (j, fy) = locate(p.y, self.grid.y, ny);
        let at = |i: usize, j: usize| {
            let v = self.vectors[j.min(ny - 1) * nx + i.min(nx - 1)];
            V2::new(v[0], v[1])
        };
        let lo = at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
        let hi = at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx;
        lo * (1.0 - fy) + hi * fy
    }
}

/// A pose: centre of mass r (m, plate frame) and angle θ (rad) of the
/// body x axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Centre of mass (m).
    pub r: V2,
    /// Angle (rad).
    pub theta: f64,
}

impl Pose {
    /// The pose (x, y, θ).
    pub fn new(x: f64, y: f64, theta: f64) -> Pose {
        Pose {
            r: V2::new(x, y),
            theta,
        }
    }
}

/// A part's mean twist: velocity of its centre of mass (m/s) and spin (rad/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Twist {
    /// Translation (m/s).
    pub v: V2,
    /// Spin (rad/s).
    pub omega: f64,
}

/// The lifted field of one part in one point field (module docs).
pub struct LiftedField<'a> {
    field: &'a dyn PointField,
    body: &'a PlanarBody,
    /// Σ c_j |ρ_j|² / Σ c_j (m²).
    polar: f64,
    /// Part radius about its centre of mass (m): the length scale.
    radius: f64,
    /// The averaged friction's damping tensor B (plate frame, relative;
    /// `None` = isotropic).
    damping: Option<Matrix2<f64>>,
}

impl<'a> LiftedField<'a> {
    /// The lifted field of `body` in `field`.
    ///
    /// ```
    /// use platefield::dynamics::{PlanarBody, V2};
    /// use platefield::pose::{LiftedField, Pose};
    /// // Two equal support points 2 cm apart in an elliptic sink (−0.3x, −y):
    /// // at 45° the weaker contraction along x turns the dumbbell toward x.
    /// let (body, _) = PlanarBody::centred(&[V2::new(-0.01, 0.0), V2::new(0.01, 0.0)], &[1.0, 1.0]);
    /// let sink = |p: V2| V2::new(-0.3 * p.x, -p.y);
    /// let t = LiftedField::new(&sink, &body).twist(Pose::new(0.0, 0.0, 45f64.to_radians()));
    /// assert!(t.v.norm() < 1e-15);
    /// assert!((t.omega + 0.35).abs() < 1e-12); // −(1 − 0.3) sin 2θ / 2
    /// ```
    pub fn new(field: &'a dyn PointField, body: &'a PlanarBody) -> LiftedField<'a> {
        let total: f64 = body.weights().iter().sum();
        let polar = body
            .points()
            .iter()
            .zip(body.weights())
            .map(|(p, c)| c * p.norm_squared())
            .sum::<f64>()
            / total;
        let radius = body.points().iter().map(|p| p.norm()).fold(0.0, f64::max);
        LiftedField {
            field,
            body,
            polar,
            radius,
            damping: None,
        }
    }

    /// The same field with an anisotropic averaged friction: f̄_j =
    /// −c_j B (ṗ_j − V(p_j)) with B (plate frame, any positive scale)
    /// symmetric positive definite. The twist then solves the B-weighted
    /// least-squares fit Σ_j c_j J_jᵀ B (J_j ξ − V_j) = 0, J_j ξ = v + ω k × a_j.
    pub fn with_damping(mut self, b: Matrix2<f64>) -> LiftedField<'a> {
        self.damping = Some(b);
        self
    }

    /// The part's length scale: its support's radius about the centre of
    /// mass (m).
    pub(crate) fn radius(&self) -> f64 {
        self.radius
    }

    /// The predicted mean twist at `pose`.
    pub fn twist(&self, pose: Pose) -> Twist {
        if let Some(b) = self.damping {
            return self.twist_damped(pose, &b);
        }
        let (s, c) = pose.theta.sin_cos();
        let mut v = V2::zeros();
        let mut torque = 0.0;
        let mut total = 0.0;
        for (rho, w) in self.body.points().iter().zip(self.body.weights()) {
            let arm = V2::new(c * rho.x - s * rho.y, s * rho.x + c * rho.y);
            let u = self.field.velocity(pose.r + arm);
            v += u * *w;
            torque += arm.perp(&u) * w;
            total += w;
        }
        Twist {
            v: v / total,
            omega: if self.polar > 0.0 {
                torque / total / self.polar
            } else {
                0.0
            },
        }
    }

    /// The twist under the damping tensor `b` ([`Self::with_damping`]).
    fn twist_damped(&self, pose: Pose, b: &Matrix2<f64>) -> Twist {
        let (s, c) = pose.theta.sin_cos();
        let mut a = Matrix3::zeros();
        let mut g = Vector3::zeros();
        for (rho, w) in self.body.points().iter().zip(self.body.weights()) {
            let arm = V2::new(c * rho.x - s * rho.y, s * rho.x + c * rho.y);
            let u = self.field.velocity(pose.r + arm);
            // J = [I | k × a]: columns (1, 0), (0, 1), (−a_y, a_x).
            let j = nalgebra::Matrix2x3::new(1.0, 0.0, -arm.y, 0.0, 1.0, arm.x);
            let jtb = j.transpose() * b;
            a += jtb * j * *w;
            g += jtb * u * *w;
        }
        let xi = a.lu().solve(&g).unwrap_or_else(Vector3::zeros);
        Twist {
            v: V2::new(xi.x, xi.y),
            omega: xi.z,
        }
    }

    /// The twist as a 3-vector (v_x, v_y, ω).
    pub(crate) fn twist3(&self, q: &nalgebra::Vector3<f64>) -> nalgebra::Vector3<f64> {
        let t = self.twist(Pose::new(q.x, q.y, q.z));
        nalgebra::Vector3::new(t.v.x, t.v.y, t.omega)
    }

    /// Jacobian ∂(v_x, v_y, ω)/∂(x, y, θ) by central differences (steps
    /// 1e-5 of the radius and 1e-5 rad).
    pub(crate) fn jacobian(&self, pose: Pose) -> Matrix3<f64> {
        let q = nalgebra::Vector3::new(pose.r.x, pose.r.y, pose.theta);
        let steps = [
            1e-5 * self.radius.max(1e-6),
            1e-5 * self.radius.max(1e-6),
            1e-5,
        ];
        let mut j = Matrix3::zeros();
        for (k, h) in steps.iter().enumerate() {
            let mut a = q;
            let mut b = q;
            a[k] += h;
            b[k] -= h;
            let d = (self.twist3(&a) - self.twist3(&b)) / (2.0 * h);
            j.set_column(k, &d);
        }
        j
    }
}

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
    pub(crate) fn contains(&self, r: &V2) -> bool {
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

/// θ wrapped into (−π, π].
pub fn wrap(theta: f64) -> f64 {
    let t = theta.rem_euclid(std::f64::consts::TAU);
    if t > std::f64::consts::PI {
        t - std::f64::consts::TAU
    } else {
        t
    }
}
