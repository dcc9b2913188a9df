//! Realised from the file (issues 26 and 27): a design's exported signals
//! played on its parts (`design::replay`, `verify --replay`) against the
//! schedule's own play, by the design's judge.
//!
//! **Tolerances.** The replayed plate follows the held samples: velocity
//! exact at every sample time, off by at most (ωΔt)²/8 inside one, and an
//! acceleration ripple of zero mean over each sample (`motion::Held`). So
//! what parts realise differs at second order in ωΔt: (ωΔt)² = 4.4e-4 for
//! the primitives' ω = 209 rad/s at the export's 10 kHz. The tests allow
//! the strength to differ by (ωΔt)² relatively and the shape error by
//! (ωΔt)²/4 (0.011 percentage points); measured 4.5e-5 and 4.5e-6 (sequenced
//! sink), 7.0e-5 and 5.2e-6 (synthesized sink), a fourth as much at twice
//! the rate — far inside the 1 % and 0.5 pp.

mod common;
use common::held_order;

use platefield::design::method::Method;
use platefield::design::replay::{exported, judge_replay, replay_check};
use platefield::design::DesignOptions;
use platefield::motion::sample_hold::HoldSamples;
use platefield::play::replay::{replay_motion, ReplayCheck};
use platefield::play::sensitivity::friction_sweep;
use platefield::request::Target;
use platefield::schedule::export::{export, DEFAULT_STEADY_CYCLES};
use platefield::schedule::Schedule;
use platefield::synth::SynthOptions;

fn load(path: &str) -> Schedule {
    Schedule::load(std::path::Path::new(path)).unwrap()
}

fn agrees(c: &ReplayCheck, strength: f64, shape: f64) -> bool {
    c.played.valid == c.replayed.valid && c.strength_gap() <= strength && c.shape_gap() <= shape
}

/// `file` with channel `axis` (0 = a_x … 5 = α_z) negated.
fn flipped(file: &HoldSamples, axis: usize) -> HoldSamples {
    let mut f = file.clone();
    for s in &mut f.samples {
        s[axis] = -s[axis];
    }
    f
}

/// The shipped sink (synthesized, exported with its ramps) and the
/// sequenced sink, exported at 10 kHz and read back from the CSV: the
/// replay realises the schedule's strength and shape within the
/// tolerances above. The same file with the y acceleration's sign flipped
/// does not (measured: 7.9 pp more shape error and 20 of 24 parts lost for
/// the sequenced sink, 93 % less strength for the synthesized one).
#[test]
fn shipped_sinks_replay_as_they_play_and_a_corrupted_export_does_not() {
    for path in [
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/synthesized/sink/schedule.json"
        ),
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/sequenced/sink/schedule.json"
        ),
    ] {
        let schedule = load(path);
        let order = held_order(&schedule, 10_000.0);
        let file = exported(&schedule).unwrap();
        let c = if path.ends_with("/sequenced/sink/schedule.json") {
            sequenced_sink_check().clone()
        } else {
            replay_check(&schedule, &file, "export", None).unwrap()
        };
        println!("{path}:\n{}", c.text());
        println!(
            "gaps: strength {:.3e}, shape {:.3e}; (ωΔt)² = {order:.3e}",
            c.strength_gap(),
            c.shape_gap()
        );
        assert_eq!(c.played.valid, c.played.points, "{path}");
        assert!(agrees(&c, order, order / 4.0), "{path}");
        let bad = replayed_instead(&schedule, &flipped(&file, 1), &c);
        println!("flipped a_y:\n{}", bad.text());
        assert!(
            !agrees(&bad, 0.01, 0.005),
            "{path}: a flipped channel agrees"
        );
    }
}

/// `check` with `file` replayed in place of its file: the schedule's own
/// play, the same in both, is reused (what [`replay_check`] does but
/// playing the schedule once).
fn replayed_instead(schedule: &Schedule, file: &HoldSamples, check: &ReplayCheck) -> ReplayCheck {
    let target = schedule.target_spec.as_ref().unwrap();
    let sampled = target.sample().unwrap();
    let sm = replay_motion(schedule, file, "flipped").unwrap();
    let settings = &schedule.settings;
    let rows = friction_sweep(settings, &[settings.friction], &|s| {
        Ok(judge_replay(target, &sampled, &sm, s))
    })
    .unwrap();
    ReplayCheck {
        file: "flipped".into(),
        played: check.played.clone(),
        replayed: rows[0].clone(),
    }
}

/// The sequenced sink's export (10 kHz, read back from its CSV text)
/// replayed against its schedule's play ([`replay_check`]), once for the
/// tests that read it.
fn sequenced_sink_check() -> &'static ReplayCheck {
    static CELL: std::sync::OnceLock<ReplayCheck> = std::sync::OnceLock::new();
    CELL.get_or_init(|| {
        let schedule = load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/sequenced/sink/schedule.json"
        ));
        replay_check(&schedule, &exported(&schedule).unwrap(), "export", None).unwrap()
    })
}

/// Second order in Δt: the sequenced sink's strength gap at 5 kHz is about
/// four times the gap at 10 kHz (measured 1.80e-4 and 4.50e-5, ratio 4.0;
/// a first-order error would give 2).
#[test]
fn the_replay_gap_falls_as_the_square_of_the_hold_time() {
    let schedule = load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/sequenced/sink/schedule.json"
    ));
    let gap = |rate: f64| {
        let csv = export(&schedule, rate, DEFAULT_STEADY_CYCLES)
            .unwrap()
            .to_csv();
        let file = platefield::motion::held_csv::parse(&csv, "export").unwrap();
        replay_check(&schedule, &file, "export", None)
            .unwrap()
            .strength_gap()
    };
    // At 10 kHz the file is `exported`'s (the export's own rate).
    let (coarse, fine) = (gap(5_000.0), sequenced_sink_check().strength_gap());
    println!("strength gap {coarse:.3e} at 5 kHz, {fine:.3e} at 10 kHz");
    assert!(
        (3.0..=5.5).contains(&(coarse / fine)),
        "{coarse:e} / {fine:e}"
    );
}

/// Another schedule's file is refused when its rows cannot be this
/// schedule's segments (naming the file), and read otherwise — then it
/// does not agree (the sequenced sink's export replayed as the
/// synthesized sink's: both 12040 rows at 10 kHz).
#[test]
fn another_schedules_export_does_not_pass() {
    let synthesized = load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    ));
    let sequenced = load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/sequenced/sink/schedule.json"
    ));
    let other = exported(&sequenced).unwrap();
    let c = replay_check(&synthesized, &other, "other.csv", None).unwrap();
    assert!(!agrees(&c, 0.01, 0.005), "{}", c.text());
    let mut short = other.clone();
    short.samples.truncate(12_000);
    let e = replay_motion(&sequenced, &short, "short.csv").unwrap_err();
    assert!(e.to_string().starts_with("short.csv:"), "{e}");
    assert!(e.to_string().contains("12000 rows"), "{e}");
}

/// `verify --replay` prints both numbers; a file with a bad row exits 2
/// naming the line and column, before anything is played.
#[test]
fn verify_replay_prints_both_and_refuses_a_bad_file() {
    let dir = std::env::temp_dir().join(format!("platefield-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let schedule = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/sequenced/sink/schedule.json"
    );
    let csv = dir.join("sink.csv");
    let (code, _, err) = common::platefield(&["export", schedule, "--out", csv.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let verify = |file: &std::path::Path| {
        common::platefield(&[
            "verify",
            schedule,
            "--replay",
            file.to_str().unwrap(),
            "--points",
            "2",
            "--swarm",
            "1",
            "--rect-poses",
            "0",
            "--quiet",
            "--out",
            dir.join("out").to_str().unwrap(),
        ])
    };
    let (code, out, err) = verify(&csv);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("schedule played: realised strength 0.29"),
        "{out}"
    );
    assert!(
        out.contains("export replayed: realised strength 0.29"),
        "{out}"
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let row = lines.iter().position(|l| l.starts_with("t_s")).unwrap() + 5;
    let mut fields: Vec<&str> = lines[row].split(',').collect();
    fields[2] = "NaN";
    lines[row] = fields.join(",");
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, lines.join("\n")).unwrap();
    let (code, _, err) = verify(&bad);
    assert_eq!(code, 2, "{err}");
    let needle = format!("bad.csv line {} column 3 (ay_m_s2)", row + 1);
    assert!(err.contains(&needle), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A 40-point sampled whirlpool without a grid, its vectors with 5 %
/// noise (deterministic), in ±3 cm.
fn sampled_whirlpool() -> Target {
    let whirl = |p: [f64; 2]| [-p[0] - p[1], -p[1] + p[0]];
    let mut seed: u64 = 27;
    let mut next = move || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut points = Vec::new();
    let mut vectors = Vec::new();
    for _ in 0..40 {
        let p = [0.06 * next() - 0.03, 0.06 * next() - 0.03];
        let v = whirl(p);
        let n = 0.05 * v[0].hypot(v[1]);
        points.push(p);
        vectors.push([
            v[0] + n * (2.0 * next() - 1.0),
            v[1] + n * (2.0 * next() - 1.0),
        ]);
    }
    let json = serde_json::json!({
        "name": "sampled_whirlpool_40",
        "field": {"kind": "sampled", "points": points, "vectors": vectors},
    });
    Target::from_json_str(&json.to_string()).unwrap()
}

fn design_options() -> (DesignOptions, SynthOptions) {
    (
        DesignOptions {
            runtime: platefield::work::Runtime::QUIET,
            ..DesignOptions::default()
        },
        SynthOptions {
            progress: platefield::progress::ProgressMode::quiet_if(true),
            ..SynthOptions::default()
        },
    )
}

/// Issue 27: a 40-point grid-less sampled whirlpool with 5 % noise,
/// designed by `method` — its reported (played) numbers agree with a
/// replay of its export within a few percent (the sequenced
/// candidate was reported at 225290 % shape error while its export
/// replayed at 30–34 %). Measured: sequenced, reported and replayed
/// strength 0.1291 at 70.51 % shape error (a sequence of primitives
/// cannot make this whirlpool; the numbers agree); `auto`, reported 0.6089
/// at 4.70 %, replayed 0.6088 at 4.70 %.
fn sampled_target_reports_what_its_export_replays(method: Method) {
    let target = sampled_whirlpool();
    let (opts, synth) = design_options();
    let md = platefield::inverse::run(&target, &opts.by_method(method, &synth))
        .and_then(|o| o.into_method())
        .unwrap();
    let kept = &md.kept().schedule;
    let played = md.kept().played();
    let c = replay_check(kept, &exported(kept).unwrap(), "export", None).unwrap();
    println!(
        "{method:?}: reported strength {:?}, shape {:?}\n{}",
        played.realised_strength,
        played.realised_shape_error,
        c.text()
    );
    assert_eq!(c.played.realised_strength, played.realised_strength);
    assert!(
        c.strength_gap() <= 0.03 && c.shape_gap() <= 0.01,
        "{}",
        c.text()
    );
}

/// By `sequence` (about 8 s of CPU: `cargo test --release -p
/// platefield-cli --test replay -- --ignored sequenced`; the default run
/// replays the shipped sinks' exports against their plays).
#[test]
#[ignore = "about 8 s of CPU: cargo test --release -p platefield-cli --test replay -- --ignored sequenced"]
fn sampled_whirlpool_sequenced_reports_what_its_export_replays() {
    sampled_target_reports_what_its_export_replays(Method::Sequence);
}

/// The same for `design`'s default (`auto`: synthesis and played polish).
/// Long: `cargo test --release --test replay -- --ignored --nocapture`
/// (28 s wall at load 9 on 2 cores).
#[test]
#[ignore = "designs by auto (synthesis and played polish): about half a minute"]
fn sampled_whirlpool_auto_reports_what_its_export_replays() {
    sampled_target_reports_what_its_export_replays(Method::Auto);
}
