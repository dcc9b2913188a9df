//! Segment order and rest (`crate::design::order`): the search over
//! orders up to rotation and rest insertions, the heuristic beyond four
//! segments, and the reordered schedule `choose_order` returns.

use std::collections::BTreeSet;

use crate::basis::{Primitive, PrimitiveKind};
use crate::design::order::{
    choose, choose_order, region_grid, search_orders, OrderOptions, OrderSearch,
};
use crate::dynamics::Model;
use crate::play::{PlayOptions as VerifyOptions, PlayedSegment, ScheduleMotion};
use crate::schedule::Schedule;

/// A primitive segment with the paper's defaults, rotated by `deg`.
fn segment(kind: PrimitiveKind, deg: f64, cycles: u32) -> PlayedSegment {
    let p = Primitive {
        rotation_deg: deg,
        ..Primitive::new(kind)
    };
    PlayedSegment::moving(format!("{}@{deg}°", kind.name()), p.motion(), cycles)
}

fn options(points: Vec<[f64; 2]>, rest: Vec<u32>) -> OrderOptions {
    OrderOptions {
        rest_cycles: rest,
        warmup_cycles: 20,
        ..OrderOptions::new(
            VerifyOptions {
                model: Model::FROZEN,
                ..VerifyOptions::default()
            },
            points,
        )
    }
}

fn distinct_orders(s: &OrderSearch) -> BTreeSet<Vec<usize>> {
    s.candidates.iter().map(|c| c.order.clone()).collect()
}

fn segments(n: usize) -> Vec<PlayedSegment> {
    let kinds = [
        (PrimitiveKind::LineSink, 90.0),
        (PrimitiveKind::Trans, 0.0),
        (PrimitiveKind::LineSink, 0.0),
        (PrimitiveKind::Trans, 90.0),
        (PrimitiveKind::LineSink, 270.0),
    ];
    kinds[..n]
        .iter()
        .map(|&(k, deg)| segment(k, deg, 2))
        .collect()
}

/// The search enumerates orders up to rotation: one for 2 segments, (n − 1)!
/// for 3 and 4, each with every rest insertion; the rest is inserted at
/// every join (moving fraction = moving time / period, exactly); and the
/// chosen candidate is the table's minimum (tie tolerance 0), or within
/// the tolerance of it with the least rest.
#[test]
fn order_search_enumerates_orders_up_to_rotation() {
    let pts = vec![[0.01, 0.015], [-0.02, -0.005]];
    for (n, orders) in [(2, 1), (3, 2), (4, 6)] {
        let segs = segments(n);
        let s = search_orders(&segs, &options(pts.clone(), vec![0, 1])).unwrap();
        assert_eq!(distinct_orders(&s).len(), orders, "n = {n}");
        assert_eq!(s.candidates.len(), 2 * orders, "n = {n}");
        assert!(s.candidates.iter().all(|c| c.order[0] == 0 && c.valid == 2));
        let t = segs[0].motion.as_ref().unwrap().period();
        for c in &s.candidates {
            let expect = 2.0 * n as f64 * t / (2.0 * n as f64 * t + c.inserted_rest_s);
            assert!((c.moving_fraction - expect).abs() < 1e-12, "{c:?}");
            assert_eq!(c.rest_joins, if c.rest_cycles == 1 { n } else { 0 });
        }
        let min = s
            .candidates
            .iter()
            .map(|c| c.relative_error)
            .fold(f64::INFINITY, f64::min);
        assert_eq!(
            choose(&s.candidates, 0.0),
            Some(
                s.candidates
                    .iter()
                    .position(|c| c.relative_error == min)
                    .unwrap()
            )
        );
        let best = s.chosen();
        assert!(best.relative_error <= min + s.tie_tolerance);
        for c in &s.candidates {
            if c.relative_error <= min + s.tie_tolerance {
                assert!(
                    best.inserted_rest_s <= c.inserted_rest_s,
                    "{best:?} vs {c:?}"
                );
            }
        }
    }
}

/// Beyond four segments the heuristic is deterministic, stays within its
/// budget and keeps the first segment first.
#[test]
fn order_heuristic_is_deterministic_and_bounded() {
    let segs = segments(5);
    let opts = OrderOptions {
        max_evaluations: 7,
        ..options(vec![[0.01, 0.015]], vec![0, 1])
    };
    let a = search_orders(&segs, &opts).unwrap();
    let b = search_orders(&segs, &opts).unwrap();
    assert_eq!(a, b);
    // 7 orders without rest, then the rest insertion on the best of them.
    assert_eq!(a.candidates.len(), 8);
    assert!(a.method.starts_with("heuristic"));
    assert!(a.candidates.iter().all(|c| c.order[0] == 0));
    let best_order = a.candidates[..7]
        .iter()
        .min_by(|x, y| x.relative_error.total_cmp(&y.relative_error))
        .unwrap()
        .order
        .clone();
    assert_eq!(a.candidates[7].order, best_order);
    assert_eq!(a.candidates[7].rest_cycles, 1);
}

fn squeeze_schedule() -> Schedule {
    Schedule::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/results/sequenced/squeeze_trans/schedule.json"
    )))
    .unwrap()
}

/// `choose_order` returns the schedule of the chosen candidate in the same
/// format: the same segments in the chosen order, the inserted rest
/// segments, and `total_cycles` and `period_s` that add up.
#[test]
fn choose_order_keeps_the_schedule_consistent() {
    let schedule = squeeze_schedule();
    let opts = options(region_grid(&[[-0.03, -0.03], [0.03, 0.03]], 2), vec![1]);
    let (out, search) = choose_order(&schedule, &opts).unwrap();
    // n segments: (n − 1)! orders up to rotation, each with 1 rest cycle at every join.
    let n = schedule.segments.len();
    assert!(
        n >= 2,
        "the shipped squeeze_trans schedule has {n} segments"
    );
    assert_eq!(distinct_orders(&search).len(), (1..n).product::<usize>());
    let best = search.chosen();
    assert_eq!(best.rest_cycles, 1);
    assert_eq!(out.segments.len(), 2 * n);
    let moving: Vec<&str> = out
        .segments
        .iter()
        .filter(|s| s.primitive.is_some())
        .map(|s| s.label.as_str())
        .collect();
    let expect: Vec<&str> = best
        .order
        .iter()
        .map(|&i| schedule.segments[i].label.as_str())
        .collect();
    assert_eq!(moving, expect);
    assert!(out
        .segments
        .iter()
        .skip(1)
        .step_by(2)
        .all(|s| s.primitive.is_none() && s.cycles == 1));
    assert_eq!(out.total_cycles, schedule.total_cycles + n as u32);
    let sum: f64 = out.segments.iter().map(|s| s.duration_s).sum();
    assert!((out.period_s - sum).abs() < 1e-12);
    assert!((out.period_s - best.period_s).abs() < 1e-12);
    // Played again, the reordered schedule has the chosen candidate's period.
    let sm = ScheduleMotion::from_schedule(&out).unwrap();
    assert!((sm.period() - best.period_s).abs() < 1e-12);
    // The JSON format is kept.
    let text = serde_json::to_string(&out).unwrap();
    let back = Schedule::from_json_str(&text, "text").unwrap();
    assert_eq!(back, out);
}

/// A segment that never moves cannot be ordered: a clear error.
#[test]
fn order_search_needs_a_moving_segment() {
    let segs = vec![PlayedSegment::rest(0.1)];
    let e = search_orders(&segs, &options(vec![[0.0, 0.0]], vec![0])).unwrap_err();
    assert!(e.to_string().contains("moving segment"), "{e}");
}
