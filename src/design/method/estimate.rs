//! The work of a design, stated before it runs: the synthesis' evaluations
//! and plays, the sequenced design's library and plays, the judges, in
//! steps ([`crate::work::Estimate`]).

use super::*;

/// The work of [`sweep_schedule`] over `values` frictions: the judge
/// ([`crate::design::judge::judge_term`]) at each friction.
pub(crate) fn sweep_estimate(schedule: &Schedule, values: usize) -> Result<Estimate> {
    let (target, sampled) = recorded_target(schedule, "--friction")?;
    Ok(Estimate::new(
        "schedule",
        "sweeping its friction",
        "fewer frictions (N of --friction LO:HI:N)",
    )
    .plus(
        crate::design::judge::judge_term(
            target,
            &sampled,
            crate::design::judge::judged_cycles(schedule),
            schedule.settings.numerics.steps_per_cycle,
        )
        .named("friction sweep")
        .times(values as f64, "frictions"),
    ))
}

/// Independent shapes of an affine field about its centre: divergence,
/// curl and two shears ([`sequenced_cycles`]).
pub(super) const AFFINE_SHAPES: u32 = 4;

/// The target's region as a grid: its own grid, or the bounding box of
/// its weighted points at 21 × 21.
pub(super) fn region(target: &Target, sampled: &SampledTarget) -> Grid {
    if let Some(g) = &target.grid {
        return Grid {
            x: g.x,
            y: g.y,
            n: g.n,
        };
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for (p, w) in sampled.points.iter().zip(&sampled.weights) {
        if *w > 0.0 {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    Grid {
        x: [lo[0], hi[0]],
        y: [lo[1], hi[1]],
        n: [21, 21],
    }
}

/// The work of one synthesis and its played polish ([`crate::work`]), as
/// they run: the seed, its phase calibration and the
/// Levenberg–Marquardt steps (`LmOptions::evaluations` over the
/// parameters of the target's shaker limits; all of
/// `--synth-evaluations` for Nelder–Mead), each a steady-state field on
/// the coarse grid; the check of the motion on the full grid; and every
/// play of the polish — its start points (those of the judge,
/// `check_starts`: 40 for a 40-point grid-less target) over the cycles
/// the check plays plus one coarse field for its
/// contact check — the start's two plays and those of its steps, as many
/// as its patience and one gain allow (all of `--polish-plays` for
/// Nelder–Mead). Over a friction range optimised
/// for its worst case, every evaluation and play is made under its three
/// physics. The promise's flow that each play's measure integrates costs
/// O(1) per step (a grid-less sampled target's field through its
/// `crate::request::SampledInterpolant`), within the steps counted.
pub fn synthesis_estimate(
    target: &Target,
    sampled: &SampledTarget,
    synth: &SynthOptions,
    opts: &DesignOptions,
    limits: &ShakerLimits,
) -> Estimate {
    let opts = &resolving(opts, limits.harmonics);
    let region = region(target, sampled);
    let (evaluations, plays, checks, physics) =
        synthesis_counts(target, &region, synth, &opts.settings, limits);
    let coarse = (synth.coarse[0] * synth.coarse[1]) as f64;
    let velocity = |label: &str, fields: f64, name: &str, samples: f64| {
        crate::work::field_term(
            label,
            fields,
            name,
            samples,
            FieldKind::Velocity,
            &opts.settings,
        )
    };
    Estimate::new(
        "target",
        "synthesizing a six-signal motion",
        "fewer --synth-evaluations or --polish-plays, or a smaller target grid n",
    )
    .plus(
        velocity("synthesis", evaluations as f64, "evaluations", coarse).times(physics, "physics"),
    )
    .plus(velocity(
        "full-grid check",
        checks,
        "field",
        region.len() as f64,
    ))
    .plus(
        Term::new("played polish")
            .times(plays as f64, "plays")
            .times(physics, "physics")
            .times(judge_points(target, sampled).len() as f64, "points")
            .times(f64::from(JUDGE_MIN_PERIODS), "cycles")
            .times(opts.settings.numerics.steps_per_cycle as f64, "steps"),
    )
    .plus(velocity("polish contact check", plays as f64, "plays", coarse).times(physics, "physics"))
}

/// The counts of [`synthesis_estimate`]: coarse evaluations, polish plays,
/// full-grid checks and physics per evaluation.
pub(super) fn synthesis_counts(
    target: &Target,
    region: &Grid,
    synth: &SynthOptions,
    settings: &crate::field::FieldSettings,
    limits: &ShakerLimits,
) -> (usize, usize, f64, f64) {
    let n = crate::synth::params::Layout::new(limits).len();
    let ranged = target.friction.filter(|f| !f.is_exact()).is_some();
    let robust = synth.robust.is_some_and(|f| !f.is_exact()) || (synth.robust_synthesis && ranged);
    let physics = if robust { 3.0 } else { 1.0 };
    // Limits the closed-form seed finds no motion in end the synthesis
    // before its first simulation.
    let seeded = crate::synth::seed::seed(
        &target.field,
        region,
        limits,
        settings.friction,
        settings.gravity,
    )
    .is_ok();
    if !seeded {
        return (0, 0, 0.0, physics);
    }
    let evaluations = synth.lm.map_or(synth.max_evaluations, |lm| {
        (1 + crate::synth::calibrate::STEPS + lm.evaluations(n)).min(synth.max_evaluations)
    });
    let plays = match (synth.polish_plays, synth.polish_lm) {
        (0, _) => 0,
        // The polish stops after its patience without a gain: counted
        // as one gain (the sink's takes one step, the saddle's all four).
        (p, Some(lm)) => {
            let steps = PolishOptions::default()
                .patience
                .map_or(lm.max_iterations, |k| lm.max_iterations.min(k + 1));
            (2 + LmOptions {
                max_iterations: steps,
                ..lm
            }
            .evaluations(n))
            .min(p + 1)
        }
        (p, None) => p + 1,
    };
    (evaluations, plays, 1.0, physics)
}

/// The work of designing `target` by `method` ([`crate::work`]), stated
/// before it starts and compared with the work done by `tests/estimates.rs`
/// ([`crate::dynamics::steps_taken`], within 3×): the sequenced design's
/// library when the cache does not hold it (the basis stage), the
/// synthesis and its polish (`synthesis_estimate`), the judge
/// of every candidate and, for a target that states its friction, each
/// candidate's friction sweep.
/// `limits` are those the synthesis keeps, `library` the basis stage's
/// work when the cache does not hold the library
/// (`stages::cold_library_estimate`). `fitted_cycles`: the sequenced
/// schedule's cycles per period once it is fitted
/// (`judge::judged_cycles`); `None` before, when `sequenced_cycles`
/// counts them. A fit whose least weight is small takes up to the
/// quantisation's longest schedule (`MAX_TOTAL_CYCLES`), so the count
/// before the fit can be short by that factor; the design states its
/// work again once it knows.
#[allow(clippy::too_many_arguments)]
pub fn design_estimate(
    target: &Target,
    sampled: &SampledTarget,
    synth: &SynthOptions,
    opts: &DesignOptions,
    method: Method,
    limits: &ShakerLimits,
    library: Option<Estimate>,
    fitted_cycles: Option<u32>,
) -> Estimate {
    let mut e = Estimate::new(
        "target",
        "designing it",
        "fewer --synth-evaluations or --polish-plays, a smaller target grid n, a larger --rotation-step, or --method sequence",
    );
    let sequenced = matches!(method, Method::Sequence | Method::Auto | Method::Mix);
    if let Some(library) = library.filter(|_| sequenced) {
        e.terms.extend(library.terms);
    }
    let ranged = target.friction.is_some_and(|f| !f.is_exact());
    if method != Method::Sequence {
        let one = synthesis_estimate(target, sampled, synth, opts, limits);
        // A target without a symmetry line through the centre has its mirror-image partner
        // synthesized too (`crate::design::mirror::counter_share`).
        let pair = (method == Method::Mirror || (method == Method::Auto && ranged))
            && !crate::design::mirror::mirror_axis(target, sampled)
                .is_some_and(|l| l.is_through_centre());
        if pair {
            let partner = |t: &Term| t.clone().named(&format!("partner's {}", t.label));
            e.terms.extend(one.terms.iter().map(partner));
        }
        e.terms.extend(one.terms);
    }
    // Judges of sequenced schedules (and mixes) at their cycles per
    // period, of synthesized motions at one cycle, of a mirror pair at
    // its two segments' cycles (`judge::judged_cycles`).
    let (sequenced, synthesized, pairs) = match method {
        Method::Auto => (1, 1 + usize::from(ranged), usize::from(ranged)),
        Method::Mix => (2, 0, 0),
        Method::Sequence => (1, 0, 0),
        Method::Synthesize => (0, 1, 0),
        Method::Mirror => (0, 0, 1),
    };
    // The sequenced schedule's judge at its fitted cycles once known; its
    // friction sweep too where it always runs (`sequence` asked), while
    // under `auto` it runs only when the judge does not find the schedule
    // POOR, and stays at the count before the fit (a long fitted period
    // comes from a fit spending whole cycles on its least weights, which
    // is mostly a poor one).
    let counted = sequenced_cycles(opts);
    let fitted = fitted_cycles.unwrap_or(counted);
    let swept = if method == Method::Sequence {
        fitted
    } else {
        counted
    };
    let judges = [
        (sequenced, fitted, swept),
        (synthesized, 1, 1),
        (pairs, 2 * SYNTH_SEGMENT_CYCLES, 2 * SYNTH_SEGMENT_CYCLES),
    ];
    for (count, cycles, swept) in judges.into_iter().filter(|(n, ..)| *n > 0) {
        let judge = |cycles| {
            crate::design::judge::judge_term(
                target,
                sampled,
                cycles,
                opts.settings.numerics.steps_per_cycle,
            )
            .times(count as f64, "candidates")
        };
        e = e.plus(judge(cycles).named("judges"));
        if ranged {
            e = e.plus(
                judge(swept)
                    .named("friction sweeps")
                    .times(sensitivity::SWEEP_VALUES as f64, "frictions"),
            );
        }
    }
    if target.friction.is_some_and(|f| f.is_exact()) {
        // The kept design around an exact value.
        e = e.plus(
            crate::design::judge::judge_term(
                target,
                sampled,
                sequenced_cycles(opts),
                opts.settings.numerics.steps_per_cycle,
            )
            .named("friction sweep")
            .times(sensitivity::SWEEP_VALUES as f64, "frictions"),
        );
    }
    e
}

/// Cycles per period a sequenced schedule is counted at before it is
/// designed: the asked total, else [`AFFINE_SHAPES`] segments of the least
/// cycles each — one segment per independent shape of an affine field
/// about its centre (divergence, curl and two shears), what a fit of a
/// smooth target mostly spends its segments on (the shipped sequenced
/// designs hold 1–5 segments).
pub(crate) fn sequenced_cycles(opts: &DesignOptions) -> u32 {
    opts.schedule
        .total_cycles
        .unwrap_or(AFFINE_SHAPES * opts.schedule.min_cycles)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Once the sequenced schedule is fitted, its judges are counted at
    /// its own cycles per period: under `sequence` (one judge, no range)
    /// the judge's share of the work grows by the ratio of the fitted
    /// cycles to the count before the fit, and nothing else changes.
    #[test]
    fn a_fitted_period_replaces_the_count_before_the_fit() {
        let target = Target::from_json_str(
            r#"{"name": "sink", "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 21]},
                "field": {"kind": "sink", "center": [0.0, 0.0], "strength": 1.0}}"#,
        )
        .unwrap();
        let sampled = target.sample().unwrap();
        let opts = DesignOptions::default();
        let limits = ShakerLimits::from_spec(None);
        let synth = asked_synthesis(&target, &opts);
        let at = |fitted| {
            design_estimate(
                &target,
                &sampled,
                &synth,
                &opts,
                Method::Sequence,
                &limits,
                None,
                fitted,
            )
            .steps()
        };
        let counted = sequenced_cycles(&opts);
        let judge = |cycles: u32| {
            crate::design::judge::judge_term(
                &target,
                &sampled,
                cycles,
                opts.settings.numerics.steps_per_cycle,
            )
            .steps()
        };
        let grown = at(Some(5000)) - at(None);
        let expected = judge(5000) - judge(counted);
        assert!(
            grown > 0.0 && (grown - expected).abs() <= 1e-9 * expected,
            "{grown} against {expected}"
        );
    }
}
