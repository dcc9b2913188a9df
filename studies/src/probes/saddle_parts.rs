//! The saddle's synthesized motion looked at start point by start point:
//! where each part was measured, or where and when it left the plate.
//!
//! First the motion `platefield study synthesis` keeps for its saddle row (where
//! the saddle's parts are lost, `results/synthesis.md`, "valid / played"),
//! as the study measures it. Then a controller that plays a third harmonic
//! (which can lower the corners' peak normal acceleration for the same
//! first harmonic, [`platefield::synth`] docs): the phase-calibrated synthesis
//! under the same per-axis peaks with harmonics 1–3, played, then the
//! played polish ([`platefield::design::polish`]: 300 plays of step 0.03, a
//! region shape budget of 6 %, `PolishOptions::grid_budget`) and the kept
//! motion played from the held-out start points as well.

use std::fmt::Write as _;
use std::path::Path;

use crate::synthesis::{
    holdout_starts, limits_of, measure, row, sequenced, starts, synthesized_motion, Measured,
    StudySettings,
};
use platefield::design::closed_loop::realised::{
    play_motion, realised_error, MeasureOptions, RealisedError,
};
use platefield::design::polish::{polish, PolishOptions};
use platefield::error::{Error, Result};
use platefield::field::{FieldSettings, Grid};
use platefield::play::measure::PointPlay;
use platefield::request::{SampledTarget, Target};
use platefield::synth::{synthesize, ShakerLimits, SynthOptions, Synthesis};

use super::synthesis_line;

/// Plays of the played polish.
const PLAYS: usize = 300;
/// The polish's simplex step.
const STEP: f64 = 0.03;
/// The polish's shape budget over the region.
const REGION_BUDGET: f64 = 0.06;

/// One line per start point: where its part was measured, or where and
/// why it was lost.
fn start_lines(md: &mut String, played: &[PointPlay]) {
    for p in played {
        let at = format!("start ({:+.3}, {:+.3}) m", p.start[0], p.start[1]);
        let _ = match (&p.note, p.lost_at) {
            (Some(n), Some(l)) => {
                writeln!(md, "- {at}: lost at ({:+.4}, {:+.4}) m: {n}", l[0], l[1])
            }
            (Some(n), None) => writeln!(md, "- {at}: {n}"),
            _ => writeln!(
                md,
                "- {at}: measured at mean position ({:+.4}, {:+.4}) m",
                p.position[0], p.position[1]
            ),
        };
    }
}

/// "ŝ … at … %, valid / played".
fn measured(e: &RealisedError, played: usize) -> String {
    format!(
        "ŝ {:.4} s⁻¹ at shape {:.2} %, {} / {played} valid",
        e.realised_strength,
        100.0 * e.shape_error,
        e.valid
    )
}

/// `syn` played from the start points `st` (one cycle per period).
fn played(
    syn: &Synthesis,
    target: &Target,
    sampled: &SampledTarget,
    st: &[usize],
    settings: &FieldSettings,
) -> Result<(Vec<PointPlay>, RealisedError)> {
    let sm = synthesized_motion(syn)?;
    let options = MeasureOptions::default();
    let plays = play_motion(&sm, 1, &sampled.points, st, settings, &options);
    let e = realised_error(target, &sampled.weights, &plays, None);
    Ok((plays, e))
}

/// The synthesis `s` polished on its plays from `st` (one of the
/// `sampled` target's points each), measured as the study does, and
/// played from the held-out start points before and after the polish.
fn polished(
    md: &mut String,
    target: &Target,
    sampled: &SampledTarget,
    st: &[usize],
    s: &Synthesis,
    (region, limits, settings): (&Grid, &ShakerLimits, &FieldSettings),
) -> Result<()> {
    let polish_options = PolishOptions {
        max_plays: PLAYS,
        step: STEP,
        grid_budget: REGION_BUDGET,
        ..PolishOptions::default()
    };
    let p = polish(
        target,
        sampled,
        st,
        region,
        limits,
        settings,
        s,
        &polish_options,
    )?;
    eprintln!("probes: saddle polish {:.1} s", p.seconds);
    let _ = writeln!(
        md,
        "\npolish ({} plays, kept {}): {} → {}; {}",
        p.plays,
        p.improved,
        measured(&p.before, st.len()),
        measured(&p.after, st.len()),
        synthesis_line(&p.synthesis)
    );
    let sm = synthesized_motion(&p.synthesis)?;
    let m = measure(target, &sm, 1, settings, true)?;
    let _ = writeln!(md, "\n{}", study_measured(&m));
    let ho = holdout_starts(target, sampled);
    for (label, syn) in [("before", s), ("after", &p.synthesis)] {
        let (_, e) = played(syn, target, sampled, &ho, settings)?;
        let _ = writeln!(
            md,
            "\nheld-out starts, {label} the polish: {}",
            measured(&e, ho.len())
        );
    }
    Ok(())
}

/// The saddle synthesized, played and polished with `harmonics`.
fn run_harmonics(md: &mut String, target: &Target, cache: &Path, harmonics: u32) -> Result<()> {
    let schedule = sequenced(target, cache)?;
    let settings = schedule.settings;
    let limits = limits_of(&schedule, harmonics)?;
    let region = target
        .grid
        .ok_or_else(|| Error::invalid("grid", "targets/saddle.json needs a grid"))?;
    let options = SynthOptions {
        calibrate: true,
        ..StudySettings::default().options()
    };
    let s = synthesize(&target.field, &region, &limits, &settings, &options)?;
    let sampled = target.sample()?;
    let st = starts(target, &sampled);
    let _ = writeln!(
        md,
        "\n### Harmonics 1–{harmonics}\n\nsynthesis: {}\n",
        synthesis_line(&s)
    );
    let (plays, e) = played(&s, target, &sampled, &st, &settings)?;
    start_lines(md, &plays);
    let _ = writeln!(md, "\nplayed: {}", measured(&e, st.len()));
    let physics = (&region, &limits, &settings);
    polished(md, target, &sampled, &st, &s, physics)
}

/// A motion measured as `platefield study synthesis` measures it.
fn study_measured(m: &Measured) -> String {
    format!(
        "measured as `platefield study synthesis` does: ŝ {:.4} s⁻¹ at shape {:.2} %, {:.2} % from its prediction, {} / {} valid",
        m.strength,
        100.0 * m.shape_error,
        100.0 * m.vs_predicted,
        m.valid,
        m.played
    )
}

/// `platefield study synthesis`'s saddle row: the motion it keeps, start point
/// by start point, and from the held-out start points.
fn study_row(md: &mut String, cache: &Path) -> Result<()> {
    let r = row(
        "saddle",
        Path::new("targets"),
        cache,
        &StudySettings::default(),
    )?;
    md.push_str("\n### `platefield study synthesis`'s saddle row\n\n");
    match &r.synthesis {
        Ok((s, _)) => {
            let how = if r.calibrated {
                "phase-calibrated"
            } else {
                "from the seed"
            };
            let _ = writeln!(
                md,
                "kept: harmonics 1–{}, {how}; {}\n",
                r.harmonics,
                synthesis_line(s)
            );
        }
        Err(why) => {
            let _ = writeln!(md, "no synthesized motion: {why}\n");
        }
    }
    start_lines(md, &r.plays);
    if let Ok((_, m)) = &r.synthesis {
        let _ = writeln!(md, "\n{}", study_measured(m));
    }
    if let Some((k, e, valid, played)) = r.holdout {
        let _ = writeln!(
            md,
            "\nheld-out starts: ŝ {k:.4} s⁻¹ at shape {:.2} %, {valid} / {played} valid",
            100.0 * e
        );
    }
    Ok(())
}

/// The section of `probes.md`.
pub(crate) fn section(cache: &Path) -> Result<String> {
    let mut md = String::from(
        "\n## The saddle's synthesized motion, start point by start point\n\n\
         `targets/saddle.json` under its sequenced schedule's per-axis peaks, played from the \
         study's start points: the motion `platefield study synthesis` keeps for its row, then a \
         phase-calibrated synthesis (300 coarse evaluations) with harmonics 1–3 and its played \
         polish (300 plays, step 0.03, region shape budget 6 %).\n",
    );
    study_row(&mut md, cache)?;
    let target = Target::load(Path::new("targets/saddle.json"))?;
    run_harmonics(&mut md, &target, cache, 3)?;
    Ok(md)
}
