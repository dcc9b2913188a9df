//! `platefield study rungs-auto`: the automatic model rung
//! ([`platefield::schedule::Schedule::rungs`], the rule in
//! [`platefield::field::rung`]) of every shipped design's segments, as
//! `verify --model auto` chooses it: on the realised grid's points over the
//! target region (`verify`'s default 5 × 5), for the schedule's field kind
//! at its own friction, at the default tolerance.
//!
//! `rungs_auto.md` holds, per schedule and moving segment, the cheapest
//! rung and its error against `full`, and the rung the schedule is played
//! at (the cheapest acceptable for every segment) with that rung's error;
//! it is deterministic. The time each rung's fields took and the time the
//! played rung saves against `full` on the sample points are printed only.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use platefield::error::{non_negative, Error, Result};
use platefield::field::rung::RUNGS;
use platefield::field::Grid;
use platefield::output::significant_percent;
use platefield::output::write_atomic;
use platefield::schedule::{Schedule, ScheduleRungs};
use platefield::verify::VerifyRequest;
use platefield_report::table::Table;

/// Default output folder of `platefield study rungs-auto`.
pub const DIR: &str = "results";

/// The shipped designs: every `schedule.json` one folder below `results`,
/// sorted by folder name.
pub fn shipped_schedules(results: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(results)
        .map_err(|e| Error::invalid("results", format!("{}: {e}", results.display())))?;
    let mut out: Vec<PathBuf> = entries
        .filter_map(|e| e.ok())
        .map(|e| e.path().join("schedule.json"))
        .filter(|p| p.is_file())
        .collect();
    out.sort();
    Ok(out)
}

/// One schedule's rungs as `verify --model auto` measures them.
pub fn schedule_rungs(schedule: &Schedule, tolerance: f64) -> ScheduleRungs {
    let points = VerifyRequest::default().points;
    let grid = Grid {
        n: [points, points],
        ..schedule.region()
    };
    schedule.rungs(&grid, &schedule.settings, tolerance)
}

/// `rungs_auto.md` for `rows` (folder name, rungs): deterministic, no times.
pub fn markdown(rows: &[(String, ScheduleRungs)], tolerance: f64) -> String {
    let mut md = format!(
        "# Automatic model rungs of the shipped designs\n\n\
         Every `results/*/schedule.json`, as `verify --model auto` measures it: each moving \
         segment's steady motion at every model rung on the 5×5 realised grid over the target \
         region, the schedule's field kind at its own friction, compared with the full model \
         (relative L2 error over the samples valid in both). A segment's rung is the cheapest \
         with error ≤ {} and validity flags identical to full's; the schedule is played at the \
         cheapest rung that moves the part and is acceptable for every segment (one model \
         per play; `paper` holds the part's position in the kinematics, exact for a field at \
         held points, not for parts that travel). Rungs, cheapest \
         first: {}. Regenerate: `platefield study rungs-auto` (it also prints the fields' \
         compute times and the time the played rung saves, which are not written here; \
         what a cheaper rung saves, and why not always: \
         `platefield::field::rung`).\n\n",
        significant_percent(tolerance),
        RUNGS
            .iter()
            .map(|r| format!("`{}`", r.0))
            .collect::<Vec<_>>()
            .join(", "),
    );
    let mut summary = Table::new(["design", "segments", "played rung", "worst played error"]);
    for (name, r) in rows {
        let worst = r
            .segments
            .iter()
            .map(|s| s.played_error)
            .fold(0.0_f64, |a, e| if e.is_nan() { a } else { a.max(e) });
        summary.row([
            name.clone(),
            r.segments.len().to_string(),
            format!("**{}**", r.rung),
            significant_percent(worst),
        ]);
    }
    md.push_str(&summary.markdown());
    md.push_str("\n## Per segment\n\n");
    let mut table = Table::new(
        ["design", "segment", "cheapest rung", "its error"]
            .into_iter()
            .chain(RUNGS.map(|r| r.0))
            .chain(["played", "played error"]),
    );
    for (name, r) in rows {
        for s in &r.segments {
            let mut row = vec![
                name.clone(),
                format!("{} {}", s.segment, s.label),
                s.report.rung.to_string(),
                significant_percent(s.report.error),
            ];
            row.extend(s.report.rungs.iter().map(|x| x.error_text()));
            row.push(r.rung.to_string());
            row.push(significant_percent(s.played_error));
            table.row(row);
        }
    }
    md.push_str(&table.markdown());
    md
}

/// Per schedule, the seconds the fields at the played rung and at `full`
/// took on the sample points, and their ratio (printed only).
fn times_text(rows: &[(String, ScheduleRungs)]) -> String {
    let mut t = format!(
        "{:<16} {:<32} {:>10} {:>10} {:>8}\n",
        "design", "played rung", "played s", "full s", "ratio"
    );
    for (name, r) in rows {
        let k = RUNGS.iter().position(|x| x.0 == r.rung).unwrap_or(3);
        let played: f64 = r.segments.iter().map(|s| s.report.rungs[k].seconds).sum();
        let full: f64 = r.segments.iter().map(|s| s.report.rungs[3].seconds).sum();
        let _ = writeln!(
            t,
            "{name:<16} {:<32} {played:>10.4} {full:>10.4} {:>8.3}",
            r.rung,
            if full > 0.0 { played / full } else { f64::NAN }
        );
    }
    t
}

/// `platefield study rungs-auto`: reads every shipped schedule under
/// `results`, writes `out/rungs_auto.md` and returns it with the times.
pub fn run(results: &Path, out: &Path, tolerance: f64) -> Result<String> {
    non_negative("--tolerance", tolerance)?;
    let mut rows = Vec::new();
    for path in shipped_schedules(results)? {
        let schedule = Schedule::load(&path)?;
        let name = path
            .parent()
            .and_then(Path::file_name)
            .map_or(String::new(), |n| n.to_string_lossy().into_owned());
        rows.push((name, schedule_rungs(&schedule, tolerance)));
    }
    let md = markdown(&rows, tolerance);
    let file = out.join("rungs_auto.md");
    write_atomic(&file, md.as_bytes())?;
    let mut s = md;
    let _ = write!(s, "\n{}", times_text(&rows));
    let _ = writeln!(s, "wrote {}", file.display());
    Ok(s)
}
