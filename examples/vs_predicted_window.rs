//! Where the synthesized motions' realised-vs-predicted gap comes from
//! (issue 11): the lab-class sink is synthesized as in `platefield
//! synthesis`, then played from rest at the study's points with different
//! warm-ups and measured spans, each compared with the motion's own
//! steady-state prediction (`verify`'s number). A start-up transient would
//! shrink with the warm-up; an end-point artefact of the measured span
//! (the part's position within its orbit differs at the window's two ends)
//! shrinks with the span as 1/span.
//!
//! `cargo run --release --example vs_predicted_window`

use std::path::Path;

use platefield::design::closed_loop::measure::{play_motion, MeasureOptions};
use platefield::field::{FieldSettings, Grid};
use platefield::play::measure::{against_prediction, PlayOptions};
use platefield::request::Target;
use platefield::studies::synthesis::{starts, synthesized_motion, StudySettings};
use platefield::synth::{synthesize, ShakerLimits};

fn main() -> platefield::Result<()> {
    let target = Target::load(Path::new("targets/sink.json"))?;
    let limits = ShakerLimits::lab_class();
    let settings = FieldSettings::default();
    let Some(g) = target.grid.as_ref() else {
        return Err(platefield::Error::invalid(
            "grid",
            "targets/sink.json needs a grid",
        ));
    };
    let region = Grid {
        x: g.x,
        y: g.y,
        n: g.n,
    };
    let s = synthesize(
        &target.field,
        &region,
        &limits,
        &settings,
        &StudySettings::default().options(),
    )?;
    println!("lab sink: {}", s.summary());
    let sampled = target.sample()?;
    let points = starts(&target, &sampled);
    let sm = synthesized_motion(&s)?;
    for (warmup_cycles, measured_cycles) in [(40, 20), (200, 20), (400, 20), (40, 100), (200, 100)]
    {
        let plays = play_motion(
            &sm,
            1,
            &sampled.points,
            &points,
            &settings,
            &MeasureOptions {
                warmup_cycles,
                measured_cycles,
            },
        );
        let r = against_prediction(&sm, plays, &PlayOptions::from_settings(&settings));
        println!(
            "warm-up {warmup_cycles:>3} cycles, measured {measured_cycles:>3}: realised vs predicted {:.2} % (realised/predicted {:.4}, shape {:.2} %)",
            100.0 * r.relative_error,
            r.realised_scale,
            100.0 * r.shape_error
        );
    }
    Ok(())
}
