//! The zero-velocity force field at one point.

use nalgebra::Vector2;

use super::Validity;
use crate::dynamics::{PartState, Simulator};
use crate::motion::V3;

/// Mean over `phases` start phases of (inertial velocity change)/T for a
/// part released at rest in the inertial frame at `p`.
pub fn sample(sim: &Simulator<'_>, p: [f64; 2], phases: usize) -> ([f64; 2], Validity) {
    let period = sim.period();
    let anchor = Vector2::from(p);
    let plate_velocity = |t: f64, r: &Vector2<f64>| {
        let k = sim.motion().kinematics(t, sim.gravity(), sim.model().tilt);
        let q = if sim.model().moving { r } else { &anchor };
        let v = k.velocity_at(&V3::new(q.x, q.y, 0.0));
        Vector2::new(v.x, v.y)
    };
    let mut sum = Vector2::zeros();
    for j in 0..phases {
        let t0 = period * j as f64 / phases as f64;
        let mut state = PartState::new(anchor, -plate_velocity(t0, &anchor));
        if sim
            .advance(t0, t0 + period, &mut state, &anchor, None)
            .is_err()
        {
            return ([0.0, 0.0], Validity::ContactLost);
        }
        // Periodic motion: the frame at t0 + T is the frame at t0.
        let v_end = plate_velocity(t0 + period, &state.r) + state.u;
        sum += v_end / period;
    }
    let f = sum / phases as f64;
    ([f.x, f.y], Validity::Ok)
}
