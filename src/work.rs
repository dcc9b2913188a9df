//! Work estimates before long computations: every command that
//! may run for long (`field`, a `design`'s library build, `verify`,
//! `order`) first counts the RK4 steps of point parts it is about to take,
//! converts them to seconds at a stated rate, and refuses above
//! `LIMIT_S` unless `--allow-long` is given, naming the knobs that make
//! the work smaller. One estimator, here; the callers only supply counts.
//!
//! The unit of work is one RK4 step of one point part (`SECONDS_PER_STEP`
//! on one core); a planar step of one support point (rectangles, parts
//! dropped by `poses`) costs [`PLANAR_POINT_STEP_COST`] point-part steps;
//! a steady-state velocity sample costs `VELOCITY_CYCLES` cycles. The
//! counts are plain `f64` products, so no count from user input can
//! overflow (a `cycles: 1e9` schedule is an estimate of 1e9 × …, not a wrap
//! to a small number).

use std::fmt::Write as _;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};
use crate::field::{FieldKind, FieldSettings};
use crate::progress::Progress;

/// Why an iterative loop ended: one vocabulary for the loops of the
/// design (the Levenberg–Marquardt runs of the synthesis and the polish,
/// the closed loop's re-fits).
///
/// ```
/// use platefield::work::Stop;
/// assert_eq!(Stop::NoGain.to_string(), "no gain");
/// assert_eq!(serde_json::to_string(&Stop::NotRun).unwrap(), "\"not_run\"");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stop {
    /// The last step changed nothing that counts: an improvement below
    /// the loop's tolerance, or a point already visited.
    Converged,
    /// The loop's iteration cap.
    Iterations,
    /// Steps in a row that did not improve the best so far.
    NoGain,
    /// The caller's budget (evaluations, time) was spent.
    Spent,
    /// No iteration was asked for.
    NotRun,
    /// A step could not be computed; the best so far is kept.
    Failed,
}

impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Stop::Converged => "converged",
            Stop::Iterations => "iteration cap",
            Stop::NoGain => "no gain",
            Stop::Spent => "budget spent",
            Stop::NotRun => "not run",
            Stop::Failed => "failed",
        })
    }
}

/// How a long computation runs, not what it computes: its progress output
/// and the long-run guard. One section shared by the design, `verify`,
/// `order`, `field` and `poses` requests.
///
/// ```
/// use platefield::work::Runtime;
/// let r = Runtime { quiet: true, ..Runtime::default() };
/// assert!(!r.allow_long);
/// assert_eq!(r.progress(), platefield::progress::ProgressMode::Quiet);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Runtime {
    /// No progress output (default: progress on stderr).
    pub quiet: bool,
    /// Run even when the work estimate exceeds `LIMIT_S`.
    pub allow_long: bool,
}

impl Runtime {
    /// No progress output, the long-run guard on.
    pub const QUIET: Runtime = Runtime {
        quiet: true,
        allow_long: false,
    };

    /// The progress mode these settings ask for.
    pub fn progress(&self) -> crate::progress::ProgressMode {
        crate::progress::ProgressMode::quiet_if(self.quiet)
    }

    /// [`Estimate::check`] of `estimate` under this long-run guard.
    pub(crate) fn check(&self, estimate: &Estimate) -> Result<()> {
        estimate.check(self.allow_long)
    }

    /// [`Estimate::admit`] of `estimate` under these settings: refused over
    /// the limit unless `allow_long`, then stated on stderr unless `quiet`
    /// when it is long enough.
    pub(crate) fn admit(&self, estimate: &Estimate) -> Result<()> {
        estimate.admit(self.allow_long, self.progress())
    }

    /// `Estimate::check` of `estimate` under this long-run guard, then
    /// its [`Estimate::announcement`] on stderr whenever there is one,
    /// `quiet` or not (work expected past `ANNOUNCE_S` always says so
    /// first); returns the progress mode for the work: shown unless
    /// `quiet`, and when the work is that long also under `quiet`.
    pub(crate) fn admit_stated(
        &self,
        estimate: &Estimate,
    ) -> Result<crate::progress::ProgressMode> {
        estimate.check(self.allow_long)?;
        estimate.announce(crate::progress::ProgressMode::Auto);
        let long = estimate.announcement(threads()).is_some();
        Ok(crate::progress::ProgressMode::quiet_if(self.quiet && !long))
    }
}

/// Seconds per RK4 step of one point part on one core: a stated, slightly
/// pessimistic rate, above the measured ones (`docs/commands.md`, **The
/// rates behind the estimates**).
pub(crate) const SECONDS_PER_STEP: f64 = 1.0e-6;

/// Cost of one nominal planar step of one support point in point-part
/// steps: its share of the implicit friction solve and of the halved
/// steps at stick-slip events, per nominal support-point step
/// ([`crate::dynamics::steps_taken`]'s unit for a planar body): between
/// the measured costs of `verify`'s rectangles and of `poses --play`
/// drops (`docs/commands.md`, **The rates behind the estimates**),
/// against `SECONDS_PER_STEP` per point-part step. A
/// rectangle's cost grows with its support points (`--rect 1e-9x1e-9` is
/// sampled by 16 × 16 and takes about four times as long as the default
/// 16 × 4: an estimate blind to the support points would miss that).
pub const PLANAR_POINT_STEP_COST: f64 = 0.15;

/// Expected cycle evaluations of one steady-state velocity sample (a few
/// plain iterations, then Newton steps of three cycle maps each; above
/// the measured count, `docs/commands.md`, **The rates behind the
/// estimates**).
pub(crate) const VELOCITY_CYCLES: f64 = 20.0;

/// Longest expected run accepted without `--allow-long` (seconds).
pub(crate) const LIMIT_S: f64 = 600.0;

/// Expected seconds above which a command states its estimate on stderr
/// before the work ([`Estimate::announcement`]: every command that can
/// take more than 10 s says so first).
pub(crate) const ANNOUNCE_S: f64 = 10.0;

/// One term of an estimate: a product of named counts, e.g. `8 primitives
/// × 2500 samples × 20 cycles × 64 steps`.
#[derive(Debug, Clone, PartialEq)]
pub struct Term {
    /// What the term is (e.g. "swarm").
    pub label: String,
    /// Named factors; their product is the term's RK4 steps.
    pub factors: Vec<(String, f64)>,
}

impl Term {
    /// A term named `label` with no factors yet (product 1).
    pub fn new(label: impl Into<String>) -> Term {
        Term {
            label: label.into(),
            factors: Vec::new(),
        }
    }

    /// The same term named `label`.
    pub(crate) fn named(mut self, label: &str) -> Term {
        self.label = label.to_string();
        self
    }

    /// Multiplies by `count` named `name`.
    pub fn times(mut self, count: f64, name: &str) -> Term {
        self.factors.push((name.to_string(), count));
        self
    }

    /// RK4 point-part steps of this term.
    pub fn steps(&self) -> f64 {
        self.factors.iter().map(|(_, c)| c).product()
    }
}

/// The expected work of one command: a sum of [`Term`]s.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// What is refused if the work is too long (the JSON path or argument
    /// the error names, e.g. "schedule").
    pub subject: String,
    /// What would be done (e.g. "building the velocity library").
    pub what: String,
    /// The terms summed.
    pub terms: Vec<Term>,
    /// The knobs that make the work smaller, as the user spells them.
    pub knobs: String,
}

/// Worker threads the work is spread over (rayon's pool).
pub(crate) fn threads() -> usize {
    rayon::current_num_threads().max(1)
}

impl Estimate {
    /// An estimate of `what` for `subject`, reduced by `knobs`.
    pub fn new(subject: &str, what: &str, knobs: &str) -> Estimate {
        Estimate {
            subject: subject.to_string(),
            what: what.to_string(),
            terms: Vec::new(),
            knobs: knobs.to_string(),
        }
    }

    /// Adds `term`.
    pub fn plus(mut self, term: Term) -> Estimate {
        self.terms.push(term);
        self
    }

    /// Total RK4 point-part steps.
    pub fn steps(&self) -> f64 {
        self.terms.iter().map(Term::steps).sum()
    }

    /// Expected seconds on `threads` threads at `SECONDS_PER_STEP`.
    pub(crate) fn seconds(&self, threads: usize) -> f64 {
        self.steps() * SECONDS_PER_STEP / threads.max(1) as f64
    }

    /// Whether the work exceeds [`LIMIT_S`] on `threads` threads.
    pub(crate) fn is_long(&self, threads: usize) -> bool {
        // NaN work (it cannot be NaN from finite counts) counts as long.
        self.seconds(threads).is_nan() || self.seconds(threads) > LIMIT_S
    }

    /// The estimate in words: total, terms with their factors, rate.
    pub fn describe(&self, threads: usize) -> String {
        let mut s = format!(
            "{} would take about {} ({:.2e} RK4 part steps: ",
            self.what,
            duration(self.seconds(threads)),
            self.steps()
        );
        for (i, t) in self.terms.iter().enumerate() {
            if i > 0 {
                s.push_str(" + ");
            }
            let _ = write!(s, "{} ", t.label);
            for (j, (name, c)) in t.factors.iter().enumerate() {
                if j > 0 {
                    s.push_str(" × ");
                }
                let _ = write!(s, "{} {name}", count(*c));
            }
        }
        let _ = write!(
            s,
            "; at {:.1} µs per step on {threads} thread{})",
            SECONDS_PER_STEP * 1e6,
            if threads == 1 { "" } else { "s" }
        );
        s
    }

    /// The line a command prints on stderr before work expected to take
    /// more than `ANNOUNCE_S` on `threads` threads (the estimate in words,
    /// [`Estimate::describe`]); `None` for shorter work.
    pub(crate) fn announcement(&self, threads: usize) -> Option<String> {
        let s = self.seconds(threads);
        (s.is_nan() || s > ANNOUNCE_S).then(|| self.describe(threads))
    }

    /// [`Estimate::check`], then the [`Estimate::announcement`] unless
    /// `progress` is quiet: what a command calls before long work.
    pub(crate) fn admit(
        &self,
        allow_long: bool,
        progress: crate::progress::ProgressMode,
    ) -> Result<()> {
        self.check(allow_long)?;
        self.announce(progress);
        Ok(())
    }

    /// Gives the `Estimate::announcement`, if any, to the progress
    /// observer ([`crate::progress::say`]) unless `progress` is quiet.
    pub fn announce(&self, progress: crate::progress::ProgressMode) {
        match self.announcement(threads()) {
            Some(line) if progress != crate::progress::ProgressMode::Quiet => {
                crate::progress::say(&line)
            }
            _ => {}
        }
    }

    /// `Ok` when the work is within `LIMIT_S` or `allow_long`; else an
    /// [`Error::Invalid`] naming [`Estimate::subject`], stating the
    /// estimate, the limit, the knobs and `--allow-long`.
    pub(crate) fn check(&self, allow_long: bool) -> Result<()> {
        self.check_on(threads(), allow_long)
    }

    /// [`Estimate::check`] on `threads` threads.
    pub(crate) fn check_on(&self, threads: usize, allow_long: bool) -> Result<()> {
        if allow_long || !self.is_long(threads) {
            return Ok(());
        }
        Err(Error::invalid(
            self.subject.clone(),
            format!(
                "{}, more than the limit of {}: make it smaller with {}, or pass --allow-long to run it anyway",
                self.describe(threads),
                duration(LIMIT_S),
                self.knobs
            ),
        ))
    }
}

/// Runs `f` while `progress` follows the steps the engine counts
/// ([`crate::dynamics::steps_taken`], in thousands, from their reading
/// now): progress for work whose loops the caller does not own, such as
/// drops played in parallel. `progress` should count thousands of counted
/// steps; it is read every 100 ms and finished when `f` returns.
pub fn with_counted_progress<T>(progress: &Progress, f: impl FnOnce() -> T) -> T {
    let start = crate::dynamics::steps_taken();
    let done = AtomicBool::new(false);
    let out = std::thread::scope(|scope| {
        scope.spawn(|| {
            while !done.load(Ordering::Relaxed) {
                progress.set_position((crate::dynamics::steps_taken() - start) / 1000);
                std::thread::sleep(std::time::Duration::from_millis(100));
            }
        });
        let out = f();
        done.store(true, Ordering::Relaxed);
        out
    });
    progress.finish();
    out
}

/// The term of computing `kind` fields on `samples` grid points per field,
/// `fields` fields: force fields take `settings.phases` cycles per sample,
/// steady-state velocity fields `VELOCITY_CYCLES` (at most the
/// settings' `max_iterations`).
pub fn field_term(
    label: &str,
    fields: f64,
    field_name: &str,
    samples: f64,
    kind: FieldKind,
    settings: &FieldSettings,
) -> Term {
    let (cycles, name) = match kind {
        FieldKind::Force => (settings.phases as f64, "phases"),
        FieldKind::Velocity => (
            VELOCITY_CYCLES.min(settings.numerics.max_iterations as f64),
            "cycles",
        ),
    };
    Term::new(label)
        .times(fields, field_name)
        .times(samples, "samples")
        .times(cycles, name)
        .times(settings.numerics.steps_per_cycle as f64, "steps")
}

/// A count for messages: an integer below 1e7, else in e-notation.
fn count(c: f64) -> String {
    if c.is_finite() && c.abs() < 1e7 && c.fract() == 0.0 {
        format!("{c:.0}")
    } else {
        format!("{c:.2e}")
    }
}

/// Seconds in words: "40 s", "12 min", "3.5 h", "2.1e5 days".
pub(crate) fn duration(s: f64) -> String {
    if !s.is_finite() {
        "an unbounded time".to_string()
    } else if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.0} min", s / 60.0)
    } else if s < 48.0 * 3600.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.2e} days", s / 86400.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn library(samples: f64) -> Estimate {
        Estimate::new(
            "target",
            "building the velocity library",
            "the target's grid n or --rotation-step",
        )
        .plus(
            Term::new("library")
                .times(8.0, "primitives")
                .times(samples, "samples")
                .times(VELOCITY_CYCLES, "cycles")
                .times(64.0, "steps"),
        )
    }

    /// A dense sampled target: 63,504 samples per primitive, 8
    /// primitives: 8 × 63504 × 20 × 64 = 6.50e8 steps, 650 s at 1 µs on
    /// one thread (325 s on two). Refused on one thread, accepted on two,
    /// and accepted on one with --allow-long.
    #[test]
    fn estimate_is_the_product_and_the_threshold_applies() {
        let e = library(63_504.0);
        assert_eq!(e.steps(), 8.0 * 63_504.0 * 20.0 * 64.0);
        assert!((e.seconds(1) - 650.28).abs() < 0.01, "{}", e.seconds(1));
        assert!((e.seconds(2) - 325.14).abs() < 0.01);
        assert!(e.is_long(1) && !e.is_long(2));
        assert!(e.check_on(2, false).is_ok());
        assert!(e.check_on(1, true).is_ok(), "--allow-long accepts");
        let err = e.check_on(1, false).unwrap_err();
        let text = err.to_string();
        for needle in [
            "target: building the velocity library would take about 11 min",
            "6.50e8 RK4 part steps",
            "library 8 primitives × 63504 samples × 20 cycles × 64 steps",
            "1.0 µs per step on 1 thread)",
            "limit of 10 min",
            "--rotation-step",
            "--allow-long",
        ] {
            assert!(text.contains(needle), "{needle:?} not in {text}");
        }
    }

    /// Sums of terms; huge counts stay finite and long (no wrap-around);
    /// the duration words.
    #[test]
    fn sums_huge_counts_and_words() {
        let e = Estimate::new("schedule", "verifying", "--points")
            .plus(Term::new("grid").times(25.0, "parts").times(2.0, "periods"))
            .plus(Term::new("swarm").times(81.0, "parts"));
        assert_eq!(e.steps(), 50.0 + 81.0);
        assert!(!e.is_long(1));
        let huge = Estimate::new("schedule", "verifying", "--points").plus(
            Term::new("swarm")
                .times(4.0 * 1e9, "cycles per period")
                .times(f64::from(u32::MAX), "periods"),
        );
        assert!(huge.is_long(2));
        assert!(huge.describe(2).contains("4.00e9 cycles per period"));
        assert_eq!(duration(30.0), "30 s");
        assert_eq!(duration(600.0), "10 min");
        assert_eq!(duration(5400.0), "90 min");
        assert_eq!(duration(3.0 * 3600.0), "3.0 h");
        assert_eq!(duration(f64::INFINITY), "an unbounded time");
    }

    /// A worked example of `work::Runtime::admit_stated`.
    #[test]
    fn example_runtime_admit_stated() -> Result<(), crate::Error> {
        use crate::progress::ProgressMode;
        use crate::work::{Estimate, Runtime, Term};
        let short = Estimate::new("--drops", "settling", "--drops")
            .plus(Term::new("a").times(1e3, "steps"));
        assert_eq!(Runtime::QUIET.admit_stated(&short)?, ProgressMode::Quiet);
        let long = Estimate::new("--drops", "settling", "--drops")
            .plus(Term::new("a").times(1e8, "steps"));
        assert_eq!(Runtime::QUIET.admit_stated(&long)?, ProgressMode::Auto);
        Ok(())
    }

    /// A worked example of `work::Term::named`.
    #[test]
    fn example_term_named() {
        use crate::work::Term;
        let t = Term::new("a").times(3.0, "parts").named("b");
        assert_eq!((t.label.as_str(), t.steps()), ("b", 3.0));
    }

    /// A worked example of `work::Estimate::announcement`.
    #[test]
    fn example_estimate_announcement() {
        use crate::work::{Estimate, Term};
        let e = Estimate::new("target", "playing", "fewer plays")
            .plus(Term::new("plays").times(1e3, "plays").times(1e5, "steps"));
        assert!(e
            .announcement(1)
            .unwrap()
            .starts_with("playing would take about"));
        assert!(e.announcement(1000).is_none());
    }
}
