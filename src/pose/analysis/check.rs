//! The lifted field checked against the planar simulation: a part placed
//! at rest at a pose on a vibrating plate, played by
//! [`PlanarSimulator`] for a warm-up and then a measured window of whole
//! cycles; its measured twist is the change of pose over the window
//! divided by its length, compared with the lifted field at the window's
//! mean pose.

use crate::dynamics::{ContactLoss, PartPhysics, PlanarBody, PlanarSimulator, PlanarState, Plate};
use crate::motion::Motion;

use super::lifted::{LiftedField, Pose, Twist};

/// How a part is played to measure its twist.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measure {
    /// Cycles played before the window (the start-up transient).
    pub warm_up: u32,
    /// Cycles in the window.
    pub cycles: u32,
    /// Planar integrator steps per cycle.
    pub steps_per_cycle: usize,
}

/// One pose's simulated and predicted twists.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwistCheck {
    /// The window's mean pose.
    pub pose: Pose,
    /// Measured by the planar simulation.
    pub simulated: Twist,
    /// Predicted by the lifted field at `pose`.
    pub predicted: Twist,
}

/// Plays `body` from rest at `start` on `motion` and measures its mean
/// twist over the window (module docs); `lifted` gives the prediction.
pub fn check_twist(
    lifted: &LiftedField<'_>,
    body: &PlanarBody,
    motion: &Motion,
    physics: PartPhysics,
    start: Pose,
    measure: &Measure,
) -> Result<TwistCheck, ContactLoss> {
    let sim = PlanarSimulator::for_body(
        body.clone(),
        Plate::Moving(motion),
        physics,
        motion.period() / measure.steps_per_cycle as f64,
    );
    let t = motion.period();
    let mut s = PlanarState::at_rest(start.r, start.theta);
    let anchor = (start.r, start.theta);
    let t0 = t * f64::from(measure.warm_up);
    sim.advance(0.0, t0, &mut s, anchor, None)?;
    let a = s;
    let t1 = t0 + t * f64::from(measure.cycles);
    sim.advance(t0, t1, &mut s, anchor, None)?;
    let span = t1 - t0;
    let pose = Pose {
        r: (a.r + s.r) * 0.5,
        theta: 0.5 * (a.theta + s.theta),
    };
    Ok(TwistCheck {
        pose,
        simulated: Twist {
            v: (s.r - a.r) / span,
            omega: (s.theta - a.theta) / span,
        },
        predicted: lifted.twist(pose),
    })
}
