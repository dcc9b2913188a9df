//! The command-line shell: outputs and clear errors on bad input.

mod common;
use common::platefield;

const BASE: [&str; 7] = [
    "linesink", "--accel", "180", "--depth", "0.05", "--period", "0.03",
];

#[test]
fn linesink_json_reports_eq17_and_contact_loss() {
    let mut args = BASE.to_vec();
    args.extend([
        "--wave",
        "square",
        "--mu",
        "0.3",
        "--r",
        "0.01,0.06",
        "--json",
    ]);
    let (code, out, err) = platefield(&args);
    assert_eq!(code, 0, "{err}");
    let rows: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    let rows = rows.as_array().expect("array");
    assert_eq!(rows.len(), 2);
    let (v, e) = (
        rows[0]["v_ss"].as_f64().unwrap(),
        rows[0]["eq17"].as_f64().unwrap(),
    );
    assert!(((v - e) / e).abs() < 1e-9);
    assert_eq!(rows[0]["contact_lost"], false);
    assert_eq!(rows[0]["stick_fraction"].as_f64(), Some(0.0));
    assert_eq!(rows[1]["contact_lost"], true);
    assert!(rows[1]["v_ss"].is_null() && rows[1]["eq17"].is_null());
}

#[test]
fn linesink_sine_has_no_eq17() {
    let mut args = BASE.to_vec();
    args.extend(["--wave", "sine", "--r", "0.02", "--json", "--model", "full"]);
    let (code, out, _) = platefield(&args);
    assert_eq!(code, 0);
    let rows: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(rows[0]["eq17"].is_null());
    assert!(rows[0]["v_ss"].as_f64().unwrap() < 0.0);
}

#[test]
fn bad_linesink_input_names_the_argument() {
    let cases: [(&[&str], &str); 7] = [
        (&["--mu", "-0.1", "--r", "0.01"], "--mu"),
        (&["--r", "0.01", "--wave", "triangle"], "--wave"),
        (&["--r", ""], "--r"),
        (&["--r", "0.01,NaN"], "--r"),
        (&["--r", "0.01", "--model", "exact"], "--model"),
        (
            &["--r", "0.01", "--mu", "0.3", "--mu-static", "0.1"],
            "--mu-static",
        ),
        (&["--r", "0.01", "--steps", "0"], "--steps"),
    ];
    for (extra, name) in cases {
        let mut args = BASE.to_vec();
        args.extend_from_slice(extra);
        let (code, out, err) = platefield(&args);
        assert_ne!(code, 0, "{extra:?} should fail");
        assert!(
            err.contains(name),
            "{extra:?}: stderr {err:?} should name {name}"
        );
        assert!(out.is_empty(), "{extra:?}: nothing on stdout");
    }
    for (accel, depth, period, name) in [
        ("180", "0.05", "0", "--period"),
        ("180", "0.05", "-1", "--period"),
        ("nan", "0.05", "0.03", "--accel"),
        ("180", "inf", "0.03", "--depth"),
    ] {
        let args = [
            "linesink", "--accel", accel, "--depth", depth, "--period", period, "--r", "0.01",
        ];
        let (code, _, err) = platefield(&args);
        assert_ne!(code, 0, "{args:?} should fail");
        assert!(err.contains(name), "{args:?}: {err}");
    }
}

/// `platefield verify --json` prints the issue's keys, and bad arguments
/// are named with their range, exit 2 and write nothing.
#[test]
fn verify_json_reports_the_issue_keys_and_rejects_bad_input() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli-verify");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let target = dir.join("small_sink.json");
    std::fs::write(
        &target,
        r#"{"name": "small_sink", "grid": {"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [7, 7]},
            "field": {"kind": "sink"}}"#,
    )
    .unwrap();
    let out = dir.join("out");
    let (code, _, err) = platefield(&[
        "design",
        target.to_str().unwrap(),
        "--primitives",
        "LineSink",
        "--rotation-step",
        "90",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let schedule = out.join("small_sink").join("schedule.json");
    let s = schedule.to_str().unwrap();
    let o = out.to_str().unwrap();
    let (code, stdout, err) = platefield(&[
        "verify",
        s,
        "--points",
        "3",
        "--swarm",
        "3",
        "--duration",
        "3",
        "--json",
        "--out",
        o,
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("JSON on stdout");
    let e = v["realised_vs_predicted_relative_error"].as_f64().unwrap();
    assert!(e > 0.0 && e < 0.3, "{e}");
    let f = v["converged_fraction"].as_f64().unwrap();
    assert!((0.0..=1.0).contains(&f));
    assert!(v["median_time_to_converge_s"].is_number() || v["median_time_to_converge_s"].is_null());
    let rects = v["rectangles"].as_array().expect("rectangles");
    assert_eq!(rects.len(), 4);
    for r in rects {
        assert!(
            r["end_axis_deg"]
                .as_f64()
                .is_some_and(|a| (-90.0..=90.0).contains(&a)),
            "{r}"
        );
        // Started 12 mm from the centre (0.3 × the 4 cm region); 3 s in a sink
        // of strength ~0.3/s takes it to ~5 mm: well within 9 mm.
        let d = r["distance_to_attractor_m"].as_f64().unwrap();
        assert!(d < 0.009, "{r}");
    }
    let written = out.join("small_sink").join("verify");
    assert!(written.join("summary.json").exists() && written.join("trajectories.svg").exists());

    for (args, name) in [
        (vec!["--tol", "-1"], "--tol"),
        (vec!["--points", "0"], "--points"),
        (vec!["--duration", "2", "--repetitions", "2"], "--duration"),
        (vec!["--duration", "nan"], "--duration"),
        (vec!["--model", "quantum"], "--model"),
        (vec!["--rect", "0.02"], "--rect"),
        (vec!["--rect", "0.02x-1"], "--rect"),
        (vec!["--rect-poses", "100"], "--rect-poses"),
    ] {
        let fresh = dir.join("bad");
        let mut a = vec!["verify", s, "--out", fresh.to_str().unwrap()];
        a.extend(args.iter());
        let (code, _, err) = platefield(&a);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(name), "{args:?}: {err}");
        assert!(!fresh.exists(), "{args:?} wrote output");
    }
    let (code, _, err) = platefield(&["verify", dir.join("missing.json").to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("missing.json"), "{err}");
}
