//! Helpers shared by the integration tests.

use std::process::Command;

/// Runs the `platefield` binary; returns (exit code, stdout, stderr).
pub fn platefield(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_platefield"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args(args)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The arguments of a fast design (0.1 s) of `target` into `out`.
#[allow(dead_code)] // not every test file that shares this module designs
pub fn design_args<'a>(target: &'a str, out: &'a str) -> Vec<&'a str> {
    let fast = "--method sequence --primitives LineSink --rotation-step 90 --no-cache --quiet";
    ["design", target]
        .into_iter()
        .chain(fast.split(' '))
        .chain(["--out", out])
        .collect()
}

/// (ωΔt)² for the primitives' period at `rate`: the relative order of
/// what a replay of an export held at `rate` differs by from the
/// schedule's own play (`tests/replay.rs`, "Tolerances").
#[allow(dead_code)] // not every test file that shares this module replays
pub fn held_order(schedule: &platefield::schedule::Schedule, rate: f64) -> f64 {
    let period = schedule.segments[0].cycle_period().unwrap();
    let w_dt = 2.0 * std::f64::consts::PI / period / rate;
    w_dt * w_dt
}
