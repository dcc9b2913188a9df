//! The synthesized candidate: one six-signal motion within shaker limits,
//! written as a one-segment schedule, and the limits a sequenced schedule
//! gives it.

use super::*;

/// Shaker limits equal to a sequenced schedule's per-axis peaks
/// ([`schedule_peaks`]) and its primitives' common period, with `base`'s
/// harmonics and contact margin: the shaker that plays the schedule.
///
/// # Errors
/// No moving primitive segment, or primitives of different periods (one
/// set of limits needs one period).
pub fn sequenced_limits(schedule: &Schedule, base: &ShakerLimits) -> Result<ShakerLimits> {
    let mut period: Option<f64> = None;
    for (i, seg) in schedule.segments.iter().enumerate() {
        let Some(p) = &seg.primitive else { continue };
        let t = p.motion().period();
        match period {
            Some(t0) if (t - t0).abs() > 1e-12 * t0 => {
                return Err(Error::invalid(
                    format!("schedule.segments[{i}].primitive.omega"),
                    format!(
                        "all primitives must share one period for one set of shaker limits; {t:.6} s against {t0:.6} s"
                    ),
                ))
            }
            _ => period = Some(t),
        }
    }
    let period = period.ok_or_else(|| {
        Error::invalid(
            "schedule.segments",
            "has no moving primitive segment: no peaks to take as limits",
        )
    })?;
    let p = schedule_peaks(schedule);
    Ok(ShakerLimits {
        period,
        linear: [p[0], p[1], p[2]],
        angular: [p[3], p[4], p[5]],
        ..base.clone()
    })
}

/// `opts` with its steps per cycle raised, if needed, to resolve
/// `harmonics` at [`STEPS_PER_HARMONIC`](crate::dynamics::STEPS_PER_HARMONIC)
/// steps per period of the highest (a schedule whose steps do not is
/// refused when read back).
pub(super) fn resolving(opts: &DesignOptions, harmonics: u32) -> DesignOptions {
    let mut o = opts.clone();
    let needed = harmonics as usize * crate::dynamics::STEPS_PER_HARMONIC;
    let steps = &mut o.settings.numerics.steps_per_cycle;
    *steps = (*steps).max(needed);
    o
}

/// Synthesizes one six-signal motion for `target` within `limits` and
/// writes it as a one-segment schedule: fit metrics of its full-grid
/// steady-state field against the target at its realised strength. The
/// steps per cycle are raised to resolve the limits' harmonics
/// (`resolving`).
pub(crate) fn synthesize_schedule(
    target: &Target,
    sampled: &SampledTarget,
    limits: &ShakerLimits,
    opts: &DesignOptions,
    synth: &SynthOptions,
) -> Result<(Synthesis, Schedule)> {
    let opts = &resolving(opts, limits.harmonics);
    let grid = region(target, sampled);
    // Asked for, over a friction range the synthesis and its polish
    // optimise the worst case (`crate::synth::robust`).
    let synth = &SynthOptions {
        robust: if synth.robust_synthesis {
            target.friction.filter(|f| !f.is_exact())
        } else {
            synth.robust
        },
        ..*synth
    };
    let syn = synthesize(&target.field, &grid, limits, &opts.settings, synth)?;
    // A motion that keeps no part on the plate anywhere is no design: said
    // as such (an error; `auto` keeps the other method and says why).
    if syn.checked.realised.invalid >= syn.checked.field.grid.len() {
        return Err(Error::ContactLost(format!(
            "the synthesized motion keeps no part on the plate anywhere in the region: all {} samples lose contact or do not converge (least N {:.3} m/s², the margin asks ≥ {:.3}); the shaker limits (period {} s, linear peaks [{:.3}, {:.3}, {:.3}] m/s², angular peaks [{:.1}, {:.1}, {:.1}] rad/s², a tilt of up to {:.3} rad at harmonic 1) give no motion that keeps contact",
            syn.checked.field.grid.len(),
            syn.checked.least_normal,
            limits.contact_margin * opts.settings.gravity,
            crate::input::num(limits.period),
            limits.linear[0],
            limits.linear[1],
            limits.linear[2],
            limits.angular[0],
            limits.angular[1],
            limits.angular[2],
            // Harmonic 1: angle = angular acceleration / ω².
            limits.angular[0].max(limits.angular[1])
                * (limits.period / std::f64::consts::TAU).powi(2),
        )));
    }
    let (syn, polished) = polish_played(target, sampled, &grid, limits, opts, synth, syn)?;
    // The synthesized field at the target's points (the region grid is the
    // target's grid when it has one).
    let strength = syn.checked.realised.strength;
    let fit_metrics = if target.grid.is_some() && strength > 0.0 && strength.is_finite() {
        fit::field_metrics(
            &sampled.vectors,
            &syn.checked.field.vectors,
            strength,
            Some(&sampled.weights),
        )
        .map_err(|e| Error::Internal(format!("synthesized field metrics: {e}")))?
    } else {
        FitMetrics {
            relative_l2_error: syn.checked.realised.shape_error.min(1.0),
            mean_angle_error_deg: f64::NAN,
            max_error: f64::NAN,
            strength: strength.max(0.0),
        }
    };
    let segment = Segment {
        label: "Synthesized".into(),
        primitive: None,
        motion: Some(syn.checked.motion.clone()),
        ramp_cycles: None,
        weight: 1.0,
        cycles: SYNTH_SEGMENT_CYCLES,
        duration_s: 0.0,
    };
    let mut schedule =
        Schedule::of_segments(&target.name, vec![segment], opts.settings, fit_metrics);
    schedule.target_spec = Some(target.clone());
    schedule.poor_fit = syn.checked.poor;
    schedule.solver = SolverInfo {
        mode: "synthesize".into(),
        status: format!(
            "seed {:.4} predicted, {:.4} at {} on the coarse grid; Nelder–Mead, {} starts, seed {}",
            syn.seed_strength,
            syn.seed_realised.strength,
            crate::output::percent(syn.seed_realised.shape_error, 2),
            synth.multistart.starts,
            synth.multistart.seed
        ) + &polished.map(|n| format!("; {n}")).unwrap_or_default(),
        iterations: u32::try_from(syn.evaluations).unwrap_or(u32::MAX),
        kkt_residual: 0.0,
        independent_gap: 0.0,
    };
    schedule.basis = BasisInfo {
        columns: 0,
        excluded: Vec::new(),
        kept_with_invalid_points: Vec::new(),
        kind: crate::field::FieldKind::Velocity,
        rotation_step_deg: 0.0,
        shifts: Vec::new(),
    };
    Ok((syn, schedule))
}
