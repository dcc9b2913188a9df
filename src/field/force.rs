//! The zero-velocity force field at one point.

use nalgebra::Vector2;

use super::Validity;
use crate::dynamics::{PartState, Simulator};
use crate::motion::{Kinematics, V3};

/// The plate kinematics at the start t₀ = T j/`phases` and end t₀ + T of
/// each start phase j: they depend on time only, so a field evaluates them
/// once for all its points.
pub(crate) fn phase_frames(sim: &Simulator<'_>, phases: usize) -> Vec<(Kinematics, Kinematics)> {
    let period = sim.period();
    let at = |t: f64| sim.motion().kinematics(t, sim.gravity(), sim.model().tilt);
    (0..phases)
        .map(|j| {
            let t0 = period * j as f64 / phases as f64;
            (at(t0), at(t0 + period))
        })
        .collect()
}

/// Mean over the start phases of `frames` ([`phase_frames`]) of (inertial
/// velocity change)/T for a part released at rest in the inertial frame at
/// `p`.
pub(crate) fn sample(
    sim: &Simulator<'_>,
    p: [f64; 2],
    frames: &[(Kinematics, Kinematics)],
) -> ([f64; 2], Validity) {
    let period = sim.period();
    let phases = frames.len();
    let anchor = Vector2::from(p);
    let plate_velocity = |k: &Kinematics, r: &Vector2<f64>| {
        let q = if sim.model().moving { r } else { &anchor };
        let v = k.velocity_at(&V3::new(q.x, q.y, 0.0));
        Vector2::new(v.x, v.y)
    };
    let mut sum = Vector2::zeros();
    for (j, (start, end)) in frames.iter().enumerate() {
        let t0 = period * j as f64 / phases as f64;
        let mut state = PartState::new(anchor, -plate_velocity(start, &anchor));
        if sim
            .advance(t0, t0 + period, &mut state, &anchor, None)
            .is_err()
        {
            return ([0.0, 0.0], Validity::ContactLost);
        }
        // Periodic motion: the frame at t0 + T is the frame at t0.
        let v_end = plate_velocity(end, &state.r) + state.u;
        sum += v_end / period;
    }
    let f = sum / phases as f64;
    ([f.x, f.y], Validity::Ok)
}
