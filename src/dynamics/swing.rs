//! A 2-D slip swinging past u = 0, followed in regularised time
//! ([`SlipScheme::Regularised`](super::SlipScheme)).
//!
//! Near u = 0 the slip direction û = u/|u| of a slip whose free
//! acceleration a_free has a part a_⊥ across it turns at the rate
//! |a_⊥|/|u|, and friction damps across the slip at the rate μ_k N/|u|: a
//! step in t cannot follow either. With s = |u| and a new time τ,
//!
//! ```text
//! dt/dτ = s,   dr/dτ = s u,   du/dτ = s a_free(t, r, u) − μ_k N(t, r, u) u,
//! ```
//!
//! which is the same Coulomb law (not smoothed) with the singular factor
//! 1/|u| gone: the right-hand side is Lipschitz, the turn takes a τ of
//! order π/|a_⊥|, and |u| changes by at most a factor e^(Δτ (|a_free| +
//! μ_k N)) per step. The swing is taken with classical RK4 steps in τ of
//! Δτ = c / max(|a_free|, μ_k N), with c proportional to the nominal step
//! h (c = [`C64`] at 64 steps per cycle, at most [`C_MAX`]): the swing's
//! error then falls like h⁴ while its step count grows like 1/h; a slip
//! slaved to a_free takes longer steps, set by how fast its log-speed
//! changes ([`Simulator::tau_step`]). Outside
//! the region, explicit steps in t are limited to a turn of the slip
//! direction by c as well (`Simulator::slip_step`).
//!
//! The regularised steps are used only where an explicit step in t is
//! stiff or cannot follow the turn: |u| < [`REGION`] h_r max(|a_free|, μ_k N)
//! (h_r the nominal step, held at its [`REGION_STEPS`]-step width), with
//! a_free not (nearly) along û, or a slip slowing towards u = 0 off an
//! exact straight line (an exact 1-D slip keeps its exact explicit steps). They end
//! * at the nominal step's end (the last τ-step's length is the root of
//!   t(Δτ) = t_end, found by the Illinois method);
//! * where |u| is back above that bound and growing (the explicit steps in
//!   t, or the implicit ones of `radau.rs`, go on);
//! * where the slip speeds up with its direction slaved to a_free (û within
//!   `radau.rs`'s SLAVED of it), slowly (by the bound of [`IMPLICIT_AFTER`]
//!   the τ-steps would need more than that many steps to leave the region)
//!   and with friction's damping across it stiff for the rest of the nominal
//!   step (μ_k N Δt > STIFF |u|): there one implicit Radau IIA step
//!   (`radau.rs`) takes it to the nominal step's end, as it would outside
//!   the region, unless its collocation equations fail or its end is
//!   reversed or no longer a slaved speed-up ([`still_slaved`]; then the
//!   τ-steps go on). Without that step such a slip is followed by τ-steps
//!   until |u| passes the bound: each grows ln |u| by only about
//!   C_SLAVED (a_free·û − μ_k N)/|a_free|, dozens of steps where μ_k N is
//!   close to |a_free|. With it the default library's 2-D force fields
//!   take less CPU at nearly unchanged errors (measured: `docs/dev/forward-model.md`, **Measurements
//!   behind the integrator's constants**);
//! * at a stop, finished in closed form ([`Simulator::finish`]): where the
//!   exact flow with a_free and N frozen (`frozen.rs`; μ_k N > |a_free|)
//!   comes to rest within [`FINISH`] of the nominal step, the rest of the
//!   way (or the way to the nominal step's end, if that comes first) is the
//!   commutator-free composition of two such flows (`frozen.rs` [`Cf4`]),
//!   with a_free and N from the two Gauss nodes of the remaining time.
//!   Without it, a slowing slip is followed by τ-steps down to |u| = 1e-7
//!   of the bound: 64 or more τ-steps per stop, several hundred where μ_k N is
//!   close to |a_free| (ψ turns onto a_free at the rate |a_free| in τ, but
//!   s falls only at μ_k N − |a_free|), in all about half the τ-steps of
//!   ScaledCircle's and DivCircle's force fields. With it the CPU time of
//!   those fields falls by about a third, with the same errors at 32 steps
//!   per cycle and more (see [`FINISH`]; measured: `docs/dev/forward-model.md`, **Measurements
//!   behind the integrator's constants**).
//! * where |u| has fallen below [`STOP`] of the bound while slowing with
//!   μ_k N ≤ |a_free| (no frozen stop; rare), the rest of the way to u = 0
//!   is taken with a_free and N frozen and û fixed: it lasts s/(μ_k N −
//!   a_free·û) and moves the part s²/(2(μ_k N − a_free·û)) along û (an
//!   error of order s²).
//!
//! The part then sticks or slips away from rest as at any stop. What the
//! τ-steps cost is mostly slow slips that neither stop nor leave the region
//! within a nominal step (|u| about 1/20 of the bound): nearly straight
//! ones (DivCircle's, whose a_free is within 1e-3 of the slip's line) take
//! steps set by their log-speed ([`Simulator::tau_step`]), the others must
//! resolve friction's damping across the slip, μ_k N/|u|, explicitly or in
//! τ alike.

use super::frozen::{Cf4, Frozen};
use super::radau::{SLAVED, STIFF};
use super::simulator::{hermite_root, Simulator, ACROSS_ROUND_OFF};
use super::state::{PartState, Step, V2};
use super::ContactLoss;

/// The τ-step's c = Δτ max(|a_free|, μ_k N) at 64 steps per cycle; it
/// scales with the nominal step (capped at [`C_MAX`]).
pub(super) const C64: f64 = 0.25;

/// The largest Δτ max(|a_free|, μ_k N) of a τ-step whose slip is slaved to
/// a_free ([`Simulator::tau_step`]) at 64 steps per cycle and fewer
/// (proportional to c beyond): inside RK4's real stability interval
/// (−2.78, 0), for the turn onto a_free, at a damping factor of 1/3 per step.
const C_SLAVED: f64 = 2.0;

/// The longest time s Δτ a slaved τ-step spans, as a fraction of the
/// nominal step, so that its stages resolve a_free(t) and N(t) as the
/// nominal steps do. Without it, at 8 steps per cycle (where the region is
/// 8× wider and its slips faster) the force fields err up to several
/// times more than with it; from 16 steps on the errors and the CPU time are the same
/// with or without it (measured: `docs/dev/forward-model.md`, **Measurements behind the
/// integrator's constants**).
const SLAVED_SPAN: f64 = 0.1;

/// A slip speeding up slaved to a_free inside the region is taken by one
/// implicit step to the nominal step's end when the τ-steps would need more
/// than this many steps to leave the region by the bound ln(bound/|u|)
/// max(|a_free|, μ_k N)/([`C_SLAVED`] (a_free·û − μ_k N)) (each grows ln |u|
/// by at most C_SLAVED (a_free·û − μ_k N)/max(|a_free|, μ_k N); their other
/// limits in `tau_step`, and c below C64 beyond 64 steps per cycle, make
/// them more, so the bound is a lower one). A faster speed-up
/// keeps its few τ-steps: taken implicitly too, it costs the force fields'
/// observed order (`tests/unit/slip2d.rs` `order_2d`), which this threshold
/// keeps for nearly all of the speed-up (module docs; measured:
/// `docs/dev/forward-model.md`, **Measurements behind the integrator's constants**).
const IMPLICIT_AFTER: f64 = 5.0;

/// Largest c (at fewer than 32 steps per cycle).
const C_MAX: f64 = 0.5;

/// The regularised region: |u| < REGION h_r max(|a_free|, μ_k N), with
/// h_r = max(h, T/[`REGION_STEPS`]) (an explicit step there would have
/// h μ_k N/|u| or its turn h |a_⊥|/|u| above 1/REGION).
///
/// # Why the width is held below 64 steps'
///
/// A bound that scales with h at every h leaves an error floor: just
/// outside the region the explicit steps then see h μ_k N/|u| and
/// h |a_⊥|/|u| near 1/REGION *whatever h is*, so each near pass of u = 0
/// errs by a fixed fraction of |u| ≈ REGION h max(|a_free|, μ_k N), an
/// error of order h: the force fields' error then stops falling beyond 64
/// steps per cycle. Held at its 64-step width, together with the explicit
/// steps limited by friction's damping across the slip
/// (`Simulator::slip_step`), it falls again with h (nothing changes at 64
/// steps and fewer). Widening it at 64 steps instead (REGION 4) makes the
/// τ-steps carry more of the swing, and the Circle's error grows
/// (measured: `docs/dev/forward-model.md`, **Measurements behind the integrator's
/// constants**).
///
/// Two rarer errors at single fine step counts only (a break-away just
/// before a step's end, a slip slowing to a stop with a_free nearly along
/// û) are handled in `radau.rs::wants_radau` and
/// [`Simulator::wants_tau`]: without them a fine field can be off a
/// coarser one from a single cycle; with them the two agree cycle by
/// cycle (measured: `docs/dev/forward-model.md`, **Measurements behind the integrator's
/// constants**).
const REGION: f64 = 2.0;

/// The region's width stops shrinking with h beyond this many steps per
/// cycle (see [`REGION`]).
const REGION_STEPS: f64 = 64.0;

/// A slowing slip whose speed is below this fraction of the regularised
/// region's bound is finished analytically (a stop).
const STOP: f64 = 1e-7;

/// A slip that the frozen flow brings to a stop within this fraction of
/// the nominal step is finished with it ([`Simulator::finish`]).
///
/// 0.05: at a larger fraction single cycles find a stop that a fine run
/// swings past and the default library's errors grow, while 0.05 leaves
/// every force field's error as without the finish at 32 steps per cycle
/// and more, for less CPU (measured: `docs/dev/forward-model.md`, **Measurements behind the
/// integrator's constants**).
const FINISH: f64 = 0.05;

/// Most τ-steps in one call (a guard; a swing takes a few dozen).
const MAX_TAU_STEPS: u32 = 100_000;

/// True when a slip `u` with du/dt = `du` speeds up with its direction
/// slaved: du·û > 0 and the part of du across û (a_free's) within
/// [`SLAVED`] of |du|. Stricter than the test before the step (a_⊥ within
/// SLAVED of |a_free|), since |du| ≈ a_free·û − μ_k N there: an implicit
/// step is kept only where its end is clearly a slaved speed-up (on
/// DivCircle's force fields at 16, 32 and 64 steps per cycle it turned down
/// 6, 9 and 22 steps that the looser test would have kept, against about
/// 9 600 kept in all).
fn still_slaved(u: &V2, du: &V2) -> bool {
    let s = u.norm();
    if s == 0.0 {
        return false;
    }
    let uhat = u / s;
    let along = du.dot(&uhat);
    along > 0.0 && (du - uhat * along).norm() <= SLAVED * du.norm()
}

/// State in regularised time: (t, r, u).
#[derive(Debug, Clone, Copy)]
struct Tau {
    t: f64,
    r: V2,
    u: V2,
}

impl Simulator<'_> {
    /// h_r of the region's bound: the nominal step, at least T/[`REGION_STEPS`].
    fn region_step(&self) -> f64 {
        let steps = self.numerics().steps_per_cycle as f64;
        self.period() / steps.min(REGION_STEPS)
    }

    /// The c of the τ-steps: [`C64`] scaled with the nominal step.
    pub(super) fn tau_c(&self) -> f64 {
        (C64 * 64.0 / self.numerics().steps_per_cycle as f64).min(C_MAX)
    }

    /// Δτ of the next τ-step of a slip with speed `s` and direction `uhat`
    /// under a_free `free` (`along` = a_free·û) and kinetic friction
    /// `mu_n` = μ_k N.
    ///
    /// In general c / max(|a_free|, μ_k N). A slip slaved to a_free (û within
    /// [`SLAVED`] of it: the slow speed-ups and slow-downs of a nearly
    /// straight slip, most of DivCircle's τ-steps) has two modes in τ: its
    /// log-speed changes at the rate g = a_free·û − μ_k N, slowly when
    /// μ_k N is near |a_free|, and its direction relaxes onto a_free at the
    /// rate μ_k N (across u, du/dτ = s a_free − μ_k N u damps u's part
    /// across a_free). The step only has to resolve the first, |g| Δτ ≤ c,
    /// and a_free(t) and N(t) over its span, s Δτ ≤ [`SLAVED_SPAN`] h, and
    /// keep the second stable, max(|a_free|, μ_k N) Δτ ≤ [`C_SLAVED`]:
    /// RK4 keeps the slaved direction (a frozen linear system's equilibrium
    /// is every Runge–Kutta method's) and damps the departure from it by
    /// R(−2) = 1/3 per step instead of e⁻². Never shorter than the general
    /// step. On the default library's force fields it about halves the
    /// kinematics evaluations per one-cycle simulation at unchanged errors
    /// (measured: `docs/dev/forward-model.md`, **Measurements behind the integrator's constants**).
    fn tau_step(&self, c: f64, free: &V2, mu_n: f64, along: f64, uhat: &V2, s: f64) -> f64 {
        let fm = free.norm();
        let scale = fm.max(mu_n);
        let general = c / scale;
        if (free - uhat * along).norm() > SLAVED * fm {
            return general;
        }
        // Held at C_SLAVED down to 64 steps per cycle, shrinking with c
        // beyond: the turn's damping R(−C_SLAVED) ≠ e^(−C_SLAVED) is an
        // error that more steps must remove too.
        let slaved = (C_SLAVED * c / C64).min(C_SLAVED);
        let h = self.period() / self.numerics().steps_per_cycle as f64;
        (slaved / scale)
            .min(c / (along - mu_n).abs())
            .min(SLAVED_SPAN * h / s)
            .max(general)
    }

    /// True when a part slipping with `state.u` ≠ 0 (forces `n`, `free`)
    /// is in the region followed in regularised time.
    pub(super) fn wants_tau(&self, n: f64, free: &V2, u: &V2) -> bool {
        let s = u.norm();
        if s == 0.0 {
            return false;
        }
        let h_r = self.region_step();
        let scale = free.norm().max(self.friction().kinetic * n);
        if s >= REGION * h_r * scale {
            return false;
        }
        let uhat = u / s;
        let along = free.dot(&uhat);
        let across = (free - uhat * along).norm();
        // Turning, or slowing (d|u|/dt = a_free·û − μ_k N < 0) towards
        // u = 0 off a straight line (an exact 1-D slip, a_⊥ = 0, keeps its
        // exact explicit steps). Slowing, not only a_free·û < 0: a slip
        // slowing with a_free nearly along û would take explicit steps that
        // grow stiff near the stop, and one DivCircle cycle at 1024 steps
        // per cycle would end 2.2e-7 m/s off (512 and 2048 steps agree to
        // 1e-8).
        let slowing = along < self.friction().kinetic * n;
        across > SLAVED * free.norm() || (slowing && across > ACROSS_ROUND_OFF * free.norm())
    }

    /// d(t, r, u)/dτ at `y`, with N and a_free there.
    fn tau_rhs(&self, y: &Tau, piece: f64, anchor: &V2) -> Result<(Tau, f64, V2), ContactLoss> {
        let k = self.kin_off_grid(y.t, piece);
        let (n, free) = self.forces(&k, &y.r, &y.u, anchor);
        if n < 0.0 {
            return Err(self.contact_loss(y.t, &y.r, anchor, n));
        }
        let s = y.u.norm();
        let mu = self.friction().kinetic;
        Ok((
            Tau {
                t: s,
                r: y.u * s,
                u: free * s - y.u * (mu * n),
            },
            n,
            free,
        ))
    }

    /// One RK4 step of size `d` in τ from `y` with `f0` its derivative.
    fn tau_rk4(
        &self,
        y: &Tau,
        f0: &Tau,
        d: f64,
        piece: f64,
        anchor: &V2,
    ) -> Result<Tau, ContactLoss> {
        let at = |f: &Tau, w: f64| Tau {
            t: y.t + f.t * w,
            r: y.r + f.r * w,
            u: y.u + f.u * w,
        };
        let f1 = self.tau_rhs(&at(f0, 0.5 * d), piece, anchor)?.0;
        let f2 = self.tau_rhs(&at(&f1, 0.5 * d), piece, anchor)?.0;
        let f3 = self.tau_rhs(&at(&f2, d), piece, anchor)?.0;
        let w = d / 6.0;
        Ok(Tau {
            t: y.t + (f0.t + 2.0 * (f1.t + f2.t) + f3.t) * w,
            r: y.r + (f0.r + (f1.r + f2.r) * 2.0 + f3.r) * w,
            u: y.u + (f0.u + (f1.u + f2.u) * 2.0 + f3.u) * w,
        })
    }

    /// Finishes a slip slowing to a stop with the exact frozen flow
    /// (`frozen.rs`) when the stop is near: true when it did (`y` advanced
    /// to the stop, `state.stuck` set, or to `target` if that comes first),
    /// false when the flow with a_free and N (`free`, `n`, at `y`) frozen
    /// does not stop within [`FINISH`] of the nominal step.
    ///
    /// The frozen flow errs by the change of a_free and N over the time it
    /// covers: the rest of the way is taken with the commutator-free
    /// fourth-order composition of two frozen flows ([`Cf4::to_stop`]),
    /// whose fields are a_free and N at the two Gauss nodes of the span
    /// (kinematics there; position and slip velocity from the composition
    /// itself), and which falls back to τ-steps where μ_k N ≤ |a_free| at
    /// either node (the slip may swing past u = 0 instead of stopping).
    fn finish(
        &self,
        at: &mut Step<'_>,
        y: &mut Tau,
        n: f64,
        free: &V2,
    ) -> Result<bool, ContactLoss> {
        let (target, piece, anchor) = (at.target, at.piece, at.anchor);
        let mu = self.friction().kinetic;
        let Some(flow) = Frozen::new(free, mu * n, &y.u) else {
            return Ok(false);
        };
        let nominal = self.period() / self.numerics().steps_per_cycle as f64;
        let stop = flow.stop_time();
        if stop.is_nan() || stop > FINISH * nominal {
            return Ok(false);
        }
        let rest = target - y.t;
        let field = |dt: f64, dr: &V2, u: &V2| {
            let r = y.r + dr;
            let k = self.kin_off_grid(y.t + dt, piece);
            let (ni, ai) = self.forces(&k, &r, u, anchor);
            if ni < 0.0 {
                return Err(self.contact_loss(y.t + dt, &r, anchor, ni));
            }
            Ok((ai, mu * ni))
        };
        let Some(path) = Cf4::to_stop(flow, &y.u, rest, field)? else {
            return Ok(false);
        };
        let stop = path.stop_time();
        let tol = self.numerics().event_tol * self.period();
        if y.t + stop < target - tol {
            at.out.events += 1;
            y.t += stop;
            y.r += path.at(stop).0;
            y.u = V2::zeros();
            at.state.stuck = self.margin(y.t, piece, &y.r, anchor) >= 0.0;
        } else {
            let (dr, u) = path.at(rest);
            y.r += dr;
            y.u = u;
            y.t = target;
        }
        Ok(true)
    }

    /// One implicit step from `y` to the nominal step's end, for a slip
    /// speeding up with its direction slaved to a_free (module docs); true
    /// when taken (`y` then at the target), false when it did not converge
    /// or left the slaved slip.
    fn implicit_to_target(&self, at: &mut Step<'_>, y: &mut Tau) -> Result<bool, ContactLoss> {
        let (target, piece, anchor) = (at.target, at.piece, at.anchor);
        let mut here = PartState::new(y.r, y.u);
        let rest = target - y.t;
        let mut from = Step {
            t: y.t,
            target,
            piece,
            anchor,
            state: &mut here,
            out: &mut *at.out,
        };
        Ok(match self.radau_step(&mut from, rest)? {
            Some(e) if e.u.dot(&y.u) > 0.0 && still_slaved(&e.u, &e.du) => {
                (y.t, y.r, y.u) = (target, e.r, e.u);
                true
            }
            _ => false,
        })
    }

    /// The rest of the way to u = 0 with a_free and N frozen: a uniform
    /// deceleration `decel` along `uhat` from `y` at speed `s`, to the target or to rest
    /// (an event; the part then sticks if its friction margin allows).
    fn coast_to_rest(&self, at: &mut Step<'_>, y: &mut Tau, (uhat, s): (V2, f64), decel: f64) {
        let (target, piece, anchor) = (at.target, at.piece, at.anchor);
        let tol = self.numerics().event_tol * self.period();
        let dt = s / decel;
        if y.t + dt >= target - tol {
            let d = target - y.t;
            y.r += uhat * (s * d - 0.5 * decel * d * d);
            y.u = uhat * (s - decel * d).max(0.0);
            y.t = target;
        } else {
            at.out.events += 1;
            y.t += dt;
            y.r += uhat * (0.5 * s * dt);
            y.u = V2::zeros();
            at.state.stuck = self.margin(y.t, piece, &y.r, anchor) >= 0.0;
        }
    }

    /// The τ-step of length `d` from `y` (speed `s`; ending at `y1`) ends at or past
    /// the target: its length found as the root of t(m) = target. Newton
    /// with dt/dτ = |u| at each trial's end (safeguarded by the bracket
    /// [lo, hi]), from the root of the cubic Hermite interpolant of t over
    /// the step (t and dt/dτ = s known at both ends): two or three trials
    /// instead of the Illinois method's five or six. Returns the state at
    /// the target.
    fn land_on_target(
        &self,
        at: &mut Step<'_>,
        (y, s): (&Tau, f64),
        f0: &Tau,
        d: f64,
        y1: Tau,
    ) -> Result<Tau, ContactLoss> {
        let (target, piece, anchor) = (at.target, at.piece, at.anchor);
        let tol = self.numerics().event_tol * self.period();
        let (mut lo, mut hi) = (0.0, d);
        // (`hermite_root` wants a falling function over θ = m/d ∈ [0, 1].)
        let theta = hermite_root(target - y.t, -d * s, target - y1.t, -d * y1.u.norm());
        let mut m = d * theta.clamp(0.0, 1.0);
        let mut best = y1;
        for _ in 0..100 {
            if (best.t - target).abs() <= tol || hi - lo <= 1e-15 * d {
                break;
            }
            let ym = self.tau_rk4(y, f0, m, piece, anchor)?;
            at.out.rk4_steps += 1;
            let g = ym.t - target;
            if g.abs() <= tol {
                best = ym;
                break;
            }
            if g > 0.0 {
                (hi, best) = (m, ym);
            } else {
                lo = m;
            }
            let next = m - g / ym.u.norm();
            m = if next > lo && next < hi {
                next
            } else {
                0.5 * (lo + hi)
            };
        }
        best.t = target;
        Ok(best)
    }

    /// Follows a slipping part (`state.u` ≠ 0) in regularised time from
    /// `*t` until it leaves the region (see the module docs), stops, or
    /// reaches `target`. Advances `t` and `state`.
    #[inline(never)]
    pub(super) fn swing(&self, at: &mut Step<'_>) -> Result<(), ContactLoss> {
        let (target, piece, anchor) = (at.target, at.piece, at.anchor);
        let c = self.tau_c();
        let mu = self.friction().kinetic;
        let h_r = self.region_step();
        let tol = self.numerics().event_tol * self.period();
        let mut y = Tau {
            t: at.t,
            r: at.state.r,
            u: at.state.u,
        };
        let mut implicit_failed = false;
        for _ in 0..MAX_TAU_STEPS {
            let (f0, n, free) = self.tau_rhs(&y, piece, anchor)?;
            let s = y.u.norm();
            let scale = free.norm().max(mu * n);
            let bound = REGION * h_r * scale;
            let uhat = y.u / s;
            let along = free.dot(&uhat);
            if s >= bound && along > mu * n {
                break;
            }
            // A slip speeding up with its direction slaved to a_free, slowly
            // enough that the τ-steps would take more than IMPLICIT_AFTER
            // steps to leave the region: one implicit step to the nominal
            // step's end (module docs).
            if !implicit_failed
                && along > mu * n
                && (free - uhat * along).norm() <= SLAVED * free.norm()
                && (target - y.t) * mu * n > STIFF * s
                && (bound / s).ln() * scale > IMPLICIT_AFTER * C_SLAVED * (along - mu * n)
            {
                if self.implicit_to_target(at, &mut y)? {
                    break;
                }
                implicit_failed = true;
            }
            if self.finish(at, &mut y, n, &free)? {
                break;
            }
            if s < STOP * bound && along < mu * n {
                self.coast_to_rest(at, &mut y, (uhat, s), mu * n - along);
                break;
            }
            let d = self.tau_step(c, &free, mu * n, along, &uhat, s);
            let y1 = self.tau_rk4(&y, &f0, d, piece, anchor)?;
            at.out.rk4_steps += 1;
            if y1.t < target - tol {
                y = y1;
                continue;
            }
            y = self.land_on_target(at, (&y, s), &f0, d, y1)?;
            break;
        }
        at.t = y.t;
        at.state.r = y.r;
        at.state.u = y.u;
        Ok(())
    }
}
