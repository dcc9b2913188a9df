//! `export --format pose` and `--format cycle`: they loop exactly, state
//! their peaks, and say what the held-sample export says.

#[path = "../common/plate.rs"]
mod plate;

use crate::schedule::export::export;
use crate::schedule::export::pose::{cycle, poses};
use crate::schedule::Schedule;
use plate::{angle_between, mul, read_export, Plate, Quat};

fn schedule(name: &str) -> Schedule {
    Schedule::load(std::path::Path::new(&format!(
        "results/{name}/schedule.json"
    )))
    .unwrap()
}

/// The power of harmonics above `highest` in the discrete Fourier
/// transform of `x` (one period, if the points loop exactly), relative to
/// the whole.
fn leak(x: &[f64], highest: usize) -> f64 {
    let n = x.len();
    let power = |h: usize| {
        let (a, b) = x.iter().enumerate().fold((0.0, 0.0), |(a, b), (k, v)| {
            let (s, c) = (std::f64::consts::TAU * (h * k) as f64 / n as f64).sin_cos();
            (a + v * c, b + v * s)
        });
        a * a + b * b
    };
    let all: f64 = (0..=n / 2).map(power).sum();
    (highest + 1..=n / 2).map(power).sum::<f64>() / all
}

/// The quaternion of fixed-axis x-y-z angles: R = Rz(yaw)·Ry(pitch)·Rx(roll),
/// from the angle set the header states.
fn from_xyz(roll: f64, pitch: f64, yaw: f64) -> Quat {
    let about = |axis: usize, angle: f64| -> Quat {
        let (s, c) = (angle / 2.0).sin_cos();
        let mut q = [c, 0.0, 0.0, 0.0];
        q[1 + axis] = s;
        q
    };
    mul(&about(2, yaw), &mul(&about(1, pitch), &about(0, roll)))
}

/// One steady cycle of the synthesized sink (harmonics 1 and 2): the
/// table loops exactly (the linear channels, sums of harmonics 1–2, leak
/// nothing above harmonic 2 over the table: a missing or repeated point
/// would), the header states the angle set and the peaks, and each pose is
/// the orientation a plate playing the CSV export reaches at the same time
/// in its steady cycles.
#[test]
fn a_steady_pose_table_loops_and_is_what_the_export_plays() {
    let s = schedule("synthesized/sink");
    let p = poses(&s, 10_000.0).unwrap();
    assert!(p.steady);
    for axis in 0..2 {
        let x: Vec<f64> = p.points.iter().map(|r| r[axis]).collect();
        let l = leak(&x, 2);
        assert!(l < 1e-24, "axis {axis}: {l:e}");
    }
    let csv = p.to_csv();
    for needle in [
        "Rz(yaw)·Ry(pitch)·Rx(roll)",
        "pose peaks",
        "stroke",
        "loop it",
    ] {
        assert!(csv.contains(needle), "{needle}");
    }
    // The CSV export at the same rate: 10 cycles of ramp, then the steady
    // cycles, each of the table's length.
    let e = export(&s, 10_000.0, 20).unwrap();
    let (dt, rows) = read_export(&e.samples.to_csv());
    let n = p.points.len();
    assert_eq!(e.samples.samples_per_period, n);
    let mut plate = Plate::rest();
    let (mut angle, mut position) = (0.0_f64, 0.0_f64);
    for (k, a) in rows.iter().enumerate().take(15 * n) {
        if k >= 10 * n {
            let r = &p.points[k % n];
            angle = angle.max(angle_between(&plate.q, &from_xyz(r[3], r[4], r[5])));
            for (x, r) in plate.x.iter().zip(r) {
                position = position.max((x - r).abs());
            }
        }
        plate.hold(a, dt, 2);
    }
    println!("steady table against the played export: {angle:.2e} rad, {position:.2e} m");
    // Holding a linear acceleration a for Δt moves the plate off the exact
    // path by at most a Δt²/2.
    let peak = e.samples.peaks()[..3].iter().copied().fold(0.0, f64::max);
    assert!(
        angle < 1e-6 && position < 0.5 * peak * dt * dt,
        "{angle:e} rad, {position:e} m"
    );
}

/// One period of the sequenced sink: from home back to home (the point
/// after the last is home, so the table loops), each pose the one a plate
/// playing the CSV export at the same rate reaches.
#[test]
fn a_sequence_pose_table_runs_home_to_home() {
    let s = schedule("sequenced/sink");
    let p = poses(&s, 10_000.0).unwrap();
    assert!(!p.steady && p.points[0] == [0.0; 6]);
    let e = export(&s, 10_000.0, 20).unwrap();
    let (dt, rows) = read_export(&e.samples.to_csv());
    assert_eq!(rows.len(), p.points.len());
    let mut plate = Plate::rest();
    let (mut angle, mut position) = (0.0_f64, 0.0_f64);
    for (a, r) in rows.iter().zip(&p.points) {
        angle = angle.max(angle_between(&plate.q, &from_xyz(r[3], r[4], r[5])));
        for (x, r) in plate.x.iter().zip(r) {
            position = position.max((x - r).abs());
        }
        plate.hold(a, dt, 2);
    }
    let home = angle_between(&plate.q, &[1.0, 0.0, 0.0, 0.0]);
    println!("sequence table against the played export: {angle:.2e} rad, {position:.2e} m; home {home:.1e} rad");
    assert!(
        angle < 1e-6 && position < 1e-7,
        "{angle:e} rad, {position:e} m"
    );
    assert!(home < 1e-12 && plate.x.iter().all(|x| x.abs() < 1e-12));
}

/// One steady cycle of the sink's six accelerations at 64 points: every
/// channel's mean (its velocity change per cycle over T) is zero to
/// round-off, the linear channels leak nothing above harmonic 2 (the cycle
/// loops exactly), the points at 64 are every other point at 128, and the
/// header states the peaks and the means.
#[test]
fn a_cycle_loops_with_no_velocity_change() {
    let s = schedule("synthesized/sink");
    let c = cycle(&s, 64).unwrap();
    let means = c.means();
    for i in 0..6 {
        let peak = c.peaks.acceleration[3 * (i / 3)].max(c.peaks.acceleration[3 * (i / 3) + 1]);
        assert!(means[i].abs() < 1e-13 * peak, "{i}: {means:?}");
    }
    for axis in 0..2 {
        let x: Vec<f64> = c.points.iter().map(|r| r[axis]).collect();
        assert!(leak(&x, 2) < 1e-24, "{axis}");
    }
    let fine = cycle(&s, 128).unwrap();
    for (k, a) in c.points.iter().enumerate() {
        for (a, f) in a.iter().zip(&fine.points[2 * k]) {
            assert!((a - f).abs() < 1e-12 * (1.0 + a.abs()));
        }
    }
    let csv = c.to_csv();
    assert!(csv.contains("peaks per axis") && csv.contains("channel means"));
    // The sequenced sink is not one steady cycle.
    let e = cycle(&schedule("sequenced/sink"), 64)
        .unwrap_err()
        .to_string();
    assert!(e.contains("--format"), "{e}");
    let e = cycle(&s, 4).unwrap_err().to_string();
    assert!(e.contains("--points") && e.contains("5..="), "{e}");
}
