//! The automatic model rung of a schedule's segments
//! (`Schedule::rungs`, `study rungs-auto`): the rule's outcomes on shipped
//! schedules, and `results/rungs_auto.md` regenerated from them (about
//! 1 s of CPU).

use std::path::Path;

use platefield::field::rung::{DEFAULT_RUNG_TOLERANCE, RUNGS};
use platefield::schedule::Schedule;
use platefield_studies::rungs_auto;

fn shipped(name: &str) -> Schedule {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../results")
        .join(name)
        .join("schedule.json");
    Schedule::load(&path).expect("a shipped schedule")
}

/// sink_trans's Trans segment is a pure in-plane translation: N = g and
/// Ω = 0, so every rung's field equals full's to the last bit and `paper`
/// is its rung with error exactly 0; its synthesized segment rotates the
/// plate out of plane and needs more, so the schedule is not played at
/// `paper`, and every segment's error at the rung played is within the
/// tolerance.
#[test]
fn a_translation_segment_takes_paper_exactly_and_the_play_takes_what_every_segment_needs() {
    let s = shipped("sink_trans");
    let r = rungs_auto::schedule_rungs(&s, DEFAULT_RUNG_TOLERANCE);
    let trans = r
        .segments
        .iter()
        .find(|g| g.label.starts_with("Trans"))
        .expect("a Trans segment");
    assert_eq!(trans.report.rung, "paper", "{trans:?}");
    assert_eq!(trans.report.error, 0.0);
    assert!(trans.report.rungs.iter().all(|x| x.error == 0.0));
    assert_ne!(r.rung, "paper", "{r:?}");
    let played = RUNGS.iter().position(|x| x.0 == r.rung).unwrap();
    for g in &r.segments {
        assert!(g.report.rungs[played].acceptable, "{g:?}");
        assert!(g.played_error <= DEFAULT_RUNG_TOLERANCE, "{g:?}");
    }
}

/// A LineSink segment tilts the plate: `paper` misses full by about 8 %
/// (`results/primitives/rungs.md`), so it is never chosen, and the rung
/// chosen is within the tolerance.
#[test]
fn an_out_of_plane_line_sink_segment_does_not_take_paper() {
    let r = rungs_auto::schedule_rungs(&shipped("ellipse"), DEFAULT_RUNG_TOLERANCE);
    assert!(!r.segments.is_empty());
    for g in &r.segments {
        assert!(g.label.starts_with("LineSink"), "{}", g.label);
        assert_ne!(g.report.rung, "paper", "{g:?}");
        assert!(g.report.rungs[0].error > 0.05, "{g:?}");
        assert!(g.report.error <= DEFAULT_RUNG_TOLERANCE, "{g:?}");
    }
    assert_ne!(r.rung, "paper");
}

/// `results/rungs_auto.md` is what `study rungs-auto` writes today.
#[test]
fn rungs_auto_md_is_current() {
    let results = Path::new(env!("CARGO_MANIFEST_DIR")).join("../results");
    let out = std::env::temp_dir().join(format!("platefield-rungs-auto-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    rungs_auto::run(&results, &out, DEFAULT_RUNG_TOLERANCE).unwrap();
    let fresh = std::fs::read_to_string(out.join("rungs_auto.md")).unwrap();
    let committed = std::fs::read_to_string(results.join("rungs_auto.md")).unwrap();
    std::fs::remove_dir_all(&out).ok();
    assert!(
        fresh == committed,
        "results/rungs_auto.md is stale: regenerate with `platefield study rungs-auto`"
    );
}
