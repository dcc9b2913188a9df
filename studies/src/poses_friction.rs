//! "Robust, not lucky": the shipped pose designs played over
//! ±20 % of their part's friction, `results/poses_friction.md`.
//!
//! Each shipped pose target (`targets/pose_{rectangle,bracket,triangle}.json`,
//! parts of μ = 0.3, and `pose_{bracket,triangle}_range.json`, designed for
//! μ ∈ [0.24, 0.36], whose own plays over the range are their rows) is
//! designed as `design` does
//! ([`platefield::pose::design::design_pose`], [`platefield::pose::design::DROPS`] drops) and its kept
//! schedule's drops are played again, from the same starts for the same
//! time, at μ 0.24 and 0.36 ([`FrictionSpec::around`] 0.3 by
//! [`FRACTION`], its ends and middle: the middle is the design's own
//! play), each judged against the lifted field at that μ
//! ([`platefield::pose::design::friction`]). Minutes of CPU: three designs, then
//! three times their drops; its own command, `platefield study poses-friction`.

use std::fmt::Write as _;
use std::path::Path;

use platefield::pose::design::friction;
use platefield::request::FrictionSpec;
use platefield::Result;

/// Default output folder.
pub const DIR: &str = "results";

/// The shipped pose targets: the three at the part's μ, then the bracket
/// and the triangle designed for μ ∈ [0.24, 0.36]
/// (`targets/pose_{bracket,triangle}_range.json`).
const TARGETS: [&str; 5] = [
    "rectangle",
    "bracket",
    "triangle",
    "bracket_range",
    "triangle_range",
];

/// The friction band played: ± this fraction of the part's μ.
pub const FRACTION: f64 = 0.2;

/// The study's head.
const INTRO: &str = "Each shipped pose target designed as `platefield design targets/pose_<part>.json` \
does (the part's μ = 0.3; `results/poses.md` has each design), then its kept schedule's drops \
played again from the same starts for the same time with the parts' friction at 0.24 and 0.36 \
(±20 %), and at 0.30 again (the design's own play, the same bytes): every support point's Coulomb law in the planar \
simulator at that μ, each end judged against the lifted field at that μ \
(`pose::design::friction`). The last two sections are the bracket and the triangle designed \
for μ ∈ [0.24, 0.36] (`targets/pose_<part>_range.json`): spin candidates screened in their cycle \
with the ellipse at the range's middle and ends, kept only if the cycle's played pose turns by at most twice the tolerance between the \
ends, and the placement centred between the ends' rests (`pose::design::screen`, \
`pose::design::correct`); their rows are the design's own plays over the range. Columns: the fraction of the drops ending within 1 mm and 3° of the \
asked pose (modulo the part's symmetry), the median settle time, drops that lost contact, the \
lifted field's stable poses modulo symmetry and each one's played basin, where the played drops \
rest near the asked pose (the median distance and signed angle from it of the ends within 30° of \
it), and the lifted field's stable pose nearest the asked one: its distance and angle from the asked pose and its slowest \
decay rate.\n\n";

/// One target designed and played over the band: its section and a
/// summary line.
fn target(md: &mut String, summary: &mut String, name: &str) -> Result<()> {
    let (path, req, d) = super::poses::designed(name)?;
    let schedule = &d.method.kept().schedule;
    let nominal = platefield_report::pose_design::played(&d).clone();
    let band = FrictionSpec::around(schedule.settings.friction, FRACTION);
    let own = nominal.pose_fraction;
    // A design for a range has played its drops over it already.
    let p = match nominal.over_friction {
        Some(_) => nominal,
        None => friction::over_range(&req, schedule, nominal, friction::rate(&d), Some(band))?,
    };
    let o = p
        .over_friction
        .as_ref()
        .expect("over_range with a range records it");
    let _ = writeln!(
        md,
        "## {name} (`{path}`)\n\n{} drops of {:.1} s, pose ({:.1} mm, {:.1} mm, {:.1}°), symmetry {}; field {}.\n\n{}",
        p.drops,
        p.duration_s,
        1e3 * p.pose[0],
        1e3 * p.pose[1],
        p.pose[2],
        p.symmetry,
        p.field,
        platefield_report::pose_friction::table(o)
    );
    let cells: Vec<String> =
        o.at.iter()
            .map(|a| format!("{:.1} %", 100.0 * a.pose_fraction))
            .collect();
    let _ = writeln!(
        summary,
        "pose_{name}: within 1 mm and 3° at μ {}: {} (the design's own play: {:.1} %)",
        band.to_json(),
        cells.join(" / "),
        100.0 * own
    );
    Ok(())
}

/// Runs the study and writes `poses_friction.md` into `out`.
///
/// # Errors
/// An unwritable `out`; a shipped pose target that does not load or design.
pub fn run(out: &Path) -> Result<String> {
    platefield::output::check_writable(out, "--out")?;
    let mut md = format!(
        "# Pose designs over ±{:.0} % of the part's friction (issue 28)\n\n\
         Regenerate: `platefield study poses-friction` (deterministic). {INTRO}",
        100.0 * FRACTION
    );
    let mut summary = String::new();
    for name in TARGETS {
        target(&mut md, &mut summary, name)?;
    }
    super::poses::write_md(out, "poses_friction.md", &md, summary)
}
