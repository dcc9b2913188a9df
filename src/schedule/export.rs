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

use std::fmt::Write as _;

use super::Schedule;
use crate::error::{positive, Error, Result};
use crate::motion::{rotate, Motion, V3};

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

/// CSV of the six signals over one schedule period at `rate` samples/s.
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
    let mut csv =
        String::from("t_s,ax_m_s2,ay_m_s2,az_m_s2,alpha_x_rad_s2,alpha_y_rad_s2,alpha_z_rad_s2\n");
    let n = (schedule.period_s * rate).round() as u64;
    // Segment start times.
    let mut starts = Vec::new();
    let mut t0 = 0.0;
    for seg in &schedule.segments {
        starts.push(t0);
        t0 += seg.duration_s;
    }
    let motions: Vec<Option<Motion>> = schedule
        .segments
        .iter()
        .map(|s| s.primitive.as_ref().map(|p| p.motion()))
        .collect();
    let mut seg = 0;
    for i in 0..n {
        let t = i as f64 / rate;
        while seg + 1 < starts.len() && t >= starts[seg + 1] {
            seg += 1;
        }
        let (lin, ang) = match &motions[seg] {
            Some(m) => centre_acceleration(m, t - starts[seg]),
            None => (V3::zeros(), V3::zeros()),
        };
        let _ = writeln!(
            csv,
            "{t:.7},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}",
            lin.x, lin.y, lin.z, ang.x, ang.y, ang.z
        );
    }
    Ok(csv)
}
