//! `verify --replay MEASURED.csv`: an accelerometer recording (any rate,
//! noisy, a header-less CSV) replayed on the design's parts.

mod common;

use common::platefield;
use platefield::design::replay::{conform, replay_check};
use platefield::motion::held_csv::parse_recording;
use platefield::schedule::export::export;
use platefield::schedule::Schedule;

/// A seeded xorshift generator of standard normal numbers (Box–Muller).
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// The sink's export (10 kHz) as a 5 kHz accelerometer records it: each
/// row the mean of the held signal over its 0.2 ms (an anti-aliased
/// sample), plus white noise of 1 % of the channel's peak (seeded), six
/// columns, no header.
fn recorded_sink() -> String {
    let s = Schedule::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    )))
    .unwrap();
    let file = export(&s, 10_000.0, 20).unwrap().samples;
    let (dt, rate) = (file.dt, 5_000.0);
    let peaks = file.peaks();
    let span = dt * file.samples.len() as f64;
    // The held signal's integral at t.
    let mut nodes = vec![[0.0; 6]];
    for a in &file.samples {
        let l = nodes[nodes.len() - 1];
        nodes.push(std::array::from_fn(|i| l[i] + a[i] * dt));
    }
    let integral = |t: f64| -> [f64; 6] {
        let k = ((t / dt).floor() as usize).min(file.samples.len() - 1);
        std::array::from_fn(|i| nodes[k][i] + file.samples[k][i] * (t - k as f64 * dt))
    };
    let mut noise = Noise(0x0dd_ba11_5eed_cafe);
    let rows = (span * rate).floor() as usize;
    let mut out = String::new();
    for k in 0..rows {
        let (a, b) = (integral(k as f64 / rate), integral((k + 1) as f64 / rate));
        let row: Vec<String> = (0..6)
            .map(|i| {
                format!(
                    "{:.9e}",
                    (b[i] - a[i]) * rate + 0.01 * peaks[i] * noise.normal()
                )
            })
            .collect();
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}

/// The recording replays within 1 % of the strength the schedule plays
/// (`replay_check`: the design's judge, both at the schedule's
/// friction), through the library and through `verify --replay --rate`.
#[test]
fn a_noisy_5_khz_recording_replays_within_1_percent() {
    let s = Schedule::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    )))
    .unwrap();
    let text = recorded_sink();
    let recording = parse_recording(&text, "measured.csv", Some(5_000.0)).unwrap();
    let file = conform(&s, &recording, "measured.csv").unwrap();
    let check = replay_check(&s, &file, "measured.csv", None).unwrap();
    println!(
        "played {:?}, replayed {:?}: gap {:.3e}",
        check.played.realised_strength,
        check.replayed.realised_strength,
        check.strength_gap()
    );
    assert!(check.strength_gap() < 0.01, "{}", check.strength_gap());
    // The same file through `verify --replay --rate`.
    let dir = std::env::temp_dir().join(format!("platefield-recorded-ok-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("measured.csv");
    std::fs::write(&path, &text).unwrap();
    let (code, out, err) = platefield(&[
        "verify",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/synthesized/sink/schedule.json"
        ),
        "--replay",
        path.to_str().unwrap(),
        "--rate",
        "5000",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("export replayed"), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A recording that is too short, or whose rows are malformed, is refused
/// naming the file (and the line); a 6-column file without `--rate` names
/// `--rate`.
#[test]
fn a_bad_recording_names_the_file() {
    let s = Schedule::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    )))
    .unwrap();
    let short: String = (0..100).map(|_| "0,0,0,0,0,0\n").collect();
    let r = parse_recording(&short, "m.csv", Some(5_000.0)).unwrap();
    let e = conform(&s, &r, "m.csv").unwrap_err().to_string();
    assert!(
        e.contains("m.csv") && e.contains("not one whole cycle"),
        "{e}"
    );
    let e = parse_recording("0,0,0,0,0,0\n1,x,0,0,0,0\n", "m.csv", Some(10.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("m.csv line 2 column 2 (ay_m_s2)"), "{e}");
    let dir = std::env::temp_dir().join(format!("platefield-recorded-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("m.csv");
    std::fs::write(&path, &short).unwrap();
    let (code, _, err) = platefield(&[
        "verify",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../results/synthesized/sink/schedule.json"
        ),
        "--replay",
        path.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--rate"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
