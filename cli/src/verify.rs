//! `platefield verify`: arguments and the [`VerifyRequest`] they build.

use std::path::PathBuf;

use clap::Args;

use super::values::ModelChoice;
use super::{AllowLong, Play, Quiet};
use platefield::verify::friction::FrictionArg;
use platefield::verify::{Duration, VerifyRequest};
use platefield::{Error, Result};
use platefield_report as report;

/// Arguments of `platefield verify`.
#[derive(Args)]
pub struct VerifyArgs {
    /// A schedule.json written by `design`.
    pub schedule: PathBuf,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub play: Play,
    /// Swarm: point parts per side of the N×N grid over the target region.
    #[arg(long, default_value_t = 9)]
    pub swarm: usize,
    /// Swarm duration in seconds (rounded up to whole schedule periods); default: long enough to converge by the design's strength (a sort's class swarms: at least 90 s, 60 s judged and 30 s held, as `design` plays them).
    #[arg(long, allow_negative_numbers = true)]
    pub duration: Option<f64>,
    /// Swarm duration in schedule periods.
    #[arg(long)]
    pub repetitions: Option<u32>,
    /// Convergence tolerance on the distance to the target's attractor (m).
    #[arg(long, default_value_t = 0.003, allow_negative_numbers = true)]
    pub tol: f64,
    /// Rectangle size LENGTHxWIDTH in metres.
    #[arg(long, default_value = "0.02x0.005")]
    pub rect: String,
    /// Rectangle start poses (0: no rectangles).
    #[arg(long, default_value_t = 4)]
    pub rect_poses: usize,
    /// Output folder; writes `OUT/<target>/verify/{summary.json, trajectories.svg}`. Default: beside the schedule, in `verify/` next to it.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Parts' friction: MU plays everything at μ_s = μ_k = MU; LO:HI:N also sweeps the design's judge over N values (table and plot in verify/). Default: the schedule's own.
    #[arg(long, allow_negative_numbers = true)]
    pub friction: Option<String>,
    /// The schedule's exported CSV (`platefield export`), or an accelerometer recording of it (a header-less CSV of t and the six channels, or the six with --rate; averaged cycle by cycle onto the export's grid): also plays the file's held samples on the same parts by the design's judge and prints both (schedule played, export replayed); for a sort's schedule (a target with classes) also every class's swarm at its own friction, with the time to sort, at own attractor, mixed up and lost contact.
    #[arg(long, value_name = "EXPORT.csv")]
    pub replay: Option<PathBuf>,
    /// The rate (samples/s) of a `--replay` recording whose rows hold the six channels without t (a header-less CSV; with t first, the times give it).
    #[arg(long, allow_negative_numbers = true)]
    pub rate: Option<f64>,
    /// Judge the schedule under the shaker's delivery error: each channel's harmonics off by up to AMPLITUDE (a fraction, ≤ 0.5) and PHASE_DEG degrees (≤ 45), seeded random draws (--draws), at the friction where the design's worst case falls; without a value, the target's shaker.tolerance.
    #[arg(long, value_name = "AMPLITUDE:PHASE_DEG", num_args = 0..=1, default_missing_value = "")]
    pub tolerance: Option<String>,
    /// Delivery-error draws of --tolerance.
    #[arg(long, default_value_t = platefield::design::tolerance::DEFAULT_DRAWS as u64, value_parser = clap::value_parser!(u64).range(1..=10_000))]
    pub draws: u64,
    /// Print the summary JSON on stdout.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub long: AllowLong,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub quiet: Quiet,
}

/// `--rect LENGTHxWIDTH` (metres).
pub fn rect_size(text: &str) -> Result<[f64; 2]> {
    let bad = || {
        Error::invalid(
            "--rect",
            format!("expected LENGTHxWIDTH in metres, e.g. 0.02x0.005, got \"{text}\""),
        )
    };
    let (l, w) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let l: f64 = l.trim().parse().map_err(|_| bad())?;
    let w: f64 = w.trim().parse().map_err(|_| bad())?;
    Ok([l, w])
}

/// `--tolerance`'s value: empty for the target's own, else
/// `AMPLITUDE:PHASE_DEG`.
fn tolerance(text: &str) -> Result<Option<platefield::request::Tolerance>> {
    if text.is_empty() {
        return Ok(None);
    }
    let bad = || {
        Error::invalid(
            "--tolerance",
            format!("must be AMPLITUDE:PHASE_DEG (e.g. 0.05:5), got {text:?}"),
        )
    };
    let (a, p) = text.split_once(':').ok_or_else(bad)?;
    let t = platefield::request::Tolerance {
        amplitude: a.trim().parse().map_err(|_| bad())?,
        phase_deg: p.trim().parse().map_err(|_| bad())?,
    };
    t.validate("--tolerance")
        .map_err(|e| Error::invalid("--tolerance", e.to_string()))?;
    Ok(Some(t))
}

impl VerifyArgs {
    /// The verification request these arguments ask for.
    pub fn request(&self) -> Result<VerifyRequest> {
        let duration = match (self.duration, self.repetitions) {
            (Some(_), Some(_)) => {
                return Err(Error::invalid(
                    "--duration",
                    "give either --duration or --repetitions, not both",
                ))
            }
            (Some(s), None) => Duration::Seconds(s),
            (None, Some(n)) => Duration::Repetitions(n),
            (None, None) => Duration::Auto,
        };
        Ok(VerifyRequest {
            points: self.play.points,
            warmup: self.play.warmup,
            periods: self.play.periods,
            model: match self.play.model {
                Some(ModelChoice::Model(m)) => Some(m),
                _ => None,
            },
            rung_tolerance: (self.play.model == Some(ModelChoice::Auto))
                .then_some(platefield::field::rung::DEFAULT_RUNG_TOLERANCE),
            swarm: self.swarm,
            duration,
            tol: self.tol,
            rectangle: rect_size(&self.rect)?,
            rectangle_poses: self.rect_poses,
            runtime: platefield::work::Runtime {
                quiet: self.quiet.quiet,
                allow_long: self.long.allow_long,
            },
            friction: self
                .friction
                .as_deref()
                .map(FrictionArg::parse)
                .transpose()?,
            replay: self.replay.clone(),
            replay_rate: self.rate,
            tolerance: self.tolerance.as_deref().map(tolerance).transpose()?,
            draws: self.draws as usize,
        })
    }

    /// Verifies the schedule, writes the report files and returns the summary to print.
    pub fn run(&self) -> Result<String> {
        report::verify::run(
            &self.schedule,
            &self.request()?,
            self.out.as_deref(),
            self.json,
        )
    }
}
