//! Scenes as JSON: the example scenes, the six-signal reading against the
//! screw it stands for, and the `platefield field` command.

mod common;
use common::platefield;

use std::f64::consts::{FRAC_PI_2, PI};
use std::path::{Path, PathBuf};

use platefield::dynamics::Friction;
use platefield::field::{Field, Validity};
use platefield::progress::ProgressMode;
use platefield::scene::Scene;
use platefield_studies::linesink::{LineSink, Wave};
use serde_json::{json, Value};

fn scenes_dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("targets/scenes")
}

fn load(name: &str) -> Scene {
    Scene::load(&scenes_dir().join(name)).expect("example scene loads")
}

/// Largest |a − b| over the samples, and the larger of the two fields'
/// maximum magnitudes.
fn difference(a: &Field, b: &Field) -> (f64, f64) {
    assert_eq!(a.grid, b.grid);
    assert_eq!(a.validity, b.validity);
    let d = a
        .vectors
        .iter()
        .zip(&b.vectors)
        .map(|(u, v)| (u[0] - v[0]).hypot(u[1] - v[1]))
        .fold(0.0, f64::max);
    (d, a.max_magnitude().max(b.max_magnitude()))
}

// ---------------------------------------------------------------------------
// (a) The example scenes.

/// Every example scene parses, round-trips through its JSON, computes with
/// every sample valid, and in well under a second.
#[test]
fn every_example_scene_parses_and_computes() {
    let mut names: Vec<String> = std::fs::read_dir(scenes_dir())
        .expect("targets/scenes exists")
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".json"))
        .collect();
    names.sort();
    for required in [
        "linesink.json",
        "linesink_signals.json",
        "sine_square_linesink.json",
        "trans_signals.json",
    ] {
        assert!(names.iter().any(|n| n == required), "{required} missing");
    }
    for name in &names {
        let scene = load(name);
        let back = Scene::from_json_str(&scene.to_json().to_string()).expect("round trip");
        assert_eq!(back, scene, "{name}");
        let start = std::time::Instant::now();
        let field = scene
            .compute(ProgressMode::Quiet)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let seconds = start.elapsed().as_secs_f64();
        assert_eq!(field.valid_count(), scene.grid.len(), "{name}");
        assert!(field.max_magnitude() > 0.0, "{name}");
        assert!(seconds < 5.0, "{name} took {seconds} s");
    }
}

/// What the example fields show: the LineSink squeezes onto x = 0, the
/// Trans pushes uniformly along x, and the paper's square-wave LineSink is
/// eq. 17 (its assumptions hold over the whole grid: hα = 9 > μ(g + |x|α),
/// |x|α ≤ g), to the 1e-9 that `tests/linesink.rs` holds.
#[test]
fn example_fields_have_their_shapes() {
    let sink = load("linesink.json").compute(ProgressMode::Quiet).unwrap();
    let xs = sink.grid.xs();
    let nx = xs.len();
    for (k, v) in sink.vectors.iter().enumerate() {
        let x = xs[k % nx];
        if x.abs() > 0.01 {
            assert!(
                v[0] * x < 0.0,
                "LineSink pushes towards x = 0 (x = {x}, {v:?})"
            );
            assert!(v[1].abs() < 1e-3 * v[0].abs(), "{v:?}");
        }
    }

    let trans = load("trans_signals.json")
        .compute(ProgressMode::Quiet)
        .unwrap();
    let f0 = trans.vectors[0];
    assert!(f0[0].abs() > 0.01 && f0[1].abs() < 1e-12, "{f0:?}");
    for v in &trans.vectors {
        // In-plane translation: the field is the same everywhere.
        assert!((v[0] - f0[0]).abs() < 1e-12 && v[1].abs() < 1e-12, "{v:?}");
    }

    let square = load("sine_square_linesink.json");
    let field = square.compute(ProgressMode::Quiet).unwrap();
    let ls = LineSink {
        wave: Wave::Square,
        accel: 180.0,
        depth: 0.05,
        period: 0.03,
        friction: Friction::uniform(0.3),
        gravity: 9.81,
    };
    for (k, v) in field.vectors.iter().enumerate() {
        let x = xs[k % nx];
        let eq17 = ls.eq17(x).expect("eq. 17 assumptions hold on the grid");
        assert!(
            (v[0] - eq17).abs() <= 1e-9 * eq17.abs().max(1e-3),
            "x = {x}: {} vs eq. 17 {eq17}",
            v[0]
        );
        assert!(v[1].abs() < 1e-12);
    }
}

/// `linesink_signals.json` is `linesink.json` written as six signals. Two
/// things a six-signal motion cannot carry: the rest-to-rest pose's mean
/// offset ψ0 (six-signal poses are zero-mean) and the constant part
/// −h ψ0² ω²/2 of the vertical plate-centre acceleration. With the tilt
/// switch off the pose offset has no effect, and a constant vertical plate
/// acceleration c is exactly a change of gravity g → g − c; so with tilt
/// off and gravity 9.81 − 0.027300625 the two scenes give the same field to
/// rounding. With the full model the difference is, to first order in ψ0,
/// the mean tilt: a constant extra in-plane gravity g sin ψ0 ≈ 0.049 m/s²,
/// which changes a one-cycle velocity change by at most its value × T, so F
/// by at most g sin ψ0 (the rest, the dropped constant and the frame
/// rotation of a_c, is O(μ ψ0² ω² h) ≈ 0.02 m/s² in N, i.e. ≲ 0.01 m/s² in
/// F); the field differs by a near-uniform offset of 0.03 m/s².
#[test]
fn linesink_signals_is_linesink() {
    let mut screw = load("linesink.json");
    let mut signals = load("linesink_signals.json");
    let (d, scale) = difference(
        &screw.compute(ProgressMode::Quiet).unwrap(),
        &signals.compute(ProgressMode::Quiet).unwrap(),
    );
    assert!(
        d <= 9.81 * 0.005f64.sin() && d > 0.1 * 9.81 * 0.005,
        "full model: |ΔF| = {d} (scale {scale})"
    );

    screw.model.tilt = false;
    signals.model.tilt = false;
    signals.gravity = 9.81 - 0.05 * 0.005f64.powi(2) * 209f64.powi(2) / 2.0;
    let (d, scale) = difference(
        &screw.compute(ProgressMode::Quiet).unwrap(),
        &signals.compute(ProgressMode::Quiet).unwrap(),
    );
    assert!(d <= 1e-9 * scale, "tilt off: |ΔF| = {d} (scale {scale})");
}

// ---------------------------------------------------------------------------
// (b) Faithful six-signal reading.

const OMEGA: f64 = 209.0;
const PSI0: f64 = 0.005;
const DEPTH: f64 = 0.05;
/// Direction of the horizontal axis (not a coordinate axis, so that every
/// in-plane signal is exercised).
const BETA: f64 = 0.7;

fn period() -> f64 {
    2.0 * PI / OMEGA
}

/// Bessel function J_n(x) by its power series (x is small here).
fn bessel_j(n: u32, x: f64) -> f64 {
    let mut sum = 0.0;
    let mut term = (0.5 * x).powi(n as i32) / (1..=n).map(f64::from).product::<f64>();
    for m in 0..20 {
        sum += term;
        term *= -(0.25 * x * x) / (f64::from(m + 1) * f64::from(m + 1 + n));
    }
    sum
}

fn scene_json(motion: Value, model: Value, kind: &str, gravity: f64) -> Scene {
    let text = json!({
        "motion": motion,
        "kind": kind,
        "model": model,
        "gravity": gravity,
        "phases": 6,
        "grid": {"x": [-0.04, 0.04], "y": [-0.02, 0.02], "n": [5, 3]},
    })
    .to_string();
    Scene::from_json_str(&text).unwrap_or_else(|e| panic!("{e}"))
}

/// The screw: ψ'' = A sin ωt (a symmetric sine, so ψ = −ψ0 sin ωt has zero
/// mean, like every six-signal pose), about k = (cos β, sin β, 0) through
/// (0, 0, −h).
fn screw_motion() -> Value {
    json!({
        "type": "screw",
        "axis": [BETA.cos(), BETA.sin(), 0.0],
        "point": [0.0, 0.0, -DEPTH],
        "period": period(),
        "rotation": {"type": "sine", "accel": PSI0 * OMEGA * OMEGA},
    })
}

fn term(amplitude: f64, phase: f64, harmonic: u32) -> Value {
    json!({"amplitude": amplitude, "phase": phase, "harmonic": harmonic})
}

/// The same rotation as six signals. Angular acceleration ψ'' k. The
/// plate-centre acceleration in the plate frame is
/// a_c = ψ'' k × (0 − h) + ψ'² k × (k × (0 − h)) = h ψ'' e − h ψ'² z,
/// e = k × z = (k_y, −k_x, 0), with ψ'² = ψ0² ω² (1 + cos 2ωt)/2: harmonic
/// 1 in-plane, harmonics 0 and 2 vertically. `centripetal` adds the
/// harmonic-2 part (the harmonic-0 part, −c with c = h ψ0² ω²/2, is not a
/// periodic acceleration: [`plate_frame_gravity_shift`] moves it into g).
fn plate_frame_signals(centripetal: bool) -> Value {
    let a = PSI0 * OMEGA * OMEGA;
    let (kx, ky) = (BETA.cos(), BETA.sin());
    let c = DEPTH * PSI0 * PSI0 * OMEGA * OMEGA / 2.0;
    let z = if centripetal {
        vec![term(-c, FRAC_PI_2, 2)]
    } else {
        vec![]
    };
    json!({
        "type": "signals",
        "period": period(),
        "linear": {"x": [term(DEPTH * a * ky, 0.0, 1)], "y": [term(-DEPTH * a * kx, 0.0, 1)], "z": z},
        "angular": {"x": [term(a * kx, 0.0, 1)], "y": [term(a * ky, 0.0, 1)]},
    })
}

/// c = h ψ0² ω²/2, the constant downward plate-centre acceleration of the
/// centripetal term; a constant vertical plate acceleration is exactly a
/// change of gravity (N and a_free see only a_s − g_S, and with tilt off
/// g_S = (0, 0, −g)).
fn plate_frame_gravity_shift() -> f64 {
    DEPTH * PSI0 * PSI0 * OMEGA * OMEGA / 2.0
}

/// The same rotation as the exact world-frame plate-centre acceleration.
/// The plate centre is at p = (I − R)h = h (e sin ψ, cos ψ − 1); with
/// ψ = −ψ0 sin ωt, Jacobi–Anger gives sin ψ = −2 Σ_odd J_n(ψ0) sin nωt and
/// cos ψ = J_0(ψ0) + 2 Σ_even J_n(ψ0) cos nωt, so
/// p'' = 2h Σ_odd n²ω² J_n(ψ0) sin(nωt) e − 2h Σ_even n²ω² J_n(ψ0) cos(nωt) z,
/// zero-mean in every component (the pose is periodic). Terms up to n = 6;
/// the first one left out is of relative size J_7(ψ0)/J_1(ψ0) ≈ 1e-20.
fn world_frame_signals() -> Value {
    let a = PSI0 * OMEGA * OMEGA;
    let (kx, ky) = (BETA.cos(), BETA.sin());
    let (mut x, mut y, mut z) = (vec![], vec![], vec![]);
    for n in 1..=6u32 {
        let amp = 2.0 * DEPTH * f64::from(n * n) * OMEGA * OMEGA * bessel_j(n, PSI0);
        if n % 2 == 1 {
            x.push(term(amp * ky, 0.0, n));
            y.push(term(-amp * kx, 0.0, n));
        } else {
            z.push(term(-amp, FRAC_PI_2, n));
        }
    }
    json!({
        "type": "signals",
        "period": period(),
        "linear": {"x": x, "y": y, "z": z},
        "angular": {"x": [term(a * kx, 0.0, 1)], "y": [term(a * ky, 0.0, 1)]},
    })
}

fn switches(centripetal: bool, tilt: bool, coriolis: bool, moving: bool) -> Value {
    json!({"centripetal": centripetal, "tilt": tilt, "coriolis": coriolis, "moving": moving})
}

/// A rotation about a horizontal axis through (0, 0, −h), written as six
/// signals, gives the screw's field, force and velocity, under each model.
///
/// What is exact, and why the tolerance is 1e-9 of the field's scale:
///
/// * Tilt off: both motions read their accelerations as plate-frame
///   vectors with gravity (0, 0, −g); the signals carry h ψ'' e (and with
///   the centripetal switch the harmonic-2 part of −h ψ'² z, its constant
///   part moved into gravity). The kinematics agree to rounding.
/// * Tilt on: the six signals are world-frame accelerations rotated into
///   the plate by R(θ)ᵀ, θ the zero-mean double integral of the angular
///   acceleration; for the sine θ = ψ exactly, and the exact world-frame
///   series of p'' above makes R(θ)ᵀ p'' the screw's plate-frame a_c.
///   (A rest-to-rest ψ has mean ψ0, which θ cannot have: that case differs
///   by the mean tilt, see `linesink_signals_is_linesink`.)
///
/// The two simulations then integrate the same equations with kinematics
/// that differ by rounding (~1e-16 relative). Force fields are one-cycle
/// integrations with events located to 1e-14 of T: they agree to ~1e-13 of
/// the field's scale. Velocity fields are fixed points found to a residual
/// of steady_tol = 1e-11 of μ_k g T (≈ 1e-12 m/s against fields of ~0.025
/// m/s): they agree to ~3e-11 of the scale. The tolerance, 1e-9 of the
/// scale, leaves a margin of 30 over the velocity fields' solver tolerance
/// and still catches any error of the reading: the plate-frame signals under
/// tilt (R(θ)ᵀ applied to an acceleration that is already in the plate
/// frame, off by O(ψ0²ω²h) ≈ 0.05 m/s² in the normal direction) differ by
/// ~1e-3 of the scale, checked below to exceed 1e-4.
#[test]
fn six_signals_reproduce_the_screw() {
    let g = 9.81;
    let cases = [
        // (label, model, signals, gravity of the signals scene)
        ("paper", json!("paper"), plate_frame_signals(false), g),
        (
            "tilt off, no centripetal",
            switches(false, false, true, true),
            plate_frame_signals(false),
            g,
        ),
        (
            "tilt off, centripetal",
            switches(true, false, true, true),
            plate_frame_signals(true),
            g - plate_frame_gravity_shift(),
        ),
        ("full", json!("full"), world_frame_signals(), g),
        (
            "tilt, frozen",
            switches(true, true, true, false),
            world_frame_signals(),
            g,
        ),
    ];
    for (label, model, signals, g_signals) in cases {
        for kind in ["force", "velocity"] {
            let screw = scene_json(screw_motion(), model.clone(), kind, g);
            let sig = scene_json(signals.clone(), model.clone(), kind, g_signals);
            let (a, b) = (
                screw.compute(ProgressMode::Quiet).unwrap(),
                sig.compute(ProgressMode::Quiet).unwrap(),
            );
            assert!(
                a.validity.iter().all(|v| *v == Validity::Ok),
                "{label} {kind}"
            );
            let (d, scale) = difference(&a, &b);
            assert!(
                scale > 1e-4,
                "{label} {kind}: field is not trivial ({scale})"
            );
            assert!(
                d <= 1e-9 * scale,
                "{label} {kind}: |Δ| = {d:e}, scale {scale:e}"
            );
        }
    }

    // The test can tell readings apart: the plate-frame signals (right with
    // tilt off) are not the screw once the tilt rotates them.
    let screw = scene_json(screw_motion(), json!("full"), "force", g);
    let sig = scene_json(
        plate_frame_signals(true),
        json!("full"),
        "force",
        g - plate_frame_gravity_shift(),
    );
    let (d, scale) = difference(
        &screw.compute(ProgressMode::Quiet).unwrap(),
        &sig.compute(ProgressMode::Quiet).unwrap(),
    );
    assert!(
        d > 1e-4 * scale,
        "plate-frame reading under tilt: |Δ| = {d:e}"
    );
}

// ---------------------------------------------------------------------------
// (c), (d) The `platefield field` command.

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("platefield-scene-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const GOOD: &str = r#"{
  "motion": {"type": "screw", "axis": [0, 1, 0], "point": [0, 0, -0.05],
             "period": 0.03, "rotation": {"type": "rest_to_rest", "amplitude": 0.005}},
  "kind": "force",
  "phases": 4,
  "grid": {"x": [-0.04, 0.04], "y": [-0.02, 0.02], "n": [5, 3]}
}"#;

/// Bad scenes exit non-zero, name the JSON path on stderr, and write
/// nothing (neither `--out` nor `--svg`).
#[test]
fn field_command_rejects_bad_scenes() {
    let dir = temp_dir("bad");
    let cases: [(&str, &str, &str, &[&str]); 13] = [
        (
            "spiral",
            "\"screw\"",
            "\"spiral\"",
            &[
                "scene.motion.type",
                "unknown type \"spiral\"",
                "screw, signals, primitive",
            ],
        ),
        (
            "negative_grid",
            "[5, 3]",
            "[-3, 3]",
            &["scene.grid.n[0]", "must be a non-negative integer, got -3"],
        ),
        (
            "no_period",
            "\"period\": 0.03,",
            "",
            &["scene.motion.period", "missing (required)"],
        ),
        (
            "nan",
            "\"amplitude\": 0.005",
            "\"amplitude\": NaN",
            &["scene.motion.rotation.amplitude", "finite"],
        ),
        (
            "zero_period",
            "\"period\": 0.03",
            "\"period\": 0",
            &["scene.motion.period", "must be in [0.0001, 100] s, got 0"],
        ),
        (
            "flying",
            "\"amplitude\": 0.005",
            "\"amplitude\": 0.4",
            &[
                "leaves the plate (N < 0) at every grid point",
                "scene.motion.rotation.amplitude",
            ],
        ),
        // Issue 10: a misspelt key is named with its path.
        (
            "misspelt",
            "\"phases\": 4",
            "\"phase\": 4",
            &["scene.phase: unknown field (expected one of name, description, motion, kind, grid, friction, gravity, model, phases, numerics)"],
        ),
        (
            "misspelt_wave",
            "\"amplitude\": 0.005",
            "\"amplitud\": 0.005",
            &["scene.motion.rotation.amplitud: unknown field for type \"rest_to_rest\""],
        ),
        // Issue 13: physics out of range is a range error naming the field,
        // not "reduce the amplitude"; numbers stay short.
        (
            "friction",
            "\"phases\": 4",
            "\"phases\": 4, \"friction\": 1e5",
            &["scene.friction: must be in [0, 2], got 100000"],
        ),
        (
            "gravity",
            "\"phases\": 4",
            "\"phases\": 4, \"gravity\": 1e308",
            &["scene.gravity: must be in [0.1, 100] m/s², got 1e308"],
        ),
        (
            "huge_rotation",
            "\"amplitude\": 0.005",
            "\"amplitude\": 1e308",
            &["scene.motion.rotation.amplitude: must be in [-0.5, 0.5] rad, got 1e308"],
        ),
        (
            "steps",
            "\"phases\": 4",
            "\"phases\": 4, \"numerics\": {\"steps_per_cycle\": 1000000}",
            &["scene.numerics.steps_per_cycle: must be in 8..=4096, got 1000000"],
        ),
        (
            "not_an_object",
            "\"kind\": \"force\"",
            "\"kind\": \"force\", \"model\": [1]",
            &["scene.model: must be \"paper\", \"full\" or an object of the switches"],
        ),
    ];
    for (tag, from, to, expected) in cases {
        assert!(GOOD.contains(from), "{tag}");
        let scene = dir.join(format!("{tag}.json"));
        std::fs::write(&scene, GOOD.replace(from, to)).unwrap();
        let (out, svg) = (
            dir.join(format!("{tag}.out.json")),
            dir.join(format!("{tag}.svg")),
        );
        let (code, stdout, stderr) = platefield(&[
            "field",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--svg",
            svg.to_str().unwrap(),
            "--quiet",
        ]);
        assert_eq!(code, 2, "{tag} should fail with exit 2: {stderr}");
        assert!(
            !stderr.contains("reduce the amplitude") || tag == "flying",
            "{tag}: {stderr}"
        );
        assert!(
            stderr.lines().all(|l| l.len() < 400),
            "{tag}: short lines: {stderr}"
        );
        for e in expected {
            assert!(
                stderr.contains(e),
                "{tag}: stderr {stderr:?} should contain {e:?}"
            );
        }
        assert!(
            stderr.contains(&format!("{tag}.json")),
            "{tag}: names the file: {stderr}"
        );
        assert!(stdout.is_empty(), "{tag}: stdout {stdout:?}");
        assert!(!out.exists() && !svg.exists(), "{tag}: nothing written");
    }
    let (code, _, stderr) = platefield(&["field", dir.join("absent.json").to_str().unwrap()]);
    assert_ne!(code, 0);
    assert!(stderr.contains("absent.json"), "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `--json` prints the documented field JSON with nx × ny arrays; `--out`
/// writes the same bytes; `--svg` a quiver plot; the summary names the
/// grid, kind, model and counts.
#[test]
fn field_command_outputs() {
    let dir = temp_dir("good");
    let scene = dir.join("good.json");
    std::fs::write(&scene, GOOD).unwrap();
    let scene = scene.to_str().unwrap();
    let (out, svg) = (dir.join("f.json"), dir.join("f.svg"));
    let (code, stdout, stderr) = platefield(&[
        "field",
        scene,
        "--json",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let v: Value = serde_json::from_str(&stdout).expect("field JSON");
    let (nx, ny) = (5, 3);
    assert_eq!(v["x"].as_array().unwrap().len(), nx);
    assert_eq!(v["y"].as_array().unwrap().len(), ny);
    for key in ["fx", "fy", "valid", "status"] {
        let rows = v[key].as_array().unwrap_or_else(|| panic!("{key}"));
        assert_eq!(rows.len(), ny, "{key}");
        assert!(
            rows.iter().all(|r| r.as_array().unwrap().len() == nx),
            "{key}"
        );
    }
    assert_eq!(v["kind"], "force");
    assert_eq!(v["units"], "m/s^2");
    assert_eq!(v["settings"]["phases"], 4);
    assert_eq!(v["model"]["tilt"], true);
    assert_eq!(v["stats"]["valid"], nx * ny);
    // A LineSink: f_x changes sign across x = 0.
    let row = v["fx"][1].as_array().unwrap();
    assert!(row[0].as_f64().unwrap() > 0.0 && row[nx - 1].as_f64().unwrap() < 0.0);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), stdout);
    let plot = std::fs::read_to_string(&svg).unwrap();
    assert!(plot.contains("<svg") && plot.trim_end().ends_with("</svg>"));

    let (code, stdout, stderr) = platefield(&["field", scene, "--quiet"]);
    assert_eq!(code, 0, "{stderr}");
    // A LineSink moves the points of each line along its axis (y) alike:
    // one point per column is simulated.
    for s in [
        "5×3",
        "simulated 5 of 15",
        "force",
        "model full",
        "15 of 15",
        "max |f|",
        "time",
    ] {
        assert!(
            stdout.contains(s),
            "summary {stdout:?} should contain {s:?}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
