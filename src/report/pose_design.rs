//! A pose target's design written and summarised: the kept schedule's
//! files as for any design ([`super::method::write`]), its `report.md`
//! headed by the pose section (the candidates placed, the lifted field's
//! stable poses, the played drops), and the terminal summary.

use std::fmt::Write as _;
use std::path::Path;

use crate::design::pose::{PoseDesign, TOL_DEG, TOL_MM};
use crate::error::{Error, Result};
use crate::schedule::PosePlayed;

/// The played drops of `d`'s kept schedule.
pub fn played(d: &PoseDesign) -> &PosePlayed {
    d.method
        .kept()
        .schedule
        .played
        .as_ref()
        .and_then(|p| p.pose.as_ref())
        .expect("design_pose records the played drops")
}

/// One line: the pose fraction, the median settle time, the uniqueness.
pub fn headline(d: &PoseDesign) -> String {
    let p = played(d);
    let settle = p
        .median_settle_s
        .map_or("none (half or more never settle)".into(), |t| {
            format!("{t:.1} s")
        });
    format!(
        "pose {} at ({:.1} mm, {:.1} mm, {:.1}°), symmetry {}: {:.1} % of {} played drops end within {TOL_MM} mm and {TOL_DEG}° (median settle {settle}); field {}; {}\n",
        p.part,
        1e3 * p.pose[0],
        1e3 * p.pose[1],
        p.pose[2],
        p.symmetry,
        100.0 * p.pose_fraction,
        p.drops,
        p.field,
        if p.distinct_stable == 1 {
            "the lifted field has one stable pose modulo symmetry".to_string()
        } else {
            format!(
                "the lifted field has {} stable poses modulo symmetry (basins below)",
                p.distinct_stable
            )
        }
    )
}

/// The candidates table.
fn trials_md(d: &PoseDesign, md: &mut String) {
    let asked = &d.request.pose;
    let n = d.request.part.symmetry();
    md.push_str("| candidate | kept | designs | centre (mm) | angle (°) | stable poses (mod symmetry) | nearest: Δr (mm), Δθ (°) | slowest rate (1/s) |\n|---|---|---|---|---|---|---|---|\n");
    for (i, (family, trial)) in d.trials.iter().enumerate() {
        let kept = if i == d.kept { "yes" } else { "" };
        match trial {
            Ok(t) => {
                let err = t
                    .error(asked, n)
                    .map_or("none stable".into(), |(r, a)| format!("{r:.2}, {a:+.2}"));
                let _ = writeln!(
                    md,
                    "| {} | {kept} | {} | ({:+.2}, {:+.2}) | {:.2} | {} | {err} | {:.3} |",
                    family.label(),
                    t.designs,
                    1e3 * t.center.x,
                    1e3 * t.center.y,
                    t.angle,
                    t.distinct,
                    t.slowest_rate()
                );
            }
            Err(e) => {
                let _ = writeln!(md, "| {} | | not designed: {e} | | | | | |", family.label());
            }
        }
    }
}

/// The placement on played probes.
fn rounds_md(d: &PoseDesign, md: &mut String) {
    let _ = writeln!(
        md,
        "\nPlaced again on played probes (`design::pose::correct`: {} drops at and around the pose, {} s each; their mean end moves the kept candidate):\n\n| round | centre (mm) | angle (°) | probes' mean end (mm, mm, °) | Δr (mm) | Δθ (°) |\n|---|---|---|---|---|---|",
        crate::design::pose::correct::PROBES,
        crate::design::pose::correct::PROBE_S
    );
    for (i, r) in d.rounds.iter().enumerate() {
        let _ = writeln!(
            md,
            "| {} | ({:+.2}, {:+.2}) | {:.2} | ({:+.2}, {:+.2}, {:+.2}) | {:.2} | {:+.2} |",
            i + 1,
            1e3 * r.center.x,
            1e3 * r.center.y,
            r.angle,
            1e3 * r.end.r.x,
            1e3 * r.end.r.y,
            r.end.theta.to_degrees(),
            r.error.0,
            r.error.1
        );
    }
    let n = d.request.part.symmetry();
    if let Some((mm, deg)) = d.corrected.error(&d.request.pose, n) {
        let _ = writeln!(
            md,
            "\nKept: centre ({:+.2}, {:+.2}) mm, angle {:.2}°; its lifted field's stable pose nearest the asked one is {mm:.2} mm and {deg:+.2}° from it (the lifted field's bias against play).",
            1e3 * d.corrected.center.x,
            1e3 * d.corrected.center.y,
            d.corrected.angle
        );
    }
}

/// The stable poses with their basins.
fn basins_md(p: &PosePlayed, md: &mut String) {
    md.push_str("\n| stable pose x (mm) | y (mm) | θ (°) | basin (lifted) | basin (played) |\n|---|---|---|---|---|\n");
    for b in &p.stable {
        let _ = writeln!(
            md,
            "| {:+.2} | {:+.2} | {:+.2} | {:.1} % | {:.1} % |",
            1e3 * b.pose[0],
            1e3 * b.pose[1],
            b.pose[2],
            100.0 * b.lifted,
            100.0 * b.played
        );
    }
}

/// The pose section of `report.md`.
pub fn pose_md(d: &PoseDesign) -> String {
    let p = played(d);
    let mut md = String::from("## Pose target\n\n");
    md.push_str(&headline(d));
    let _ = writeln!(
        md,
        "\nCandidates (`design::pose::search`): each requested field designed by the sequenced fit and placed so that the stable pose of its designed schedule's lifted field nearest the asked one sits on it; kept: a unique stable pose first, then the smaller error, then the faster slowest rate.\n"
    );
    trials_md(d, &mut md);
    rounds_md(d, &mut md);
    let _ = writeln!(
        md,
        "\nPlayed: {} drops (centres uniform over the region inset by the part's radius, angles uniform), {:.1} s each by the planar simulator; {} lost contact. Basins: each end counted for its nearest stable pose of the kept schedule's lifted field; lifted: {} drops integrated along it.",
        p.drops,
        p.duration_s,
        p.lost,
        d.analysis.drops
    );
    basins_md(p, &mut md);
    md
}

/// Puts the pose section at the head of `dir/report.md`.
pub fn write(d: &PoseDesign, dir: &Path) -> Result<Vec<&'static str>> {
    let files = super::method::write(&d.method, dir)?;
    let path = dir.join("report.md");
    let io = |source| Error::Io {
        path: path.display().to_string(),
        source,
    };
    let report = std::fs::read_to_string(&path).map_err(io)?;
    let (title, rest) = report.split_once("\n\n").unwrap_or((&report, ""));
    let text = format!("{title}\n\n{}\n{rest}", pose_md(d));
    std::fs::write(&path, text).map_err(io)?;
    Ok(files)
}
