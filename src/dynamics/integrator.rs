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
//!   (`tests/unit/slip2d.rs`, `results/library_speed.md`).
//! * [`SlipScheme::Stiff`] takes them with the implicit Radau IIA method
//!   (`src/dynamics/radau.rs`): a slip speeding up once its direction has
//!   turned onto a_free (from rest, after a swing), and a slip slowing along
//!   a_free towards a stop, whose time is the root of the implicit
//!   solution's speed. A swing is backed off to half the speed (where the
//!   explicit step is accurate) and followed with short explicit steps, and
//!   an explicit step whose end falls inside a swing's fast turn is backed
//!   off the same way. 2-D force fields at 64 steps per cycle are 10–100×
//!   more accurate than the legacy scheme's (`tests/unit/slip2d.rs`).
//! * [`SlipScheme::Regularised`] (the default) is the stiff scheme with a 2-D swing past
//!   u = 0 (and a slow-down towards a 2-D stop) followed in regularised time
//!   dτ = dt/|u| instead of short explicit steps (`src/dynamics/swing.rs`):
//!   2-D force fields within 1e-4 at 64 steps per cycle, observed order
//!   3.2–4.3 from 16 to 64 steps (`tests/unit/slip2d.rs`, `results/engine_speed.md`).
//!
//! 1-D slips are unaffected by the choice except at starts from rest (both
//! exact for piecewise-constant accelerations). A slip on the motion's line
//! ([`Motion::slip_axis`]: the LineSink, LineSource and Trans) skips the 2-D
//! checks, which cannot fire there, bitwise the same (`line_tests.rs`).

use super::kinematics_table::StepNodes;
use super::scheme::{Legacy, LineStart, Regularised, Scheme, Stiff, ZERO_FRACTION};
use super::simulator::{hermite_root, Simulator};
use super::state::{CycleOutcome, PartState, Step, TrajectoryPoint, V2};
use super::{ContactLoss, SlipScheme};
use crate::motion::Kinematics;

/// Shortest slip step outside a swing, as a fraction of the nominal step.
const MIN_SUBSTEP: f64 = 1.0 / 64.0;

/// Steps after a swing past zero during which the step may shrink freely.
const MAX_SWING_STEPS: u32 = 400;

/// Most step cuts at roots of u(s)·u₀ within one step (a 2-D slip
/// velocity swinging past zero is cut a few times while it turns).
const MAX_CUTS: u32 = 16;

/// The loop state of one smooth piece in `advance_piece`.
#[derive(Default)]
struct Walk {
    /// Cuts and back-offs so far (at most [`MAX_CUTS`]).
    cuts: u32,
    /// Short steps left in a swing past u = 0.
    swing: u32,
    /// Kinematics at the end of the last accepted step: the next step's
    /// start, reused instead of evaluated again.
    next_k: Option<(f64, Kinematics)>,
}

/// The kinematics at an explicit step's stages t + h/2 and t + h, when
/// already looked up.
type Stages = Option<(Kinematics, Kinematics)>;

/// One explicit step tried in `advance_piece`.
struct Trial<'k> {
    /// Its length (s).
    h: f64,
    /// The kinematics at its start.
    k0: &'k Kinematics,
    /// The slip velocity at its start.
    u0: V2,
    /// A slip on the motion's line.
    line: bool,
    /// Event tolerance (s).
    tiny: f64,
}

impl Simulator<'_> {
    /// Advances `state` from `t0` to `t1`. The kinematics use the current
    /// position when the model's `moving` switch is on, `anchor` otherwise.
    /// Every accepted step is appended to `record` when given.
    pub fn advance(
        &self,
        t0: f64,
        t1: f64,
        state: &mut PartState,
        anchor: &V2,
        record: Option<&mut Vec<TrajectoryPoint>>,
    ) -> Result<CycleOutcome, ContactLoss> {
        let span = (t0, t1);
        match self.numerics.slip {
            SlipScheme::Legacy => self.advance_by::<Legacy>(span, state, anchor, record),
            SlipScheme::Stiff => self.advance_by::<Stiff>(span, state, anchor, record),
            SlipScheme::Regularised => self.advance_by::<Regularised>(span, state, anchor, record),
        }
    }

    /// [`Simulator::advance`] over `(t0, t1)` with the slip scheme `S`.
    fn advance_by<S: Scheme>(
        &self,
        (t0, t1): (f64, f64),
        state: &mut PartState,
        anchor: &V2,
        mut record: Option<&mut Vec<TrajectoryPoint>>,
    ) -> Result<CycleOutcome, ContactLoss> {
        let mut out = CycleOutcome::starting(*state);
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
            super::count_steps(n);
            let piece = 0.5 * (a + b);
            let nodes = self.table.and_then(|table| table.piece(a, b, n, piece));
            let mut at = Step {
                t: a,
                target: a,
                piece,
                anchor,
                state: &mut *state,
                out: &mut out,
            };
            for i in 1..=n {
                at.target = super::step_end(a, b, n, i);
                let grid = nodes.map(|p| p.step(i));
                self.advance_piece::<S>(&mut at, grid)?;
                if let Some(rec) = record.as_deref_mut() {
                    rec.push(TrajectoryPoint {
                        t: at.t,
                        state: *at.state,
                    });
                }
            }
        }
        out.state = *state;
        Ok(out)
    }

    /// Advances `at` to `at.target` within one smooth piece; `grid` holds
    /// the tabulated kinematics of the fixed step ending there.
    ///
    /// Each pass of the loop: a part at rest is checked for sticking
    /// ([`Self::update_stuck`]) and held while stuck; otherwise the scheme
    /// may take the step itself ([`Self::scheme_start`]), or an explicit
    /// RK4 step of [`Self::slip_step`]'s length is tried and accepted or
    /// cut where the slip stops or turns ([`Self::settle_step`]).
    fn advance_piece<S: Scheme>(
        &self,
        at: &mut Step<'_>,
        grid: Option<StepNodes<'_>>,
    ) -> Result<(), ContactLoss> {
        let tiny = self.numerics.event_tol * self.period;
        let mut walk = Walk::default();
        while at.t < at.target {
            self.update_stuck(at, &walk.next_k, grid);
            if at.state.stuck {
                self.hold(at, tiny);
                continue;
            }
            let k0 = self.start_kinematics(at, walk.next_k.take(), grid);
            let u0 = at.state.u;
            let line = self.line.is_some_and(|i| u0[1 - i] == 0.0);
            let stages = match self.scheme_start::<S>(at, &k0, grid, line)? {
                Some(stages) => stages,
                None => {
                    walk.swing = 0;
                    continue;
                }
            };
            let h = if line && walk.swing == 0 {
                at.target - at.t
            } else {
                self.slip_step::<S>(at, &k0, walk.swing > 0)
            };
            walk.swing = walk.swing.saturating_sub(1);
            let nodes = match &stages {
                Some((km, k1)) => Some([km, k1]),
                None => grid.and_then(|g| g.stages(at.t, h, at.target)),
            };
            let (r1, u1, k1) = match nodes {
                Some([km, k1]) => self.rk4_with(at, h, [&k0, km, k1])?,
                None => self.rk4(at, h, &k0, false)?,
            };
            at.out.rk4_steps += 1;
            if !(r1.iter().all(|x| x.is_finite()) && u1.norm_squared().is_finite()) {
                // Arithmetic overflow (|u|² beyond f64): stop with the slip
                // velocity marked NaN, which callers report (a field sample
                // is then `non_finite`).
                (at.state.r, at.state.u, at.t) = (r1, V2::repeat(f64::NAN), at.target);
                return Ok(());
            }
            let trial = Trial {
                h,
                k0: &k0,
                u0,
                line,
                tiny,
            };
            self.settle_step::<S>(at, &mut walk, &trial, (r1, u1, k1))?;
        }
        Ok(())
    }

    /// A part at rest relative to the plate and not yet stuck: stuck when
    /// its friction margin is non-negative (the kinematics at `at.t` from
    /// the last accepted step, else the grid, else evaluated).
    fn update_stuck(
        &self,
        at: &mut Step<'_>,
        next_k: &Option<(f64, Kinematics)>,
        grid: Option<StepNodes<'_>>,
    ) {
        if at.state.u == V2::zeros() && !at.state.stuck {
            let (r, anchor) = (&at.state.r, at.anchor);
            at.state.stuck = match (next_k, grid.and_then(|g| g.at_start(at.t))) {
                (Some((tk, k)), _) if *tk == at.t => self.margin_of(k, r, anchor),
                (_, Some(k)) => self.margin_of(k, r, anchor),
                _ => self.margin(at.t, at.piece, r, anchor),
            } >= 0.0;
        }
    }

    /// The kinematics at the step's start: those at the end of the last
    /// accepted step when it ended at `at.t` (reused instead of evaluated
    /// again), else the grid's, else evaluated.
    fn start_kinematics(
        &self,
        at: &Step<'_>,
        next_k: Option<(f64, Kinematics)>,
        grid: Option<StepNodes<'_>>,
    ) -> Kinematics {
        match next_k {
            Some((tk, k)) if tk == at.t => k,
            _ => match grid.and_then(|g| g.at_start(at.t)) {
                Some(k) => *k,
                None => self.kin(at.t, at.piece),
            },
        }
    }

    /// What the scheme does before the explicit step: `None` when it took
    /// the step itself (the step advanced), else the kinematics at the
    /// explicit step's stages when already looked up.
    ///
    /// A slip on the motion's line ([`Motion::slip_axis`]): a_free lies
    /// along it, a_⊥ = 0, so the 2-D checks cannot fire (the schemes' own
    /// steps and `ends_in_turn` are skipped, `slip_step` is the rest of the
    /// step outside a swing). A start from rest asks only whether a_free
    /// keeps its sign over the step, with the kinematics the explicit step
    /// then reuses.
    ///
    /// [`Motion::slip_axis`]: crate::motion::Motion::slip_axis
    fn scheme_start<S: Scheme>(
        &self,
        at: &mut Step<'_>,
        k0: &Kinematics,
        grid: Option<StepNodes<'_>>,
        line: bool,
    ) -> Result<Option<Stages>, ContactLoss> {
        if !S::IMPLICIT {
            return Ok(Some(None));
        }
        if !line {
            return Ok(if self.own_step::<S>(at, k0)? {
                None
            } else {
                Some(None)
            });
        }
        if at.state.u != V2::zeros() {
            return Ok(Some(None));
        }
        match self.line_start(at, k0, grid)? {
            LineStart::Implicit => {
                #[cfg(test)]
                line_tests::LINE_RADAU.with(|c| c.set(c.get() + 1));
                Ok(None)
            }
            LineStart::Explicit(s) => Ok(Some(s)),
        }
    }

    /// The explicit step `trial` ended at `end` = (r₁, u₁, k₁): backed off
    /// where the slip turns faster than the step can follow, cut where the
    /// slip stops (u₁·u₀ ≤ 0), each at most [`MAX_CUTS`] times per piece;
    /// else accepted.
    fn settle_step<S: Scheme>(
        &self,
        at: &mut Step<'_>,
        walk: &mut Walk,
        trial: &Trial<'_>,
        (r1, u1, k1): (V2, V2, Kinematics),
    ) -> Result<(), ContactLoss> {
        let (h, k0, u0) = (trial.h, trial.k0, trial.u0);
        if !trial.line
            && u0 != V2::zeros()
            && u1.dot(&u0) > 0.0
            && walk.cuts < MAX_CUTS
            && S::IMPLICIT
            && self.ends_in_turn(at, h, (&r1, &u1, &k1))
        {
            // The explicit step ended where the slip direction turns
            // faster than the step can follow (close to a 2-D swing
            // past u = 0): back off to where the component along u₀ is
            // half the speed and follow the turn with short steps.
            walk.cuts += 1;
            let level = 0.5 * u0.norm();
            self.back_off(at, h, k0, level)?;
            walk.swing = MAX_SWING_STEPS;
            return Ok(());
        }
        if u0 != V2::zeros() && u1.dot(&u0) <= 0.0 && walk.cuts < MAX_CUTS {
            walk.cuts += 1;
            if let Some(k) = self.cut_at_stop::<S>(at, h, k0, (&r1, &u1, &k1), trial.tiny)? {
                walk.next_k = Some(k);
            } else {
                walk.swing = MAX_SWING_STEPS;
            }
            return Ok(());
        }
        at.state.r = r1;
        at.state.u = u1;
        at.t = at.snapped(at.t + h, trial.tiny);
        walk.next_k = Some((at.t, k1));
        Ok(())
    }

    /// A stuck part at `at`: held until it breaks away or the fixed step
    /// ends (stuck time and the break-away event tallied).
    fn hold(&self, at: &mut Step<'_>, tiny: f64) {
        match self.breakaway(at) {
            None => {
                at.out.stuck_time += at.target - at.t;
                at.t = at.target;
            }
            Some(tb) => {
                at.out.stuck_time += tb - at.t;
                at.out.events += 1;
                at.t = at.snapped(tb, tiny);
                at.state.stuck = false;
                at.state.u = V2::zeros();
            }
        }
    }

    /// The explicit step of size `h` from `at` (kinematics `k0`) ended at
    /// `end` = (r₁, u₁, k₁) with its slip velocity turned against u₀: cut
    /// it at the root of u(s)·u₀. Where the slip velocity reached zero
    /// there, the part sticks or (a reversal) slips away from rest along
    /// a_free: returns the kinematics at that time, for the next step.
    /// Otherwise (a 2-D slip swinging past zero) the step is backed off to
    /// the scheme's level before the swing and `None` returned.
    fn cut_at_stop<S: Scheme>(
        &self,
        at: &mut Step<'_>,
        h: f64,
        k0: &Kinematics,
        end: (&V2, &V2, &Kinematics),
        tiny: f64,
    ) -> Result<Option<(f64, Kinematics)>, ContactLoss> {
        let (s, rs, us) = self.stop_in_step(at, h, k0, end)?;
        let ts = at.snapped(at.t + s, tiny);
        let ks = self.kin(ts, at.piece);
        let holds = self.margin_of(&ks, &rs, at.anchor) >= 0.0;
        at.out.events += 1;
        let (left, start) = (us.norm(), at.state.u.norm());
        if left <= ZERO_FRACTION * start || (holds && left <= S::stop_fraction() * start) {
            at.t = ts;
            at.state.r = rs;
            at.state.u = V2::zeros();
            at.state.stuck = holds;
            return Ok(Some((ts, ks)));
        }
        // A 2-D slip swinging past zero. The coarse step cannot follow the
        // turn, which happens while |u| is of the order of its closest
        // approach ε = |u(s*)|: back off to where the component along u₀ is
        // still at the scheme's level (BACKOFF·ε in the legacy scheme; half
        // the speed in the stiff ones, where the explicit step is still
        // accurate, h μ_k N/|u| small) and go on from there with steps
        // short enough to follow it.
        self.back_off(at, s, k0, S::swing_level(start, left))?;
        Ok(None)
    }

    /// Advances `at` by the explicit step, of at most `h`, at whose end the
    /// slip velocity's component along its initial direction has fallen to
    /// `level`.
    fn back_off(
        &self,
        at: &mut Step<'_>,
        h: f64,
        k0: &Kinematics,
        level: f64,
    ) -> Result<(), ContactLoss> {
        let sb = self.locate_stop(at, h, k0, level)?;
        let (rb, ub, _) = self.rk4(at, sb, k0, true)?;
        at.out.rk4_steps += 1;
        at.t += sb;
        at.state.r = rb;
        at.state.u = ub;
        Ok(())
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
    /// fixed fraction of |u| at each near pass of u = 0. The limit cuts
    /// the 2-D force fields' error at 64 steps per cycle for a few per cent
    /// more RK4 steps (measured: `docs/dev/forward-model.md`, **Measurements behind the
    /// integrator's constants**).
    fn slip_step<S: Scheme>(&self, at: &Step<'_>, k0: &Kinematics, swinging: bool) -> f64 {
        let (rest, state, anchor) = (at.target - at.t, &*at.state, at.anchor);
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
        let turn = S::turn(self);
        let rate_across = S::rate_across(self, across, &free, n);
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
    fn locate_stop(
        &self,
        at: &mut Step<'_>,
        h: f64,
        k0: &Kinematics,
        level: f64,
    ) -> Result<f64, ContactLoss> {
        let (t, state, anchor) = (at.t, *at.state, at.anchor);
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
            let (rs, us, ks) = self.rk4(at, s, k0, true)?;
            at.out.rk4_steps += 1;
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
    /// goes to [`Simulator::locate_stop`] (Newton from s = 0).
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
    fn stop_in_step(
        &self,
        at: &mut Step<'_>,
        h: f64,
        k0: &Kinematics,
        end: (&V2, &V2, &Kinematics),
    ) -> Result<(f64, V2, V2), ContactLoss> {
        let (r1, u1, k1) = end;
        let (t, state, anchor) = (at.t, *at.state, at.anchor);
        let u0 = state.u;
        let on_x = u0.y == 0.0 && u1.y == 0.0;
        if !(on_x || (u0.x == 0.0 && u1.x == 0.0)) {
            // A 2-D slip (swinging past u = 0 or stopping): Newton from s = 0.
            let s = self.locate_stop(at, h, k0, 0.0)?;
            let (rs, us, _) = self.rk4(at, s, k0, true)?;
            at.out.rk4_steps += 1;
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
            let (rs, us, ks) = self.rk4(at, s, k0, true)?;
            at.out.rk4_steps += 1;
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
            let next = s + delta;
            let converged = stop_converged(delta, last_delta, tol, h);
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
        let (rs, us, _) = self.rk4(at, hi, k0, true)?;
        at.out.rk4_steps += 1;
        Ok((hi, rs, us))
    }

    /// Sample times of [a, b] an event scan visits: n ≥ `min` equal
    /// intervals of at most half an integration step, sample n exactly b.
    pub(super) fn half_step_samples(
        &self,
        a: f64,
        b: f64,
        min: usize,
    ) -> (usize, impl Fn(usize) -> f64 + use<>) {
        let spacing = 0.5 * self.period / self.numerics.steps_per_cycle as f64;
        let n = ((b - a) / spacing).ceil().max(min as f64) as usize;
        let time = move |i: usize| {
            if i == n {
                b
            } else {
                a + (b - a) * i as f64 / n as f64
            }
        };
        (n, time)
    }

    /// First time in [a, b] = [`at.t`, `at.target`] at which the stuck part
    /// of `at` breaks away, if any.
    fn breakaway(&self, at: &Step<'_>) -> Option<f64> {
        let (a, b, piece, r, anchor) = (at.t, at.target, at.piece, &at.state.r, at.anchor);
        // Samples at half-step spacing fall on the table's grid where the
        // stuck episode spans a whole step; refinements never do.
        let phi = |t: f64| self.margin(t, piece, r, anchor);
        let phi_off = |t: f64| self.margin_of(&self.kin_off_grid(t, piece), r, anchor);
        let fa = phi(a);
        if fa < 0.0 {
            return Some(a);
        }
        // Sample i's time, and φ there (each sample evaluated once, as the
        // scan reaches it; the scan needs samples i − 1, i and i + 1).
        let (n, time) = self.half_step_samples(a, b, 2);
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
    pub(super) fn illinois(
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
pub(super) fn brent_min(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> (f64, f64) {
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

/// Whether the stop search of `stop_in_step` has converged after the
/// correction `delta` (the last one `last_delta`) in a step of length `h`.
///
/// Newton with g' from the right-hand side converges linearly at the rate
/// ρ of the RK4 solution's mismatch with it (O(h⁴)), estimated from the
/// last two corrections: s + δ is then within ρ|δ|/(1 − ρ) of the root.
fn stop_converged(delta: f64, last_delta: f64, tol: f64, h: f64) -> bool {
    let rate = (delta / last_delta).abs();
    let error = if rate < 0.5 {
        rate * delta.abs() / (1.0 - rate)
    } else {
        f64::INFINITY
    };
    delta.abs() <= tol || (2.0 * error <= tol && delta.abs() <= 1e-6 * h)
}

#[cfg(test)]
#[path = "stop_tests.rs"]
mod stop_tests;

#[cfg(test)]
#[path = "line_tests.rs"]
mod line_tests;

#[cfg(test)]
#[path = "../../tests/unit/slip2d.rs"]
mod slip2d_tests;
