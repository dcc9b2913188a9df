//! Exporting a schedule for a shaker controller from Rust: the six
//! plate-centre acceleration signals as CSV samples (what
//! `platefield export` prints).
//!
//! `cargo run --release --example export [-- SCHEDULE [RATE_HZ]] > signals.csv`
//! (default `results/sink/schedule.json` at 5000 Hz).

use std::path::Path;

use platefield::schedule::export::{export, DEFAULT_STEADY_CYCLES};
use platefield::schedule::Schedule;

fn main() -> platefield::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args
        .first()
        .map_or("results/sink/schedule.json", String::as_str);
    let rate: f64 = match args.get(1) {
        Some(r) => r
            .parse()
            .map_err(|_| platefield::Error::invalid("RATE_HZ", format!("not a number: {r}")))?,
        None => 5000.0,
    };
    let schedule = Schedule::load(Path::new(path))?;
    let signals = export(&schedule, rate, DEFAULT_STEADY_CYCLES)?;
    print!("{}", signals.to_csv());
    Ok(())
}
