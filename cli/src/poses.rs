//! `platefield poses PART.json SOURCE.json`: where a part comes to rest in
//! a field, in which orientation, and from how many drops each
//! ([`platefield::pose::poses`] analyses; this shell writes and prints).

use std::path::Path;

use platefield::output::write_all_atomic;
use platefield::pose::{poses, PoseRequest};
use platefield::{Error, Result};
use platefield_report::poses::{picture, summary, to_json, Extras};

/// Runs the analysis and writes `poses.json` and `poses.svg` into `out`
/// (when given); returns the JSON with `json`, else a summary.
pub fn run(
    part: &Path,
    source: &Path,
    drops: usize,
    play: Option<f64>,
    json: bool,
    out: Option<&Path>,
    allow_long: bool,
) -> Result<String> {
    platefield::pose::check_counts(drops, play)?;
    if let Some(dir) = out {
        platefield::output::check_writable(dir, "--out")?;
    }
    let o = poses(&PoseRequest {
        part: part.to_path_buf(),
        source: source.to_path_buf(),
        drops,
        play,
        runtime: platefield::work::Runtime {
            quiet: false,
            allow_long,
        },
    })?;
    let extras = Extras {
        played: o.played.as_ref(),
        bounds: o.bounds.as_deref(),
        lift_check: o.lift_check.as_ref(),
        refined: o.refined.as_deref(),
        averaged_skipped: o.averaged_skipped.as_deref(),
    };
    let mut text = serde_json::to_string_pretty(&to_json(&o.part, &o.analysis, &extras))
        .map_err(|e| Error::Physical(e.to_string()))?;
    text.push('\n');
    let mut summary = summary(&o.part, &o.analysis, &extras);
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
