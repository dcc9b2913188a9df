//! The saddle's synthesized motion looked at point by point: at which of
//! the judge's points ([`platefield::design::judge`]) a held part loses
//! contact.
//!
//! First the motion `platefield study synthesis` keeps for its saddle row
//! (`results/synthesis.md`, "valid / judged"), as the study judges it. Then a controller that plays a third harmonic
//! (which can lower the corners' peak normal acceleration for the same
//! first harmonic, [`platefield::synth`] docs): the phase-calibrated synthesis
//! under the same per-axis peaks with harmonics 1–3, played, then the
//! played polish ([`platefield::design::polish`]: 300 plays of step 0.03, a
//! region shape budget of 6 %, `PolishOptions::grid_budget`) and the kept
//! motion judged at the held-out points as well.

use std::fmt::Write as _;
use std::path::Path;

use crate::synthesis::{
    holdout_starts, limits_of, measure, row, sequenced, starts, synthesized_motion, Measured,
    StudySettings,
};
use platefield::design::judge::play_motion;
use platefield::design::judge::{realised_error, RealisedError};
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

/// How many held parts keep contact, and one line per point where one
/// does not, saying why.
fn start_lines(md: &mut String, played: &[PointPlay]) {
    let lost: Vec<&PointPlay> = played.iter().filter(|p| p.note.is_some()).collect();
    let _ = writeln!(
        md,
        "{} of {} held parts keep contact{}",
        played.len() - lost.len(),
        played.len(),
        if lost.is_empty() { "." } else { "; lost:" }
    );
    for p in lost {
        let at = format!("({:+.3}, {:+.3}) m", p.start[0], p.start[1]);
        let _ = writeln!(md, "- {at}: {}", p.note.clone().unwrap_or_default());
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

/// `syn` judged at the points `st` (parts held there, as the judge plays).
fn played(
    syn: &Synthesis,
    target: &Target,
    sampled: &SampledTarget,
    st: &[usize],
    settings: &FieldSettings,
) -> Result<(Vec<PointPlay>, RealisedError)> {
    let sm = synthesized_motion(syn)?;
    let plays = play_motion(&sm, &sampled.points, st, settings);
    let e = realised_error(target, &sampled.weights, &plays, None);
    Ok((plays, e))
}

/// The synthesis `s` polished on its plays from `st` (one of the
/// `sampled` target's points each), judged as the study does, and
/// judged at the held-out points before and after the polish.
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
            "\nheld-out points, {label} the polish: {}",
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
    let _ = writeln!(md, "\njudge: {}", measured(&e, st.len()));
    let physics = (&region, &limits, &settings);
    polished(md, target, &sampled, &st, &s, physics)
}

/// A motion judged and model-checked as `platefield study synthesis` does.
fn study_measured(m: &Measured) -> String {
    format!(
        "judged as `platefield study synthesis` does: ŝ {:.4} s⁻¹ at shape {:.2} %, model check {:.2} %, {} / {} valid",
        m.strength,
        100.0 * m.shape_error,
        100.0 * m.vs_predicted,
        m.valid,
        m.played
    )
}

/// `platefield study synthesis`'s saddle row: the motion it keeps, point by
/// point, and at the held-out points.
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
            "\nheld-out points: ŝ {k:.4} s⁻¹ at shape {:.2} %, {valid} / {played} valid",
            100.0 * e
        );
    }
    Ok(())
}

/// The section of `probes.md`.
pub(crate) fn section(cache: &Path) -> Result<String> {
    let mut md = String::from(
        "\n## The saddle's synthesized motion, point by point\n\n\
         `targets/saddle.json` under its sequenced schedule's per-axis peaks, judged at the \
         judge's points (parts held there): the motion `platefield study synthesis` keeps for its row, then a \
         phase-calibrated synthesis (300 coarse evaluations) with harmonics 1–3 and its played \
         polish (300 plays, step 0.03, region shape budget 6 %).\n",
    );
    study_row(&mut md, cache)?;
    let target = Target::load(Path::new("targets/saddle.json"))?;
    run_harmonics(&mut md, &target, cache, 3)?;
    Ok(md)
}
