//! Property test (issues 10 and 13): valid scene, target and schedule files, mutated
//! (deleted keys, misspelt keys, wrong types, NaN, ±1e308, negatives, empty
//! arrays, huge counts), go through the library's load-and-validate path
//! without a panic, and every error names a JSON path under `scene` or
//! `target`, with short numbers.

use std::path::Path;

use proptest::prelude::*;
use serde_json::Value;

use crate::play::ScheduleMotion;
use crate::progress::ProgressMode;
use crate::request::{examples, Target};
use crate::scene::Scene;
use crate::schedule::Schedule;
use crate::Error;

/// The shipped scenes and the target examples, as JSON values.
fn bases() -> (Vec<Value>, Vec<Value>) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("targets/scenes");
    let mut scenes: Vec<Value> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            serde_json::from_str(&std::fs::read_to_string(e.unwrap().path()).unwrap()).unwrap()
        })
        .collect();
    scenes.push(serde_json::json!({
        "motion": {"type": "primitive", "kind": "SkewSink", "depth": 0.04, "shift": [0.01, 0]},
        "kind": "velocity", "friction": {"kinetic": 0.25},
        "model": {"centripetal": false, "tilt": true, "coriolis": false, "moving": true},
        "numerics": {"steps_per_cycle": 32, "max_iterations": 50},
        "grid": {"x": [0, 0], "y": [0, 0], "n": [1, 1]}
    }));
    let mut targets: Vec<Value> = examples()
        .into_iter()
        .map(|(_, text)| serde_json::from_str(&text).unwrap())
        .collect();
    targets.push(serde_json::json!({
        "name": "sum", "grid": {"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [5, 5]},
        "field": {"kind": "sum", "terms": [{"weight": 0.5, "field": {"kind": "line_sink", "angle": 30}},
                                           {"field": {"kind": "jet", "width": 0.004}}]},
        "weights": [[1, 1, 1, 1, 1], [1, 1, 1, 1, 1], [1, 1, 1, 1, 1], [1, 1, 1, 1, 1], [1, 1, 1, 1, 1]],
        "mask": [{"rect": {"x": [0, 0.01], "y": [0, 0.01]}}]
    }));
    (scenes, targets)
}

/// Every location in `v`: a path of object keys and array indices.
#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

fn locations(v: &Value, here: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    out.push(here.clone());
    match v {
        Value::Object(map) => {
            for (k, child) in map {
                here.push(Step::Key(k.clone()));
                locations(child, here, out);
                here.pop();
            }
        }
        Value::Array(items) => {
            for (i, child) in items.iter().enumerate() {
                here.push(Step::Index(i));
                locations(child, here, out);
                here.pop();
            }
        }
        _ => {}
    }
}

fn at<'a>(v: &'a mut Value, path: &[Step]) -> &'a mut Value {
    path.iter().fold(v, |v, step| match step {
        Step::Key(k) => &mut v[k.as_str()],
        Step::Index(i) => &mut v[*i],
    })
}

/// Placeholder strings replaced in the text by tokens JSON cannot hold.
const NAN: &str = "\"@NaN@\"";
const INF: &str = "\"@-Infinity@\"";

/// Applies mutation `kind` at location `which` of `v`; returns the text.
fn mutate(v: Value, which: usize, kind: u8) -> String {
    mutate_under(v, which, kind, &[])
}

/// [`mutate`] at a location under one of the top-level keys `under` (any
/// location when `under` is empty).
fn mutate_under(mut v: Value, which: usize, kind: u8, under: &[&str]) -> String {
    let mut all = Vec::new();
    locations(&v, &mut Vec::new(), &mut all);
    if !under.is_empty() {
        all.retain(|p| matches!(p.first(), Some(Step::Key(k)) if under.contains(&k.as_str())));
    }
    let path = all[which % all.len()].clone();
    let (parent, last) = match path.split_last() {
        Some((last, parent)) => (parent.to_vec(), Some(last.clone())),
        None => (Vec::new(), None),
    };
    let target = at(&mut v, &path);
    let number = target.as_f64();
    match kind % 12 {
        0 | 1 => {
            // Delete a key, or misspell it.
            if let (Some(Step::Key(k)), Value::Object(map)) = (last, at(&mut v, &parent)) {
                if let Some(child) = map.remove(&k) {
                    if kind % 12 == 1 {
                        map.insert(format!("{k}x"), child);
                    }
                }
            }
        }
        2 => *target = Value::from("wrong"),
        3 => *target = Value::from(true),
        4 => *target = Value::from(NAN.trim_matches('"')),
        5 => *target = Value::from(INF.trim_matches('"')),
        6 => *target = serde_json::json!(1e308),
        7 => *target = serde_json::json!(-1e308),
        8 => *target = serde_json::json!(-number.unwrap_or(1.0).abs() - 1.0),
        9 => *target = serde_json::json!([]),
        10 => *target = serde_json::json!(4_294_967_296_u64),
        _ => *target = serde_json::json!({}),
    }
    v.to_string().replace(NAN, "NaN").replace(INF, "-Infinity")
}

/// The shipped schedules (`results/*/schedule.json`), as JSON values.
fn schedules() -> Vec<Value> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("results");
    let mut out: Vec<Value> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| {
            let file = e.unwrap().path().join("schedule.json");
            let text = std::fs::read_to_string(file).ok()?;
            Some(serde_json::from_str(&text).unwrap())
        })
        .collect();
    assert!(out.len() >= 5, "the shipped schedules");
    // A rest segment, so that rest durations are mutated too.
    let mut with_rest = out[0].clone();
    with_rest["segments"].as_array_mut().unwrap().push(
        serde_json::json!({"label": "Rest", "primitive": null, "weight": 0.0,
            "cycles": 0, "duration_s": 0.05}),
    );
    out.push(with_rest);
    out
}

/// The top-level keys of a schedule whose values are played or checked
/// (half of the mutations go there; the rest anywhere, mostly the basis).
const SCHEDULE_KEYS: [&str; 4] = ["segments", "settings", "target_spec", "total_cycles"];

/// An error message with a number of more than 20 digits.
fn has_long_number(s: &str) -> bool {
    s.split(|c: char| !c.is_ascii_digit())
        .any(|run| run.len() > 20)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenes_load_or_name_a_path(base in 0usize..16, which in 0usize..10_000, kind in 0u8..12) {
        let (scenes, _) = bases();
        let text = mutate(scenes[base % scenes.len()].clone(), which, kind);
        match Scene::from_json_str(&text) {
            Ok(scene) => prop_assert!(scene.validate().is_ok()),
            Err(Error::Invalid { field, message }) => {
                prop_assert!(field.starts_with("scene"), "{field}: {message}\n{text}");
                prop_assert!(!has_long_number(&message), "{field}: {message}");
            }
            Err(other) => prop_assert!(false, "unlocated error {other}\n{text}"),
        }
    }

    /// Issue 13: mutated schedule files through the one loader
    /// ([`Schedule::from_json_str`]: serde with unknown keys rejected,
    /// validate, derive) and then the player every command builds
    /// ([`ScheduleMotion::from_schedule`]): never a panic; every error is
    /// located: the origin (file name) and then a JSON path, short numbers.
    #[test]
    fn mutated_schedules_load_or_name_a_path(base in 0usize..16, which in 0usize..10_000, kind in 0u8..12, focus in 0u8..2) {
        let all = schedules();
        let under: &[&str] = if focus == 1 { &SCHEDULE_KEYS } else { &[] };
        let text = mutate_under(all[base % all.len()].clone(), which, kind, under);
        let checked = Schedule::from_json_str(&text, "s.json")
            .and_then(|s| ScheduleMotion::from_schedule(&s).map(|_| s));
        match checked {
            Ok(s) => {
                prop_assert!(s.validate().is_ok());
                prop_assert!(s.period_s.is_finite() && s.period_s > 0.0, "period {}", s.period_s);
            }
            Err(Error::Invalid { field, message }) => {
                // The loader prefixes the origin; the player names "schedule.…".
                let path = field
                    .strip_prefix("s.json: ")
                    .or_else(|| field.strip_prefix("schedule."))
                    .unwrap_or("");
                let located = ["segments", "settings", "target", "fit", "basis", "solver",
                    "schedule", "total_cycles", "period_s", "min_cycles", "quantization_error",
                    "poor_fit"].iter().any(|k| path.starts_with(k));
                prop_assert!(located, "unlocated: {field}: {message}\n{text}");
                prop_assert!(!has_long_number(&message), "{field}: {message}");
            }
            Err(other) => prop_assert!(false, "unlocated error {other}\n{text}"),
        }
    }

    #[test]
    fn mutated_targets_load_or_name_a_path(base in 0usize..16, which in 0usize..10_000, kind in 0u8..12) {
        let (_, targets) = bases();
        let text = mutate(targets[base % targets.len()].clone(), which, kind);
        let checked = Target::from_json_str(&text).and_then(|t| t.sample().map(|_| ()));
        if let Err(e) = checked {
            let message = e.to_string();
            let path = e.field_path();
            prop_assert!(path.is_some_and(|p| p.starts_with("target")), "{message}\n{text}");
            prop_assert!(!has_long_number(&message), "{message}");
        }
    }
}

/// The Trans signals (harmonics 1 and 2 along x) plus a y term of
/// 20 m/s² at `harmonic`, a velocity field at two points, at `steps`
/// steps per cycle.
fn harmonic_scene(harmonic: u32, steps: usize) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("targets/scenes/trans_signals.json");
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v["motion"]["linear"]["y"] =
        serde_json::json!([{"amplitude": 20, "phase": 0.3, "harmonic": harmonic}]);
    v["kind"] = serde_json::json!("velocity");
    v["grid"] = serde_json::json!({"x": [-0.01, 0.01], "y": [0, 0], "n": [2, 1]});
    v["numerics"] = serde_json::json!({ "steps_per_cycle": steps });
    v.to_string()
}

/// A field's largest vector difference from `reference`, relative to the
/// reference's largest vector.
fn relative_error(field: &[[f64; 2]], reference: &[[f64; 2]]) -> f64 {
    let norm = |v: [f64; 2]| v[0].hypot(v[1]);
    let scale = reference.iter().map(|v| norm(*v)).fold(0.0, f64::max);
    let diff = field
        .iter()
        .zip(reference)
        .map(|(a, b)| norm([a[0] - b[0], a[1] - b[1]]))
        .fold(0.0, f64::max);
    diff / scale
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, failure_persistence: None, ..ProptestConfig::default() })]

    /// Harmonics against steps (issue 30): a scene is refused, naming the
    /// harmonic's or the steps' path, or its field is within 3 % of the
    /// 4096-step field (8 steps per harmonic period measured at most 1.7 %;
    /// `STEPS_PER_HARMONIC` in `src/dynamics/mod.rs`). Before, harmonic
    /// 100 at 64 steps passed, 28 % off.
    #[test]
    fn harmonics_against_steps(harmonic in 1u32..=600, steps in 1usize..=5000) {
        let scene = Scene::from_json_str(&harmonic_scene(harmonic, steps));
        match scene {
            Err(e) => {
                let e = e.to_string();
                prop_assert!(
                    e.starts_with("scene.motion.linear.y[0].harmonic: ")
                        || e.starts_with("scene.numerics.steps_per_cycle: "),
                    "{}", e
                );
                let resolvable = (8..=4096).contains(&steps) && harmonic as usize * 8 <= steps;
                prop_assert!(!resolvable, "refused a resolvable scene: {}", e);
            }
            Ok(scene) => {
                prop_assert!(harmonic as usize * 8 <= steps && steps >= 16);
                let field = scene.compute(ProgressMode::Quiet).unwrap();
                let reference = Scene::from_json_str(&harmonic_scene(harmonic, 4096))
                    .unwrap()
                    .compute(ProgressMode::Quiet)
                    .unwrap();
                let error = relative_error(&field.vectors, &reference.vectors);
                prop_assert!(error < 0.03, "harmonic {} at {} steps: {:.3e}", harmonic, steps, error);
            }
        }
    }
}

/// The bounds themselves: harmonic 100 at 64 steps (the case) is
/// refused with the 800 steps it needs; steps 1, 2 and 7 are refused; at
/// 8 steps the Trans x term's harmonic 2 is refused (it needs 16), at 16
/// accepted.
#[test]
fn harmonic_and_step_bounds() {
    let steps_range = "scene.numerics.steps_per_cycle: must be in 8..=4096";
    for (harmonic, steps, expected) in [
        (
            100,
            64,
            "scene.motion.linear.y[0].harmonic: harmonic 100 needs at least 800 steps per cycle",
        ),
        (1, 1, steps_range),
        (1, 2, steps_range),
        (1, 7, steps_range),
        (
            1,
            8,
            "scene.motion.linear.x[1].harmonic: harmonic 2 needs at least 16",
        ),
    ] {
        let e = Scene::from_json_str(&harmonic_scene(harmonic, steps))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(expected), "{harmonic} at {steps}: {e}");
    }
    assert!(Scene::from_json_str(&harmonic_scene(2, 16)).is_ok());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, failure_persistence: None, ..ProptestConfig::default() })]

    /// Sampled targets of 1–5000 points (issue 30's numerical edges):
    /// pseudo-random points within ±`half` (up to 0.9 m) with vectors −p
    /// (an exact sink), at 5 decimals so that repeats happen at the
    /// largest counts. Each target is refused naming a
    /// `target.field.points[i]` path, or it loads with every sample kept,
    /// its field reproduces each sample's vector at the sample (the
    /// interpolation's own reference, exact to 1e-15), and the grid its
    /// basis is resampled on — which `verify` also plays over — covers
    /// every point within at most `SCATTERED_N` nodes per side.
    #[test]
    fn sampled_targets_of_any_count_load_or_name_a_point(
        count in 1usize..=5000,
        seed in 0u64..1000,
        half in prop::sample::select(vec![0.001, 0.04, 0.9]),
    ) {
        let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let mut uniform = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let points: Vec<[f64; 2]> = (0..count)
            .map(|_| {
                let c = |u: f64| ((2.0 * u - 1.0) * half * 1e5).round() / 1e5;
                [c(uniform()), c(uniform())]
            })
            .collect();
        let vectors: Vec<[f64; 2]> = points.iter().map(|p| [-p[0], -p[1]]).collect();
        let json = serde_json::json!({
            "name": "many",
            "field": {"kind": "sampled", "points": points, "vectors": vectors},
        })
        .to_string();
        match Target::from_json_str(&json).and_then(|t| t.sample().map(|s| (t, s))) {
            Err(e) if count < crate::request::MIN_WEIGHTED_POINTS => {
                let e = e.to_string();
                prop_assert!(e.starts_with("target.field.points: leaves"), "{}", e);
            }
            Err(e) => {
                let e = e.to_string();
                prop_assert!(e.starts_with("target.field.points["), "{}", e);
                prop_assert!(e.contains("repeats"), "{}", e);
            }
            Ok((t, s)) => {
                prop_assert_eq!(s.points.len(), count);
                for (p, v) in points.iter().zip(&vectors).step_by(7) {
                    let f = t.field.eval(*p);
                    prop_assert!((f[0] - v[0]).abs() <= 1e-15 && (f[1] - v[1]).abs() <= 1e-15);
                }
                let g = crate::request::scattered_grid(&s.points);
                prop_assert!(g.n[0] <= crate::request::SCATTERED_N && g.n[1] <= crate::request::SCATTERED_N);
                for p in &s.points {
                    prop_assert!(g.x[0] <= p[0] && p[0] <= g.x[1] && g.y[0] <= p[1] && p[1] <= g.y[1], "{:?} outside {:?}", p, g);
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]

    /// Weights and masks that leave 0, 1, 2 or 3 of a 5 × 5 grid's points
    /// (issue 30: a target masked to one point reported a realised strength
    /// of 1.95 against 0.47; one whose weights left one point marked a 2 %
    /// fit POOR). Fewer than three are refused naming `target.weights` or
    /// `target.mask` and the count; three load with exactly those three
    /// weighted.
    #[test]
    fn weights_and_masks_leaving_few_points_name_the_path(
        kept in 0usize..=3,
        seed in 0u64..1000,
        by_mask in any::<bool>(),
    ) {
        // `kept` distinct grid indices, chosen from the seed.
        let mut order: Vec<usize> = (0..25).collect();
        let mut state = seed.wrapping_add(1);
        for i in (1..25).rev() {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            order.swap(i, (state >> 33) as usize % (i + 1));
        }
        let keep = &order[..kept];
        let node = |k: usize| [-0.02 + 0.01 * (k % 5) as f64, -0.02 + 0.01 * (k / 5) as f64];
        let mut t = serde_json::json!({
            "name": "few",
            "grid": {"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [5, 5]},
            "field": {"kind": "sink"},
        });
        if by_mask {
            // Every node not kept masked by a small rectangle around it.
            let masks: Vec<Value> = (0..25)
                .filter(|k| !keep.contains(k))
                .map(|k| {
                    let p = node(k);
                    serde_json::json!({"rect": {"x": [p[0] - 1e-3, p[0] + 1e-3], "y": [p[1] - 1e-3, p[1] + 1e-3]}})
                })
                .collect();
            t["mask"] = Value::Array(masks);
        } else {
            let w: Vec<Vec<f64>> = (0..5)
                .map(|j| (0..5).map(|i| if keep.contains(&(5 * j + i)) { 0.5 } else { 0.0 }).collect())
                .collect();
            t["weights"] = serde_json::json!(w);
        }
        let path = if by_mask { "target.mask" } else { "target.weights" };
        match Target::from_json_str(&t.to_string()).and_then(|t| t.sample()) {
            Ok(s) => {
                prop_assert_eq!(kept, 3);
                prop_assert_eq!(s.weights.iter().filter(|&&w| w > 0.0).count(), 3);
            }
            Err(e) => {
                let e = e.to_string();
                prop_assert!(kept < 3, "{}", e);
                if kept == 0 {
                    prop_assert!(e.contains("have weight 0"), "{}", e);
                } else {
                    let want = format!("{path}: leaves {kept} of 25 sample points");
                    prop_assert!(e.starts_with(&want), "{} should start with {}", e, want);
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    /// Sizes of input files (issue 30): every input is read through
    /// `crate::input::read_capped`. For a file of any size against
    /// any cap, the bytes come back whole exactly when the size is within
    /// the cap; else the read is refused with `InvalidInput` stating the
    /// cap, never truncated (the file's bytes differ at every position, so
    /// a short read would show).
    #[test]
    fn files_of_any_size_are_read_whole_or_refused(size in 0usize..=6000, cap in 0u64..=3000) {
        let dir = std::env::temp_dir().join(format!("pf_sizes_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(format!("in_{size}_{cap}"));
        let bytes: Vec<u8> = (0..size).map(|i| (i % 251) as u8).collect();
        std::fs::write(&path, &bytes).unwrap();
        let read = crate::input::read_capped(&path, cap);
        std::fs::remove_file(&path).ok();
        match read {
            Ok(got) => {
                prop_assert!(size as u64 <= cap, "{} bytes read past a cap of {}", size, cap);
                prop_assert_eq!(got, bytes);
            }
            Err(e) => {
                prop_assert!(size as u64 > cap, "{} bytes within the cap {} refused: {}", size, cap, e);
                prop_assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
                prop_assert!(e.to_string().contains("larger than the cap"), "{}", e);
            }
        }
    }
}

/// The real cap on targets, scenes and schedules
/// ([`crate::input::MAX_INPUT_BYTES`], 64 MiB): a file one byte over
/// it (sparse, so the test writes nothing) is refused naming the file and
/// the cap, for each loader; a file at the cap is read and fails as the
/// JSON it is not, naming the file.
#[test]
fn inputs_one_byte_over_the_cap_are_refused_by_every_loader() {
    let cap = crate::input::MAX_INPUT_BYTES;
    let dir = std::env::temp_dir().join(format!("pf_cap_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("big.json");
    let load = |p: &Path| -> [String; 3] {
        [
            Target::load(p)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default(),
            Scene::load(p)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default(),
            Schedule::load(p)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default(),
        ]
    };
    let file = std::fs::File::create(&path).unwrap();
    file.set_len(cap + 1).unwrap();
    for e in load(&path) {
        assert!(
            e.contains(&path.display().to_string()) && e.contains("larger than the cap of 64 MiB"),
            "{e}"
        );
    }
    file.set_len(cap).unwrap();
    for e in load(&path) {
        assert!(
            e.contains(&path.display().to_string()) && !e.contains("larger than the cap"),
            "{e}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
