//! The command-line shell: outputs and clear errors on bad input.

use std::path::Path;

mod common;
use common::platefield;

const BASE: [&str; 8] = [
    "study", "linesink", "--accel", "180", "--depth", "0.05", "--period", "0.03",
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
            "study", "linesink", "--accel", accel, "--depth", depth, "--period", period, "--r",
            "0.01",
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
        "--method",
        "sequence",
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
    let e = v["model_check_error"].as_f64().unwrap();
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

/// The shipped sink schedule as a JSON value.
fn sink_schedule() -> serde_json::Value {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/sequenced/sink/schedule.json"
    ))
    .expect("sink schedule");
    serde_json::from_str(&text).expect("JSON")
}

/// A fresh temporary folder for one case.
fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("platefield-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `export` and `verify` on `schedule` (written to a temporary file);
/// returns their (exit code, stderr) and whether anything was written.
/// Each `(name, schedule, needles)` of `cases` is refused by both `export`
/// and `verify`: exit 2, every needle in the message, nothing written.
fn refused_by_export_and_verify(cases: Vec<(&str, serde_json::Value, &[&str])>) {
    for (name, s, needles) in cases {
        for (command, (code, err, written)) in
            ["export", "verify"].iter().zip(export_and_verify(name, &s))
        {
            assert_eq!(code, 2, "{command} {name}: {err}");
            for n in needles {
                assert!(err.contains(n), "{command} {name}: {err:?} should name {n}");
            }
            assert!(!written, "{command} {name}: nothing may be written");
        }
    }
}

fn export_and_verify(name: &str, schedule: &serde_json::Value) -> [(i32, String, bool); 2] {
    run_both(name, schedule, true)
}

/// [`export_and_verify`]; `export` false skips the export (code 0).
fn run_both(name: &str, schedule: &serde_json::Value, export: bool) -> [(i32, String, bool); 2] {
    let dir = temp_dir(name);
    let file = dir.join("schedule.json");
    std::fs::write(&file, serde_json::to_string_pretty(schedule).unwrap()).unwrap();
    let (csv, out) = (dir.join("signals.csv"), dir.join("out"));
    let (ce, _, ee) = if export {
        platefield(&[
            "export",
            file.to_str().unwrap(),
            "--rate",
            "1000",
            "--out",
            csv.to_str().unwrap(),
        ])
    } else {
        (0, String::new(), String::new())
    };
    let (cv, _, ev) = platefield(&[
        "verify",
        file.to_str().unwrap(),
        "--points",
        "2",
        "--swarm",
        "2",
        "--rect-poses",
        "0",
        "--out",
        out.to_str().unwrap(),
    ]);
    let written = [csv.exists(), out.exists()];
    let _ = std::fs::remove_dir_all(&dir);
    [(ce, ee, written[0]), (cv, ev, written[1])]
}

/// Issue 13: bad schedule files are refused by `export` and `verify` alike
/// (one loader): exit 2, the message names the JSON path (and the key or
/// the allowed range), nothing is written. Covers `segments: []` (export
/// used to panic), unknown keys (used to be ignored), omega 0, a negative
/// rest and a billion cycles.
#[test]
fn bad_schedule_files_are_refused_naming_the_path() {
    let mut cases: Vec<(&str, serde_json::Value, &[&str])> = Vec::new();
    let mut s = sink_schedule();
    s["segments"] = serde_json::json!([]);
    cases.push(("empty", s, &["segments", "at least one segment"]));
    let mut s = sink_schedule();
    s["colour"] = serde_json::json!("red");
    cases.push(("unknown-top", s, &["colour", "unknown field"]));
    let mut s = sink_schedule();
    s["segments"][1]["primitive"]["omegaa"] = serde_json::json!(209.0);
    cases.push(("unknown-nested", s, &["segments[1].primitive", "omegaa"]));
    let mut s = sink_schedule();
    s["solver"]["solve_time_s"] = serde_json::json!(0.1);
    cases.push(("timing", s, &["solver", "solve_time_s"]));
    let mut s = sink_schedule();
    s["segments"][0]["primitive"]["omega"] = serde_json::json!(0.0);
    cases.push((
        "omega",
        s,
        &[
            "segments[0].primitive.omega",
            "must be in [6.2832e-2, 6.2832e4] rad/s, got 0",
        ],
    ));
    let mut s = sink_schedule();
    s["segments"][3] = serde_json::json!({"label": "Rest", "primitive": null, "weight": 0.0,
        "cycles": 1, "duration_s": -0.03});
    cases.push(("rest", s, &["segments[3].duration_s", "≥ 0"]));
    let mut s = sink_schedule();
    s["segments"][2]["cycles"] = serde_json::json!(1_000_000_000u64);
    cases.push(("cycles", s, &["segments[2].cycles", "1..=100000"]));
    refused_by_export_and_verify(cases);
}

/// The period is derived from the segments: a `period_s` of 0 (or any
/// other value) in the file changes nothing, and `export` samples the
/// period `verify` plays: 4 × 10 cycles of 2π/209 s, each cycle a whole
/// number of held samples at about 1 kHz (round(1000 · 2π/209) = 30), 1200 rows.
#[test]
fn export_plays_the_period_derived_from_the_segments() {
    let dir = temp_dir("period");
    let mut rows = Vec::new();
    for period in [None, Some(0.0), Some(99.0)] {
        let mut s = sink_schedule();
        if let Some(p) = period {
            s["period_s"] = serde_json::json!(p);
        }
        let file = dir.join("schedule.json");
        std::fs::write(&file, s.to_string()).unwrap();
        let (code, out, err) = platefield(&["export", file.to_str().unwrap(), "--rate", "1000"]);
        assert_eq!(code, 0, "{err}");
        // The comment lines (`# `) state the layout, frame and peaks.
        rows.push(out.lines().filter(|l| !l.starts_with('#')).count() - 1);
    }
    let _ = std::fs::remove_dir_all(&dir);
    let per_cycle = (1000.0 * std::f64::consts::TAU / 209.0).round() as usize;
    assert_eq!(rows, vec![40 * per_cycle; 3]);
}

/// `verify` refuses what it cannot report: a rest-only schedule (used to
/// print "0.00 %") and a schedule whose parts all leave the plate (used to
/// print "NaN %"). Exit 2, nothing written. (Overlong schedules: see
/// [`long_runs_are_refused_at_once_stating_the_estimate`].)
#[test]
fn verify_refuses_rest_only_and_lost_contact_schedules() {
    let mut rest = sink_schedule();
    rest["segments"] = serde_json::json!([{"label": "Rest", "primitive": null, "weight": 1.0,
        "cycles": 10, "duration_s": 0.3}]);
    let mut lost = sink_schedule();
    for k in 0..4 {
        lost["segments"][k]["primitive"]["amplitude"] = serde_json::json!(0.5);
    }
    // Audit: so gentle that every part sticks (0.02 m/s² at the plate
    // centre): the prediction is zero and verify printed "shape NaN %",
    // exit 0.
    let mut stuck = sink_schedule();
    for k in 0..4 {
        stuck["segments"][k]["primitive"]["amplitude"] = serde_json::json!(1e-5);
    }
    for (name, s, needle) in [
        ("rest-only", rest, "every segment is rest"),
        ("lost", lost, "left the plate"),
        ("stuck", stuck, "no predicted field"),
    ] {
        let [export, (code, err, written)] = run_both(name, &s, true);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(
            err.contains(needle),
            "{name}: {err:?} should say {needle:?}"
        );
        assert!(!written, "{name}: nothing may be written");
        assert_eq!(export.0, 0, "{name}: export plays it: {}", export.1);
    }
}

/// Issue 13, work estimates (`platefield::work`): a field of 1001 × 1001
/// samples at 4096 steps per cycle, a force library for a 703 × 703 target grid,
/// `verify` with its default swarm and rectangles on a sink schedule of
/// 4 × 20 000 cycles, and an order search on it (on 2 threads): each is
/// refused within a second (exit 2, nothing written), and the message names the subject,
/// states the expected time and RK4 steps with its factors, the 10 min
/// limit, the knobs that make the work smaller, and `--allow-long`.
#[test]
fn long_runs_are_refused_at_once_stating_the_estimate() {
    let dir = temp_dir("long");
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let mut scene: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../targets/scenes/linesink.json"
        ))
        .unwrap(),
    )
    .unwrap();
    scene["grid"]["n"] = serde_json::json!([1001, 1001]);
    // A tilted axis: no two points move alike, so every sample is simulated
    // (a LineSink's would simulate one point per line, 1001).
    scene["motion"]["axis"] = serde_json::json!([0, 1, 1]);
    scene["numerics"] = serde_json::json!({"steps_per_cycle": 4096});
    let scene_file = dir.join("scene.json");
    std::fs::write(&scene_file, scene.to_string()).unwrap();
    let mut target: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"))
            .unwrap(),
    )
    .unwrap();
    // The most points a ±4 cm region allows, and force fields: DivCircle
    // alone (no two points move alike) is then over the limit.
    target["grid"]["n"] = serde_json::json!([703, 703]);
    let target_file = dir.join("target.json");
    std::fs::write(&target_file, target.to_string()).unwrap();
    let mut long = sink_schedule();
    for k in 0..4 {
        long["segments"][k]["cycles"] = serde_json::json!(20_000);
    }
    let schedule_file = dir.join("schedule.json");
    std::fs::write(&schedule_file, long.to_string()).unwrap();
    let (scene, target, schedule) = (
        scene_file.to_str().unwrap(),
        target_file.to_str().unwrap(),
        schedule_file.to_str().unwrap(),
    );
    for (args, head, factors, knob) in [
        (
            vec!["field", scene, "--out", out],
            "scene: computing the field would take about",
            "1002001 samples × 30 phases × 4096 steps",
            "scene.grid.n",
        ),
        (
            vec![
                "design",
                target,
                "--basis",
                "force",
                "--no-cache",
                "--out",
                out,
            ],
            "target: building the force library would take about",
            "DivCircle 1 field × ",
            "--rotation-step",
        ),
        (
            vec!["verify", schedule, "--out", out],
            "schedule: verifying it would take about",
            "swarm 81 parts × ",
            "--swarm",
        ),
        (
            vec!["order", schedule, "--out", out],
            "schedule: searching the segment order would take about",
            "25 parts × ",
            "--points",
        ),
    ] {
        let start = std::time::Instant::now();
        // Two worker threads, so that the estimates (which divide by the
        // threads) are the same on any machine.
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_platefield"))
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
            .args(&args)
            .env("RAYON_NUM_THREADS", "2")
            .output()
            .expect("runs");
        let seconds = start.elapsed().as_secs_f64();
        let (code, stdout, err) = (
            run.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&run.stdout).into_owned(),
            String::from_utf8_lossy(&run.stderr).into_owned(),
        );
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(stdout.is_empty(), "{args:?}: {stdout}");
        for needle in [
            head,
            factors,
            knob,
            "RK4 part steps",
            "limit of 10 min",
            "--allow-long",
        ] {
            assert!(err.contains(needle), "{args:?}: {needle:?} not in {err}");
        }
        // Refused before the work (which would take hours), not after it:
        // a bound far from both, so a loaded machine (2.5 s seen at load
        // 7–12) does not fail it.
        assert!(seconds < 30.0, "{args:?} took {seconds:.2} s to refuse");
        assert!(!Path::new(out).exists(), "{args:?} wrote files");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--allow-long` is accepted by every command that estimates its work
/// (a short run: the flag changes nothing below the limit; the accept path
/// above the limit is `platefield::work`'s unit test, not run here).
#[test]
fn allow_long_is_accepted() {
    let (code, stdout, err) = platefield(&[
        "field",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../targets/scenes/linesink.json"
        ),
        "--allow-long",
        "--quiet",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("\"fx\""), "{stdout}");
    for cmd in ["design", "verify", "order"] {
        let (code, stdout, _) = platefield(&[cmd, "--help"]);
        assert_eq!(code, 0);
        assert!(stdout.contains("--allow-long"), "{cmd}: {stdout}");
        assert!(stdout.contains("--quiet"), "{cmd}: {stdout}");
    }
}

/// `design` range-checks its counts and shifts before any library build:
/// `--cycles 0` used to write a 0-cycle schedule, `--cycles 4294967295`
/// overflowed to one, and `--shift 1,0` asked for 4.4 M samples per
/// primitive. Each now exits 2 at once, naming the argument and its range,
/// and writes nothing.
#[test]
fn design_refuses_out_of_range_counts_and_shifts() {
    let dir = temp_dir("design-ranges");
    let out = dir.to_str().unwrap();
    for (extra, name, range) in [
        (["--cycles", "0"], "--cycles", "1..=100000"),
        (["--cycles", "4294967295"], "--cycles", "1..=100000"),
        (["--shift", "1,0"], "--shift", "[-0.1, 0.1] m"),
    ] {
        let start = std::time::Instant::now();
        let mut args = vec![
            "design",
            concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"),
            "--out",
            out,
        ];
        args.extend_from_slice(&extra);
        let (code, stdout, err) = platefield(&args);
        assert_eq!(code, 2, "{extra:?}: {err}");
        assert!(
            err.contains(name) && err.contains(range),
            "{extra:?}: {err}"
        );
        assert!(stdout.is_empty(), "{extra:?}: {stdout}");
        assert!(
            start.elapsed().as_secs_f64() < 5.0,
            "{extra:?} was not refused at once"
        );
        assert!(!dir.join("sink").exists(), "{extra:?} wrote files");
    }
}

/// Bad `shaker` values in a target file (negative, zero period, zero or
/// negative harmonics, a margin ≥ 1, an unknown key) exit 2 at once naming
/// `target.shaker.…` and write nothing; a valid one is accepted with the
/// missing keys defaulted.
#[test]
fn design_refuses_bad_shaker_limits_naming_the_field() {
    let dir = temp_dir("design-shaker");
    let out = dir.to_str().unwrap();
    let base: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"))
            .unwrap(),
    )
    .unwrap();
    for (shaker, field) in [
        (serde_json::json!({"period": 0.0}), "target.shaker.period"),
        (serde_json::json!({"period": -0.05}), "target.shaker.period"),
        (
            serde_json::json!({"linear": [10, -1, 0]}),
            "target.shaker.linear[1]",
        ),
        (
            serde_json::json!({"angular": [70, 70, -5]}),
            "target.shaker.angular[2]",
        ),
        (
            serde_json::json!({"harmonics": 0}),
            "target.shaker.harmonics",
        ),
        (
            serde_json::json!({"harmonics": -1}),
            "target.shaker.harmonics",
        ),
        (
            serde_json::json!({"contact_margin": 1.0}),
            "target.shaker.contact_margin",
        ),
        (serde_json::json!({"periodd": 0.05}), "target.shaker"),
        // Audit: a period of 1e-300 s ran the synthesis without end; peaks
        // of 1e300 ended in an unlocated error full of long numbers.
        (
            serde_json::json!({"period": 1e-300}),
            "target.shaker.period: must be a period in [0.0001, 10] s, got 1e-300",
        ),
        (
            serde_json::json!({"linear": [1e300, 10, 0]}),
            "target.shaker.linear[0]: must be a peak acceleration in [0, 10000] m/s², got 1e300",
        ),
        (
            serde_json::json!({"angular": [70, 70, 1e6]}),
            "target.shaker.angular[2]: must be a peak acceleration in [0, 100000] rad/s²",
        ),
        // Travel limits (issue 29): each group checked against its range.
        (
            serde_json::json!({"stroke": {"linear": [-1e-3, 1e-3, 1e-3]}}),
            "target.shaker.stroke.linear[0]: must be a stroke in [0, 1] m, got -0.001",
        ),
        (
            serde_json::json!({"stroke": {"angular": [0.01, 0.01, 2.0]}}),
            "target.shaker.stroke.angular[2]: must be a stroke in [0, 1] rad, got 2",
        ),
        (
            serde_json::json!({"velocity": {"linear": [0.1, 1e3, 0.1]}}),
            "target.shaker.velocity.linear[1]: must be a peak velocity in [0, 100] m/s",
        ),
        (
            serde_json::json!({"velocity": {"angular": [1, 1, 1], "spin": 2}}),
            "target.shaker.velocity",
        ),
    ] {
        let mut t = base.clone();
        t["shaker"] = shaker.clone();
        let file = dir.join("t.json");
        std::fs::write(&file, t.to_string()).unwrap();
        let start = std::time::Instant::now();
        let (code, stdout, err) = platefield(&["design", file.to_str().unwrap(), "--out", out]);
        assert_eq!(code, 2, "{shaker}: {err}");
        assert!(err.contains(field), "{shaker}: {err} should name {field}");
        assert!(stdout.is_empty(), "{shaker}: {stdout}");
        assert!(
            start.elapsed().as_secs_f64() < 5.0,
            "{shaker} not refused at once"
        );
        assert!(!dir.join("sink").exists(), "{shaker} wrote files");
    }
    // NaN cannot be written in JSON; a target built in code is checked too.
    let mut t = platefield::request::Target::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../targets/sink.json"
    )))
    .unwrap();
    t.shaker = Some(platefield::request::ShakerSpec {
        period: Some(f64::NAN),
        ..Default::default()
    });
    let e = t.validate().unwrap_err().to_string();
    assert!(e.starts_with("target.shaker.period"), "{e}");
    t.shaker = Some(platefield::request::ShakerSpec {
        period: Some(0.05),
        linear: Some([10.0, 10.0, 0.0]),
        ..Default::default()
    });
    t.validate().unwrap();
    let l = platefield::synth::ShakerLimits::from_spec(t.shaker.as_ref());
    let env = platefield::synth::ShakerLimits::envelope();
    assert_eq!((l.period, l.linear), (0.05, [10.0, 10.0, 0.0]));
    assert_eq!(
        (l.angular, l.harmonics, l.contact_margin),
        (env.angular, 2, 0.1)
    );
}

/// `design TARGET --method synthesize` on a small budget (20 evaluations,
/// no played polish) into `out`; asserts exit 0.
fn design_synthesized_quickly(target: &Path, out: &Path) {
    let (code, _, err) = platefield(&[
        "design",
        target.to_str().unwrap(),
        "--method",
        "synthesize",
        "--synth-evaluations",
        "20",
        "--polish-plays",
        "0",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
}

/// A small sink under lab-class shaker limits on an n × n grid, written in
/// `dir`.
fn small_lab(dir: &Path, n: usize) -> std::path::PathBuf {
    let target = dir.join("small_lab.json");
    let text = format!(
        r#"{{"name": "small_lab", "grid": {{"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [{n}, {n}]}},
            "field": {{"kind": "sink"}},
            "shaker": {{"period": 0.05, "linear": [12, 12, 0.2], "angular": [220, 220, 0], "harmonics": 1}}}}"#
    );
    std::fs::write(&target, text).unwrap();
    target
}

/// `design --method auto` end to end on a small sink with lab-class
/// limits: both candidates are played and printed with their realised
/// shape error and strength, the choice is stated, the files are written
/// (signals.svg for the synthesis), `schedule.json` carries the realised
/// check, and `export --steady-cycles` of a synthesized schedule states its
/// ramp. `--method bogus`, `--synth-evaluations 0` and a synthesis whose
/// work estimate exceeds the limit exit 2.
#[test]
fn design_method_auto_plays_both_and_states_the_choice() {
    let dir = temp_dir("design-method");
    let target = small_lab(&dir, 7);
    let out = dir.join("out");
    let base = [
        "design",
        target.to_str().unwrap(),
        "--primitives",
        "LineSink",
        "--rotation-step",
        "90",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    for (extra, name) in [
        (&["--method", "bogus"][..], "--method"),
        (&["--synth-evaluations", "0"][..], "--synth-evaluations"),
        // Refused by the work estimate before any simulation: it names the
        // knobs and --allow-long. (Nelder–Mead spends the budgets; least
        // squares takes its steps, whatever they allow.)
        (
            &[
                "--optimizer",
                "nelder-mead",
                "--synth-evaluations",
                "100000000",
            ][..],
            "--allow-long",
        ),
        (
            &["--optimizer", "nelder-mead", "--polish-plays", "100000000"][..],
            "--polish-plays",
        ),
    ] {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        let (code, _, err) = platefield(&args);
        assert_eq!(code, 2, "{extra:?}: {err}");
        assert!(err.contains(name), "{err}");
        assert!(!out.exists());
    }
    let mut args = base.to_vec();
    args.extend_from_slice(&["--synth-evaluations", "20", "--polish-plays", "10"]);
    let (code, stdout, err) = platefield(&args);
    assert_eq!(code, 0, "{err}");
    for needle in [
        " sequence: predicted strength",
        " synthesize: predicted strength",
        "realised shape error",
        "realised strength",
        "auto kept ",
        "signals.svg",
    ] {
        assert!(stdout.contains(needle), "{needle:?} not in {stdout}");
    }
    let folder = out.join("small_lab");
    for f in ["schedule.json", "fit.svg", "report.md", "signals.svg"] {
        assert!(folder.join(f).exists(), "{f}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("schedule.json")).unwrap())
            .unwrap();
    let played = &json["played"];
    assert_eq!(played["asked"], "auto");
    assert!(played["realised_shape_error"].is_number(), "{played}");
    assert!(played["realised_strength"].is_number(), "{played}");
    let report = std::fs::read_to_string(folder.join("report.md")).unwrap();
    assert!(report.contains("## Method and the judge") && report.contains("## Synthesized motion"));
    // A synthesized schedule exports with its ramp stated.
    let syn = dir.join("syn");
    design_synthesized_quickly(&target, &syn);
    let csv = dir.join("syn.csv");
    let (code, stdout, err) = platefield(&[
        "export",
        syn.join("small_lab/schedule.json").to_str().unwrap(),
        "--rate",
        "20000",
        "--steady-cycles",
        "5",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("ramp-in from rest") && stdout.contains("5 steady cycles"),
        "{stdout}"
    );
    // 10 + 5 + 10 cycles of 1000 samples, after the comment lines that
    // state the frame, the reference point and the peaks.
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(
        text.lines().filter(|l| !l.starts_with('#')).count(),
        1 + 25_000
    );
    for needle in [
        "reference point: the plate centre",
        "world axes",
        "stroke",
        "velocity",
    ] {
        assert!(text.contains(needle), "{needle}: {text:.600}");
    }
    harmonics_are_the_motions_terms(&syn.join("small_lab/schedule.json"), &dir);
}

/// `export --format harmonics` of the lab-class sink's synthesized motion
/// (`schedule`, synthesized above) writes each of its linear terms exactly:
/// per channel one row (harmonic, amplitude, phase) equal, as f64, to the
/// schedule's own term (the lab class plays one harmonic, so every
/// channel holds one term; a negative amplitude is written as |A| with
/// φ + π); its angular terms are the plate's world α, the schedule's θ″
/// terms to second order in the tilts.
fn harmonics_are_the_motions_terms(schedule: &Path, dir: &Path) {
    let out = dir.join("harmonics.csv");
    let (code, stdout, err) = platefield(&[
        "export",
        schedule.to_str().unwrap(),
        "--format",
        "harmonics",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("terms over 6 channels"), "{stdout}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("reference point: the plate centre") && text.contains("stroke"));
    let rows: Vec<Vec<String>> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(schedule).unwrap()).unwrap();
    let motion = json["segments"]
        .as_array()
        .unwrap()
        .iter()
        .find_map(|s| s.get("motion").filter(|m| !m.is_null()))
        .expect("a synthesized motion");
    let mut expected = Vec::new();
    for (group, names) in [
        ("linear", ["ax_m_s2", "ay_m_s2", "az_m_s2"]),
        (
            "angular",
            ["alpha_x_rad_s2", "alpha_y_rad_s2", "alpha_z_rad_s2"],
        ),
    ] {
        for (axis, name) in ["x", "y", "z"].iter().zip(names) {
            for t in motion[group][axis].as_array().into_iter().flatten() {
                let a = t["amplitude"].as_f64().unwrap();
                let phase = t.get("phase").and_then(|p| p.as_f64()).unwrap_or(0.0);
                let n = t.get("harmonic").and_then(|n| n.as_u64()).unwrap_or(1);
                expected.push((name.to_string(), n, a, phase));
            }
        }
    }
    assert!(expected.len() >= 4, "{expected:?}");
    let got: Vec<(String, u64, f64, f64)> = rows
        .iter()
        .map(|r| {
            (
                r[0].clone(),
                r[1].parse().unwrap(),
                r[2].parse().unwrap(),
                r[3].parse().unwrap(),
            )
        })
        .collect();
    // The angular channels are the plate's world α, the schedule's θ″ terms
    // but for second-order terms in the tilts (a few 1e-6 of them here):
    // each θ″ term within 1e-4, and every other term below 1e-3 of them.
    let angular = |r: &&(String, u64, f64, f64)| r.0.starts_with("alpha");
    let (got_angular, got): (Vec<_>, Vec<_>) = got.iter().partition(angular);
    let (expected_angular, expected): (Vec<_>, Vec<_>) = expected.iter().partition(angular);
    let largest = expected_angular
        .iter()
        .fold(0.0_f64, |m, e| m.max(e.2.abs()));
    for g in &got_angular {
        match expected_angular.iter().find(|e| (&e.0, e.1) == (&g.0, g.1)) {
            Some(e) => {
                let (a, phase) = if e.2 >= 0.0 {
                    (e.2, e.3)
                } else {
                    (-e.2, e.3 + std::f64::consts::PI)
                };
                let d = (g.3 - phase).rem_euclid(std::f64::consts::TAU);
                assert!(
                    (g.2 / a - 1.0).abs() < 1e-4 && d.min(std::f64::consts::TAU - d) < 1e-4,
                    "{g:?} against {e:?}"
                );
            }
            None => assert!(g.2 < 1e-3 * largest, "{g:?}"),
        }
    }
    assert_eq!(got.len(), expected.len(), "{got:?} against {expected:?}");
    for (g, e) in got.iter().zip(&expected) {
        assert_eq!((&g.0, g.1), (&e.0, e.1));
        if e.2 >= 0.0 {
            // Written unchanged: the same f64s.
            assert_eq!((g.2, g.3), (e.2, e.3), "{g:?} against {e:?}");
        } else {
            // −A sin(θ + φ) = A sin(θ + φ + π): the amplitude exact, the
            // phase to one rounding of the added π.
            let d = (g.3 - e.3 - std::f64::consts::PI).rem_euclid(std::f64::consts::TAU);
            assert!(
                g.2 == -e.2 && d.min(std::f64::consts::TAU - d) < 1e-14,
                "{g:?} against {e:?}"
            );
        }
    }
    // A sequenced schedule is not a sum of harmonics: refused, naming --format.
    let (code, _, err) = platefield(&[
        "export",
        concat!(
            concat!(env!("CARGO_MANIFEST_DIR"), "/.."),
            "/results/sequenced/sink/schedule.json"
        ),
        "--format",
        "harmonics",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--format"), "{err}");
}

/// Runs the binary with `PLATEFIELD_PROGRESS_INTERVAL=0` (a progress line
/// at every update) and stderr piped (not a terminal).
fn with_progress_lines(args: &[&str]) -> (i32, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_platefield"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args(args)
        .env(platefield::progress::INTERVAL_ENV, "0")
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Issue 30: `design --json` prints its synthesis and played-polish
/// progress on stderr (stdout carries the JSON); before, --json silenced it.
#[test]
fn design_json_still_prints_progress_on_stderr() {
    let dir = temp_dir("design-json-progress");
    let target = small_lab(&dir, 5);
    let out = dir.join("out");
    let (code, err) = with_progress_lines(&[
        "design",
        target.to_str().unwrap(),
        "--primitives",
        "LineSink",
        "--rotation-step",
        "90",
        "--method",
        "synthesize",
        "--synth-evaluations",
        "4",
        "--polish-plays",
        "2",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    for needle in [
        "synthesis: ",
        "/4 evaluations",
        "played polish: ",
        "elapsed",
    ] {
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
}

/// Issue 13, progress without a terminal: with stderr piped, a library
/// build (`primitives`: force then velocity library of 8 primitives × 9
/// samples), `verify` (in thousands of RK4 part steps, each stage named)
/// and `order` print plain progress lines on stderr
/// (counts out of the total, elapsed time); with `--quiet` stderr is empty.
#[test]
fn progress_lines_without_a_terminal_and_none_when_quiet() {
    let dir = temp_dir("progress");
    let out = dir.to_str().unwrap();
    let runs: [(Vec<&str>, &[&str]); 3] = [
        (
            vec!["study", "primitives", "--grid", "3", "--out", out],
            &[
                "force library: 1/72 samples",
                "velocity library: 72/72 samples (100 %)",
                "elapsed",
            ],
        ),
        (
            vec![
                "verify",
                concat!(
                    env!("CARGO_MANIFEST_DIR"),
                    "/../results/sequenced/sink/schedule.json"
                ),
                "--points",
                "2",
                "--swarm",
                "2",
                "--rect-poses",
                "1",
                "--repetitions",
                "1",
                "--out",
                out,
            ],
            &[
                "verify: ",
                " k RK4 steps (100 %)",
                "realised grid",
                "swarm",
                "rectangles",
            ],
        ),
        (
            vec![
                "order",
                concat!(
                    env!("CARGO_MANIFEST_DIR"),
                    "/../results/sequenced/sink/schedule.json"
                ),
                "--points",
                "2",
                "--rest",
                "0",
                "--out",
                out,
            ],
            &[
                "order search: 1/6 candidates",
                "order search: 6/6 candidates",
            ],
        ),
    ];
    for (args, needles) in runs {
        let (code, err) = with_progress_lines(&args);
        assert_eq!(code, 0, "{args:?}: {err}");
        for needle in needles {
            assert!(err.contains(needle), "{args:?}: {needle:?} not in {err}");
        }
        let mut quiet = args.clone();
        quiet.push("--quiet");
        let (code, err) = with_progress_lines(&quiet);
        assert_eq!(code, 0, "{quiet:?}: {err}");
        assert!(err.is_empty(), "{quiet:?} printed {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 13: `trajectories.svg` is readable: arrows and markers clipped to
/// the axes, a legend naming the velocity arrows, the part paths, start and
/// end markers, the rectangle path and its start and end outlines, and the
/// attractor; the rectangles' outlines are drawn (five-vertex closed paths).
#[test]
fn trajectories_svg_has_legend_clipping_and_outlines() {
    let dir = temp_dir("trajectories");
    let out = dir.to_str().unwrap();
    let (code, _, err) = platefield(&[
        "verify",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/sequenced/sink/schedule.json"
        ),
        "--points",
        "3",
        "--swarm",
        "3",
        "--rect-poses",
        "1",
        "--repetitions",
        "2",
        "--quiet",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{err}");
    let svg = std::fs::read_to_string(dir.join("sink/verify/trajectories.svg")).unwrap();
    assert!(svg.contains(r#"<g class="arrows" clip-path="url(#qp-clip)""#));
    assert!(svg.contains(r#"<g class="markers" clip-path="url(#qp-clip)">"#));
    assert!(svg.contains(r#"<g class="overlays" clip-path="url(#qp-clip)""#));
    let legend = &svg[svg.find(r#"<g class="legend""#).expect("a legend")..];
    for label in [
        "realised mean velocity",
        "point part path",
        "start",
        "end (converged)",
        "20 × 5 mm rectangle path",
        "rectangle start pose",
        "rectangle end pose",
        "attractor",
    ] {
        assert!(legend.contains(&format!(">{label}</text>")), "{label}");
    }
    // Start (dashed) and end outlines of the one rectangle: closed 4-sided paths.
    let outlines = svg
        .lines()
        .filter(|l| l.starts_with("<path d=\"M") && l.matches(" L").count() == 4)
        .filter(|l| l.contains("#9467bd") || l.contains("#000000"))
        .count();
    assert!(outlines >= 2, "{outlines} rectangle outlines");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A target file in a fresh temporary folder (named after the case).
fn target_file(dir: &Path, target: &serde_json::Value) -> String {
    text_file(dir, "target.json", &target.to_string())
}

/// Audit: `design` inputs that crashed, wrote nothing useful or were named
/// wrongly now exit 2 at once, naming the argument or JSON path and the
/// range, and write nothing: `--rotation-step 1e-9` (aborted, exit 134,
/// allocating 2.9 TB), `--cycles` too short for `--min-cycles` (named the
/// empty `schedule.segments`), a target name of 300 bytes or with a NUL
/// (failed only when writing, after the whole design, leaving the output
/// folder behind) and a jet narrower than its Gaussian can hold (an
/// unlocated "non-finite vector" error).
#[test]
fn design_refuses_degenerate_inputs_naming_them() {
    let dir = temp_dir("design-degenerate");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let small = serde_json::json!({"name": "small",
        "grid": {"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [7, 7]},
        "field": {"kind": "sink"}});
    let t = target_file(&dir, &small);
    let quick = [
        "--method",
        "sequence",
        "--primitives",
        "LineSink",
        "--quiet",
    ];
    let with = |extra: &[&str]| {
        let mut a = vec!["design", t.as_str(), "--out", o];
        a.extend_from_slice(&quick);
        if !extra.contains(&"--rotation-step") {
            a.extend_from_slice(&["--rotation-step", "90"]);
        }
        a.extend_from_slice(extra);
        platefield(&a)
    };
    let cases: [(&[&str], &[&str]); 2] = [
        (
            &["--rotation-step", "1e-9"],
            &["--rotation-step: must be in [1, 360] degrees", "got 1e-9"],
        ),
        (
            // Four LineSinks at a quarter of the time each: 5 cycles of 20
            // give each fewer than half of the 10 it needs.
            &["--cycles", "5"],
            &[
                "--cycles: 5 cycles leave no segment of at least --min-cycles 10",
                "--cycles ≥ 21",
            ],
        ),
    ];
    for (extra, needles) in cases {
        let (code, stdout, err) = with(extra);
        assert_eq!(code, 2, "{extra:?}: {err}");
        for n in needles {
            assert!(err.contains(n), "{extra:?}: {err:?} should contain {n:?}");
        }
        assert!(stdout.is_empty() && !out.exists(), "{extra:?} wrote output");
    }
    let (code, _, err) = with(&["--cycles", "21"]);
    assert_eq!(code, 0, "{err}");
    std::fs::remove_dir_all(&out).unwrap();
    for (edit, needle) in [
        (
            serde_json::json!({"name": "n".repeat(300)}),
            "target.name: must be a plain folder name (at most 205 bytes, which leaves room for its staging folder within the file system's 255 per name; no /, \\ or NUL, not starting with .), got \"nnnn",
        ),
        (
            serde_json::json!({"name": "n".repeat(300)}),
            "…\" (300 bytes)",
        ),
        (
            serde_json::json!({"name": "a\u{0}b"}),
            "target.name: must be a plain folder name (at most 205 bytes",
        ),
        (
            serde_json::json!({"field": {"kind": "jet", "width": 1e-300}}),
            "target.field.width: must be in [0.000001, 1] m, got 1e-300",
        ),
    ] {
        let mut target = small.clone();
        for (k, v) in edit.as_object().unwrap() {
            target[k] = v.clone();
        }
        target_file(&dir, &target);
        let (code, stdout, err) = with(&[]);
        assert_eq!(code, 2, "{edit}: {err}");
        assert!(
            err.contains(needle),
            "{edit}: {err:?} should contain {needle:?}"
        );
        assert!(stdout.is_empty() && !out.exists(), "{edit} wrote output");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The shipped synthesized sink schedule (one six-signal segment).
fn synthesized_schedule() -> serde_json::Value {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    ))
    .expect("sink schedule");
    serde_json::from_str(&text).expect("JSON")
}

/// Audit: a schedule's six-signal segment is held to the scene ranges, as
/// the schedule module documents (it was only checked to be finite:
/// `export` wrote peaks of 1e300 m/s², `verify` played a period of 1 µs,
/// both exit 0), and so are its settings' steady-state iterations (1e9 on a
/// motion whose steady state does not converge ran `verify` for hours).
/// `export` and `verify` exit 2 naming the JSON path and the range, and
/// write nothing.
#[test]
fn six_signal_segments_and_iterations_are_held_to_the_scene_ranges() {
    let mut cases: Vec<(&str, serde_json::Value, &[&str])> = Vec::new();
    let mut s = synthesized_schedule();
    s["segments"][0]["motion"]["linear"]["x"][0]["amplitude"] = serde_json::json!(1e300);
    cases.push((
        "amplitude",
        s,
        &["segments[0].motion.linear.x[0].amplitude: must be in [-10000, 10000] m/s², got 1e300"],
    ));
    let mut s = synthesized_schedule();
    s["segments"][0]["motion"]["period"] = serde_json::json!(1e-6);
    cases.push((
        "period",
        s,
        &["segments[0].motion.period: must be in [0.0001, 100] s, got 0.000001"],
    ));
    let mut s = synthesized_schedule();
    s["segments"][0]["motion"]["angular"]["y"][0]["phase"] = serde_json::json!(1e300);
    cases.push((
        "phase",
        s,
        &["segments[0].motion.angular.y[0].phase: must be in [-1000, 1000] rad"],
    ));
    let mut s = sink_schedule();
    s["settings"]["numerics"]["max_iterations"] = serde_json::json!(1_000_000_000u64);
    cases.push((
        "iterations",
        s,
        &["settings.numerics.max_iterations: must be in 1..=10000, got 1000000000"],
    ));
    refused_by_export_and_verify(cases);
}

/// Audit: what `design` writes, `export` and `verify` read. A synthesized
/// motion for a grid-less `sampled` target (`targets/sampled.json`) is
/// written with its angle and worst-point errors `null` (not simulated at
/// the sample points); both commands refused that file
/// (`fit.max_error: must be a number, got null`). A rest segment of 0 s,
/// which the loader accepts and `verify` plays, made `export` fail. And a
/// `--rate` far out of range is stated short (it printed 300 digits).
#[test]
fn schedules_design_writes_are_read_back() {
    let mut unset = synthesized_schedule();
    for metrics in ["fit", "fit_quantized"] {
        unset[metrics]["mean_angle_error_deg"] = serde_json::Value::Null;
        unset[metrics]["max_error"] = serde_json::Value::Null;
    }
    let mut zero_rest = sink_schedule();
    zero_rest["segments"].as_array_mut().unwrap().push(
        serde_json::json!({"label": "Rest", "primitive": null, "weight": 0.0,
            "cycles": 0, "duration_s": 0.0}),
    );
    for (name, s) in [("unset-metrics", unset), ("zero-rest", zero_rest)] {
        for (command, (code, err, written)) in
            ["export", "verify"].iter().zip(export_and_verify(name, &s))
        {
            assert_eq!(code, 0, "{command} {name}: {err}");
            assert!(written, "{command} {name}: wrote nothing");
        }
    }
    let dir = temp_dir("rate-short");
    let file = dir.join("schedule.json");
    std::fs::write(&file, sink_schedule().to_string()).unwrap();
    for (rate, needle) in [
        (
            "1e300",
            "--rate: 1e300 Hz over one 1.2025 s schedule period is about 1.203e300 rows, 1.4e293 GB of CSV",
        ),
        (
            "1e-300",
            "--rate: 1e-300 Hz gives fewer than 2 samples per 3.0063e-2 s period",
        ),
    ] {
        let (code, _, err) = platefield(&["export", file.to_str().unwrap(), "--rate", rate]);
        assert_eq!(code, 2, "{rate}: {err}");
        assert!(
            err.contains(needle),
            "{rate}: {err:?} should contain {needle:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A shaker whose synthesized motion keeps no part on the plate anywhere
/// (a 10 s period: the envelope's 218 rad/s² is a tilt of hundreds of
/// radians) is no design: `--method synthesize` exits 2 saying so, with
/// nothing written; `auto` keeps the sequenced schedule and says why.
#[test]
fn synthesis_that_keeps_no_part_on_the_plate_is_refused() {
    let dir = temp_dir("design-no-contact");
    let out = dir.to_str().unwrap();
    let mut t: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"))
            .unwrap(),
    )
    .unwrap();
    t["shaker"] = serde_json::json!({"period": 10.0});
    t["grid"]["n"] = serde_json::json!([7, 7]);
    let file = dir.join("t.json");
    std::fs::write(&file, t.to_string()).unwrap();
    let f = file.to_str().unwrap();
    let (code, _, err) = platefield(&["design", f, "--method", "synthesize", "--out", out]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("keeps no part on the plate anywhere in the region")
            && err.contains("period 10 s"),
        "{err}"
    );
    assert!(!dir.join("sink").exists(), "wrote files: {err}");
    let (code, stdout, err) = platefield(&["design", f, "--out", out, "--quiet"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("synthesize failed: the synthesized motion keeps no part"),
        "{stdout}"
    );
    assert!(!stdout.contains("inf %"), "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A design folder holds one design: a sequenced run into the folder of a
/// synthesized one removes its `signals.svg` (and leaves files that are not
/// the design's alone); an `--out` under a file is refused before the
/// design, naming `--out`, with nothing written.
#[test]
fn design_folder_holds_one_design_and_out_is_checked_first() {
    let dir = temp_dir("design-stale");
    let out = dir.to_str().unwrap();
    let mut t: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"))
            .unwrap(),
    )
    .unwrap();
    t["grid"]["n"] = serde_json::json!([7, 7]);
    let file = dir.join("t.json");
    std::fs::write(&file, t.to_string()).unwrap();
    let f = file.to_str().unwrap();
    let args = [
        "--synth-evaluations",
        "20",
        "--polish-plays",
        "0",
        "--quiet",
    ];
    let (code, _, err) = platefield(
        &[
            &["design", f, "--method", "synthesize", "--out", out][..],
            &args[..],
        ]
        .concat(),
    );
    assert_eq!(code, 0, "{err}");
    let folder = dir.join("sink");
    assert!(folder.join("signals.svg").is_file());
    std::fs::write(folder.join("notes.txt"), "mine").unwrap();
    let (code, stdout, err) =
        platefield(&["design", f, "--method", "sequence", "--out", out, "--quiet"]);
    assert_eq!(code, 0, "{err}");
    assert!(!stdout.contains("signals.svg"), "{stdout}");
    assert!(
        !folder.join("signals.svg").exists(),
        "stale signals.svg left"
    );
    for kept in ["schedule.json", "fit.svg", "report.md", "notes.txt"] {
        assert!(folder.join(kept).is_file(), "{kept} missing");
    }
    let blocker = dir.join("a_file");
    std::fs::write(&blocker, "").unwrap();
    let under = blocker.join("x");
    let start = std::time::Instant::now();
    let (code, _, err) = platefield(&["design", f, "--out", under.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--out") && err.contains("is not a folder"),
        "{err}"
    );
    assert!(start.elapsed().as_secs_f64() < 5.0, "not refused at once");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Writes `text` to `dir/name` and returns the path.
fn text_file(dir: &Path, name: &str, text: &str) -> String {
    let file = dir.join(name);
    std::fs::write(&file, text).unwrap();
    file.to_str().unwrap().to_string()
}

/// Audit: a key given twice in one JSON object was read silently as its
/// last value (`{"name": "a", "name": "b"}` designed "b"), in targets,
/// scenes and schedules alike. Every command refuses it (exit 2), naming
/// the key's JSON path, and writes nothing.
#[test]
fn duplicate_keys_are_refused_naming_the_path() {
    let dir = temp_dir("duplicate-keys");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let csv = dir.join("signals.csv");
    let c = csv.to_str().unwrap();
    // A target: the top-level name.
    let target = text_file(
        &dir,
        "target.json",
        r#"{"name": "a", "name": "dupname",
            "grid": {"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [7, 7]},
            "field": {"kind": "sink"}}"#,
    );
    // A scene: a nested key.
    let scene = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../targets/scenes/linesink.json"
    ))
    .unwrap();
    let scene = scene.replace("\"n\": [11, 11]}", "\"n\": [11, 11], \"n\": [3, 3]}");
    assert!(scene.contains("\"n\": [3, 3]"));
    let scene = text_file(&dir, "scene.json", &scene);
    // A schedule: deep inside a six-signal segment.
    let mut s = synthesized_schedule();
    s["segments"][0]["motion"]["linear"]["x"][0]["amplitude"] = serde_json::json!(1234.5);
    let text = s.to_string().replace(
        "\"amplitude\":1234.5",
        "\"amplitude\":1234.5,\"amplitude\":1.0",
    );
    assert!(text.contains("\"amplitude\":1.0"));
    let schedule = text_file(&dir, "schedule.json", &text);
    let deep = "schedule.segments[0].motion.linear.x[0].amplitude: duplicate key \"amplitude\"";
    let field_out = dir.join("field.json");
    let f = field_out.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![
                "design",
                &target,
                "--method",
                "sequence",
                "--primitives",
                "LineSink",
                "--rotation-step",
                "90",
                "--quiet",
                "--out",
                o,
            ],
            "target.name: duplicate key \"name\" (a key may appear only once in an object)",
        ),
        (
            vec!["field", &scene, "--quiet", "--out", f],
            "scene.grid.n: duplicate key \"n\"",
        ),
        (
            vec!["export", &schedule, "--rate", "1000", "--out", c],
            deep,
        ),
        (
            vec![
                "verify",
                &schedule,
                "--points",
                "2",
                "--swarm",
                "2",
                "--rect-poses",
                "0",
                "--quiet",
                "--out",
                o,
            ],
            deep,
        ),
        (vec!["order", &schedule, "--quiet", "--out", o], deep),
    ];
    for (args, needle) in cases {
        let (code, stdout, err) = platefield(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.contains(needle),
            "{args:?}: {err:?} should contain {needle:?}"
        );
        assert!(stdout.is_empty(), "{args:?}: {stdout}");
        assert!(
            !out.exists() && !csv.exists() && !field_out.exists(),
            "{args:?} wrote output"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Audit: `export results/synthesized/sink/schedule.json --rate 4e7` wrote a 5.7 GB
/// CSV (4.8e7 rows, built in memory: 7.8 GB, 92 s), exit 0, under the
/// sampler's 5e7-sample bound. The rows are estimated before anything is
/// sampled and an export over 1e7 rows (≈ 1.2 GB) is refused at once,
/// exit 2, naming `--rate` (or `--steady-cycles` when they are what is too
/// many), the estimate, its size and the largest rate that fits; no file
/// is written.
#[test]
fn export_refuses_an_oversized_file_at_once() {
    let dir = temp_dir("export-size");
    let csv = dir.join("signals.csv");
    let c = csv.to_str().unwrap();
    let cases: [(&[&str], &[&str]); 3] = [
        (
            &[
                concat!(
                    env!("CARGO_MANIFEST_DIR"),
                    "/../results/synthesized/sink/schedule.json"
                ),
                "--rate",
                "4e7",
            ],
            &[
                "--rate: 4e7 Hz over 10 + 20 (--steady-cycles) + 10 cycles",
                "about 4.810e7 rows, 5.7 GB of CSV, over the limit of 1e7 rows",
                "the largest --rate that fits is 8.31e6 Hz",
            ],
        ),
        (
            &[
                concat!(
                    env!("CARGO_MANIFEST_DIR"),
                    "/../results/synthesized/sink/schedule.json"
                ),
                "--steady-cycles",
                "4000000",
            ],
            &[
                "--steady-cycles: 10000 Hz over 10 + 4000000 (--steady-cycles)",
                "GB of CSV",
                "at most 33202 --steady-cycles at this rate",
            ],
        ),
        (
            &[
                concat!(
                    env!("CARGO_MANIFEST_DIR"),
                    "/../results/line_sink/schedule.json"
                ),
                "--rate",
                "4e7",
            ],
            &[
                "--rate: 4e7 Hz over one 0.6013 s schedule period is about 2.405e7 rows, 2.8 GB",
                "the largest --rate that fits is 1.66e7 Hz",
            ],
        ),
    ];
    for (args, needles) in cases {
        let mut a = vec!["export"];
        a.extend_from_slice(args);
        a.extend_from_slice(&["--out", c]);
        let start = std::time::Instant::now();
        let (code, _, err) = platefield(&a);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            start.elapsed().as_secs_f64() < 10.0,
            "{args:?}: not refused at once"
        );
        for n in needles {
            assert!(err.contains(n), "{args:?}: {err:?} should contain {n:?}");
        }
        assert!(!csv.exists(), "{args:?}: nothing may be written");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Audit: `design --rotation-step 7` was rounded to 51 copies at
/// 7.0588° without a word (the sink's LineSinks fell out of the basis,
/// 23 % fit error, labels `@211.76470588235293°`). A step that does not
/// divide 360 exits 2 naming `--rotation-step` and the nearest steps that
/// do, and writes nothing; a step that divides 360 with decimals (7.2) is
/// accepted.
#[test]
fn rotation_step_must_divide_360() {
    let dir = temp_dir("rotation-step");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let small = serde_json::json!({"name": "small",
        "grid": {"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [7, 7]},
        "field": {"kind": "sink"}});
    let t = target_file(&dir, &small);
    let design = |step: &str| {
        platefield(&[
            "design",
            &t,
            "--method",
            "sequence",
            "--primitives",
            "LineSink",
            "--rotation-step",
            step,
            "--quiet",
            "--out",
            o,
        ])
    };
    for (step, nearest) in [("7", "6, 7.2"), ("100", "90, 120"), ("1.1", "1, 1.125")] {
        let (code, stdout, err) = design(step);
        assert_eq!(code, 2, "{step}: {err}");
        let needle = format!("--rotation-step: {step} does not divide 360");
        assert!(err.contains(&needle), "{step}: {err:?}");
        let needle = format!("nearest steps that divide 360: {nearest}");
        assert!(
            err.contains(&needle),
            "{step}: {err:?} should contain {needle:?}"
        );
        assert!(stdout.is_empty() && !out.exists(), "{step} wrote output");
    }
    let (code, _, err) = design("7.2");
    assert_eq!(code, 0, "7.2 divides 360: {err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Audit: `verify --points 1` measured the region's centre alone (the
/// sink's attractor, where the field is zero) and reported a 317 % error
/// and a negative strength as a realised field, exit 0. At least 2 points
/// per side are needed for the least-squares strength and shape error;
/// exit 2 naming `--points`, nothing written.
#[test]
fn verify_needs_at_least_two_points_per_side() {
    let dir = temp_dir("verify-points");
    let out = dir.join("out");
    let (code, stdout, err) = platefield(&[
        "verify",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/sequenced/sink/schedule.json"
        ),
        "--points",
        "1",
        "--swarm",
        "2",
        "--rect-poses",
        "0",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    for needle in ["--points: must be in 2..=101, got 1", "least-squares"] {
        assert!(err.contains(needle), "{err:?} should contain {needle:?}");
    }
    assert!(stdout.is_empty() && !out.exists(), "wrote output");
    // `order` judges each order over the same kind of grid.
    let (code, stdout, err) = platefield(&[
        "order",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/sequenced/sink/schedule.json"
        ),
        "--points",
        "1",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--points: must be in 2..=41, got 1"),
        "{err:?}"
    );
    assert!(stdout.is_empty() && !out.exists(), "wrote output");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Audit: a scene with friction μ = 0 gave a velocity field whose every
/// sample failed to converge; `field` wrote it and exited 0. No valid
/// sample at all, for whatever reason, is now an error stating the counts
/// by reason (exit 2, nothing written); a field with some valid samples
/// is still written, exit 0, its per-point status reported.
#[test]
fn field_with_no_valid_sample_is_an_error() {
    let dir = temp_dir("field-no-valid");
    let out = dir.join("field.json");
    let o = out.to_str().unwrap();
    let base = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../targets/scenes/sine_square_linesink.json"
    ))
    .unwrap();
    let frictionless = base
        .replace(
            "\"friction\": {\"static\": 0.3, \"kinetic\": 0.3}",
            "\"friction\": {\"static\": 0, \"kinetic\": 0}",
        )
        .replace("\"n\": [11, 11]", "\"n\": [3, 3]")
        .replace("\"model\": \"paper\"", "\"model\": \"full\"");
    assert!(frictionless.contains("\"kinetic\": 0}") && frictionless.contains("\"full\""));
    let scene = text_file(&dir, "mu0.json", &frictionless);
    let (code, stdout, err) = platefield(&["field", &scene, "--quiet", "--out", o]);
    assert_eq!(code, 2, "{err}");
    for needle in [
        "no valid sample in the field: of 9 samples, the steady state did not converge at 9",
        "μ_k = 0 (scene.friction)",
    ] {
        assert!(err.contains(needle), "{err:?} should contain {needle:?}");
    }
    assert!(stdout.is_empty() && !out.exists(), "wrote output");
    // Contact lost at the two outer points of five: written, exit 0.
    let partial = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../targets/scenes/linesink.json"
    ))
    .unwrap()
    .replace("\"amplitude\": 0.005", "\"amplitude\": 0.0062")
    .replace("\"n\": [11, 11]", "\"n\": [5, 1]")
    .replace("\"y\": [-0.04, 0.04]", "\"y\": [0, 0]");
    let scene = text_file(&dir, "partial.json", &partial);
    let (code, stdout, err) = platefield(&["field", &scene, "--quiet", "--out", o]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("valid:   3 of 5 samples (contact lost 2"),
        "{stdout}"
    );
    assert!(out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Audit: gravity 1e-300 in a scene was accepted as "> 0" and every point
/// then "left the plate", with advice to reduce the amplitude; a schedule's
/// `settings.gravity` likewise. Both are held to [0.1, 100] m/s² (exit 2,
/// naming the JSON path, nothing written).
#[test]
fn gravity_is_held_to_a_physical_range() {
    let dir = temp_dir("gravity");
    let out = dir.join("field.json");
    let scene = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../targets/scenes/linesink.json"
    ))
    .unwrap()
    .replace("\"gravity\": 9.81", "\"gravity\": 1e-300");
    assert!(scene.contains("1e-300"));
    let scene = text_file(&dir, "scene.json", &scene);
    let (code, _, err) = platefield(&["field", &scene, "--quiet", "--out", out.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("scene.gravity: must be in [0.1, 100] m/s², got 1e-300"),
        "{err}"
    );
    assert!(!err.contains("amplitude") && !out.exists(), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
    let mut s = sink_schedule();
    s["settings"]["gravity"] = serde_json::json!(1e-300);
    for (command, (code, err, written)) in ["export", "verify"]
        .iter()
        .zip(export_and_verify("gravity", &s))
    {
        assert_eq!(code, 2, "{command}: {err}");
        assert!(
            err.contains("settings.gravity: must be in [0.1, 100] m/s², got 1e-300"),
            "{command}: {err}"
        );
        assert!(!written, "{command}: nothing may be written");
    }
}

/// A schedule whose settings leave one part on the plate (gravity 1 m/s²:
/// the sequenced sink's tilts lift the rest) is "not measured" by
/// `verify`, naming the count, not reported with a realised strength
/// (issue 30: it printed "realised strength −0.857 against 0.307 … over 1
/// of 25 points").
#[test]
fn verify_over_too_few_points_says_not_measured() {
    let dir = temp_dir("few");
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/sequenced/sink/schedule.json"
    ))
    .unwrap();
    let mut s: serde_json::Value = serde_json::from_str(&text).unwrap();
    s["settings"]["gravity"] = serde_json::json!(1.0);
    let path = dir.join("g1.json");
    std::fs::write(&path, s.to_string()).unwrap();
    let out = dir.join("out");
    let (code, stdout, err) = platefield(&[
        "verify",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("model check not measured: 1 of 25 points"),
        "{stdout}"
    );
    assert!(!stdout.contains("model check (moving parts"), "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `design`'s summary opens with the kept design and its one realised
/// measure (issue 29), the same numbers `schedule.json` records, before any
/// candidate's details.
#[test]
fn design_summary_opens_with_the_kept_design() {
    let dir = temp_dir("headline");
    let out = dir.join("out");
    let (code, stdout, err) = platefield(&[
        "design",
        concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"),
        "--method",
        "sequence",
        "--no-cache",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let first = stdout.lines().next().unwrap_or_default();
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sink/schedule.json")).unwrap())
            .unwrap();
    let played = &s["played"];
    let expect = format!(
        "kept sequence: realised strength {:.4} s⁻¹ ({:.4} × the target's 1 s⁻¹) at realised shape error {:.2} %",
        played["realised_strength"].as_f64().unwrap(),
        played["realised_strength"].as_f64().unwrap(),
        100.0 * played["realised_shape_error"].as_f64().unwrap()
    );
    assert!(first.starts_with(&expect), "{first}\nexpected {expect}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Runs a short `verify` (3 × 3 points, one part, no rectangles, one
/// period, and `extra` arguments) of `schedule` written to `dir`, returns
/// its `summary.json`.
fn quick_verify(dir: &Path, schedule: &serde_json::Value, extra: &[&str]) -> serde_json::Value {
    let file = dir.join("schedule.json");
    std::fs::write(&file, schedule.to_string()).unwrap();
    let out = dir.join("out");
    let mut args = vec![
        "verify",
        file.to_str().unwrap(),
        "--points",
        "3",
        "--swarm",
        "1",
        "--rect-poses",
        "0",
        "--repetitions",
        "1",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, _, err) = platefield(&args);
    assert_eq!(code, 0, "{err}");
    let name = schedule["target"].as_str().unwrap();
    let summary = out.join(name).join("verify/summary.json");
    serde_json::from_str(&std::fs::read_to_string(summary).unwrap()).unwrap()
}

/// `verify`'s judge is measured against the target (⟨R, t⟩/⟨t, t⟩), not
/// the measured ratio to the prediction times the schedule's stored
/// `fit.strength`: doubling the stored strength leaves it unchanged and
/// only the designed strength it is compared with doubles. It is the
/// design's own judge: the shipped sink's equals its `played` to
/// round-off (same points, same physics).
#[test]
fn verify_measures_the_realised_strength_of_an_edited_schedule() {
    let dir = temp_dir("verify-strength");
    let shipped: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/synthesized/sink/schedule.json"
        ))
        .unwrap(),
    )
    .unwrap();
    let own = quick_verify(&dir, &shipped, &[]);
    let mut edited = shipped.clone();
    for key in ["fit", "fit_quantized"] {
        let s = edited[key]["strength"].as_f64().unwrap();
        edited[key]["strength"] = (2.0 * s).into();
    }
    let twice = quick_verify(&dir, &edited, &[]);
    let (a, b) = (
        own["judge"]["realised_strength"].as_f64().unwrap(),
        twice["judge"]["realised_strength"].as_f64().unwrap(),
    );
    assert_eq!(a, b, "the stored strength changed the measured one");
    let designed = |v: &serde_json::Value| v["design_strength"].as_f64().unwrap();
    assert_eq!(designed(&twice), 2.0 * designed(&own));
    let played = shipped["played"]["realised_strength"].as_f64().unwrap();
    assert!(
        (a / played - 1.0).abs() < 1e-9,
        "verify's judge {a} against the design's played {played}"
    );
}

/// Issue 30: a grid-less sampled target is verified over its samples'
/// region (their bounding box on the resampling grid's lattice), not over
/// ±3 cm.
#[test]
fn verify_region_of_a_gridless_sampled_target_is_its_samples() {
    let dir = temp_dir("verify-sampled-region");
    let mut s: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/synthesized/sink/schedule.json"
        ))
        .unwrap(),
    )
    .unwrap();
    let points: Vec<[f64; 2]> = [-0.06, 0.0, 0.06]
        .iter()
        .flat_map(|&x| [-0.05, 0.0, 0.05].map(|y| [x, y]))
        .collect();
    let vectors: Vec<[f64; 2]> = points.iter().map(|p| [-p[0], -p[1]]).collect();
    let t = &mut s["target_spec"];
    t.as_object_mut().unwrap().remove("grid");
    t["mask"] = serde_json::json!([]);
    t["field"] = serde_json::json!({"kind": "sampled", "points": points, "vectors": vectors});
    let summary = quick_verify(&dir, &s, &[]);
    let region = &summary["region"];
    // The samples' bounding box (±6 cm × ±5 cm) rounded outward to the
    // resampling grid's lattice through the plate centre: within one
    // spacing of the box.
    let n = region["n"].as_array().unwrap();
    for (k, (axis, half)) in [("x", 0.06), ("y", 0.05)].into_iter().enumerate() {
        let r = region[axis].as_array().unwrap();
        let (lo, hi) = (r[0].as_f64().unwrap(), r[1].as_f64().unwrap());
        let h = (hi - lo) / (n[k].as_f64().unwrap() - 1.0);
        assert!(
            lo <= -half + 1e-12 && lo > -half - h && hi >= half - 1e-12 && hi < half + h,
            "{axis}: {region}"
        );
    }
    // The judge plays every sample of a grid-less target.
    assert_eq!(summary["judge"]["points"].as_u64(), Some(9), "{summary}");
}

/// Issue 30: `linesink --mu 0` is refused as `field` refuses it (nothing
/// drives the part to a steady velocity), and the sine's stick deadband
/// — the paper model's — is not printed as such under `--model full`.
#[test]
fn linesink_refuses_no_friction_and_keeps_the_deadband_to_the_paper_model() {
    let mut args = BASE.to_vec();
    args.extend(["--r", "0.01", "--mu", "0"]);
    let (code, out, err) = platefield(&args);
    assert_eq!(code, 2, "{out}");
    assert!(
        err.contains("--mu") && err.contains("steady velocity"),
        "{err}"
    );
    assert!(out.is_empty());
    // h A = 0.01 × 180 = 1.8 < μ_s g = 2.94: the paper model's deadband
    // |r| ≤ (2.94 − 1.8)/(0.3 × 180) = 0.021167 m; the full model slips
    // inside it (r = 0.021: v_ss −1.1e-6 m/s, stuck 0.931).
    let sine = [
        "study", "linesink", "--wave", "sine", "--accel", "180", "--depth", "0.01", "--r", "0.01",
    ];
    let (code, paper, _) = platefield(&sine);
    assert_eq!(code, 0);
    assert!(paper.contains("stick deadband: |r| ≤ 0.021167"), "{paper}");
    let mut full = sine.to_vec();
    full.extend(["--model", "full"]);
    let (code, full, _) = platefield(&full);
    assert_eq!(code, 0);
    assert!(!full.contains("stick deadband: |r|"), "{full}");
    assert!(full.contains("does not hold for the full model"), "{full}");
}

/// Issue 30: `verify --model frozen` of a schedule with a Circle segment
/// (the sequenced whirlpool) places each lost contact where the frozen
/// part is — a realised-grid point, within the ±4 cm region — not where its
/// slip would have carried it (before: "at (-0.65864, -0.57710) m" for the
/// part frozen at (0.04, 0.04)).
#[test]
fn frozen_verify_places_a_lost_contact_at_the_frozen_part() {
    let dir = temp_dir("verify-frozen-circle");
    let schedule: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/sequenced/whirlpool/schedule.json"
        ))
        .unwrap(),
    )
    .unwrap();
    let summary = quick_verify(&dir, &schedule, &["--model", "frozen"]);
    let mut lost = 0;
    for p in summary["model_check"]["per_point"].as_array().unwrap() {
        let Some(note) = p["note"].as_str() else {
            continue;
        };
        let Some((_, tail)) = note.split_once("leaves the plate") else {
            continue;
        };
        let at = tail
            .split_once(" at (")
            .unwrap()
            .1
            .split_once(") m")
            .unwrap()
            .0;
        let q: Vec<f64> = at.split(", ").map(|c| c.parse().unwrap()).collect();
        let start: Vec<f64> = p["start"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_f64().unwrap())
            .collect();
        assert!(
            (q[0] - start[0]).abs() < 1e-4 && (q[1] - start[1]).abs() < 1e-4,
            "frozen at {start:?}, lost contact reported at {q:?}: {note}"
        );
        lost += 1;
    }
    assert!(lost > 0, "no lost contact to check: {summary}");
}

/// Shaker stroke and velocity limits hold in design (issue 29). The lab
/// sink under a linear stroke limit of 3 mm and an angular velocity limit
/// of 0.5 rad/s (half of what its accelerations would move at harmonic 1:
/// 12/ω² = 7.6 mm, 220/ω = 1.75 rad/s): the synthesized motion's steady
/// stroke and velocity (zero-mean antiderivatives, `KinematicPeaks`) stay
/// within them, its export's as-played peaks too (sample-and-hold from rest,
/// 2e-3 relative), and it still moves parts. Sequenced, an angular stroke
/// limit of 4 mrad leaves out every rotation primitive (the paper's ψ0 is
/// 5 mrad) and says so per column.
#[test]
fn stroke_and_velocity_limits_hold_in_design() {
    use platefield::schedule::export::peaks::KinematicPeaks;
    let dir = temp_dir("travel");
    let target = dir.join("travel.json");
    let write = |shaker: &str| {
        std::fs::write(
            &target,
            format!(
                r#"{{"name": "travel", "grid": {{"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [5, 5]}},
                    "field": {{"kind": "sink"}}, "shaker": {shaker}}}"#
            ),
        )
        .unwrap();
    };
    write(
        r#"{"period": 0.05, "linear": [12, 12, 0.2], "angular": [220, 220, 0], "harmonics": 1,
            "stroke": {"linear": [3e-3, 3e-3, 1]}, "velocity": {"angular": [0.5, 0.5, 1]}}"#,
    );
    let out = dir.join("syn");
    design_synthesized_quickly(&target, &out);
    let file = out.join("travel/schedule.json");
    let schedule = platefield::schedule::Schedule::load(&file).unwrap();
    let motion = schedule.segments[0].plate_motion().unwrap();
    let steady = KinematicPeaks::of_motion(&motion, 1);
    println!(
        "steady stroke {:?}, velocity {:?}",
        steady.stroke, steady.velocity
    );
    let (stroke, velocity) = ([3e-3, 3e-3], [0.5, 0.5]);
    for k in 0..2 {
        assert!(steady.stroke[k] <= stroke[k] * (1.0 + 1e-9), "{steady:?}");
        assert!(
            steady.velocity[3 + k] <= velocity[k] * (1.0 + 1e-9),
            "{steady:?}"
        );
    }
    let played = schedule.played.as_ref().unwrap();
    assert!(played.realised_strength.unwrap_or(0.0) > 0.05, "{played:?}");
    let e = platefield::schedule::export::export(&schedule, 20_000.0, 5).unwrap();
    let p = e.peaks();
    for k in 0..2 {
        assert!(p.stroke[k] <= stroke[k] * 1.002, "{p:?}");
        assert!(p.velocity[3 + k] <= velocity[k] * 1.002, "{p:?}");
    }
    write(r#"{"stroke": {"angular": [4e-3, 4e-3, 4e-3]}}"#);
    let (code, stdout, err) = platefield(&[
        "design",
        target.to_str().unwrap(),
        "--method",
        "sequence",
        "--quiet",
        "--out",
        dir.join("seq").to_str().unwrap(),
    ]);
    let all = format!("{stdout}{err}");
    println!("{all}");
    assert!(all.contains("over the shaker limits"), "{all}");
    let report = std::fs::read_to_string(dir.join("seq/travel/report.md")).unwrap_or_default();
    assert!(
        report.contains("over the shaker limit on angular.x stroke")
            || report.contains("over the shaker limit on angular.y stroke"),
        "{report}"
    );
    if code == 0 {
        let s =
            platefield::schedule::Schedule::load(&dir.join("seq/travel/schedule.json")).unwrap();
        for seg in s.segments.iter().filter_map(|s| s.plate_motion()) {
            let p = KinematicPeaks::of_motion(&seg, 1);
            assert!(
                p.stroke[3..].iter().all(|&x| x <= 4e-3 * (1.0 + 1e-9)),
                "{p:?}"
            );
        }
    } else {
        assert_eq!(code, 2, "{all}");
    }
}

/// `verify --model auto` plays the sequenced sink (four LineSinks) at the
/// cheapest rung that moves the part within 2 % of full for every
/// segment — not `paper`, whose
/// LineSink error is about 8 % — records each segment's choice in the
/// summary, and its judge (strength and shape error) moves by less than
/// the tolerance from the full model's. `order` chooses no rung and
/// refuses `auto`, and a bad `--model` names the allowed values.
#[test]
fn verify_model_auto_records_its_rungs_and_keeps_the_judge() {
    let dir = temp_dir("verify-model-auto");
    let schedule: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/sequenced/sink/schedule.json"
        ))
        .unwrap(),
    )
    .unwrap();
    for sub in ["full", "auto"] {
        std::fs::create_dir_all(dir.join(sub)).unwrap();
    }
    let full = quick_verify(&dir.join("full"), &schedule, &["--model", "full"]);
    assert!(full.get("rungs").is_none(), "{full}");
    let auto = quick_verify(&dir.join("auto"), &schedule, &["--model", "auto"]);
    let rungs = &auto["rungs"];
    assert_eq!(
        rungs["rung"].as_str(),
        Some("paper+moving+centripetal+tilt"),
        "{rungs}"
    );
    let segments = rungs["segments"].as_array().unwrap();
    assert_eq!(segments.len(), 4, "{rungs}");
    for s in segments {
        assert_ne!(s["report"]["rung"].as_str(), Some("paper"), "{s}");
        assert!(s["played_error"].as_f64().unwrap() <= 0.02, "{s}");
    }
    let (jf, ja) = (&full["judge"], &auto["judge"]);
    let (sf, sa) = (
        jf["realised_strength"].as_f64().unwrap(),
        ja["realised_strength"].as_f64().unwrap(),
    );
    assert!((sa - sf).abs() <= 0.02 * sf.abs(), "{jf} {ja}");
    let (ef, ea) = (
        jf["realised_shape_error"].as_f64().unwrap(),
        ja["realised_shape_error"].as_f64().unwrap(),
    );
    assert!((ea - ef).abs() <= 0.02, "{jf} {ja}");

    let file = dir.join("full").join("schedule.json");
    let s = file.to_str().unwrap();
    let (code, _, err) = platefield(&["order", s, "--model", "auto", "--out", "/nonexistent"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--model") && err.contains("verify"), "{err}");
    let (code, _, err) = platefield(&["verify", s, "--model", "cheap"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--model") && err.contains("auto") && err.contains("paper+moving"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `field --model auto` of an in-plane translation (Trans: Ω = 0, N = g)
/// plays `paper`, whose field equals full's exactly, and records the
/// choice under `"rung"`; without `--model` the field JSON has no `"rung"`
/// and keeps the scene's model.
#[test]
fn field_model_auto_plays_paper_for_a_translation() {
    let dir = temp_dir("field-model-auto");
    let scene = dir.join("trans.json");
    std::fs::write(
        &scene,
        r#"{"motion": {"type": "primitive", "kind": "Trans"}, "kind": "force",
            "grid": {"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [7, 7]}, "phases": 4}"#,
    )
    .unwrap();
    let s = scene.to_str().unwrap();
    let (code, out, err) = platefield(&["field", s, "--json", "--quiet", "--model", "auto"]);
    assert_eq!(code, 0, "{err}");
    let auto: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        auto["rung"]["rung"].as_str(),
        Some("paper"),
        "{}",
        auto["rung"]
    );
    assert_eq!(auto["rung"]["error"].as_f64(), Some(0.0));
    assert_eq!(auto["model"]["moving"].as_bool(), Some(false));
    let (code, out, err) = platefield(&["field", s, "--json", "--quiet"]);
    assert_eq!(code, 0, "{err}");
    let plain: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(plain.get("rung").is_none());
    assert_eq!(plain["model"]["coriolis"].as_bool(), Some(true));
    assert_eq!(plain["fx"], auto["fx"]);
    std::fs::remove_dir_all(&dir).ok();
}

/// A 7 × 7 sink over ±2 cm in `dir`: a target `design` fits in well under
/// a second by four LineSinks (`--primitives LineSink --rotation-step 90`).
fn small_sink(dir: &Path) -> std::path::PathBuf {
    let target = dir.join("small_sink.json");
    std::fs::write(
        &target,
        r#"{"name": "small_sink", "grid": {"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [7, 7]},
            "field": {"kind": "sink"}}"#,
    )
    .unwrap();
    target
}

/// `design` of `target` by `method` into `out` with `extra` arguments:
/// the kept schedule.json and the summary printed.
fn small_design(
    target: &Path,
    method: &str,
    out: &Path,
    extra: &[&str],
) -> (serde_json::Value, String) {
    let mut args = vec![
        "design",
        target.to_str().unwrap(),
        "--method",
        method,
        "--primitives",
        "LineSink",
        "--rotation-step",
        "90",
        "--synth-evaluations",
        "60",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, stdout, err) = platefield(&args);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(out.join("small_sink/schedule.json")).unwrap();
    (serde_json::from_str(&text).unwrap(), stdout)
}

/// `design --model auto` records the rung choice in `schedule.json`: the
/// played rung (four LineSinks tilt the plate, so no rung below
/// `paper+moving+centripetal+tilt`, `results/primitives/rungs.md`), whose
/// model is the schedule's `settings.model`, and every moving segment's
/// choice within the tolerance; `report.md` and the summary name it.
/// `verify` of that schedule loads it, plays it at that model and reads
/// the record back (`recorded_rungs`, the same object). Without
/// `--model` the file has no `"rungs"` and keeps the full model.
#[test]
fn design_model_auto_records_its_rungs_and_verify_reads_them_back() {
    let dir = temp_dir("design-model-auto");
    let target = small_sink(&dir);
    let (auto, summary) =
        small_design(&target, "sequence", &dir.join("auto"), &["--model", "auto"]);
    let rungs = &auto["rungs"];
    assert_eq!(
        rungs["played"].as_str(),
        Some("paper+moving+centripetal+tilt"),
        "{rungs}"
    );
    assert_eq!(rungs["tolerance"].as_f64(), Some(0.02), "{rungs}");
    let model = &auto["settings"]["model"];
    assert_eq!(
        [
            &model["moving"],
            &model["centripetal"],
            &model["tilt"],
            &model["coriolis"]
        ],
        [
            &serde_json::json!(true),
            &serde_json::json!(true),
            &serde_json::json!(true),
            &serde_json::json!(false)
        ],
        "{model}"
    );
    let segments = rungs["segments"].as_array().unwrap();
    assert_eq!(segments.len(), 4, "{rungs}");
    for s in segments {
        let i = s["segment"].as_u64().unwrap() as usize;
        assert_eq!(s["label"], auto["segments"][i]["label"], "{s}");
        let e = s["played_error"].as_f64().unwrap();
        assert!(e > 0.0 && e <= 0.02, "{s}");
    }
    assert!(
        summary.contains(
            "model auto: the kept design played and judged at paper+moving+centripetal+tilt"
        ),
        "{summary}"
    );
    let report = std::fs::read_to_string(dir.join("auto/small_sink/report.md")).unwrap();
    assert!(
        report.contains("## Model") && report.contains("--model auto"),
        "{report}"
    );

    std::fs::create_dir_all(dir.join("verify")).unwrap();
    let v = quick_verify(&dir.join("verify"), &auto, &[]);
    assert_eq!(&v["recorded_rungs"], rungs, "{v}");
    assert_eq!(
        v["model"].as_str(),
        Some("paper+centripetal+tilt+moving"),
        "{v}"
    );
    // An override plays another model and reads no record back.
    std::fs::create_dir_all(dir.join("verify-full")).unwrap();
    let v = quick_verify(&dir.join("verify-full"), &auto, &["--model", "full"]);
    assert!(v.get("recorded_rungs").is_none(), "{v}");
    assert_eq!(v["model"].as_str(), Some("full"), "{v}");

    let (plain, summary) = small_design(&target, "sequence", &dir.join("plain"), &[]);
    assert!(plain.get("rungs").is_none(), "{plain}");
    assert_eq!(plain["settings"]["model"]["coriolis"].as_bool(), Some(true));
    assert!(!summary.contains("played and judged at"), "{summary}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The judge's numbers under `design --model auto` stay within the rung
/// tolerance of the full model's, for the sequenced and the synthesized
/// candidate: every segment's field at the rung played is within 2 %
/// (relative L2) of full's, and the realised strength ŝ = ⟨R, t⟩/⟨t, t⟩
/// moves relatively by at most about the field's relative change (Cauchy–
/// Schwarz), the shape error by about as much absolutely. The full
/// design's numbers are the independent reference; where auto plays a
/// cheaper rung they must differ (else auto played full).
#[test]
fn design_model_auto_keeps_the_judge_within_the_tolerance() {
    let dir = temp_dir("design-model-auto-judge");
    let target = small_sink(&dir);
    for method in ["sequence", "synthesize"] {
        let (full, _) = small_design(
            &target,
            method,
            &dir.join(method).join("full"),
            &["--model", "full"],
        );
        let (auto, _) = small_design(
            &target,
            method,
            &dir.join(method).join("auto"),
            &["--model", "auto"],
        );
        let (pf, pa) = (&full["played"], &auto["played"]);
        let (sf, sa) = (
            pf["realised_strength"].as_f64().unwrap(),
            pa["realised_strength"].as_f64().unwrap(),
        );
        let (ef, ea) = (
            pf["realised_shape_error"].as_f64().unwrap(),
            pa["realised_shape_error"].as_f64().unwrap(),
        );
        assert!((sa - sf).abs() <= 0.02 * sf, "{method}: {pf} {pa}");
        assert!((ea - ef).abs() <= 0.02, "{method}: {pf} {pa}");
        let played = auto["rungs"]["played"].as_str().unwrap();
        if played != "full" {
            assert_ne!(sa, sf, "{method}: auto played {played} but judged as full");
        }
        assert_eq!(
            full["segments"], auto["segments"],
            "{method}: the same design"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A bad `design --model` exits 2 naming `--model` and the allowed
/// values, and `auto` where the design chooses no model (the closed loop)
/// exits 2 naming `--model`; nothing is written.
#[test]
fn design_model_refuses_bad_values() {
    let dir = temp_dir("design-model-bad");
    let target = small_sink(&dir);
    let t = target.to_str().unwrap();
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let (code, _, err) = platefield(&["design", t, "--model", "cheap", "--out", o]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--model")
            && [
                "full",
                "auto",
                "paper+moving",
                "paper+moving+centripetal+tilt"
            ]
            .iter()
            .all(|v| err.contains(v)),
        "{err}"
    );
    let (code, _, err) = platefield(&[
        "design",
        t,
        "--model",
        "auto",
        "--closed-loop",
        "--quiet",
        "--out",
        o,
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--model") && err.contains("closed loop"),
        "{err}"
    );
    assert!(!out.join("small_sink").exists());
    std::fs::remove_dir_all(&dir).ok();
}
