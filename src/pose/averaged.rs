//! The averaged field: a planar part's mean twist at a pose, from the
//! rigid part's own periodic slip at that pose (the planar simulator with
//! the pose frozen), where [`super::LiftedField`] integrates the point
//! parts' mean velocities over the support.
//!
//! **Model.** The rigid part's slip ξ(t) = (u, ω) obeys the planar
//! simulator's Newton–Euler law with Coulomb friction summed over its
//! support points ([`crate::dynamics::PlanarSimulator`]). Played cycle
//! after cycle, each cycle started at the pose q = (r, θ) with the slip the
//! last one ended with, it settles to a periodic slip; the part moves
//! within each cycle (its excursion, a fraction of a millimetre, changes
//! the kinematics it sees, as the point field's `moving` model does) but
//! not from one cycle to the next. The averaged field is that state's mean
//! twist,
//!
//! ```text
//! ξ̄(q) = (1/T) ∫_cycle ξ(t) dt      (the pose's change over the cycle / T)
//! ```
//!
//! and, for a schedule, the time-weighted mean of its segments' (a rest
//! segment contributing zero), as [`super::schedule_field`] weights the
//! point fields. The only approximation is that the pose's drift over a
//! cycle does not feed back within it.
//!
//! **Why both fields.** Coulomb friction is not linear in the slip, so
//! averaging over the cycle and summing over the support do not commute.
//! The lifted field averages first (each support point's own mean
//! velocity V(p_j)) and then fits a rigid twist; that gets the
//! translation right (0.6 % RMS against the moving part, `tests/poses.rs`)
//! but not the spin, which comes from the small differences between the
//! points' drifts riding on a large shared slip. The spin then depends on
//! how friction damps a drift across that slip, which V(p) does not
//! record: the lifted field's spin is 1.3–3 times the simulated rate on
//! the LineSink (RMS error 129 %); a point-by-point Coulomb law on the shared slip gives about
//! half of it (the part's rocking spin, which the shared slip leaves out,
//! softens the damping across it). The averaged field sums first, as the
//! part does: spin within 0.3 % RMS, translation 0.6 %. The lifted field is the fast map the equilibrium
//! search and the drops integrate ([`super::equilibria`]); the averaged
//! field checks it ([`LiftCheck`]) at the cost of a few cycles of the
//! planar part per pose.

use crate::dynamics::{ContactLoss, PartPhysics, PlanarBody, PlanarSimulator, PlanarState, Plate};
use crate::motion::Motion;

use super::lifted::{LiftedField, Pose, Twist};
use super::run::{drop_starts, PoseAnalysis};

/// No motion.
const ZERO: Twist = Twist {
    v: crate::dynamics::V2::new(0.0, 0.0),
    omega: 0.0,
};

/// Planar steps per cycle by default.
pub const AVERAGING_STEPS: usize = 64;
/// Most cycles played per pose and motion before the last cycle's twist is
/// taken as it stands ([`Averaged::converged`] false).
pub const MAX_AVERAGING_CYCLES: u32 = 60;
/// Two consecutive cycles' twists closer than this, relative to the
/// slip scale μ g T (and μ g T / radius for the spin), end the averaging.
pub const AVERAGING_TOLERANCE: f64 = 1e-5;

/// A schedule's plate motions: (motion, or `None` for a plate at rest;
/// duration in s) per segment.
pub type Segments = Vec<(Option<Motion>, f64)>;

/// One pose's averaged twist.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Averaged {
    /// The mean twist of the last cycle played (time-weighted over the
    /// schedule's segments).
    pub twist: Twist,
    /// Cycles played (summed over the segments).
    pub cycles: u32,
    /// Every segment's last two cycles agreed within
    /// [`AVERAGING_TOLERANCE`].
    pub converged: bool,
}

/// The averaged field of one part on one periodic motion or schedule of
/// motions (module docs).
pub struct AveragedField<'a> {
    body: &'a PlanarBody,
    physics: PartPhysics,
    /// (steady periodic motion, weight) per segment; rest segments are
    /// left out but count in the weights' total.
    motions: Vec<(Motion, f64)>,
    /// Planar steps per cycle.
    steps: usize,
}

impl<'a> AveragedField<'a> {
    /// The averaged field of `body` on `motion` with `physics`.
    ///
    /// ```
    /// use platefield::basis::{Primitive, PrimitiveKind};
    /// use platefield::dynamics::{PartPhysics, PlanarBody, V2};
    /// use platefield::pose::{AveragedField, Pose};
    /// // Two equal support points 2 cm apart on the LineSink primitive, at
    /// // 45° to x: the pair turns toward its sink line (along y, ω > 0) and
    /// // drifts toward it (near x = 2.5 mm) from x = 5 mm.
    /// let (body, _) = PlanarBody::centred(&[V2::new(-0.01, 0.0), V2::new(0.01, 0.0)], &[1.0, 1.0]);
    /// let motion = Primitive::new(PrimitiveKind::LineSink).motion();
    /// let field = AveragedField::new(&body, &motion, PartPhysics::full(0.3));
    /// let a = field.twist(Pose::new(0.005, 0.0, 45f64.to_radians())).unwrap();
    /// assert!(a.converged && a.twist.omega > 0.0 && a.twist.v.x < 0.0);
    /// ```
    pub fn new(body: &'a PlanarBody, motion: &Motion, physics: PartPhysics) -> AveragedField<'a> {
        AveragedField::of_segments(body, physics, vec![(Some(motion.clone()), 1.0)])
    }

    /// The averaged field of `body` on a schedule's segments: (motion,
    /// duration), `None` for a plate at rest.
    pub fn of_segments(
        body: &'a PlanarBody,
        physics: PartPhysics,
        segments: Segments,
    ) -> AveragedField<'a> {
        let total: f64 = segments.iter().map(|s| s.1).sum();
        let motions = segments
            .into_iter()
            .filter_map(|(m, d)| m.map(|m| (steady(m), d / total)))
            .collect();
        AveragedField {
            body,
            physics,
            motions,
            steps: AVERAGING_STEPS,
        }
    }

    /// The same field played with `steps` planar steps per cycle (default
    /// [`AVERAGING_STEPS`]).
    pub fn with_steps(mut self, steps: usize) -> AveragedField<'a> {
        self.steps = steps.max(1);
        self
    }

    /// The mean twist at `pose`, or where a support point loses contact.
    pub fn twist(&self, pose: Pose) -> Result<Averaged, ContactLoss> {
        let mut sum = ZERO;
        let (mut cycles, mut converged) = (0, true);
        for (motion, weight) in &self.motions {
            let (t, n, ok) = self.periodic_twist(motion, pose)?;
            sum.v += t.v * *weight;
            sum.omega += t.omega * weight;
            cycles += n;
            converged &= ok;
        }
        Ok(Averaged {
            twist: sum,
            cycles,
            converged,
        })
    }

    /// One motion's periodic mean twist: cycles from rest until two agree.
    fn periodic_twist(
        &self,
        motion: &Motion,
        pose: Pose,
    ) -> Result<(Twist, u32, bool), ContactLoss> {
        let period = motion.period();
        let sim = PlanarSimulator::for_body(
            self.body.clone(),
            Plate::Moving(motion),
            self.physics,
            period / self.steps as f64,
        );
        let scale = self.physics.friction.kinetic * self.physics.gravity * period;
        let radius = self
            .body
            .points()
            .iter()
            .map(|p| p.norm())
            .fold(0.0, f64::max);
        let anchor = (pose.r, pose.theta);
        let mut s = PlanarState::at_rest(pose.r, pose.theta);
        let mut last: Option<Twist> = None;
        for k in 0..MAX_AVERAGING_CYCLES {
            // Each cycle starts at the pose with the slip the last left.
            (s.r, s.theta) = (pose.r, pose.theta);
            let (a, t0) = (s, period * f64::from(k));
            sim.advance(t0, t0 + period, &mut s, anchor, None)?;
            let twist = Twist {
                v: (s.r - a.r) / period,
                omega: (s.theta - a.theta) / period,
            };
            if let Some(p) = last {
                let dv = (twist.v - p.v).norm() / scale;
                let dw = (twist.omega - p.omega).abs() * radius / scale;
                if dv.max(dw) < AVERAGING_TOLERANCE {
                    return Ok((twist, k + 1, true));
                }
            }
            last = Some(twist);
        }
        Ok((last.unwrap_or(ZERO), MAX_AVERAGING_CYCLES, false))
    }
}

/// The periodic part of a segment's motion: a ramped segment's steady
/// signals.
fn steady(motion: Motion) -> Motion {
    match motion {
        Motion::Ramped(r) => Motion::Signals(r.signals),
        m => m,
    }
}

/// Poses the `poses` command checks at most.
pub const CHECKED_POSES: usize = 20;

/// The poses the `poses` command checks: every equilibrium of `a`, then
/// its first drop starts, [`CHECKED_POSES`] in all (equilibria first when
/// there are more).
pub fn checked_poses(a: &PoseAnalysis) -> Vec<Pose> {
    let mut poses: Vec<Pose> = a
        .equilibria
        .iter()
        .map(|e| e.pose)
        .take(CHECKED_POSES)
        .collect();
    let more = CHECKED_POSES - poses.len();
    poses.extend(drop_starts(&a.starts, more));
    poses
}

/// The lifted field against the averaged field at sampled poses.
#[derive(Debug, Clone, PartialEq)]
pub struct LiftCheck {
    /// Per pose: the pose, the lifted field's twist and the averaged one
    /// (`None` where a support point loses contact).
    pub poses: Vec<(Pose, Twist, Option<Averaged>)>,
    /// RMS of |v_lifted − v_averaged| over the RMS of |v_averaged|
    /// (`None` when no pose kept contact or every averaged v is 0).
    pub translation_rms: Option<f64>,
    /// RMS of |ω_lifted − ω_averaged| over the RMS of |ω_averaged|
    /// (`None` likewise).
    pub spin_rms: Option<f64>,
}

impl LiftCheck {
    /// Compares `lifted` with `averaged` at `poses` (in parallel; the
    /// same result on any number of threads).
    pub fn run(
        lifted: &LiftedField<'_>,
        averaged: &AveragedField<'_>,
        poses: &[Pose],
    ) -> LiftCheck {
        use rayon::prelude::*;
        let rows: Vec<_> = poses
            .par_iter()
            .map(|p| (*p, lifted.twist(*p), averaged.twist(*p).ok()))
            .collect();
        let pairs: Vec<(Twist, Twist)> = rows
            .iter()
            .filter_map(|(_, l, a)| a.map(|a| (*l, a.twist)))
            .collect();
        let rms = |f: &dyn Fn(&(Twist, Twist)) -> f64| {
            (pairs.iter().map(|p| f(p).powi(2)).sum::<f64>() / pairs.len().max(1) as f64).sqrt()
        };
        let relative = |num: f64, den: f64| (den > 0.0).then(|| num / den);
        LiftCheck {
            translation_rms: relative(rms(&|p| (p.0.v - p.1.v).norm()), rms(&|p| p.1.v.norm())),
            spin_rms: relative(rms(&|p| p.0.omega - p.1.omega), rms(&|p| p.1.omega)),
            poses: rows,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::{Primitive, PrimitiveKind};
    use crate::dynamics::V2;
    use crate::field::{Field, FieldKind, FieldSettings, Grid};

    fn rectangle() -> PlanarBody {
        let points: Vec<V2> = (0..8)
            .flat_map(|i| {
                (0..2).map(move |j| {
                    V2::new(-0.00875 + 0.0025 * i as f64, -0.00125 + 0.0025 * j as f64)
                })
            })
            .collect();
        PlanarBody::centred(&points, &vec![1.0; points.len()]).0
    }

    /// A point part's averaged twist is the point-part velocity field,
    /// computed by the event-exact point engine (an independent
    /// integrator): within 0.1 % of the field's largest speed (measured
    /// 0.02 %).
    #[test]
    fn a_point_part_drifts_at_the_point_field() {
        let motion = Primitive::new(PrimitiveKind::LineSink).motion();
        let settings = FieldSettings::default();
        let body = PlanarBody::point();
        let averaged = AveragedField::new(&body, &motion, settings.physics());
        let grid = Grid {
            x: [-0.02, 0.02],
            y: [0.0, 0.0],
            n: [5, 1],
        };
        let field = Field::compute(&motion, &grid, FieldKind::Velocity, &settings, &|| {});
        let top = field
            .vectors
            .iter()
            .map(|v| v[0].hypot(v[1]))
            .fold(0.0, f64::max);
        for (p, v) in grid.points().iter().zip(&field.vectors) {
            let a = averaged.twist(Pose::new(p[0], p[1], 0.0)).unwrap();
            let e = (a.twist.v - V2::new(v[0], v[1])).norm() / top;
            println!(
                "x {:+.3}: averaged {:+.4e}, field {:+.4e}, relative {e:.2e}",
                p[0], a.twist.v.x, v[0]
            );
            assert!(
                a.converged && e < 1e-3 && a.twist.omega == 0.0,
                "{p:?} {a:?} {v:?} {e}"
            );
        }
    }

    /// The LineSink motion is its own mirror image in y → −y, so a
    /// rectangle on its sink line's normal at ±θ spins at ∓ the same rate
    /// and drifts alike; along x (θ = 0) it does not spin.
    #[test]
    fn mirror_poses_spin_oppositely() {
        let motion = Primitive::new(PrimitiveKind::LineSink).motion();
        let body = rectangle();
        let averaged = AveragedField::new(&body, &motion, FieldSettings::default().physics());
        let at = |theta: f64| {
            averaged
                .twist(Pose::new(0.006, 0.0, theta.to_radians()))
                .unwrap()
                .twist
        };
        let (a, b, flat) = (at(30.0), at(-30.0), at(0.0));
        let scale = a.omega.abs();
        assert!(scale > 0.01, "{a:?}");
        assert!((a.omega + b.omega).abs() < 1e-6 * scale, "{a:?} {b:?}");
        assert!(
            (a.v.x - b.v.x).abs() < 1e-6 * a.v.norm() && (a.v.y + b.v.y).abs() < 1e-6 * a.v.norm()
        );
        assert!(
            flat.omega.abs() < 1e-6 * scale && flat.v.y.abs() < 1e-6 * flat.v.norm(),
            "{flat:?}"
        );
    }

    /// A schedule's averaged field is its segments' time-weighted mean: a
    /// rest segment as long as the motion halves the twist.
    #[test]
    fn a_rest_segment_weights_the_twist() {
        let motion = Primitive::new(PrimitiveKind::LineSink).motion();
        let body = rectangle();
        let physics = FieldSettings::default().physics();
        let pose = Pose::new(0.004, 0.002, 0.7);
        let whole = AveragedField::new(&body, &motion, physics)
            .twist(pose)
            .unwrap();
        let half =
            AveragedField::of_segments(&body, physics, vec![(Some(motion), 2.0), (None, 2.0)])
                .twist(pose)
                .unwrap();
        assert_eq!(half.cycles, whole.cycles);
        assert_eq!(
            (half.twist.v * 2.0, half.twist.omega * 2.0),
            (whole.twist.v, whole.twist.omega)
        );
    }

    /// 64 steps per cycle against 512: the twist within 0.3 % of its size
    /// (measured 0.01 % in v, 0.12 % in ω).
    #[test]
    fn sixty_four_steps_per_cycle_converge() {
        let motion = Primitive::new(PrimitiveKind::LineSink).motion();
        let body = rectangle();
        let physics = FieldSettings::default().physics();
        let pose = Pose::new(0.008, 0.0, 0.5);
        let coarse = AveragedField::new(&body, &motion, physics)
            .twist(pose)
            .unwrap()
            .twist;
        let fine = AveragedField::new(&body, &motion, physics)
            .with_steps(512)
            .twist(pose)
            .unwrap()
            .twist;
        println!("coarse {coarse:?}\nfine   {fine:?}");
        assert!((coarse.v - fine.v).norm() < 3e-3 * fine.v.norm());
        assert!((coarse.omega - fine.omega).abs() < 3e-3 * fine.omega.abs());
    }
}
