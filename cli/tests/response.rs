//! `export --response`: the drive through a measured shaker response plays
//! the design, and an ill-conditioned response is refused.

mod common;

use common::platefield;
use std::collections::BTreeMap;

type C = (f64, f64);

fn cmul(a: C, b: C) -> C {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

/// A seeded xorshift generator of uniform numbers in [−0.5, 0.5).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// Per harmonic the six phasors A e^{iφ} of a `channel,harmonic,amplitude,
/// phase_rad` CSV (comment lines skipped), channels in order of first
/// appearance of `names`.
fn phasors(csv: &str, names: &[&str]) -> BTreeMap<u64, [C; 6]> {
    let mut out: BTreeMap<u64, [C; 6]> = BTreeMap::new();
    for line in csv.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let ch = names.iter().position(|n| *n == f[0]).unwrap();
        let (n, a, p): (u64, f64, f64) = (
            f[1].parse().unwrap(),
            f[2].parse().unwrap(),
            f[3].parse().unwrap(),
        );
        let e = &mut out.entry(n).or_insert([(0.0, 0.0); 6])[ch];
        e.0 += a * p.cos();
        e.1 += a * p.sin();
    }
    out
}

const PLATE: [&str; 6] = [
    "ax_m_s2",
    "ay_m_s2",
    "az_m_s2",
    "alpha_x_rad_s2",
    "alpha_y_rad_s2",
    "alpha_z_rad_s2",
];
const DRIVE: [&str; 6] = [
    "drive_1", "drive_2", "drive_3", "drive_4", "drive_5", "drive_6",
];

/// The response file of `matrices` by harmonic.
fn response_json(matrices: &BTreeMap<u64, [[C; 6]; 6]>) -> String {
    let entries: Vec<serde_json::Value> = matrices
        .iter()
        .map(|(n, m)| {
            let rows: Vec<Vec<[f64; 2]>> = m
                .iter()
                .map(|r| r.iter().map(|c| [c.0, c.1]).collect())
                .collect();
            serde_json::json!({"harmonic": n, "matrix": rows})
        })
        .collect();
    serde_json::json!({ "harmonics": entries }).to_string()
}

/// The synthesized sink's drive through a random, well-conditioned 6 × 6
/// response per harmonic (5·I plus entries uniform in ±0.5 + ±0.5i, so
/// diagonally dominant), seeded: the response applied to the written drive
/// gives back the design's accelerations (`--format harmonics`, every
/// harmonic and channel) within 1e-9 of the largest.
#[test]
fn a_random_response_applied_to_the_drive_plays_the_design() {
    let dir = std::env::temp_dir().join(format!("platefield-response-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let schedule = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    );
    let (code, design, err) = platefield(&["export", schedule, "--format", "harmonics"]);
    assert_eq!(code, 0, "{err}");
    let want = phasors(&design, &PLATE);
    let mut rng = Rng(0x5eed_1234_abcd_0042);
    let matrices: BTreeMap<u64, [[C; 6]; 6]> = want
        .keys()
        .map(|n| {
            let m = std::array::from_fn(|r| {
                std::array::from_fn(|c| {
                    let d = if r == c { 5.0 } else { 0.0 };
                    (d + rng.next(), rng.next())
                })
            });
            (*n, m)
        })
        .collect();
    let file = dir.join("response.json");
    std::fs::write(&file, response_json(&matrices)).unwrap();
    let (code, drive, err) =
        platefield(&["export", schedule, "--response", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        drive.contains("condition number per harmonic"),
        "{drive:.400}"
    );
    let got = phasors(&drive, &DRIVE);
    let largest = want
        .values()
        .flatten()
        .fold(0.0_f64, |m, c| m.max(c.0.hypot(c.1)));
    let mut worst = 0.0_f64;
    for (n, a) in &want {
        let d = got.get(n).copied().unwrap_or([(0.0, 0.0); 6]);
        for (r, want) in a.iter().enumerate() {
            let played = (0..6).fold((0.0, 0.0), |s: C, c| {
                let p = cmul(matrices[n][r][c], d[c]);
                (s.0 + p.0, s.1 + p.1)
            });
            worst = worst.max((played.0 - want.0).hypot(played.1 - want.1) / largest);
        }
    }
    println!(
        "{} harmonics; worst {worst:.2e} of the largest phasor",
        want.len()
    );
    assert!(worst < 1e-9, "{worst:e}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A response with one nearly dependent pair of columns at harmonic 1
/// (condition number about 1e7) is refused with exit 2, naming the
/// harmonic and its condition number, and nothing is written; a response
/// without a harmonic the design holds is refused naming it; a malformed
/// one names its JSON path.
#[test]
fn an_ill_conditioned_or_incomplete_response_is_refused() {
    let dir = std::env::temp_dir().join(format!("platefield-response-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let schedule = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    );
    let (_, design, _) = platefield(&["export", schedule, "--format", "harmonics"]);
    let harmonics: Vec<u64> = phasors(&design, &PLATE).keys().copied().collect();
    let identity = |n: u64| -> (u64, [[C; 6]; 6]) {
        (
            n,
            std::array::from_fn(|r| std::array::from_fn(|c| (if r == c { 1.0 } else { 0.0 }, 0.0))),
        )
    };
    let mut matrices: BTreeMap<u64, [[C; 6]; 6]> = harmonics.iter().map(|n| identity(*n)).collect();
    let m = matrices.get_mut(&1).unwrap();
    m[0][1] = (1.0, 0.0);
    m[1][0] = (1.0, 0.0);
    m[1][1] = (1.0 + 1e-7, 0.0);
    let file = dir.join("response.json");
    let out = dir.join("drive.csv");
    std::fs::write(&file, response_json(&matrices)).unwrap();
    let args = [
        "export",
        schedule,
        "--response",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    let (code, _, err) = platefield(&args);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--response")
            && err.contains("harmonic 1")
            && err.contains("condition number is 4.0"),
        "{err}"
    );
    assert!(!out.exists());
    // A harmonic missing.
    let last = *harmonics.last().unwrap();
    let fewer: BTreeMap<u64, [[C; 6]; 6]> = harmonics
        .iter()
        .filter(|n| **n != last)
        .map(|n| identity(*n))
        .collect();
    std::fs::write(&file, response_json(&fewer)).unwrap();
    let (code, _, err) = platefield(&args);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(&format!("no harmonic {last}")), "{err}");
    // A diagonal of five.
    std::fs::write(
        &file,
        r#"{"harmonics": [{"harmonic": 1, "diagonal": [[1, 0], [1, 0], [1, 0], [1, 0], [1, 0]]}]}"#,
    )
    .unwrap();
    let (code, _, err) = platefield(&args);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("harmonics[0].diagonal"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
