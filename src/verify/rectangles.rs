//! Rectangles played through a schedule: where parts end up and how
//! rectangles orient.
//!
//! `play_rectangle` drives one uniform rectangle (`Rectangle`, simulated
//! by `PlanarSimulator`) through a [`ScheduleMotion`] for a given time:
//! segment after segment, repeating the schedule, each segment in
//! segment-local time from 0 (phase 0), rest segments with the plate at rest
//! in the home pose. The part is placed at rest relative to the plate.
//!
//! **Joins.** At a join from segment A to segment B the plate's in-plane
//! velocity field may jump (it is the rigid planar field v_t(p) = v_t(c) +
//! Ω_z k × (p − c), Ω_z the vertical spin); the part's inertial planar
//! velocity is kept continuous: u_B = u_A + v_A,t(r) − v_B,t(r) at the
//! rectangle's centre r (the anchor for the frozen model) and
//! ω_B = ω_A + Ω_A,z − Ω_B,z. As for point parts ([`crate::play::Player`]) the
//! normal component of a jump is an impact that is not resolved; for the
//! rest-to-rest primitives there is no jump at all.

use serde::Serialize;

use crate::dynamics::{
    Friction, Model, PartPhysics, PlanarSimulator, PlanarState, Plate, Rectangle,
    PLANAR_REFINE_DEPTH, PLANAR_STEPS_PER_CYCLE,
};
use crate::error::{finite, positive, Error, Result};
use crate::field::FieldSettings;
use crate::play::{plate_twist, PlayLoss, ScheduleMotion, V2};

/// Longest time a rectangle may be played (s).
pub(crate) const MAX_DURATION_S: f64 = 3600.0;

/// Settings of a rectangle run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RectangleOptions {
    /// Friction coefficients.
    pub friction: Friction,
    /// Gravity (m/s²).
    pub gravity: f64,
    /// Model switches (default [`Model::FULL`]).
    pub model: Model,
    /// Planar integrator steps per cycle of each segment's motion (rest
    /// segments use the shortest moving segment's step).
    pub steps_per_cycle: usize,
    /// How many times a step holding a stick-slip event may be halved.
    pub refine_depth: u32,
}

impl Default for RectangleOptions {
    fn default() -> Self {
        let s = FieldSettings::default();
        RectangleOptions {
            friction: s.friction,
            gravity: s.gravity,
            model: Model::FULL,
            steps_per_cycle: PLANAR_STEPS_PER_CYCLE,
            refine_depth: PLANAR_REFINE_DEPTH,
        }
    }
}

impl RectangleOptions {
    /// Validates ranges; errors name the field under `field`.
    pub(crate) fn validate(&self, field: &str) -> Result<()> {
        self.friction.validate(&format!("{field}.friction"))?;
        positive(&format!("{field}.gravity"), self.gravity)?;
        if !(1..=1_000_000).contains(&self.steps_per_cycle) {
            return Err(Error::invalid(
                format!("{field}.steps_per_cycle"),
                format!("must be in 1..=1000000, got {}", self.steps_per_cycle),
            ));
        }
        if self.refine_depth > 30 {
            return Err(Error::invalid(
                format!("{field}.refine_depth"),
                format!("must be in 0..=30, got {}", self.refine_depth),
            ));
        }
        Ok(())
    }
}

/// The rectangle's pose at one instant of a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PoseSample {
    /// Time from the start of the run (s).
    pub t: f64,
    /// The segment that just ended (`None` at the start).
    pub segment: Option<usize>,
    /// Centre (m, plate frame).
    pub r: [f64; 2],
    /// Angle of the long (body x) axis from the plate x axis, unwrapped (degrees).
    pub theta_deg: f64,
}

/// A played rectangle.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RectangleRun {
    /// The rectangle.
    pub rectangle: Rectangle,
    /// The start state.
    pub start: PlanarState,
    /// The final state.
    pub state: PlanarState,
    /// Time played (s).
    pub time: f64,
    /// Pose at the start, after every segment and at the end.
    pub trajectory: Vec<PoseSample>,
    /// Integrator steps taken (including refined ones).
    pub steps: u64,
}

/// Serialisable summary of a `RectangleRun`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RectangleSummary {
    /// The rectangle.
    pub rectangle: Rectangle,
    /// Start centre (m).
    pub start: [f64; 2],
    /// Start angle of the long axis (degrees).
    pub start_theta_deg: f64,
    /// Final centre (m).
    pub end: [f64; 2],
    /// Final angle of the long axis, unwrapped (degrees).
    pub end_theta_deg: f64,
    /// Final direction of the long axis folded into (−90°, 90°] (a
    /// rectangle is the same turned by 180°).
    pub end_axis_deg: f64,
    /// Net distance between the start and final centres (m).
    pub displacement_m: f64,
    /// Time played (s).
    pub time_s: f64,
}

impl RectangleRun {
    /// The summary.
    pub(crate) fn summary(&self) -> RectangleSummary {
        RectangleSummary {
            rectangle: self.rectangle,
            start: [self.start.r.x, self.start.r.y],
            start_theta_deg: self.start.theta.to_degrees(),
            end: [self.state.r.x, self.state.r.y],
            end_theta_deg: self.state.theta.to_degrees(),
            end_axis_deg: axis_deg(self.state.theta),
            displacement_m: (self.state.r - self.start.r).norm(),
            time_s: self.time,
        }
    }
}

/// The direction of an axis at angle `theta` (rad) folded into (−90°, 90°].
pub(crate) fn axis_deg(theta: f64) -> f64 {
    let d = theta.to_degrees().rem_euclid(180.0);
    if d > 90.0 {
        d - 180.0
    } else {
        d
    }
}

/// Why a rectangle run failed.
#[derive(Debug, thiserror::Error)]
pub enum RectangleFailure {
    /// Bad input.
    #[error(transparent)]
    Invalid(#[from] Error),
    /// The rectangle left the plate (an edge lifted).
    #[error("{0}")]
    ContactLoss(PlayLoss),
}

impl From<RectangleFailure> for Error {
    fn from(f: RectangleFailure) -> Error {
        match f {
            RectangleFailure::Invalid(e) => e,
            RectangleFailure::ContactLoss(l) => Error::ContactLost(format!("rectangle: {l}")),
        }
    }
}

/// Plays `rect`, placed at rest at pose `start` = (centre, angle in rad),
/// through `sm` for `duration_s` seconds (the schedule repeats; the last
/// segment may be cut short). See the module docs.
pub(crate) fn play_rectangle(
    sm: &ScheduleMotion,
    rect: &Rectangle,
    start: (V2, f64),
    duration_s: f64,
    opts: &RectangleOptions,
) -> Result<RectangleRun, RectangleFailure> {
    rect.validate("rectangle")?;
    opts.validate("rectangle_options")?;
    finite("rectangle.start.x", start.0.x)?;
    finite("rectangle.start.y", start.0.y)?;
    finite("rectangle.start.theta", start.1)?;
    positive("rectangle.duration_s", duration_s)?;
    if duration_s > MAX_DURATION_S {
        return Err(Error::invalid(
            "rectangle.duration_s",
            format!("must be in (0, {MAX_DURATION_S}] s, got {duration_s}"),
        )
        .into());
    }
    let segments = sm.segments();
    let rest_step = segments
        .iter()
        .filter_map(|s| s.motion.as_ref().map(|m| m.period()))
        .fold(f64::INFINITY, f64::min)
        .min(duration_s)
        / opts.steps_per_cycle as f64;
    let sims: Vec<PlanarSimulator> = segments
        .iter()
        .map(|s| {
            let sim = match &s.motion {
                Some(m) => PlanarSimulator::for_motion(
                    rect,
                    m,
                    PartPhysics::new(opts.friction, opts.gravity, opts.model),
                    opts.steps_per_cycle,
                ),
                None => PlanarSimulator::for_body(
                    rect,
                    Plate::Rest,
                    PartPhysics::new(opts.friction, opts.gravity, opts.model),
                    rest_step,
                ),
            };
            sim.with_refinement(opts.refine_depth)
        })
        .collect();
    let mut state = PlanarState::at_rest(start.0, start.1);
    let first = state;
    let anchor = start;
    let sample = |t: f64, segment: Option<usize>, s: &PlanarState| PoseSample {
        t,
        segment,
        r: [s.r.x, s.r.y],
        theta_deg: s.theta.to_degrees(),
    };
    let mut trajectory = vec![sample(0.0, None, &state)];
    let (mut t, mut steps) = (0.0, 0u64);
    let n = segments.len();
    let mut period = 0u32;
    'outer: loop {
        for (i, seg) in segments.iter().enumerate() {
            let left = duration_s - t;
            if left <= 1e-12 * duration_s {
                break 'outer;
            }
            if period > 0 || i > 0 {
                let from = &segments[if i == 0 { n - 1 } else { i - 1 }];
                let p = if opts.model.moving { state.r } else { anchor.0 };
                let (va, wa) = plate_twist(from, opts.gravity, opts.model.tilt, &p);
                let (vb, wb) = plate_twist(seg, opts.gravity, opts.model.tilt, &p);
                state.u += va - vb;
                if rect.is_point() {
                    state.omega = 0.0;
                } else {
                    state.omega += wa - wb;
                }
            }
            let span = seg.duration.min(left);
            let out = sims[i]
                .advance(0.0, span, &mut state, anchor, None)
                .map_err(|loss| {
                    RectangleFailure::ContactLoss(PlayLoss {
                        segment: i,
                        period,
                        loss,
                    })
                })?;
            steps += out.steps;
            t += span;
            trajectory.push(sample(t, Some(i), &state));
        }
        period += 1;
    }
    Ok(RectangleRun {
        rectangle: *rect,
        start: first,
        state,
        time: t,
        trajectory,
        steps,
    })
}
