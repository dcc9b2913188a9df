//! Point-part dynamics on the vibrating plate, with exact Coulomb stick-slip.
//!
//! State: plate-frame position r and relative (slip) velocity u = dr/dt, both
//! in the plate plane. With Ω the plate's angular velocity, a_s(r) its
//! acceleration at r and g_S gravity in the plate frame (see [`crate::motion`]),
//! Newton's law for a unit-mass part in the inertial frame S' momentarily
//! aligned with the plate gives
//!
//! ```text
//! N      = a_s,z(r) + (2 Ω × u)_z − g_S,z          normal force ("effective gravity")
//! a_free = g_S,t − a_s,t(r) − (2 Ω × u)_t           tangential, without friction
//! slipping (u ≠ 0):  du/dt = a_free − μ_k N u/|u|
//! stuck    (u = 0):  stays stuck while |a_free| ≤ μ_s N,
//!                    else slips with du/dt = a_free − μ_k N a_free/|a_free|
//! ```
//!
//! N < 0 means the part leaves the plate: it is reported as
//! [`ContactLoss`] (where and when), unless the simulator follows parts
//! through flight ([`Simulator::with_flight`], [`Simulator::advance_flying`]:
//! ballistic flight in the world frame, the landing as an event, an
//! inelastic or partly elastic impact with Coulomb friction; the model is
//! stated in `src/dynamics/flight.rs`).
//!
//! Terms the paper's closed form drops are switches in [`Model`]: the
//! centripetal part of a_s, the gravity tilt of g_S, the Coriolis term 2Ω×u,
//! and the part moving during the cycle (kinematics evaluated at the current
//! position rather than frozen at the start).
//!
//! Planar parts (a uniform rectangle in x, y, θ sampled by support points,
//! each obeying these equations) are in `PlanarSimulator`.

mod flight;
mod frozen;
mod integrator;
mod kinematics_table;
mod planar;
mod radau;
mod scheme;
mod simulator;
mod state;
mod steady;
mod swing;

pub use flight::Flight;
#[cfg(test)]
pub(crate) use flight::Hop;
pub use flight::{PartPhase, HELD_MAX_PERIODS, HELD_MIN_PERIODS, HELD_TOL};
pub use simulator::Simulator;
#[cfg(test)]
pub(crate) use state::CycleOutcome;
pub use state::PartState;
#[cfg(test)]
pub(crate) use state::TrajectoryPoint;
pub use state::V2;

/// Revision of the simulator's numerics: bumped whenever a change to the
/// integrator changes any field it computes (not for changes that keep
/// every field bitwise). Cached libraries are keyed by it
/// (`crate::basis::cache`), so a library built by an earlier engine is
/// rebuilt, not reused. What each revision changed is listed in the
/// workspace's `CHANGELOG.md`.
pub(crate) const ENGINE_REVISION: u32 = 14;
pub(crate) use kinematics_table::KinematicsTable;
pub use planar::PlanarBody;
pub(crate) use planar::PlanarOutcome;
#[cfg(test)]
pub(crate) use planar::PlanarSample;
pub(crate) use planar::PlanarSimulator;
pub(crate) use planar::PlanarState;
pub(crate) use planar::Rectangle;
pub use planar::{
    Plate, SlipRule, MAX_POINTS_PER_SIDE, PLANAR_REFINE_DEPTH, PLANAR_STEPS_PER_CYCLE,
    REFINE_CHANGE,
};
pub use steady::SteadyFailure;
pub use steady::SteadyState;

use serde::{Deserialize, Serialize};

use crate::error::{non_negative, Error, Result};
use crate::motion::{Kinematics, V3};

/// Nominal RK4 steps of point parts taken since the program started: the
/// unit of [`crate::work`]'s estimates, counted where the engine takes
/// them ([`Simulator::advance`]: every fixed step of nominal size
/// period / steps per cycle, whatever its events split it into), so an
/// estimate can be compared with the work done. A relaxed
/// atomic added once per smooth piece; never part of a result.
static STEPS_TAKEN: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// The nominal point-part steps taken so far by this process (see
/// `STEPS_TAKEN`); the difference of two readings is the work done between
/// them (by every thread).
///
/// ```
/// let before = platefield::dynamics::steps_taken();
/// assert!(platefield::dynamics::steps_taken() >= before);
/// ```
pub fn steps_taken() -> u64 {
    STEPS_TAKEN.load(std::sync::atomic::Ordering::Relaxed)
}

/// Adds `n` nominal steps to [`steps_taken`].
#[inline]
pub(crate) fn count_steps(n: usize) {
    STEPS_TAKEN.fetch_add(n as u64, std::sync::atomic::Ordering::Relaxed);
}

/// The times t0 < … < t1 that split [t0, t1] at the acceleration
/// `breakpoints` (times in [0, `period`), repeated every period), so that no
/// integration step straddles a jump.
pub(crate) fn piece_edges(t0: f64, t1: f64, period: f64, breakpoints: &[f64]) -> Vec<f64> {
    let mut edges = vec![t0];
    if !breakpoints.is_empty() {
        let first = (t0 / period).floor() as i64;
        let last = (t1 / period).ceil() as i64;
        for c in first..=last {
            for b in breakpoints {
                let tb = b + c as f64 * period;
                if tb > t0 + 1e-12 * period && tb < t1 - 1e-12 * period {
                    edges.push(tb);
                }
            }
        }
    }
    edges.push(t1);
    edges.sort_by(f64::total_cmp);
    edges
}

/// Number of fixed steps of nominal size `nominal` (at most) on the smooth
/// piece [a, b].
#[inline]
pub(crate) fn step_count(a: f64, b: f64, nominal: f64) -> usize {
    ((b - a) / nominal - 1e-9).ceil().max(1.0) as usize
}

/// End of fixed step `i` (1 ≤ i ≤ n) of the n equal steps over [a, b]
/// (exactly b for the last). [`KinematicsTable`] tabulates the instants of
/// these steps with the same arithmetic.
#[inline]
pub(crate) fn step_end(a: f64, b: f64, n: usize, i: usize) -> f64 {
    if i == n {
        b
    } else {
        a + (b - a) * i as f64 / n as f64
    }
}

/// A named model, as chosen on the command line (`--model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Preset {
    /// [`Model::PAPER`]: the paper's analysis.
    Paper,
    /// [`Model::FULL`]: everything on.
    Full,
    /// [`Model::FROZEN`]: everything on, positions frozen.
    Frozen,
}

impl Preset {
    /// The model this preset names.
    pub fn model(self) -> Model {
        match self {
            Preset::Paper => Model::PAPER,
            Preset::Full => Model::FULL,
            Preset::Frozen => Model::FROZEN,
        }
    }
}

/// Which physical terms are modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// Centripetal acceleration Ω × (Ω × (r − c)).
    pub centripetal: bool,
    /// Gravity tilted into the plate frame by the plate's rotation.
    pub tilt: bool,
    /// Coriolis acceleration 2 Ω × u (normal and tangential parts).
    pub coriolis: bool,
    /// The part moves during the cycle (kinematics at the current
    /// position); off = position frozen in the plate kinematics.
    pub moving: bool,
}

impl Model {
    /// The paper's analysis: small angle, no centripetal, tilt or Coriolis
    /// terms, position frozen in the kinematics.
    pub const PAPER: Model = Model {
        centripetal: false,
        tilt: false,
        coriolis: false,
        moving: false,
    };
    /// Everything on.
    pub const FULL: Model = Model {
        centripetal: true,
        tilt: true,
        coriolis: true,
        moving: true,
    };
    /// Everything on but `moving`: the kinematics held at the part's start
    /// point (the local field). Exact for comparing realised and predicted
    /// fields when parts drift far over a schedule period.
    pub const FROZEN: Model = Model {
        moving: false,
        ..Model::FULL
    };

    /// Normal force per unit mass N and frictionless tangential acceleration
    /// a_free (the equations above) of a point at plate point `p` slipping
    /// with velocity `u`, under these switches (`moving` is the caller's:
    /// `p` is wherever the kinematics are evaluated).
    #[inline]
    pub(crate) fn point_forces(&self, k: &Kinematics, p: &V3, u: &V2) -> (f64, V2) {
        let a = k.acceleration_at(p, self.centripetal);
        let mut n = a.z - k.gravity.z;
        let mut free = V2::new(k.gravity.x - a.x, k.gravity.y - a.y);
        if self.coriolis {
            let c = 2.0 * k.omega.cross(&V3::new(u.x, u.y, 0.0));
            n += c.z;
            free -= V2::new(c.x, c.y);
        }
        (n, free)
    }

    /// Short name: `paper`, `full`, or the list of switches that are on.
    pub fn name(&self) -> String {
        if *self == Model::PAPER {
            return "paper".into();
        }
        if *self == Model::FULL {
            return "full".into();
        }
        let on: Vec<&str> = [
            ("centripetal", self.centripetal),
            ("tilt", self.tilt),
            ("coriolis", self.coriolis),
            ("moving", self.moving),
        ]
        .iter()
        .filter(|(_, b)| *b)
        .map(|(n, _)| *n)
        .collect();
        if on.is_empty() {
            "paper".into()
        } else {
            format!("paper+{}", on.join("+"))
        }
    }
}

/// Coulomb friction coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Friction {
    /// Static coefficient μ_s (break-away threshold).
    #[serde(rename = "static")]
    pub stat: f64,
    /// Kinetic coefficient μ_k.
    pub kinetic: f64,
}

impl Friction {
    /// Equal static and kinetic coefficients μ.
    pub fn uniform(mu: f64) -> Friction {
        Friction {
            stat: mu,
            kinetic: mu,
        }
    }

    /// Validates: 0 ≤ μ_k ≤ μ_s, both finite.
    pub fn validate(&self, field: &str) -> Result<()> {
        non_negative(&format!("{field}.static"), self.stat)?;
        non_negative(&format!("{field}.kinetic"), self.kinetic)?;
        if self.kinetic > self.stat {
            return Err(Error::invalid(
                format!("{field}.static"),
                format!(
                    "must be ≥ the kinetic coefficient {} (got {})",
                    crate::input::num(self.kinetic),
                    crate::input::num(self.stat)
                ),
            ));
        }
        Ok(())
    }
}

/// The physics a part is played under: its Coulomb friction with the
/// plate, the gravity g (m/s²) that presses it onto the plate, and which
/// physical terms are modelled. The three go together wherever a part is
/// played; both simulators ([`Simulator`], `PlanarSimulator`) take them
/// as one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartPhysics {
    /// Friction coefficients.
    pub friction: Friction,
    /// Gravity (m/s²).
    pub gravity: f64,
    /// Model switches.
    pub model: Model,
}

impl PartPhysics {
    /// The physics of these three.
    pub fn new(friction: Friction, gravity: f64, model: Model) -> PartPhysics {
        PartPhysics {
            friction,
            gravity,
            model,
        }
    }

    /// Friction μ (static = kinetic) under g = 9.81 m/s² with every term
    /// modelled ([`Model::FULL`]).
    ///
    /// ```
    /// use platefield::dynamics::{Friction, Model, PartPhysics};
    /// let c = PartPhysics::full(0.3);
    /// assert_eq!((c.friction, c.gravity, c.model), (Friction::uniform(0.3), 9.81, Model::FULL));
    /// ```
    pub fn full(mu: f64) -> PartPhysics {
        PartPhysics::new(Friction::uniform(mu), 9.81, Model::FULL)
    }
}

/// Fewest RK4 steps per cycle any field is integrated with: below it a
/// field is tens of per cent off or worse, and a single step loses contact
/// where none is lost (measured: `docs/dev/forward-model.md`, **Measurements behind the
/// integrator's constants**).
/// 8 is the lowest rung of the library's calibrated ladder
/// ([`crate::basis::steps::LADDER`]), where some primitives' force fields
/// still meet their tolerance.
pub(crate) const MIN_STEPS_PER_CYCLE: usize = 8;

/// Fewest RK4 steps per period of a motion's highest harmonic (the steps
/// per cycle must be at least this times the harmonic number): at 8 steps
/// per harmonic period the field is within a few per cent of a fine run
/// whatever the harmonic, at 4 it is tens of per cent off (measured:
/// `tests/unit/inputs.rs`, `harmonics_against_steps`, and `docs/dev/forward-model.md`,
/// **Measurements behind the integrator's constants**).
pub const STEPS_PER_HARMONIC: usize = 8;

/// Numerical settings of the integrator.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Numerics {
    /// RK4 steps per cycle (spread over the smooth pieces between
    /// acceleration breakpoints).
    pub steps_per_cycle: usize,
    /// Relative tolerance (of the period) for locating stick and slip events.
    pub event_tol: f64,
    /// Convergence tolerance of the steady-state fixed point, relative to
    /// the velocity scale μ_k g T.
    pub steady_tol: f64,
    /// A steady state whose fixed-point residual stalls above `steady_tol`
    /// (2-D slips, whose cycle map is continuous only to the integrator's
    /// error) is accepted when its best residual is within this, relative
    /// to μ_k g T; the residual is reported with it.
    pub steady_accept: f64,
    /// Maximum cycle-map evaluations for the steady state (it stops
    /// earlier when the iteration stalls with an acceptable residual; see
    /// the steady-state module).
    pub max_iterations: usize,
    /// How a 2-D slip velocity is followed near u = 0.
    pub slip: SlipScheme,
}

/// How the integrator follows a 2-D slip velocity near u = 0
/// (`src/dynamics/integrator.rs`, `src/dynamics/swing.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SlipScheme {
    /// Shortened RK4 steps through a swing past u = 0 (converges at about
    /// first order in 2-D).
    Legacy,
    /// Implicit Radau IIA steps where the slip direction is stiff and the
    /// slip speeds up (from rest, after a swing past u = 0): see
    /// `src/dynamics/radau.rs`.
    Stiff,
    /// As [`SlipScheme::Stiff`], with a 2-D swing past u = 0 followed in
    /// regularised time dτ = dt/|u| (`src/dynamics/swing.rs`); the default.
    #[default]
    Regularised,
}

impl Default for Numerics {
    fn default() -> Self {
        Numerics {
            steps_per_cycle: 64,
            event_tol: 1e-14,
            steady_tol: 1e-11,
            steady_accept: 1e-4,
            max_iterations: 200,
            slip: SlipScheme::default(),
        }
    }
}

impl Numerics {
    /// Validates ranges.
    pub fn validate(&self, field: &str) -> Result<()> {
        if !(MIN_STEPS_PER_CYCLE..=1_000_000).contains(&self.steps_per_cycle) {
            return Err(Error::invalid(
                format!("{field}.steps_per_cycle"),
                format!(
                    "must be in {MIN_STEPS_PER_CYCLE}..=1000000, got {} (fewer steps than {MIN_STEPS_PER_CYCLE} per cycle leave the field off by more than 6 %)",
                    self.steps_per_cycle
                ),
            ));
        }
        for (name, v) in [
            ("event_tol", self.event_tol),
            ("steady_tol", self.steady_tol),
            ("steady_accept", self.steady_accept),
        ] {
            if !(v > 0.0 && v < 1.0) {
                return Err(Error::invalid(
                    format!("{field}.{name}"),
                    format!("must be in (0, 1), got {}", crate::input::num(v)),
                ));
            }
        }
        if self.max_iterations == 0 {
            return Err(Error::invalid(
                format!("{field}.max_iterations"),
                "must be ≥ 1",
            ));
        }
        Ok(())
    }
}

/// Where and when a part lost contact with the plate (N < 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactLoss {
    /// Plate-frame position (m).
    pub position: [f64; 2],
    /// Time (s).
    pub time: f64,
    /// Cycle index (time / T, floored).
    pub cycle: u64,
    /// Phase within the cycle, in [0, 1).
    pub phase: f64,
    /// The (negative) normal force per unit mass found (m/s²).
    pub normal: f64,
}

impl std::fmt::Display for ContactLoss {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "part leaves the plate (N = {:.4} m/s² < 0) at ({:.5}, {:.5}) m, t = {:.6} s (cycle {}, phase {:.4})",
            self.normal, self.position[0], self.position[1], self.time, self.cycle, self.phase
        )
    }
}
