//! Export of a schedule as the six plate-centre acceleration signals a
//! shaker controller is driven with: translational acceleration of the plate
//! centre along the world x, y, z axes (m/s²) and angular acceleration about
//! them (rad/s²), sampled at a given rate over one schedule period.
//!
//! For a screw primitive {k, h, ψ, d} with R = exp(ψ[k]×) and
//! p = (I − R)h + d k (exact, not small-angle):
//! p'' = −(α × Rh + ω × (ω × Rh)) + d'' k with ω = ψ'k, α = ψ''k, and the
//! angular acceleration is ψ''k. Rest segments are zero. Primitives are
//! rest-to-rest, so the signals are continuous in pose and velocity at joins.
//!
//! The schedule is validated and its period derived from the segments
//! ([`Schedule::derive`]) before anything is sampled, so `export` plays
//! exactly what `verify` plays.

use super::Schedule;
use crate::error::{positive, Error, Result};
use crate::motion::{rotate, sample_hold, Motion, V3};

/// Plate-centre (linear, angular) acceleration of `motion` at time `t`.
pub fn centre_acceleration(motion: &Motion, t: f64) -> (V3, V3) {
    match motion {
        Motion::Screw(s) => {
            let k = V3::from(s.axis).normalize();
            let psi = s.rotation.eval(t, s.period);
            let d = s.translation.eval(t, s.period);
            let rh = rotate(&V3::from(s.point), &k, psi.q);
            let (w, a) = (k * psi.dq, k * psi.ddq);
            let lin = -(a.cross(&rh) + w.cross(&w.cross(&rh))) + k * d.ddq;
            (lin, a)
        }
        Motion::Signals(sig) => {
            let kin = sig.kinematics(t, 0.0, false);
            (kin.accel_center, kin.alpha)
        }
    }
}

/// CSV of the six signals over one schedule period at (about) `rate`
/// samples/s, as a sample-and-hold controller plays them
/// ([`crate::motion::sample_hold::sequence`]): each sample is the mean
/// acceleration over its interval, Δt = T₀/round(rate·T₀) with T₀ the
/// primitives' period, and every join and the period end fall on sample
/// boundaries, so the plate integrated from the file returns to rest in the
/// home pose every period (to round-off), where point samples drift.
pub fn signals_csv(schedule: &Schedule, rate: f64) -> Result<String> {
    positive("--rate", rate)?;
    schedule.validate()?;
    let schedule = &schedule.with_segments(schedule.segments.clone());
    if schedule.period_s * rate > 5e7 {
        return Err(Error::invalid(
            "--rate",
            format!(
                "{rate} Hz over a {:.3} s schedule is more than 5e7 samples",
                schedule.period_s
            ),
        ));
    }
    let motions: Vec<Option<Motion>> = schedule
        .segments
        .iter()
        .map(|s| s.primitive.as_ref().map(|p| p.motion()))
        .collect();
    let segments: Vec<sample_hold::Segment<'_>> = schedule
        .segments
        .iter()
        .zip(&motions)
        .map(|(s, m)| sample_hold::Segment {
            motion: m.as_ref(),
            duration: s.duration_s,
        })
        .collect();
    Ok(sample_hold::sequence(&segments, rate)?.to_csv())
}
