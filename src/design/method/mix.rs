//! The mixed design: the sequenced design's basis plus one synthesized
//! column, fitted together.

use super::*;

/// The mixed design ([`Method::Mix`]): the sequenced design's basis with
/// one more column, a six-signal motion synthesized for the target — the
/// one `out` already holds, or else one synthesized within the target's
/// `shaker` limits (the paper's envelope where it gives none: the
/// sequenced schedule's own peaks may not let a single motion move parts,
/// e.g. a jet's in-plane x-only peaks) — and the conic fit free to mix it
/// with the primitives. Returns the design and the synthesis run here, if
/// any.
///
/// The motion is played at the primitives' period (its signals' amplitudes
/// and phases unchanged; e.g. 0.03 s → 0.03006 s, a 0.2 % change of
/// frequency, and its column is simulated at that period), so that the
/// mixed schedule's joins fall on one sample grid and `export` can write it
/// (two periods share no practical sample interval), and scaled down where
/// its ramps (the acceleration overshoots the steady peak by up to
/// 1.875/(πR) + 0.146/R²) would take a peak over the target's limits, or
/// its steady velocity or stroke at the primitives' period would.
///
/// # Errors
/// The synthesis or the design failing.
pub(crate) fn mix_design(
    target: &Target,
    sampled: &SampledTarget,
    out: &MethodDesign,
    opts: &DesignOptions,
    synth: &SynthOptions,
) -> Result<(Design, Option<Synthesis>)> {
    let (motion, fresh) = match &out.synthesis {
        Some(s) => (s.checked.motion.clone(), None),
        None => {
            let limits = ShakerLimits::from_spec(target.shaker.as_ref());
            let (syn, _) = synthesize_schedule(target, sampled, &limits, opts, synth)?;
            (syn.checked.motion.clone(), Some(syn))
        }
    };
    let limits = ShakerLimits::from_spec(target.shaker.as_ref());
    let motion = mixable(motion, &limits, opts)?;
    let mut with_motion = opts.clone();
    with_motion
        .basis
        .motions
        .push(("Synthesized".into(), motion));
    Ok((design(target, &with_motion)?, fresh))
}

/// `motion` made playable beside the primitives of a mixed schedule
/// ([`mix_design`]'s rules): played at the primitives' period and scaled
/// down where its ramps, or its steady velocity or stroke at that period,
/// would exceed `limits`.
///
/// # Errors
/// A ramp that cannot be built (never for [`crate::design::basis::MIXED_RAMP_CYCLES`]).
pub(crate) fn mixable(
    motion: Signals,
    limits: &ShakerLimits,
    opts: &DesignOptions,
) -> Result<Signals> {
    let mut motion = motion;
    if let Some(kind) = opts.basis.kinds.first() {
        motion.period = crate::basis::Primitive::new(*kind).period();
    }
    let ramp = crate::design::basis::MIXED_RAMP_CYCLES;
    let ramped = crate::motion::Motion::Ramped(crate::motion::Ramped::new(
        motion.clone(),
        ramp,
        2 * ramp + 1,
        "mix",
    )?);
    let steady = crate::schedule::export::peaks::KinematicPeaks::of_motion(
        &crate::motion::Motion::Signals(motion.clone()),
        limits.harmonics,
    );
    let checks = [
        (
            crate::schedule::export::motion_peaks(&ramped),
            limits.acceleration_axes(),
        ),
        (steady.velocity, limits.velocity_axes()),
        (steady.stroke, limits.stroke_axes()),
    ];
    let fit = checks
        .iter()
        .flat_map(|(peaks, axes)| {
            (0..6)
                .filter(|&k| peaks[k] > 0.0)
                .map(|k| axes[k] / peaks[k])
        })
        .fold(1.0_f64, f64::min);
    if fit < 1.0 {
        motion = motion.scaled(fit);
    }
    Ok(motion)
}
