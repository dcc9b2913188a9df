//! The averaged field: a planar part's mean twist at a pose, from the
//! rigid part's own periodic slip at that pose (the planar simulator
//! playing the plate's motion, period after period, from the pose), where
//! [`crate::pose::LiftedField`] integrates the point parts' mean velocities over
//! the support.
//!
//! **Model.** The rigid part's slip ξ(t) = (u, ω) obeys the planar
//! simulator's Newton–Euler law with Coulomb friction summed over its
//! support points ([`crate::dynamics::PlanarSimulator`]). The plate plays
//! a periodic motion, or a schedule's segments in turn with their joins
//! ([`crate::pose::PlanarPlayer`]); let T be its period. Each period is played
//! from the pose q = (r, θ) with the slip the last one ended with, until
//! two periods' displacements agree: the slip is then periodic and the
//! part moves within a period (its excursion changes the kinematics it
//! sees, as the point field's `moving` model does) but restarts from q.
//! The averaged field is that period map's mean twist,
//!
//! ```text
//! ξ̄(q) = (P(q) − q) / T,      P(q) = the pose after one period from q
//! ```
//!
//! so its zeros are exactly the poses a played part returns to after every
//! period (the rests of the stroboscopic map). The only approximation in
//! ξ̄ away from its zeros is that a period starts from q again: the drift
//! over earlier periods does not feed back.
//!
//! **Why both fields.** Coulomb friction is not linear in the slip, so
//! averaging over the cycle and summing over the support do not commute.
//! The lifted field averages first (each support point's own mean
//! velocity V(p_j)) and then fits a rigid twist; that gets the
//! translation right against the moving part but not the spin, which
//! comes from the small differences between the points' drifts riding on
//! a large shared slip. The spin then depends on how friction damps a
//! drift across that slip, which V(p) does not record: the lifted field's
//! spin is a few times the simulated rate on the LineSink; a
//! point-by-point Coulomb law on the shared slip gives about half of it
//! (the part's rocking spin, which the shared slip leaves out, softens the
//! damping across it). The averaged field sums first, as the part does,
//! and agrees closely in spin and translation (measured:
//! `tests/poses.rs` `lifted_field_against_simulation`). The lifted field is the fast map the
//! equilibrium search and the
//! drops integrate ([`super::equilibria`]); the averaged field checks it
//! ([`LiftCheck`]) and moves its equilibria onto the part's own
//! ([`super::rests`]), at the cost of a few periods of the planar part
//! per pose.

use nalgebra::{Matrix3, Vector3};

use crate::dynamics::{ContactLoss, PartPhysics, PlanarBody, PlanarState, PLANAR_REFINE_DEPTH, V2};
use crate::error::Result;
use crate::motion::Motion;
use crate::part::Part;
use crate::play::{PlayedSegment, ScheduleMotion};

use super::drops::{rest_cycle, DropPlay, PlanarPlayer, DROP_REFINE_DEPTH, DROP_SAMPLES};
use super::lifted::{LiftedField, Pose, Twist};
use super::run::{drop_starts, PoseAnalysis};

/// No motion.
const ZERO: Twist = Twist {
    v: V2::new(0.0, 0.0),
    omega: 0.0,
};

/// Planar steps per cycle by default.
pub const AVERAGING_STEPS: usize = 64;
/// Most periods played per pose before the last period's twist is taken
/// as it stands (`AveragedTwist::converged` false).
pub const MAX_AVERAGING_PERIODS: u32 = 60;
/// Two consecutive periods' twists closer than this, relative to the slip
/// scale μ g T_c (T_c the shortest motion cycle; μ g T_c / radius for the
/// spin), end the averaging.
pub const AVERAGING_TOLERANCE: f64 = 1e-6;

/// The slip (relative velocity u of the centre of mass, m/s, and spin ω,
/// rad/s) a period ends with: where the next period, or a nearby pose's
/// first, starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Slip {
    /// Translation slip (m/s).
    pub u: V2,
    /// Spin slip (rad/s).
    pub omega: f64,
}

/// Largest travel over one period, relative to the part's radius (and
/// in rad), at which the averaged field counts as local
/// (`AveragedField::is_local`).
pub const LOCAL: f64 = 0.5;

/// Jacobian step in x and y, relative to the part's radius.
pub const JACOBIAN_STEP: f64 = 0.02;
/// Jacobian step in θ (rad).
pub const JACOBIAN_STEP_RAD: f64 = 0.005;

/// One pose's averaged twist.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AveragedTwist {
    /// The mean twist of the last period played.
    pub twist: Twist,
    /// Periods played.
    pub periods: u32,
    /// The last two periods agreed within [`AVERAGING_TOLERANCE`].
    pub converged: bool,
}

/// The averaged field of one part on one periodic motion or schedule
/// (module docs).
pub struct AveragedField {
    body: PlanarBody,
    /// The body's centre of mass in the part's frame (m): nonzero for a
    /// part's resampled support ([`AveragedField::for_part`]).
    offset: V2,
    sm: ScheduleMotion,
    /// Physics, steps per cycle and refinement depth of the play.
    play: DropPlay,
}

impl AveragedField {
    /// The averaged field of `body` on the periodic `motion` with
    /// `physics` (one cycle per period).
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
    /// let field = AveragedField::new(&body, &motion, PartPhysics::full(0.3))?;
    /// let a = field.twist(Pose::new(0.005, 0.0, 45f64.to_radians())).unwrap();
    /// assert!(a.converged && a.twist.omega > 0.0 && a.twist.v.x < 0.0);
    /// # Ok::<(), platefield::Error>(())
    /// ```
    ///
    /// # Errors
    /// An invalid `motion` (its validation's error).
    pub fn new(body: &PlanarBody, motion: &Motion, physics: PartPhysics) -> Result<AveragedField> {
        let segment = PlayedSegment::moving("motion", motion.clone(), 1);
        let sm = ScheduleMotion::new(vec![segment])?;
        Ok(AveragedField::of_schedule(body, sm, physics))
    }

    /// The averaged field of `part` on a schedule's plate trajectory `sm`,
    /// played as its drops are: a uniform support resampled to about
    /// [`DROP_SAMPLES`] points (its centre of mass moved back to the
    /// part's) at refinement depth [`DROP_REFINE_DEPTH`] (the drops' end
    /// poses are within 0.02 mm and 0.2° of the full support at depth 10,
    /// [`DropPlay::new`]).
    pub fn for_part(part: &Part, sm: ScheduleMotion, physics: PartPhysics) -> AveragedField {
        let (body, offset) = part
            .coarse_body(DROP_SAMPLES)
            .unwrap_or_else(|| (part.body.clone(), V2::zeros()));
        let mut field = AveragedField::of_schedule(&body, sm, physics);
        field.offset = offset;
        field.play.refine_depth = DROP_REFINE_DEPTH;
        field
    }

    /// The averaged field of `body` on a schedule's plate trajectory `sm`.
    pub(crate) fn of_schedule(
        body: &PlanarBody,
        sm: ScheduleMotion,
        physics: PartPhysics,
    ) -> AveragedField {
        let play = DropPlay {
            friction: physics.friction,
            gravity: physics.gravity,
            model: physics.model,
            duration_s: sm.period(),
            steps_per_cycle: AVERAGING_STEPS,
            refine_depth: PLANAR_REFINE_DEPTH,
            samples: None,
            slip_rule: crate::dynamics::SlipRule::default(),
        };
        AveragedField {
            body: body.clone(),
            offset: V2::zeros(),
            sm,
            play,
        }
    }

    /// The same field played with `steps` planar steps per cycle (default
    /// [`AVERAGING_STEPS`]).
    #[cfg(test)]
    pub(crate) fn with_steps(mut self, steps: usize) -> AveragedField {
        self.play.steps_per_cycle = steps.max(1);
        self
    }

    /// The support's radius about its centre of mass (m).
    pub(crate) fn radius(&self) -> f64 {
        self.body
            .points()
            .iter()
            .map(|p| p.norm())
            .fold(0.0, f64::max)
    }

    /// The body's centre of mass in the plate frame at the part's `pose`.
    fn body_centre(&self, pose: Pose) -> V2 {
        let (s, c) = pose.theta.sin_cos();
        pose.r
            + V2::new(
                c * self.offset.x - s * self.offset.y,
                s * self.offset.x + c * self.offset.y,
            )
    }

    /// The mean twist at `pose`, or where a support point loses contact.
    pub fn twist(&self, pose: Pose) -> Result<AveragedTwist, ContactLoss> {
        self.twist_from(pose, None).map(|(a, _)| a)
    }

    /// The mean twist at `pose`, its first period started from `warm`'s
    /// slip (from rest at phase 0 when `None`): a nearby pose's periodic
    /// slip cuts the periods to convergence. Also returns the slip the
    /// last period ended with, for the next nearby pose.
    pub(crate) fn twist_from(
        &self,
        pose: Pose,
        warm: Option<Slip>,
    ) -> Result<(AveragedTwist, Slip), ContactLoss> {
        let centre = self.body_centre(pose);
        let (mut a, slip) = self.body_twist_from(
            Pose {
                r: centre,
                theta: pose.theta,
            },
            warm,
        )?;
        // The part's reference point sits at −R(θ) offset from the body's.
        a.twist.v -= V2::new(-(centre - pose.r).y, (centre - pose.r).x) * a.twist.omega;
        Ok((a, slip))
    }

    /// [`Self::twist_from`] of the body at its own centre-of-mass `pose`.
    fn body_twist_from(
        &self,
        pose: Pose,
        warm: Option<Slip>,
    ) -> Result<(AveragedTwist, Slip), ContactLoss> {
        let player = PlanarPlayer::new(&self.sm, &self.body, &self.play);
        let period = self.sm.period();
        let scale = self.play.friction.kinetic * self.play.gravity * rest_cycle(&self.sm);
        let radius = self.radius();
        let start = warm.unwrap_or(Slip {
            u: V2::zeros(),
            omega: 0.0,
        });
        let mut s = PlanarState::slipping(pose.r, pose.theta, start.u, start.omega);
        let mut last: Option<Twist> = None;
        for k in 0..MAX_AVERAGING_PERIODS {
            // Each period starts at the pose with the slip the last left.
            (s.r, s.theta) = (pose.r, pose.theta);
            let a = s;
            let joined = k > 0 || warm.is_some();
            player
                .play_period(&mut s, k, joined, (pose.r, pose.theta))
                .map_err(|e| e.loss)?;
            let twist = Twist {
                v: (s.r - a.r) / period,
                omega: (s.theta - a.theta) / period,
            };
            let slip = Slip {
                u: s.u,
                omega: s.omega,
            };
            if let Some(p) = last {
                let dv = (twist.v - p.v).norm() / scale;
                let dw = (twist.omega - p.omega).abs() * radius / scale;
                if dv.max(dw) < AVERAGING_TOLERANCE {
                    return Ok((
                        AveragedTwist {
                            twist,
                            periods: k + 1,
                            converged: true,
                        },
                        slip,
                    ));
                }
            }
            last = Some(twist);
        }
        let slip = Slip {
            u: s.u,
            omega: s.omega,
        };
        let twist = last.unwrap_or(ZERO);
        Ok((
            AveragedTwist {
                twist,
                periods: MAX_AVERAGING_PERIODS,
                converged: false,
            },
            slip,
        ))
    }

    /// Whether `twist` moves the part less than [`LOCAL`] of its radius and
    /// [`LOCAL`] rad over one period: then the period map's mean twist is
    /// the field near the pose, comparable with the lifted field's. (Over
    /// a long schedule period, a pose design's minute-long cycle, the part
    /// travels to its rest within the period, and ξ̄ is that trip over T.)
    pub(crate) fn is_local(&self, twist: &Twist) -> bool {
        let t = self.sm.period();
        twist.v.norm() * t < LOCAL * self.radius() && twist.omega.abs() * t < LOCAL
    }

    /// ∂(v_x, v_y, ω)/∂(x, y, θ) at `pose` by central differences (steps
    /// [`JACOBIAN_STEP`] of the part's radius and [`JACOBIAN_STEP_RAD`]),
    /// every evaluation warm-started from `warm`.
    pub(crate) fn jacobian(
        &self,
        pose: Pose,
        warm: Option<Slip>,
    ) -> Result<Matrix3<f64>, ContactLoss> {
        let h = [
            JACOBIAN_STEP * self.radius(),
            JACOBIAN_STEP * self.radius(),
            JACOBIAN_STEP_RAD,
        ];
        let at = |k: usize, sign: f64| {
            let mut q = [pose.r.x, pose.r.y, pose.theta];
            q[k] += sign * h[k];
            let (a, _) = self.twist_from(Pose::new(q[0], q[1], q[2]), warm)?;
            Ok(Vector3::new(a.twist.v.x, a.twist.v.y, a.twist.omega))
        };
        let mut j = Matrix3::zeros();
        for (k, hk) in h.iter().enumerate() {
            j.set_column(k, &((at(k, 1.0)? - at(k, -1.0)?) / (2.0 * hk)));
        }
        Ok(j)
    }
}

/// Poses the `poses` command checks at most.
pub const CHECKED_POSES: usize = 20;

/// The poses the `poses` command checks: every equilibrium of `a`, then
/// its first drop starts, [`CHECKED_POSES`] in all (equilibria first when
/// there are more).
pub(crate) fn checked_poses(a: &PoseAnalysis) -> Vec<Pose> {
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

/// One pose of a [`LiftCheck`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiftRow {
    /// The pose.
    pub pose: Pose,
    /// The lifted field's twist there.
    pub lifted: Twist,
    /// The averaged field's (`None` where a support point loses contact).
    pub averaged: Option<AveragedTwist>,
    /// The averaged field is local there (`AveragedField::is_local`).
    pub local: bool,
}

/// The lifted field against the averaged field at sampled poses.
#[derive(Debug, Clone, PartialEq)]
pub struct LiftCheck {
    /// Per pose, in the order asked.
    pub poses: Vec<LiftRow>,
    /// RMS of |v_lifted − v_averaged| over the RMS of |v_averaged|
    /// over the poses where the averaged field is local (`None` when none
    /// is, or every averaged v is 0).
    pub translation_rms: Option<f64>,
    /// RMS of |ω_lifted − ω_averaged| over the RMS of |ω_averaged|
    /// (`None` likewise).
    pub spin_rms: Option<f64>,
}

impl LiftCheck {
    /// Compares `lifted` with `averaged` at `poses` (in parallel; the
    /// same result on any number of threads). The RMS errors count only
    /// the poses the averaged field is local at (`AveragedField::is_local`).
    pub fn run(lifted: &LiftedField<'_>, averaged: &AveragedField, poses: &[Pose]) -> LiftCheck {
        use rayon::prelude::*;
        let rows: Vec<LiftRow> = poses
            .par_iter()
            .map(|p| {
                let a = averaged.twist(*p).ok();
                LiftRow {
                    pose: *p,
                    lifted: lifted.twist(*p),
                    averaged: a,
                    local: a.is_some_and(|a| averaged.is_local(&a.twist)),
                }
            })
            .collect();
        let pairs: Vec<(Twist, Twist)> = rows
            .iter()
            .filter(|r| r.local)
            .filter_map(|r| r.averaged.map(|a| (r.lifted, a.twist)))
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
    /// integrator): within 0.1 % of the field's largest speed.
    #[test]
    fn a_point_part_drifts_at_the_point_field() {
        let motion = Primitive::new(PrimitiveKind::LineSink).motion();
        let settings = FieldSettings::default();
        let body = PlanarBody::point();
        let averaged = AveragedField::new(&body, &motion, settings.physics()).unwrap();
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
        let averaged =
            AveragedField::new(&body, &motion, FieldSettings::default().physics()).unwrap();
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

    /// With the part's geometry frozen at the pose (`moving` off), a
    /// schedule of one segment of five cycles is the motion itself (the
    /// join of a motion to itself adds no slip): the same twist within the
    /// averaging's precision. (With the part moving the two differ by its
    /// drift over the longer period, by a few per cent in v here.)
    #[test]
    fn five_cycles_per_period_are_the_motion() {
        let motion = Primitive::new(PrimitiveKind::LineSink).motion();
        let body = rectangle();
        let mut physics = FieldSettings::default().physics();
        physics.model.moving = false;
        let pose = Pose::new(0.004, 0.002, 0.7);
        let one = AveragedField::new(&body, &motion, physics)
            .unwrap()
            .twist(pose)
            .unwrap();
        let sm = ScheduleMotion::new(vec![PlayedSegment::moving("five", motion, 5)]).unwrap();
        let five = AveragedField::of_schedule(&body, sm, physics)
            .twist(pose)
            .unwrap();
        assert!(one.converged && five.converged);
        let scale = 0.3 * 9.81 * Primitive::new(PrimitiveKind::LineSink).period();
        assert!(
            (one.twist.v - five.twist.v).norm() < 1e-5 * scale,
            "{one:?} {five:?}"
        );
        assert!(
            (one.twist.omega - five.twist.omega).abs() * 0.01 < 1e-5 * scale,
            "{one:?} {five:?}"
        );
    }

    /// 64 steps per cycle against 512: the twist within 0.3 % of its size.
    #[test]
    fn sixty_four_steps_per_cycle_converge() {
        let motion = Primitive::new(PrimitiveKind::LineSink).motion();
        let body = rectangle();
        let physics = FieldSettings::default().physics();
        let pose = Pose::new(0.008, 0.0, 0.5);
        let coarse = AveragedField::new(&body, &motion, physics)
            .unwrap()
            .twist(pose)
            .unwrap()
            .twist;
        let fine = AveragedField::new(&body, &motion, physics)
            .unwrap()
            .with_steps(512)
            .twist(pose)
            .unwrap()
            .twist;
        println!("coarse {coarse:?}\nfine   {fine:?}");
        assert!((coarse.v - fine.v).norm() < 3e-3 * fine.v.norm());
        assert!((coarse.omega - fine.omega).abs() < 3e-3 * fine.omega.abs());
    }
}
