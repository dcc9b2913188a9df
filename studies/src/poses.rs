//! Study: the shipped parts' equilibrium poses on the designed
//! elliptic sinks, `results/poses.md`.
//!
//! For each part in `targets/parts/` (rectangle, bracket, triangle) and each
//! designed ellipse (`results/ellipse/schedule.json`, the sink (−0.3x, −y),
//! and `results/ellipse_30/`, the same turned by 30°; both by `design
//! targets/<name>.json --method sequence`): the lifted field of the
//! schedule's point field (the time-weighted segment fields,
//! [`platefield::pose::schedule_field`]), its equilibria with their stability,
//! and the basins of 200 drops integrated along it. With `--play-drops N`
//! the first N of those drops are also played by the planar simulator for
//! 20 s each (minutes per part: off by default). The bracket with 3
//! unknown contacts gives the unknown-support bounds. Last, the shipped
//! pose targets (`targets/pose_*.json`) designed by
//! [`platefield::pose::design::design_pose`] (one synthesized motion placed by
//! rigid transforms) with 100 played drops each (about a minute of CPU per
//! part), with the lifted equilibria of the kept schedule's predicted and
//! realised point fields.

use std::fmt::Write as _;
use std::path::Path;

use platefield::output::write_all_atomic;
use platefield::part::Part;
use platefield::play::ScheduleMotion;
use platefield::pose::design::PoseTarget;
use platefield::pose::{
    analyse, played_basins, schedule_field, Bounds, DropPlay, PlayedBasins, PoseAnalysis, Region,
};
use platefield::schedule::Schedule;
use platefield::{Error, Result};

/// Default output folder.
pub const DIR: &str = "results";

/// The shipped parts.
const PARTS: [&str; 3] = ["rectangle", "bracket", "triangle"];

/// The designed ellipses and the angle of their weaker contraction (°).
const ELLIPSES: [(&str, f64); 2] = [("ellipse", 0.0), ("ellipse_30", 30.0)];

/// Drops integrated along the lifted field per part and ellipse.
const DROPS: usize = 200;

/// Seconds each played drop is simulated.
const PLAY_S: f64 = 20.0;

/// The scan of the unknown-support bounds.
const SCAN: [usize; 3] = [24, 24, 36];

fn load_schedule(name: &str) -> Result<(Schedule, Region)> {
    let s = Schedule::load(Path::new(&format!("results/{name}/schedule.json")))?;
    let grid = s.target_spec.as_ref().and_then(|t| t.grid).ok_or_else(|| {
        Error::invalid(
            format!("results/{name}/schedule.json: target_spec.grid"),
            "missing; the study needs the designed target's grid",
        )
    })?;
    Ok((
        s,
        Region {
            x: grid.x,
            y: grid.y,
        },
    ))
}

/// An equilibrium's table cells: x (mm) | y (mm) | θ (°) | stable.
fn equilibrium_cells(e: &platefield::pose::Equilibrium) -> String {
    format!(
        "{:+.2} | {:+.2} | {:+.2} | {}",
        1e3 * e.pose.r.x,
        1e3 * e.pose.r.y,
        e.pose.theta.to_degrees(),
        if e.stable { "yes" } else { "no" }
    )
}

/// One part's table of equilibria on one ellipse.
fn table(md: &mut String, a: &PoseAnalysis, played: Option<&PlayedBasins>) {
    md.push_str("| x (mm) | y (mm) | θ (°) | stable | basin (lifted) | basin (played) | Jacobian real parts (1/s) |\n|---|---|---|---|---|---|---|\n");
    for (i, (e, b)) in a.equilibria.iter().zip(&a.basins).enumerate() {
        let p = played
            .map(|p| format!("{:.1} %", 100.0 * p.basins[i]))
            .unwrap_or_else(|| "not played".into());
        let _ = writeln!(
            md,
            "| {} | {:.1} % | {p} | {:.3}, {:.3}, {:.3} |",
            equilibrium_cells(e),
            100.0 * b,
            e.rates[0],
            e.rates[1],
            e.rates[2]
        );
    }
    if let Some(p) = played {
        let _ = writeln!(
            md,
            "\nPlayed: {} drops for {:.1} s each; {:.1} % end at the stable pose the lifted field predicts; {} lost contact; largest end distance from its pose {:.3} (|Δr|/R + |Δθ| rad).",
            p.ends.len(),
            p.time,
            100.0 * p.agreement,
            p.lost,
            p.worst
        );
    }
    let _ = writeln!(
        md,
        "\nUnsettled (lifted): {:.1} % of {} drops.\n",
        100.0 * a.unsettled,
        a.drops
    );
}

/// The lifted equilibria `eqs` of `part` refined on the averaged field of `sm` (the period map of the
/// played schedule, `pose::played_rests`): a table.
fn averaged_table(
    md: &mut String,
    part: &Part,
    sm: &ScheduleMotion,
    settings: &platefield::field::FieldSettings,
    eqs: &[platefield::pose::Equilibrium],
    region: &Region,
) {
    use platefield::pose::{played_rests, AveragedField, RestOutcome};
    let averaged = AveragedField::for_part(part, sm.clone(), settings.physics());
    let refined = played_rests(&averaged, eqs, region, &|| {});
    md.push_str("Refined on the averaged field (the part played period after period from the pose, joins included: its zeros are the played rests; `pose::played_rests`, Newton from each lifted equilibrium):\n\n| from θ (lifted, °) | x (mm) | y (mm) | θ (°) | stable | moved (mm) | turned (°) | Newton steps |\n|---|---|---|---|---|---|---|---|\n");
    for r in &refined {
        let from = r.from.pose;
        let row = match (r.outcome, r.moved()) {
            (
                RestOutcome::Found {
                    equilibrium: e,
                    steps,
                },
                Some((d, t)),
            ) => format!(
                "{} | {:.2} | {:+.2} | {steps}",
                equilibrium_cells(&e),
                1e3 * d,
                t.to_degrees()
            ),
            (other, _) => format!("{} | | | | | | ", other.failure().unwrap_or_default()),
        };
        let _ = writeln!(md, "| {:+.2} | {row} |", from.theta.to_degrees());
    }
    md.push('\n');
}

/// The bracket with 3 unknown contacts on `field`: the bounds' size.
fn bounds_section(
    md: &mut String,
    field: &platefield::pose::GridField,
    region: &Region,
) -> Result<()> {
    let part = Part::from_json_str(
        r#"{"name": "bracket", "polygon": [[0, 0], [0.03, 0], [0.03, 0.005], [0.005, 0.005], [0.005, 0.02], [0, 0.02]],
            "support": {"unknown": {"contacts": 3}}}"#,
    )?;
    let kept = Bounds::new(&part, field).scan(region, SCAN);
    let reach = kept.iter().map(|p| p.r.norm()).fold(0.0, f64::max);
    let _ = writeln!(
        md,
        "## Unknown support: the bracket on 3 unknown contacts (designed ellipse)\n\n\
         Of a {} × {} × {} scan of (x, y, θ) over the region, {} poses may rest for some \
         admissible support (`pose::Bounds`, an outer bound: 0 in the convex hull of the contact \
         wrenches, sampling margin included); the farthest centre is {:.1} mm from the plate \
         centre (part radius {:.1} mm). With an unknown support the elliptic sink bounds the \
         position (the part must cover the field's zero) but hardly the orientation: a part \
         resting on a contact at the zero is in equilibrium at every angle. \
         `tests/poses.rs` `unknown_support_bounds_contain_random_supports` checks that the bound \
         holds every equilibrium of 20 random 3-contact supports.\n",
        SCAN[0],
        SCAN[1],
        SCAN[2],
        kept.len(),
        1e3 * reach,
        1e3 * part.radius()
    );
    Ok(())
}

/// The pose-target section's head.
const POSE_TARGETS_INTRO: &str = "## Pose targets (`design` of `targets/pose_*.json`)\n\n\
Each part asked for at a nonzero angle off the centre (`\"field\": {\"kind\": \"pose\", …}`), \
designed by `platefield design targets/pose_<part>.json` (`pose::design`: one six-signal motion \
synthesized once for the centred elliptic sink (−0.3x, −y), turned and shifted onto the pose by \
rigid transforms of the motion (the turn exact, the shift exact for a spin about the vertical and to first order in the tilts), \
the placement corrected on played probes from spread starts without redesign) and played from 100 random drops by the planar simulator; goal: 95 % within 1 mm and \
3° modulo the part's symmetry. A linear field turns a part by its second moments only, so a part \
without a 180° symmetry (the bracket, the triangle) has two stable poses 180° apart in it, each \
with about half the drops. A unique pose needs a field nonlinear over the part. For such a part \
`design` plays a cycle (`pose::design::cycle`): a stage of the isotropic sink with its translation scaled by \
0.15–0.6 and a spin about the vertical out of phase with it (`pose::design::spin`: the slip path at p \
is an ellipse spanned by the translation and the rotation's velocity at p, so the mean friction \
direction turns across the plate on the scale r* = V/Ω ≈ 1.4–27 mm: 61–70 % off affine over ±4 cm \
at 9–27 mm), which selects one of the ellipse's two poses, then a stage of the elliptic sink placed on \
the spun sink's played rest, which sets it (the spun sink alone left the triangle's drops 92 % at \
the pose and 7 % at a second rest 139° away, and its rest turned 17.6° over μ ± 20 %). The ellipse \
stage lasts ln(d)/λ, λ its slowest lifted decay rate and d the larger of the drop region's \
half-diagonal over 1 mm and tan Δθ / tan 3°, Δθ the spin stage's worst turn at the hand-over (the \
ellipse's torque goes as sin 2Δθ, so tan Δθ decays as e^{−λt}: `pose::design::cycle::Stages::handed_over`); \
the spin stage lasts as long as the placed spin takes to bring a part from either of the ellipse's \
two rests within 45° of the asked pose at μ and μ ± 20 %, measured by play (`pose::design::handover`); \
the drops play 3 periods: a drop's settle time is counted in whole periods, so the period bounds it \
from below. Its 7 \
candidate spins are judged by play, not by the lifted field alone (`pose::design::screen`: 32 probes \
× 60 s on the centred spun sink from a 4 × 4 grid of starts and each start again turned by 180° \
(the elliptic stage's two rests lie 180° apart: the twins probe the rival one's basin), whose \
largest cluster places the ellipse stage, then 32 × 20 s or 3 periods, as long as the drops, on \
the cycle placed on the asked pose and scaled as shipped; a spin whose lifted stage estimate would \
exceed 40 s, or that hands no part over, is not played): it keeps the one whose cycle puts the largest share of probes at one pose, at least \
75 %, then the shortest cycle; when none is kept, the same 7 with r* halved (`Spin::finer`), \
else the elliptic sink alone. A cycle's lifted field is the \
stages' time average, which no played part sees: its drops are counted by where they end, not by \
basin (`tests/pose_rotation.rs` `explore_cycle`, `docs/parts.md`).\n\n";

/// The shipped pose targets (`targets/pose_*.json`).
const POSE_TARGETS: [&str; 3] = ["rectangle", "bracket", "triangle"];

/// One pose target designed with [`platefield::pose::design::DROPS`] played
/// drops: its report section, the lifted equilibria of its predicted and
/// realised point fields, and a summary line; its kept schedule written to
/// `out/poses/<name>/schedule.json` (what `export` and `verify` take, and
/// `tests/envelope.rs` holds to its limits).
fn pose_target(md: &mut String, summary: &mut String, name: &str, out: &Path) -> Result<()> {
    let (path, req, d) = designed(name)?;
    let folder = out.join("poses").join(name);
    std::fs::create_dir_all(&folder).map_err(|e| Error::Io {
        path: folder.display().to_string(),
        source: e,
    })?;
    let file = folder.join("schedule.json");
    write_all_atomic(&[(&file, d.method.kept().schedule.to_json()?.as_bytes())])?;
    let _ = writeln!(summary, "wrote {}", file.display());
    let _ = writeln!(md, "### {name} (`{path}`)\n");
    let section = platefield_report::pose_design::pose_md(&d);
    md.push_str(section.trim_start_matches("## Pose target\n\n"));
    let schedule = &d.method.kept().schedule;
    let grid = req.target.grid.unwrap_or(platefield::field::Grid::DEFAULT);
    let n = req.part.symmetry();
    let near = |field: &dyn platefield::pose::PointField| {
        let eqs = platefield::pose::equilibria(
            &platefield::pose::LiftedField::new(field, &req.part.body),
            &req.region,
        );
        platefield::pose::design::search::nearest_stable(&eqs, &req.pose, n, req.part.radius())
            .map_or("none stable".to_string(), |e| {
                let (d, t) = platefield::pose::design::search::pose_error(&e.pose, &req.pose, n);
                format!("{:.2} mm, {:+.2}°", 1e3 * d, t.to_degrees())
            })
    };
    let predicted_field = schedule_field(schedule, &grid)?;
    let predicted = near(&predicted_field);
    // A physically invalid play (a point part leaving the plate somewhere
    // on the grid; the planar drops count such parts as lost) is said so,
    // not a failed study.
    let realised = match platefield::pose::realised_field(schedule, &grid) {
        Ok(field) => near(&field),
        Err(Error::ContactLost(why)) => format!("none ({why})"),
        Err(e) => return Err(e),
    };
    let _ = writeln!(
        md,
        "\nThe kept schedule's stable pose nearest the asked one, from the lifted field of its predicted point field (time-weighted segment steady states): {predicted}; of its realised point field (point parts played with frozen positions at every second grid point, joins included, `pose::realised_field`): {realised}.\n"
    );
    let lifted = platefield::pose::equilibria(
        &platefield::pose::LiftedField::new(&predicted_field, &req.part.body),
        &req.region,
    );
    let stable: Vec<_> = lifted.into_iter().filter(|e| e.stable).collect();
    let sm = ScheduleMotion::from_schedule(schedule)?;
    averaged_table(md, &req.part, &sm, &schedule.settings, &stable, &req.region);
    let p = platefield_report::pose_design::played(&d);
    let _ = writeln!(
        summary,
        "pose_{name}: {:.1} % of {} drops within 1 mm and 3°, {} stable poses modulo symmetry",
        100.0 * p.pose_fraction,
        p.drops,
        p.distinct_stable
    );
    Ok(())
}

/// The shipped pose target `targets/pose_{name}.json` designed as
/// `design` does ([`designed_at`]): its path, request and design.
///
/// # Errors
/// A target that does not load, is not a pose target or does not design.
pub(crate) fn designed(
    name: &str,
) -> Result<(String, PoseTarget, platefield::pose::design::PoseDesign)> {
    let path = format!("targets/pose_{name}.json");
    let (req, d) = designed_at(Path::new(&path))?;
    Ok((path, req, d))
}

/// The pose target at `path` designed as `design` does, quietly, with
/// [`platefield::pose::design::DROPS`] drops: its request and design.
///
/// # Errors
/// A target that does not load, is not a pose target or does not design.
pub(crate) fn designed_at(
    path: &Path,
) -> Result<(PoseTarget, platefield::pose::design::PoseDesign)> {
    use platefield::pose::design::{design_pose, DROPS};
    let req = PoseTarget::load(path)?
        .ok_or_else(|| Error::invalid(path.display().to_string(), "is not a pose target"))?;
    let opts = platefield::design::DesignOptions {
        runtime: platefield::work::Runtime::QUIET,
        ..Default::default()
    };
    let d = design_pose(&req, &opts, DROPS)?;
    Ok((req, d))
}

/// Writes `md` to `out/file` (the folder made first) and appends the
/// "wrote" line to `summary`, which it returns.
///
/// # Errors
/// The folder or the file cannot be written.
pub(crate) fn write_md(out: &Path, file: &str, md: &str, mut summary: String) -> Result<String> {
    std::fs::create_dir_all(out).map_err(|e| Error::Io {
        path: out.display().to_string(),
        source: e,
    })?;
    let path = out.join(file);
    write_all_atomic(&[(&path, md.as_bytes())])?;
    let _ = writeln!(summary, "wrote {}", path.display());
    Ok(summary)
}

/// The work `--play-drops` adds to the study: `play_drops` drops of each
/// part played on each designed ellipse for its play time
/// ([`platefield::pose::drops_estimate`], in point-part steps); no terms
/// without drops.
///
/// # Errors
/// A designed ellipse or part file that does not load.
pub fn played_drops_estimate(play_drops: usize) -> Result<platefield::work::Estimate> {
    let mut total =
        platefield::work::Estimate::new("--play-drops", "playing the drops", "fewer --play-drops");
    if play_drops == 0 {
        return Ok(total);
    }
    for (name, _) in ELLIPSES {
        let (schedule, _) = load_schedule(name)?;
        let sm = ScheduleMotion::from_schedule(&schedule)?;
        let play = DropPlay::new(&schedule.settings, PLAY_S);
        for part_name in PARTS {
            let part = Part::load(Path::new(&format!("targets/parts/{part_name}.json")))?;
            total
                .terms
                .extend(platefield::pose::drops_estimate(&part, &sm, play_drops, &play).terms);
        }
    }
    Ok(total)
}

/// Runs the study and writes `poses.md` into `out`; `play_drops` drops of
/// each part are played by the planar simulator (0: none).
pub fn run(out: &Path, play_drops: usize) -> Result<String> {
    platefield::output::check_writable(out, "--out")?;
    if play_drops > DROPS {
        return Err(Error::invalid(
            "--play-drops",
            format!("must be in 0..={DROPS}, got {play_drops}"),
        ));
    }
    let mut md = format!(
        "# Parts with planar extent on the designed elliptic sinks (issue 28)\n\n\
         Regenerate: `platefield study poses{}` (deterministic). Fields: the designed schedules \
         `results/ellipse/schedule.json` (target (−0.3x, −y): weaker contraction along x) and \
         `results/ellipse_30/schedule.json` (the same turned by 30°), each the time-weighted \
         mean of its segments' point-part velocity fields on its target grid. Per part: the \
         lifted field's equilibria (centre of mass, angle of the part file's x axis), stability \
         from the eigenvalues of its Jacobian, and the basin of each stable pose from {DROPS} \
         random drops (centres uniform over the region inset by the part's radius, angles \
         uniform) integrated along the lifted field; with `--play-drops N` the first N drops are \
         also played by the planar simulator for {PLAY_S} s (full stick-slip of every support \
         point) and each end classified by its nearest stable pose. Each lifted equilibrium is \
         then refined on the averaged field (`pose::AveragedField`: the part played period after \
         period from the pose, every support point's stick-slip and the joins included, so its \
         zeros are the poses a played part returns to; `pose::played_rests`).\n\n\
         The designed ellipses give every part two stable poses 180° apart (each with about \
         half the drops), not one; the pose targets (last section) ask for one.\n\n",
        if play_drops > 0 {
            format!(" --play-drops {play_drops}")
        } else {
            String::new()
        }
    );
    let mut summary = String::new();
    for (name, phi) in ELLIPSES {
        let (schedule, region) = load_schedule(name)?;
        let grid = schedule
            .target_spec
            .as_ref()
            .and_then(|t| t.grid)
            .expect("checked by load_schedule");
        let field = schedule_field(&schedule, &grid)?;
        let sm = ScheduleMotion::from_schedule(&schedule)?;
        let _ = writeln!(md, "## {name}: weaker contraction along {phi}°\n");
        for part_name in PARTS {
            let part = Part::load(Path::new(&format!("targets/parts/{part_name}.json")))?;
            let a = analyse(&part, &field, region, DROPS);
            let played = (play_drops > 0).then(|| {
                let mut few = a.clone();
                few.drops = play_drops;
                few.ends.truncate(play_drops);
                played_basins(&few, &part, &sm, &DropPlay::new(&schedule.settings, PLAY_S))
            });
            let _ = writeln!(md, "### {part_name}\n");
            table(&mut md, &a, played.as_ref());
            averaged_table(
                &mut md,
                &part,
                &sm,
                &schedule.settings,
                &a.equilibria,
                &region,
            );
            let _ = writeln!(
                summary,
                "{name} {part_name}: {} equilibria, {} stable",
                a.equilibria.len(),
                a.equilibria.iter().filter(|e| e.stable).count()
            );
        }
        if name == "ellipse" {
            bounds_section(&mut md, &field, &region)?;
        }
    }
    md.push_str(POSE_TARGETS_INTRO);
    for name in POSE_TARGETS {
        pose_target(&mut md, &mut summary, name, out)?;
    }
    write_md(out, "poses.md", &md, summary)
}
