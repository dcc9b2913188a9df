//! A pose target's design written and summarised: the kept schedule's
//! files as for any design ([`super::method::write`]), its `report.md`
//! headed by the pose section (the motion and its placement, the lifted field's
//! stable poses, the played drops), and the terminal summary.

use std::fmt::Write as _;
use std::path::Path;

use platefield::error::{Error, Result};
use platefield::pose::design::{Placement, PoseDesign, TOL_DEG, TOL_MM};
use platefield::schedule::PosePlayed;

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

/// One line: the pose fraction, the median settle time, the uniqueness;
/// a second with the worst fraction over the part's friction range.
pub fn headline(d: &PoseDesign) -> String {
    let p = played(d);
    let worst = p.over_friction.as_ref().map_or(String::new(), |o| {
        format!(
            "over the part's friction {}: worst {:.1} % within {TOL_MM} mm and {TOL_DEG}° (report.md has each value)\n",
            o.range.to_json(),
            100.0 * o.worst_pose_fraction
        )
    });
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
        match p.distinct_stable {
            0 => "the lifted field has no stable pose".to_string(),
            1 => "the lifted field has one stable pose modulo symmetry".to_string(),
            k => format!("the lifted field has {k} stable poses modulo symmetry (basins below)"),
        }
    ) + &worst
}

/// A placement in words: turn (°) and reference point (mm).
fn placement_text(p: &Placement) -> String {
    format!(
        "turned {:+.2}°, reference point ({:+.3}, {:+.3}) mm",
        p.angle.to_degrees(),
        1e3 * p.shift.x,
        1e3 * p.shift.y
    )
}

/// The motion, its lifted placement and the played correction.
fn placement_md(d: &PoseDesign, md: &mut String) {
    let motion = match d.spin {
        None => format!(
            "One six-signal motion synthesized once for the centred {} (`pose::design::placement`)",
            platefield::pose::design::placement::family(false).label()
        ),
        Some(_) => "The cycle named above (`pose::design::cycle`: two six-signal motions, each synthesized once; the spun sink (`pose::design::spin`: a field nonlinear at the part's scale) selects one of the ellipse's two poses, the ellipse, placed on the spun sink's played rest, sets it)".to_string(),
    };
    let lifted = match &d.centred {
        Some((c, rate)) => format!(
            "; the part's stable pose in its lifted field: ({:+.3}, {:+.3}) mm, {:+.2}°, decay rates {:.3}, {:.3}, {:.3} 1/s, turning rate −∂θ'/∂θ {:.3} 1/s. Placed on the lifted field",
            1e3 * c.pose.r.x,
            1e3 * c.pose.r.y,
            c.pose.theta.to_degrees(),
            -c.rates[0],
            -c.rates[1],
            -c.rates[2],
            rate
        ),
        None => ". Placed on the cycle's played pose (the screen's probes)".into(),
    };
    let _ = writeln!(md, "{motion}{lifted}: {}.", placement_text(&d.lifted));
    screened_md(d, md);
    let _ = writeln!(
        md,
        "\nCorrected on played probes (`pose::design::correct`: {} drops from starts spread over the region, {} s each, on the same motion; the mean end of the largest group within {} mm and {}° of one another moves the placement):\n\n| round | placement | probes' mean end (mm, mm, °) | probes in it | Δr (mm) | Δθ (°) | played turning rate (1/s) |\n|---|---|---|---|---|---|---|",
        platefield::pose::design::correct::PROBES,
        platefield::pose::design::correct::PROBE_S,
        platefield::pose::design::correct::SAME_REST[0],
        platefield::pose::design::correct::SAME_REST[1],
    );
    for (i, r) in d.rounds.iter().enumerate() {
        let _ = writeln!(
            md,
            "| {} | {} | ({:+.3}, {:+.3}, {:+.2}) | {:.0} % | {:.3} | {:+.2} | {} |",
            i + 1,
            placement_text(&r.placement),
            1e3 * r.end.r.x,
            1e3 * r.end.r.y,
            r.end.theta.to_degrees(),
            100.0 * r.together,
            r.error.0,
            r.error.1,
            r.turning_rate.map_or("—".into(), |k| format!("{k:.3}"))
        );
    }
    let _ = writeln!(md, "\nKept: {}.", placement_text(&d.placement));
    if d.scaled.is_empty() {
        md.push_str("\nThe placed schedule's peaks are within the shaker limits its motion was synthesized within.\n");
    } else {
        md.push_str("\n**Scaled into the shaker limits** its motion was synthesized within, once placed (the placement's shift adds α × c to the plate-centre signals; each segment so scaled is what the probes, the correction and the drops play):\n\n");
        for line in &d.scaled {
            let _ = writeln!(md, "- {line}");
        }
    }
}

/// The spin candidates judged by play, when there were any.
fn screened_md(d: &PoseDesign, md: &mut String) {
    use platefield::pose::design::screen::{CYCLE_S, GRID, MAX_TURN, MIN_SHARE, PROBES, PROBE_S};
    if d.screened.is_empty() {
        return;
    }
    let ranged = d.screened.iter().any(|s| s.turn.is_some());
    let (range_text, head, rule) = if ranged {
        (
            format!("; over the friction range the least share at its middle and ends, and kept only if its pose turns by at most {MAX_TURN} tolerances between the ends"),
            " turn over the range (tolerances) |",
            "---|",
        )
    } else {
        (String::new(), "", "")
    };
    let _ = writeln!(
        md,
        "\nSpin candidates judged by play (`pose::design::screen`: {PROBES} probes × {PROBE_S} s on the centred spun sink, from a 4 × 4 grid of {GRID} starts and each again turned by 180°, whose largest cluster places the ellipse stage, then × {CYCLE_S} s or {} periods on that cycle placed on the asked pose and scaled as shipped, its spin stage as long as the spin takes to bring a part from each of the ellipse's two rests within {}° of the asked pose at the target's friction and at two more (`pose::design::handover`; \"worst turn\": the farthest of those parts then), its ellipse stage ln(d)/λ from the ellipse's slowest lifted rate and that worst turn (`pose::design::cycle::Stages::handed_over`; a spin whose lifted estimate of its stage exceeds {} s, or that brings no part into the kept half, is not played); share, spread and pose are the placed cycle's, the pose taken back to the centred motion; kept: the largest share at one pose, at least {:.0} %, then the shortest cycle, then the tightest{range_text}):\n\n| α (rad/s²) | phase (rad) | translation × | spin + ellipse stage (s) | worst turn (°) | share at one pose | spread | played pose (mm, mm, °) |{head}\n|---|---|---|---|---|---|---|---|{rule}",
        platefield::pose::design::cycle::SETTLE_PERIODS,
        platefield::pose::design::handover::HANDOVER_DEG,
        platefield::pose::design::cycle::MAX_STAGE_S,
        100.0 * MIN_SHARE
    );
    for s in &d.screened {
        let pose = s.pose.map_or("—".into(), |p| {
            format!(
                "({:+.2}, {:+.2}, {:+.1})",
                1e3 * p.r.x,
                1e3 * p.r.y,
                p.theta.to_degrees()
            )
        });
        let turn = s.turn.map_or(String::new(), |t| format!(" {t:.2} |"));
        let half = platefield::pose::design::cycle::ELLIPSE_TURN_DEG;
        let stages = match (s.stages, s.handover) {
            (None, _) => "too slow, not played".to_string(),
            (Some(_), Some(h)) if h.worst_deg >= half => "no hand-over, not played".to_string(),
            (Some(t), _) => format!("{:.1} + {:.1}", t.spin_s, t.ellipse_s),
        };
        let worst = s
            .handover
            .map_or("—".into(), |h| format!("{:.0}", h.worst_deg));
        let _ = writeln!(
            md,
            "| {} | {} | {} | {stages} | {worst} | {:.0} % | {:.2} | {pose} |{turn}",
            s.spin.alpha,
            s.spin.phase,
            s.spin.translation,
            100.0 * s.score,
            s.spread
        );
    }
}

/// The stable poses with their basins.
fn basins_md(p: &PosePlayed, md: &mut String) {
    if p.stable.is_empty() {
        md.push_str("\nThe kept schedule's lifted field has no stable pose in the region (a cycle's is its stages' time average, which no played part sees): no basins; the drops are judged by where they end.\n");
        return;
    }
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
    md.push('\n');
    placement_md(d, &mut md);
    let _ = writeln!(
        md,
        "\nPlayed: {} drops (centres uniform over the region inset by the part's radius, angles uniform), {:.1} s each by the planar simulator; {} lost contact. Basins: each end counted for its nearest stable pose of the kept schedule's lifted field; lifted: {} drops integrated along it.",
        p.drops,
        p.duration_s,
        p.lost,
        d.analysis.drops
    );
    basins_md(p, &mut md);
    if let Some(o) = &p.over_friction {
        md.push_str(&super::pose_friction::section(o));
    }
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
