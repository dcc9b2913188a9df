//! `platefield poses PART.json SOURCE.json`: where a part comes to rest in
//! a field, in which orientation, and from how many drops each
//! ([`platefield::pose::poses`] analyses; this shell reads the arguments,
//! writes and prints).

use std::path::PathBuf;

use clap::Args;

use platefield::output::write_all_atomic;
use platefield::pose::{poses, AnalysisRequest};
use platefield::scene::FrictionSpec;
use platefield::{Error, Result};
use platefield_report::poses::{
    over_friction_json, over_friction_lines, picture, summary, to_json, Extras,
};

/// `platefield poses PART SOURCE`.
#[derive(Args)]
pub struct PosesArgs {
    /// The part file (targets/parts/*.json).
    pub part: PathBuf,
    /// A target (its requested field), a scene (its velocity field) or a designed schedule (the time-weighted field of its segments).
    pub source: PathBuf,
    /// Random drops for the basin fractions.
    #[arg(long, default_value_t = 200)]
    pub drops: usize,
    /// Also play every drop with the planar simulator for this many seconds through the schedule (schedule sources only) and report the played basins.
    #[arg(long)]
    pub play: Option<f64>,
    /// The parts' friction: MU, or LO:HI answered at its low end, middle and high end (scenes and schedules; default: the source's own).
    #[arg(long)]
    pub friction: Option<String>,
    /// Write poses.json and poses.svg into this folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub json: super::Json,
    /// No progress for work expected to take less than 10 s (longer work states its estimate and shows its progress on stderr anyway).
    #[arg(long)]
    pub quiet: bool,
    #[command(flatten)]
    pub long: super::AllowLong,
}

impl PosesArgs {
    /// Runs the analysis and writes `poses.json` and `poses.svg` into
    /// `--out` (when given); returns the JSON with `--json`, else a
    /// summary.
    pub fn run(&self) -> Result<String> {
        platefield::pose::check_counts(self.drops, self.play)?;
        let friction = (self.friction.as_deref())
            .map(|f| FrictionSpec::parse_arg(f, "--friction"))
            .transpose()?;
        if let Some(dir) = &self.out {
            platefield::output::check_writable(dir, "--out")?;
        }
        let o = poses(&AnalysisRequest {
            part: self.part.clone(),
            source: self.source.clone(),
            drops: self.drops,
            play: self.play,
            friction,
            runtime: platefield::work::Runtime {
                quiet: self.quiet,
                allow_long: self.long.allow_long,
            },
        })?;
        write(&o, self.json.json, self.out.as_deref())
    }
}

/// The outcome's JSON and picture written into `out` (when given); the
/// JSON with `json`, else the summary.
fn write(
    o: &platefield::pose::PoseOutcome,
    json: bool,
    out: Option<&std::path::Path>,
) -> Result<String> {
    let extras = Extras {
        played: o.played.as_ref(),
        bounds: o.bounds.as_deref(),
        lift_check: o.lift_check.as_ref(),
        played_rests: o.played_rests.as_deref(),
        averaged_skipped: o.averaged_skipped.as_deref(),
    };
    let mut value = to_json(&o.part, &o.analysis, &extras);
    if !o.over_friction.is_empty() {
        value["over_friction"] = over_friction_json(&o.over_friction);
    }
    let mut text =
        serde_json::to_string_pretty(&value).map_err(|e| Error::Internal(e.to_string()))?;
    text.push('\n');
    let mut summary = summary(&o.part, &o.analysis, &extras);
    summary.push_str(&over_friction_lines(&o.over_friction));
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).map_err(|e| Error::Io {
            path: dir.display().to_string(),
            source: e,
        })?;
        let svg = picture(&o.part, &o.analysis);
        let (jp, sp) = (dir.join("poses.json"), dir.join("poses.svg"));
        write_all_atomic(&[(&jp, text.as_bytes()), (&sp, svg.as_bytes())])?;
        summary.push_str(&format!("wrote {}\nwrote {}\n", jp.display(), sp.display()));
    }
    Ok(if json { text } else { summary })
}
