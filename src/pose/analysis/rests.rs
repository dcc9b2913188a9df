//! Equilibria on the averaged field: Newton from the lifted field's.
//!
//! The lifted field finds every equilibrium cheaply ([`super::equilibria`])
//! but its spin rates, and so where a spin balances a drift, are only as
//! good as the point field's average (the averaged field's module docs).
//! Each lifted equilibrium q₀ (at most [`MAX_RESTS`], stable ones
//! first) starts Newton's iteration on the averaged field ξ̄(q) = 0:
//!
//! ```text
//! q_{k+1} = q_k − J(q_k)⁻¹ ξ̄(q_k)
//! ```
//!
//! with J by central differences ([`crate::pose::AveragedField::jacobian`]),
//! every evaluation warm-started from the periodic slip at q_k, and each
//! step cut to at most a quarter of the part's radius and 0.3 rad (as the
//! lifted search). A Newton step that does not lower the merit
//! |v|² + (ω R)² (R the part's radius) is replaced by a step of that cut
//! length along the twist itself: the part's own flow, which a stable
//! equilibrium attracts (ω(θ) can fold between the lifted pose and the
//! part's own, where Newton alone oscillates: the rectangle on the
//! designed ellipse turned by 30°, whose averaged rest is 15° from the
//! lifted one). It stops when a step is below [`NEWTON_STOP`] of the radius
//! and [`NEWTON_STOP`] rad: the averaged twist's own precision
//! ([`crate::pose::AVERAGING_TOLERANCE`]) bounds what Newton resolves. The
//! stability is that of J at the last iterate (the eigenvalues' real
//! parts, [`Equilibrium::of_jacobian`]).

use nalgebra::{Matrix3, Vector3};

use super::averaged::AveragedField;
use super::equilibria::{wrap, Equilibrium, Region};
use super::lifted::{Pose, Twist};
use crate::dynamics::ContactLoss;

/// Most lifted equilibria searched for their played rests.
pub const MAX_RESTS: usize = 8;
/// Most Newton steps per equilibrium.
pub const MAX_NEWTON: usize = 12;
/// Smallest step that continues (relative to the radius, and in rad).
pub const NEWTON_STOP: f64 = 1e-3;

/// Where Newton on the averaged field went from one lifted equilibrium.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RestOutcome {
    /// It converged: the averaged field's equilibrium after `steps` steps.
    Found {
        /// The equilibrium and its stability.
        equilibrium: Equilibrium,
        /// Newton steps taken.
        steps: usize,
    },
    /// An iterate left the region.
    Left(Pose),
    /// No step below [`NEWTON_STOP`] in [`MAX_NEWTON`] steps (the last iterate).
    Unconverged(Pose),
    /// A support point loses contact at an iterate.
    Lost(ContactLoss),
}

/// One lifted equilibrium and the played rest Newton found from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayedRest {
    /// The lifted field's equilibrium Newton started from.
    pub from: Equilibrium,
    /// The outcome.
    pub outcome: RestOutcome,
}

impl RestOutcome {
    /// Why no equilibrium was found, in words (`None` when one was).
    pub fn failure(&self) -> Option<String> {
        let at = |p: &Pose| {
            format!(
                "({:+.2} mm, {:+.2} mm, {:+.2}°)",
                1e3 * p.r.x,
                1e3 * p.r.y,
                wrap(p.theta).to_degrees()
            )
        };
        match self {
            RestOutcome::Found { .. } => None,
            RestOutcome::Left(p) => Some(format!("left the region at {}", at(p))),
            RestOutcome::Unconverged(p) => Some(format!("no convergence (last at {})", at(p))),
            RestOutcome::Lost(c) => Some(format!(
                "a support point loses contact at ({:+.4}, {:+.4}) m",
                c.position[0], c.position[1]
            )),
        }
    }
}

impl PlayedRest {
    /// How far the averaged field's equilibrium lies from the lifted one
    /// it started from: distance (m) and turn (rad, wrapped); `None` when
    /// none was found.
    pub fn moved(&self) -> Option<(f64, f64)> {
        match self.outcome {
            RestOutcome::Found { equilibrium: e, .. } => Some((
                (e.pose.r - self.from.pose.r).norm(),
                wrap(e.pose.theta - self.from.pose.theta),
            )),
            _ => None,
        }
    }
}

/// The played rests of the lifted equilibria `lifted` (stable first, at most
/// [`MAX_RESTS`]) on `averaged` within `region`, in parallel (the same
/// result on any number of threads); `done` is called after each.
pub fn played_rests(
    averaged: &AveragedField,
    lifted: &[Equilibrium],
    region: &Region,
    done: &(dyn Fn() + Sync),
) -> Vec<PlayedRest> {
    use rayon::prelude::*;
    let mut starts: Vec<Equilibrium> = lifted.iter().filter(|e| e.stable).copied().collect();
    starts.extend(lifted.iter().filter(|e| !e.stable));
    starts.truncate(MAX_RESTS);
    starts
        .par_iter()
        .map(|e| {
            let outcome = newton(averaged, e.pose, region);
            done();
            PlayedRest { from: *e, outcome }
        })
        .collect()
}

/// Newton on the averaged field from `start`, guarded by the flow
/// (module docs).
fn newton(averaged: &AveragedField, start: Pose, region: &Region) -> RestOutcome {
    match newton_or_flow(averaged, start, region) {
        Ok(r) => r,
        Err(loss) => RestOutcome::Lost(loss),
    }
}

/// [`newton`], a lost contact as the error.
fn newton_or_flow(
    averaged: &AveragedField,
    start: Pose,
    region: &Region,
) -> Result<RestOutcome, ContactLoss> {
    let radius = averaged.radius();
    let merit = |t: &Twist| t.v.norm_squared() + (t.omega * radius).powi(2);
    let mut q = start;
    let (a, slip) = averaged.twist_from(q, None)?;
    let (mut xi, mut warm) = (a.twist, slip);
    for k in 0..MAX_NEWTON {
        let j = averaged.jacobian(q, Some(warm))?;
        let Some(newton) = newton_step(&j, &xi, radius) else {
            return Ok(RestOutcome::Unconverged(q));
        };
        let (mut dq, (mut next, mut slip)) =
            (newton, averaged.twist_from(moved(q, &newton), Some(warm))?);
        if merit(&next.twist) >= merit(&xi) {
            // Newton does not bring the twist down (a fold of ω(θ) between
            // the lifted pose and the part's own): follow the flow instead.
            dq = flow_step(&xi, radius);
            (next, slip) = averaged.twist_from(moved(q, &dq), Some(warm))?;
        }
        q = moved(q, &dq);
        (xi, warm) = (next.twist, slip);
        if !region.contains(&q.r) {
            return Ok(RestOutcome::Left(q));
        }
        if dq.fixed_rows::<2>(0).norm() < NEWTON_STOP * radius && dq.z.abs() < NEWTON_STOP {
            let pose = Pose::new(q.r.x, q.r.y, wrap(q.theta));
            return Ok(RestOutcome::Found {
                equilibrium: Equilibrium::of_jacobian(pose, &j),
                steps: k + 1,
            });
        }
    }
    Ok(RestOutcome::Unconverged(q))
}

/// `q` moved by `dq` = (Δx, Δy, Δθ).
fn moved(q: Pose, dq: &Vector3<f64>) -> Pose {
    Pose::new(q.r.x + dq.x, q.r.y + dq.y, q.theta + dq.z)
}

/// `dq` cut to at most a quarter of `radius` in position and 0.3 rad.
fn cut(mut dq: Vector3<f64>, radius: f64) -> Vector3<f64> {
    let c = (dq.fixed_rows::<2>(0).norm() / (0.25 * radius)).max(dq.z.abs() / 0.3);
    if c > 1.0 {
        dq /= c;
    }
    dq
}

/// The cut Newton step −J⁻¹ ξ (`None` when J is singular).
fn newton_step(j: &Matrix3<f64>, xi: &Twist, radius: f64) -> Option<Vector3<f64>> {
    let rhs = -Vector3::new(xi.v.x, xi.v.y, xi.omega);
    j.lu().solve(&rhs).map(|dq| cut(dq, radius))
}

/// How long (s) the part follows its twist in a flow step before the cut
/// shortens it: long enough that the cut decides for any twist above
/// 1e-9 m/s or rad/s (a smaller one is an equilibrium to the averaging's
/// precision).
const FLOW_REACH_S: f64 = 1e6;

/// A step along the twist, as far as the cut allows: where the part
/// would go (a stable equilibrium attracts it).
fn flow_step(xi: &Twist, radius: f64) -> Vector3<f64> {
    cut(
        Vector3::new(xi.v.x, xi.v.y, xi.omega) * FLOW_REACH_S,
        radius,
    )
}
