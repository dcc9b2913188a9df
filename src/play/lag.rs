//! Drift lag: the mean velocity of a part that *moves* under one periodic
//! motion, against the steady state at a fixed point.
//!
//! [`crate::dynamics::Simulator::steady_state`] at r is the periodic orbit
//! of the cycle map with the part put back at r every cycle: slip u*(r) at
//! phase 0, mean velocity F(r). A part played for many cycles is not put
//! back: it drifts by d = F T per cycle, and its slip at phase 0 chases an
//! orbit that moves with it. With e_k = u_k − u*(r_k) its lag behind the
//! orbit through its own position, linearising the cycle map P(r, u) at the
//! fixed point (J = ∂u_end/∂u, D = ∂r_end/∂u, G = ∂u*/∂r):
//!
//! ```text
//! e_{k+1} = J e_k − G d            ⇒   e = −(I − J)⁻¹ G d     (steady lag)
//! v       = F + D e / T                                       (its mean velocity)
//! ```
//!
//! first order in the drift per cycle. G d is taken as u*(r + d) − u*(r)
//! (one more steady state), J and D by finite differences of one cycle from
//! u* (three cycles). The lag is small in the slip (a fraction of a per
//! cent of |u*| for the lab-class sink) but the mean velocity is a small
//! difference of large slips, and where friction's direction turns with
//! the slip (circular translation) J is close to a rotation, (I − J)⁻¹
//! large: the lab-class sink's parts realise a few per cent more than F
//! over one cycle, and a small fraction of that against the corrected v
//! (measured: `platefield study probes`, `results/probes.md`). This is physics
//! (a moving part is not on the fixed point's orbit), not an artefact of
//! the measure: it is there over one cycle, at every warm-up.
//!
//! It applies where one motion plays without joins (a one-segment schedule:
//! a synthesized motion, or one primitive played alone): in a sequence each
//! segment plays a few cycles from the state the previous one left, and
//! the join transients are not this steady lag.

use nalgebra::Matrix2;

use super::V2;
use crate::dynamics::{PartState, Simulator, SteadyFailure, SteadyState};

/// Relative size of the slip perturbation for J and D (of max(|u*|, the
/// simulator's velocity scale)).
pub(crate) const SLIP_STEP: f64 = 1e-5;

/// The lag-corrected mean velocity of a part drifting through `r` under
/// `sim`'s motion (with moving kinematics), given the steady state `ss` at
/// `r` (see the module documentation).
///
/// # Errors
/// Contact lost on a cycle; the steady state at r + d failing; I − J
/// singular (the orbit does not attract: no steady lag), as
/// [`SteadyFailure::NotConverged`] with the steady state's residual.
pub fn lagged_velocity(
    sim: &Simulator<'_>,
    r: [f64; 2],
    ss: &SteadyState,
) -> Result<[f64; 2], SteadyFailure> {
    lagged(sim, r, ss, |p| sim.steady_state(p))
}

/// [`lagged_velocity`] with the steady state at r + d continued from the
/// orbit at r ([`Simulator::steady_state_near`]: Newton's iteration from
/// u*(r), about half the cycle maps of a start from rest). The same lag to
/// the steady state's tolerance where the orbit at r + d is the
/// continuation of the one at r, as the lag's linearisation assumes.
///
/// # Errors
/// As [`lagged_velocity`].
pub(crate) fn lagged_velocity_continued(
    sim: &Simulator<'_>,
    r: [f64; 2],
    ss: &SteadyState,
) -> Result<[f64; 2], SteadyFailure> {
    lagged(sim, r, ss, |p| sim.steady_state_near(p, ss.start_slip))
}

/// The lag-corrected velocity, the steady state at r + d by `ahead`.
fn lagged(
    sim: &Simulator<'_>,
    r: [f64; 2],
    ss: &SteadyState,
    ahead: impl Fn([f64; 2]) -> Result<SteadyState, SteadyFailure>,
) -> Result<[f64; 2], SteadyFailure> {
    let t = sim.period();
    let r0 = V2::from(r);
    let f = V2::from(ss.velocity);
    let ustar = V2::from(ss.start_slip);
    let d = f * t;
    let ahead = ahead([r0.x + d.x, r0.y + d.y])?;
    let gd = V2::from(ahead.start_slip) - ustar;
    let cycle = |u: V2| -> Result<(V2, V2), SteadyFailure> {
        let mut s = PartState::new(r0, u);
        sim.advance(0.0, t, &mut s, &r0, None)?;
        Ok((s.r, s.u))
    };
    let h = SLIP_STEP * ustar.norm().max(sim.velocity_scale());
    let (rb, ub) = cycle(ustar)?;
    let mut j = Matrix2::zeros();
    let mut dm = Matrix2::zeros();
    for c in 0..2 {
        let mut du = V2::zeros();
        du[c] = h;
        let (rp, up) = cycle(ustar + du)?;
        j.set_column(c, &((up - ub) / h));
        dm.set_column(c, &((rp - rb) / h));
    }
    let inv = (Matrix2::identity() - j)
        .try_inverse()
        .filter(|m| m.iter().all(|x| x.is_finite()))
        .ok_or(SteadyFailure::NotConverged {
            residual: ss.residual,
            iterations: ss.iterations,
        })?;
    let e = -(inv * gd);
    let v = f + dm * e / t;
    Ok([v.x, v.y])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{Numerics, PartPhysics};
    use crate::schedule::Schedule;

    /// The steady state a drift ahead continued from the orbit at r is the
    /// one from rest to the steady state's tolerance (the lag within
    /// 1e-10 m/s, against velocities of millimetres to centimetres per
    /// second), in at most two thirds of the cycle maps over the points:
    /// on the shipped squeeze_trans motion at
    /// μ 0.23, 25 points over ±3 cm.
    #[test]
    fn a_continued_steady_state_is_the_one_from_rest() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/results/squeeze_trans/schedule.json"
        );
        let schedule = Schedule::load(std::path::Path::new(path)).expect("a shipped schedule");
        let motion = schedule.segments[0]
            .steady_motion()
            .expect("a moving segment");
        let sim = Simulator::new(&motion, PartPhysics::full(0.23), Numerics::default());
        let (mut cold_maps, mut warm_maps) = (0, 0);
        for i in 0..5 {
            for j in 0..5 {
                let r = [-0.03 + 0.015 * f64::from(i), -0.03 + 0.015 * f64::from(j)];
                let ss = sim.steady_state(r).expect("a steady state");
                let d = [ss.velocity[0] * sim.period(), ss.velocity[1] * sim.period()];
                let ahead = [r[0] + d[0], r[1] + d[1]];
                let cold = sim.steady_state(ahead).expect("from rest");
                let warm = sim
                    .steady_state_near(ahead, ss.start_slip)
                    .expect("continued");
                cold_maps += cold.iterations;
                warm_maps += warm.iterations;
                let a = lagged_velocity(&sim, r, &ss).expect("lag");
                let b = lagged_velocity_continued(&sim, r, &ss).expect("lag");
                for k in 0..2 {
                    assert!((a[k] - b[k]).abs() <= 1e-10, "{r:?}: {a:?} {b:?}");
                }
            }
        }
        assert!(
            3 * warm_maps <= 2 * cold_maps,
            "{warm_maps} against {cold_maps}"
        );
    }
}
