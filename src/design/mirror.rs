//! Mirror-image time-share: a synthesized motion played alternately with
//! its mirror image, a design that holds its shape over the parts'
//! friction.
//!
//! **Why a synthesized field turns with friction.** A part slips against
//! the plate in the direction that leads the plate velocity by about
//! δ = asin(μg/A) (A the in-plane acceleration amplitude), so a motion
//! synthesized for one μ makes, at another, its field turned by the change
//! in δ: the synthesized sink gains swirl (measured: 4.7 % shape error at
//! μ 0.3, 16.7 % at 0.2 and 14.6 % at 0.4).
//!
//! **Why the mirror image cancels it.** Let M = diag(1, −1, 1) reflect the
//! world in the vertical plane y = 0. The mirror motion
//! ([`crate::motion::Signals::mirrored_y`]) moves a part at (x, −y) as the
//! mirror image of a part at (x, y) under the original, *at every friction*
//! (gravity and Coulomb's law are unchanged by the reflection), so its
//! field is F′(x, y) = (Fx(x, −y), −Fy(x, −y)). Playing the two for equal
//! time makes the time-weighted field ½(F + F′), which is symmetric under
//! the reflection whatever μ is. Every field splits into a symmetric and an
//! antisymmetric part; a swirl J q is antisymmetric (the reflection
//! reverses rotation). So for a target that is itself symmetric
//! ([`mirror_symmetric`]: a sink, a saddle or a squeeze line along x, not a
//! whirlpool) the time-share keeps the part of F that the target can use
//! and removes, at every friction, the swirl a friction error adds — to the
//! extent that sequencing combines fields (the joins' interaction, see the
//! crate docs).
//!
//! **Its schedule.** Two six-signal segments of [`MIRROR_SEGMENT_CYCLES`]
//! cycles each, the motion and its mirror, each ramped in from rest and out
//! to rest over [`MIXED_RAMP_CYCLES`] cycles (the
//! plate velocities of the two motions differ at a cycle's start, so they
//! cannot be joined directly). Measured for the synthesized sink, worst
//! over μ ∈ [0.2, 0.4] (the design's realised check, moving parts): 8
//! steady-plus-ramp cycles per segment 7.1 % at 0.22 s⁻¹, 12: 4.3 % at
//! 0.39, 20: 3.1 % at 0.55, 28: 3.5 % at 0.62, 36: 4.6 % at 0.66 —
//! longer segments lose less to the ramps and gain back some interaction;
//! 28 is the knee. The ramps raise the acceleration above the steady peak
//! (up to about 16 %); where that passes a shaker limit, the motion is
//! scaled down to keep every axis within its limit.

use super::basis::MIXED_RAMP_CYCLES;
use crate::error::{Error, Result};
use crate::request::{SampledTarget, Target};
use crate::schedule::export::schedule_peaks;
use crate::schedule::{Schedule, Segment};
use crate::synth::ShakerLimits;

/// Cycles of each of the two segments, ramps included.
pub const MIRROR_SEGMENT_CYCLES: u32 = 28;

/// Relative tolerance of the symmetry test of a target.
const SYMMETRY_TOL: f64 = 1e-9;

/// `true` when the target is symmetric under the reflection y → −y at
/// every sample point of positive weight: t(x, −y) = (tx(x, y), −ty(x, y))
/// within 1e-9 of its largest vector.
pub fn mirror_symmetric(target: &Target, sampled: &SampledTarget) -> bool {
    let scale = sampled.max_norm().max(f64::MIN_POSITIVE);
    sampled
        .points
        .iter()
        .zip(&sampled.vectors)
        .zip(&sampled.weights)
        .filter(|(_, &w)| w > 0.0)
        .all(|((p, t), _)| {
            let m = target.field.eval([p[0], -p[1]]);
            (m[0] - t[0]).hypot(m[1] + t[1]) <= SYMMETRY_TOL * scale
        })
}

/// The mirror-image time-share of a one-motion schedule (a synthesized
/// design): the motion and its mirror image, [`MIRROR_SEGMENT_CYCLES`]
/// cycles each, ramped, scaled down where the ramps would pass `limits`.
/// The rest of the schedule (target, settings, fit metrics) is kept.
///
/// # Errors
/// The schedule does not hold exactly one six-signal motion.
pub fn mirror_share(synthesized: &Schedule, limits: &ShakerLimits) -> Result<Schedule> {
    let [one] = synthesized.segments.as_slice() else {
        return Err(Error::invalid(
            "segments",
            "a mirror-image time-share is made from a one-motion (synthesized) schedule",
        ));
    };
    let Some(motion) = &one.motion else {
        return Err(Error::invalid(
            "segments[0].motion",
            "a mirror-image time-share is made from a six-signal motion",
        ));
    };
    let build = |signals: crate::motion::Signals| {
        let segment = |label: &str, signals: crate::motion::Signals| Segment {
            label: label.into(),
            primitive: None,
            motion: Some(signals),
            ramp_cycles: Some(MIXED_RAMP_CYCLES),
            weight: 0.5,
            cycles: MIRROR_SEGMENT_CYCLES,
            duration_s: 0.0,
        };
        let mirrored = signals.mirrored_y();
        let mut s = synthesized.clone();
        s.segments = vec![
            segment("Synthesized", signals),
            segment("Synthesized, mirrored (y → −y)", mirrored),
        ];
        s.played = None;
        s.solver.mode = "mirror".into();
        s.derive();
        s
    };
    let schedule = build(motion.clone());
    let peaks = schedule_peaks(&schedule);
    let allowed = [limits.linear, limits.angular].concat();
    let scale = peaks
        .iter()
        .zip(&allowed)
        .filter(|(p, _)| **p > 0.0)
        .map(|(p, a)| a / p)
        .fold(1.0_f64, f64::min);
    Ok(if scale < 1.0 {
        build(motion.scaled(scale))
    } else {
        schedule
    })
}
