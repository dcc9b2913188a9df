//! A pose design's drops over the part's friction range
//! ([`platefield::pose::design::friction`]) as a markdown table: one row per
//! friction played.

use crate::table::Table;
use platefield::dynamics::Friction;
use platefield::schedule::{PoseAtFriction, PoseOverFriction};

/// μ as written: one number when static = kinetic, else both.
fn mu(f: &Friction) -> String {
    if f.stat == f.kinetic {
        format!("{:.3}", f.kinetic)
    } else {
        format!("{:.3} / {:.3}", f.stat, f.kinetic)
    }
}

/// The played basin of each stable pose, `θ°: %`.
fn basins(a: &PoseAtFriction) -> String {
    let cells: Vec<String> = a
        .stable
        .iter()
        .map(|b| format!("{:+.1}°: {:.0} %", b.pose[2], 100.0 * b.played))
        .collect();
    if cells.is_empty() {
        "none stable".into()
    } else {
        cells.join(", ")
    }
}

/// One row per friction: the fraction at the pose, the median settle,
/// the stable poses and their played basins, where the played drops rest
/// near the asked pose, and the lifted field's stable pose nearest it
/// (offset and slowest decay rate).
///
/// ```
/// use platefield::dynamics::Friction;
/// use platefield::request::FrictionSpec;
/// use platefield::schedule::{PoseAtFriction, PoseOverFriction};
/// let at = PoseAtFriction {
///     friction: Friction::uniform(0.3),
///     pose_fraction: 0.97,
///     median_settle_s: Some(6.0),
///     lost: 0,
///     stable: vec![],
///     distinct_stable: 1,
///     lifted_offset: Some([0.1, -0.5]),
///     lifted_rates: Some([0.4, 0.9, 1.1]),
///     played_offset: Some([0.05, 0.3]),
/// };
/// let o = PoseOverFriction { range: FrictionSpec::uniform(0.3), worst_pose_fraction: 0.97, at: vec![at] };
/// let md = platefield_report::pose_friction::table(&o);
/// assert!(md.contains("| 0.300 | 97.0 % | 6.0 s |"));
/// ```
pub fn table(o: &PoseOverFriction) -> String {
    let mut t = Table::new([
        "μ",
        "within 1 mm & 3°",
        "median settle",
        "lost",
        "stable poses (mod symmetry)",
        "played basins",
        "played rest off the asked (mm, °)",
        "lifted pose off the asked (mm, °)",
        "slowest lifted rate (1/s)",
    ]);
    for a in &o.at {
        t.row([
            mu(&a.friction),
            format!("{:.1} %", 100.0 * a.pose_fraction),
            a.median_settle_s
                .map_or("none".into(), |s| format!("{s:.1} s")),
            a.lost.to_string(),
            a.distinct_stable.to_string(),
            basins(a),
            a.played_offset
                .map_or("none near".into(), |[d, t]| format!("{d:.3}, {t:+.2}")),
            a.lifted_offset
                .map_or("none stable".into(), |[d, t]| format!("{d:.3}, {t:+.2}")),
            a.lifted_rates
                .map_or("—".into(), |r| format!("{:.3}", r[0])),
        ]);
    }
    t.markdown()
}

/// The section `report.md` carries for a design played over a friction
/// range: the worst fraction and the table.
pub fn section(o: &PoseOverFriction) -> String {
    format!(
        "\nOver the part's friction {} (ends and middle, the same drops and play time; `pose::design::friction`): worst {:.1} % within 1 mm and 3°.\n\n{}",
        o.range.to_json(),
        100.0 * o.worst_pose_fraction,
        table(o)
    )
}
