//! Designing a target file from Rust through the one door,
//! `platefield::inverse::run`, and writing nothing: the kept candidate's
//! realised check and its schedule.
//!
//! `cargo run --release --example design [-- TARGET [METHOD]]`
//! (default `targets/sink.json`, `sequence`; METHOD one of sequence,
//! synthesize, auto, mix, mirror; a pose target, `targets/pose_*.json`, is
//! designed as a pose whatever the method).

use std::path::Path;

use platefield::design::{DesignOptions, Method};
use platefield::inverse::{self, DesignOutcome, TargetFile};

fn main() -> platefield::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.first().map_or("targets/sink.json", String::as_str);
    let method = match args.get(1).map_or("sequence", String::as_str) {
        "sequence" => Method::Sequence,
        "synthesize" => Method::Synthesize,
        "auto" => Method::Auto,
        "mix" => Method::Mix,
        "mirror" => Method::Mirror,
        other => {
            return Err(platefield::Error::invalid(
                "METHOD",
                format!("one of sequence, synthesize, auto, mix, mirror; got {other}"),
            ))
        }
    };
    let target = TargetFile::load(Path::new(path))?;
    let options = DesignOptions {
        method,
        runtime: platefield::work::Runtime::QUIET,
        ..DesignOptions::default()
    };
    match inverse::run(&target, &options)? {
        DesignOutcome::Method(outcome) => {
            for (k, c) in outcome.candidates.iter().enumerate() {
                let p = c.played();
                println!(
                    "{} {}: predicted strength {:.4}, realised strength {:?}, realised shape error {:?}, POOR {}",
                    if k == outcome.chosen { "kept" } else { "not kept" },
                    c.method.name(),
                    p.predicted_strength,
                    p.realised_strength,
                    p.realised_shape_error,
                    p.poor
                );
            }
            println!("choice: {:?}", outcome.choice);
            println!("{}", outcome.kept().schedule.to_json()?);
        }
        DesignOutcome::Sorted(candidates) => {
            // Unplayed: `platefield::verify::sort_play::play_sort` keeps the
            // one that sorts soonest.
            for d in &candidates {
                println!("{}: period {:.2} s", d.label(), d.schedule.period_s);
            }
        }
        DesignOutcome::ClosedLoop { closed_loop, .. } => {
            println!("closed loop: {} candidates", closed_loop.candidates.len())
        }
        DesignOutcome::Pose(pose) => {
            let played = pose.method.kept().schedule.played.as_ref();
            if let Some(drops) = played.and_then(|p| p.pose.as_ref()) {
                println!(
                    "pose: {:.1} % of {} played drops end at the pose",
                    100.0 * drops.pose_fraction,
                    drops.drops
                );
            }
            println!("{}", pose.method.kept().schedule.to_json()?);
        }
    }
    Ok(())
}
