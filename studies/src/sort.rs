//! Study: where sorting by friction stops being possible, and why,
//! `results/sort.md`.
//!
//! Two classes of point parts, μ_lo = [`MU_LO`] and μ_hi = r μ_lo, each
//! sent to its own sink on the x axis, designed as `design` designs a
//! classes target (`platefield::design::sort`, `--min-cycles 1`, every
//! candidate played by `platefield::verify::sort_play`, the one that sorts
//! soonest kept) over two sweeps:
//! - **friction contrast**: r ∈ [`RATIOS`], sinks [`CONTRAST_APART`] apart;
//! - **attractors' distance**: sinks [`DISTANCES`] apart at r =
//!   [`DISTANCE_RATIO`].
//!
//! Beside each sort's time, the quantities the physics says limit it
//! (`platefield::design::sort` module docs):
//! - the **gentle window** 1 − μ_lo/μ_hi: the in-plane peaks between
//!   μ_lo g and μ_hi g move the slippery class while the sticky one is held
//!   (N = g), as a fraction of the sticky threshold;
//! - the **slip-lead difference** δ_hi − δ_lo, δ = asin(μg/A), at the kept
//!   schedule's in-plane peak A: how far one strong motion turns the two
//!   classes' fields apart;
//! - the weaker class's **realised strength**, and the **aim**: how far
//!   (mm) the fit had to move a class's target so that its parts settle on
//!   their sink (the schedule's within-period excursion), against half the
//!   sinks' distance.
//!
//! The study's work is stated first and followed on stderr
//! (`crate::work`); CPU seconds are printed only.

use std::fmt::Write as _;
use std::path::Path;

use platefield::design::sort::{design_sort, SortDesign};
use platefield::design::{DesignOptions, ScheduleSection};
use platefield::error::Result;
use platefield::output::percent;
use platefield::request::Target;
use platefield::verify::sort_play::{play_sort, SortOutcome, SORT_SHARE};
use platefield::work::Runtime;
use platefield_report::sort::goal_met;
use platefield_report::table::Table;

use super::speed::process_cpu_seconds;

/// Default output folder.
pub const DIR: &str = "results";
/// The slippery class's friction.
pub const MU_LO: f64 = 0.2;
/// Friction contrasts μ_hi/μ_lo of the contrast sweep.
pub const RATIOS: [f64; 4] = [1.25, 1.5, 2.0, 3.0];
/// The sinks' distance (m) in the contrast sweep.
pub const CONTRAST_APART: f64 = 0.03;
/// The sinks' distances (m) of the distance sweep.
pub const DISTANCES: [f64; 3] = [0.01, 0.02, 0.04];
/// The friction contrast of the distance sweep.
pub const DISTANCE_RATIO: f64 = 2.0;
/// The share of each class the second time column counts.
pub const SECOND_SHARE: f64 = 0.9;

/// One sort of the study: two classes, sinks `apart` on the x axis
/// about the centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Case {
    /// μ_hi / μ_lo.
    pub ratio: f64,
    /// The sinks' distance (m).
    pub apart: f64,
}

impl Case {
    /// The two classes' frictions.
    pub fn frictions(&self) -> [f64; 2] {
        [MU_LO, (MU_LO * self.ratio * 1e6).round() / 1e6]
    }

    /// The classes target: x ±4 cm, y ±2 cm (`targets/sort_friction.json`'s
    /// region), μ_lo to (−apart/2, 0), μ_hi to (+apart/2, 0).
    ///
    /// # Errors
    /// Never for the study's cases (a target that does not validate).
    pub fn target(&self) -> Result<Target> {
        let [lo, hi] = self.frictions();
        let h = 0.5 * self.apart;
        let json = format!(
            r#"{{"name": "sort_r{}_d{}mm",
              "grid": {{"x": [-0.04, 0.04], "y": [-0.02, 0.02], "n": [17, 9]}},
              "classes": [
                {{"name": "mu_{lo}", "friction": {lo}, "field": {{"kind": "sink", "center": [{}, 0.0]}}}},
                {{"name": "mu_{hi}", "friction": {hi}, "field": {{"kind": "sink", "center": [{h}, 0.0]}}}}]}}"#,
            self.ratio,
            (1e3 * self.apart).round(),
            -h
        );
        Target::from_json_str(&json).map_err(platefield::Error::from)
    }
}

/// The study's cases: the contrast sweep, then the distance sweep.
///
/// ```
/// use platefield_studies::sort::cases;
/// let all = cases();
/// assert_eq!(all.len(), 7);
/// assert_eq!(all[0].frictions(), [0.2, 0.25]);
/// assert_eq!(all[0].target()?.classes.len(), 2);
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn cases() -> Vec<Case> {
    let mut out: Vec<Case> = RATIOS
        .iter()
        .map(|&ratio| Case {
            ratio,
            apart: CONTRAST_APART,
        })
        .collect();
    out.extend(DISTANCES.iter().map(|&apart| Case {
        ratio: DISTANCE_RATIO,
        apart,
    }));
    out
}

/// One case designed and played.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The case.
    pub case: Case,
    /// Every candidate.
    pub designs: Vec<SortDesign>,
    /// Every candidate played, one kept.
    pub played: SortOutcome,
    /// CPU seconds (printed only).
    pub cpu_s: f64,
}

/// The options the study designs with: `design`'s defaults with
/// `--min-cycles 1` (as `results/sort_friction/` is made), quiet, the
/// long-run guard off (the study states its own estimate).
pub fn options() -> DesignOptions {
    DesignOptions {
        runtime: Runtime {
            quiet: true,
            allow_long: true,
        },
        schedule: ScheduleSection {
            min_cycles: 1,
            ..Default::default()
        },
        ..DesignOptions::default()
    }
}

/// Designs and plays one case (minutes of CPU).
///
/// ```no_run
/// let o = platefield_studies::sort::outcome(platefield_studies::sort::cases()[3])?;
/// println!("{:?}", o.played.kept().time_to_sort_s);
/// # Ok::<(), platefield::Error>(())
/// ```
///
/// # Errors
/// The design or the plays fail.
pub fn outcome(case: Case) -> Result<Outcome> {
    let cpu = process_cpu_seconds();
    let target = case.target()?;
    let opts = options();
    let designs = design_sort(&target, &opts)?;
    let played = play_sort(&target, &designs, &opts.runtime)?;
    Ok(Outcome {
        case,
        designs,
        played,
        cpu_s: process_cpu_seconds()
            .zip(cpu)
            .map_or(f64::NAN, |(b, a)| b - a),
    })
}

/// The slip lead δ = asin(μg/A) (degrees) of a part of friction `mu`
/// under an in-plane plate acceleration of amplitude `a` (m/s²); `None`
/// when μg ≥ A (the part is held).
///
/// ```
/// use platefield_studies::sort::slip_lead_deg;
/// assert!((slip_lead_deg(0.5, 10.0, 10.0).unwrap() - 30.0).abs() < 1e-9);
/// assert_eq!(slip_lead_deg(0.5, 10.0, 4.0), None);
/// ```
pub fn slip_lead_deg(mu: f64, g: f64, a: f64) -> Option<f64> {
    let s = mu * g / a;
    (s < 1.0).then(|| s.asin().to_degrees())
}

/// The kept schedule's in-plane peak plate acceleration (m/s²): the
/// larger of its x and y peaks over every moving segment.
fn in_plane_peak(d: &SortDesign) -> f64 {
    let p = platefield::schedule::export::schedule_peaks(&d.schedule);
    p[0].max(p[1])
}

fn seconds(t: Option<f64>) -> String {
    t.map_or("not within the play".into(), |t| format!("{t:.1} s"))
}

/// One row of either table.
fn row(o: &Outcome) -> Vec<String> {
    let k = o.played.kept();
    let d = &o.designs[o.played.kept];
    let [lo, hi] = o.case.frictions();
    let g = d.schedule.settings.gravity;
    let a = in_plane_peak(d);
    let lead = match (slip_lead_deg(lo, g, a), slip_lead_deg(hi, g, a)) {
        (Some(l), Some(h)) => format!("{:.1}° (A {a:.1} m/s²)", h - l),
        _ => format!("μ_hi held (A {a:.1} m/s²)"),
    };
    let worst = |f: &dyn Fn(&platefield::verify::sort_play::ClassPlay) -> f64, min: bool| {
        k.classes
            .iter()
            .map(f)
            .fold(if min { f64::INFINITY } else { 0.0 }, |x, y| {
                if min {
                    x.min(y)
                } else {
                    x.max(y)
                }
            })
    };
    let slowest = |share: f64| {
        k.classes
            .iter()
            .map(|c| c.time_to(share))
            .try_fold(0.0_f64, |m, t| t.map(|t| m.max(t)))
    };
    let aim = d.aim.iter().map(|e| e[0].hypot(e[1])).fold(0.0, f64::max);
    vec![
        format!("{lo} / {hi}"),
        format!("{}", o.case.ratio),
        format!("{:.0}", 1e2 * o.case.apart),
        percent(1.0 - lo / hi, 0),
        k.method.clone(),
        seconds(k.time_to_sort_s),
        seconds(slowest(SECOND_SHARE)),
        percent(worst(&|c| c.at_own.unwrap_or(0.0), true), 1),
        percent(worst(&|c| c.mixed_up, false), 1),
        k.classes
            .iter()
            .map(|c| c.contact_lost)
            .sum::<usize>()
            .to_string(),
        format!("{:.3}", worst(&|c| c.realised_strength, true)),
        lead,
        format!("{:.1} / {:.1}", 1e3 * aim, 0.5e3 * o.case.apart),
        if goal_met(&k.classes) {
            "sorted".into()
        } else {
            "not sorted".into()
        },
    ]
}

const HEADER: [&str; 14] = [
    "μ_lo / μ_hi",
    "ratio",
    "sinks apart (cm)",
    "gentle window",
    "kept",
    "time to sort (95 %)",
    "time to 90 %",
    "worst at own",
    "worst mixed up",
    "lost",
    "weaker realised strength (1/s)",
    "slip-lead difference at A",
    "aim / half distance (mm)",
    "verdict",
];

/// Where a sweep stops sorting: the first and last rows that meet the
/// goal, in the sweep's order, named by `what`.
fn limit(outcomes: &[&Outcome], what: &dyn Fn(&Case) -> String) -> String {
    let sorted: Vec<bool> = outcomes
        .iter()
        .map(|o| goal_met(&o.played.kept().classes))
        .collect();
    let names: Vec<String> = outcomes.iter().map(|o| what(&o.case)).collect();
    let yes: Vec<&str> = names
        .iter()
        .zip(&sorted)
        .filter(|(_, s)| **s)
        .map(|(n, _)| n.as_str())
        .collect();
    let no: Vec<&str> = names
        .iter()
        .zip(&sorted)
        .filter(|(_, s)| !**s)
        .map(|(n, _)| n.as_str())
        .collect();
    format!(
        "sorted (goal met): {}; not sorted: {}",
        if yes.is_empty() {
            "none".to_string()
        } else {
            yes.join(", ")
        },
        if no.is_empty() {
            "none".to_string()
        } else {
            no.join(", ")
        }
    )
}

/// `sort.md` from the outcomes (the contrast sweep's first, as
/// [`cases`] orders them).
pub fn render(outcomes: &[Outcome]) -> String {
    let mut md = format!(
        "# Sorting by friction: where it stops, and why\n\nGenerated by `platefield study sort` (see `platefield_studies::sort`). Two classes of point parts, μ_lo = {MU_LO} sent to a sink at (−d/2, 0) and μ_hi to (+d/2, 0), over x ±4 cm, y ±2 cm; each designed as `design TARGET --min-cycles 1` designs a classes target (`platefield::design::sort`: the primitives' stacked fit and the fits with synthesized motions, aimed by playing, every candidate's swarms of 45 parts per class played, the one that sorts soonest kept). Time to sort: the time by which {} of every class is within 5 mm of its own sink and stays there; time to {}: the same at {}. The goal (verdict \"sorted\"): ≥ {} of each class at its own sink at the end of the play, ≤ {} mixed up, none lost.\n\nWhat limits a sort, per row: the **gentle window** 1 − μ_lo/μ_hi (in-plane peaks between μ_lo g and μ_hi g carry the slippery class while the sticky one is held, as a fraction of the sticky threshold); the **slip-lead difference** δ_hi − δ_lo, δ = asin(μg/A), at the kept schedule's in-plane peak A (how far one strong motion turns the classes' fields apart); the weaker class's **realised strength**; the **aim** (how far the fit moved a class's target so that its parts settle on their sink: the schedule's within-period excursion) against half the sinks' distance.\n\n",
        percent(SORT_SHARE, 0),
        percent(SECOND_SHARE, 0),
        percent(SECOND_SHARE, 0),
        percent(platefield_report::sort::GOAL_AT_OWN, 0),
        percent(platefield_report::sort::GOAL_MIXED_UP, 0),
    );
    let contrast: Vec<&Outcome> = outcomes
        .iter()
        .filter(|o| o.case.apart == CONTRAST_APART && RATIOS.contains(&o.case.ratio))
        .collect();
    let distance: Vec<&Outcome> = outcomes
        .iter()
        .filter(|o| o.case.ratio == DISTANCE_RATIO && DISTANCES.contains(&o.case.apart))
        .collect();
    for (title, rows) in [
        (
            format!(
                "Against the friction contrast (sinks {:.0} cm apart)",
                1e2 * CONTRAST_APART
            ),
            &contrast,
        ),
        (
            format!("Against the sinks' distance (ratio {DISTANCE_RATIO})"),
            &distance,
        ),
    ] {
        let _ = writeln!(md, "## {title}\n");
        let mut table = Table::new(HEADER);
        for o in rows.iter() {
            table.row(row(o));
        }
        md.push_str(&table.markdown());
        md.push('\n');
    }
    let _ = writeln!(
        md,
        "## Where sorting stops\n\n- Friction contrast: {}.\n- Sinks' distance: {}.\n",
        limit(&contrast, &|c| format!("ratio {}", c.ratio)),
        limit(&distance, &|c| format!("{:.0} cm", 1e2 * c.apart)),
    );
    md.push_str(WHY);
    md
}

/// The reading of the tables: the physics of each limit.
const WHY: &str = "Reading. The tables give the times; why they grow as they do: every class follows every motion. Under the strong motions the kept schedules use, the two classes' slip leads δ = asin(μg/A) differ by the column \"slip-lead difference\", a few degrees at most, so a strong motion turns their fields hardly apart; what separates them is the threshold, the gentle window 1 − μ_lo/μ_hi of in-plane peaks that carry the slippery class while the sticky one is held (no gentle synthesis is offered below a ratio of 1/0.7 ≈ 1.43, where the gentle limits cannot make the slippery class slip). As the window closes, the difference the fit can build weakens: the weaker class's realised strength falls and the time to sort grows. Against the distance, close sinks need nearly one field (a common sink and a small difference), far ones a large difference that only the slow gentle transports give; the aim (how far the fit moved a class's target so that its parts settle on their sink) is set against half the sinks' distance: an aim beyond it means that, unaimed, a class's parts could settle nearer the other class's sink than their own, so the aim, not the field's strength, decides such a sort; it is a measure of difficulty, not a limit (rows with an aim beyond half the distance still sort). These are one design per case, not bounds: which candidate sorts fastest varies from target to target by a factor of several.\n";

/// `platefield study sort`: designs and plays every case, writes
/// `OUT/sort.md` and returns its text with each case's CPU seconds
/// (printed only).
///
/// ```no_run
/// platefield_studies::sort::run(std::path::Path::new("results"))?;
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn run(out: &Path) -> Result<String> {
    platefield::output::check_writable(out, "--out")?;
    let all = cases();
    let n = all.len();
    let mut outcomes = Vec::new();
    let mut cpu = String::new();
    for (k, case) in all.into_iter().enumerate() {
        let [lo, hi] = case.frictions();
        eprintln!(
            "sort: μ {lo} / {hi}, sinks {:.0} cm apart ({} of {n})",
            1e2 * case.apart,
            k + 1
        );
        let o = outcome(case)?;
        let _ = writeln!(
            cpu,
            "μ {lo} / {hi}, {:.0} cm: {:.1} s CPU, time to sort {}",
            1e2 * case.apart,
            o.cpu_s,
            seconds(o.played.kept().time_to_sort_s)
        );
        outcomes.push(o);
    }
    let md = render(&outcomes);
    let path = out.join("sort.md");
    platefield::output::write_atomic(&path, md.as_bytes())?;
    Ok(format!("{md}\n{cpu}wrote {}\n", path.display()))
}

#[cfg(test)]
mod tests {
    use super::WHY;

    /// The committed `results/sort.md` ends with the reading this code
    /// writes, so that a change of the reading is seen to need the file
    /// regenerated (or, the reading being fixed text, edited alike).
    #[test]
    fn committed_reading_is_the_codes() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../results/sort.md");
        let md = std::fs::read_to_string(&path).expect("results/sort.md is committed");
        assert!(
            md.ends_with(WHY),
            "{} does not end with the study's reading",
            path.display()
        );
    }
}
