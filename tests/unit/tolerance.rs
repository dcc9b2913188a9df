//! The judge under the shaker's delivery error (`design::tolerance`).

use crate::design::method::judge_check;
use crate::design::tolerance::{delivered, draws, spread, Draw};
use crate::request::Tolerance;
use crate::schedule::Schedule;

fn sink() -> Schedule {
    Schedule::load(std::path::Path::new(
        "results/synthesized/sink/schedule.json",
    ))
    .unwrap()
}

/// A phase shift of h·φ at harmonic h on every channel, gains 1, is the
/// whole motion played φ/ω later: a steady motion's judge (a periodic
/// mean) cannot change. Within 1e-4 relative in strength and 0.01
/// percentage point in shape (the judge's settle tolerance is 1e-4 of
/// each part's drift). A sign slip in one channel's shift breaks it.
#[test]
fn a_common_time_shift_leaves_the_judge_unchanged() {
    let s = sink();
    let target = s.target_spec.clone().unwrap();
    let sampled = target.sample().unwrap();
    let base = judge_check(&target, &sampled, &s, &s.settings).unwrap();
    let shift = Draw {
        errors: (1..=16).map(|h| [(1.0, 0.7 * f64::from(h)); 6]).collect(),
    };
    let shifted = judge_check(&target, &sampled, &delivered(&s, &shift), &s.settings).unwrap();
    let ds = (shifted.realised_strength / base.realised_strength - 1.0).abs();
    let de = (shifted.shape_error - base.shape_error).abs();
    assert!(ds < 1e-4 && de < 1e-4, "strength {ds:e}, shape {de:e}");
    // One channel alone shifted is a different motion.
    let mut one = shift.clone();
    for row in &mut one.errors {
        row[1..].fill((1.0, 0.0));
    }
    let off = judge_check(&target, &sampled, &delivered(&s, &one), &s.settings).unwrap();
    assert!(
        (off.shape_error - base.shape_error).abs() > 0.01,
        "{off:?} against {base:?}"
    );
}

/// With a zero tolerance every draw is the design's own judge, exactly;
/// within ±5 % and ±5° the 8 draws spread (median above the design's
/// shape error, worst above the median) and the same call gives the same
/// draws.
#[test]
fn the_spread_is_the_judge_over_seeded_draws() {
    let s = sink();
    let target = s.target_spec.clone().unwrap();
    let sampled = target.sample().unwrap();
    let base = judge_check(&target, &sampled, &s, &s.settings).unwrap();
    let zero = Tolerance::default();
    let z = spread(&target, &sampled, &s, &s.settings, (&zero, 4)).unwrap();
    assert!(z.shape_errors.iter().all(|e| *e == base.shape_error));
    assert_eq!(z.perturbed_segments, 1);
    let tol = Tolerance {
        amplitude: 0.05,
        phase_deg: 5.0,
    };
    let a = spread(&target, &sampled, &s, &s.settings, (&tol, 8)).unwrap();
    let [median, _, worst] = a.shape();
    assert!(
        median > base.shape_error && worst > median,
        "{median} {worst} against {}",
        base.shape_error
    );
    assert!(worst < 0.5, "{worst}");
    assert_eq!(
        a,
        spread(&target, &sampled, &s, &s.settings, (&tol, 8)).unwrap()
    );
    assert_eq!(draws(&tol, 8).len(), 8);
}

/// A target that states `shaker.tolerance` is designed with the kept
/// design's spread (`MethodDesign::tolerance`), judged at the friction of
/// its worst case. A sequenced schedule of screw primitives has nothing a
/// draw perturbs: all 64 draws are the kept design's own judge, exactly,
/// at the worst friction of its range (μ 0.2, 0.3, 0.4 judged; the spread
/// at the row the headline names).
#[test]
fn a_stated_tolerance_is_judged_at_the_worst_friction() {
    use crate::basis::PrimitiveKind;
    use crate::design::{BasisSection, DesignOptions};
    use crate::inverse::run;
    let target = crate::request::Target::from_json_str(
        r#"{"name": "sink_tol", "field": {"kind": "sink"},
            "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [9, 9]},
            "friction": [0.2, 0.4],
            "shaker": {"tolerance": {"amplitude": 0.05, "phase_deg": 5}}}"#,
    )
    .unwrap();
    let opts = DesignOptions {
        method: crate::design::Method::Sequence,
        basis: BasisSection {
            kinds: vec![PrimitiveKind::LineSink],
            rotation_step_deg: 90.0,
            cache_dir: Some(
                std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("target/tmp")
                    .join("tol-cache"),
            ),
            ..Default::default()
        },
        runtime: crate::work::Runtime::QUIET,
        ..DesignOptions::default()
    };
    let md = run(&target, &opts).unwrap().into_method().unwrap();
    let t = md
        .tolerance
        .as_ref()
        .expect("the target states a tolerance");
    let played = md.kept().played();
    let worst = played.worst_friction.expect("a friction range");
    assert_eq!(t.friction, worst.kinetic);
    assert_eq!((t.shape_errors.len(), t.perturbed_segments), (64, 0));
    assert_eq!(t.primitive_segments, md.kept().schedule.segments.len());
    assert!(t
        .shape_errors
        .iter()
        .all(|e| Some(*e) == played.realised_shape_error));
    // Without a stated tolerance, no spread.
    let mut plain = target.clone();
    plain.shaker = None;
    let md = run(&plain, &opts).unwrap().into_method().unwrap();
    assert!(md.tolerance.is_none());
}

/// The sink (`targets/sink.json`) over μ 0.2–0.4 with the shaker's
/// tolerance ±5 % and ±5° (`auto`, the design's defaults): the kept
/// design's worst shape error over 64 delivery-error draws is ≤ 8 % at
/// each of μ 0.2, 0.3 and 0.4. Without the tolerance `auto` keeps the
/// mirror-image share within the envelope's contact margin, whose worst
/// over the draws misses that (measured 8.25 % at μ 0.4); with it the
/// design weighs the wider-margin candidates over the same draws
/// (`design::method::Choice::Delivered`; measured 6.75, 6.71 and 6.83 %).
/// About 3 min of CPU: `cargo test --release --lib design::tolerance::tolerance_tests -- --ignored`.
#[test]
#[ignore = "about 3 min of CPU: cargo test --release --lib design::tolerance::tolerance_tests -- --ignored"]
fn the_sink_holds_its_tolerance_over_the_range() {
    use crate::design::tolerance::judged_at;
    use crate::design::DesignOptions;
    use crate::inverse::run;
    let mut target =
        crate::request::Target::load(std::path::Path::new("targets/sink.json")).unwrap();
    target.friction = Some(crate::scene::FrictionSpec::range(0.2, 0.4));
    let tol = Tolerance {
        amplitude: 0.05,
        phase_deg: 5.0,
    };
    target.shaker = Some(crate::request::ShakerSpec {
        tolerance: Some(tol),
        ..Default::default()
    });
    let opts = DesignOptions {
        runtime: crate::work::Runtime::QUIET,
        ..DesignOptions::default()
    };
    let md = run(&target, &opts).unwrap().into_method().unwrap();
    eprintln!("{}", md.why());
    let kept = &md.kept().schedule;
    let sampled = target.sample().unwrap();
    for mu in [0.2, 0.3, 0.4] {
        let physics = judged_at(
            kept,
            &kept.settings,
            Some(crate::dynamics::Friction::uniform(mu)),
        );
        let s = spread(&target, &sampled, kept, &physics, (&tol, 64)).unwrap();
        let [median, p90, worst] = s.shape();
        eprintln!("μ {mu}: median {median:.4}, 90th {p90:.4}, worst {worst:.4}");
        assert!(worst <= 0.08, "μ {mu}: worst {worst}");
    }
}
