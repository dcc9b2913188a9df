//! A sort's files: `schedule.json`, `sort.json` (per class: the fit and
//! the plays) and `report.md` with the per-class table and the verdict
//! against the goal (≥ [`GOAL_AT_OWN`] of each class at its own attractor,
//! ≤ [`GOAL_MIXED_UP`] mixed up), stated whether met or not.

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use super::table::Table;
use platefield::design::sort::{ClassFit, SortDesign};
use platefield::error::{Error, Result};
use platefield::output::percent;
use platefield::verify::sort_play::{ClassPlay, SORT_TOL};

/// Goal: fraction of each class's swarm at its own attractor.
pub(crate) const GOAL_AT_OWN: f64 = 0.95;
/// Goal: largest fraction of a class's swarm at another class's attractor.
pub(crate) const GOAL_MIXED_UP: f64 = 0.02;

/// What `sort.json` and `design --json`'s `played` hold.
#[derive(Debug, Clone, Serialize)]
pub(crate) struct SortReport<'a> {
    /// Per class, the stacked fit's prediction.
    pub fits: &'a [ClassFit],
    /// Per class, played.
    pub played: &'a [ClassPlay],
    /// The gentle columns offered to the fit.
    pub gentle: &'a [String],
    /// Whether every class met the goal.
    pub goal_met: bool,
}

/// Whether every class met the goal.
pub(crate) fn goal_met(played: &[ClassPlay]) -> bool {
    played
        .iter()
        .all(|c| c.at_own.is_some_and(|f| f >= GOAL_AT_OWN) && c.mixed_up <= GOAL_MIXED_UP)
}

/// `report.md` of a sort.
pub(crate) fn report_md(target_name: &str, d: &SortDesign, played: &[ClassPlay]) -> String {
    let mut s = format!("# Sort by friction: {target_name}\n\n");
    let _ = writeln!(
        s,
        "One schedule of {} segments, period {:.2} s, for {} part classes, each class's field matched at its own friction by one stacked conic fit (`platefield::design::sort`). Gentle columns offered: {}.\n",
        d.schedule.segments.len(),
        d.schedule.period_s,
        played.len(),
        if d.gentle.is_empty() { "none".to_string() } else { d.gentle.join(", ") }
    );
    let mut table = Table::new([
        "class",
        "μ",
        "predicted strength (1/s)",
        "predicted shape",
        "realised strength (1/s)",
        "realised shape",
        "swarm",
        "played (s)",
        "at own attractor",
        "mixed up",
        "median distance (mm)",
        "lost contact",
    ]);
    for (f, p) in d.classes.iter().zip(played) {
        table.row([
            f.name.clone(),
            p.friction.to_string(),
            format!("{:.4}", f.strength),
            percent(f.shape_error, 1),
            format!("{:.4}", p.realised_strength),
            percent(p.realised_shape_error, 1),
            p.parts.to_string(),
            format!("{:.0}", p.duration_s),
            p.at_own.map_or("n/a".into(), |x| percent(x, 1)),
            percent(p.mixed_up, 1),
            p.median_distance_m
                .map_or("n/a".into(), |m| format!("{:.1}", 1e3 * m)),
            p.contact_lost.to_string(),
        ]);
    }
    s.push_str(&table.markdown());
    let _ = writeln!(
        s,
        "\n\"At own attractor\": the swarm's parts ending within {:.0} mm of the class's attractor; \"mixed up\": ending within {:.0} mm of another class's.\n",
        1e3 * SORT_TOL,
        1e3 * SORT_TOL
    );
    if goal_met(played) {
        let _ = writeln!(
            s,
            "**Goal met**: every class ≥ {} at its own attractor and ≤ {} mixed up.",
            percent(GOAL_AT_OWN, 0),
            percent(GOAL_MIXED_UP, 0)
        );
    } else {
        let _ = writeln!(
            s,
            "**Goal NOT met** (≥ {} of each class at its own attractor, ≤ {} mixed up). {}",
            percent(GOAL_AT_OWN, 0),
            percent(GOAL_MIXED_UP, 0),
            WHY_NOT
        );
    }
    s.push_str("\n## Schedule\n\n| segment | cycles | weight |\n|---|---|---|\n");
    for seg in &d.schedule.segments {
        let _ = writeln!(s, "| {} | {} | {:.4} |", seg.label, seg.cycles, seg.weight);
    }
    s
}

/// The physical limits of a sort with the paper's primitives, stated with
/// a verdict that is not met (measured on `targets/sort_friction.json`:
/// with the default 10 cycles per segment, period 36.7 s, 22-24 % of each
/// class at its own sink after 147 s; with `--min-cycles 1` all of it).
pub(crate) const WHY_NOT: &str = "What limits a sort: the primitives' fields change with friction mostly in strength, hardly in direction, so the fit separates the classes chiefly by the gentle in-plane translations under which the stickier class does not slip, and these carry the slippery parts at only 2-3 mm/s at 209 rad/s (plate speed ≤ μg/ω). Sinks centimetres apart then have rates of about 0.01 1/s (time constants ~100 s), built of strong motions that nearly cancel; segments must be short (`--min-cycles 1`) so that a part's excursion within a segment (a strong Trans carries a μ 0.2 part at 20 mm/s) stays well below the distances sorted, and the swarm must play for minutes.";

/// Writes `schedule.json`, `sort.json` and `report.md` into `dir`.
pub fn write(target_name: &str, d: &SortDesign, played: &[ClassPlay], dir: &Path) -> Result<()> {
    let schedule = d.schedule.to_json()?;
    let sort = sort_json(d, played)?;
    let md = report_md(target_name, d, played);
    platefield::output::write_all_atomic(&[
        (&dir.join("schedule.json"), schedule.as_bytes()),
        (&dir.join("sort.json"), sort.as_bytes()),
        (&dir.join("report.md"), md.as_bytes()),
    ])
}

/// `sort.json`: the [`SortReport`].
pub(crate) fn sort_json(d: &SortDesign, played: &[ClassPlay]) -> Result<String> {
    let r = SortReport {
        fits: &d.classes,
        played,
        gentle: &d.gentle,
        goal_met: goal_met(played),
    };
    let mut text = serde_json::to_string_pretty(&r).map_err(|e| Error::Physical(e.to_string()))?;
    text.push('\n');
    Ok(text)
}

/// `design --json` for a sort: the schedule with `played` holding the
/// [`SortReport`].
pub(crate) fn design_json(d: &SortDesign, played: &[ClassPlay]) -> Result<String> {
    let mut value =
        serde_json::to_value(&d.schedule).map_err(|e| Error::Physical(e.to_string()))?;
    let report = serde_json::from_str::<serde_json::Value>(&sort_json(d, played)?)
        .map_err(|e| Error::Physical(e.to_string()))?;
    if let Some(map) = value.as_object_mut() {
        map.insert("played".into(), report);
    }
    let mut text =
        serde_json::to_string_pretty(&value).map_err(|e| Error::Physical(e.to_string()))?;
    text.push('\n');
    Ok(text)
}

/// Terminal summary of a sort.
pub fn summary(played: &[ClassPlay]) -> String {
    let mut s = String::new();
    for c in played {
        let _ = writeln!(
            s,
            "class {}: μ {}, realised strength {:.4} 1/s, shape {}, {} at its attractor, {} mixed up",
            c.name,
            c.friction,
            c.realised_strength,
            percent(c.realised_shape_error, 1),
            c.at_own.map_or("n/a".into(), |x| percent(x, 1)),
            percent(c.mixed_up, 1)
        );
    }
    let _ = writeln!(
        s,
        "{}",
        if goal_met(played) {
            "sort goal met"
        } else {
            "sort goal NOT met (see report.md for the reason)"
        }
    );
    s
}

/// `platefield design` for a target with classes, once designed
/// ([`platefield::design::DesignOutcome::Sorted`]): play every class, write
/// `OUT/<target>/` whole; the summary or the `--json` text.
pub fn run(
    target: &platefield::request::Target,
    d: &platefield::design::sort::SortDesign,
    dir: &Path,
    json: bool,
    files: &[&str],
    runtime: &platefield::work::Runtime,
) -> Result<String> {
    let played = platefield::verify::sort_play::play_classes(target, d, None, runtime)?;
    let stage = platefield::output::Staged::new(dir)?;
    write(&target.name, d, &played, stage.path())?;
    stage.commit(files)?;
    if json {
        return design_json(d, &played);
    }
    Ok(format!(
        "{}wrote {}/{{schedule.json, sort.json, report.md}}\n",
        summary(&played),
        dir.display()
    ))
}
