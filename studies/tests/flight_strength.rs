//! Designs that may fly (`platefield study flight-strength`,
//! `results/flight_strength.md`): the flying judge against the product's
//! judge on a motion that keeps contact, and the study's finding.

use std::path::Path;

use platefield::request::Target;
use platefield::schedule::Schedule;
use platefield_studies::flight_strength::{
    judge_flying, study_target, MAX_FLIGHT, RATIO_ASKED, SHAKERS, SHAPE_LIMIT, TARGETS,
};

/// The shipped synthesized sink (`results/synthesized/sink`, contact
/// margin 0.1 g, judged 2.8512 s⁻¹ at 6.15 %) judged with the flight rung:
/// no part flies, and the realised strength and shape error are the
/// judge's within 0.2 % and 0.05 percentage points (the same frozen play
/// of each point, settled by another rule).
#[test]
fn the_flying_judge_is_the_judge_in_contact() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let schedule = Schedule::load(&root.join("results/synthesized/sink/schedule.json")).unwrap();
    let target = Target::load(&root.join("targets/sink.json")).unwrap();
    let played = schedule.played.as_ref().unwrap();
    let (s, e) = (
        played.realised_strength.unwrap(),
        played.realised_shape_error.unwrap(),
    );
    let motion = schedule.segments[0].plate_motion().unwrap();
    let j = judge_flying(&target, &motion, &schedule.settings).unwrap();
    println!(
        "flying judge {:.5} at {:.4} % (airborne ≤ {}), the judge {s:.5} at {:.4} %",
        j.strength,
        100.0 * j.shape_error,
        j.max_airborne,
        100.0 * e
    );
    assert_eq!((j.points, j.unsettled, j.flying_points), (120, 0, 0));
    assert!((j.strength / s - 1.0).abs() < 2e-3, "{} against {s}", j.strength);
    assert!((j.shape_error - e).abs() < 5e-4, "{} against {e}", j.shape_error);
}
