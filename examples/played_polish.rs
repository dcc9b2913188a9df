//! One row of `platefield synthesis`, looked at point by point: the
//! 2-harmonic, phase-calibrated synthesis for `targets/<TARGET>.json` under
//! the per-axis peaks of its sequenced schedule, every played start point
//! with where its part ended (or where it left the plate), the played
//! measure, then the played polish (`platefield::design::polish`) and the
//! kept motion played from the 16 held-out start points as well.
//!
//! `cargo run --release --example played_polish [TARGET [PLAYS [STEP [HARMONICS [EVALUATIONS [REGION_BUDGET]]]]]]`
//! (defaults: saddle, 300, 0.03, 2, 300, 0.06: the study's shaker and budgets;
//! EVALUATIONS are the synthesis's coarse evaluations, REGION_BUDGET the
//! polish's shape budget over the region, `PolishOptions::grid_budget`; 3 harmonics lets the
//! controller play a third harmonic, which can lower the corners' peak
//! normal acceleration for the same first harmonic, `synth` docs). Used to find where the saddle's parts
//! are lost (results/synthesis.md, "valid / played").

use std::path::Path;
use std::time::Instant;

use platefield::design::closed_loop::measure::{play_motion, realised_error, MeasureOptions};
use platefield::design::polish::{polish, PolishOptions};
use platefield::field::Grid;
use platefield::request::Target;
use platefield::studies::synthesis::{
    holdout_starts, limits_of, measure, sequenced, starts, synthesized_motion, StudySettings,
};
use platefield::synth::{synthesize, SynthOptions};

fn arg<T: std::str::FromStr>(i: usize, default: T) -> T {
    std::env::args()
        .nth(i)
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn main() -> platefield::Result<()> {
    let name: String = arg(1, "saddle".to_string());
    let plays: usize = arg(2, 300);
    let step: f64 = arg(3, 0.03);
    let harmonics: u32 = arg(4, 2);
    let evaluations: usize = arg(5, 300);
    let region_budget: f64 = arg(6, 0.06);
    let target = Target::load(Path::new(&format!("targets/{name}.json")))?;
    let schedule = sequenced(&target, Path::new(".platefield-cache"))?;
    let settings = schedule.settings;
    let limits = limits_of(&schedule, harmonics)?;
    let Some(g) = target.grid.as_ref() else {
        println!("{name}: the target has no grid");
        return Ok(());
    };
    let region = Grid {
        x: g.x,
        y: g.y,
        n: g.n,
    };
    let so = SynthOptions {
        calibrate: true,
        max_evaluations: evaluations,
        ..StudySettings::default().options()
    };
    let s = synthesize(&target.field, &region, &limits, &settings, &so)?;
    println!("synthesis: {}", s.summary());
    let sm = synthesized_motion(&s)?;
    let sampled = target.sample()?;
    let st = starts(&target, &sampled);
    let played = play_motion(
        &sm,
        1,
        &sampled.points,
        &st,
        &settings,
        &MeasureOptions::default(),
    );
    for p in &played {
        match (&p.note, p.lost_at) {
            (Some(n), Some(at)) => println!(
                "start ({:+.3}, {:+.3}) m: lost at ({:+.4}, {:+.4}) m: {n}",
                p.start[0], p.start[1], at[0], at[1]
            ),
            (Some(n), None) => println!("start ({:+.3}, {:+.3}) m: {n}", p.start[0], p.start[1]),
            _ => println!(
                "start ({:+.3}, {:+.3}) m: measured at mean position ({:+.4}, {:+.4}) m",
                p.start[0], p.start[1], p.position[0], p.position[1]
            ),
        }
    }
    let e = realised_error(&target, &sampled.weights, &played, None);
    println!(
        "played ŝ {:.4} at shape {:.2} %, {} / {} valid",
        e.realised_strength,
        100.0 * e.shape_error,
        e.valid,
        st.len()
    );
    let clock = Instant::now();
    let p = polish(
        &target,
        &sampled,
        &st,
        &region,
        &limits,
        &settings,
        &s,
        &PolishOptions {
            max_plays: plays,
            step,
            grid_budget: region_budget,
            ..PolishOptions::default()
        },
    )?;
    println!(
        "polish ({:.1} s, {} plays, kept {}): ŝ {:.4} at {:.2} % → {:.4} at {:.2} %; {}",
        clock.elapsed().as_secs_f64(),
        p.plays,
        p.improved,
        p.before.realised_strength,
        100.0 * p.before.shape_error,
        p.after.realised_strength,
        100.0 * p.after.shape_error,
        p.synthesis.summary()
    );
    let m = measure(
        &target,
        &synthesized_motion(&p.synthesis)?,
        1,
        &settings,
        true,
    )?;
    println!("measured as the study does: {m:?}");
    let ho = holdout_starts(&target, &sampled);
    for (label, syn) in [("before", &s), ("after", &p.synthesis)] {
        let pl = play_motion(
            &synthesized_motion(syn)?,
            1,
            &sampled.points,
            &ho,
            &settings,
            &MeasureOptions::default(),
        );
        let e = realised_error(&target, &sampled.weights, &pl, None);
        println!(
            "held-out starts, {label} the polish: ŝ {:.4} at {:.2} %, {} / {} valid",
            e.realised_strength,
            100.0 * e.shape_error,
            e.valid,
            ho.len()
        );
    }
    Ok(())
}
