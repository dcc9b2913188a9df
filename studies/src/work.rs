//! The work of a study, stated before it runs and followed while it runs
//! (every command that can take more than 10 s says so first and shows
//! progress on stderr).
//!
//! A study's inputs are fixed — the shipped targets and its own settings —
//! so its engine work is a fixed count of the steps the engine takes
//! ([`platefield::dynamics::steps_taken`]: RK4 point-part steps, and planar
//! steps of each support point). [`EXPECTED_STEPS`] holds each study's
//! count as measured when its results were last regenerated, with its
//! cost in [`platefield::work`]'s unit; the study
//! states it as an [`Estimate`] before it starts, shows progress against
//! it, and prints the count it took when it ends, so a stale entry shows.
//!
//! A study run with other inputs states its own model ([`Expected`]):
//! `study primitives` scales its count by the field terms of its grid and steps
//! (`primitives::work_factor`); `study poses --play-drops N` adds the
//! drops' planar work (`poses::played_drops_estimate`); `design-speed
//! --targets` sums the work each design states
//! (`design_speed::estimate`); `study synthesis --rows/--harmonics/…` takes its
//! rows' share of the count times the settings' ratio
//! (`synthesis::expected`); `study rungs` computes every rung whatever its
//! tolerance, the same work.

use platefield::error::Result;
use platefield::progress::{Progress, ProgressMode};
use platefield::work::{with_counted_progress, Estimate, Term, PLANAR_POINT_STEP_COST};

/// Steps each study's command took with its defaults when its results
/// were last regenerated (printed by [`watched`] at its end), and the
/// point-part steps one of them costs: 1 for studies of point parts (RK4
/// steps), [`PLANAR_POINT_STEP_COST`] for `study poses` and `study
/// poses-friction` and `study pose-family`, whose steps are mostly planar support-point steps of
/// their pose targets' drops (the pose targets' cycles the most of it;
/// `study poses-friction`'s two targets designed for a friction range
/// reuse their own play for their middle rows). `study design-speed`'s
/// count is the sum of `results/design_speed.md`'s counted column (its
/// basis is read from a warm cache after the first design). `study
/// robust`'s count is of the run with `auto` within the envelope over a
/// range, and within the sequenced peaks where the envelope's candidates
/// do not hold it; `study robust-family`'s likewise.
pub const EXPECTED_STEPS: &[(&str, f64, f64)] = &[
    ("reproduce", 9.75e5, 1.0),
    ("rungs", 1.64e6, 1.0),
    ("rungs-auto", 2.87e6, 1.0),
    ("primitives", 1.70e6, 1.0),
    ("feeder", 1.84e6, 1.0),
    ("interaction", 4.29e6, 1.0),
    ("fit-quality", 1.96e7, 1.0),
    ("engine-speed", 1.31e7, 1.0),
    ("speed", 2.71e7, 1.0),
    ("squeeze-order", 9.73e7, 1.0),
    ("flight-strength", 2.38e8, 1.0),
    ("synthesis", 3.46e8, 1.0),
    ("probes", 3.81e8, 1.0),
    ("design-speed", 1.07e9, 1.0),
    ("sort", 3.98e9, 1.0),
    ("robust", 2.85e9, 1.0),
    ("robust-knobs", 3.44e9, 1.0),
    ("robust-family", 6.75e9, 1.0),
    ("poses-study", 5.34e9, PLANAR_POINT_STEP_COST),
    ("poses-friction-study", 1.87e10, PLANAR_POINT_STEP_COST),
    ("pose-family", 3.05e10, PLANAR_POINT_STEP_COST),
];

/// Study `name`'s entry of [`EXPECTED_STEPS`]: its steps and their cost.
fn entry(name: &str) -> Option<(f64, f64)> {
    EXPECTED_STEPS
        .iter()
        .find(|(n, ..)| *n == name)
        .map(|&(_, steps, cost)| (steps, cost))
}

/// What one run of a study is expected to take: the estimate it states
/// before it starts and the engine steps its progress counts towards.
///
/// ```
/// use platefield_studies::work::Expected;
/// let defaults = Expected::defaults("rungs").expect("a recorded count");
/// let twice = Expected::scaled("rungs", 2.0, "a model").unwrap();
/// assert_eq!(twice.steps, 2.0 * defaults.steps);
/// assert_eq!(twice.estimate.steps(), 2.0 * defaults.estimate.steps());
/// ```
#[derive(Debug, Clone)]
pub struct Expected {
    /// The estimate, in [`platefield::work`]'s point-part steps.
    pub estimate: Estimate,
    /// The engine steps ([`platefield::dynamics::steps_taken`]) it counts.
    pub steps: f64,
}

impl Expected {
    /// Study `name` run with its defaults: the count of its last
    /// regeneration ([`EXPECTED_STEPS`]).
    pub fn defaults(name: &str) -> Option<Expected> {
        Expected::scaled(name, 1.0, "")
    }

    /// Study `name` run with inputs its own `model` says scale its default
    /// work by `factor` (the model named in the estimate; empty: none).
    pub fn scaled(name: &str, factor: f64, model: &str) -> Option<Expected> {
        let (steps, cost) = entry(name)?;
        let mut term = Term::new("its last regeneration").times(steps, "steps");
        if !model.is_empty() {
            term = term.times(factor, model);
        }
        Some(Expected {
            estimate: Estimate::new(name, &format!("the {name} study"), "—")
                .plus(term.times(cost, "point steps per step")),
            steps: steps * factor,
        })
    }

    /// The library's own `estimate` of the study's work, each counted
    /// step costing `cost` point-part steps.
    pub fn estimated(estimate: Estimate, cost: f64) -> Expected {
        Expected {
            steps: estimate.steps() / cost,
            estimate,
        }
    }

    /// This and the library's estimate `more` (each of its counted steps
    /// costing `cost` point-part steps).
    pub fn plus(mut self, more: Estimate, cost: f64) -> Expected {
        self.steps += more.steps() / cost;
        for term in more.terms {
            self.estimate = self.estimate.plus(term);
        }
        self
    }
}

/// The estimate of study `name` with its defaults, if its count is known.
pub fn estimate(name: &str) -> Option<Estimate> {
    Expected::defaults(name).map(|e| e.estimate)
}

/// Runs study `name` (`f`) with its `expected` work stated first and
/// progress in thousands of counted steps on stderr, unless `quiet`; the
/// count it took is printed at the end. `None`: no estimate is known for
/// these inputs (progress without a total).
pub fn watched<T>(
    name: &str,
    expected: Option<Expected>,
    quiet: bool,
    f: impl FnOnce() -> Result<T>,
) -> Result<T> {
    if let Some(e) = &expected {
        e.estimate
            .announce(platefield::progress::ProgressMode::quiet_if(quiet));
    }
    let total = expected.map_or(0, |e| (e.steps / 1e3).ceil() as u64);
    let progress = Progress::new(name, "k steps", total, ProgressMode::quiet_if(quiet));
    let before = platefield::dynamics::steps_taken();
    let out = with_counted_progress(&progress, f);
    if !quiet {
        let counted = platefield::dynamics::steps_taken() - before;
        eprintln!("{name}: took {counted} steps (expected: {total} k)");
    }
    out
}

/// [`watched`] with the study's defaults: the count of its last
/// regeneration ([`Expected::defaults`]).
pub fn watched_defaults<T>(name: &str, quiet: bool, f: impl FnOnce() -> Result<T>) -> Result<T> {
    watched(name, Expected::defaults(name), quiet, f)
}
