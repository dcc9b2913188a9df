//! Equilibria on the averaged field: Newton from the lifted field's.
//!
//! The lifted field finds every equilibrium cheaply ([`super::equilibria`])
//! but its spin rates, and so where a spin balances a drift, are only as
//! good as the point field's average (the averaged field's module docs).
//! Each lifted equilibrium q₀ (at most [`MAX_REFINED`], stable ones
//! first) starts Newton's iteration on the averaged field ξ̄(q) = 0:
//!
//! ```text
//! q_{k+1} = q_k − J(q_k)⁻¹ ξ̄(q_k)
//! ```
//!
//! with J by central differences ([`super::AveragedField::jacobian`]),
//! every evaluation warm-started from the periodic slip at q_k, and each
//! step cut to at most a quarter of the part's radius and 0.3 rad (as the
//! lifted search). It stops when a step is below [`STOP`] of the radius
//! and [`STOP`] rad: the averaged twist's own precision
//! ([`super::AVERAGING_TOLERANCE`]) bounds what Newton resolves. The
//! stability is that of J at the last iterate (the eigenvalues' real
//! parts, [`Equilibrium::of_jacobian`]).

use nalgebra::{Matrix3, Vector3};

use super::averaged::{AveragedField, Slip};
use super::equilibria::{wrap, Equilibrium, Region};
use super::lifted::Pose;
use crate::dynamics::ContactLoss;

/// Most lifted equilibria refined.
pub const MAX_REFINED: usize = 8;
/// Most Newton steps per equilibrium.
pub const MAX_NEWTON: usize = 12;
/// Smallest step that continues (relative to the radius, and in rad).
pub const STOP: f64 = 1e-3;

/// Where Newton on the averaged field went from one lifted equilibrium.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Refined {
    /// It converged: the averaged field's equilibrium after `steps` steps.
    Found {
        /// The equilibrium and its stability.
        equilibrium: Equilibrium,
        /// Newton steps taken.
        steps: usize,
    },
    /// An iterate left the region.
    Left(Pose),
    /// No step below [`STOP`] in [`MAX_NEWTON`] steps (the last iterate).
    Unconverged(Pose),
    /// A support point loses contact at an iterate.
    Lost(ContactLoss),
}

/// One lifted equilibrium and where it refined to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refinement {
    /// The lifted field's equilibrium Newton started from.
    pub from: Equilibrium,
    /// The outcome.
    pub outcome: Refined,
}

impl Refined {
    /// Why no equilibrium was found, in words (`None` when one was).
    pub fn failure(&self) -> Option<String> {
        let at = |p: &Pose| {
            format!(
                "({:+.2} mm, {:+.2} mm, {:+.2}°)",
                1e3 * p.r.x,
                1e3 * p.r.y,
                p.theta.to_degrees()
            )
        };
        match self {
            Refined::Found { .. } => None,
            Refined::Left(p) => Some(format!("left the region at {}", at(p))),
            Refined::Unconverged(p) => Some(format!("no convergence (last at {})", at(p))),
            Refined::Lost(c) => Some(format!(
                "a support point loses contact at ({:+.4}, {:+.4}) m",
                c.position[0], c.position[1]
            )),
        }
    }
}

impl Refinement {
    /// How far the averaged field's equilibrium lies from the lifted one
    /// it started from: distance (m) and turn (rad, wrapped); `None` when
    /// none was found.
    pub fn moved(&self) -> Option<(f64, f64)> {
        match self.outcome {
            Refined::Found { equilibrium: e, .. } => Some((
                (e.pose.r - self.from.pose.r).norm(),
                wrap(e.pose.theta - self.from.pose.theta),
            )),
            _ => None,
        }
    }
}

/// Refines the lifted equilibria `lifted` (stable first, at most
/// [`MAX_REFINED`]) on `averaged` within `region`, in parallel (the same
/// result on any number of threads); `done` is called after each.
pub fn refine(
    averaged: &AveragedField,
    lifted: &[Equilibrium],
    region: &Region,
    done: &(dyn Fn() + Sync),
) -> Vec<Refinement> {
    use rayon::prelude::*;
    let mut starts: Vec<Equilibrium> = lifted.iter().filter(|e| e.stable).copied().collect();
    starts.extend(lifted.iter().filter(|e| !e.stable));
    starts.truncate(MAX_REFINED);
    starts
        .par_iter()
        .map(|e| {
            let outcome = newton(averaged, e.pose, region);
            done();
            Refinement { from: *e, outcome }
        })
        .collect()
}

/// Newton on the averaged field from `start` (module docs).
fn newton(averaged: &AveragedField, start: Pose, region: &Region) -> Refined {
    let radius = averaged.radius();
    let mut q = start;
    let mut warm: Option<Slip> = None;
    for k in 0..MAX_NEWTON {
        let step = match newton_step(averaged, q, &mut warm) {
            Ok(s) => s,
            Err(loss) => return Refined::Lost(loss),
        };
        let Some((dq, j)) = step else {
            return Refined::Unconverged(q);
        };
        q = Pose::new(q.r.x + dq[0], q.r.y + dq[1], q.theta + dq[2]);
        if !region.contains(&q.r) {
            return Refined::Left(q);
        }
        if (dq[0].hypot(dq[1])) < STOP * radius && dq[2].abs() < STOP {
            let pose = Pose::new(q.r.x, q.r.y, wrap(q.theta));
            return Refined::Found {
                equilibrium: Equilibrium::of_jacobian(pose, &j),
                steps: k + 1,
            };
        }
    }
    Refined::Unconverged(q)
}

/// A Newton step (Δx, Δy, Δθ) and the Jacobian it solved with.
type Step = ([f64; 3], Matrix3<f64>);

/// One cut Newton step at `q` and the Jacobian there (`None` when it is
/// singular); `warm` carries the periodic slip from iterate to iterate.
fn newton_step(
    averaged: &AveragedField,
    q: Pose,
    warm: &mut Option<Slip>,
) -> Result<Option<Step>, ContactLoss> {
    let (a, slip) = averaged.twist_from(q, *warm)?;
    *warm = Some(slip);
    let j = averaged.jacobian(q, *warm)?;
    let xi = Vector3::new(a.twist.v.x, a.twist.v.y, a.twist.omega);
    let Some(mut dq) = j.lu().solve(&(-xi)) else {
        return Ok(None);
    };
    let radius = averaged.radius();
    let cut = (dq.fixed_rows::<2>(0).norm() / (0.25 * radius)).max(dq.z.abs() / 0.3);
    if cut > 1.0 {
        dq /= cut;
    }
    Ok(Some(([dq.x, dq.y, dq.z], j)))
}
