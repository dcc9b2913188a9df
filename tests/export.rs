//! `platefield export` as a controller plays it: every shipped design's
//! exported CSV, each sample held for its interval and the file looped, must
//! bring the plate back to rest in the home pose every period (issue 11:
//! point samples drifted 4.8e-3 rad per period at 20 kHz).

use platefield::schedule::{export::signals_csv, Schedule};

/// Integrates the six held signals of `csv` over `loops` loops of the file
/// (x ← x + vΔt + aΔt²/2, v ← v + aΔt; the small rotation vector like a
/// translation) and returns the largest |pose| and |velocity| at the end of
/// any loop.
fn drift(csv: &str, loops: usize) -> (f64, f64) {
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let dt = rows[1][0] - rows[0][0];
    let (mut x, mut v) = ([0.0_f64; 6], [0.0_f64; 6]);
    let (mut pose, mut vel) = (0.0_f64, 0.0_f64);
    for _ in 0..loops {
        for r in &rows {
            for i in 0..6 {
                let a = r[i + 1];
                x[i] += v[i] * dt + 0.5 * a * dt * dt;
                v[i] += a * dt;
            }
        }
        pose = x.iter().fold(pose, |m, p| m.max(p.abs()));
        vel = v.iter().fold(vel, |m, p| m.max(p.abs()));
    }
    (pose, vel)
}

#[test]
fn every_shipped_export_returns_to_rest_each_period() {
    for name in [
        "sink",
        "saddle",
        "squeeze_trans",
        "whirlpool",
        "line_sink",
        "jet",
    ] {
        let path = format!("results/{name}/schedule.json");
        let schedule = Schedule::load(std::path::Path::new(&path)).unwrap();
        let csv = signals_csv(&schedule, 20_000.0).unwrap();
        let (pose, vel) = drift(&csv, 15);
        assert!(
            pose < 1e-6 && vel < 1e-6,
            "{name}: after 15 periods pose {pose:.2e} (m, rad), velocity {vel:.2e} (m/s, rad/s)"
        );
    }
}
