//! Inverse design end to end on small grids: fit quality, poor-fit
//! reporting, whole-cycle schedules, controller export, bad input.

use std::path::PathBuf;
use std::process::Command;

use platefield::basis::PrimitiveKind;
use platefield::design::{design, DesignOptions};
use platefield::field::FieldSettings;
use platefield::request::Target;
use platefield::schedule::export::{centre_acceleration, signals_csv};

fn target(name: &str, field: &str) -> Target {
    Target::from_json_str(&format!(
        r#"{{"name": "{name}", "grid": {{"x": [-0.03, 0.03], "y": [-0.03, 0.03], "n": [9, 9]}}, "field": {field}}}"#
    ))
    .expect("valid target")
}

/// Small, fast settings shared by the tests (the cache is shared too).
fn options() -> DesignOptions {
    let mut settings = FieldSettings::default();
    settings.numerics.steps_per_cycle = 32;
    settings.phases = 6;
    DesignOptions {
        settings,
        basis: platefield::design::BasisSection {
            rotation_step_deg: 45.0,
            cache_dir: Some(PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("design-cache")),
            ..Default::default()
        },
        runtime: platefield::work::Runtime::QUIET,
        ..DesignOptions::default()
    }
}

#[test]
fn sink_fits_within_five_percent_with_a_consistent_schedule() {
    let d = design(&target("sink", r#"{"kind": "sink"}"#), &options()).expect("design");
    let s = &d.schedule;
    assert!(
        s.fit.relative_l2_error <= 0.05,
        "{}",
        s.fit.relative_l2_error
    );
    assert!(s.fit.strength > 0.0 && !s.poor_fit);
    assert!(s.solver.status.starts_with("Solved"), "{}", s.solver.status);
    // Whole cycles, at least the minimum each, durations add up.
    let total: f64 = s.segments.iter().map(|g| g.duration_s).sum();
    assert!((total - s.period_s).abs() < 1e-12);
    assert!(s
        .segments
        .iter()
        .all(|g| g.cycles >= s.min_cycles || g.primitive.is_none()));
    assert!(
        s.quantization_error <= 0.02 + 1e-12,
        "{}",
        s.quantization_error
    );
    assert!(
        s.fit_quantized.relative_l2_error <= s.fit.relative_l2_error + s.quantization_error + 1e-9
    );
    // A sink needs squeezing in two directions: LineSinks (or skews) at two angles.
    let angles: std::collections::BTreeSet<i64> = s
        .segments
        .iter()
        .filter_map(|g| g.primitive.as_ref())
        .map(|p| (p.rotation_deg.rem_euclid(180.0)).round() as i64)
        .collect();
    assert!(angles.len() >= 2, "{angles:?}");
}

#[test]
fn unreachable_target_reports_a_poor_fit() {
    // A pure rotation from sink-like primitives only.
    let mut opts = options();
    opts.basis.kinds = vec![PrimitiveKind::LineSink, PrimitiveKind::LineSource];
    let d = design(&target("rotation", r#"{"kind": "scaled_circle"}"#), &opts)
        .expect("best fit, not an error");
    assert!(d.schedule.poor_fit, "{:?}", d.schedule.fit);
    assert!(d.schedule.fit.relative_l2_error > 0.5);
}

#[test]
fn export_is_rest_to_rest_and_sampled_at_the_rate() {
    let d = design(&target("sink", r#"{"kind": "sink"}"#), &options()).expect("design");
    let s = &d.schedule;
    let rate = 20000.0;
    let csv = signals_csv(s, rate).expect("export");
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    // Every cycle is a whole number of held samples: round(rate · T) per cycle.
    let cycle = s.period_s / f64::from(s.total_cycles);
    let per_cycle = (rate * cycle).round() as usize;
    assert_eq!(rows.len(), s.total_cycles as usize * per_cycle);
    assert!(rows
        .iter()
        .all(|r| r.len() == 7 && r.iter().all(|x| x.is_finite())));
    // Integrating the angular acceleration over each segment returns the
    // angular velocity to zero (the plate is at rest at every join).
    let seg = s.segments.iter().find(|g| g.primitive.is_some()).unwrap();
    let motion = seg.primitive.as_ref().unwrap().motion();
    let n = 20000;
    let h = seg.duration_s / n as f64;
    let mut w = [0.0f64; 3];
    for i in 0..n {
        let (_, a) = centre_acceleration(&motion, (i as f64 + 0.5) * h);
        for k in 0..3 {
            w[k] += a[k] * h;
        }
    }
    let scale = 0.005 * 209.0; // ψ0 ω
    assert!(w.iter().all(|x| x.abs() < 1e-6 * scale), "{w:?}");
}

#[test]
fn bad_targets_are_named_and_nothing_is_written() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bad-targets");
    std::fs::create_dir_all(&dir).unwrap();
    let cases = [
        (
            "kind",
            r#"{"name": "a", "grid": {"x": [-0.03, 0.03], "y": [-0.03, 0.03], "n": [5, 5]}, "field": {"kind": "sinc"}}"#,
            "target.field.kind",
        ),
        (
            "grid",
            r#"{"name": "b", "field": {"kind": "sink"}}"#,
            "grid",
        ),
        (
            "nan",
            r#"{"name": "c", "grid": {"x": [-0.03, 0.03], "y": [-0.03, NaN], "n": [5, 5]}, "field": {"kind": "sink"}}"#,
            "",
        ),
        (
            "lengths",
            r#"{"name": "d", "field": {"kind": "sampled", "points": [[0, 0], [0.01, 0]], "vectors": [[1, 0]]}}"#,
            "target.field.points",
        ),
    ];
    for (label, json, path) in cases {
        let file = dir.join(format!("{label}.json"));
        std::fs::write(&file, json).unwrap();
        let out = dir.join(format!("out-{label}"));
        let run = Command::new(env!("CARGO_BIN_EXE_platefield"))
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
            .args([
                "design",
                file.to_str().unwrap(),
                "--quiet",
                "--no-cache",
                "--out",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert_ne!(run.status.code(), Some(0), "{label}");
        assert!(err.contains(path), "{label}: {err}");
        assert!(!out.exists(), "{label}: nothing may be written");
    }
}

/// Issue 13: degenerate targets exit 2 within a second, before any
/// library is built, naming the JSON path and the allowed range once
/// (the path is not repeated), with short numbers; nothing is written.
#[test]
fn degenerate_targets_are_refused_before_the_library_build() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("degenerate-targets");
    std::fs::create_dir_all(&dir).unwrap();
    let grid = r#""grid": {"x": [-0.03, 0.03], "y": [-0.03, 0.03], "n": [5, 5]}"#;
    let strength = "must be non-zero, with |value| in [0.000001, 1000000] 1/s, got";
    let cases: [(&str, String, &[&str]); 8] = [
        ("zero", format!(r#"{{{grid}, "field": {{"kind": "sink", "strength": 0}}}}"#), &["target.field.strength: ", strength, "got 0"]),
        ("tiny", format!(r#"{{{grid}, "field": {{"kind": "sink", "strength": 1e-300}}}}"#), &["target.field.strength: ", strength, "got 1e-300"]),
        (
            "weight0",
            format!(r#"{{{grid}, "field": {{"kind": "sum", "terms": [{{"weight": 0, "field": {{"kind": "sink"}}}}]}}}}"#),
            &["target.field.terms[0].weight: must be non-zero"],
        ),
        (
            "cancels",
            format!(r#"{{{grid}, "field": {{"kind": "sum", "terms": [{{"field": {{"kind": "sink"}}}}, {{"field": {{"kind": "source"}}}}]}}}}"#),
            &["target.field: is zero (|f| ≤ 1e-12 m/s) at every sample point"],
        ),
        (
            "fine",
            r#"{"grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [1001, 1001]}, "field": {"kind": "sink"}}"#.to_string(),
            &["target.grid.n: must be at most [703, 703] over this region", "got [1001, 1001]"],
        ),
        (
            "flat",
            format!(r#"{{{grid}, "field": {{"kind": "sink"}}, "weights": [1, 1, 1, 1, 1]}}"#),
            &["target.weights: must be an array of rows", "ny rows of nx numbers", "flat list of 5 numbers"],
        ),
        (
            "misspelt",
            format!(r#"{{{grid}, "field": {{"kind": "sink", "strenght": 2}}}}"#),
            &["target.field.strenght: unknown field for kind \"sink\" (expected one of kind, center, strength)"],
        ),
        (
            "misspelt_top",
            format!(r#"{{{grid}, "field": {{"kind": "sink"}}, "mask ": []}}"#),
            &["target.mask : unknown field (expected one of name, grid, field, weights, mask, shaker, friction, gravity, classes)"],
        ),
    ];
    for (label, json, expected) in cases {
        let file = dir.join(format!("{label}.json"));
        std::fs::write(&file, &json).unwrap();
        let out = dir.join(format!("out-{label}"));
        let start = std::time::Instant::now();
        let run = Command::new(env!("CARGO_BIN_EXE_platefield"))
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
            .args([
                "design",
                file.to_str().unwrap(),
                "--quiet",
                "--no-cache",
                "--out",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        let seconds = start.elapsed().as_secs_f64();
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{label}: {err}");
        assert!(seconds < 5.0, "{label}: refused after {seconds} s");
        for e in expected {
            assert!(err.contains(e), "{label}: {err:?} lacks {e:?}");
        }
        let path = expected[0].split(':').next().unwrap();
        assert_eq!(
            err.matches(path).count(),
            1,
            "{label}: path repeated: {err}"
        );
        // Found when reading the file: the file is named first; a field
        // that samples to zero is found by the design's first step.
        let origin = if label == "cancels" {
            String::new()
        } else {
            format!("{}: ", file.display())
        };
        assert!(
            err.starts_with(&format!("error: {origin}{path}")),
            "{label}: {err}"
        );
        assert!(err.len() < 600, "{label}: long message: {err}");
        assert!(!out.exists(), "{label}: nothing may be written");
    }
}

/// Issue 13: a sampled target of four points within 1 cm designs on a
/// library grid sized by its region (a few hundred samples, not 63,504).
#[test]
fn small_sampled_target_designs_on_a_small_grid() {
    let t = Target::from_json_str(
        r#"{"name": "tiny", "field": {"kind": "sampled",
            "points": [[0, 0], [0.009, 0], [0, 0.009], [0.009, 0.009]],
            "vectors": [[0.0045, 0.0045], [-0.0045, 0.0045], [0.0045, -0.0045], [-0.0045, -0.0045]]}}"#,
    )
    .expect("valid target");
    let mut opts = options();
    opts.basis.kinds = vec![PrimitiveKind::LineSink];
    opts.basis.rotation_step_deg = 90.0;
    let start = std::time::Instant::now();
    let d = design(&t, &opts).expect("design");
    assert!(start.elapsed().as_secs_f64() < 60.0);
    assert_eq!(d.target.len(), 4);
    let g = platefield::design::basis::sampling_grid(None, &d.target.points);
    let cover = platefield::basis::symmetry::source_grid(
        &g,
        &[
            0.0,
            90f64.to_radians(),
            180f64.to_radians(),
            270f64.to_radians(),
        ],
        &[[0.0, 0.0]],
    );
    assert!(cover.len() <= 500, "{} library samples", cover.len());
}

/// Issue 30: 1000 scattered samples of an exact sink −p over ±4 cm kept
/// no LineSink ("contact lost" at interpolation nodes beyond the samples,
/// where the plate lifts the part) and fitted 26 % with DivCircles only;
/// 25 or 200 samples fitted 2 %. The four LineSinks 90° apart make a sink
/// at any density: the fit must be as good as the gridded sink's (≤ 3 %).
#[test]
fn dense_scattered_sink_keeps_its_line_sinks() {
    // A fixed linear congruential sequence: the same points on every run.
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut uniform = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        ((state >> 11) as f64 / (1u64 << 53) as f64) * 0.08 - 0.04
    };
    let points: Vec<[f64; 2]> = (0..1000).map(|_| [uniform(), uniform()]).collect();
    let vectors: Vec<[f64; 2]> = points.iter().map(|p| [-p[0], -p[1]]).collect();
    let json = serde_json::json!({"name": "dense", "field": {"kind": "sampled",
        "points": points, "vectors": vectors}});
    let t = Target::from_json_str(&json.to_string()).expect("valid target");
    let mut opts = options();
    opts.basis.kinds = vec![PrimitiveKind::LineSink];
    opts.basis.rotation_step_deg = 90.0;
    let d = design(&t, &opts).expect("design");
    let kept = d.basis.columns.len();
    assert_eq!(
        kept, 4,
        "LineSinks kept: {kept} of 4 ({:?})",
        d.basis.excluded
    );
    let e = d.schedule.fit.relative_l2_error;
    assert!(e <= 0.03, "fit error {e}");
}

#[test]
fn design_is_deterministic() {
    let t = target("saddle", r#"{"kind": "saddle"}"#);
    // No timings in the schedule: the bytes are the same.
    let a = design(&t, &options()).unwrap().schedule;
    let b = design(&t, &options()).unwrap().schedule;
    assert_eq!(
        serde_json::to_string(&a).unwrap(),
        serde_json::to_string(&b).unwrap()
    );
}

/// Issue 5: under the sink schedule at least 95 % of point parts started
/// over the region end within 3 mm of the centre, and the median time they
/// take matches the time the design's strength predicts,
/// ln(d₀/3 mm)/σ, within 20 % (measured: see the assertion message; the
/// realised field differs from the prediction by the interaction of the
/// segments, about 10 %, and parts start on different paths).
#[test]
fn sink_swarm_converges_in_the_time_the_strength_predicts() {
    use platefield::play::{PlayOptions, ScheduleMotion};
    use platefield::request::Attractor;
    use platefield::verify::run::{region_points, swarm_periods};
    use platefield::verify::{run_swarm, Duration, SwarmOptions};
    let t = target("sink", r#"{"kind": "sink"}"#);
    let d = design(&t, &options()).expect("design");
    let s = &d.schedule;
    let sm = ScheduleMotion::from_schedule(s).expect("schedule");
    let settings = options().settings;
    let attractor = Attractor::of(&t.field);
    let grid = t.grid.expect("grid");
    let starts = region_points(&grid, 9);
    let strength = s.fit_quantized.strength;
    let periods = swarm_periods(
        Duration::Auto,
        sm.period(),
        attractor.as_ref(),
        &starts,
        strength,
        0.003,
    );
    let swarm = run_swarm(
        &sm,
        &starts,
        attractor,
        &SwarmOptions {
            verify: PlayOptions::from_settings(&settings),
            periods,
            tol: 0.003,
            strength,
        },
    );
    let f = swarm.converged_fraction.expect("a sink has an attractor");
    let ratio = swarm.time_ratio.expect("parts converged");
    eprintln!(
        "sink swarm: {:.1} % converged, median {:?} s measured, {:?} s predicted, ratio {ratio:.3}",
        100.0 * f,
        swarm.median_time_to_converge_s,
        swarm.median_predicted_time_s
    );
    assert!(f >= 0.95, "converged fraction {f}");
    assert!(
        (ratio - 1.0).abs() <= 0.2,
        "median time {:?} s against {:?} s predicted (ratio {ratio})",
        swarm.median_time_to_converge_s,
        swarm.median_predicted_time_s
    );
    assert_eq!(swarm.contact_lost, 0);
    // The measured time is independent of the prediction: recompute one part's
    // predicted time from the attractor directly.
    let p = &swarm.parts[0];
    let d0 = (p.start[0].powi(2) + p.start[1].powi(2)).sqrt();
    assert!((p.predicted_time_s.unwrap() - (d0 / 0.003).ln() / strength).abs() < 1e-12);
}

/// `git status --porcelain` of the workspace (tracked changes and files
/// git does not ignore), or `None` where the workspace is no git checkout.
fn git_status(root: &str) -> Option<String> {
    let out = Command::new("git")
        .args(["status", "--porcelain", "--untracked-files=all"])
        .current_dir(root)
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).into_owned())
}

/// `design` without `--out` writes to `out/`, which git ignores: designing
/// a shipped target, with a non-default option, changes nothing git tracks
/// or shows.
#[test]
fn design_by_default_leaves_the_checkout_as_it_was() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let Some(before) = git_status(root) else {
        eprintln!("not a git checkout: nothing to compare");
        return;
    };
    let run = Command::new(env!("CARGO_BIN_EXE_platefield"))
        .args(["design", "targets/line_sink.json", "--method", "sequence"])
        .args(["--min-cycles", "12", "--quiet"])
        .current_dir(root)
        .output()
        .expect("runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let written = std::path::Path::new(root).join("out/line_sink/schedule.json");
    assert!(written.is_file(), "design writes under out/");
    assert_eq!(git_status(root).as_deref(), Some(before.as_str()));
}
