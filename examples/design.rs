//! Designing a target file from Rust through the one door,
//! `platefield::design::run`, and writing nothing: the kept candidate's
//! realised check and its schedule.
//!
//! `cargo run --release --example design [-- TARGET [METHOD]]`
//! (default `targets/sink.json`, `sequence`; METHOD one of sequence,
//! synthesize, auto, mix, mirror).

use std::path::Path;

use platefield::design::{self, DesignOptions, DesignOutcome, Method};
use platefield::request::Target;

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
    let target = Target::load(Path::new(path))?;
    let options = DesignOptions {
        method,
        runtime: platefield::work::Runtime::QUIET,
        ..DesignOptions::default()
    };
    match design::run(&target, &options)? {
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
        DesignOutcome::Sorted(sort) => println!("{}", sort.schedule.to_json()?),
        DesignOutcome::ClosedLoop { closed_loop, .. } => {
            println!("closed loop: {} candidates", closed_loop.candidates.len())
        }
    }
    Ok(())
}
