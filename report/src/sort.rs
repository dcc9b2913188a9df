//! A sort's files: the kept candidate's `schedule.json`, `sort.json` (per
//! candidate and class: the fit and the plays), `report.md` opening with
//! the time to sort, the candidates' table, the kept candidate's per-class
//! table and the verdict against the goal (≥ [`GOAL_AT_OWN`] of each class
//! at its own attractor, ≤ [`GOAL_MIXED_UP`] mixed up, none lost), stated
//! whether met or not, and `sorted.svg` (each class's fraction at its own
//! attractor against time).

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use super::table::Table;
use crate::plot::{LinePlot, Series};
use platefield::design::sort::{ClassFit, SortDesign};
use platefield::error::{Error, Result};
use platefield::output::percent;
use platefield::verify::sort_play::{
    ClassPlay, SortOutcome, SortPlay, MIN_SORT_PLAY_S, SORT_HOLD_S, SORT_SHARE, SORT_TOL,
};

/// Goal: fraction of each class's swarm at its own attractor.
pub const GOAL_AT_OWN: f64 = 0.95;
/// Goal: largest fraction of a class's swarm at another class's attractor.
pub const GOAL_MIXED_UP: f64 = 0.02;

/// One candidate in `sort.json`.
#[derive(Debug, Clone, Serialize)]
pub(crate) struct CandidateReport<'a> {
    /// `primitives` or `synthesized` (with its shape budget).
    pub method: String,
    /// The synthesized motions offered to its fit.
    pub motions: &'a [String],
    /// The gentle columns offered to its fit.
    pub gentle: &'a [String],
    /// Per class, the stacked fit's prediction.
    pub fits: &'a [ClassFit],
    /// The interleaved sub-periods its schedule was cut into (absent: not
    /// cut).
    #[serde(skip_serializing_if = "is_one")]
    pub sub_periods: u32,
    /// Played.
    pub play: &'a SortPlay,
}

/// Whether `n` is 1 (a schedule not cut into sub-periods).
fn is_one(n: &u32) -> bool {
    *n == 1
}

/// What `sort.json` and `design --json`'s `played` hold.
#[derive(Debug, Clone, Serialize)]
pub(crate) struct SortReport<'a> {
    /// The kept candidate's name.
    pub kept: String,
    /// Its time to sort (s).
    pub time_to_sort_s: Option<f64>,
    /// Every candidate.
    pub candidates: Vec<CandidateReport<'a>>,
    /// Whether every class of the kept candidate met the goal.
    pub goal_met: bool,
}

/// Whether every class met the goal: at its own attractor, not mixed up,
/// none lost.
pub fn goal_met(played: &[ClassPlay]) -> bool {
    played.iter().all(|c| {
        c.at_own.is_some_and(|f| f >= GOAL_AT_OWN)
            && c.mixed_up <= GOAL_MIXED_UP
            && c.contact_lost == 0
    })
}

/// What a sort's measures say in words: for sinks (and other attractors)
/// where a class ends up, for lanes (classes with an `exit`) which edge
/// it leaves through.
struct Words {
    /// What "sorted" means for one part.
    sorted: String,
    /// The fraction of a class counted as sorted.
    own: &'static str,
    /// The fraction counted as mixed up.
    mixed: &'static str,
}

fn words(plays: &[ClassPlay]) -> Words {
    if plays.iter().any(|c| c.exit.is_some()) {
        Words {
            sorted: "out through its own edge of the region".into(),
            own: "through its own edge",
            mixed: "through another edge",
        }
    } else {
        Words {
            sorted: format!(
                "within {:.0} mm of its own attractor and staying",
                1e3 * SORT_TOL
            ),
            own: "at its own attractor",
            mixed: "mixed up",
        }
    }
}

/// `t` in seconds, or "not within the play".
fn seconds(t: Option<f64>) -> String {
    t.map_or("not within the play".into(), |t| format!("{t:.1} s"))
}

/// The first line of a sort's summary and report: the time to sort.
pub(crate) fn headline(out: &SortOutcome) -> String {
    let k = out.kept();
    let w = words(&k.classes);
    format!(
        "time to sort: {} ({} of every class {}; {} for 90 %; {} candidate of {}, played {:.0} s; worst class {} {}, {} {}, {} lost contact)",
        seconds(k.time_to_sort_s),
        percent(SORT_SHARE, 0),
        w.sorted,
        seconds(slowest(&k.classes, 0.9)),
        k.method,
        out.plays.len(),
        k.played_s,
        percent(
            k.classes
                .iter()
                .map(|c| c.at_own.unwrap_or(0.0))
                .fold(f64::INFINITY, f64::min),
            1
        ),
        w.own,
        percent(k.classes.iter().map(|c| c.mixed_up).fold(0.0, f64::max), 1),
        w.mixed,
        k.classes.iter().map(|c| c.contact_lost).sum::<usize>()
    )
}

/// The slowest class's time (s) to bring `share` of it to its own
/// attractor (or out through its own edge); `None` when a class does not.
fn slowest(plays: &[ClassPlay], share: f64) -> Option<f64> {
    plays
        .iter()
        .map(|c| c.time_to(share))
        .try_fold(0.0_f64, |m, t| t.map(|t| m.max(t)))
}

/// `report.md` of a sort.
pub(crate) fn report_md(target_name: &str, ds: &[SortDesign], out: &SortOutcome) -> String {
    let d = &ds[out.kept];
    let played = &out.kept().classes;
    let w = words(played);
    let lanes = played.iter().any(|c| c.exit.is_some());
    let mut s = format!(
        "# Sort by friction: {target_name}\n\n**{}**\n\n",
        headline(out)
    );
    let _ = writeln!(
        s,
        "Kept: the {} candidate, one schedule of {} segments, period {:.2} s{}{}, for {} part classes, each class's field matched at its own friction by one stacked conic fit (`platefield::design::sort`). Gentle columns offered: {}. Synthesized motions offered: {}.\n",
        d.label(),
        d.schedule.segments.len(),
        d.schedule.period_s,
        if d.sub_periods > 1 {
            format!(
                " (its fit's segments cut into {} interleaved sub-periods: the least number that brings its parts' swing within the uncut period, over it, below {:.1} mm, at most {}; `platefield::design::sort::interleaved`)",
                d.sub_periods,
                1e3 * platefield::design::sort::EXCURSION_MAX,
                platefield::design::sort::MAX_SUB_PERIODS
            )
        } else {
            String::new()
        },
        if d.cycles_aimed {
            format!(
                " (its segments' whole cycles aimed by playing, its columns fixed, until every class's settled orbit reaches within {:.1} mm of its attractor or no change of {:?} cycles brings it nearer, at most {} steps: `platefield::design::sort`, **Cycle aim**)",
                1e3 * platefield::design::sort::CYCLE_REACH_OK,
                platefield::design::sort::CYCLE_STEPS,
                platefield::design::sort::CYCLE_SWEEPS
            )
        } else {
            String::new()
        },
        played.len(),
        if d.gentle.is_empty() { "none".to_string() } else { d.gentle.join(", ") },
        if d.motions.is_empty() { "none".to_string() } else { d.motions.join(", ") }
    );
    let mut cands = Table::new([
        "candidate".to_string(),
        "period (s)".into(),
        "played (s)".into(),
        "time to sort".into(),
        format!("worst {}", w.own),
        format!("worst {}", w.mixed),
        "lost contact".into(),
    ]);
    for p in &out.plays {
        cands.row([
            p.method.clone(),
            format!("{:.2}", p.period_s),
            format!("{:.0}", p.played_s),
            seconds(p.time_to_sort_s),
            percent(
                p.classes
                    .iter()
                    .map(|c| c.at_own.unwrap_or(0.0))
                    .fold(f64::INFINITY, f64::min),
                1,
            ),
            percent(p.classes.iter().map(|c| c.mixed_up).fold(0.0, f64::max), 1),
            p.classes
                .iter()
                .map(|c| c.contact_lost)
                .sum::<usize>()
                .to_string(),
        ]);
    }
    let _ = write!(
        s,
        "## Candidates\n\nEvery candidate's swarms played, every class for the same time: {:.0} s (or the soonest sort so far, if longer) and {:.0} s beyond, so that a class sorted by then is seen to stay sorted; the one that sorts soonest is kept.\n\n",
        MIN_SORT_PLAY_S,
        SORT_HOLD_S,
    );
    s.push_str(&cands.markdown());
    s.push_str("\n## Kept candidate per class\n\n");
    let mut table = Table::new([
        "class".to_string(),
        "μ".into(),
        "predicted strength (1/s)".into(),
        "predicted shape".into(),
        "realised strength (1/s)".into(),
        "realised shape".into(),
        "swarm".into(),
        "played (s)".into(),
        "time to sort".into(),
        w.own.into(),
        w.mixed.into(),
        if lanes {
            "mean exit time (s)".into()
        } else {
            "median distance (mm)".into()
        },
        "lost contact".into(),
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
            seconds(p.time_to_sort_s),
            p.at_own.map_or("n/a".into(), |x| percent(x, 1)),
            percent(p.mixed_up, 1),
            match p.exit {
                Some(e) => format!(
                    "{} ({})",
                    e.mean_exit_time_s
                        .map_or("n/a".into(), |t| format!("{t:.1}")),
                    e.edge.name()
                ),
                None => p
                    .median_distance_m
                    .map_or("n/a".into(), |m| format!("{:.1}", 1e3 * m)),
            },
            p.contact_lost.to_string(),
        ]);
    }
    s.push_str(&table.markdown());
    if lanes {
        let _ = writeln!(
            s,
            "\n\"Through its own edge\": the swarm's parts (started at the centres of a 9 × 5 grid of cells over the region) whose first exit from the region is through the class's edge, the crossing interpolated between segment ends; \"through another edge\": through any other; \"time to sort\": the time by which {} of the class has left through its own edge; mean exit time over those. `sorted.svg`: each class's fraction out through its own edge against time.\n",
            percent(SORT_SHARE, 0),
        );
    } else {
        let _ = writeln!(
            s,
            "\n\"At own attractor\": the swarm's parts ending within {:.0} mm of the class's attractor; \"mixed up\": ending within {:.0} mm of another class's; \"time to sort\": the time by which {} of the class is within {:.0} mm of its own attractor and stays there to the end of the play. `sorted.svg`: each class's fraction at its own attractor (from then on) against time.\n",
            1e3 * SORT_TOL,
            1e3 * SORT_TOL,
            percent(SORT_SHARE, 0),
            1e3 * SORT_TOL
        );
    }
    if goal_met(played) {
        let _ = writeln!(
            s,
            "**Goal met**: every class ≥ {} {}, ≤ {} {}, none lost.",
            percent(GOAL_AT_OWN, 0),
            w.own,
            percent(GOAL_MIXED_UP, 0),
            w.mixed
        );
    } else {
        let _ = writeln!(
            s,
            "**Goal NOT met** (≥ {} of each class {}, ≤ {} {}, none lost). {}",
            percent(GOAL_AT_OWN, 0),
            w.own,
            percent(GOAL_MIXED_UP, 0),
            w.mixed,
            if lanes { LANES_WHY_NOT } else { WHY_NOT }
        );
    }
    s.push_str("\n## Schedule\n\n| segment | cycles | weight |\n|---|---|---|\n");
    for seg in &d.schedule.segments {
        let _ = writeln!(s, "| {} | {} | {:.4} |", seg.label, seg.cycles, seg.weight);
    }
    s
}

/// `sorted.svg`: the kept candidate's classes, each class's fraction at its
/// own attractor (from then on) against time, with the share that counts
/// as sorted.
pub(crate) fn sorted_svg(target_name: &str, out: &SortOutcome) -> String {
    const SAMPLES: usize = 200;
    let k = out.kept();
    let w = words(&k.classes);
    let t_end = k.played_s.max(f64::MIN_POSITIVE);
    let mut plot = LinePlot::new(format!(
        "{target_name}: each class {} ({} candidate)",
        w.own, k.method
    ))
    .labels(
        "time played (s)",
        if k.classes.iter().any(|c| c.exit.is_some()) {
            "fraction out through its own edge".to_string()
        } else {
            format!(
                "fraction within {:.0} mm of its own attractor",
                1e3 * SORT_TOL
            )
        },
    );
    for c in &k.classes {
        let points = (0..=SAMPLES)
            .map(|i| {
                let t = t_end * i as f64 / SAMPLES as f64;
                [t, c.sorted_at(t)]
            })
            .collect();
        plot = plot.series(Series::new(
            format!("{} (μ {})", c.name, c.friction),
            points,
        ));
    }
    plot.series(
        Series::new(
            percent(SORT_SHARE, 0),
            vec![[0.0, SORT_SHARE], [t_end, SORT_SHARE]],
        )
        .dashed(),
    )
    .to_svg()
}

/// What limits a sort, stated with a verdict that is not met (measured on
/// `targets/sort_friction.json`, `results/sort_friction/`).
pub(crate) const WHY_NOT: &str = "What limits a sort: every class follows every motion, so each class's attractor must come from how differently the classes follow the same motions. A motion synthesized for one class's sink is followed by the others nearly unturned (the slip lead δ = asin(μg/A) is a few degrees at the tens of m/s² that make strong fields), and the primitives' fields change with friction mostly in strength; a sort therefore rests on transports whose speed depends on friction, balanced against a common sink, or on gentle motions under which the stickier class does not slip at all (2-3 mm/s at 209 rad/s). Where the parts settle is off the time-averaged field's attractor by the schedule's within-period excursion (millimetres), so candidates are aimed by playing and several shape budgets tried; a target whose classes' transports hardly differ, or whose attractors are closer than those excursions, is not sorted by any of them.";

/// What limits lanes, stated with a verdict that is not met.
pub(crate) const LANES_WHY_NOT: &str = "What limits lanes: every class follows every motion, and a uniform transport carries all classes the same way, faster or slower; opposite lanes need a motion that carries the slippery class and holds the sticky one (an in-plane peak between μ_lo g and μ_hi g: a few mm/s), time-shared with a strong transport the other way that the sticky class follows at least as fast as the slippery one. Where the strong transport carries the slippery class nearly as fast, the gentle share must win it back and both lanes slow down.";

/// Writes the kept candidate's `schedule.json`, `sort.json` (every
/// candidate), `report.md` and `sorted.svg` into `dir`.
pub fn write(target_name: &str, ds: &[SortDesign], out: &SortOutcome, dir: &Path) -> Result<()> {
    let schedule = ds[out.kept].schedule.to_json()?;
    let sort = sort_json(ds, out)?;
    let md = report_md(target_name, ds, out);
    let svg = sorted_svg(target_name, out);
    platefield::output::write_all_atomic(&[
        (&dir.join("schedule.json"), schedule.as_bytes()),
        (&dir.join("sort.json"), sort.as_bytes()),
        (&dir.join("report.md"), md.as_bytes()),
        (&dir.join("sorted.svg"), svg.as_bytes()),
    ])
}

/// `sort.json`: the [`SortReport`].
pub(crate) fn sort_json(ds: &[SortDesign], out: &SortOutcome) -> Result<String> {
    let r = SortReport {
        kept: ds[out.kept].label(),
        time_to_sort_s: out.kept().time_to_sort_s,
        candidates: ds
            .iter()
            .zip(&out.plays)
            .map(|(d, play)| CandidateReport {
                method: d.label(),
                motions: &d.motions,
                gentle: &d.gentle,
                fits: &d.classes,
                sub_periods: d.sub_periods,
                play,
            })
            .collect(),
        goal_met: goal_met(&out.kept().classes),
    };
    let mut text = serde_json::to_string_pretty(&r).map_err(|e| Error::Internal(e.to_string()))?;
    text.push('\n');
    Ok(text)
}

/// `design --json` for a sort: the kept schedule with `played` holding the
/// [`SortReport`].
pub(crate) fn design_json(ds: &[SortDesign], out: &SortOutcome) -> Result<String> {
    let mut value =
        serde_json::to_value(&ds[out.kept].schedule).map_err(|e| Error::Internal(e.to_string()))?;
    let report = serde_json::from_str::<serde_json::Value>(&sort_json(ds, out)?)
        .map_err(|e| Error::Internal(e.to_string()))?;
    if let Some(map) = value.as_object_mut() {
        map.insert("played".into(), report);
    }
    let mut text =
        serde_json::to_string_pretty(&value).map_err(|e| Error::Internal(e.to_string()))?;
    text.push('\n');
    Ok(text)
}

/// One class's line of a summary.
fn class_line(c: &ClassPlay) -> String {
    let w = words(std::slice::from_ref(c));
    format!(
        "class {}: μ {}, realised strength {:.4} 1/s, shape {}, sorted in {}, {} {}, {} {}{}, {} lost contact",
        c.name,
        c.friction,
        c.realised_strength,
        percent(c.realised_shape_error, 1),
        seconds(c.time_to_sort_s),
        c.at_own.map_or("n/a".into(), |x| percent(x, 1)),
        w.own,
        percent(c.mixed_up, 1),
        w.mixed,
        c.exit.map_or(String::new(), |e| format!(
            ", mean exit time {} through the {} edge",
            seconds(e.mean_exit_time_s),
            e.edge.name()
        )),
        c.contact_lost
    )
}

/// Terminal summary of a sort: the time to sort first, then per class.
pub fn summary(out: &SortOutcome) -> String {
    let mut s = format!("{}\n", headline(out));
    for c in &out.kept().classes {
        let _ = writeln!(s, "{}", class_line(c));
    }
    let _ = writeln!(
        s,
        "{}",
        if goal_met(&out.kept().classes) {
            "sort goal met"
        } else {
            "sort goal NOT met (see report.md for the reason)"
        }
    );
    s
}

/// The text `verify` prints for a sort's schedule
/// ([`platefield::verify::sort_play::SortVerify`]): per motion (the
/// schedule played, the export replayed) the time to sort and per class
/// the measures of the design's plays, and the goal's verdict.
pub fn verify_text(v: &platefield::verify::sort_play::SortVerify) -> String {
    use platefield::verify::sort_play::SortVerify;
    let parts = v.played.first().map_or(0, |c| c.parts);
    let mut s = format!(
        "sort: every class's swarm of {parts} parts at its own friction, {:.1} s:\n",
        v.played_s
    );
    let mut section = |what: &str, plays: &[ClassPlay]| {
        let _ = writeln!(
            s,
            "  {what}: time to sort {} ({} of every class {}; {} for 90 %); goal {}",
            seconds(SortVerify::time_to_sort(plays)),
            percent(SORT_SHARE, 0),
            words(plays).sorted,
            seconds(slowest(plays, 0.9)),
            if goal_met(plays) { "met" } else { "NOT met" }
        );
        for c in plays {
            let _ = writeln!(s, "    {}", class_line(c));
        }
    };
    section("schedule played", &v.played);
    if let Some((file, plays)) = &v.replayed {
        section(&format!("export {file} replayed"), plays);
    }
    s
}

/// `platefield design` for a target with classes, once designed
/// ([`platefield::inverse::DesignOutcome::Sorted`]): play every candidate,
/// keep the faster, write `OUT/<target>/` whole; the summary or the
/// `--json` text.
pub fn run(
    target: &platefield::request::Target,
    ds: &[SortDesign],
    dir: &Path,
    json: bool,
    files: &[&str],
    runtime: &platefield::work::Runtime,
) -> Result<String> {
    let out = platefield::verify::sort_play::play_sort(target, ds, runtime)?;
    let stage = platefield::output::Staged::new(dir)?;
    write(&target.name, ds, &out, stage.path())?;
    stage.commit(files)?;
    if json {
        return design_json(ds, &out);
    }
    Ok(format!(
        "{}wrote {}/{{schedule.json, sort.json, report.md, sorted.svg}}\n",
        summary(&out),
        dir.display()
    ))
}
