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

use super::continua::{self, cut, eigenvalues, Continuum, Destination, Scaled, Spectrum, ARRIVE};
pub use super::lifted::wrap;
pub use super::lifted::Region;
use super::lifted::{LiftedField, Pose};
use crate::dynamics::V2;

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

/// Poses of the start grid ([`start_poses`]).
pub(crate) const START_POSES: usize = 3 * 3 * 24;

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

/// What Newton from one start converged to.
enum Found {
    /// An isolated zero.
    Zero(Pose),
    /// A point of a slow curve (scaled, [`super::continua`]).
    Slow(Vector3<f64>),
}

/// Newton from `start`: the zero it converged to inside the region, or
/// the point of a slow curve where the fast residual vanishes (the
/// Jacobian's smallest singular value below [`GAP`] of the next: its step
/// then takes the fast components only, [`super::continua`]).
fn newton(lifted: &LiftedField<'_>, start: Pose, region: &Region, tol: f64) -> Option<Found> {
    let r = lifted.radius();
    let scaled = Scaled::new(lifted);
    let mut q = Vector3::new(start.r.x, start.r.y, start.theta);
    for _ in 0..60 {
        let t = lifted.twist3(&q);
        let j = lifted.jacobian(Pose::new(q.x, q.y, q.z));
        let spectrum = Spectrum::of(&scaled.scale_jacobian(&j));
        let mut step = if spectrum.slow() {
            let f = scaled.scale_twist3(&t);
            if spectrum.fast_residual(&f) <= tol / r.max(f64::MIN_POSITIVE) {
                let pose = Pose::new(q.x, q.y, q.z);
                return region
                    .contains(&pose.r)
                    .then(|| Found::Slow(scaled.of(pose)));
            }
            let d = cut(spectrum.fast_step(&f));
            Vector3::new(d.x * r, d.y * r, d.z)
        } else {
            if t.fixed_rows::<2>(0).norm() <= tol && t.z.abs() * r <= tol {
                let pose = Pose::new(q.x, q.y, wrap(q.z));
                return region.contains(&pose.r).then_some(Found::Zero(pose));
            }
            j.lu().solve(&(-t))?
        };
        let c = (step.fixed_rows::<2>(0).norm() / (0.25 * r)).max(step.z.abs() / 0.3);
        if c > 1.0 {
            step /= c;
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
    pub(crate) fn of_jacobian(pose: Pose, j: &Matrix3<f64>) -> Equilibrium {
        let e = eigenvalues(j);
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

/// The rests of a lifted field over a region: its isolated equilibria and
/// its continua (`super::continua`).
#[derive(Debug, Clone, PartialEq)]
pub struct Rests {
    /// Isolated equilibria, sorted by θ then x then y: Newton's zeros and
    /// the drift's zeros on the continua.
    pub equilibria: Vec<Equilibrium>,
    /// The slow curves traced, in the order their first point was found.
    pub continua: Vec<Continuum>,
}

/// Every equilibrium of `lifted` found from the start grid over `region`,
/// sorted by θ then x then y ([`rests`]' equilibria).
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
    rests(lifted, region).equilibria
}

/// The isolated equilibria and the continua of `lifted` over `region`:
/// Newton from every pose of the start grid (in parallel: the same result
/// on any number of threads); each start that lands on a slow curve not
/// yet traced traces it (`super::continua`), and the drift's zeros on
/// the curves are refined into isolated equilibria.
///
/// ```
/// use platefield::dynamics::{PlanarBody, V2};
/// use platefield::pose::{rests, LiftedField, Region, Shape};
/// let (body, _) = PlanarBody::centred(
///     &[V2::new(-0.01, -0.002), V2::new(0.01, -0.002), V2::new(0.01, 0.002), V2::new(-0.01, 0.002)],
///     &[1.0; 4],
/// );
/// // A round sink turns no part: at its centre, any angle is a rest.
/// let sink = |p: V2| V2::new(-p.x, -p.y);
/// let region = Region { x: [-0.03, 0.03], y: [-0.03, 0.03] };
/// let r = rests(&LiftedField::new(&sink, &body), &region);
/// assert!(r.equilibria.is_empty() && r.continua.len() == 1);
/// let Shape::AnyAngle { at, spread } = r.continua[0].shape else { panic!() };
/// assert!(at.norm() < 1e-9 && spread < 1e-9);
/// ```
pub fn rests(lifted: &LiftedField<'_>, region: &Region) -> Rests {
    use rayon::prelude::*;
    let starts = start_poses(region);
    let tol = 1e-9 * speed_scale(lifted, &starts);
    let r = lifted.radius();
    let outcomes: Vec<Option<Found>> = starts
        .par_iter()
        .map(|s| newton(lifted, *s, region, tol))
        .collect();
    let same = |q: &Pose, p: &Pose| {
        (q.r - p.r).norm() <= 1e-6 * r && wrap(q.theta - p.theta).abs() <= 1e-4
    };
    let scaled = Scaled::new(lifted);
    let step = continua::step(region, r);
    let mut found: Vec<Pose> = Vec::new();
    let mut continua: Vec<Continuum> = Vec::new();
    for outcome in outcomes.into_iter().flatten() {
        match outcome {
            Found::Zero(p) => {
                if !found.iter().any(|q| same(q, &p)) {
                    found.push(p);
                }
            }
            Found::Slow(q) => {
                let p = scaled.pose(&q);
                if continua.iter().any(|c| c.distance(&p).0 <= 2.0 * step) {
                    continue;
                }
                let c = continua::trace(&scaled, q, region, tol / r.max(f64::MIN_POSITIVE));
                // A slow stretch shorter than two steps is a fold (the
                // Jacobian singular at one pose: ω(θ) at its extremum),
                // not a curve of rests.
                if c.points.len() >= continua::MIN_POINTS {
                    continua.push(c);
                }
            }
        }
    }
    let mut equilibria: Vec<Equilibrium> = found
        .into_iter()
        .map(|pose| Equilibrium::of_jacobian(pose, &lifted.jacobian(pose)))
        .collect();
    for c in &continua {
        for z in c.zeros() {
            let Some(e) = refine_zero(lifted, z, region, tol / r.max(f64::MIN_POSITIVE)) else {
                continue;
            };
            if !equilibria.iter().any(|q| same(&q.pose, &e.pose)) {
                equilibria.push(e);
            }
        }
    }
    equilibria.sort_by(|a, b| {
        a.pose
            .theta
            .total_cmp(&b.pose.theta)
            .then(a.pose.r.x.total_cmp(&b.pose.r.x))
            .then(a.pose.r.y.total_cmp(&b.pose.r.y))
    });
    Rests {
        equilibria,
        continua,
    }
}

/// Full Newton on the lifted field from `start` (a drift zero on a
/// curve): the zero within the region, or `None`.
fn refine_zero(
    lifted: &LiftedField<'_>,
    start: Pose,
    region: &Region,
    tol: f64,
) -> Option<Equilibrium> {
    let s = Scaled::new(lifted);
    let mut q = s.of(start);
    for _ in 0..40 {
        let f = s.f(&q);
        let j = s.j(&q);
        if f.norm() <= tol {
            let pose = s.pose(&q);
            let pose = Pose::new(pose.r.x, pose.r.y, wrap(pose.theta));
            return region
                .contains(&pose.r)
                .then(|| Equilibrium::of_jacobian(pose, &lifted.jacobian(pose)));
        }
        let spec = Spectrum::of(&j);
        // All three components: σ₃ is small on a slow curve, not zero.
        let mut step = spec.fast_step(&f);
        if spec.sigma[2] > 0.0 {
            step += spec.v[2] * (-spec.u[2].dot(&f) / spec.sigma[2]);
        }
        q += cut(step);
        if !q.iter().all(|x| x.is_finite()) {
            return None;
        }
    }
    None
}

/// Whether a drop at `pose` has arrived on one of the `attracting`
/// continua (within [`ARRIVE`]) and where the flow along it takes it:
/// `Some(end)` to stop there (`None` inside: it drifts out of the
/// region), `None` to go on integrating.
fn arrival(
    scaled: &Scaled<'_, '_>,
    pose: &Pose,
    stable: &[Equilibrium],
    attracting: &[(usize, &Continuum)],
    step: f64,
) -> Option<Option<End>> {
    for (k, c) in attracting {
        let (d, i) = c.distance(pose);
        if d > ARRIVE {
            continue;
        }
        match c.destination(i) {
            Destination::Rest(_) | Destination::Around => return Some(Some(End::On(*k))),
            Destination::Zero(z) => {
                let at = scaled.of(z);
                let k = stable
                    .iter()
                    .map(|e| {
                        let mut d = scaled.of(e.pose) - at;
                        d.z = wrap(d.z);
                        d.norm()
                    })
                    .enumerate()
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .filter(|(_, d)| *d <= 2.0 * step);
                if let Some((k, _)) = k {
                    return Some(Some(End::At(k)));
                }
            }
            Destination::Leaves => return Some(None),
            Destination::Off => {}
        }
    }
    None
}

/// Where a drop ends (`settle_on`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// At the stable equilibrium of this index (in the list given).
    At(usize),
    /// On the continuum of this index: resting on it, or going round it.
    On(usize),
}

/// Where one drop ends: the index of the stable equilibrium it reached.
pub fn settle(
    lifted: &LiftedField<'_>,
    start: Pose,
    stable: &[Equilibrium],
    region: &Region,
) -> Option<usize> {
    match settle_on(lifted, start, stable, &[], region)? {
        End::At(k) => Some(k),
        End::On(_) => None,
    }
}

/// Where one drop ends among the `stable` equilibria and the `continua`
/// (module docs): within [`ARRIVE`] of an attracting continuum, the flow
/// along it decides (`Continuum::destination`): a rest on it or a
/// curve it goes round is its end, a drift zero the stable equilibrium
/// there (the drop goes on integrating when the drift carries it off the
/// curve, or to a zero that is not a stable equilibrium).
pub(crate) fn settle_on(
    lifted: &LiftedField<'_>,
    start: Pose,
    stable: &[Equilibrium],
    continua: &[Continuum],
    region: &Region,
) -> Option<End> {
    let r = lifted.radius();
    let attracting: Vec<(usize, &Continuum)> = continua
        .iter()
        .enumerate()
        .filter(|(_, c)| c.attracting())
        .collect();
    let fastest = stable
        .iter()
        .map(|e| e.rates.iter().fold(0.0f64, |m, x| m.max(x.abs())))
        .chain(attracting.iter().map(|(_, c)| c.fastest))
        .fold(0.0f64, f64::max);
    let scaled = Scaled::new(lifted);
    let step = continua::step(region, r);
    let near = |q: &Vector3<f64>| {
        stable.iter().position(|e| {
            (V2::new(q.x, q.y) - e.pose.r).norm() <= 1e-3 * r
                && wrap(q.z - e.pose.theta).abs() <= 0.1f64.to_radians()
        })
    };
    let mut q = Vector3::new(start.r.x, start.r.y, start.theta);
    for _ in 0..SETTLE_STEPS {
        if let Some(k) = near(&q) {
            return Some(End::At(k));
        }
        if !region.contains(&V2::new(q.x, q.y)) {
            return None;
        }
        let pose = Pose::new(q.x, q.y, q.z);
        if let Some(end) = arrival(&scaled, &pose, stable, &attracting, step) {
            return end;
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
