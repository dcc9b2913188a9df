//! The part's state and the state of one integration step, shared by the
//! simulator's files (the bottom of their one-way imports:
//! `state` ← `simulator` ← `radau` ← `swing` ← `scheme` ← `integrator`).

use nalgebra::Vector2;

/// 2-vector of f64.
pub type V2 = Vector2<f64>;

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

impl CycleOutcome {
    /// Nothing simulated yet: the part in `state`, no stuck time, events
    /// or RK4 steps.
    pub(crate) fn starting(state: PartState) -> CycleOutcome {
        CycleOutcome {
            state,
            stuck_time: 0.0,
            events: 0,
            rk4_steps: 0,
        }
    }
}
/// Where the integration of one fixed step stands: the time reached `t`,
/// the fixed step's end `target`, the key `piece` of the smooth piece it
/// lies on, the part's `state`, the point `anchor` at which the kinematics
/// are evaluated when the model's `moving` switch is off, and the tally
/// `out` of events and RK4 steps. Every stage of the stick-slip integrator
/// (explicit steps, stop location, implicit and τ-steps) advances it.
#[derive(Debug)]
pub(super) struct Step<'s> {
    /// Time reached (s).
    pub(super) t: f64,
    /// End of the fixed step (s).
    pub(super) target: f64,
    /// Key of the smooth piece (its midpoint; see `Motion::kinematics_piece`).
    pub(super) piece: f64,
    /// Where the kinematics are frozen when the part's position is not used.
    pub(super) anchor: &'s V2,
    /// The part.
    pub(super) state: &'s mut PartState,
    /// Events, stuck time and RK4 steps so far.
    pub(super) out: &'s mut CycleOutcome,
}

impl Step<'_> {
    /// The time `t`, or the fixed step's end if `t` is within `tiny` of it
    /// (an event that close to the end is taken as at the end).
    #[inline]
    pub(super) fn snapped(&self, t: f64, tiny: f64) -> f64 {
        if self.target - t <= tiny {
            self.target
        } else {
            t
        }
    }
}
