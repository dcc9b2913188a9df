//! Pose designs played over the part's friction range
//! (`pose::design::friction`): a part file's range reaches the drops at
//! each of its values, an exact friction leaves `over_friction` absent
//! (the schedule's bytes unchanged), and on a mirror-symmetric schedule a
//! friction error moves the lifted pose nowhere and scales its rates by
//! one factor.
//!
//! Played on the designed ellipse `results/ellipse/schedule.json`
//! (sequenced, (−0.3x, −y)) with the rectangle asked at the centre at 0°,
//! one of its two stable poses there (`tests/poses.rs`); an 11 × 11 grid
//! and 3 drops keep it to seconds.

use std::path::{Path, PathBuf};

use crate::design::stacked::ranged;
use crate::dynamics::Friction;
use crate::pose::design::{friction, PoseTarget};
use crate::request::FrictionSpec;
use crate::schedule::{PoseAtFriction, PoseOverFriction, PosePlayed, Schedule};

/// The rectangle with `friction` (JSON) asked at the centre, 0°, over ±4 cm.
fn request(tag: &str, friction: &str) -> PoseTarget {
    let dir: PathBuf = std::env::temp_dir().join(format!("platefield-pose-friction-{tag}"));
    std::fs::create_dir_all(&dir).unwrap();
    let part = format!(
        r#"{{"name": "rectangle", "polygon": [[-0.01, -0.0025], [0.01, -0.0025], [0.01, 0.0025], [-0.01, 0.0025]], "friction": {friction}}}"#
    );
    std::fs::write(dir.join("part.json"), part).unwrap();
    let target = r#"{"name": "pose_test", "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [11, 11]},
    "field": {"kind": "pose", "part": "part.json", "pose": [0, 0, 0]}}"#;
    PoseTarget::from_json_str(target, &dir).unwrap().unwrap()
}

/// Drops played at each friction: enough for the two ends to differ.
const DROPS: usize = 3;

fn ellipse() -> Schedule {
    Schedule::load(Path::new("results/ellipse/schedule.json")).unwrap()
}

/// What the drops decide at one friction (the lifted field's own columns
/// left out): the fraction at the pose, the median settle, each played basin.
fn played(a: &PoseAtFriction) -> (f64, Option<f64>, Vec<f64>) {
    (
        a.pose_fraction,
        a.median_settle_s,
        a.stable.iter().map(|b| b.played).collect(),
    )
}

/// A part file's friction range becomes the target's, and `play_at` plays
/// the drops with each value: the ends give different lifted fields and
/// different played drops, and each row names its friction. Measured: none of the 3 drops at the pose
/// after 20 s at μ 0.2 (slowest lifted rate 0.097 1/s), 2 of 3 at 0.4
/// (0.172 1/s).
#[test]
fn a_part_friction_range_reaches_the_drops_at_each_value() {
    let req = request("range", "[0.2, 0.4]");
    let range = ranged(&req.target).expect("the part's range becomes the target's");
    assert_eq!(range, FrictionSpec::range(0.2, 0.4));
    let values = range.values(friction::PER_RANGE);
    assert_eq!(values.len(), 3);
    let s = ellipse();
    let at: Vec<PoseAtFriction> = [values[0], values[2]]
        .iter()
        .map(|&f| friction::play_at(&req, &s, f, 1.0, DROPS).unwrap())
        .collect();
    for (a, f) in at.iter().zip([values[0], values[2]]) {
        assert_eq!(a.friction, f);
        println!(
            "μ {:.2}: {:?}, lifted offset {:?}, rates {:?}",
            f.kinetic,
            played(a),
            a.lifted_offset,
            a.lifted_rates
        );
    }
    assert_ne!(
        played(&at[0]),
        played(&at[1]),
        "the drops at μ 0.2 and 0.4 must differ"
    );
    assert_ne!(at[0].lifted_rates, at[1].lifted_rates);
    symmetric_schedule_keeps_the_pose(&at[0], &at[1]);
}

/// What holds of the μ dependence on this schedule, whose four line sinks
/// at 0°, 90°, 180° and 270° make a field mirror-symmetric in x and in y
/// at every μ (a line sink's field is odd across its line): the lifted
/// field's stable pose stays at the centre and at 0° (offset below
/// 1e-6 mm and 1e-6°) at both ends of the range, so on such a schedule a
/// friction error changes the speed of the approach, never the pose.
/// The speed: each decay rate grows with μ by one common factor (the
/// line sink's field is scaled, its profile over the part kept): the
/// three rates' ratios μ 0.4 / μ 0.2 agree within 2 % and exceed 1
/// (measured 1.78 for all three: the velocity field grows less than μ
/// does, which doubles).
fn symmetric_schedule_keeps_the_pose(lo: &PoseAtFriction, hi: &PoseAtFriction) {
    for a in [lo, hi] {
        let [d, t] = a.lifted_offset.expect("a stable pose at the centre");
        assert!(d < 1e-6 && t.abs() < 1e-6, "{d} mm, {t}°");
    }
    let (rl, rh) = (lo.lifted_rates.unwrap(), hi.lifted_rates.unwrap());
    let ratios: Vec<f64> = rl.iter().zip(&rh).map(|(l, h)| h / l).collect();
    println!("rate ratios μ 0.4 / μ 0.2: {ratios:?}");
    for r in &ratios {
        assert!(*r > 1.0 && *r < 2.0, "{ratios:?}");
        assert!((r / ratios[0] - 1.0).abs() < 0.02, "{ratios:?}");
    }
}

/// The shipped pose targets' parts state one friction: no range, and
/// `over_range` returns the design's own play unchanged, its JSON without
/// `over_friction` (so a shipped design's `schedule.json` keeps its bytes).
/// A recorded `over_friction` reads back as written.
#[test]
fn an_exact_friction_leaves_over_friction_absent() {
    for name in ["rectangle", "bracket", "triangle"] {
        let path = format!("targets/pose_{name}.json");
        let req = PoseTarget::load(Path::new(&path)).unwrap().unwrap();
        assert_eq!(ranged(&req.target), None, "{path}");
    }
    let req = request("exact", "0.3");
    assert_eq!(ranged(&req.target), None);
    let s = ellipse();
    let nominal = PosePlayed {
        part: "part.json".into(),
        pose: [0.0; 3],
        symmetry: 2,
        field: "ellipse".into(),
        drops: 6,
        duration_s: 20.0,
        tolerance: [1.0, 3.0],
        pose_fraction: 0.5,
        median_settle_s: None,
        lost: 0,
        stable: vec![],
        distinct_stable: 1,
        over_friction: None,
    };
    let same = friction::over_range(&req, &s, nominal.clone(), 1.0, None).unwrap();
    assert_eq!(same, nominal);
    let json = serde_json::to_string(&same).unwrap();
    assert!(!json.contains("over_friction"), "{json}");
    let at = friction::play_at(&req, &s, Friction::uniform(0.3), 1.0, 2).unwrap();
    let with = PosePlayed {
        over_friction: Some(PoseOverFriction {
            range: FrictionSpec::range(0.24, 0.36),
            worst_pose_fraction: at.pose_fraction,
            at: vec![at],
        }),
        ..nominal
    };
    let text = serde_json::to_string(&with).unwrap();
    assert_eq!(serde_json::from_str::<PosePlayed>(&text).unwrap(), with);
}
