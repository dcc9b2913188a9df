//! Study: pose design over a seeded family of random parts,
//! `results/pose_family.md`.
//!
//! The family is [`platefield::part::family::family`] (seed [`SEED`],
//! [`COUNT`] parts: star-shaped polygons, L brackets, rectangles; each
//! with a random friction and a pose asked at a random place and angle).
//! Each member is written as a part file and a pose target under
//! `OUT/pose_family/` (so any one can be designed again with `platefield
//! design`), designed as `design` does
//! ([`platefield::pose::design::design_pose`],
//! [`platefield::pose::design::DROPS`] drops), and its kept schedule's
//! drops played again at the part's μ ± 20 %
//! ([`platefield::pose::design::friction::over_range`]). The file gives
//! per part what the design kept (the spin, the stage lengths and the
//! worst turn at its hand-over), the share of the drops at the pose
//! (within 1 mm and 3°) at each friction, the median settle, and the
//! distribution over the family against the pose designs' goals (≥ 95 % at the
//! pose at μ ± 20 %; a median settle ≤ 20 s). CPU seconds are printed
//! only.

use std::fmt::Write as _;
use std::path::Path;

use platefield::design::tolerance::quantile;
use platefield::part::Part;
use platefield::pose::design::{friction, PoseDesign, DROPS};
use platefield::request::FrictionSpec;
use platefield::{Error, Result};
use platefield_report::table::Table;

use super::speed::process_cpu_seconds;

/// Default output folder.
pub const DIR: &str = "results";
/// The family's seed.
pub const SEED: u64 = 48;
/// Parts in the family.
pub const COUNT: usize = 8;
/// The friction band every design is played over: ± this fraction of
/// the part's μ (as `study poses-friction`).
pub const FRACTION: f64 = 0.2;
/// Goals: the least share at the pose at every friction of the band, and
/// the longest median settle (s).
pub const GOALS: (f64, f64) = (0.95, 20.0);
/// Half the side of every member's square region (m): the shipped pose
/// targets'.
const HALF_SIDE: f64 = 0.04;

/// One member designed and played over the band, or why it was not.
struct Outcome {
    part: Part,
    pose: [f64; 3],
    design: std::result::Result<Designed, String>,
}

/// What a member's design kept and its drops did.
struct Designed {
    /// The kept spin and stage lengths, or the ellipse alone.
    kept: String,
    /// The worst part's turn at the kept spin's hand-over (degrees).
    handover_deg: Option<f64>,
    /// The design's median settle at the part's μ (s; `None`: half the
    /// drops or more never settle).
    settle: Option<f64>,
    /// Share at the pose and median settle at each friction of the band.
    band: Vec<(f64, f64, Option<f64>)>,
}

impl Outcome {
    /// The least share at the pose over the band (0 for a member that did
    /// not design).
    fn worst_share(&self) -> f64 {
        self.design.as_ref().map_or(0.0, |d| {
            d.band.iter().map(|b| b.1).fold(f64::INFINITY, f64::min)
        })
    }

    /// The design's median settle at the part's μ (infinite when none).
    fn settle(&self) -> f64 {
        self.design
            .as_ref()
            .ok()
            .and_then(|d| d.settle)
            .unwrap_or(f64::INFINITY)
    }
}

/// Writes member `part`'s part file and pose target under `dir`; the
/// target's path.
fn write_member(dir: &Path, part: &Part, pose: [f64; 3]) -> Result<std::path::PathBuf> {
    let polygon: Vec<[f64; 2]> = part.polygon.iter().map(|v| [v.x, v.y]).collect();
    let part_json = serde_json::json!({
        "name": part.name,
        "polygon": polygon,
        "support": part.support,
        "friction": part.friction.to_json(),
    });
    let target = serde_json::json!({
        "name": format!("pose_{}", part.name),
        "grid": {"x": [-HALF_SIDE, HALF_SIDE], "y": [-HALF_SIDE, HALF_SIDE], "n": [21, 21]},
        "field": {"kind": "pose", "part": format!("parts/{}.json", part.name), "pose": pose},
    });
    let parts = dir.join("parts");
    std::fs::create_dir_all(&parts).map_err(|e| Error::Io {
        path: parts.display().to_string(),
        source: e,
    })?;
    let (part_path, target_path) = (
        parts.join(format!("{}.json", part.name)),
        dir.join(format!("{}.json", part.name)),
    );
    let text = |v: &serde_json::Value| format!("{:#}\n", v);
    platefield::output::write_all_atomic(&[
        (&part_path, text(&part_json).as_bytes()),
        (&target_path, text(&target).as_bytes()),
    ])?;
    Ok(target_path)
}

/// What `d` kept: its spin and stages, or the ellipse alone.
fn kept(d: &PoseDesign) -> (String, Option<f64>) {
    match (d.spin, d.stages) {
        (Some(s), Some(st)) => {
            let handover = d
                .screened
                .iter()
                .find(|c| c.spin == s)
                .and_then(|c| c.handover)
                .map(|h| h.worst_deg);
            (
                format!(
                    "spin {} × {}, {:.1} s + {:.1} s",
                    s.alpha, s.translation, st.spin_s, st.ellipse_s
                ),
                handover,
            )
        }
        _ => ("the ellipse alone".into(), None),
    }
}

/// The member at `target_path` designed and played over the band.
fn designed(target_path: &Path) -> Result<Designed> {
    let (req, d) = super::poses::designed_at(target_path)?;
    let schedule = &d.method.kept().schedule;
    let own = platefield_report::pose_design::played(&d).clone();
    let settle = own.median_settle_s;
    let band = FrictionSpec::around(schedule.settings.friction, FRACTION);
    let played = friction::over_range(&req, schedule, own, friction::rate(&d), Some(band))?;
    let band = played
        .over_friction
        .map(|o| {
            o.at.iter()
                .map(|a| (a.friction.kinetic, a.pose_fraction, a.median_settle_s))
                .collect()
        })
        .unwrap_or_default();
    let (kept, handover_deg) = kept(&d);
    Ok(Designed {
        kept,
        handover_deg,
        settle,
        band,
    })
}

/// Percent with one decimal.
fn pct(x: f64) -> String {
    format!("{:.1} %", 100.0 * x)
}

/// Seconds, or "never" for none.
fn seconds(s: Option<f64>) -> String {
    s.map_or("never".into(), |s| format!("{s:.1} s"))
}

/// The per-member table.
fn members(outcomes: &[Outcome]) -> String {
    let mut table = Table::new([
        "part",
        "across (cm)",
        "μ",
        "pose (mm, mm, °)",
        "kept",
        "worst turn at hand-over",
        "at the pose at μ × 0.8 / 1 / 1.2",
        "median settle at μ",
        "worst share",
    ]);
    for o in outcomes {
        let p = &o.part;
        let head = [
            p.name.clone(),
            format!("{:.2}", 100.0 * p.size()),
            format!("{:.3}", p.friction.nominal().kinetic),
            format!(
                "({:.1}, {:.1}, {:.1})",
                1e3 * o.pose[0],
                1e3 * o.pose[1],
                o.pose[2]
            ),
        ];
        let rest = match &o.design {
            Ok(d) => [
                d.kept.clone(),
                d.handover_deg.map_or("—".into(), |t| format!("{t:.1}°")),
                d.band
                    .iter()
                    .map(|b| pct(b.1))
                    .collect::<Vec<_>>()
                    .join(" / "),
                seconds(d.settle),
                pct(o.worst_share()),
            ],
            Err(e) => [
                format!("not designed: {e}"),
                "—".into(),
                "—".into(),
                "—".into(),
                pct(0.0),
            ],
        };
        table.row(head.into_iter().chain(rest));
    }
    table.markdown()
}

/// The distribution over the family and the goals met.
fn distribution(outcomes: &[Outcome]) -> String {
    let shares: Vec<f64> = outcomes.iter().map(Outcome::worst_share).collect();
    let settles: Vec<f64> = outcomes.iter().map(Outcome::settle).collect();
    let mut table = Table::new(["measure", "median", "10th / 90th percentile", "worst"]);
    let worst_share = shares.iter().copied().fold(f64::INFINITY, f64::min);
    table.row([
        "worst share at the pose over μ ± 20 %".to_string(),
        pct(quantile(&shares, 0.5)),
        format!("{} (10th)", pct(quantile(&shares, 0.1))),
        pct(worst_share),
    ]);
    let worst_settle = settles.iter().copied().fold(0.0, f64::max);
    let s = |x: f64| seconds(x.is_finite().then_some(x));
    table.row([
        "median settle at μ".to_string(),
        s(quantile(&settles, 0.5)),
        format!("{} (90th)", s(quantile(&settles, 0.9))),
        s(worst_settle),
    ]);
    let held = shares.iter().filter(|&&x| x >= GOALS.0).count();
    let fast = shares
        .iter()
        .zip(&settles)
        .filter(|&(&x, &s)| x >= GOALS.0 && s <= GOALS.1)
        .count();
    format!(
        "{}\n{held} of {n} parts hold ≥ {:.0} % of their drops at the pose at every friction of μ ± {:.0} % (goal: all); {fast} of {n} hold it and settle in a median ≤ {:.0} s (goal: all; a median settle counts the drops that never settle as the longest, so a part holding about half its drops can show one).\n",
        table.markdown(),
        100.0 * GOALS.0,
        100.0 * FRACTION,
        GOALS.1,
        n = outcomes.len()
    )
}

/// `platefield study pose-family`: designs a family of `count` parts
/// ([`COUNT`] by default), writes their files under `OUT/pose_family/`
/// and `OUT/pose_family.md`, and returns the text with each design's CPU
/// seconds (printed only).
///
/// # Errors
/// An unwritable `out`. A member whose design fails is a row saying why.
pub fn run(out: &Path, count: usize) -> Result<String> {
    platefield::output::check_writable(out, "--out")?;
    let dir = out.join("pose_family");
    let mut outcomes = Vec::new();
    let mut cpu = String::new();
    let members_drawn = platefield::part::family::family(SEED, count)?;
    let n = members_drawn.len();
    for (k, (part, pose)) in members_drawn.into_iter().enumerate() {
        eprintln!("pose-family: {} ({} of {n})", part.name, k + 1);
        let target = write_member(&dir, &part, pose)?;
        let before = process_cpu_seconds();
        let design = designed(&target).map_err(|e| e.to_string());
        if let (Some(a), Some(b)) = (before, process_cpu_seconds()) {
            let _ = writeln!(
                cpu,
                "{}: {:.1} s CPU (design and the band's plays)",
                part.name,
                b - a
            );
        }
        outcomes.push(Outcome { part, pose, design });
    }
    let md = format!(
        "# Pose design over a family of random parts\n\n\
         Generated by `platefield study pose-family` (see `platefield_studies::pose_family`): {n} parts from the seeded generator `platefield::part::family` (seed {SEED}), each with its own friction and a pose asked at a random place and angle; their part files and pose targets are in `pose_family/`. Each is designed as `design` does ({DROPS} drops played) and its drops played again at μ ± {:.0} %. At the pose: within 1 mm and 3° of it (modulo the part's symmetry). Median settle: the median over the drops of the end of the first schedule period from which the part stays at the pose. Kept: the spin (rad/s² × the sink's translation) and its cycle's stage lengths (spin + ellipse), or the elliptic sink alone for a part with a 180° symmetry; worst turn at hand-over: the worst of the spin stage's parts from the ellipse's two rests at the end of the spin stage.\n\n{}\n## Over the family\n\n{}",
        100.0 * FRACTION,
        members(&outcomes),
        distribution(&outcomes)
    );
    let path = out.join("pose_family.md");
    platefield::output::write_atomic(&path, md.as_bytes())?;
    Ok(format!("{md}\n{cpu}wrote {}\n", path.display()))
}
