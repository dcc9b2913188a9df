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
    assert!(
        (j.strength / s - 1.0).abs() < 2e-3,
        "{} against {s}",
        j.strength
    );
    assert!(
        (j.shape_error - e).abs() < 5e-4,
        "{} against {e}",
        j.shape_error
    );
}

/// The study's finding (`results/flight_strength.md`; about 80 s of CPU,
/// run with `-- --ignored`), on both targets and both shakers:
///
/// * the flying judge of every unscaled contact synthesis is the product's
///   judge of it (strength within 0.2 %, shape error within 0.05
///   percentage points) where no part flies, which is everywhere but at
///   the corners of the margin-0 motions, which fly at up to 2 points
///   (the saddle's on the sequenced shaker 2.3 % of the cycle, on the
///   envelope 20 %; the sink's on the envelope at 2 corners not settled
///   in 80 periods): the margin is kept on the synthesis's own grids,
///   not at every instant of every judge point. At margins 0.1–0.3 g no
///   part flies;
/// * the baseline (strongest judged at ≤ 5 %) is a contact synthesis at a
///   margin of 0.2–0.3 g, at least 1.9× the shipped sequenced design on
///   the sequenced shaker (the shipped 0.290 and 0.298 against 0.585 and
///   0.582);
/// * no motion that flies is admitted: each is airborne over 10 % of the
///   cycle at some point or over 5 % shape error (measured: every one
///   over 6.6 %), and every motion at 1.3× the baseline or more has a
///   shape error over 7 % (measured: 7.7 % and more; the shape error
///   grows with the strength along one curve, in contact as in flight):
///   the 1.3× asked is not reached.
#[test]
#[ignore = "about 80 s of CPU: the whole study"]
fn flight_does_not_buy_strength_at_five_percent() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for shaker in SHAKERS {
        for name in TARGETS {
            let st =
                study_target(name, shaker, &root.join("targets"), &root.join("results")).unwrap();
            let (base, what) = st.baseline();
            println!("{name}, {shaker}: baseline {base:.4} ({what})");
            for c in &st.contact {
                let row = st
                    .rows
                    .iter()
                    .find(|r| r.margin == c.margin && r.scale == 1.0)
                    .unwrap();
                let j = row.judged;
                if c.margin == 0.0 {
                    // At margin 0 corners may leave the plate (measured:
                    // up to 2 points, airborne up to 20 % of the cycle).
                    assert!(j.flying_points <= 2, "{j:?}");
                    continue;
                }
                assert_eq!(j.flying_points, 0, "{name}, {shaker}, m = {}", c.margin);
                assert!(
                    (j.strength / c.strength - 1.0).abs() < 2e-3
                        && (j.shape_error - c.shape_error).abs() < 5e-4,
                    "{name}, {shaker}, m = {}: {j:?} against {} at {}",
                    c.margin,
                    c.strength,
                    c.shape_error
                );
            }
            assert!(what.starts_with("synthesize"), "{what}");
            if shaker == "sequenced" {
                assert!(
                    base >= 1.9 * st.shipped.1,
                    "{base} against {}",
                    st.shipped.1
                );
            }
            for r in &st.rows {
                let j = r.judged;
                // Grazing flights at margin 0 (the sink's on the envelope)
                // leave at most 2 points unsettled after 80 periods.
                let grazing = r.margin == 0.0 && r.scale == 1.0;
                assert!(
                    j.unsettled == 0 || (grazing && j.unsettled <= 2),
                    "{name}, {shaker}: {r:?}"
                );
                if j.max_airborne > 0.0 {
                    assert!(
                        j.max_airborne > MAX_FLIGHT || j.shape_error > SHAPE_LIMIT,
                        "{name}, {shaker}: {r:?}"
                    );
                }
                if j.strength >= RATIO_ASKED * base {
                    assert!(j.shape_error > 0.07, "{name}, {shaker}: {r:?}");
                }
            }
            assert!(st
                .best_flying()
                .is_some_and(|b| b.judged.max_airborne == 0.0));
        }
    }
}
