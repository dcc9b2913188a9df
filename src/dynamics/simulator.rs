//! The simulator of point parts under one plate motion: its settings, the
//! plate kinematics (tabulated or evaluated), the forces on a part and the
//! explicit RK4 step of the slipping dynamics (module docs of
//! [`crate::dynamics`]). The stick-slip integrator built on it is in
//! `integrator.rs`, the implicit and regularised-time steps of the slip
//! schemes in `radau.rs`, `swing.rs` and `scheme.rs`.

use super::kinematics_table::KinematicsTable;
use super::state::{Step, V2};
use super::{ContactLoss, Friction, Model, Numerics, PartPhysics};
use crate::motion::{Kinematics, Motion, PreparedMotion, V3};

/// A part a_⊥ of a_free across the slip below this fraction of |a_free| is
/// round-off of a 1-D slip along a rotated line (cos 90° ≈ 6e-17), not a
/// 2-D slip: its exact explicit steps are kept.
pub(super) const ACROSS_ROUND_OFF: f64 = 1e-12;

/// Simulates point parts under one plate motion.
#[derive(Debug, Clone)]
pub struct Simulator<'a> {
    pub(super) motion: &'a Motion,
    pub(super) friction: Friction,
    pub(super) gravity: f64,
    pub(super) model: Model,
    pub(super) numerics: Numerics,
    pub(super) period: f64,
    pub(super) breakpoints: Vec<f64>,
    pub(super) v_scale: f64,
    /// Kinematics tabulated on the fixed-step time grid, when given.
    pub(super) table: Option<&'a KinematicsTable<'a>>,
    /// The motion with its constants worked out, for evaluating the
    /// kinematics off the table ([`Motion::kinematics_piece`] to
    /// round-off; bitwise for a motion with a slip axis, whose few
    /// off-grid instants are those of event location, so that its 1-D
    /// fields stay bitwise those of libm's sin and cos).
    pub(super) prepared: PreparedMotion<'a>,
    /// The motion's slip axis ([`Motion::slip_axis`]): a part whose slip
    /// velocity has no component across it slips on a line.
    pub(super) line: Option<usize>,
    /// How parts are followed through flight, when they are
    /// ([`Simulator::with_flight`]).
    pub(super) flight: Option<super::Flight>,
}

impl<'a> Simulator<'a> {
    /// A simulator; parameters are assumed validated by the caller.
    pub fn new(motion: &'a Motion, physics: PartPhysics, numerics: Numerics) -> Simulator<'a> {
        let PartPhysics {
            friction,
            gravity,
            model,
        } = physics;
        let period = motion.period();
        let line = motion.slip_axis();
        Simulator {
            motion,
            friction,
            gravity,
            model,
            numerics,
            period,
            breakpoints: motion.breakpoints(),
            v_scale: (friction.kinetic.max(1e-3) * gravity.max(1e-3) * period).max(1e-300),
            table: None,
            line,
            prepared: if line.is_some() {
                PreparedMotion::direct(motion)
            } else {
                PreparedMotion::new(motion)
            },
            flight: None,
        }
    }

    /// The same simulator reading the plate kinematics from `table` where
    /// it holds them (a memo: results are bitwise unchanged).
    ///
    /// # Panics
    /// When `table` was built for another motion, gravity or tilt switch.
    pub(crate) fn with_table(mut self, table: &'a KinematicsTable<'a>) -> Simulator<'a> {
        assert!(
            table.fits(self.motion, self.gravity, self.model.tilt),
            "kinematics table built for another motion"
        );
        self.table = Some(table);
        self
    }

    /// The plate motion.
    pub(crate) fn motion(&self) -> &'a Motion {
        self.motion
    }
    /// The model switches.
    pub(crate) fn model(&self) -> Model {
        self.model
    }
    /// The friction coefficients.
    pub(crate) fn friction(&self) -> Friction {
        self.friction
    }
    /// Gravity (m/s²).
    pub(crate) fn gravity(&self) -> f64 {
        self.gravity
    }
    /// The part physics (friction, gravity, model).
    pub(crate) fn physics(&self) -> PartPhysics {
        PartPhysics::new(self.friction, self.gravity, self.model)
    }
    /// Numerical settings.
    pub(crate) fn numerics(&self) -> Numerics {
        self.numerics
    }
    /// The period T (s).
    pub fn period(&self) -> f64 {
        self.period
    }
    /// Velocity scale μ_k g T used for tolerances (m/s).
    pub(crate) fn velocity_scale(&self) -> f64 {
        self.v_scale
    }

    /// The motion prepared for evaluation off the table (the table is a
    /// memo of it).
    pub(super) fn prepared(&self) -> &PreparedMotion<'a> {
        &self.prepared
    }

    /// Kinematics at `t` on the piece keyed `piece`: from the table on the
    /// fixed-step grid, evaluated otherwise.
    #[inline]
    pub(super) fn kin(&self, t: f64, piece: f64) -> Kinematics {
        if let Some(k) = self.table.and_then(|table| table.get(t, piece)) {
            return *k;
        }
        self.prepared
            .kinematics_piece(t, piece, self.gravity, self.model.tilt)
    }

    /// Kinematics at `t` on the piece keyed `piece`, evaluated without
    /// asking the table: for instants that are (almost) never on its grid
    /// (the stages of τ-steps and implicit steps), where the lookup is a
    /// miss that costs a tenth of a 2-D field's time. The same value as
    /// [`Simulator::kin`] (the table is a memo of this evaluation).
    #[inline]
    pub(super) fn kin_off_grid(&self, t: f64, piece: f64) -> Kinematics {
        self.prepared
            .kinematics_piece(t, piece, self.gravity, self.model.tilt)
    }

    /// Position at which the kinematics are evaluated.
    #[inline]
    fn kin_point(&self, r: &V2, anchor: &V2) -> V3 {
        let p = if self.model.moving { r } else { anchor };
        V3::new(p.x, p.y, 0.0)
    }

    /// Normal force N and frictionless tangential acceleration a_free.
    #[inline]
    pub(super) fn forces(&self, k: &Kinematics, r: &V2, u: &V2, anchor: &V2) -> (f64, V2) {
        self.model.point_forces(k, &self.kin_point(r, anchor), u)
    }

    /// Break-away margin φ = μ_s N − |a_free| of a stuck part (u = 0), and N.
    #[inline]
    pub(super) fn margin(&self, t: f64, piece: f64, r: &V2, anchor: &V2) -> f64 {
        self.margin_of(&self.kin(t, piece), r, anchor)
    }

    /// The break-away margin φ with the kinematics `k` at hand.
    #[inline]
    pub(super) fn margin_of(&self, k: &Kinematics, r: &V2, anchor: &V2) -> f64 {
        let (n, free) = self.forces(k, r, &V2::zeros(), anchor);
        self.friction.stat * n - free.norm()
    }

    /// du/dt of a slipping part: a_free − μ_k N û. Where u is zero or has
    /// turned against `dir0`, the slip direction at the start of the step,
    /// friction keeps the side it came from: a reversal is an event that
    /// ends the step, so a stage landing on (or numerically just past)
    /// u = 0 must not flip it.
    #[inline(always)]
    pub(super) fn slip_rhs(
        &self,
        k: &Kinematics,
        t: f64,
        r: &V2,
        u: &V2,
        dir0: &V2,
        anchor: &V2,
    ) -> Result<V2, ContactLoss> {
        let (n, free) = self.forces(k, r, u, anchor);
        if n < 0.0 {
            return Err(self.contact_loss(t, r, anchor, n));
        }
        let along = u.dot(dir0);
        let dir = if along > 0.0 { unit(u) } else { *dir0 };
        Ok(free - dir * (self.friction.kinetic * n))
    }

    /// Direction in which a part with slip velocity `u` slips at the start
    /// of a step: û, or for a part slipping from rest, that of a_free.
    pub(super) fn slip_direction(&self, k: &Kinematics, r: &V2, u: &V2, anchor: &V2) -> V2 {
        if *u != V2::zeros() {
            return unit(u);
        }
        let (_, free) = self.forces(k, r, u, anchor);
        let f = free.norm();
        if f > 0.0 {
            free / f
        } else {
            V2::zeros()
        }
    }

    /// The contact loss at `t` with normal force `n`, placed where the
    /// kinematics were evaluated: `r`, or `anchor` for a frozen part (whose
    /// `r` drifts with its slip while the plate's motion is taken at the
    /// anchor; the drift is not where the part lost contact).
    pub(super) fn contact_loss(&self, t: f64, r: &V2, anchor: &V2, n: f64) -> ContactLoss {
        let c = (t / self.period).floor();
        let at = self.kin_point(r, anchor);
        ContactLoss {
            position: [at.x, at.y],
            time: t,
            cycle: c.max(0.0) as u64,
            phase: (t / self.period - c).clamp(0.0, 1.0),
            normal: n,
        }
    }

    /// One RK4 step of the slipping dynamics from `at` (time, position and
    /// slip velocity) over `h`, with `k0` the kinematics at its time.
    /// Returns (r, u, kinematics at the end). The stage kinematics are
    /// evaluated directly when `off_grid` (the trial steps of an event
    /// location: a stop, a back-off, whose stage instants are off the
    /// table's grid; the same values), looked up in the table first
    /// otherwise.
    #[inline]
    pub(super) fn rk4(
        &self,
        at: &Step<'_>,
        h: f64,
        k0: &Kinematics,
        off_grid: bool,
    ) -> Result<(V2, V2, Kinematics), ContactLoss> {
        let kin = |t: f64| {
            if off_grid {
                self.kin_off_grid(t, at.piece)
            } else {
                self.kin(t, at.piece)
            }
        };
        let t = at.t;
        let (km, k1k) = (kin(t + 0.5 * h), kin(t + h));
        self.rk4_with(at, h, [k0, &km, &k1k])
    }

    /// [`Simulator::rk4`] with the kinematics at t, t + h/2 and t + h at hand.
    #[inline]
    pub(super) fn rk4_with(
        &self,
        at: &Step<'_>,
        h: f64,
        [k0, km, k1k]: [&Kinematics; 3],
    ) -> Result<(V2, V2, Kinematics), ContactLoss> {
        let (t, r, u, anchor) = (at.t, &at.state.r, &at.state.u, at.anchor);
        let d0 = self.slip_direction(k0, r, u, anchor);
        let a1 = self.slip_rhs(k0, t, r, u, &d0, anchor)?;
        let (r2, u2) = (r + u * (0.5 * h), u + a1 * (0.5 * h));
        let a2 = self.slip_rhs(km, t + 0.5 * h, &r2, &u2, &d0, anchor)?;
        let (r3, u3) = (r + u2 * (0.5 * h), u + a2 * (0.5 * h));
        let a3 = self.slip_rhs(km, t + 0.5 * h, &r3, &u3, &d0, anchor)?;
        let (r4, u4) = (r + u3 * h, u + a3 * h);
        let a4 = self.slip_rhs(k1k, t + h, &r4, &u4, &d0, anchor)?;
        let r1 = r + (u + (u2 + u3) * 2.0 + u4) * (h / 6.0);
        let u1 = u + (a1 + (a2 + a3) * 2.0 + a4) * (h / 6.0);
        Ok((r1, u1, *k1k))
    }
}

impl<'a> KinematicsTable<'a> {
    /// The kinematics `sim` asks for when it advances over each span
    /// `[t0, t1]` in `spans` on its fixed-step path.
    pub(crate) fn new(sim: &Simulator<'a>, spans: &[(f64, f64)]) -> KinematicsTable<'a> {
        let nominal = sim.period() / sim.numerics().steps_per_cycle as f64;
        KinematicsTable::tabulate(
            (sim.motion(), sim.prepared()),
            (sim.gravity(), sim.model().tilt),
            nominal,
            spans,
        )
    }

    /// The table for one cycle [0, T] (steady-state velocity fields).
    pub(crate) fn cycle(sim: &Simulator<'a>) -> KinematicsTable<'a> {
        KinematicsTable::new(sim, &[(0.0, sim.period())])
    }

    /// The table for `phases` cycles starting at T j / `phases`, j = 0 …
    /// `phases` − 1 (zero-velocity force fields).
    pub(crate) fn phases(sim: &Simulator<'a>, phases: usize) -> KinematicsTable<'a> {
        let period = sim.period();
        let spans: Vec<(f64, f64)> = (0..phases)
            .map(|j| {
                let t0 = period * j as f64 / phases as f64;
                (t0, t0 + period)
            })
            .collect();
        KinematicsTable::new(sim, &spans)
    }
}

/// u/|u| for u ≠ 0. A slip along a coordinate axis (1-D slips: the
/// LineSink moves every point along x) takes the sign, which is what the
/// division gives there (√(x²) = |x| exactly), without the square root and
/// division that dominate a 1-D right-hand side.
#[inline]
fn unit(u: &V2) -> V2 {
    if u.y == 0.0 {
        V2::new(u.x.signum(), u.y)
    } else if u.x == 0.0 {
        V2::new(u.x, u.y.signum())
    } else {
        u / u.norm()
    }
}

/// Root θ ∈ [0, 1] of the cubic Hermite interpolant p with p(0) = `p0` > 0,
/// p'(0) = `d0`, p(1) = `p1` ≤ 0, p'(1) = `d1` (derivatives per unit θ), by
/// Newton's method safeguarded by bisection.
pub(super) fn hermite_root(p0: f64, d0: f64, p1: f64, d1: f64) -> f64 {
    // p(θ) = p0 + d0 θ + c2 θ² + c3 θ³.
    let c2 = 3.0 * (p1 - p0) - 2.0 * d0 - d1;
    let c3 = 2.0 * (p0 - p1) + d0 + d1;
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut x = p0 / (p0 - p1);
    for _ in 0..60 {
        let p = p0 + x * (d0 + x * (c2 + x * c3));
        if p > 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let step = p / (d0 + x * (2.0 * c2 + x * 3.0 * c3));
        // A first guess: the interpolant itself is accurate to O(h⁴) only.
        if step.abs() <= 1e-12 {
            return (x - step).clamp(lo, hi);
        }
        let next = x - step;
        x = if next > lo && next < hi {
            next
        } else {
            0.5 * (lo + hi)
        };
        if hi - lo <= 1e-12 {
            break;
        }
    }
    x
}

#[cfg(test)]
#[path = "../../tests/unit/engine.rs"]
mod engine_tests;
