//! Where the synthesized motions' realised-vs-predicted gap came from
//! (issue 11): the lab-class sink is synthesized as in `platefield
//! synthesis`, then played from rest at the study's points with different
//! warm-ups and measured spans. Each play is compared with four
//! predictions built from the motion's steady states F (see
//! `platefield::play::measure` and `platefield::play::lag`):
//!
//! * flow of F (the measure before this study),
//! * F iterated once per cycle (r ← r + T F(r): what F means),
//! * flow of the drift-lag-corrected F,
//! * the corrected F iterated once per cycle (the measure now, `verify`'s
//!   number, also printed from `against_prediction`).
//!
//! `cargo run --release --example vs_predicted_window`

use std::path::Path;

use platefield::design::closed_loop::measure::{play_motion, MeasureOptions};
use platefield::dynamics::Simulator;
use platefield::field::{FieldSettings, Grid};
use platefield::motion::Motion;
use platefield::play::lag::lagged_velocity;
use platefield::play::measure::{against_prediction, relative_l2, PlayOptions};
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
    let motion = Motion::Signals(s.motion.clone());
    let sim = Simulator::new(
        &motion,
        settings.friction,
        settings.gravity,
        settings.model,
        settings.numerics,
    );
    let t = sim.period();
    let steady = |r: [f64; 2]| sim.steady_state(r).map_err(|e| e.to_string());
    let mut plain = |r: [f64; 2]| steady(r).map(|s| s.velocity);
    let mut lagged = |r: [f64; 2]| {
        let s = steady(r)?;
        lagged_velocity(&sim, r, &s).map_err(|e| e.to_string())
    };
    println!("realised vs predicted (relative L2) by prediction:");
    println!("warm-up | measured | flow of F | F per cycle | flow of lagged F | lagged F per cycle | against_prediction");
    for (warmup_cycles, measured_cycles) in [(40, 1), (40, 20), (200, 20), (400, 20), (40, 100)] {
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
        let ok: Vec<_> = plays.iter().filter(|p| p.note.is_none()).collect();
        let real: Vec<[f64; 2]> = ok.iter().map(|p| p.realised).collect();
        let gap = |f: &mut dyn FnMut(
            &platefield::play::measure::PointPlay,
        ) -> Result<[f64; 2], String>| {
            let e: Result<Vec<[f64; 2]>, String> = ok.iter().map(|p| f(p)).collect();
            e.map_or(f64::NAN, |e| relative_l2(&real, &e))
        };
        let a = gap(&mut |p| p.expected(&mut plain));
        let b = gap(&mut |p| p.expected_cycles(&mut plain, t));
        let c = gap(&mut |p| p.expected(&mut lagged));
        let d = gap(&mut |p| p.expected_cycles(&mut lagged, t));
        let r = against_prediction(&sm, plays, &PlayOptions::from_settings(&settings));
        println!(
            "{warmup_cycles:>7} | {measured_cycles:>8} | {:>8.2} % | {:>10.2} % | {:>15.2} % | {:>17.2} % | {:.2} % (realised/predicted {:.4}, shape {:.2} %)",
            100.0 * a,
            100.0 * b,
            100.0 * c,
            100.0 * d,
            100.0 * r.relative_error,
            r.realised_scale,
            100.0 * r.shape_error
        );
    }
    Ok(())
}
