//! Continua of rest: where the lifted field's zeros are not isolated
//! points but a curve in (x, y, θ), found, traced and classified.
//!
//! **Where they come from.** A field with a symmetry the part's twist
//! inherits has a whole curve of rests: a rotationally symmetric sink
//! V(p) = −k p turns no part (ω ≡ 0), so every angle at its centre is a
//! rest ("at (x, y), any angle"); a line sink V = −k (n·p) n is the same
//! all along its line ("anywhere on the line, at angle θ"). A designed
//! field is symmetric only nearly: the translation still settles onto
//! the curve, and the part then moves slowly along it, turning for ever
//! (the shipped sink turns a 3 × 1 cm rectangle sitting at its centre at
//! a few degrees a second) or drifting towards a few isolated rests on
//! it. Isolated-zero Newton finds none of this: on the curve the
//! Jacobian is singular and Newton wanders along it.
//!
//! **Scaled coordinates.** Position in units of the part's radius R and
//! angle in radians, q̃ = (x/R, y/R, θ); the twist likewise,
//! f̃ = (v_x/R, v_y/R, ω) (1/s), and J̃ = ∂f̃/∂q̃ with singular values
//! σ₁ ≥ σ₂ ≥ σ₃ (1/s), right singular vectors v₁, v₂, v₃.
//!
//! **The near-zero threshold.** A drop counts as arrived within
//! δ = [`ARRIVE`] (of R, and in rad) of a rest ([`crate::pose::settle`]).
//! Near a rest the transverse directions decay at least at σ₂: from a
//! unit offset to δ they take T = ln(1/δ)/σ₂. The direction v₃ is *slow*
//! when, over T, its own linearised motion changes its coordinate by at
//! most 10 % (e^{σ₃T} ≤ e^{0.1}):
//!
//! ```text
//! σ₃ ≤ GAP σ₂,    GAP = 0.1 / ln(1/δ) = 0.0145
//! ```
//!
//! Then the fast residual (f̃ on u₁, u₂) vanishes on a curve through the
//! point, tangent to v₃, that the flow reaches first and moves along
//! after; Newton restricted to the fast components (the pseudo-inverse
//! truncated to σ₁, σ₂) lands on it and a predictor–corrector traces it
//! (steps of [`STEP`] along v₃, corrected across it to the Newton
//! tolerance, until it closes, leaves the region, or stops being slow).
//! The finite-difference Jacobian's own error (steps 1e-5 R, the zeros
//! solved to 1e-9 of the field's speed) is orders of magnitude below
//! GAP, so it never decides. Along the curve the part moves at the
//! *drift* g = t·f̃ (t the unit tangent). A point of the curve is a rest
//! (*neutral*) when over the same T the drift moves the part less than δ:
//!
//! ```text
//! |g| ≤ δ σ₂ / ln(1/δ)
//! ```
//!
//! A curve whose every point is neutral is a continuum of rest; a closed
//! curve on which g keeps one sign is a part turning (or circling) for
//! ever; elsewhere g's sign changes are isolated rests on the curve,
//! refined by full Newton and listed with the other equilibria, and a
//! drop that reaches the curve ends at the one the drift carries it to
//! (the flow along the curve is one-dimensional: [`Continuum::destination`]).
//! The curve attracts when the two transverse eigenvalues of J̃ (all but
//! the one nearest 0) have negative real parts at every point.
//!
//! **Shape.** A closed curve whose θ runs through a full turn is "at
//! (x, y), any angle" (its points' mean position and their largest
//! distance from it); a curve whose θ stays within [`LINE_TURN`] and whose
//! points lie within [`LINE_BEND`] of its length from the chord between
//! its ends is "on the line from … to …, at θ"; anything else is a
//! curve, given by its points. A two-dimensional set of rests (σ₂ slow
//! too, a region where the field vanishes) is traced along v₃ only.

use nalgebra::{Complex, Matrix3, Vector3};

use super::lifted::{wrap, LiftedField, Pose, Region, Twist};
use crate::dynamics::V2;

/// δ: a drop within this fraction of the part's radius (and this angle,
/// rad) of a rest has arrived; the resolution the thresholds derive from.
pub const ARRIVE: f64 = 1e-3;

/// ln(1/δ): the transverse decay, in time constants, from a unit offset
/// to [`ARRIVE`].
const SETTLE_LOG: f64 = 6.907_755_278_982_137;

/// σ₃ ≤ GAP σ₂ makes v₃ slow (module docs): 0.1 / ln(1/δ).
pub const GAP: f64 = 0.1 / SETTLE_LOG;

/// Tracing step along the curve, scaled (of R, and rad: 2°); longer for
/// a small part in a large region, so that a curve across the region
/// takes at most [`MAX_STEPS`] steps.
pub const STEP: f64 = 0.035;

/// Fewest points of a reported curve: a slow stretch shorter than two
/// steps is a fold of the field (the Jacobian singular at one pose, such
/// as ω(θ) at its extremum in an elliptic sink), not a curve.
pub const MIN_POINTS: usize = 3;

/// Most tracing steps each way.
pub const MAX_STEPS: usize = 400;

/// Most iterations of a singular value decomposition.
const SVD_ITERATIONS: usize = 200;

/// Most corrector iterations per tracing step: Newton converges
/// quadratically on a smooth field, and only linearly where a grid
/// field's kinks spoil the
/// finite-difference Jacobian.
const CORRECTOR: usize = 40;

/// A curve whose θ stays within this (rad: 1°) may be a line.
pub const LINE_TURN: f64 = 0.017_453_292_519_943_295;

/// … and whose points lie within this fraction of its length from its
/// chord is one.
pub const LINE_BEND: f64 = 0.01;

/// Most iterations of the Schur decomposition behind [`eigenvalues`].
const SCHUR_ITERATIONS: usize = 1000;

/// The eigenvalues of `j`: from its Schur form, or, where that does not
/// converge in `SCHUR_ITERATIONS` (nalgebra's unbounded one can loop
/// for ever on an exactly singular Jacobian, a round sink's
/// diag(−k, −k, 0)), the roots of its characteristic polynomial
/// λ³ − tr J λ² + c₂ λ − det J (c₂ the sum of its principal 2 × 2 minors)
/// in closed form.
pub(crate) fn eigenvalues(j: &Matrix3<f64>) -> [Complex<f64>; 3] {
    if let Some(schur) = nalgebra::Schur::try_new(*j, f64::EPSILON, SCHUR_ITERATIONS) {
        let e = schur.complex_eigenvalues();
        return [e[0], e[1], e[2]];
    }
    let a = -j.trace();
    let minor = |p: usize, q: usize| j[(p, p)] * j[(q, q)] - j[(p, q)] * j[(q, p)];
    let b = minor(0, 1) + minor(0, 2) + minor(1, 2);
    let c = -j.determinant();
    cubic_roots(a, b, c)
}

/// The roots of λ³ + a λ² + b λ + c (Cardano; trigonometric for three
/// real roots).
fn cubic_roots(a: f64, b: f64, c: f64) -> [Complex<f64>; 3] {
    let shift = a / 3.0;
    let p = b - a * a / 3.0;
    let q = 2.0 * a * a * a / 27.0 - a * b / 3.0 + c;
    let disc = (q / 2.0).powi(2) + (p / 3.0).powi(3);
    let real = |t: f64| Complex::new(t - shift, 0.0);
    if disc > 0.0 {
        let root = disc.sqrt();
        let (u, v) = ((-q / 2.0 + root).cbrt(), (-q / 2.0 - root).cbrt());
        let im = 0.5 * 3f64.sqrt() * (u - v);
        let re = -(u + v) / 2.0 - shift;
        return [real(u + v), Complex::new(re, im), Complex::new(re, -im)];
    }
    if p == 0.0 {
        return [real(0.0); 3];
    }
    let r = (-p / 3.0).sqrt();
    let phi = (-q / (2.0 * r * r * r)).clamp(-1.0, 1.0).acos();
    let tau = std::f64::consts::TAU;
    [0.0, 1.0, 2.0].map(|k| real(2.0 * r * ((phi + tau * k) / 3.0).cos()))
}

/// The lifted field in scaled coordinates (module docs).
pub(crate) struct Scaled<'a, 'b> {
    lifted: &'b LiftedField<'a>,
    r: f64,
}

impl<'a, 'b> Scaled<'a, 'b> {
    pub(crate) fn new(lifted: &'b LiftedField<'a>) -> Scaled<'a, 'b> {
        Scaled {
            lifted,
            r: lifted.radius().max(f64::MIN_POSITIVE),
        }
    }

    /// The pose of scaled `q`.
    pub(crate) fn pose(&self, q: &Vector3<f64>) -> Pose {
        Pose::new(q.x * self.r, q.y * self.r, q.z)
    }

    /// The scaled coordinates of `p`.
    pub(crate) fn of(&self, p: Pose) -> Vector3<f64> {
        Vector3::new(p.r.x / self.r, p.r.y / self.r, p.theta)
    }

    /// f̃ at `q`.
    pub(crate) fn f(&self, q: &Vector3<f64>) -> Vector3<f64> {
        self.scale_twist(&self.lifted.twist(self.pose(q)))
    }

    /// f̃ of a twist (v_x, v_y, ω) as a 3-vector.
    pub(crate) fn scale_twist3(&self, t: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(t.x / self.r, t.y / self.r, t.z)
    }

    /// A twist scaled.
    fn scale_twist(&self, t: &Twist) -> Vector3<f64> {
        Vector3::new(t.v.x / self.r, t.v.y / self.r, t.omega)
    }

    /// J̃ at `q`.
    pub(crate) fn j(&self, q: &Vector3<f64>) -> Matrix3<f64> {
        self.scale_jacobian(&self.lifted.jacobian(self.pose(q)))
    }

    /// J̃ from the lifted field's Jacobian `j` (m, rad, s).
    pub(crate) fn scale_jacobian(&self, j: &Matrix3<f64>) -> Matrix3<f64> {
        let s = [self.r, self.r, 1.0];
        Matrix3::from_fn(|i, k| j[(i, k)] * s[k] / s[i])
    }
}

/// The singular values of J̃, largest first, with their vectors.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Spectrum {
    pub(crate) sigma: [f64; 3],
    pub(crate) u: [Vector3<f64>; 3],
    pub(crate) v: [Vector3<f64>; 3],
}

impl Spectrum {
    pub(crate) fn of(j: &Matrix3<f64>) -> Spectrum {
        // nalgebra's unbounded SVD can loop for ever on some exactly
        // singular matrices (a round sink's diag(−k, −k, 0)): bounded
        // iterations, then the eigenvectors of JᵀJ.
        if let Some(svd) = j.try_svd_unordered(true, true, f64::EPSILON, SVD_ITERATIONS) {
            if let (Some(u), Some(vt)) = (svd.u, svd.v_t) {
                let sigma = [0, 1, 2].map(|i| svd.singular_values[i]);
                let u = [0, 1, 2].map(|i| u.column(i).into_owned());
                let v = [0, 1, 2].map(|i| vt.row(i).transpose());
                return Spectrum::sorted(sigma, u, v);
            }
        }
        Spectrum::gram(j)
    }

    /// The spectrum from the symmetric eigenproblem of JᵀJ: v_i its
    /// eigenvectors, σ_i the roots of its eigenvalues, u_i = J v_i / σ_i
    /// (completed by cross products where σ_i is 0).
    fn gram(j: &Matrix3<f64>) -> Spectrum {
        let fallback = Spectrum {
            sigma: [0.0; 3],
            u: [Vector3::x(), Vector3::y(), Vector3::z()],
            v: [Vector3::x(), Vector3::y(), Vector3::z()],
        };
        let Some(e) =
            nalgebra::SymmetricEigen::try_new(j.transpose() * j, f64::EPSILON, SVD_ITERATIONS)
        else {
            return fallback;
        };
        let sigma = [0, 1, 2].map(|i| e.eigenvalues[i].max(0.0).sqrt());
        let v = [0, 1, 2].map(|i| e.eigenvectors.column(i).into_owned());
        let mut s = Spectrum::sorted(sigma, [Vector3::zeros(); 3], v);
        for i in 0..3 {
            s.u[i] = if s.sigma[i] > 0.0 {
                j * s.v[i] / s.sigma[i]
            } else {
                s.u[(i + 1) % 3].cross(&s.u[(i + 2) % 3])
            };
        }
        if s.u[2].norm() == 0.0 {
            s.u[2] = s.u[0].cross(&s.u[1]);
        }
        s
    }

    /// The triples ordered by σ, largest first.
    fn sorted(sigma: [f64; 3], u: [Vector3<f64>; 3], v: [Vector3<f64>; 3]) -> Spectrum {
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| sigma[b].total_cmp(&sigma[a]));
        Spectrum {
            sigma: order.map(|i| sigma[i]),
            u: order.map(|i| u[i]),
            v: order.map(|i| v[i]),
        }
    }

    /// v₃ is slow: σ₃ ≤ [`GAP`] σ₂.
    pub(crate) fn slow(&self) -> bool {
        self.sigma[2] <= GAP * self.sigma[1]
    }

    /// |f̃ on u₁, u₂|.
    pub(crate) fn fast_residual(&self, f: &Vector3<f64>) -> f64 {
        self.u[0].dot(f).hypot(self.u[1].dot(f))
    }

    /// Newton's step on the fast components only: −Σ_{i≤2} (u_i·f̃/σ_i) v_i.
    pub(crate) fn fast_step(&self, f: &Vector3<f64>) -> Vector3<f64> {
        (0..2)
            .filter(|&i| self.sigma[i] > 0.0)
            .map(|i| self.v[i] * (-self.u[i].dot(f) / self.sigma[i]))
            .sum()
    }

    /// The neutral drift bound δ σ₂ / ln(1/δ) (1/s, scaled).
    fn neutral(&self) -> f64 {
        ARRIVE * self.sigma[1] / SETTLE_LOG
    }
}

/// `dq` (scaled) cut to at most a quarter of the radius in position and
/// 0.3 rad, as every Newton step of the pose search.
pub(crate) fn cut(mut dq: Vector3<f64>) -> Vector3<f64> {
    let c = (dq.xy().norm() / 0.25).max(dq.z.abs() / 0.3);
    if c > 1.0 {
        dq /= c;
    }
    dq
}

/// What shape a continuum has (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// A closed curve through every angle at one place: "at (x, y), any
    /// angle".
    AnyAngle {
        /// Mean position of its points (m).
        at: V2,
        /// Largest distance of a point from `at` (m).
        spread: f64,
    },
    /// A straight segment at one angle: "on the line from … to …, at θ".
    Line {
        /// One end (m).
        from: V2,
        /// The other end (m).
        to: V2,
        /// The angle (rad, the points' mean).
        theta: f64,
        /// Largest distance of a point from the chord (m).
        bend: f64,
    },
    /// Any other curve (its points are the answer).
    Curve,
}

/// How the part moves once it is on a continuum ([`Continuum::motion`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// Every point is a rest: the part stays where it arrives.
    Rest,
    /// A closed curve with no rest on it: the part goes round for ever,
    /// turning (or moving) at the drift's range.
    Around,
    /// The drift carries the part along the curve to isolated rests on it
    /// (or off it); some stretches may be neutral.
    Drifts,
}

/// Where the flow along a continuum takes a part that arrived at one of
/// its points (`Continuum::destination`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Destination {
    /// It stays at this point (a neutral one).
    Rest(usize),
    /// It goes round the closed curve for ever.
    Around,
    /// It drifts to the isolated rest at this pose (between two points).
    Zero(Pose),
    /// It drifts off the curve's end where the curve stops being slow:
    /// the flow carries on there.
    Off,
    /// It drifts along the curve out of the region.
    Leaves,
}

/// One traced continuum (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Continuum {
    /// Its points in order along it (θ unwrapped along the curve).
    pub points: Vec<Pose>,
    /// The lifted twist at each point.
    pub twists: Vec<Twist>,
    /// Drift along the curve at each point (scaled, 1/s; positive
    /// towards the later points).
    pub drift: Vec<f64>,
    /// The neutral bound at each point (module docs; scaled, 1/s).
    pub neutral: Vec<f64>,
    /// Whether the last point joins the first.
    pub closed: bool,
    /// How the curve ends before its first point and after its last.
    pub ends: [CurveEnd; 2],
    /// Largest real part of the transverse eigenvalues over the points
    /// (1/s): negative when the curve attracts.
    pub transverse: f64,
    /// Largest transverse |eigenvalue| over the points (1/s).
    pub fastest: f64,
    /// Its shape.
    pub shape: Shape,
    /// The part's radius (m), the length scale of the drift.
    pub radius: f64,
}

impl Continuum {
    /// The curve attracts: both transverse eigenvalues have negative real
    /// parts at every point.
    pub fn attracting(&self) -> bool {
        self.transverse < 0.0
    }

    /// How a part moves along it.
    pub fn motion(&self) -> Motion {
        let neutral = |i: usize| self.drift[i].abs() <= self.neutral[i];
        if (0..self.points.len()).all(neutral) {
            Motion::Rest
        } else if self.closed
            && !(0..self.points.len()).any(neutral)
            && self
                .drift
                .iter()
                .all(|g| g.signum() == self.drift[0].signum())
        {
            Motion::Around
        } else {
            Motion::Drifts
        }
    }

    /// The range of the spin ω over the points (rad/s).
    pub fn spin_range(&self) -> [f64; 2] {
        let w = self.twists.iter().map(|t| t.omega);
        [
            w.clone().fold(f64::INFINITY, f64::min),
            w.fold(f64::NEG_INFINITY, f64::max),
        ]
    }

    /// The largest speed |v| over the points (m/s).
    pub fn top_speed(&self) -> f64 {
        self.twists.iter().map(|t| t.v.norm()).fold(0.0, f64::max)
    }

    /// Number of segments (a closed curve's last joins its first point).
    fn segments(&self) -> usize {
        let n = self.points.len();
        if self.closed {
            n
        } else {
            n.saturating_sub(1)
        }
    }

    /// The scaled distance from `q` (pose) to the curve and the index of
    /// the nearer end of the nearest segment (θ compared modulo 2π).
    pub(crate) fn distance(&self, q: &Pose) -> (f64, usize) {
        let r = self.radius.max(f64::MIN_POSITIVE);
        let scaled = |p: &Pose| Vector3::new(p.r.x / r, p.r.y / r, p.theta);
        let x = scaled(q);
        let n = self.points.len();
        if n == 1 {
            let mut d = x - scaled(&self.points[0]);
            d.z = wrap(d.z);
            return (d.norm(), 0);
        }
        let mut best = (f64::INFINITY, 0);
        for i in 0..self.segments() {
            let a = scaled(&self.points[i]);
            let b = scaled(&self.points[(i + 1) % n]);
            let mut d = x - a;
            d.z = wrap(d.z);
            let mut s = b - a;
            s.z = wrap(s.z);
            let t = (d.dot(&s) / s.norm_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
            let dist = (d - s * t).norm();
            if dist < best.0 {
                best = (dist, if t < 0.5 { i } else { (i + 1) % n });
            }
        }
        best
    }

    /// Where the drift along the curve takes a part arriving at point `i`
    /// (module docs).
    pub(crate) fn destination(&self, i: usize) -> Destination {
        let n = self.points.len();
        let neutral = |k: usize| self.drift[k].abs() <= self.neutral[k];
        if neutral(i) {
            return Destination::Rest(i);
        }
        let forward = self.drift[i] > 0.0;
        let mut k = i;
        for _ in 0..n {
            let next = match (forward, self.closed) {
                (true, _) if k + 1 < n => k + 1,
                (true, true) => 0,
                (false, _) if k > 0 => k - 1,
                (false, true) => n - 1,
                _ => {
                    let stop = self.ends[usize::from(forward)];
                    return if stop == CurveEnd::Edge {
                        Destination::Leaves
                    } else {
                        Destination::Off
                    };
                }
            };
            if neutral(next) {
                return Destination::Rest(next);
            }
            if (self.drift[next] > 0.0) != forward {
                return Destination::Zero(self.zero_between(k, next));
            }
            k = next;
        }
        Destination::Around
    }

    /// The drift's zero between neighbouring points `a` and `b`, by linear
    /// interpolation (refined by [`refine_zero`] where it is reported).
    fn zero_between(&self, a: usize, b: usize) -> Pose {
        let (ga, gb) = (self.drift[a], self.drift[b]);
        let t = ga / (ga - gb);
        let (p, q) = (self.points[a], self.points[b]);
        Pose::new(
            p.r.x + t * (q.r.x - p.r.x),
            p.r.y + t * (q.r.y - p.r.y),
            p.theta + t * wrap(q.theta - p.theta),
        )
    }

    /// The drift's sign changes: the interpolated zeros between
    /// successive non-neutral points (a zero inside a neutral stretch lies
    /// between the non-neutral points on either side of it).
    pub(crate) fn zeros(&self) -> Vec<Pose> {
        let neutral = |k: usize| self.drift[k].abs() <= self.neutral[k];
        let counted: Vec<usize> = (0..self.points.len()).filter(|&k| !neutral(k)).collect();
        let wrap =
            (self.closed && counted.len() > 2).then(|| (counted[counted.len() - 1], counted[0]));
        counted
            .windows(2)
            .map(|w| (w[0], w[1]))
            .chain(wrap)
            .filter(|&(a, b)| (self.drift[a] > 0.0) != (self.drift[b] > 0.0))
            .map(|(a, b)| self.zero_between(a, b))
            .collect()
    }
}

/// The tracing step (scaled) for a part of radius `r` (m) in `region`:
/// [`STEP`], or longer where a curve across the region's diagonal would
/// take more than two thirds of [`MAX_STEPS`].
pub(crate) fn step(region: &Region, r: f64) -> f64 {
    let across =
        (region.x[1] - region.x[0]).hypot(region.y[1] - region.y[0]) / r.max(f64::MIN_POSITIVE);
    STEP.max(1.5 * across / MAX_STEPS as f64)
}

/// Traces the slow curve through the slow point `q0` (scaled) within
/// `region`, correcting to the fast residual `tol` (scaled, 1/s).
pub(crate) fn trace(s: &Scaled<'_, '_>, q0: Vector3<f64>, region: &Region, tol: f64) -> Continuum {
    let h = step(region, s.r);
    let t0 = Spectrum::of(&s.j(&q0)).v[2];
    let (forward, ahead) = walk(s, q0, t0, h, region, tol);
    let mut qs: Vec<Vector3<f64>> = Vec::new();
    let mut behind = CurveEnd::Closed;
    if ahead != CurveEnd::Closed {
        let (mut back, stop) = walk(s, q0, -t0, h, region, tol);
        back.reverse();
        qs.extend(back);
        behind = stop;
    }
    qs.push(q0);
    qs.extend(forward);
    build(s, &qs, [behind, ahead])
}

/// How a traced curve ends at one side (an end of a curve, not an
/// iterative loop's stop: that is [`crate::work::Stop`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CurveEnd {
    /// It joined its start: a closed curve.
    Closed,
    /// The next point is outside the region: a part drifting there leaves.
    Edge,
    /// It stops being slow there (or the tracing's steps ran out): the
    /// flow off the curve takes over.
    Ends,
}

/// Steps from `q0` along the slow curve starting in direction `t`, step
/// `h`: the points after `q0`, and why it stopped.
fn walk(
    s: &Scaled<'_, '_>,
    q0: Vector3<f64>,
    mut t: Vector3<f64>,
    h: f64,
    region: &Region,
    tol: f64,
) -> (Vec<Vector3<f64>>, CurveEnd) {
    let mut out = Vec::new();
    let mut q = q0;
    for _ in 0..MAX_STEPS {
        let Some((p, spec)) = correct(s, q, q + t * h, tol) else {
            return (out, CurveEnd::Ends);
        };
        if !region.contains(&s.pose(&p).r) {
            return (out, CurveEnd::Edge);
        }
        // Points are h apart, so the return passes within h/2 of q0; the
        // first points after q0 are at least 2h from it.
        let mut back = p - q0;
        back.z = wrap(back.z);
        if out.len() >= 3 && back.norm() < 0.75 * h {
            return (out, CurveEnd::Closed);
        }
        let tn = spec.v[2];
        t = if tn.dot(&t) < 0.0 { -tn } else { tn };
        out.push(p);
        q = p;
    }
    (out, CurveEnd::Ends)
}

/// The predicted point `p` (a step on from `q`) moved across the curve
/// until its fast residual is within `tol`: the point and its spectrum;
/// `None` when the corrector does not converge or the curve is not slow
/// there. A kink of a grid field's bilinear interpolation under one
/// support point can spoil one finite-difference Jacobian, so the gap
/// counts as lost only when it is lost both at the point and at the
/// step's midpoint.
fn correct(
    s: &Scaled<'_, '_>,
    q: Vector3<f64>,
    mut p: Vector3<f64>,
    tol: f64,
) -> Option<(Vector3<f64>, Spectrum)> {
    for _ in 0..CORRECTOR {
        let f = s.f(&p);
        let spec = Spectrum::of(&s.j(&p));
        if spec.fast_residual(&f) <= tol {
            let slow = spec.slow() || Spectrum::of(&s.j(&((p + q) * 0.5))).slow();
            return slow.then_some((p, spec));
        }
        p += cut(spec.fast_step(&f));
        if !p.iter().all(|x| x.is_finite()) {
            return None;
        }
    }
    None
}

/// The continuum through the scaled points `qs` (module docs).
fn build(s: &Scaled<'_, '_>, qs: &[Vector3<f64>], ends: [CurveEnd; 2]) -> Continuum {
    let closed = ends[1] == CurveEnd::Closed;
    let n = qs.len();
    let mut twists = Vec::with_capacity(n);
    let mut drift = Vec::with_capacity(n);
    let mut neutral = Vec::with_capacity(n);
    let (mut transverse, mut fastest) = (f64::NEG_INFINITY, 0.0f64);
    for q in qs {
        let twist = s.lifted.twist(s.pose(q));
        let j = s.j(q);
        let spec = Spectrum::of(&j);
        // The tangent's sign: towards the next point along the curve.
        let t = spec.v[2];
        let drift_at = t.dot(&s.scale_twist(&twist));
        let mut by_size = eigenvalues(&j);
        by_size.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
        for z in &by_size[1..] {
            transverse = transverse.max(z.re);
            fastest = fastest.max(z.norm());
        }
        twists.push(twist);
        drift.push((t, drift_at));
        neutral.push(spec.neutral());
    }
    // Orient each tangent along the curve (towards the next point; the
    // last as its predecessor's).
    let drift: Vec<f64> = (0..n)
        .map(|i| {
            let (t, g) = drift[i];
            let along = if i + 1 < n {
                qs[i + 1] - qs[i]
            } else if n > 1 {
                qs[i] - qs[i - 1]
            } else {
                t
            };
            let mut along = along;
            along.z = wrap(along.z);
            if t.dot(&along) < 0.0 {
                -g
            } else {
                g
            }
        })
        .collect();
    let points: Vec<Pose> = qs.iter().map(|q| s.pose(q)).collect();
    let shape = shape_of(&points, closed);
    Continuum {
        points,
        twists,
        drift,
        neutral,
        closed,
        ends,
        transverse,
        fastest,
        shape,
        radius: s.r,
    }
}

/// The shape of a traced curve (module docs).
fn shape_of(points: &[Pose], closed: bool) -> Shape {
    let n = points.len().max(1) as f64;
    let mean = points.iter().fold(V2::zeros(), |m, p| m + p.r) / n;
    let spread = points
        .iter()
        .map(|p| (p.r - mean).norm())
        .fold(0.0, f64::max);
    // θ unwrapped along the curve.
    let mut theta = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        let t = match i {
            0 => p.theta,
            _ => theta[i - 1] + wrap(p.theta - points[i - 1].theta),
        };
        theta.push(t);
    }
    let lo = theta.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = theta.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if closed && hi - lo >= std::f64::consts::PI {
        return Shape::AnyAngle { at: mean, spread };
    }
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return Shape::Curve;
    };
    let chord = last.r - first.r;
    let length = chord.norm();
    let bend = points
        .iter()
        .map(|p| {
            let d = p.r - first.r;
            if length > 0.0 {
                (d.x * chord.y - d.y * chord.x).abs() / length
            } else {
                d.norm()
            }
        })
        .fold(0.0, f64::max);
    if !closed && hi - lo <= LINE_TURN && length > 0.0 && bend <= LINE_BEND * length {
        return Shape::Line {
            from: first.r,
            to: last.r,
            theta: wrap(theta.iter().sum::<f64>() / n),
            bend,
        };
    }
    Shape::Curve
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::part::Part;
    use crate::pose::Uniform;
    use crate::pose::{analyse, Region};

    const REGION: Region = Region {
        x: [-0.04, 0.04],
        y: [-0.04, 0.04],
    };

    /// A seeded part: a rectangle (aspect 1.5–4) or a triangle, 8–30 mm
    /// long, turned at random in its file frame.
    fn random_part(rng: &mut Uniform, k: usize) -> Part {
        let long = 0.008 + 0.022 * rng.next();
        let turn = std::f64::consts::TAU * rng.next();
        let corners: Vec<[f64; 2]> = if k.is_multiple_of(2) {
            let wide = long / (1.5 + 2.5 * rng.next());
            [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
                .iter()
                .map(|c| [0.5 * long * c[0], 0.5 * wide * c[1]])
                .collect()
        } else {
            let (a, b) = (0.3 + 0.4 * rng.next(), 0.2 + 0.3 * rng.next());
            vec![[0.0, 0.0], [long, 0.0], [a * long, b * long]]
        };
        let (s, c) = turn.sin_cos();
        let polygon: Vec<[f64; 2]> = corners
            .iter()
            .map(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]])
            .collect();
        let text = serde_json::json!({"name": format!("part {k}"), "polygon": polygon}).to_string();
        Part::from_json_str(&text).expect("a valid part")
    }

    /// Round sinks V = −s (p − c), centre c within ±10 mm and strength s
    /// in 0.5–2 /s, on 6 seeded parts: no isolated equilibrium and one
    /// continuum, through every angle at c (within 1e-6 of the part's
    /// radius), neutral (a round sink turns no part) and attracting, that
    /// all 60 drops end on.
    #[test]
    fn a_round_sink_rests_any_angle_at_its_centre() {
        let mut rng = Uniform::new(7);
        for k in 0..6 {
            let part = random_part(&mut rng, k);
            let centre = V2::new(0.02 * rng.next() - 0.01, 0.02 * rng.next() - 0.01);
            let strength = 0.5 + 1.5 * rng.next();
            let sink = move |p: V2| (centre - p) * strength;
            let a = analyse(&part, &sink, REGION, 60);
            assert!(a.equilibria.is_empty(), "{k}: {:?}", a.equilibria);
            assert_eq!(a.continua.len(), 1, "{k}");
            let c = &a.continua[0];
            let Shape::AnyAngle { at, spread } = c.shape else {
                panic!("{k}: {:?}", c.shape);
            };
            let r = part.radius();
            assert!(
                (at - centre).norm() < 1e-6 * r && spread < 1e-6 * r,
                "{k}: {at} {spread}"
            );
            assert!(
                c.closed && c.attracting() && c.motion() == Motion::Rest,
                "{k}"
            );
            assert_eq!(a.continuum_basins, vec![1.0], "{k}");
        }
    }

    /// Line sinks V = −s (n·p − o) n at a random angle φ and offset o
    /// (±10 mm), on 6 seeded parts: every continuum is a neutral line on
    /// the sink line (its points within 1e-6 R of n·p = o, its chord along
    /// it within 1e-6 of its length) at an angle where the part's
    /// principal axes lie along it (within 1e-6 rad); the attracting ones
    /// hold the major axis along the line; all 60 drops end on them.
    #[test]
    fn a_line_sink_rests_along_its_line() {
        let mut rng = Uniform::new(11);
        for k in 0..6 {
            let part = random_part(&mut rng, k);
            let phi = std::f64::consts::PI * rng.next();
            let (t, n) = (
                V2::new(phi.cos(), phi.sin()),
                V2::new(-phi.sin(), phi.cos()),
            );
            let offset = 0.02 * rng.next() - 0.01;
            let strength = 0.5 + 1.5 * rng.next();
            let sink = move |p: V2| n * (-strength * (n.dot(&p) - offset));
            let a = analyse(&part, &sink, REGION, 60);
            let r = part.radius();
            assert!(!a.continua.is_empty(), "{k}");
            let quarter = |x: f64| {
                let m = x.rem_euclid(std::f64::consts::FRAC_PI_2);
                m.min(std::f64::consts::FRAC_PI_2 - m)
            };
            let half = |x: f64| {
                let m = x.rem_euclid(std::f64::consts::PI);
                m.min(std::f64::consts::PI - m)
            };
            let major = part.principal_angle();
            for c in &a.continua {
                let Shape::Line {
                    from, to, theta, ..
                } = c.shape
                else {
                    panic!("{k}: {:?}", c.shape);
                };
                let chord = to - from;
                assert!(
                    (chord.x * t.y - chord.y * t.x).abs() < 1e-6 * chord.norm(),
                    "{k}"
                );
                for p in &c.points {
                    assert!((n.dot(&p.r) - offset).abs() < 1e-6 * r, "{k}: {p:?}");
                }
                assert!(quarter(theta + major - phi) < 1e-6, "{k}: θ {theta}");
                assert!(c.motion() == Motion::Rest, "{k}");
                if c.attracting() {
                    assert!(half(theta + major - phi) < 1e-6, "{k}: θ {theta}");
                }
            }
            let held: f64 = a.continuum_basins.iter().sum();
            assert!((held - 1.0).abs() < 1e-12, "{k}: {held}");
        }
    }

    /// A worked example of `pose::analysis::continua::eigenvalues`.
    #[test]
    fn example_eigenvalues() {
        use crate::pose::eigenvalues;
        use nalgebra::Matrix3;
        let e = eigenvalues(&Matrix3::from_diagonal(&nalgebra::Vector3::new(
            -1.0, -1.0, 0.0,
        )));
        let mut re: Vec<f64> = e.iter().map(|z| z.re).collect();
        re.sort_by(f64::total_cmp);
        assert!((re[0] + 1.0).abs() < 1e-12 && (re[1] + 1.0).abs() < 1e-12 && re[2].abs() < 1e-12);
    }
}
