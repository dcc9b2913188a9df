//! Planar parts: a rigid body of weighted support points ([`PlanarBody`]:
//! a uniform rectangle, or any part file's, `crate::part`) moving in
//! (x, y, θ) on the plate. The
//! paper's observation it must reproduce: in a LineSink field a rectangle
//! moves to the sink line and aligns its long side with it.
//!
//! **Model.** Written for the uniform rectangle; a general body replaces
//! the mass m/K of point j by c_j m/K (relative weights c_j of mean 1,
//! their centroid the body origin). The rectangle (length L along its body x axis, width W) is
//! sampled by K support points at the cell centres of a regular nx × ny grid,
//! body offsets ρ_j, each carrying the mass m/K (uniform density; each also
//! carries the normal load its own mass needs, below). The pose is the
//! plate-frame centre r and the angle θ of the body x axis; the generalised
//! slip velocity is ξ = (u, ω): the centre's velocity relative to the plate
//! and the spin relative to the plate. Support point j sits at
//! p_j = r + R(θ)ρ_j and slips with J_j ξ = u + ω k × R(θ)ρ_j.
//!
//! Each support point obeys the point-part physics of [`crate::dynamics`]
//! with its own position and slip velocity (per unit mass, with the
//! [`Model`] switches):
//!
//! ```text
//! N_j      = a_s,z(p_j) + (2Ω × J_j ξ)_z − g_S,z
//! a_free,j = g_S,t − a_s,t(p_j) − (2Ω × J_j ξ)_t
//! ```
//!
//! and the rigid body sums them (internal forces cancel): with the mass
//! matrix M = diag(m, m, I),
//!
//! ```text
//! M ξ' = W_free + Σ_j f_j,   W_free = (Σ_j m_j a_free,j,  Σ_j m_j (R ρ_j) × a_free,j)
//! f_j  = −μ m_j N_j (J_j ξ/|J_j ξ|, (R ρ_j) × J_j ξ/|J_j ξ|)      (Coulomb, per point)
//! ```
//!
//! N_j is affine in ρ_j, so the normal load is the linear pressure
//! distribution that gives the flat body the plate's vertical acceleration
//! and angular acceleration about horizontal axes (uniform on an in-plane
//! motion, as in the paper). N_j < 0 at any support point means an edge
//! lifts: [`ContactLoss`] at that point, never integrated through.
//!
//! **Sampled inertia.** I = Σ_j m_j |ρ_j|², not the continuum (L² + W²)/12:
//! the K support points are then an exact rigid body, so the sums above are
//! Newton–Euler for it, with no mismatch between the inertia and the
//! torques that drive it. E.g. a plate spinning up at α about a vertical axis
//! exerts the free torque −α Σ m_j |ρ_j|² on a stuck body, which needs
//! exactly that to keep its inertial orientation; the continuum inertia
//! would give it a spurious relative spin, of relative size
//! (L²/nx² + W²/ny²)/(L² + W²).
//!
//! A point part is the case K = 1 (nx = ny = 1, ρ = 0): no lever arms, no
//! inertia and no friction torque, so θ is frozen and ω stays 0.
//!
//! **Stick-slip: Moreau–Jean midpoint time-stepping**, velocity-level and
//! implicit in the friction, with exact (unregularised) Coulomb friction.
//! Per step of size h:
//!
//! ```text
//! q_mid   = q_n + (h/2) ξ_n                    kinematics at t_n + h/2
//! ξ_free  = ξ_n + h M⁻¹ W_free(q_mid, ξ_n)
//! ξ*      = argmin_ξ ½ (ξ − ξ_free)ᵀ M (ξ − ξ_free) + h Σ_j μ m_j N_j |J_j ξ|
//! q_{n+1} = q_mid + (h/2) ξ_{n+1}              (ξ_{n+1} = ξ*, or the corrector's below)
//! ```
//!
//! The minimisation is convex and non-smooth; its minimiser is *exactly*
//! ξ = 0 whenever the free impulse M ξ_free lies in the set of impulses
//! friction can supply, so a stuck body stays exactly stuck (no creep: the
//! pose is unchanged to the bit). μ = μ_s while the body is stuck (ξ_n = 0,
//! the break-away test); when that minimiser is not 0 the step is re-solved
//! with μ_k, as it is while slipping. The solver is in `planar/solver.rs`
//! (closed form for K = 1). Friction can only remove kinetic energy in a
//! step: on a plate at rest ξ_{n+1}ᵀ M ξ_{n+1} ≤ ξ_nᵀ M ξ_n.
//!
//! **Between events: the implicit midpoint corrector** ([`SlipRule::Midpoint`],
//! the default). The step above takes the friction at the step's end
//! (backward Euler in the friction) and the Coriolis terms at its start,
//! each with a local error of order h² whenever they change through the
//! step. Friction changes while a body slips whenever a support point's
//! slip direction turns: a body that spins, or slips in 2-D, turns them
//! all the time, so over a cycle the error is first order (on a plate
//! translating in a circle, where no event ever happens, the slip speed's
//! error halves per halving of h: `tests/unit/planar.rs`
//! `circular_slip_is_second_order_between_events`). Time and position are
//! already taken at the midpoint, so the remedy is the implicit midpoint
//! rule for the velocity,
//!
//! ```text
//! ξ_{n+1} = ξ_n + h M⁻¹ (W_free + F)(q_mid, t_n + h/2, ξ̄),   ξ̄ = (ξ_n + ξ_{n+1})/2,
//! F(ξ̄) = −Σ_j μ m_j N_j J_jᵀ J_j ξ̄/|J_j ξ̄|,
//! ```
//!
//! symmetric in the step and so second order wherever W_free + F is
//! smooth, i.e. wherever every support point slips. Written for ξ̄ it is
//! the same convex problem over half the step, solved by the same solver:
//!
//! ```text
//! ξ̃       = (ξ_n + ξ*)/2                     ξ̄ to O(h²), for the Coriolis terms in W_free and N_j
//! ξ̄_free  = ξ_n + (h/2) M⁻¹ W_free(q_mid, ξ̃)
//! ξ̄       = argmin_ξ ½ (ξ − ξ̄_free)ᵀ M (ξ − ξ̄_free) + (h/2) Σ_j μ_k m_j N_j(ξ̃) |J_j ξ|
//! ξ_{n+1} = 2 ξ̄ − ξ_n
//! ```
//!
//! (the optimality condition M(ξ̄ − ξ̄_free) + (h/2) ∂φ(ξ̄) ∋ 0 is the
//! midpoint equation above with ξ_{n+1} = 2ξ̄ − ξ_n; ξ̃'s O(h²) error enters
//! ξ_{n+1} times h, O(h³) per step). It is taken only where the predictor
//! ξ* found a smooth slip: the body slipping at both ends, no event
//! ([`REFINE_CHANGE`]), and every support point's slip J_j ξ turned by
//! less than 90°; and its answer is kept only where it passes the same
//! tests. Once a step of a smooth piece was a corrector step, the next
//! skips the predictor's solve: ξ̃ = ξ_n + (h/2) ξ'_last, with ξ'_last =
//! (ξ_n − ξ_{n−1})/h_last the last step's slip acceleration, which is
//! ξ' at its midpoint to O(h²), so ξ̃ is ξ̄ to O(h²) as above; when that
//! corrector's answer fails the tests the step starts over from the
//! predictor. A slipping step thus costs one solve, as the Moreau–Jean
//! step alone does (about as many Newton iterations per step on a played
//! drop, `tests/poses.rs` `drop_defaults_are_converged`).
//! Elsewhere (a stick, a break-away, a reversal, a support point
//! coming to rest) the step keeps ξ*, the Moreau–Jean step with its exact
//! stick, and is an event. A body stuck at the step's start never takes
//! the corrector, so the no-creep property holds bit for bit. The
//! corrector also only removes energy on a plate at rest: M ξ_{n+1} =
//! M ξ_n − h g with g ∈ ∂φ(ξ̄), and ξ_n = ξ̄ + (h/2) M⁻¹ g give
//! ξ_{n+1}ᵀ M ξ_{n+1} = ξ_nᵀ M ξ_n − 2h gᵀξ̄, with gᵀξ̄ = Σ_j μ m_j N_j |J_j ξ̄| ≥ 0.
//! [`SlipRule::Backward`] keeps ξ* always (the first-order scheme, for
//! comparison).
//!
//! **Accuracy.** The scheme is second order while every support point
//! slips (circular translation above, `tests/unit/planar.rs`: the slip speed's
//! error falls fourfold per halving of h, far below the backward rule's)
//! and first order at events: it does not locate
//! stick, slip and reversal events inside a step, and there its error is
//! one step's friction impulse times where in the step the event falls (an
//! erratic factor in [0, 1]). Because a vibrating part's mean velocity is a
//! small residual of a large oscillating slip, these errors matter: a step
//! whose slip velocity changes by more than [`REFINE_CHANGE`] of its smaller
//! end value (a stick, a break-away, a reversal, a 2-D swing past zero), or
//! that the corrector refused, is therefore halved, recursively, up to
//! [`PLANAR_REFINE_DEPTH`] times. Each piece is a step of this scheme
//! (so the no-creep property holds); the error at events shrinks by
//! 2^depth at the cost of a few extra steps per event. Measured numbers
//! are in `tests/unit/planar.rs`; on a played drop dominated by stick-slip
//! events (`tests/poses.rs` `planar_scheme_is_first_order_at_events`: end
//! pose after 3 s against 4096 steps per cycle) the order without
//! refinement is about 1 for either rule, and refinement cuts the error
//! several-fold. Where the error is the slip's own (the bracket's pose
//! design, `docs/parts.md`), the midpoint rule gives at 64 steps per cycle
//! the rest angle the backward rule reaches only at many times the steps
//! (measured: `docs/dev/forward-model.md`, **Measurements behind the integrator's constants**).
//!
//! **Cost.** A slipping step's implicit solve is usually a few Newton
//! iterations on the exact objective from the last slip velocity (the
//! solver's fast path); only steps where the body comes to rest or breaks
//! away pay the smoothing continuation.
//!
//! With the model's `moving` switch off the body's geometry is frozen at
//! the anchor pose (kinematics at the anchor's support points, lever arms
//! of the anchor's orientation), as the frozen point part's kinematics are.
//! Steps never straddle the motion's acceleration breakpoints.

mod solver;

use serde::{Deserialize, Serialize};

use self::solver::{minimise, shrink, Contact};
use super::{ContactLoss, Friction, Model, PartPhysics, V2};
use crate::error::{positive, Error, Result};
use crate::motion::{Kinematics, Motion, V3};

/// Default steps per cycle of the planar integrator.
pub const PLANAR_STEPS_PER_CYCLE: usize = 128;

/// Default number of times a step holding an event is halved.
pub const PLANAR_REFINE_DEPTH: u32 = 10;

/// A step is an event (and is halved) when it changes the slip velocity by
/// more than this fraction of the smaller of its end values (M-norm).
pub const REFINE_CHANGE: f64 = 0.5;

/// Most support points per side.
pub const MAX_POINTS_PER_SIDE: usize = 64;

/// A uniform rectangle sampled by an nx × ny grid of support points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rectangle {
    /// Length L along the body x axis (m).
    pub length: f64,
    /// Width W along the body y axis (m).
    pub width: f64,
    /// Support points along the length.
    pub nx: usize,
    /// Support points along the width.
    pub ny: usize,
}

impl Rectangle {
    /// A rectangle with nx × ny support points.
    pub(crate) fn new(length: f64, width: f64, nx: usize, ny: usize) -> Rectangle {
        Rectangle {
            length,
            width,
            nx,
            ny,
        }
    }

    /// A point part (one support point at the centre).
    #[cfg(test)]
    pub(crate) fn point() -> Rectangle {
        Rectangle::new(0.0, 0.0, 1, 1)
    }

    /// Validates: sizes finite and > 0 (≥ 0 for a point, nx = ny = 1),
    /// 1..=64 support points per side.
    pub(crate) fn validate(&self, field: &str) -> Result<()> {
        for (name, n) in [("nx", self.nx), ("ny", self.ny)] {
            if !(1..=MAX_POINTS_PER_SIDE).contains(&n) {
                return Err(Error::invalid(
                    format!("{field}.{name}"),
                    format!("must be in 1..={MAX_POINTS_PER_SIDE} support points, got {n}"),
                ));
            }
        }
        for (name, v) in [("length", self.length), ("width", self.width)] {
            let f = format!("{field}.{name}");
            if self.is_point() {
                crate::error::non_negative(&f, v)?;
            } else {
                positive(&f, v)?;
            }
        }
        Ok(())
    }

    /// True for a single support point (a point part).
    pub(crate) fn is_point(&self) -> bool {
        self.nx == 1 && self.ny == 1
    }

    /// Body offsets ρ_j of the support points (cell centres, x fastest).
    /// Mirror pairs are exact negatives of each other.
    pub(crate) fn support_points(&self) -> Vec<V2> {
        let coord = |i: usize, n: usize, size: f64| {
            (2.0 * i as f64 + 1.0 - n as f64) / (2.0 * n as f64) * size
        };
        let mut out = Vec::with_capacity(self.nx * self.ny);
        for j in 0..self.ny {
            for i in 0..self.nx {
                out.push(V2::new(
                    coord(i, self.nx, self.length),
                    coord(j, self.ny, self.width),
                ));
            }
        }
        out
    }

    /// Sampled moment of inertia per unit mass, I/m = mean |ρ_j|²
    /// (= (L²(1 − 1/nx²) + W²(1 − 1/ny²))/12).
    #[cfg(test)]
    pub(crate) fn inertia_per_mass(&self) -> f64 {
        let p = self.support_points();
        p.iter().map(|r| r.norm_squared()).sum::<f64>() / p.len() as f64
    }
}

/// A rigid planar body as the simulator sees it: support points ρ_j (body
/// frame, m) with relative weights c_j ≥ 0 of mean 1 (point j carries the
/// mass fraction c_j/K and the normal load of that mass). The weighted
/// centroid Σ c_j ρ_j is the body origin (the centre of mass), so that the
/// mass matrix is diag(m, m, I) with I/m = Σ c_j |ρ_j|²/K.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanarBody {
    points: Vec<V2>,
    weights: Vec<f64>,
}

impl PlanarBody {
    /// A body from support points and non-negative weights (not all zero;
    /// any scale), moved so that its weighted centroid is the origin.
    /// Returns the body and the centroid it was moved by (in the input
    /// frame). Inputs are assumed validated (see `crate::part`).
    ///
    /// ```
    /// use platefield::dynamics::{PlanarBody, V2};
    /// let (body, c) = PlanarBody::centred(&[V2::new(0.0, 0.0), V2::new(0.02, 0.0)], &[1.0, 3.0]);
    /// assert!((c.x - 0.015).abs() < 1e-15);
    /// assert!((body.points()[0].x + 0.015).abs() < 1e-15);
    /// assert_eq!(body.weights(), &[0.5, 1.5]);
    /// ```
    pub fn centred(points: &[V2], weights: &[f64]) -> (PlanarBody, V2) {
        let total: f64 = weights.iter().sum();
        let k = points.len() as f64;
        let c = points
            .iter()
            .zip(weights)
            .fold(V2::zeros(), |acc, (p, w)| acc + p * *w)
            / total;
        let body = PlanarBody {
            points: points.iter().map(|p| p - c).collect(),
            weights: weights.iter().map(|w| w * k / total).collect(),
        };
        (body, c)
    }

    /// A point part: one support point at the origin.
    pub(crate) fn point() -> PlanarBody {
        PlanarBody {
            points: vec![V2::zeros()],
            weights: vec![1.0],
        }
    }

    /// Support points ρ_j (body frame, weighted centroid at the origin).
    pub fn points(&self) -> &[V2] {
        &self.points
    }

    /// Relative weights c_j (mean 1).
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// True for a single support point (no lever arms, no inertia).
    pub(crate) fn is_point(&self) -> bool {
        self.points.len() == 1
    }

    /// Sampled moment of inertia per unit mass I/m = Σ c_j |ρ_j|²/K (0 for
    /// a point).
    pub(crate) fn inertia_per_mass(&self) -> f64 {
        if self.is_point() {
            return 0.0;
        }
        self.points
            .iter()
            .zip(&self.weights)
            .map(|(r, c)| r.norm_squared() * c)
            .sum::<f64>()
            / self.points.len() as f64
    }
}

impl From<&Rectangle> for PlanarBody {
    /// The rectangle's grid of equal weights (its centroid is the origin
    /// by symmetry, so nothing is moved).
    fn from(rect: &Rectangle) -> PlanarBody {
        if rect.is_point() {
            return PlanarBody::point();
        }
        let points = rect.support_points();
        PlanarBody {
            weights: vec![1.0; points.len()],
            points,
        }
    }
}

/// State of a planar part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PlanarState {
    /// Plate-frame centre r (m).
    pub r: V2,
    /// Angle θ of the body x axis from the plate x axis (rad).
    pub theta: f64,
    /// Slip velocity of the centre relative to the plate (m/s).
    pub u: V2,
    /// Spin relative to the plate (rad/s).
    pub omega: f64,
    /// True when the body is at rest relative to the plate (ξ = 0 exactly).
    pub stuck: bool,
}

impl PlanarState {
    /// A part at rest relative to the plate at pose (r, θ).
    pub(crate) fn at_rest(r: V2, theta: f64) -> PlanarState {
        PlanarState {
            r,
            theta,
            u: V2::zeros(),
            omega: 0.0,
            stuck: true,
        }
    }

    /// A part at pose (r, θ) slipping with (u, ω).
    pub(crate) fn slipping(r: V2, theta: f64, u: V2, omega: f64) -> PlanarState {
        PlanarState {
            r,
            theta,
            u,
            omega,
            stuck: u == V2::zeros() && omega == 0.0,
        }
    }

    /// Kinetic energy of the slip per unit mass, ½(|u|² + (I/m) ω²), for a
    /// body of sampled inertia per unit mass `inertia`.
    #[cfg(test)]
    pub(crate) fn slip_energy(&self, inertia: f64) -> f64 {
        0.5 * (self.u.norm_squared() + inertia * self.omega * self.omega)
    }
}

/// One recorded sample of a planar trajectory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PlanarSample {
    /// Time (s).
    pub t: f64,
    /// State after the step ending at `t`.
    pub state: PlanarState,
}

/// What one [`PlanarSimulator::advance`] produced.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct PlanarOutcome {
    /// Time spent stuck (s): the steps that ended with ξ = 0.
    pub stuck_time: f64,
    /// Steps computed (including those redone as halves by refinement).
    pub steps: u64,
    /// Newton iterations of the implicit friction solves.
    pub solver_iterations: u64,
    /// Solves in which some smoothing level hit its iteration limit (the
    /// exact-objective test still bounds the result by f(0)).
    pub unconverged_solves: u64,
    /// Steps halved because they held an event.
    pub refinements: u64,
}

impl std::ops::AddAssign for PlanarOutcome {
    /// The cost of two runs together.
    fn add_assign(&mut self, o: PlanarOutcome) {
        self.stuck_time += o.stuck_time;
        self.steps += o.steps;
        self.solver_iterations += o.solver_iterations;
        self.unconverged_solves += o.unconverged_solves;
        self.refinements += o.refinements;
    }
}

/// Per-call data of the steps of one smooth piece.
struct StepContext<'c> {
    piece: f64,
    anchor: (V2, f64),
    contacts: &'c mut Vec<Contact>,
    out: &'c mut PlanarOutcome,
    /// The slip acceleration (u', ω') of the last step when it was a
    /// corrector step of the same smooth piece, else `None`.
    slope: Option<(V2, f64)>,
}

/// What [`PlanarSimulator::loads`] returns beside the contacts.
struct Loads {
    /// Frictionless force per unit mass, times K (m/s²).
    force: V2,
    /// Frictionless torque per unit mass, times K (m²/s²).
    torque: f64,
    /// The least normal load per unit mass and where it acts.
    lowest: (f64, V2),
}

/// How a step treats the friction of a body that slips through it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SlipRule {
    /// The Moreau–Jean step alone: friction at the end of the step
    /// (backward Euler), first order while slipping.
    Backward,
    /// The Moreau–Jean step as predictor, then the implicit midpoint rule
    /// where every support point keeps slipping (module docs): second
    /// order between events.
    #[default]
    Midpoint,
}

/// The plate a planar part sits on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Plate<'a> {
    /// Vibrating with a periodic motion.
    Moving(&'a Motion),
    /// At rest in the home pose (kinematics zero, gravity (0, 0, −g)).
    Rest,
}

/// Simulates one rectangle on one plate (see the module docs).
#[derive(Debug, Clone)]
pub(crate) struct PlanarSimulator<'a> {
    plate: Plate<'a>,
    friction: Friction,
    gravity: f64,
    model: Model,
    step: f64,
    period: f64,
    breakpoints: Vec<f64>,
    body: PlanarBody,
    inertia: f64,
    refine_depth: u32,
    slip_rule: SlipRule,
}

impl<'a> PlanarSimulator<'a> {
    /// A simulator of a rigid body of support points with nominal step
    /// `step` (s): a [`Rectangle`] (`&rect`), or any [`PlanarBody`] (e.g. a
    /// part file's, `crate::part`). Parameters are assumed validated
    /// ([`Rectangle::validate`], [`Friction::validate`], step > 0).
    pub(crate) fn for_body(
        body: impl Into<PlanarBody>,
        plate: Plate<'a>,
        physics: PartPhysics,
        step: f64,
    ) -> PlanarSimulator<'a> {
        let body = body.into();
        let PartPhysics {
            friction,
            gravity,
            model,
        } = physics;
        let (period, breakpoints) = match plate {
            Plate::Moving(m) => (m.period(), m.breakpoints()),
            Plate::Rest => (f64::INFINITY, Vec::new()),
        };
        PlanarSimulator {
            plate,
            friction,
            gravity,
            model,
            step,
            period,
            breakpoints,
            inertia: body.inertia_per_mass(),
            body,
            refine_depth: PLANAR_REFINE_DEPTH,
            slip_rule: SlipRule::default(),
        }
    }

    /// A simulator for `motion` with `steps_per_cycle` steps per period.
    pub(crate) fn for_motion(
        rect: &Rectangle,
        motion: &'a Motion,
        physics: PartPhysics,
        steps_per_cycle: usize,
    ) -> PlanarSimulator<'a> {
        let step = motion.period() / steps_per_cycle.max(1) as f64;
        PlanarSimulator::for_body(rect, Plate::Moving(motion), physics, step)
    }

    /// The same simulator halving a step that holds an event at most
    /// `depth` times (0 = plain fixed steps).
    pub(crate) fn with_refinement(mut self, depth: u32) -> PlanarSimulator<'a> {
        self.refine_depth = depth;
        self
    }

    /// The same simulator with slip rule `rule` (default
    /// [`SlipRule::Midpoint`]).
    pub(crate) fn with_slip_rule(mut self, rule: SlipRule) -> PlanarSimulator<'a> {
        self.slip_rule = rule;
        self
    }

    /// Nominal step (s).
    #[cfg(test)]
    pub(crate) fn step(&self) -> f64 {
        self.step
    }

    /// Kinematics at `t` on the smooth piece containing `piece`.
    fn kin(&self, t: f64, piece: f64) -> Kinematics {
        match self.plate {
            Plate::Moving(m) => m.kinematics_piece(t, piece, self.gravity, self.model.tilt),
            Plate::Rest => Kinematics {
                omega: V3::zeros(),
                alpha: V3::zeros(),
                center: V3::zeros(),
                vel_center: V3::zeros(),
                accel_center: V3::zeros(),
                gravity: V3::new(0.0, 0.0, -self.gravity),
            },
        }
    }

    /// Advances `state` from `t0` to `t1` (steps of at most the nominal
    /// step, none straddling a breakpoint). With the model's `moving` off the
    /// geometry is frozen at `anchor` = (r, θ). Every step is appended to
    /// `record` when given.
    pub(crate) fn advance(
        &self,
        t0: f64,
        t1: f64,
        state: &mut PlanarState,
        anchor: (V2, f64),
        mut record: Option<&mut Vec<PlanarSample>>,
    ) -> Result<PlanarOutcome, ContactLoss> {
        let mut out = PlanarOutcome::default();
        if self.inertia == 0.0 {
            state.omega = 0.0;
        }
        state.stuck = state.u == V2::zeros() && state.omega == 0.0;
        if matches!(self.plate, Plate::Rest) && state.stuck {
            // At rest on a plate at rest nothing acts: exact.
            out.stuck_time = t1 - t0;
            return Ok(out);
        }
        let edges = super::piece_edges(t0, t1, self.period, &self.breakpoints);
        let mut contacts = Vec::with_capacity(self.body.points.len());
        for w in edges.windows(2) {
            let (a, b) = (w[0], w[1]);
            let n = ((b - a) / self.step - 1e-9).ceil().max(1.0) as usize;
            // One nominal step of every support point (`steps_taken`).
            super::count_steps(n * self.body.points.len());
            let piece = 0.5 * (a + b);
            // The slip acceleration does not carry across a breakpoint.
            let mut slope = None;
            for i in 0..n {
                let ta = a + (b - a) * i as f64 / n as f64;
                let tb = if i + 1 == n {
                    b
                } else {
                    a + (b - a) * (i + 1) as f64 / n as f64
                };
                let mut ctx = StepContext {
                    piece,
                    anchor,
                    contacts: &mut contacts,
                    out: &mut out,
                    slope,
                };
                self.refined_step(ta, tb - ta, state, &mut ctx, self.refine_depth)?;
                slope = ctx.slope;
                if let Some(rec) = record.as_deref_mut() {
                    rec.push(PlanarSample {
                        t: tb,
                        state: *state,
                    });
                }
                if matches!(self.plate, Plate::Rest) && state.stuck {
                    out.stuck_time += t1 - tb;
                    return Ok(out);
                }
            }
        }
        Ok(out)
    }

    /// A step from `t` over `h`, halved recursively (at most `depth`
    /// times) where it holds an event ([`Self::is_event`]).
    fn refined_step(
        &self,
        t: f64,
        h: f64,
        s: &mut PlanarState,
        ctx: &mut StepContext<'_>,
        depth: u32,
    ) -> Result<(), ContactLoss> {
        let (before, slope) = (*s, ctx.slope);
        let smooth = self.step_once(t, h, s, ctx)?;
        let event = !smooth || self.is_event(&before, s);
        if event && depth > 0 {
            *s = before;
            ctx.slope = slope;
            ctx.out.refinements += 1;
            self.refined_step(t, 0.5 * h, s, ctx, depth - 1)?;
            self.refined_step(t + 0.5 * h, 0.5 * h, s, ctx, depth - 1)?;
        } else if s.stuck {
            ctx.out.stuck_time += h;
        }
        Ok(())
    }

    /// True when a step changed the slip velocity by more than
    /// [`REFINE_CHANGE`] times the smaller of its values at the ends
    /// (M-norm): a stick or break-away, a reversal, a swing past zero.
    fn is_event(&self, a: &PlanarState, b: &PlanarState) -> bool {
        let norm = |u: V2, w: f64| (u.norm_squared() + self.inertia * w * w).sqrt();
        let change = norm(b.u - a.u, b.omega - a.omega);
        change > REFINE_CHANGE * norm(a.u, a.omega).min(norm(b.u, b.omega))
    }

    /// One step from `t` over `h` (module docs): the Moreau–Jean step, then,
    /// under [`SlipRule::Midpoint`] and where that step is a smooth slip,
    /// the implicit-midpoint corrector. Returns false when a slipping step
    /// could not take the corrector (a support point's slip turned by 90°
    /// or more, or the corrector's answer was an event): the step holds a
    /// support point's event and [`Self::refined_step`] halves it.
    fn step_once(
        &self,
        t: f64,
        h: f64,
        s: &mut PlanarState,
        ctx: &mut StepContext<'_>,
    ) -> Result<bool, ContactLoss> {
        let half = 0.5 * h;
        let r_mid = s.r + s.u * half;
        let theta_mid = s.theta + s.omega * half;
        let geometry = if self.model.moving {
            (r_mid, theta_mid)
        } else {
            ctx.anchor
        };
        let tm = t + half;
        let k = self.kin(tm, ctx.piece);
        let midpoint = self.slip_rule == SlipRule::Midpoint && !s.stuck;
        // Within a smooth slip the last step's slip acceleration gives ξ̄
        // to O(h²) without the predictor's solve (module docs).
        let direct = match ctx.slope.filter(|_| midpoint) {
            Some((du, dw)) => {
                let estimate = (s.u + du * half, s.omega + dw * half);
                self.corrector(s, (&k, geometry), estimate, h, ctx)
            }
            None => None,
        };
        let (next, smooth, corrected) = match direct {
            Some(next) => (next, true, true),
            None => {
                let loads = self.loads(&k, geometry, (s.u, s.omega), h, ctx.contacts);
                if loads.lowest.0 < 0.0 {
                    return Err(self.contact_loss(tm, &loads.lowest.1, loads.lowest.0));
                }
                let moreau = self.implicit(s, &loads, h, ctx, (s.u, s.omega), s.stuck);
                let slipping = moreau.0 != V2::zeros() || moreau.1 != 0.0;
                if midpoint && slipping {
                    let estimate = (0.5 * (s.u + moreau.0), 0.5 * (s.omega + moreau.1));
                    let corrected = self
                        .smooth_between(s, moreau, ctx)
                        .then(|| self.corrector(s, (&k, geometry), estimate, h, ctx))
                        .flatten();
                    let ok = corrected.is_some();
                    (corrected.unwrap_or(moreau), ok, ok)
                } else {
                    (moreau, true, false)
                }
            }
        };
        ctx.slope = corrected.then(|| ((next.0 - s.u) / h, (next.1 - s.omega) / h));
        let (u1, omega1) = next;
        s.r = r_mid + u1 * half;
        s.theta = theta_mid + omega1 * half;
        s.u = u1;
        s.omega = omega1;
        s.stuck = u1 == V2::zeros() && omega1 == 0.0;
        ctx.out.steps += 1;
        Ok(smooth)
    }

    /// True when a step from `s`'s slip velocity to `next` is a smooth slip:
    /// no event ([`Self::is_event`]) and every support point's slip (at the
    /// levers in `ctx`'s contacts) turned by less than 90°.
    fn smooth_between(&self, s: &PlanarState, next: (V2, f64), ctx: &StepContext<'_>) -> bool {
        let before = PlanarState::slipping(s.r, s.theta, s.u, s.omega);
        let after = PlanarState::slipping(s.r, s.theta, next.0, next.1);
        !self.is_event(&before, &after)
            && solver::keeps_direction(
                ctx.contacts,
                &self.scaled(s.u, s.omega),
                &self.scaled(next.0, next.1),
            )
    }

    /// The implicit-midpoint corrector of a step of size `h` from `s`
    /// (module docs): the loads at `at` = (kinematics, geometry) with the
    /// Coriolis terms at `estimate` of ξ̄, the half-step problem solved from
    /// `estimate`, and ξ_{n+1} = 2ξ̄ − ξ_n; `None` where a support point
    /// loses its load at the estimate or the answer is not a smooth slip
    /// ([`Self::smooth_between`]).
    fn corrector(
        &self,
        s: &PlanarState,
        at: (&Kinematics, (V2, f64)),
        estimate: (V2, f64),
        h: f64,
        ctx: &mut StepContext<'_>,
    ) -> Option<(V2, f64)> {
        let half = 0.5 * h;
        let mid = self.loads(at.0, at.1, estimate, half, ctx.contacts);
        if mid.lowest.0 < 0.0 {
            return None;
        }
        let (uy, wy) = self.implicit(s, &mid, half, ctx, estimate, false);
        let next = (2.0 * uy - s.u, 2.0 * wy - s.omega);
        self.smooth_between(s, next, ctx).then_some(next)
    }

    /// The generalised slip velocity scaled so that the mass matrix is the
    /// identity, z = (u, ω √(I/m)) (the solver's variable).
    fn scaled(&self, u: V2, omega: f64) -> solver::V3 {
        solver::V3::new(u.x, u.y, omega * self.inertia.sqrt())
    }

    /// The loads of a step of size `h` at kinematics `k`, the support points
    /// placed at `geometry` = (r, θ) and slipping with `velocity` = (u, ω)
    /// (which the Coriolis terms take): the frictionless force and torque
    /// per unit mass, and in `contacts` each point's lever and friction
    /// weight h N_j c_j / K.
    fn loads(
        &self,
        k: &Kinematics,
        geometry: (V2, f64),
        velocity: (V2, f64),
        h: f64,
        contacts: &mut Vec<Contact>,
    ) -> Loads {
        let (r_geo, theta_geo) = geometry;
        let (u, omega) = velocity;
        let (sin, cos) = theta_geo.sin_cos();
        let weight = 1.0 / self.body.points.len() as f64;
        let sqrt_i = self.inertia.sqrt();
        let mut force = V2::zeros();
        let mut torque = 0.0;
        let mut lowest = (f64::INFINITY, V2::zeros());
        contacts.clear();
        for (rho, c) in self.body.points.iter().zip(&self.body.weights) {
            let arm = V2::new(cos * rho.x - sin * rho.y, sin * rho.x + cos * rho.y);
            let perp = V2::new(-arm.y, arm.x);
            let p = r_geo + arm;
            let v = u + perp * omega;
            let (n, free) = self.model.point_forces(k, &V3::new(p.x, p.y, 0.0), &v);
            if n < lowest.0 {
                lowest = (n, p);
            }
            // c = 1 (a uniform body) multiplies exactly.
            force += free * *c;
            torque += arm.perp(&free) * *c;
            contacts.push(Contact {
                lever: if sqrt_i > 0.0 { perp / sqrt_i } else { perp },
                weight: h * n * weight * *c,
            });
        }
        Loads {
            force,
            torque,
            lowest,
        }
    }

    /// The implicit Coulomb velocity of a step of size `h` from `s`'s slip
    /// velocity under `loads` (whose contacts are in `ctx`): the minimiser
    /// of the module docs' objective, its Newton started at `start`; with
    /// `stuck` the break-away test (μ_s, then μ_k when the body moves).
    fn implicit(
        &self,
        s: &PlanarState,
        loads: &Loads,
        h: f64,
        ctx: &mut StepContext<'_>,
        start: (V2, f64),
        stuck: bool,
    ) -> (V2, f64) {
        let contacts = &*ctx.contacts;
        let out = &mut *ctx.out;
        let weight = 1.0 / self.body.points.len() as f64;
        let u_free = s.u + loads.force * (h * weight);
        let mu = |stuck: bool| {
            if stuck {
                self.friction.stat
            } else {
                self.friction.kinetic
            }
        };
        if self.inertia == 0.0 {
            // One support point: the closed form.
            let total: f64 = contacts.iter().map(|c| c.weight).sum();
            let mut u1 = shrink(&u_free, mu(stuck) * total);
            if stuck && u1 != V2::zeros() {
                u1 = shrink(&u_free, mu(false) * total);
            }
            return (u1, 0.0);
        }
        let sqrt_i = self.inertia.sqrt();
        let omega_free = s.omega + loads.torque * (h * weight) / self.inertia;
        let zf = self.scaled(u_free, omega_free);
        let start = self.scaled(start.0, start.1);
        let mut sol = minimise(&zf, &start, contacts, mu(stuck));
        out.solver_iterations += sol.iterations as u64;
        out.unconverged_solves += u64::from(!sol.converged);
        if stuck && sol.z != solver::V3::zeros() {
            sol = minimise(&zf, &sol.z, contacts, mu(false));
            out.solver_iterations += sol.iterations as u64;
            out.unconverged_solves += u64::from(!sol.converged);
        }
        (V2::new(sol.z.x, sol.z.y), sol.z.z / sqrt_i)
    }

    fn contact_loss(&self, t: f64, p: &V2, n: f64) -> ContactLoss {
        let (cycle, phase) = if self.period.is_finite() {
            let c = (t / self.period).floor();
            (c.max(0.0) as u64, (t / self.period - c).clamp(0.0, 1.0))
        } else {
            (0, 0.0)
        };
        ContactLoss {
            position: [p.x, p.y],
            time: t,
            cycle,
            phase,
            normal: n,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cell centres: symmetric pairs are exact negatives, the centroid is
    /// at the origin, and the sampled inertia matches its closed form.
    #[test]
    fn support_grid_and_sampled_inertia() {
        let r = Rectangle::new(0.02, 0.005, 16, 4);
        let p = r.support_points();
        assert_eq!(p.len(), 64);
        for j in 0..4 {
            for i in 0..16 {
                let a = p[j * 16 + i];
                let b = p[(3 - j) * 16 + (15 - i)];
                assert_eq!(a, -b);
                assert!(a.x.abs() < 0.01 && a.y.abs() < 0.0025);
            }
        }
        let closed =
            (0.02f64.powi(2) * (1.0 - 1.0 / 256.0) + 0.005f64.powi(2) * (1.0 - 1.0 / 16.0)) / 12.0;
        assert!((r.inertia_per_mass() - closed).abs() <= 1e-12 * closed);
        assert!(Rectangle::point().is_point() && Rectangle::point().validate("p").is_ok());
    }

    /// Weights are multiplicities: a point of weight 2 acts as two equal
    /// points at the same place (a slipping, spinning body sliding to rest
    /// on a plate at rest, compared step for step to round-off).
    #[test]
    fn weight_is_multiplicity() {
        let (a, b, c) = (
            V2::new(0.01, 0.0),
            V2::new(-0.01, 0.002),
            V2::new(0.0, -0.006),
        );
        let (weighted, o1) = PlanarBody::centred(&[a, b, c], &[2.0, 1.0, 1.0]);
        let (copies, o2) = PlanarBody::centred(&[a, a, b, c], &[1.0; 4]);
        assert!((o1 - o2).norm() < 1e-18);
        assert!((weighted.inertia_per_mass() - copies.inertia_per_mass()).abs() < 1e-18);
        let run = |body: PlanarBody| {
            let sim = PlanarSimulator::for_body(body, Plate::Rest, PartPhysics::full(0.3), 1e-4);
            let mut s = PlanarState::slipping(V2::zeros(), 0.2, V2::new(0.02, -0.01), 3.0);
            sim.advance(0.0, 0.005, &mut s, (V2::zeros(), 0.2), None)
                .unwrap();
            s
        };
        let (p, q) = (run(weighted), run(copies));
        assert!(!p.stuck && p.omega.abs() > 0.1, "{p:?}");
        assert!(
            (p.r - q.r).norm() < 1e-15 && (p.theta - q.theta).abs() < 1e-12,
            "{p:?} {q:?}"
        );
        assert!(
            (p.u - q.u).norm() < 1e-12 && (p.omega - q.omega).abs() < 1e-9,
            "{p:?} {q:?}"
        );
    }

    /// A point part keeps θ and ω = 0 whatever it is given.
    #[test]
    fn point_part_does_not_turn() {
        let sim = PlanarSimulator::for_body(
            &Rectangle::point(),
            Plate::Rest,
            PartPhysics::full(0.3),
            1e-4,
        );
        let mut s = PlanarState::slipping(V2::zeros(), 0.3, V2::new(0.01, 0.0), 5.0);
        sim.advance(0.0, 0.01, &mut s, (V2::zeros(), 0.3), None)
            .unwrap();
        assert_eq!((s.theta, s.omega), (0.3, 0.0));
        assert!(s.stuck && (s.r.x - 0.01f64.powi(2) / (2.0 * 0.3 * 9.81)).abs() < 1e-12);
    }

    /// A worked example of `dynamics::planar::PlanarSimulator::for_body`.
    #[test]
    fn example_planar_simulator_for_body() {
        use crate::dynamics::{PartPhysics, PlanarBody, PlanarSimulator, PlanarState, Plate, V2};
        let (body, _) = PlanarBody::centred(
            &[V2::new(-0.01, 0.0), V2::new(0.01, 0.0), V2::new(0.0, 0.01)],
            &[1.0, 1.0, 2.0],
        );
        let sim = PlanarSimulator::for_body(body, Plate::Rest, PartPhysics::full(0.3), 1e-4);
        let mut s = PlanarState::slipping(V2::zeros(), 0.0, V2::new(0.01, 0.0), 0.0);
        sim.advance(0.0, 0.01, &mut s, (V2::zeros(), 0.0), None)
            .unwrap();
        assert!(s.stuck); // sliding to rest on a plate at rest
    }

    /// A worked example of `dynamics::planar::PlanarSimulator::with_slip_rule`.
    #[test]
    fn example_planar_simulator_with_slip_rule() {
        use crate::dynamics::{
            PartPhysics, PlanarSimulator, PlanarState, Plate, Rectangle, SlipRule, V2,
        };
        let rect = Rectangle::new(0.02, 0.005, 4, 2);
        let sim = PlanarSimulator::for_body(&rect, Plate::Rest, PartPhysics::full(0.3), 1e-4)
            .with_slip_rule(SlipRule::Backward);
        let mut s = PlanarState::slipping(V2::zeros(), 0.0, V2::new(0.01, 0.0), 2.0);
        sim.advance(0.0, 0.01, &mut s, (V2::zeros(), 0.0), None)
            .unwrap();
        assert!(s.stuck);
    }
}

#[cfg(test)]
#[path = "../../tests/unit/planar.rs"]
mod rectangle_tests;
