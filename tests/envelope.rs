//! Every committed design is played within the shaker limits it is held to.
//!
//! For each `schedule.json` under `results/` (the shipped designs, the
//! sequenced ones, the sorts, the closed loops and the pose designs
//! `results/poses/<part>/`), the export as `platefield export` writes it
//! (10 kHz, the default steady cycles, ramps included) has its peaks of
//! acceleration, velocity and stroke, as played from rest at home, within
//! the limits the design recorded or, for a design that records none, its
//! target's (keys left out the default envelope): no "over the shaker
//! limit" line. An angular axis the limits forbid (0) may only carry the
//! exact rotation's second-order turn (`Export::undriven_turns`), at most
//! 1e-3 of the largest angular acceleration.

use std::path::{Path, PathBuf};

use platefield::schedule::export::{export, DEFAULT_STEADY_CYCLES};
use platefield::schedule::Schedule;
use platefield::synth::ShakerLimits;

/// Every `schedule.json` under `dir`, sorted.
fn schedules(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.file_name().is_some_and(|n| n == "schedule.json") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn every_committed_design_exports_within_its_limits() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("results");
    let files = schedules(&root);
    // 23 designs and the three pose designs.
    assert!(files.len() >= 26, "{} schedules: {files:?}", files.len());
    for path in [
        "poses/rectangle",
        "poses/bracket",
        "poses/triangle",
        "sort_three",
    ] {
        assert!(
            files.contains(&root.join(path).join("schedule.json")),
            "{path}"
        );
    }
    let mut failures = Vec::new();
    for path in &files {
        let s = Schedule::load(path).unwrap();
        let e = export(&s, 10_000.0, DEFAULT_STEADY_CYCLES)
            .unwrap()
            .held_to(ShakerLimits::stated(&s));
        assert!(e.limits.is_some(), "{}: no limits stated", path.display());
        for line in e.over_limits() {
            failures.push(format!("{}: {line}", path.display()));
        }
        let p = e.peaks().acceleration;
        let angular = p[3].max(p[4]).max(p[5]);
        let forbidden = e
            .limits
            .as_ref()
            .and_then(|l| l.angular)
            .unwrap_or([1.0; 3]);
        for k in (0..3).filter(|&k| forbidden[k] == 0.0) {
            assert!(
                p[3 + k] <= 1e-3 * angular,
                "{}: angular {k} at {} of {angular}",
                path.display(),
                p[3 + k]
            );
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
