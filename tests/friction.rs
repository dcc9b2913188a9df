//! The parts' friction in a target: read, validated, used by every
//! simulation of a design, recorded in `schedule.json`, and played back by
//! `verify` at the schedule's own friction or at another one.

use std::path::{Path, PathBuf};

mod common;
use common::platefield;

fn temp_dir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("platefield-friction-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `targets/sink.json` with `extra` keys set (e.g. `"friction": 0.2`).
fn sink_with(dir: &Path, name: &str, extra: &[(&str, serde_json::Value)]) -> String {
    let text = std::fs::read_to_string("targets/sink.json").unwrap();
    let mut t: serde_json::Value = serde_json::from_str(&text).unwrap();
    t["name"] = name.into();
    for (k, v) in extra {
        t[*k] = v.clone();
    }
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, t.to_string()).unwrap();
    path.display().to_string()
}

/// Each bad friction or gravity exits 2 naming its JSON path and the
/// allowed range, and writes nothing.
#[test]
fn bad_friction_is_refused_naming_the_path() {
    let dir = temp_dir("bad");
    let out = dir.join("out");
    let cases: Vec<(serde_json::Value, &str, &str)> = vec![
        (
            serde_json::json!(-0.1),
            "target.friction",
            "must be in [0, 2], got -0.1",
        ),
        (
            serde_json::json!(2.5),
            "target.friction",
            "must be in [0, 2], got 2.5",
        ),
        (
            serde_json::json!([0.4, 0.2]),
            "target.friction",
            "(reversed)",
        ),
        (
            serde_json::json!([0.2, 3.0]),
            "target.friction[1]",
            "must be in [0, 2], got 3",
        ),
        (
            serde_json::json!("NaN"),
            "target.friction",
            "must be a number",
        ),
        (serde_json::json!([0.2]), "target.friction", "two numbers"),
        (
            serde_json::json!({"static": 0.2, "kinetic": 0.3}),
            "target.friction.static",
            "must be ≥ the kinetic coefficient 0.3",
        ),
        (
            serde_json::json!({"static": 0.3, "kinetik": 0.3}),
            "target.friction.kinetik",
            "unknown field",
        ),
    ];
    for (i, (friction, path, message)) in cases.into_iter().enumerate() {
        let name = format!("bad{i}");
        let target = sink_with(&dir, &name, &[("friction", friction.clone())]);
        let (code, stdout, err) = platefield(&[
            "design",
            &target,
            "--method",
            "sequence",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{friction}: {err}");
        assert!(
            err.contains(path) && err.contains(message),
            "{friction}: {err}"
        );
        assert!(stdout.is_empty());
        assert!(!out.join(&name).exists(), "{friction}: nothing written");
    }
    let target = sink_with(&dir, "badg", &[("gravity", serde_json::json!(0.0))]);
    let (code, _, err) = platefield(&["design", &target, "--out", out.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("target.gravity: must be in [0.1, 100] m/s², got 0"),
        "{err}"
    );
}

fn design_sequence(target: &str, out: &Path) -> serde_json::Value {
    let (code, stdout, err) = platefield(&[
        "design",
        target,
        "--method",
        "sequence",
        "--json",
        "--quiet",
        "--no-cache",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&stdout).expect("schedule JSON")
}

/// A design for μ = 0.2 is made, played and recorded at μ = 0.2. The
/// sequenced sink is four LineSinks, whose strength near their line is
/// eq. 19's b = μT(μ²g² − 3h²α²)/(8h²α): the predicted strength at μ 0.2
/// against μ 0.3 must follow b's ratio (0.676 for the paper's LineSink,
/// h = 5 cm, α = 218.4 rad/s², square-wave value) within 5 %; the sine
/// wave and the sink's extent away from the lines account for the rest.
#[test]
fn a_design_is_made_for_the_targets_friction() {
    let dir = temp_dir("design");
    let low = design_sequence(&sink_with(&dir, "mu02", &[("friction", 0.2.into())]), &dir);
    let nominal = design_sequence(&sink_with(&dir, "mu03", &[]), &dir);
    assert_eq!(low["settings"]["friction"]["kinetic"], 0.2);
    assert_eq!(low["settings"]["friction"]["static"], 0.2);
    assert_eq!(low["target_spec"]["friction"], 0.2);
    assert_eq!(nominal["settings"]["friction"]["kinetic"], 0.3);
    assert!(nominal["target_spec"].get("friction").is_none());
    let s = |d: &serde_json::Value| d["fit"]["strength"].as_f64().unwrap();
    let b = |mu: f64| {
        let (g, h, a, t) = (9.81, 0.05, 218.4_f64, 0.03);
        mu * t * (mu * mu * g * g - 3.0 * h * h * a * a) / (8.0 * h * h * a)
    };
    let (ratio, expected) = (s(&low) / s(&nominal), b(0.2) / b(0.3));
    assert!(
        (ratio / expected - 1.0).abs() < 0.05,
        "strength ratio {ratio:.4} against eq. 19's {expected:.4}"
    );
    // The design's own play is at its friction: realised close to predicted.
    let played = &low["played"];
    let realised = played["realised_strength"].as_f64().unwrap();
    assert!(
        (realised / s(&low) - 1.0).abs() < 0.15,
        "played at μ 0.2: {realised} against predicted {}",
        s(&low)
    );
    // A range designs for its middle.
    let range = design_sequence(
        &sink_with(
            &dir,
            "range",
            &[("friction", serde_json::json!([0.2, 0.4]))],
        ),
        &dir,
    );
    let mid = range["settings"]["friction"]["kinetic"].as_f64().unwrap();
    assert!((mid - 0.3).abs() < 1e-12, "{mid}");
    assert_eq!(
        range["target_spec"]["friction"],
        serde_json::json!([0.2, 0.4])
    );
}

/// Without `friction` a target designs exactly as before: the sequenced
/// sink's `schedule.json` is byte-identical to the committed one.
#[test]
fn no_friction_key_changes_nothing() {
    let dir = temp_dir("same");
    let (code, _, err) = platefield(&[
        "design",
        "targets/sink.json",
        "--method",
        "sequence",
        "--quiet",
        "--no-cache",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let new = std::fs::read(dir.join("sink/schedule.json")).unwrap();
    let old = std::fs::read("results/sequenced/sink/schedule.json").unwrap();
    assert!(
        new == old,
        "schedule.json differs from results/sequenced/sink/"
    );
}
