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
