//! `results/designs.md`, the committed designs' judge in one table, is
//! generated from their `schedule.json` files: this test fails when the
//! table and the files disagree, and
//! `PLATEFIELD_WRITE_DESIGNS=1 cargo test --release --test designs`
//! rewrites it.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use platefield::schedule::{Played, Schedule};

/// The designs `results/README.md` lists, in its order.
const DESIGNS: [&str; 10] = [
    "sink",
    "saddle",
    "squeeze_trans",
    "whirlpool",
    "jet",
    "line_sink",
    "line_sink_30",
    "sink_trans",
    "ellipse",
    "ellipse_30",
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn played(path: &Path) -> Option<Played> {
    Schedule::load(path).ok()?.played
}

fn cells(p: &Played) -> String {
    let n = |x: Option<f64>| x.map_or("n/a".into(), |v| format!("{v:.4}"));
    let pc = |x: Option<f64>| x.map_or("n/a".into(), |v| format!("{:.2} %", 100.0 * v));
    format!(
        "{} | {} | {} ({}){}",
        n(p.realised_strength),
        pc(p.realised_shape_error),
        p.points,
        p.valid,
        if p.poor { ", POOR" } else { "" }
    )
}

fn table() -> String {
    let mut md = String::from(
        "# The committed designs, judged\n\n\
         Generated from `results/<target>/schedule.json` and `results/sequenced/<target>/schedule.json` \
         by `tests/designs.rs` (`PLATEFIELD_WRITE_DESIGNS=1 cargo test --release --test designs`). \
         The judge (`docs/measures.md`): realised strength ŝ (× the target's strength) and realised \
         shape error of the realised field at the judge's points over the whole region. Each design's \
         `report.md` has every candidate.\n\n\
         | target | kept | realised strength | realised shape error | points (valid) | sequenced: realised strength | realised shape error | points (valid) |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    for t in DESIGNS {
        let kept = played(&root().join(format!("results/{t}/schedule.json")))
            .unwrap_or_else(|| panic!("results/{t}/schedule.json is judged"));
        let seq = played(&root().join(format!("results/sequenced/{t}/schedule.json")))
            .filter(|_| kept.method.name() != "sequence")
            .map_or("— | — | —".to_string(), |p| cells(&p));
        let _ = writeln!(
            md,
            "| {t} | {} | {} | {seq} |",
            kept.method.name(),
            cells(&kept)
        );
    }
    md
}

#[test]
fn the_designs_table_is_the_committed_designs() {
    let path = root().join("results/designs.md");
    let want = table();
    if std::env::var_os("PLATEFIELD_WRITE_DESIGNS").is_some() {
        std::fs::write(&path, &want).unwrap();
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert_eq!(
        have, want,
        "results/designs.md is stale: PLATEFIELD_WRITE_DESIGNS=1 cargo test --release --test designs"
    );
}
