//! The three ways of following a 2-D slip velocity near u = 0
//! ([`SlipScheme`](super::SlipScheme)), one type each behind [`Scheme`]:
//! what the stick-slip integrator (`integrator.rs`) asks of a scheme at
//! each step. The physics of each is in the integrator's module docs,
//! `radau.rs` (implicit steps) and `swing.rs` (regularised time).
//!
//! * [`Legacy`]: explicit RK4 steps only; a 2-D stop ends where |u| has
//!   fallen below [`STOP_FRACTION`] of its value at the step's start, and a
//!   swing past zero is backed off to [`BACKOFF`] times its closest approach.
//! * [`Stiff`]: implicit Radau steps where the slip direction is stiff (a
//!   slip speeding up from rest or after a swing, a slip slowing along
//!   a_free towards a stop), explicit steps ending inside a swing's fast
//!   turn backed off to half the speed.
//! * [`Regularised`]: [`Stiff`], with a 2-D swing past u = 0 and a slow-down
//!   towards a 2-D stop followed in regularised time, and explicit steps
//!   limited by friction's damping across the slip.

use super::kinematics_table::StepNodes;
use super::radau::Slowing;
use super::simulator::{Simulator, ACROSS_ROUND_OFF};
use super::state::{Step, V2};
use super::ContactLoss;
use crate::motion::Kinematics;

/// A root of u(s)·u₀ where the part can stick and |u(s)| is at most this
/// fraction of |u₀| is a stop (in 2-D, u reaches zero along a_free);
/// legacy scheme only.
pub(super) const STOP_FRACTION: f64 = 0.1;

/// A root of u(s)·u₀ where |u(s)| is at most this fraction of |u₀| is a
/// zero crossing (exact in 1-D, up to round-off).
pub(super) const ZERO_FRACTION: f64 = 1e-9;

/// Largest turn of the slip direction per step (radians, approximately).
pub(super) const TURN: f64 = 0.25;

/// Where a 2-D swing past zero starts to be followed with short steps: when
/// the velocity component along the step's initial direction is this many
/// times the closest approach (legacy scheme).
pub(super) const BACKOFF: f64 = 8.0;

/// How a start from rest on the motion's line was taken. (A return value
/// only, once per start from rest: boxing the kinematics would allocate.)
#[allow(clippy::large_enum_variant)]
pub(super) enum LineStart {
    /// By an implicit step (the step advanced).
    Implicit,
    /// By the explicit step, with the kinematics at its stages t + h/2 and
    /// t + h when the scheme has already looked them up.
    Explicit(Option<(Kinematics, Kinematics)>),
}

/// What a slip scheme decides in the stick-slip integrator. The defaults
/// are the stiff scheme's ([`Stiff`]).
pub(super) trait Scheme {
    /// Whether the scheme takes implicit steps (a start from rest on the
    /// motion's line, its own step off the line) and backs off explicit
    /// steps ending in a swing's fast turn (`Simulator::ends_in_turn`);
    /// false: explicit RK4 steps only ([`Legacy`]).
    const IMPLICIT: bool = true;

    /// True when a part slipping with `u` ≠ 0 (N and a_free `start` at the
    /// step's start) is in the region the scheme follows in regularised
    /// time (`swing.rs`).
    fn in_swing(_sim: &Simulator<'_>, _u: &V2, _start: (f64, V2)) -> bool {
        false
    }

    /// A root of u(s)·u₀ where the part can stick and |u(s)| is at most
    /// this fraction of |u₀| is a stop.
    fn stop_fraction() -> f64 {
        ZERO_FRACTION
    }

    /// The component along u₀ to which a 2-D swing past zero is backed off,
    /// with `start` = |u₀| and `left` the closest approach.
    fn swing_level(start: f64, _left: f64) -> f64 {
        0.5 * start
    }

    /// Largest turn of the slip direction per explicit step (radians).
    fn turn(_sim: &Simulator<'_>) -> f64 {
        TURN
    }

    /// The rate (per unit time, times |u|) that limits an explicit step of
    /// a 2-D slip: the turn rate's `across` = |a_⊥| of a_free `free`, with
    /// N = `n`.
    fn rate_across(_sim: &Simulator<'_>, across: f64, _free: &V2, _n: f64) -> f64 {
        across
    }
}

/// [`SlipScheme::Legacy`](super::SlipScheme::Legacy).
pub(super) struct Legacy;

/// [`SlipScheme::Stiff`](super::SlipScheme::Stiff).
pub(super) struct Stiff;

/// [`SlipScheme::Regularised`](super::SlipScheme::Regularised).
pub(super) struct Regularised;

impl Scheme for Legacy {
    const IMPLICIT: bool = false;

    fn stop_fraction() -> f64 {
        STOP_FRACTION
    }

    fn swing_level(_start: f64, left: f64) -> f64 {
        BACKOFF * left
    }
}

impl Scheme for Stiff {}

impl Scheme for Regularised {
    fn in_swing(sim: &Simulator<'_>, u: &V2, (n, free): (f64, V2)) -> bool {
        sim.wants_tau(n, &free, u)
    }

    fn turn(sim: &Simulator<'_>) -> f64 {
        sim.tau_c()
    }

    /// The faster of the turn and friction's damping across the slip,
    /// max(|a_⊥|, μ_k N) (see `integrator.rs` `slip_step`), for a slip off a
    /// straight line.
    fn rate_across(sim: &Simulator<'_>, across: f64, free: &V2, n: f64) -> f64 {
        if across > ACROSS_ROUND_OFF * free.norm() {
            across.max(sim.friction().kinetic * n.max(0.0))
        } else {
            across
        }
    }
}

impl Simulator<'_> {
    /// A part at rest on the motion's line (`at.state.u` = 0; `k0` the
    /// kinematics at `at.t`, `grid` the tabulated kinematics of the fixed
    /// step), in an implicit scheme ([`Scheme::IMPLICIT`]): from rest
    /// a_free keeps its line, so only whether it keeps its direction over
    /// the step matters; if not, an implicit step.
    pub(super) fn line_start(
        &self,
        at: &mut Step<'_>,
        k0: &Kinematics,
        grid: Option<StepNodes<'_>>,
    ) -> Result<LineStart, ContactLoss> {
        let h = at.target - at.t;
        let (km, k1) = match grid.and_then(|g| g.stages(at.t, h, at.target)) {
            Some([km, k1]) => (*km, *k1),
            None => (
                self.kin(at.t + 0.5 * h, at.piece),
                self.kin(at.t + h, at.piece),
            ),
        };
        if !self.keeps_direction(at, k0, [&km, &k1]) && self.radau_to(at)? {
            return Ok(LineStart::Implicit);
        }
        Ok(LineStart::Explicit(Some((km, k1))))
    }

    /// A slipping or resting part off the motion's line, before the
    /// explicit step, in an implicit scheme: the scheme's own step, where
    /// it takes one (true when it did; `at` advanced) — followed in
    /// regularised time where the scheme says so ([`Scheme::in_swing`]),
    /// else implicit where the slip direction is stiff.
    pub(super) fn own_step<S: Scheme>(
        &self,
        at: &mut Step<'_>,
        k0: &Kinematics,
    ) -> Result<bool, ContactLoss> {
        let start = self.start_forces(at, k0);
        if start.is_some_and(|s| S::in_swing(self, &at.state.u, s)) {
            self.swing(at)?;
            return Ok(true);
        }
        self.implicit_slip(at, k0, start)
    }

    /// N and a_free at the start of a slip step from `at` (u ≠ 0), for the
    /// implicit schemes' checks; `None` from rest.
    fn start_forces(&self, at: &Step<'_>, k0: &Kinematics) -> Option<(f64, V2)> {
        (at.state.u != V2::zeros()).then(|| self.forces(k0, &at.state.r, &at.state.u, at.anchor))
    }

    /// An implicit step (`radau.rs`) where the slip direction is stiff;
    /// true when one was taken (`at` advanced), false when the explicit
    /// step is to be taken. `start`: N and a_free at the step's start.
    #[inline(never)]
    fn implicit_slip(
        &self,
        at: &mut Step<'_>,
        k0: &Kinematics,
        start: Option<(f64, V2)>,
    ) -> Result<bool, ContactLoss> {
        let tiny = self.numerics.event_tol * self.period;
        match self.wants_radau(at, k0, start) {
            None => Ok(false),
            Some(true) => self.radau_to(at),
            Some(false) => {
                let dir0 = at.state.u / at.state.u.norm();
                let du0 = self.slip_rhs(k0, at.t, &at.state.r, &at.state.u, &dir0, at.anchor)?;
                let slowing = self.radau_slowing(at, &du0)?;
                match slowing {
                    None => Ok(false),
                    Some(Slowing::Slipped(e)) => {
                        at.state.r = e.r;
                        at.state.u = e.u;
                        at.t = at.target;
                        Ok(true)
                    }
                    Some(Slowing::Partial(h, e)) => {
                        at.state.r = e.r;
                        at.state.u = e.u;
                        at.t = at.snapped(at.t + h, tiny);
                        Ok(true)
                    }
                    Some(Slowing::Stopped { h, r }) => {
                        at.out.events += 1;
                        at.state.r = r;
                        at.state.u = V2::zeros();
                        at.t = at.snapped(at.t + h, tiny);
                        at.state.stuck = self.margin(at.t, at.piece, &at.state.r, at.anchor) >= 0.0;
                        Ok(true)
                    }
                }
            }
        }
    }

    /// An implicit step from `at.t` to `at.target` (a slip speeding up);
    /// true when it was taken (`at` advanced), false when its collocation
    /// equations did not converge.
    fn radau_to(&self, at: &mut Step<'_>) -> Result<bool, ContactLoss> {
        let rest = at.target - at.t;
        match self.radau_step(at, rest)? {
            Some(e) => {
                at.state.r = e.r;
                at.state.u = e.u;
                at.t = at.target;
                Ok(true)
            }
            None => Ok(false),
        }
    }

    /// True when an explicit step of size `h` from `at` (slip velocity
    /// u₀) ended at `end` = (r₁, u₁, k₁) with the speed fallen below a
    /// quarter and the slip direction there turning through more than
    /// [`TURN`] per h/4 (rate |a_⊥|/|u|, a_⊥ the part of a_free across u₁):
    /// the step's end lies in the fast turn of a 2-D swing, which it cannot
    /// have followed.
    pub(super) fn ends_in_turn(
        &self,
        at: &Step<'_>,
        h: f64,
        (r1, u1, k1): (&V2, &V2, &Kinematics),
    ) -> bool {
        let s1 = u1.norm();
        if s1 >= 0.25 * at.state.u.norm() {
            return false;
        }
        let (_, free) = self.forces(k1, r1, u1, at.anchor);
        let uhat = u1 / s1;
        let across = (free - uhat * free.dot(&uhat)).norm();
        0.25 * h * across > TURN * s1
    }
}
