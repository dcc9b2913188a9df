//! Pose targets in `design` (issue 28): bad pose-target input exits 2
//! naming the JSON path; the rectangle's pose design, its placement on the
//! lifted field and its played drops.

use std::path::{Path, PathBuf};
use std::process::Command;

use platefield::design::pose::{search, PoseRequest};
use platefield::design::DesignOptions;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// A pose target in `dir` with `field` as its field, `half` the region's
/// half-width (m).
fn target(dir: &Path, field: &str, half: f64) -> PathBuf {
    write(
        dir,
        "pose.json",
        &format!(
            r#"{{"name": "pose", "grid": {{"x": [-{half}, {half}], "y": [-{half}, {half}], "n": [21, 21]}},
                "field": {field}}}"#
        ),
    )
}

#[test]
fn bad_pose_targets_exit_2_naming_the_path() {
    let dir = std::env::temp_dir().join(format!("pf_pose_design_{}", std::process::id()));
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    std::fs::copy(
        "targets/parts/rectangle.json",
        dir.join("parts/rectangle.json"),
    )
    .unwrap();
    let part = r#""part": "parts/rectangle.json""#;
    let cases = [
        (
            format!(r#"{{"kind": "pose", {part}, "pose": [0.0, 0.0]}}"#),
            0.04,
            "target.field.pose: must be [x, y, theta_deg]",
        ),
        (
            format!(r#"{{"kind": "pose", {part}, "pose": [0.0, "a", 0]}}"#),
            0.04,
            "target.field.pose[1]: must be a finite number",
        ),
        (
            format!(r#"{{"kind": "pose", {part}, "pose": [0.035, 0.0, 0]}}"#),
            0.04,
            "target.field.pose: the part placed at this pose reaches",
        ),
        (
            format!(r#"{{"kind": "pose", {part}, "pose": [0, 0, 0]}}"#),
            0.008,
            "target.field.part: part.polygon: the part",
        ),
        (
            r#"{"kind": "pose", "part": "parts/none.json", "pose": [0, 0, 0]}"#.to_string(),
            0.04,
            "target.field.part: cannot read",
        ),
        (
            format!(r#"{{"kind": "pose", {part}, "pose": [0, 0, 0], "angle": 3}}"#),
            0.04,
            "target.field.angle: unknown key",
        ),
    ];
    for (field, half, needle) in cases {
        let path = target(&dir, &field, half);
        let out = Command::new(env!("CARGO_BIN_EXE_platefield"))
            .args(["design", path.to_str().unwrap(), "--quiet", "--out"])
            .arg(dir.join("out"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{field}: {err}");
        assert!(
            err.contains(needle),
            "{field}: expected {needle:?} in {err}"
        );
        assert!(!dir.join("out/pose").exists(), "{field}: nothing written");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The rectangle's elliptic candidate placed on its designed lifted field:
/// one stable pose modulo 180° (the rectangle's symmetry, detected), within
/// 1 mm and 1° of the asked (12 mm, −8 mm, 30°).
#[test]
fn rectangle_pose_is_the_lifted_fields_stable_equilibrium() {
    let req = PoseRequest::load(Path::new("targets/pose_rectangle.json"))
        .unwrap()
        .unwrap();
    assert_eq!(req.part.symmetry(), 2);
    let opts = DesignOptions {
        quiet: true,
        ..DesignOptions::default()
    };
    let trial = search::place(&req, &opts, search::Family::Ellipse { ratio: 0.5 }).unwrap();
    assert_eq!(trial.distinct, 1, "{:?}", trial.equilibria);
    let (mm, deg) = trial.error(&req.pose, 2).unwrap();
    assert!(mm <= 1.0 && deg.abs() <= 1.0, "{mm} mm, {deg}°");
    // Both stable poses are the same pose of the part turned by 180°.
    let stable: Vec<_> = trial.equilibria.iter().filter(|e| e.stable).collect();
    assert_eq!(stable.len(), 2);
    let turn = (stable[0].pose.theta - stable[1].pose.theta)
        .abs()
        .to_degrees();
    assert!((turn - 180.0).abs() < 1e-3, "{turn}");
}
