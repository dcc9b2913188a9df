//! The work of a study, stated before it runs and followed while it runs
//! (issue 30: every command that can take more than 10 s says so first
//! and shows progress on stderr).
//!
//! A study's inputs are fixed — the shipped targets and its own settings —
//! so its engine work is a fixed count of the steps the engine takes
//! ([`crate::dynamics::steps_taken`]: RK4 point-part steps, and planar
//! steps of each support point). [`EXPECTED_STEPS`] holds each study's
//! count as measured when its results were last regenerated; the study
//! states it as an [`Estimate`] before it starts, shows progress against
//! it, and prints the count it took when it ends, so a stale entry shows.

use crate::error::Result;
use crate::progress::{Progress, ProgressMode};
use crate::work::{with_counted_progress, Estimate, Term};

/// Steps each study's command took with its defaults when its results
/// were last regenerated (printed by [`watched`] at its end). Missing:
/// `poses-study`, whose work is mostly the lifted field's quadrature, which
/// the engine does not count (1.3e5 steps in 12 s of CPU).
pub const EXPECTED_STEPS: &[(&str, f64)] = &[
    ("reproduce", 9.75e5),
    ("rungs", 1.64e6),
    ("primitives", 1.70e6),
    ("interaction", 4.29e6),
    ("fit-quality", 6.46e6),
    ("engine-speed", 1.31e7),
    ("speed", 2.71e7),
    ("squeeze-order", 9.73e7),
];

/// The estimate of study `name`, if its count is known.
pub fn estimate(name: &str) -> Option<Estimate> {
    let (_, steps) = EXPECTED_STEPS.iter().find(|(n, _)| *n == name)?;
    Some(
        Estimate::new(name, &format!("the {name} study"), "—")
            .plus(Term::new("its last regeneration").times(*steps, "steps")),
    )
}

/// Runs study `name` (`f`) with its estimate stated first (when it runs
/// with its `defaults`, the inputs the count was measured on) and progress
/// in thousands of counted steps on stderr, unless `quiet`; the count it
/// took is printed at the end.
pub fn watched<T>(
    name: &str,
    defaults: bool,
    quiet: bool,
    f: impl FnOnce() -> Result<T>,
) -> Result<T> {
    let estimate = estimate(name).filter(|_| defaults);
    if let Some(e) = &estimate {
        e.announce(quiet);
    }
    let total = estimate.map_or(0, |e| (e.steps() / 1e3).ceil() as u64);
    let progress = Progress::new(name, "k steps", total, ProgressMode::quiet_if(quiet));
    let before = crate::dynamics::steps_taken();
    let out = with_counted_progress(&progress, f);
    if !quiet {
        let counted = crate::dynamics::steps_taken() - before;
        eprintln!("{name}: took {counted} steps (expected: {total} k)");
    }
    out
}
