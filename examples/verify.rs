//! Verifying a designed schedule from Rust: its realised field against the
//! prediction and where a swarm of parts ends up (what `platefield verify`
//! writes, without writing).
//!
//! `cargo run --release --example verify [-- SCHEDULE]`
//! (default `results/sequenced/sink/schedule.json`).

use std::path::Path;

use platefield::verify::{verify_schedule_file, VerifyRequest};

fn main() -> platefield::Result<()> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "results/sequenced/sink/schedule.json".into());
    let request = VerifyRequest {
        runtime: platefield::work::Runtime::QUIET,
        rectangle_poses: 0,
        ..VerifyRequest::default()
    };
    let report = verify_schedule_file(Path::new(&path), &request)?;
    println!(
        "{}: designed strength {:.4}, realised strength {:?} (the judge)",
        report.target,
        report.design_strength,
        report.judge.map(|j| j.realised_strength)
    );
    println!(
        "swarm of {} parts over {:.2} s: converged fraction {:?}, contact lost {}",
        report.swarm.parts.len(),
        report.swarm.duration_s,
        report.swarm.converged_fraction,
        report.swarm.contact_lost
    );
    Ok(())
}
