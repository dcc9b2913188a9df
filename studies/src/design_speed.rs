//! `platefield study design-speed`: what the design costs against what it
//! realises: `results/design_speed.md`.
//!
//! Every shipped target ([`TARGETS`]) is designed as `design --method auto`
//! does (`design_by_method`, default options, the basis from the cache)
//! under each of the `BUDGETS`: the synthesis's evaluation budget and
//! stall rule, the played polish's plays and stall rule. For each it writes
//! the synthesized candidate's judge — realised shape error and strength
//! (`platefield::design::judge`, what every design reports under
//! `"played"`) — and what `auto` kept. The file holds no timings, so it is deterministic;
//! wall and CPU seconds of each design go to the printed summary only (the
//! machine is shared: CPU seconds are the steadier number).
//!
//! The default refines by least squares: up to six
//! Levenberg–Marquardt steps on the coarse residuals
//! (`platefield::synth::least_squares`) and four on the played ones
//! ([`platefield::design::polish`]); the other rows take fewer steps,
//! no polish, or the Nelder–Mead path of before with its stall rules
//! (`SYNTH_STALL`, `POLISH_STALL`; its polish plays the check's
//! cycles too).

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use super::speed::process_cpu_seconds;
use platefield::design::method::{design_by_method, design_estimate, Method};
use platefield::design::DesignOptions;
use platefield::error::Result;
use platefield::output::write_atomic;
use platefield::request::Target;
use platefield::synth::levenberg::LmOptions;
use platefield::synth::progress::ProgressMode;
use platefield::synth::stall::{StallRule, POLISH_STALL, SYNTH_STALL};
use platefield::synth::{ShakerLimits, SynthOptions, POLISH_LM, SYNTH_LM};
use platefield::work::{Estimate, Term};
use platefield_report::table::Table;

/// Default output folder.
pub const DIR: &str = "results";

/// The shipped targets (`results/<target>/`).
pub const TARGETS: [&str; 8] = [
    "sink",
    "saddle",
    "squeeze_trans",
    "whirlpool",
    "jet",
    "line_sink",
    "line_sink_30",
    "sink_trans",
];

/// One budget of the synthesis and its played polish.
#[derive(Debug, Clone, Copy)]
pub struct Budget {
    /// Row label.
    pub label: &'static str,
    /// Coarse re-simulations allowed.
    pub evaluations: usize,
    /// Synthesis by least squares with these settings (`None`: Nelder–Mead).
    pub lm: Option<LmOptions>,
    /// Synthesis stall rule.
    pub synth_stall: Option<StallRule>,
    /// Plays of the played polish (0: none).
    pub plays: usize,
    /// Polish by least squares with these settings (`None`: Nelder–Mead).
    pub polish_lm: Option<LmOptions>,
    /// Polish stall rule.
    pub polish_stall: Option<StallRule>,
}

/// `lm` with at most `steps` steps.
const fn steps(lm: LmOptions, steps: usize) -> LmOptions {
    LmOptions {
        max_iterations: steps,
        ..lm
    }
}

/// The budgets compared: the default first, then cheaper ones, then the
/// Nelder–Mead path (`SynthOptions::lm` `None`) with its stall rules.
pub(crate) const BUDGETS: [Budget; 5] = [
    Budget {
        label: "least squares 6+4 (default)",
        evaluations: 300,
        lm: Some(SYNTH_LM),
        synth_stall: None,
        plays: 300,
        polish_lm: Some(POLISH_LM),
        polish_stall: None,
    },
    Budget {
        label: "least squares 6, no polish",
        evaluations: 300,
        lm: Some(SYNTH_LM),
        synth_stall: None,
        plays: 0,
        polish_lm: Some(POLISH_LM),
        polish_stall: None,
    },
    Budget {
        label: "least squares 3+2",
        evaluations: 300,
        lm: Some(steps(SYNTH_LM, 3)),
        synth_stall: None,
        plays: 300,
        polish_lm: Some(steps(POLISH_LM, 2)),
        polish_stall: None,
    },
    Budget {
        label: "least squares 1+1",
        evaluations: 300,
        lm: Some(steps(SYNTH_LM, 1)),
        synth_stall: None,
        plays: 300,
        polish_lm: Some(steps(POLISH_LM, 1)),
        polish_stall: None,
    },
    Budget {
        label: "Nelder–Mead stall 60/40",
        evaluations: 300,
        lm: None,
        synth_stall: Some(SYNTH_STALL),
        plays: 300,
        polish_lm: None,
        polish_stall: Some(POLISH_STALL),
    },
];

impl Budget {
    /// The synthesis options of this budget (quiet).
    fn synthesis(&self) -> SynthOptions {
        SynthOptions {
            max_evaluations: self.evaluations,
            lm: self.lm,
            polish_lm: self.polish_lm,
            stall: self.synth_stall,
            polish_plays: self.plays,
            polish_stall: self.polish_stall,
            progress: ProgressMode::Quiet,
            ..SynthOptions::default()
        }
    }
}

/// The work of the study over the shipped targets `names` (every budget
/// of each): the sum of the work each design states before its synthesis
/// ([`platefield::design::method::design_estimate`], on the target's own
/// shaker limits or the envelope; the basis read from the warm cache).
///
/// # Errors
/// A target file that does not load.
pub fn estimate(names: &[String]) -> Result<Estimate> {
    let mut total = Estimate::new("--targets", "the design-speed study", "fewer --targets");
    for name in names {
        let target = Target::load(&Path::new("targets").join(format!("{name}.json")))?;
        let sampled = target.sample()?;
        let limits = ShakerLimits::from_spec(target.shaker.as_ref());
        for b in &BUDGETS {
            let opts = DesignOptions::default();
            let e = design_estimate(
                &target,
                &sampled,
                &b.synthesis(),
                &opts,
                Method::Auto,
                &limits,
                None,
                None,
            );
            let label = format!("{name}, {}", b.label);
            total = total.plus(Term::new(label).times(e.steps(), "steps"));
        }
    }
    Ok(total)
}

/// One target under one budget.
#[derive(Debug, Clone)]
pub struct Row {
    /// Target name.
    pub target: String,
    /// Budget label.
    pub budget: &'static str,
    /// Synthesized candidate: the judge's realised shape error and strength
    /// (None when the synthesis failed or was not judged).
    pub synthesized: Option<(Option<f64>, Option<f64>)>,
    /// Kept method, the judge's realised shape error and strength.
    pub kept: (String, Option<f64>, Option<f64>),
    /// Wall seconds of the design (printed only).
    pub seconds: f64,
    /// CPU seconds of the design over all threads (printed only).
    pub cpu_seconds: Option<f64>,
    /// The work `design` states before its synthesis (RK4 point-part
    /// steps, [`platefield::design::method::design_estimate`]).
    pub estimated_steps: f64,
    /// The nominal point-part steps the engine took
    /// ([`platefield::dynamics::steps_taken`]).
    pub counted_steps: u64,
}

/// Designs `target` (auto) under `budget`, the basis cached in `cache`.
///
/// # Errors
/// The design fails.
pub fn row(target: &Target, budget: &Budget, cache: &Path) -> Result<Row> {
    let synthesis = budget.synthesis();
    let steps0 = platefield::dynamics::steps_taken();
    let cpu0 = process_cpu_seconds();
    let clock = Instant::now();
    let opts = DesignOptions {
        method: Method::Auto,
        synthesis,
        ..DesignOptions::cached_quiet(cache)
    };
    let m = design_by_method(target, &opts)?;
    let seconds = clock.elapsed().as_secs_f64();
    let counted_steps = platefield::dynamics::steps_taken() - steps0;
    let estimated_steps = m.estimate.steps();
    let cpu_seconds = cpu0.zip(process_cpu_seconds()).map(|(a, b)| b - a);
    let synthesized = m
        .candidates
        .iter()
        .find(|c| c.method == Method::Synthesize)
        .map(|c| {
            let p = c.played();
            (p.realised_shape_error, p.realised_strength)
        });
    let k = m.kept().played();
    Ok(Row {
        target: target.name.clone(),
        budget: budget.label,
        synthesized,
        kept: (
            m.kept().method.name().to_string(),
            k.realised_shape_error,
            k.realised_strength,
        ),
        seconds,
        cpu_seconds,
        estimated_steps,
        counted_steps,
    })
}

/// Builds (or reads) `target`'s basis library into `cache`.
fn warm_cache(target: &Target, cache: &Path) -> Result<()> {
    let opts = DesignOptions::cached_quiet(cache);
    platefield::design::design(target, &opts).map(|_| ())
}

fn pct(x: Option<f64>) -> String {
    platefield::design::method::percent(x)
}

fn strength(x: Option<f64>) -> String {
    platefield::design::method::number(x)
}

/// The markdown table (no timings).
pub(crate) fn markdown(rows: &[Row]) -> String {
    let mut s = String::from(
        "# Design cost against the judge (issue 27)\n\n\
         Written by `platefield study design-speed` (`studies/src/design_speed.rs` says how). \
         Every shipped target designed by `design --method auto` under each budget; \
         the judge's realised shape error and strength (s⁻¹; `docs/measures.md`); the work `design` \
         estimates before it starts and the work the engine counted (nominal RK4 point-part \
         steps, `platefield::dynamics::steps_taken`; the basis read from a warm cache), and \
         their ratio (issue 30: within 3×). Timings, and the seconds per counted step that \
         turn work into time, are printed by the command, never written here.\n\n",
    );
    let mut table = Table::new([
        "target",
        "budget",
        "synthesized shape",
        "synthesized strength",
        "kept",
        "kept shape",
        "kept strength",
        "estimated steps",
        "counted steps",
        "estimated / counted",
    ]);
    for r in rows {
        let (ss, st) = r
            .synthesized
            .map_or(("—".to_string(), "—".to_string()), |(e, s)| {
                (pct(e), strength(s))
            });
        table.row([
            r.target.clone(),
            r.budget.to_string(),
            ss,
            st,
            r.kept.0.to_string(),
            pct(r.kept.1),
            strength(r.kept.2),
            format!("{:.3e}", r.estimated_steps),
            format!("{:.3e}", r.counted_steps as f64),
            format!(
                "{:.2}",
                r.estimated_steps / (r.counted_steps as f64).max(1.0)
            ),
        ]);
    }
    s.push_str(&table.markdown());
    s
}

/// Runs the study on `targets` (all of [`TARGETS`] when empty) and writes
/// `design_speed.md` under `out`; returns the summary with the times.
///
/// # Errors
/// A target fails to load or design; the file cannot be written.
pub fn run(out: &Path, targets: &[String]) -> Result<String> {
    let names: Vec<String> = if targets.is_empty() {
        TARGETS.iter().map(|s| s.to_string()).collect()
    } else {
        targets.to_vec()
    };
    let cache = Path::new(".platefield-cache");
    let mut rows = Vec::new();
    let mut summary = String::from("design-speed (wall and CPU seconds; shared machine):\n");
    for name in &names {
        let target = Target::load(&Path::new("targets").join(format!("{name}.json")))?;
        // The basis in the cache first, so that every row's work is the
        // same whatever the cache held before.
        warm_cache(&target, cache)?;
        for b in &BUDGETS {
            let r = row(&target, b, cache)?;
            let _ = writeln!(
                summary,
                "  {:<14} {:<24} {:>6.1} s wall {:>6} s CPU ({} µs per counted step; estimated {:.2e}, counted {:.2e} steps)  synthesized {} at {}, kept {} {} at {}",
                r.target,
                r.budget,
                r.seconds,
                r.cpu_seconds.map_or("—".into(), |c| format!("{c:.1}")),
                r.cpu_seconds.map_or("—".into(), |c| format!(
                    "{:.2}",
                    1e6 * c / (r.counted_steps as f64).max(1.0)
                )),
                r.estimated_steps,
                r.counted_steps as f64,
                r.synthesized.map_or("—".into(), |(e, _)| pct(e)),
                r.synthesized.map_or("—".into(), |(_, s)| strength(s)),
                r.kept.0,
                pct(r.kept.1),
                strength(r.kept.2)
            );
            rows.push(r);
        }
    }
    let path = out.join("design_speed.md");
    write_atomic(&path, markdown(&rows).as_bytes())?;
    let _ = writeln!(summary, "wrote {}", path.display());
    Ok(summary)
}
