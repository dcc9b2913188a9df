//! A sort's schedule cut into interleaved sub-periods (see the parent
//! module's **Interleaving**): the same time fractions, each segment cut
//! into pieces played in turn, so that the parts swing less within a
//! period.

use crate::play::{PlayOptions, ScheduleMotion, V2};
use crate::request::Target;
use crate::schedule::{Schedule, Segment};

/// Largest within-period excursion (m) a sort's parts may swing off their
/// mean drift: half the 5 mm a part may be from its attractor to count as
/// there (`crate::verify::sort_play::SORT_TOL`), and half a swarm cell
/// (3.3 mm on `targets/sort_lanes.json`) from the edge a lane's outermost
/// starts lie.
pub const EXCURSION_MAX: f64 = 2.5e-3;

/// Most sub-periods a schedule is cut into.
pub const MAX_SUB_PERIODS: u32 = 8;

/// The within-period excursion (m) of a part's `path` at segment ends over
/// one period, `(t, position)` from the period's start to its end: the
/// largest distance of a segment end from the uniform drift between the
/// period's ends (for a settled part, from its orbit's start).
pub(crate) fn excursion(path: &[(f64, [f64; 2])]) -> f64 {
    let (Some(&(t0, p0)), Some(&(t1, p1))) = (path.first(), path.last()) else {
        return 0.0;
    };
    let span = t1 - t0;
    path.iter()
        .map(|&(t, p)| {
            let s = if span > 0.0 { (t - t0) / span } else { 0.0 };
            let q = [p0[0] + s * (p1[0] - p0[0]), p0[1] + s * (p1[1] - p0[1])];
            (p[0] - q[0]).hypot(p[1] - q[1])
        })
        .fold(0.0, f64::max)
}

/// The largest excursion ([`excursion`]) over `target`'s classes of a
/// part played under `schedule` at the class's friction, started at rest
/// at the class's attractor (at the region's centre for a class without
/// one), over its second period (the first holds the start-up transient).
/// A class whose part loses contact counts as not swinging (the plays
/// report the loss).
///
/// # Errors
/// The schedule cannot be played.
pub(crate) fn class_excursion(target: &Target, schedule: &Schedule) -> crate::Result<f64> {
    use crate::dynamics::PartState;
    let sm = ScheduleMotion::from_schedule(schedule)?;
    let centre = target.grid.as_ref().map_or([0.0; 2], |g| {
        [0.5 * (g.x[0] + g.x[1]), 0.5 * (g.y[0] + g.y[1])]
    });
    let segments = sm.segments().len();
    let mut worst = 0.0_f64;
    for i in 0..target.classes.len() {
        let ct = target.class_target(i);
        let start = match crate::request::Attractor::of(&ct.field) {
            Some(crate::request::Attractor::Point { center, .. }) => center,
            Some(crate::request::Attractor::Line { point, .. }) => point,
            None => centre,
        };
        let v = PlayOptions::from_settings(&ct.physics(&schedule.settings));
        let player = v.moving_player(&sm);
        let anchor = V2::from(start);
        let mut state = PartState::new(anchor, V2::zeros());
        let mut path: Vec<(f64, [f64; 2])> = vec![(0.0, start)];
        if player
            .play_periods(&mut state, &anchor, 0, 2, |t, _, s| {
                path.push((t, [s.r.x, s.r.y]));
            })
            .is_ok()
            && path.len() > segments
        {
            worst = worst.max(excursion(&path[segments..]));
        }
    }
    Ok(worst)
}

/// The most pieces `seg` can be cut into: one per cycle for a primitive,
/// any number for a rest, and for a ramped six-signal segment (R ramp
/// cycles each way, c = cycles − R cycles' worth of its field) ⌊c / R⌋,
/// so that every piece keeps the segment's ramps of R cycles (its
/// accelerations as checked, `super::super::stages`' ramps within the
/// shaker limits) and at least 2R cycles.
fn most_pieces(seg: &Segment) -> u32 {
    match (seg.ramp_cycles, seg.cycle_period()) {
        (Some(r), _) => ((seg.cycles - r) / r.max(1)).max(1),
        (None, Some(_)) => seg.cycles.max(1),
        (None, None) => MAX_SUB_PERIODS,
    }
}

/// `n` split into `k` nearly equal whole parts (the first n mod k one
/// larger).
fn split(n: u32, k: u32) -> Vec<u32> {
    (0..k).map(|j| n / k + u32::from(j < n % k)).collect()
}

/// `schedule` cut into `k` interleaved sub-periods: each segment into
/// min(k, `most_pieces`) pieces of nearly equal steady cycles (a rest,
/// of equal time), piece m placed in sub-period ⌊m k / pieces⌋, the
/// segments' order kept within each sub-period. Every segment keeps its
/// steady cycles and so its time fraction; a ramped six-signal segment cut
/// into p pieces plays its ramps p times, (p − 1)·R cycles more per
/// period (its two ramps of R cycles play about R cycles' worth of its
/// field, so its proportion holds, as in `super::super::basis`'s mixed
/// segments).
/// `k` ≤ 1 returns the schedule unchanged.
pub(crate) fn interleaved(schedule: &Schedule, k: u32) -> Schedule {
    if k <= 1 {
        return schedule.clone();
    }
    let mut subs: Vec<Vec<Segment>> = vec![Vec::new(); k as usize];
    for seg in &schedule.segments {
        let pieces = k.min(most_pieces(seg));
        let ramp = seg.ramp_cycles.unwrap_or(0);
        let steady = seg.cycles - ramp;
        let parts: Vec<Segment> = match seg.cycle_period() {
            Some(_) => split(steady, pieces)
                .into_iter()
                .filter(|&c| c > 0)
                .map(|c| Segment {
                    cycles: c + ramp,
                    weight: seg.weight * f64::from(c) / f64::from(steady.max(1)),
                    ..seg.clone()
                })
                .collect(),
            None => (0..pieces)
                .map(|_| Segment {
                    duration_s: seg.duration_s / f64::from(pieces),
                    weight: seg.weight / f64::from(pieces),
                    ..seg.clone()
                })
                .collect(),
        };
        let p = parts.len() as u32;
        for (m, piece) in parts.into_iter().enumerate() {
            subs[(m as u32 * k / p) as usize].push(piece);
        }
    }
    let mut out = schedule.clone();
    out.segments = subs.into_iter().flatten().collect();
    out.derive();
    out
}

/// The sub-periods a sort's schedule is cut into ([`interleaved`]): the
/// least k with the excursion `e` (m, `class_excursion`) over k at most
/// [`EXCURSION_MAX`] (a part's swing within a period scales with the
/// segments' durations), at most [`MAX_SUB_PERIODS`].
pub(crate) fn sub_periods(e: f64) -> u32 {
    let k = (e / EXCURSION_MAX).ceil();
    if k.is_finite() && k >= 1.0 {
        (k as u32).min(MAX_SUB_PERIODS)
    } else {
        1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cut into k sub-periods, a schedule keeps every segment's steady
    /// cycles and weight; a ramped six-signal segment keeps its ramp in
    /// every piece and is cut into at most ⌊steady / R⌋ pieces.
    #[test]
    fn interleaving_keeps_the_time_fractions() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/results/sort_friction/schedule.json"
        );
        let s = Schedule::load(path.as_ref()).unwrap();
        let steady = |s: &Schedule, label: &str| -> (u32, f64) {
            s.segments
                .iter()
                .filter(|g| g.label == label)
                .fold((0, 0.0), |(c, w), g| {
                    (c + g.cycles - g.ramp_cycles.unwrap_or(0), w + g.weight)
                })
        };
        for k in 1..=MAX_SUB_PERIODS {
            let cut = interleaved(&s, k);
            for g in &s.segments {
                let (c0, w0) = steady(&s, &g.label);
                let (c1, w1) = steady(&cut, &g.label);
                assert_eq!(c0, c1, "k {k}: {}", g.label);
                assert!((w0 - w1).abs() < 1e-12, "k {k}: {}", g.label);
                let pieces: Vec<&Segment> =
                    cut.segments.iter().filter(|p| p.label == g.label).collect();
                assert!(pieces.len() as u32 <= k.min(most_pieces(g)));
                for p in pieces {
                    assert_eq!(p.ramp_cycles, g.ramp_cycles);
                    if let Some(r) = p.ramp_cycles {
                        assert!(p.cycles >= 2 * r, "k {k}: {p:?}");
                    }
                }
            }
            let ramps: u32 = cut.segments.iter().filter_map(|g| g.ramp_cycles).sum();
            let before: u32 = s.segments.iter().filter_map(|g| g.ramp_cycles).sum();
            assert_eq!(
                cut.total_cycles - s.total_cycles,
                ramps - before,
                "k {k}: only the ramps lengthen the period"
            );
        }
        assert_eq!(interleaved(&s, 1), s);
    }

    /// A worked example of `design::sort::interleave::excursion`.
    #[test]
    fn example_excursion() {
        use crate::design::sort::excursion;
        // Out 3 mm along x and back within the period, drifting 1 mm along y.
        let path = [
            (0.0, [0.0, 0.0]),
            (1.0, [0.003, 0.0005]),
            (2.0, [0.0, 0.001]),
        ];
        assert!((excursion(&path) - 0.003).abs() < 1e-12);
    }

    /// A worked example of `design::sort::interleave::interleaved`.
    #[test]
    fn example_interleaved() -> Result<(), crate::Error> {
        use crate::design::sort::interleaved;
        use crate::schedule::Schedule;
        let s = Schedule::load("results/sort_friction/schedule.json".as_ref())?;
        let cut = interleaved(&s, 2);
        assert!(cut.segments.len() > s.segments.len());
        Ok(())
    }

    /// A worked example of `design::sort::interleave::sub_periods`.
    #[test]
    fn example_sub_periods() {
        use crate::design::sort::{sub_periods, EXCURSION_MAX};
        assert_eq!(sub_periods(0.5 * EXCURSION_MAX), 1);
        assert_eq!(sub_periods(2.5 * EXCURSION_MAX), 3);
        assert_eq!(sub_periods(100.0 * EXCURSION_MAX), 8);
    }
}
