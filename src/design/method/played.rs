//! A candidate judged as it is reported: the played polish of a synthesized
//! motion and the judge's measure of a schedule ([`crate::schedule::Played`]).

use super::*;

/// The played polish of a synthesized motion ([`crate::design::polish`]:
/// `synth.polish_plays` plays on the judge's start points, the
/// polish's own measure): the polished synthesis when the polish found a
/// better motion, else `syn`; and a line saying what it did. A POOR
/// synthesis, or `polish_plays` 0, is returned as it is.
pub(super) fn polish_played(
    target: &Target,
    sampled: &SampledTarget,
    grid: &Grid,
    limits: &ShakerLimits,
    opts: &DesignOptions,
    synth: &SynthOptions,
    syn: Synthesis,
) -> Result<(Synthesis, Option<String>)> {
    if synth.polish_plays == 0 || syn.checked.poor {
        return Ok((syn, None));
    }
    let options = PolishOptions {
        max_plays: synth.polish_plays,
        stall: synth.polish_stall,
        progress: synth.progress,
        robust: synth.robust,
        lm: synth.polish_lm,
        ..PolishOptions::default()
    };
    let p = polish(
        target,
        sampled,
        &judge_points(target, sampled),
        grid,
        limits,
        &opts.settings,
        &syn,
        &options,
    )?;
    let line = format!(
        "played polish ({} plays): played strength {:.4} at shape {} → {:.4} at {}, {}",
        p.plays,
        p.before.realised_strength,
        crate::output::percent(p.before.shape_error, 2),
        p.after.realised_strength,
        crate::output::percent(p.after.shape_error, 2),
        if p.improved { "kept" } else { "not kept" }
    );
    Ok((if p.improved { p.synthesis } else { syn }, Some(line)))
}

/// Judges `schedule` ([`crate::design::judge`]) and compares what it realises with
/// the target (see the [module documentation](self)); `predicted` is the
/// strength the design predicts.
pub(crate) fn play_check(
    target: &Target,
    sampled: &SampledTarget,
    schedule: &Schedule,
    predicted: f64,
    asked: Method,
    limits: Option<crate::request::ShakerSpec>,
) -> Result<Played> {
    let (plays, r) = realised_check(
        target,
        sampled,
        schedule,
        &schedule.settings,
        Some(predicted),
    )?;
    Ok(played_of(&plays, &r, schedule, predicted, asked, limits))
}

/// The [`Played`] record of `schedule` from the judge's `plays` and what
/// they realise, `r` ([`play_check`]): POOR with the reasons when too few
/// points count, the shape error exceeds [`fit::POOR_ERROR`], or a held part
/// loses contact or reaches no steady state.
pub(crate) fn played_of(
    plays: &[PointPlay],
    r: &RealisedError,
    schedule: &Schedule,
    predicted: f64,
    asked: Method,
    limits: Option<crate::request::ShakerSpec>,
) -> Played {
    let finite = |x: f64| x.is_finite().then_some(x);
    // Every judge point is in the region: a part that loses contact at
    // one fails the design.
    let lost: Vec<&PointPlay> = plays.iter().filter(|p| p.lost_at.is_some()).collect();
    // A held part with no steady state has no realised velocity to judge.
    let unsteady: Vec<&PointPlay> = plays
        .iter()
        .filter(|p| p.note.is_some() && p.lost_at.is_none())
        .collect();
    let mut notes = Vec::new();
    if r.valid == 0 {
        notes.push("no valid point".to_string());
    } else if r.valid < MIN_MEASURED_POINTS {
        notes.push(format!(
            "not measured: {} of {} parts counted, and a realised strength and shape need at least {MIN_MEASURED_POINTS} (mask, weights or lost contact leave too few)",
            r.valid,
            plays.len()
        ));
    }
    if r.shape_error.is_nan() || r.shape_error > fit::POOR_ERROR {
        notes.push(format!(
            "realised shape error {} > {:.0} %",
            percent(finite(r.shape_error)),
            100.0 * fit::POOR_ERROR
        ));
    }
    for (parts, what) in [
        (&lost, "parts lost contact in the region"),
        (&unsteady, "held parts in the region reach no steady state"),
    ] {
        if let Some(first) = parts.first() {
            notes.push(format!(
                "{} of {} {what} ({})",
                parts.len(),
                plays.len(),
                first.note.clone().unwrap_or_default()
            ));
        }
    }
    Played {
        method: match (
            schedule.segments.iter().any(|s| s.motion.is_some()),
            schedule.segments.iter().filter(|s| s.is_moving()).count() > 1,
        ) {
            (true, true) if schedule.segments.iter().all(|s| s.primitive.is_none()) => {
                Method::Mirror
            }
            (true, true) => Method::Mix,
            (true, false) => Method::Synthesize,
            (false, _) => Method::Sequence,
        },
        asked,
        choice: String::new(),
        points: plays.len(),
        valid: r.valid,
        predicted_strength: predicted,
        realised_strength: finite(r.realised_strength),
        realised_shape_error: finite(r.shape_error),
        worst_friction: None,
        realised_error: finite(r.error),
        poor: !notes.is_empty(),
        notes,
        peaks: AxisPeaks::from_six(schedule_peaks(schedule)),
        limits,
        pose: None,
        moving_escaped: None,
    }
}
