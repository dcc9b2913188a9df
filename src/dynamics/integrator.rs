//! The stick-slip integrator.
//!
//! Smooth pieces of the motion (between acceleration breakpoints) are
//! divided into fixed RK4 steps. Coulomb friction is not smoothed: the two
//! discontinuities of the law are located inside a step as events.
//!
//! * **Stop** (slipping → u = 0): with u₀ the slip velocity at the start of
//!   a step, the event function is g(s) = u(s)·u₀ where u(s) is the RK4
//!   solution after a step of size s. Its root is found by safeguarded
//!   Newton iteration (g'(s) ≈ u̇(s)·u₀) from the root of the cubic Hermite
//!   interpolant of g over the whole step, each iteration a trial RK4 step
//!   (see `stop_in_step`: two or three per stop), the step is cut there,
//!   and the part either sticks (|a_free| ≤ μ_s N) or reverses, slipping
//!   from rest along a_free. For piecewise-constant accelerations (the
//!   square wave) u is linear in s, RK4 is exact and Newton converges in
//!   one iteration, so the whole cycle is integrated exactly.
//! * **Break-away** (stuck → slipping): while stuck nothing in the state
//!   changes, so the stuck episode is resolved at once: the margin
//!   φ(t) = μ_s N(t) − |a_free(t)| is sampled at half-step spacing, every
//!   discrete local minimum is refined by Brent's minimization (parabolic
//!   steps, golden section where they fail; so a short dip below zero
//!   between samples is not missed), and the first root is bracketed and
//!   found by the Illinois method.
//!
//! In 2-D the slip velocity of a part that cannot stick (|a_free| > μ_s N)
//! passes close to zero without reaching it (closest approach ε = |u(s*)|
//! at the root of u(s)·u₀) and turns rapidly: its direction changes at the
//! rate |a_⊥|/|u|. The step is then backed off to where the velocity along
//! u₀ is still 8ε, and the swing is followed with steps short enough for the
//! turn (see `slip_step`). The friction law itself is never smoothed.
//!
//! Stiffness across the slip ([`Numerics::slip`]): friction across a small
//! slip velocity damps at the rate μ_k N/|u|. Just after a 2-D slip starts
//! from rest, after a swing past zero and just before a stop, a step h sees
//! h μ_k N/|u| ≫ 1 and the explicit step overshoots across the slip.
//!
//! * [`SlipScheme::Legacy`] takes those steps explicitly and
//!   ends a 2-D stop where |u| has fallen below `STOP_FRACTION` of its
//!   value at the step's start; 2-D fields converge at about first order
//!   (`tests/slip2d.rs`, `results/library_speed.md`).
//! * [`SlipScheme::Stiff`] takes them with the implicit Radau IIA method
//!   (`src/dynamics/radau.rs`): a slip speeding up once its direction has
//!   turned onto a_free (from rest, after a swing), and a slip slowing along
//!   a_free towards a stop, whose time is the root of the implicit
//!   solution's speed. A swing is backed off to half the speed (where the
//!   explicit step is accurate) and followed with short explicit steps, and
//!   an explicit step whose end falls inside a swing's fast turn is backed
//!   off the same way. 2-D force fields at 64 steps per cycle are 10–100×
//!   more accurate than the legacy scheme's (`tests/slip2d.rs`).
//! * [`SlipScheme::Regularised`] (the default) is the stiff scheme with a 2-D swing past
//!   u = 0 (and a slow-down towards a 2-D stop) followed in regularised time
//!   dτ = dt/|u| instead of short explicit steps (`src/dynamics/swing.rs`):
//!   2-D force fields within 1e-4 at 64 steps per cycle, observed order
//!   3.2–4.3 from 16 to 64 steps (`tests/slip2d.rs`, `results/engine_speed.md`).
//!
//! 1-D slips are unaffected by the choice except at starts from rest (both
//! exact for piecewise-constant accelerations). A slip on the motion's line
//! ([`Motion::slip_axis`]: the LineSink, LineSource and Trans) skips the 2-D
//! checks, which cannot fire there, bitwise the same (`line_tests.rs`).

use nalgebra::Vector2;

use super::kinematics_table::StepNodes;
use super::radau::Slowing;
use super::swing::ACROSS_ROUND_OFF;
use super::{ContactLoss, Friction, KinematicsTable, Model, Numerics, SlipScheme};
use crate::motion::{Kinematics, Motion, PreparedMotion, V3};

/// 2-vector of f64.
pub type V2 = Vector2<f64>;

/// A root of u(s)·u₀ where the part can stick and |u(s)| is at most this
/// fraction of |u₀| is a stop (in 2-D, u reaches zero along a_free);
/// legacy scheme only.
const STOP_FRACTION: f64 = 0.1;

/// A root of u(s)·u₀ where |u(s)| is at most this fraction of |u₀| is a
/// zero crossing (exact in 1-D, up to round-off).
const ZERO_FRACTION: f64 = 1e-9;

/// Largest turn of the slip direction per step (radians, approximately).
const TURN: f64 = 0.25;

/// Shortest slip step outside a swing, as a fraction of the nominal step.
const MIN_SUBSTEP: f64 = 1.0 / 64.0;

/// Where a 2-D swing past zero starts to be followed with short steps: when
/// the velocity component along the step's initial direction is this many
/// times the closest approach.
const BACKOFF: f64 = 8.0;

/// Steps after a swing past zero during which the step may shrink freely.
const MAX_SWING_STEPS: u32 = 400;

/// Most step cuts at roots of u(s)·u₀ within one step (a 2-D slip
/// velocity swinging past zero is cut a few times while it turns).
const MAX_CUTS: u32 = 16;

/// State of a point part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartState {
    /// Plate-frame position r (m).
    pub r: V2,
    /// Slip velocity u = dr/dt relative to the plate (m/s).
    pub u: V2,
    /// True while the part sticks to the plate (then u = 0).
    pub stuck: bool,
}

impl PartState {
    /// A part at `r` with slip velocity `u` (stuck status decided on the first step).
    pub fn new(r: V2, u: V2) -> PartState {
        PartState { r, u, stuck: false }
    }
}

/// One recorded sample of a trajectory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrajectoryPoint {
    /// Time (s).
    pub t: f64,
    /// The part's state after the step ending at `t`.
    pub state: PartState,
}

/// What one simulated time span produced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CycleOutcome {
    /// Final state.
    pub state: PartState,
    /// Total time spent stuck (s).
    pub stuck_time: f64,
    /// Number of stop and break-away events.
    pub events: u32,
    /// RK4 steps taken, trial steps of event location included (a cost
    /// measure: each is four right-hand sides and two kinematics evaluations).
    pub rk4_steps: u32,
}

/// Simulates point parts under one plate motion.
#[derive(Debug, Clone)]
pub struct Simulator<'a> {
    motion: &'a Motion,
    friction: Friction,
    gravity: f64,
    model: Model,
    numerics: Numerics,
    period: f64,
    breakpoints: Vec<f64>,
    v_scale: f64,
    /// Kinematics tabulated on the fixed-step time grid, when given.
    table: Option<&'a KinematicsTable<'a>>,
    /// The motion with its constants worked out, for evaluating the
    /// kinematics off the table ([`Motion::kinematics_piece`] to
    /// round-off; bitwise for a motion with a slip axis, whose few
    /// off-grid instants are those of event location, so that its 1-D
    /// fields stay bitwise those of libm's sin and cos).
    prepared: PreparedMotion<'a>,
    /// The motion's slip axis ([`Motion::slip_axis`]): a part whose slip
    /// velocity has no component across it slips on a line.
    line: Option<usize>,
}

impl<'a> Simulator<'a> {
    /// A simulator; parameters are assumed validated by the caller.
    pub fn new(
        motion: &'a Motion,
        friction: Friction,
        gravity: f64,
        model: Model,
        numerics: Numerics,
    ) -> Simulator<'a> {
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
        }
    }

    /// The same simulator reading the plate kinematics from `table` where
    /// it holds them (a memo: results are bitwise unchanged).
    ///
    /// # Panics
    /// When `table` was built for another motion, gravity or tilt switch.
    pub fn with_table(mut self, table: &'a KinematicsTable<'a>) -> Simulator<'a> {
        assert!(
            table.fits(self.motion, self.gravity, self.model.tilt),
            "kinematics table built for another motion"
        );
        self.table = Some(table);
        self
    }

    /// The plate motion.
    pub fn motion(&self) -> &'a Motion {
        self.motion
    }
    /// The model switches.
    pub fn model(&self) -> Model {
        self.model
    }
    /// The friction coefficients.
    pub fn friction(&self) -> Friction {
        self.friction
    }
    /// Gravity (m/s²).
    pub fn gravity(&self) -> f64 {
        self.gravity
    }
    /// Numerical settings.
    pub fn numerics(&self) -> Numerics {
        self.numerics
    }
    /// The period T (s).
    pub fn period(&self) -> f64 {
        self.period
    }
    /// Velocity scale μ_k g T used for tolerances (m/s).
    pub fn velocity_scale(&self) -> f64 {
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
    fn margin_of(&self, k: &Kinematics, r: &V2, anchor: &V2) -> f64 {
        let (n, free) = self.forces(k, r, &V2::zeros(), anchor);
        self.friction.stat * n - free.norm()
    }

    /// du/dt of a slipping part: a_free − μ_k N û. Where u is zero or has
    /// turned against `dir0`, the slip direction at the start of the step,
    /// friction keeps the side it came from: a reversal is an event that
    /// ends the step, so a stage landing on (or numerically just past)
    /// u = 0 must not flip it.
    #[inline(always)]
    fn slip_rhs(
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
            return Err(self.contact_loss(t, r, n));
        }
        let along = u.dot(dir0);
        let dir = if along > 0.0 { unit(u) } else { *dir0 };
        Ok(free - dir * (self.friction.kinetic * n))
    }

    /// Direction in which a part with slip velocity `u` slips at the start
    /// of a step: û, or for a part slipping from rest, that of a_free.
    fn slip_direction(&self, k: &Kinematics, r: &V2, u: &V2, anchor: &V2) -> V2 {
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

    /// The contact loss at `t`, `r` with normal force `n`.
    pub(super) fn contact_loss(&self, t: f64, r: &V2, n: f64) -> ContactLoss {
        let c = (t / self.period).floor();
        ContactLoss {
            position: [r.x, r.y],
            time: t,
            cycle: c.max(0.0) as u64,
            phase: (t / self.period - c).clamp(0.0, 1.0),
            normal: n,
        }
    }

    /// One RK4 step of the slipping dynamics from (t, r, u) over `h`,
    /// with `k0` the kinematics at t. Returns (r, u, du/dt at the end).
    /// The stage kinematics are evaluated directly when `off_grid` (the
    /// trial steps of an event location: a stop, a back-off, whose stage
    /// instants are off the table's grid; the same values), looked up in the
    /// table first otherwise.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn rk4(
        &self,
        t: f64,
        h: f64,
        piece: f64,
        k0: &Kinematics,
        r: &V2,
        u: &V2,
        anchor: &V2,
        off_grid: bool,
    ) -> Result<(V2, V2, Kinematics), ContactLoss> {
        let kin = |t: f64| {
            if off_grid {
                self.kin_off_grid(t, piece)
            } else {
                self.kin(t, piece)
            }
        };
        let (km, k1k) = (kin(t + 0.5 * h), kin(t + h));
        self.rk4_with(t, h, [k0, &km, &k1k], r, u, anchor)
    }

    /// [`Simulator::rk4`] with the kinematics at t, t + h/2 and t + h at hand.
    #[inline]
    fn rk4_with(
        &self,
        t: f64,
        h: f64,
        [k0, km, k1k]: [&Kinematics; 3],
        r: &V2,
        u: &V2,
        anchor: &V2,
    ) -> Result<(V2, V2, Kinematics), ContactLoss> {
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

    /// Advances `state` from `t0` to `t1`. The kinematics use the current
    /// position when the model's `moving` switch is on, `anchor` otherwise.
    /// Every accepted step is appended to `record` when given.
    pub fn advance(
        &self,
        t0: f64,
        t1: f64,
        state: &mut PartState,
        anchor: &V2,
        mut record: Option<&mut Vec<TrajectoryPoint>>,
    ) -> Result<CycleOutcome, ContactLoss> {
        let mut out = CycleOutcome {
            state: *state,
            stuck_time: 0.0,
            events: 0,
            rk4_steps: 0,
        };
        let nominal = self.period / self.numerics.steps_per_cycle as f64;
        // One smooth piece without breakpoints (no allocation per call).
        let whole = [t0, t1];
        let split;
        let edges: &[f64] = if self.breakpoints.is_empty() && t0 <= t1 {
            &whole
        } else {
            split = super::piece_edges(t0, t1, self.period, &self.breakpoints);
            &split
        };
        for w in edges.windows(2) {
            let (a, b) = (w[0], w[1]);
            let n = super::step_count(a, b, nominal);
            let piece = 0.5 * (a + b);
            let nodes = self.table.and_then(|table| table.piece(a, b, n, piece));
            let mut t = a;
            for i in 1..=n {
                let target = super::step_end(a, b, n, i);
                let grid = nodes.map(|p| p.step(i));
                self.advance_piece(&mut t, target, piece, grid, state, anchor, &mut out)?;
                if let Some(rec) = record.as_deref_mut() {
                    rec.push(TrajectoryPoint { t, state: *state });
                }
            }
        }
        out.state = *state;
        Ok(out)
    }

    /// Advances from `*t` to `target` within one smooth piece; `grid` holds
    /// the tabulated kinematics of the fixed step ending at `target`.
    #[allow(clippy::too_many_arguments)]
    fn advance_piece(
        &self,
        t: &mut f64,
        target: f64,
        piece: f64,
        grid: Option<StepNodes<'_>>,
        state: &mut PartState,
        anchor: &V2,
        out: &mut CycleOutcome,
    ) -> Result<(), ContactLoss> {
        let tiny = self.numerics.event_tol * self.period;
        let mut cuts = 0;
        let mut swing: u32 = 0;
        // Kinematics at the end of the last accepted step: the next step's
        // start, reused instead of evaluated again.
        let mut next_k: Option<(f64, Kinematics)> = None;
        while *t < target {
            if state.u == V2::zeros() && !state.stuck {
                state.stuck = match (&next_k, grid.and_then(|g| g.at_start(*t))) {
                    (Some((tk, k)), _) if *tk == *t => self.margin_of(k, &state.r, anchor),
                    (_, Some(k)) => self.margin_of(k, &state.r, anchor),
                    _ => self.margin(*t, piece, &state.r, anchor),
                } >= 0.0;
            }
            if state.stuck {
                match self.breakaway(*t, target, piece, &state.r, anchor) {
                    None => {
                        out.stuck_time += target - *t;
                        *t = target;
                    }
                    Some(tb) => {
                        out.stuck_time += tb - *t;
                        out.events += 1;
                        *t = if target - tb <= tiny { target } else { tb };
                        state.stuck = false;
                        state.u = V2::zeros();
                    }
                }
                continue;
            }
            let k0 = match next_k.take() {
                Some((tk, k)) if tk == *t => k,
                _ => match grid.and_then(|g| g.at_start(*t)) {
                    Some(k) => *k,
                    None => self.kin(*t, piece),
                },
            };
            let u0 = state.u;
            let line = self.line.is_some_and(|i| u0[1 - i] == 0.0);
            // Kinematics at the stages of a start from rest on a line.
            let mut stages = None;
            if line {
                // A slip on the motion's line ([`Motion::slip_axis`]): a_free
                // lies along it, a_⊥ = 0, so the 2-D checks cannot fire
                // (`wants_tau`, `wants_radau` while slipping and
                // `ends_in_turn` are false, `slip_step` the rest of the step
                // outside a swing) and are skipped. A start from rest asks
                // only whether a_free keeps its sign over the step, with the
                // kinematics the explicit step then reuses.
                if u0 == V2::zeros() && self.numerics.slip != SlipScheme::Legacy {
                    let h = target - *t;
                    let (km, k1) = match grid.and_then(|g| g.stages(*t, h, target)) {
                        Some([km, k1]) => (*km, *k1),
                        None => (self.kin(*t + 0.5 * h, piece), self.kin(*t + h, piece)),
                    };
                    if !self.keeps_direction(&k0, [&km, &k1], &state.r, &u0, anchor)
                        && self.radau_to(t, target, piece, state, anchor, out)?
                    {
                        #[cfg(test)]
                        line_tests::LINE_RADAU.with(|c| c.set(c.get() + 1));
                        swing = 0;
                        continue;
                    }
                    stages = Some((km, k1));
                }
            } else {
                // N and a_free at the step's start, for the schemes' checks.
                let start = (self.numerics.slip != SlipScheme::Legacy && u0 != V2::zeros())
                    .then(|| self.forces(&k0, &state.r, &u0, anchor));
                if let (SlipScheme::Regularised, Some((n, free))) = (self.numerics.slip, start) {
                    if self.wants_tau(n, &free, &u0) {
                        self.swing(t, target, piece, state, anchor, out)?;
                        swing = 0;
                        continue;
                    }
                }
                if self.numerics.slip != SlipScheme::Legacy
                    && self.implicit_slip(&k0, t, target, piece, state, anchor, out, start)?
                {
                    swing = 0;
                    continue;
                }
            }
            let h = if line && swing == 0 {
                target - *t
            } else {
                self.slip_step(&k0, target - *t, state, anchor, swing > 0)
            };
            swing = swing.saturating_sub(1);
            let nodes = match &stages {
                Some((km, k1)) => Some([km, k1]),
                None => grid.and_then(|g| g.stages(*t, h, target)),
            };
            let (r1, u1, k1) = match nodes {
                Some([km, k1]) => self.rk4_with(*t, h, [&k0, km, k1], &state.r, &u0, anchor)?,
                None => self.rk4(*t, h, piece, &k0, &state.r, &u0, anchor, false)?,
            };
            out.rk4_steps += 1;
            if !(r1.iter().all(|x| x.is_finite()) && u1.norm_squared().is_finite()) {
                // Arithmetic overflow (|u|² beyond f64): stop with the slip
                // velocity marked NaN, which callers report (a field sample
                // is then `non_finite`).
                (state.r, state.u, *t) = (r1, V2::repeat(f64::NAN), target);
                return Ok(());
            }
            if self.numerics.slip != SlipScheme::Legacy
                && !line
                && u0 != V2::zeros()
                && u1.dot(&u0) > 0.0
                && cuts < MAX_CUTS
                && self.ends_in_turn(&k1, h, &r1, &u1, &u0, anchor)
            {
                // The explicit step ended where the slip direction turns
                // faster than the step can follow (close to a 2-D swing
                // past u = 0): back off to where the component along u₀ is
                // half the speed and follow the turn with short steps.
                cuts += 1;
                let level = 0.5 * u0.norm();
                self.back_off(t, h, piece, &k0, state, anchor, level, out)?;
                swing = MAX_SWING_STEPS;
                continue;
            }
            if u0 != V2::zeros() && u1.dot(&u0) <= 0.0 && cuts < MAX_CUTS {
                cuts += 1;
                let end = (&r1, &u1, &k1);
                let (s, rs, us) = self.stop_in_step(*t, h, piece, &k0, state, anchor, end, out)?;
                let ts = if target - (*t + s) <= tiny {
                    target
                } else {
                    *t + s
                };
                let ks = self.kin(ts, piece);
                let holds = self.margin_of(&ks, &rs, anchor) >= 0.0;
                out.events += 1;
                let (left, start) = (us.norm(), u0.norm());
                // The stiff scheme finds 2-D stops by its implicit steps
                // (the slip slowing along a_free) rather than by a fraction.
                let stop_fraction = if self.numerics.slip != SlipScheme::Legacy {
                    ZERO_FRACTION
                } else {
                    STOP_FRACTION
                };
                if left <= ZERO_FRACTION * start || (holds && left <= stop_fraction * start) {
                    // The slip velocity reached zero: the part sticks, or
                    // (a reversal) slips away from rest along a_free.
                    *t = ts;
                    state.r = rs;
                    state.u = V2::zeros();
                    state.stuck = holds;
                    next_k = Some((ts, ks));
                } else {
                    // A 2-D slip swinging past zero. The coarse step cannot
                    // follow the turn, which happens while |u| is of the
                    // order of its closest approach ε = |u(s*)|: back off to
                    // where the component along u₀ is still BACKOFF·ε and
                    // go on from there with steps short enough to follow it.
                    // The stiff scheme backs off to half the speed, where the
                    // explicit step is still accurate (h μ_k N/|u| small).
                    let level = if self.numerics.slip != SlipScheme::Legacy {
                        0.5 * start
                    } else {
                        BACKOFF * left
                    };
                    self.back_off(t, s, piece, &k0, state, anchor, level, out)?;
                    swing = MAX_SWING_STEPS;
                }
                continue;
            }
            state.r = r1;
            state.u = u1;
            *t += h;
            if target - *t <= tiny {
                *t = target;
            }
            next_k = Some((*t, k1));
        }
        Ok(())
    }

    /// Advances `state` from `*t` by the explicit step, of at most `h`, at
    /// whose end the slip velocity's component along its initial direction
    /// has fallen to `level`.
    #[allow(clippy::too_many_arguments)]
    fn back_off(
        &self,
        t: &mut f64,
        h: f64,
        piece: f64,
        k0: &Kinematics,
        state: &mut PartState,
        anchor: &V2,
        level: f64,
        out: &mut CycleOutcome,
    ) -> Result<(), ContactLoss> {
        let sb = self.locate_stop(*t, h, piece, k0, state, anchor, level, out)?;
        let (rb, ub, _) = self.rk4(*t, sb, piece, k0, &state.r, &state.u, anchor, true)?;
        out.rk4_steps += 1;
        *t += sb;
        state.r = rb;
        state.u = ub;
        Ok(())
    }

    /// [`SlipScheme::Stiff`]: an implicit step (`src/dynamics/radau.rs`)
    /// where the slip direction is stiff; true when one was taken (`t`,
    /// `state` advanced), false when the explicit step is to be taken.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn implicit_slip(
        &self,
        k0: &Kinematics,
        t: &mut f64,
        target: f64,
        piece: f64,
        state: &mut PartState,
        anchor: &V2,
        out: &mut CycleOutcome,
        start: Option<(f64, V2)>,
    ) -> Result<bool, ContactLoss> {
        let rest = target - *t;
        let tiny = self.numerics.event_tol * self.period;
        match self.wants_radau(k0, *t, rest, piece, state, anchor, start) {
            None => Ok(false),
            Some(true) => self.radau_to(t, target, piece, state, anchor, out),
            Some(false) => {
                let dir0 = state.u / state.u.norm();
                let du0 = self.slip_rhs(k0, *t, &state.r, &state.u, &dir0, anchor)?;
                let slowing =
                    self.radau_slowing(*t, rest, piece, state, anchor, &du0, &mut out.rk4_steps)?;
                match slowing {
                    None => Ok(false),
                    Some(Slowing::Slipped(e)) => {
                        state.r = e.r;
                        state.u = e.u;
                        *t = target;
                        Ok(true)
                    }
                    Some(Slowing::Partial(h, e)) => {
                        state.r = e.r;
                        state.u = e.u;
                        *t = if target - (*t + h) <= tiny {
                            target
                        } else {
                            *t + h
                        };
                        Ok(true)
                    }
                    Some(Slowing::Stopped { h, r }) => {
                        out.events += 1;
                        state.r = r;
                        state.u = V2::zeros();
                        *t = if target - (*t + h) <= tiny {
                            target
                        } else {
                            *t + h
                        };
                        state.stuck = self.margin(*t, piece, &state.r, anchor) >= 0.0;
                        Ok(true)
                    }
                }
            }
        }
    }

    /// An implicit step from `*t` to `target` (a slip speeding up); true
    /// when it was taken (`t`, `state` advanced), false when its
    /// collocation equations did not converge.
    fn radau_to(
        &self,
        t: &mut f64,
        target: f64,
        piece: f64,
        state: &mut PartState,
        anchor: &V2,
        out: &mut CycleOutcome,
    ) -> Result<bool, ContactLoss> {
        let rest = target - *t;
        match self.radau_step(*t, rest, piece, state, anchor, &mut out.rk4_steps)? {
            Some(e) => {
                state.r = e.r;
                state.u = e.u;
                *t = target;
                Ok(true)
            }
            None => Ok(false),
        }
    }

    /// True when an explicit step of size `h` from slip velocity `u0` ended
    /// at `u1` (position `r1`, kinematics `k1`) with the speed fallen below a
    /// quarter and the slip direction there turning through more than
    /// [`TURN`] per h/4 (rate |a_⊥|/|u|, a_⊥ the part of a_free across u₁):
    /// the step's end lies in the fast turn of a 2-D swing, which it cannot
    /// have followed.
    fn ends_in_turn(
        &self,
        k1: &Kinematics,
        h: f64,
        r1: &V2,
        u1: &V2,
        u0: &V2,
        anchor: &V2,
    ) -> bool {
        let s1 = u1.norm();
        if s1 >= 0.25 * u0.norm() {
            return false;
        }
        let (_, free) = self.forces(k1, r1, u1, anchor);
        let uhat = u1 / s1;
        let across = (free - uhat * free.dot(&uhat)).norm();
        0.25 * h * across > TURN * s1
    }

    /// Step size for a slipping part: the rest of the step, shortened where
    /// the slip direction turns fast. û turns at the rate |a_⊥|/|u|, with a_⊥
    /// the part of a_free across the slip; near a 2-D closest approach to
    /// u = 0 that rate is large and an explicit step cannot follow it, so
    /// the step is limited to a fraction of |u|/|a_⊥|. Right after a swing
    /// past zero (`swinging`, for at most a fixed number of steps) the step
    /// may shrink as far as the turn needs — |u| then grows geometrically, so
    /// the swing takes a few dozen steps; elsewhere it stays above 1/64 of
    /// the nominal step, which bounds the cost of long slow slips.
    /// In 1-D a_⊥ = 0 and the step is never shortened.
    ///
    /// With [`SlipScheme::Regularised`] a 2-D slip's step is limited by the
    /// faster of the turn and friction's damping across the slip,
    /// max(|a_⊥|, μ_k N)/|u| (the Jacobian of −μ_k N u/|u| across û; see
    /// `radau.rs`): just outside the regularised region (`swing.rs`) an
    /// explicit step would otherwise see h μ_k N/|u| up to ½ and err by a
    /// fixed fraction of |u| at each near pass of u = 0. Measured
    /// (`order_2d`, 4×4×6 force fields against 4096 steps): DivCircle at 64
    /// steps 3.9e-6 → 7.8e-7, SkewSink 8.1e-6 → 4.3e-6, for 1–6 % more RK4
    /// steps.
    fn slip_step(
        &self,
        k0: &Kinematics,
        rest: f64,
        state: &PartState,
        anchor: &V2,
        swinging: bool,
    ) -> f64 {
        let nominal = self.period / self.numerics.steps_per_cycle as f64;
        let shortest = if swinging {
            1e-12 * self.period
        } else {
            MIN_SUBSTEP * nominal
        };
        let speed = state.u.norm();
        if speed == 0.0 {
            return rest;
        }
        let (n, free) = self.forces(k0, &state.r, &state.u, anchor);
        let uhat = state.u / speed;
        let across = (free - uhat * free.dot(&uhat)).norm();
        // While swinging, |u| may also shrink by at most half per step, so
        // the approach to the closest point is followed too.
        let rate = if swinging {
            (free - uhat * (self.friction.kinetic * n.max(0.0))).norm()
        } else {
            0.0
        };
        let turn = if self.numerics.slip == SlipScheme::Regularised {
            self.tau_c()
        } else {
            TURN
        };
        let rate_across = if self.numerics.slip == SlipScheme::Regularised
            && across > ACROSS_ROUND_OFF * free.norm()
        {
            across.max(self.friction.kinetic * n.max(0.0))
        } else {
            across
        };
        let limit = (turn * speed / rate_across).min(0.5 * speed / rate);
        if limit >= rest {
            rest
        } else {
            limit.max(shortest)
        }
    }

    /// Root s* ∈ (0, h] of g(s) = u(s)·û₀ − `level` (the slip velocity's
    /// component along its initial direction falls to `level`) by
    /// safeguarded Newton.
    #[allow(clippy::too_many_arguments)]
    fn locate_stop(
        &self,
        t: f64,
        h: f64,
        piece: f64,
        k0: &Kinematics,
        state: &PartState,
        anchor: &V2,
        level: f64,
        out: &mut CycleOutcome,
    ) -> Result<f64, ContactLoss> {
        let u0 = state.u;
        let shift = level * u0.norm();
        let g0 = u0.dot(&u0) - shift;
        let dir0 = u0 / u0.norm();
        let (mut lo, mut hi) = (0.0, h);
        let mut s = h;
        // Initial Newton step from s = 0 (g'(0) from the RHS at the start).
        let d0 = self.slip_rhs(k0, t, &state.r, &u0, &dir0, anchor)?.dot(&u0);
        if d0 < 0.0 {
            s = (-g0 / d0).clamp(0.0, h);
        }
        let tol = self.numerics.event_tol * self.period;
        for _ in 0..60 {
            let (rs, us, ks) = self.rk4(t, s, piece, k0, &state.r, &u0, anchor, true)?;
            out.rk4_steps += 1;
            let g = us.dot(&u0) - shift;
            if g > 0.0 {
                lo = s;
            } else {
                hi = s;
            }
            let dg = self.slip_rhs(&ks, t + s, &rs, &us, &dir0, anchor)?.dot(&u0);
            let mut next = if dg < 0.0 { s - g / dg } else { f64::NAN };
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (next - s).abs() <= tol || hi - lo <= tol || g == 0.0 {
                return Ok(if g <= 0.0 { s } else { next.min(hi) });
            }
            s = next;
        }
        Ok(hi)
    }

    /// The stop inside a slip step whose end has turned against its start:
    /// the root s* ∈ (0, h] of g(s) = u(s)·u₀ (u(s) the RK4 solution after a
    /// step of size s, u₀ the slip velocity at the start) given the full
    /// step's end `end` = (r₁, u₁, k₁) with g(h) ≤ 0 < g(0). Returns s*, to
    /// the event tolerance, and the state (r, u) there.
    ///
    /// This is for a 1-D slip: u₀ and u₁ on one coordinate axis, their other
    /// component exactly zero, so that no stage of the step had a free
    /// acceleration across the axis (the LineSink and LineSource move every
    /// point along x, as does an in-plane translation along x). A 2-D slip
    /// goes to [`Simulator::locate_stop`] (Newton from s = 0), as before.
    ///
    /// Each evaluation of g is a trial RK4 step with two kinematics
    /// evaluations off the tabulated grid, so they are kept few: the first
    /// trial is at the root of the cubic Hermite interpolant of g from g and
    /// g' at both ends of the step (error O(h⁴) relative to h, about 3e-4 at
    /// 8 steps per cycle), then Newton with g' = u̇·u₀ from the right-hand
    /// side, safeguarded by the bracket. That g' differs from the slope of
    /// the RK4 solution by O(h⁴), so Newton converges linearly at that rate
    /// ρ; it stops once the correction δ, or the remaining error ρ|δ|/(1 − ρ)
    /// with ρ measured from the last two corrections, is within the event
    /// tolerance, and carries the last trial's state to s + δ by its Taylor
    /// polynomial instead of another trial step (|δ| ≤ 1e-6 h there, so that
    /// its error is O(1e-12) relative). Typically two or three trials per stop, the
    /// same root as Newton run to |δ| ≤ tolerance from s = 0 (five to seven).
    #[allow(clippy::too_many_arguments)]
    fn stop_in_step(
        &self,
        t: f64,
        h: f64,
        piece: f64,
        k0: &Kinematics,
        state: &PartState,
        anchor: &V2,
        end: (&V2, &V2, &Kinematics),
        out: &mut CycleOutcome,
    ) -> Result<(f64, V2, V2), ContactLoss> {
        let (r1, u1, k1) = end;
        let u0 = state.u;
        let on_x = u0.y == 0.0 && u1.y == 0.0;
        if !(on_x || (u0.x == 0.0 && u1.x == 0.0)) {
            // A 2-D slip (swinging past u = 0 or stopping): Newton from s = 0.
            let s = self.locate_stop(t, h, piece, k0, state, anchor, 0.0, out)?;
            let (rs, us, _) = self.rk4(t, s, piece, k0, &state.r, &u0, anchor, true)?;
            out.rk4_steps += 1;
            return Ok((s, rs, us));
        }
        let dir0 = u0 / u0.norm();
        let g0 = u0.dot(&u0);
        let gh = u1.dot(&u0);
        if gh == 0.0 {
            return Ok((h, *r1, *u1));
        }
        let d0 = self.slip_rhs(k0, t, &state.r, &u0, &dir0, anchor)?.dot(&u0);
        // (A contact loss at the step's end, past the stop, is no error.)
        let dh = match self.slip_rhs(k1, t + h, r1, u1, &dir0, anchor) {
            Ok(a) => a.dot(&u0),
            Err(_) => (gh - g0) / h,
        };
        let tol = self.numerics.event_tol * self.period;
        let (mut lo, mut hi) = (0.0, h);
        let mut s = h * hermite_root(g0, h * d0, gh, h * dh);
        let mut last_delta = f64::NAN;
        for _ in 0..60 {
            let (rs, us, ks) = self.rk4(t, s, piece, k0, &state.r, &u0, anchor, true)?;
            out.rk4_steps += 1;
            let g = us.dot(&u0);
            if g == 0.0 {
                return Ok((s, rs, us));
            }
            if g > 0.0 {
                lo = s;
            } else {
                hi = s;
            }
            let a = self.slip_rhs(&ks, t + s, &rs, &us, &dir0, anchor)?;
            let dg = a.dot(&u0);
            let delta = if dg < 0.0 { -g / dg } else { f64::NAN };
            // Newton with g' from the right-hand side converges linearly at
            // the rate ρ of the RK4 solution's mismatch with it (O(h⁴)),
            // estimated from the last two corrections: s + δ is then within
            // ρ|δ|/(1 − ρ) of the root.
            let rate = (delta / last_delta).abs();
            let error = if rate < 0.5 {
                rate * delta.abs() / (1.0 - rate)
            } else {
                f64::INFINITY
            };
            let next = s + delta;
            let converged = delta.abs() <= tol || (2.0 * error <= tol && delta.abs() <= 1e-6 * h);
            if converged && next >= lo - tol && next <= hi + tol {
                // The root is within the tolerance of s + δ, which the
                // trial's state reaches by its Taylor polynomial (error
                // O(δ²) ≤ 1e-12 relative).
                let next = next.clamp(lo, hi);
                let delta = next - s;
                let r = rs + (us + a * (0.5 * delta)) * delta;
                return Ok((next, r, us + a * delta));
            }
            last_delta = delta;
            s = if next > lo && next < hi {
                next
            } else {
                last_delta = f64::NAN;
                0.5 * (lo + hi)
            };
            if hi - lo <= tol {
                break;
            }
        }
        let (rs, us, _) = self.rk4(t, hi, piece, k0, &state.r, &u0, anchor, true)?;
        out.rk4_steps += 1;
        Ok((hi, rs, us))
    }

    /// First time in [a, b] at which a stuck part at `r` breaks away, if any.
    fn breakaway(&self, a: f64, b: f64, piece: f64, r: &V2, anchor: &V2) -> Option<f64> {
        // Samples at half-step spacing fall on the table's grid where the
        // stuck episode spans a whole step; refinements never do.
        let phi = |t: f64| self.margin(t, piece, r, anchor);
        let phi_off = |t: f64| self.margin_of(&self.kin_off_grid(t, piece), r, anchor);
        let fa = phi(a);
        if fa < 0.0 {
            return Some(a);
        }
        let spacing = 0.5 * self.period / self.numerics.steps_per_cycle as f64;
        let n = ((b - a) / spacing).ceil().max(2.0) as usize;
        // Sample i's time, and φ there (each sample evaluated once, as the
        // scan reaches it; the scan needs samples i − 1, i and i + 1).
        let time = |i: usize| {
            if i == n {
                b
            } else {
                a + (b - a) * i as f64 / n as f64
            }
        };
        let probe = 1e-4 * (b - a) / n as f64;
        let (mut prev, mut cur) = (fa, phi(time(1)));
        for i in 1..=n {
            if cur < 0.0 {
                return Some(self.illinois(&phi_off, time(i - 1), prev, time(i), cur));
            }
            let next = if i < n { phi(time(i + 1)) } else { f64::NAN };
            let fs = [prev, cur, next];
            (prev, cur) = (cur, next);
            // A local minimum of φ around sample i (or at an end) may dip
            // below zero between samples: refine it.
            let interior = i < n && fs[1] <= fs[0] && fs[1] <= fs[2];
            let at_start = i == 1 && fs[0] < fs[1] && phi_off(a + probe) < fs[0];
            let at_end = i == n && fs[1] < fs[0] && phi_off(b - probe) < fs[1];
            let bracket = if interior {
                Some((time(i - 1), time(i + 1)))
            } else if at_start {
                Some((a, time(1)))
            } else if at_end {
                Some((time(n - 1), b))
            } else {
                None
            };
            if let Some((lo, hi)) = bracket {
                // The minimum's position to 1e-9 of the bracket fixes its
                // value to O(1e-18) relative: whether it dips below zero.
                let tol = (1e-9 * (hi - lo)).max(1e-3 * self.numerics.event_tol * self.period);
                let (tm, fm) = brent_min(&phi_off, lo, hi, tol);
                if fm < 0.0 {
                    return Some(self.illinois(&phi_off, lo, phi(lo), tm, fm));
                }
            }
        }
        None
    }

    /// Root of f in [a, b] with f(a) ≥ 0 > f(b) (Illinois false position).
    fn illinois(
        &self,
        f: &impl Fn(f64) -> f64,
        mut a: f64,
        mut fa: f64,
        mut b: f64,
        mut fb: f64,
    ) -> f64 {
        let tol = self.numerics.event_tol * self.period;
        let mut side = 0;
        for _ in 0..200 {
            if b - a <= tol {
                break;
            }
            let c = (a * fb - b * fa) / (fb - fa);
            let c = if c > a && c < b { c } else { 0.5 * (a + b) };
            let fc = f(c);
            if fc < 0.0 {
                b = c;
                fb = fc;
                if side == -1 {
                    fa *= 0.5;
                }
                side = -1;
            } else {
                a = c;
                fa = fc;
                if side == 1 {
                    fb *= 0.5;
                }
                side = 1;
            }
        }
        // The first time at which the part is certainly not held.
        b
    }
}

/// Minimum of a unimodal f on [a, b], to within `tol` in its position, by
/// Brent's method: parabolic interpolation through the three best points,
/// golden-section steps where the parabola is not trusted. Returns (t, f(t))
/// for the best point, early as soon as a value below zero is seen (all the
/// caller needs to know is whether the minimum dips below zero). On a smooth
/// minimum it converges superlinearly: about ten evaluations where golden
/// section alone needs forty or more.
fn brent_min(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> (f64, f64) {
    // (3 − √5)/2, the golden-section fraction.
    const GOLD: f64 = 0.381_966_011_250_105_1;
    let mut x = a + GOLD * (b - a);
    let mut fx = f(x);
    let (mut w, mut fw, mut v, mut fv) = (x, fx, x, fx);
    // The last step d and the one before it, e.
    let (mut d, mut e): (f64, f64) = (0.0, 0.0);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if fx < 0.0 || (x - m).abs() <= 2.0 * tol - 0.5 * (b - a) {
            break;
        }
        let mut parabolic = false;
        if e.abs() > tol {
            // Vertex of the parabola through (v, fv), (w, fw), (x, fx),
            // accepted if it falls inside [a, b] and the step is less than
            // half the one before last.
            let r = (x - w) * (fx - fv);
            let q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            let mut q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            } else {
                q = -q;
            }
            if p.abs() < (0.5 * q * e).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - a < 2.0 * tol || b - u < 2.0 * tol {
                    d = tol.copysign(m - x);
                }
                parabolic = true;
            }
        }
        if !parabolic {
            e = if x >= m { a - x } else { b - x };
            d = GOLD * e;
        }
        let u = if d.abs() >= tol {
            x + d
        } else {
            x + tol.copysign(d)
        };
        let fu = f(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, fx)
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
#[path = "stop_tests.rs"]
mod stop_tests;

#[cfg(test)]
#[path = "line_tests.rs"]
mod line_tests;
