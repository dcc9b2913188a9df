//! Refinement of a sequenced design by re-simulation
//! (`crate::design::refine`), on a small case: the shipped line-sink
//! schedule (LineSink at 0° and 180°) with its second segment detuned by
//! 20°, so its line is turned and its realised shape error is large;
//! Nelder–Mead over the segments' cycles, rotation and amplitude must bring
//! it back (coarse: 3 × 3 held points, ≤ 30 plays; before and after judged).

use std::path::Path;

use crate::design::refine::{apply, dimension, refine_schedule, RefineOptions};
use crate::request::Target;
use crate::schedule::Schedule;

fn line_sink() -> (Schedule, Target) {
    (
        Schedule::load(Path::new("results/line_sink/schedule.json")).unwrap(),
        Target::load(Path::new("targets/line_sink.json")).unwrap(),
    )
}

/// The parameter map: zero is the design itself (same cycles, rotations
/// and motions); cycles scale by e^x and round; rotation moves by 10° per
/// unit; amplitude only shrinks.
#[test]
fn parameters_map_onto_the_primitives() {
    let (s, _) = line_sink();
    assert_eq!(dimension(&s), 6);
    let same = apply(&s, &[0.0; 6]);
    for (a, b) in same.segments.iter().zip(&s.segments) {
        assert_eq!(a.cycles, b.cycles);
        let (pa, pb) = (a.primitive.as_ref().unwrap(), b.primitive.as_ref().unwrap());
        assert_eq!(pa.motion(), pb.motion());
    }
    let moved = apply(&s, &[2f64.ln(), 1.5, 0.5, 0.0, 0.0, (0.5f64).ln()]);
    let (a, b) = (&moved.segments[0], &moved.segments[1]);
    assert_eq!(a.cycles, 2 * s.segments[0].cycles);
    let p = a.primitive.as_ref().unwrap();
    assert!(
        (p.rotation_deg - (s.segments[0].primitive.as_ref().unwrap().rotation_deg + 15.0)).abs()
            < 1e-12
    );
    assert_eq!(p.amplitude, Some(crate::basis::primitives::PSI0));
    assert_eq!(
        b.primitive.as_ref().unwrap().amplitude,
        Some(0.5 * crate::basis::primitives::PSI0)
    );
    assert!((moved.period_s - (3.0 * s.segments[0].duration_s)).abs() < 1e-12);
}

/// Detuned by 20°, refined: the realised shape error falls by at least
/// 70 % and the refined schedule costs no more than the detuned one.
#[test]
fn refinement_repairs_a_detuned_line_sink() {
    let (s, target) = line_sink();
    let mut segments = s.segments.clone();
    if let Some(p) = &mut segments[1].primitive {
        p.rotation_deg += 20.0;
    }
    let detuned = s.with_segments(segments);
    let options = RefineOptions {
        coarse_stride: 10,
        max_evaluations: 30,
        step: 0.5,
    };
    let r = refine_schedule(&detuned, &target, &options).unwrap();
    let (b, a) = (&r.before.error, &r.after.error);
    println!(
        "detuned line sink: shape {:.2} % → {:.2} %, strength {:.4} → {:.4}, {} plays, {:.1} s",
        100.0 * b.shape_error,
        100.0 * a.shape_error,
        b.realised_strength,
        a.realised_strength,
        r.evaluations,
        r.seconds
    );
    assert!(r.improved);
    assert!(r.evaluations <= 30);
    // Nelder–Mead's simplex does not shrink to its 1e-6 spread in 30
    // plays of a 20° detuning: the budget ends it, and the stop says so.
    assert_eq!(r.stop, crate::work::Stop::Spent, "{} plays", r.evaluations);
    assert!(r.after.cost <= r.before.cost);
    // Measured by the judge 25.5 % → 3.9 % (30 plays).
    assert!(
        a.shape_error <= 0.3 * b.shape_error,
        "{} vs {}",
        a.shape_error,
        b.shape_error
    );
    assert!(
        b.shape_error > 0.2,
        "the detuning must matter: {}",
        b.shape_error
    );
}
