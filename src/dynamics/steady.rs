//! Steady-state velocity of a point part: the mean velocity over one cycle
//! of the periodic motion.
//!
//! The cycle map P sends the slip velocity u at phase 0 (part at r₀) to the
//! slip velocity one period later, with the part put back at r₀. Its fixed
//! point u* = P(u*) is the periodic orbit:
//!
//! * **frozen** (model switch `moving` off): the plate kinematics are held at
//!   r₀, as in the paper's analysis; the fixed point is the exact periodic
//!   orbit of the cycle map.
//! * **free** (`moving` on): the part moves during the cycle and the
//!   kinematics follow it; the fixed point is the velocity with which the
//!   part passes r₀ at phase 0 in its steady motion (exact as the field
//!   varies slowly over one cycle's travel).
//!
//! The steady-state velocity is the mean of u over that cycle, i.e. the
//! displacement over T (the plate's own velocity has zero mean). The fixed
//! point is found by a few plain iterations and then Newton's method with a
//! finite-difference Jacobian (P is piecewise smooth, piecewise linear for
//! the square wave, so Newton terminates at machine precision).
//!
//! **Stall test.** Where the cycle map is continuous only up to the
//! integrator's error (2-D slips passing near u = 0), the residual stops
//! decreasing at that error level and wanders. The iteration has stalled
//! when [`STALL_ROUNDS`] Newton rounds in a row have not lowered the best
//! residual (an iteration that still decreases, however slowly — plateaus
//! of a few per cent per round before Newton's method locks on are common
//! on piecewise-smooth maps — never stalls). It stops there when the
//! best iterate's residual is within `steady_accept`, which is then
//! accepted and reported with it; otherwise it goes on (the wandering
//! residual may still fall within `steady_accept`) up to `max_iterations`
//! evaluations, and a point whose best residual is still above is
//! [`SteadyFailure::NotConverged`] (a field sample reports it as its
//! validity, `not_converged`).

use nalgebra::Matrix2;
use serde::Serialize;

use super::simulator::Simulator;
use super::state::{PartState, V2};
use super::ContactLoss;

/// A converged steady state.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SteadyState {
    /// Mean velocity over the cycle (m/s), plate frame.
    pub velocity: [f64; 2],
    /// Slip velocity at phase 0 on the periodic orbit (m/s).
    pub start_slip: [f64; 2],
    /// Fraction of the cycle spent stuck.
    pub stick_fraction: f64,
    /// Largest excursion of the part from r₀ during the cycle (m).
    pub excursion: f64,
    /// |P(u) − u| at the returned u (m/s).
    pub residual: f64,
    /// Cycle-map evaluations used.
    pub iterations: usize,
}

/// Why a steady state could not be found.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum SteadyFailure {
    /// The part leaves the plate.
    ContactLoss(ContactLoss),
    /// The fixed-point iteration did not converge.
    NotConverged {
        /// Final |P(u) − u| (m/s).
        residual: f64,
        /// Evaluations used.
        iterations: usize,
    },
}

impl std::fmt::Display for SteadyFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SteadyFailure::ContactLoss(c) => write!(f, "{c}"),
            SteadyFailure::NotConverged {
                residual,
                iterations,
            } => write!(
                f,
                "steady state not converged after {iterations} cycle evaluations (residual {residual:.3e} m/s)"
            ),
        }
    }
}

impl From<ContactLoss> for SteadyFailure {
    fn from(c: ContactLoss) -> Self {
        SteadyFailure::ContactLoss(c)
    }
}

/// Newton rounds without a new best residual after which the iteration
/// has stalled.
pub(crate) const STALL_ROUNDS: usize = 4;

struct CycleResult {
    u_end: V2,
    displacement: V2,
    stuck_time: f64,
    excursion: f64,
}

impl Simulator<'_> {
    fn cycle_from(&self, r0: &V2, u: &V2, track: bool) -> Result<CycleResult, ContactLoss> {
        let mut state = PartState::new(*r0, *u);
        let mut rec = Vec::new();
        let out = self.advance(
            0.0,
            self.period(),
            &mut state,
            r0,
            if track { Some(&mut rec) } else { None },
        )?;
        let excursion = rec
            .iter()
            .map(|p| (p.state.r - r0).norm())
            .fold(0.0, f64::max);
        Ok(CycleResult {
            u_end: out.state.u,
            displacement: out.state.r - r0,
            stuck_time: out.stuck_time,
            excursion,
        })
    }

    /// Steady-state velocity at plate position `r0` (frozen or free as set
    /// by the model's `moving` switch).
    pub fn steady_state(&self, r0: [f64; 2]) -> Result<SteadyState, SteadyFailure> {
        self.steady_from(r0, None)
    }

    /// [`Simulator::steady_state`] continued from a nearby orbit: Newton's
    /// iteration from the slip `guess` at phase 0 (the orbit at a point a
    /// drift of one cycle away), without the plain iterations that bring a
    /// part from rest near its orbit. The same fixed point to
    /// `steady_tol`, on the branch through `guess`.
    pub(crate) fn steady_state_near(
        &self,
        r0: [f64; 2],
        guess: [f64; 2],
    ) -> Result<SteadyState, SteadyFailure> {
        self.steady_from(r0, Some(V2::from(guess)))
    }

    /// The steady state at `r0` from `start` (`None`: from rest, after two
    /// plain iterations of the cycle map).
    fn steady_from(&self, r0: [f64; 2], start: Option<V2>) -> Result<SteadyState, SteadyFailure> {
        let r0 = V2::from(r0);
        let tol = self.numerics().steady_tol * self.velocity_scale();
        let max_it = self.numerics().max_iterations;
        let evals = std::cell::Cell::new(0usize);
        let map = |u: &V2| -> Result<V2, ContactLoss> {
            evals.set(evals.get() + 1);
            Ok(self.cycle_from(&r0, u, false)?.u_end)
        };
        let mut u = start.unwrap_or_else(V2::zeros);
        let mut pu = map(&u)?;
        // From rest, a few plain iterations bring u near the orbit (exactly
        // onto it when the part sticks somewhere in the cycle).
        let plain = if start.is_some() { 0 } else { 2 };
        for _ in 0..plain {
            u = pu;
            pu = map(&u)?;
        }
        let mut residual = (pu - u).norm();
        let delta = 1e-5 * self.velocity_scale();
        let mut best = (u, residual);
        // Newton rounds since the best residual last decreased.
        let mut stalled = 0;
        while residual > tol {
            let acceptable = best.1 <= self.numerics().steady_accept * self.velocity_scale();
            if evals.get() >= max_it || (stalled >= STALL_ROUNDS && acceptable) {
                // Capped or stalled. The cycle map of a 2-D slip is
                // continuous only up to the integrator's error near u = 0;
                // accept the best iterate when its residual is within
                // `steady_accept`, and say so.
                if acceptable {
                    (u, residual) = best;
                    break;
                }
                return Err(SteadyFailure::NotConverged {
                    residual: best.1,
                    iterations: evals.get(),
                });
            }
            let f = pu - u;
            let jx = (map(&(u + V2::new(delta, 0.0)))? - pu) / delta;
            let jy = (map(&(u + V2::new(0.0, delta)))? - pu) / delta;
            let jac = Matrix2::from_columns(&[jx, jy]) - Matrix2::identity();
            let mut next = pu; // plain iteration as a fallback
            if let Some(inv) = jac.try_inverse() {
                let cand = u - inv * f;
                if cand.iter().all(|x| x.is_finite()) {
                    next = cand;
                }
            }
            let mut pn = map(&next)?;
            if (pn - next).norm() >= residual {
                // Newton did not help (a kink between u and the step): iterate.
                next = pu;
                pn = map(&next)?;
            }
            u = next;
            pu = pn;
            residual = (pu - u).norm();
            stalled = if residual < best.1 { 0 } else { stalled + 1 };
            if residual < best.1 {
                best = (u, residual);
            }
        }
        let cycle = self.cycle_from(&r0, &u, true)?;
        let period = self.period();
        Ok(SteadyState {
            velocity: [cycle.displacement.x / period, cycle.displacement.y / period],
            start_slip: [u.x, u.y],
            stick_fraction: (cycle.stuck_time / period).clamp(0.0, 1.0),
            excursion: cycle.excursion,
            residual,
            iterations: evals.get() + 1,
        })
    }

    /// True when the model freezes the position (the frozen variant).
    pub(crate) fn is_frozen(&self) -> bool {
        !self.model().moving
    }
}
