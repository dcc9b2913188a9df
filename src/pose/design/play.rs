//! A pose design played: the part dropped at random poses and simulated by
//! the planar simulator ([`crate::pose::play_part`]).
//!
//! **Duration.** Near a stable pose the lifted field decays as e^{λt} with
//! λ its slowest rate (the Jacobian eigenvalue of largest real part): a
//! drop starting a region's half-width (4 cm) away comes within 0.4 mm,
//! a hundredth, after ln(100)/|λ|. A played part may turn slower than the
//! isotropic lifted field predicts ([`crate::pose::LiftedField`]: several
//! times slower on a line sink and on a time-shared elliptic schedule; on
//! the one synthesized motion of a pose design the rectangle turns faster,
//! `results/poses.md`; measured: `docs/parts.md`, **Measurements behind the pose design's
//! choices**), so each drop
//! plays [`SPIN_SLOWER`] times that long, at least [`MIN_PLAY_S`] and at
//! most [`MAX_PLAY_S`] (whole schedule periods).
//!
//! **Settle time.** The pose is recorded at the end of every schedule
//! period; a drop's settle time is the end of the first period from which
//! on every recorded pose is within the tolerance of the asked one
//! (modulo the part's symmetry); a drop whose end is not has none. The
//! median counts those as longer than any.

use super::search::pose_error;
use super::{PoseTarget, TOL_DEG, TOL_MM};
use crate::field::FieldSettings;
use crate::play::ScheduleMotion;
use crate::pose::{drop_starts, nearest, play_part, DropPlay, Pose, PoseAnalysis};
use crate::schedule::{PoseBasin, PosePlayed};

/// Shortest play per drop (s).
pub const MIN_PLAY_S: f64 = 20.0;
/// Longest play per drop (s).
pub const MAX_PLAY_S: f64 = 120.0;
/// How many times slower than the lifted field's slowest rate a played
/// drop is taken to settle (module docs).
pub const SPIN_SLOWER: f64 = 3.0;

/// Seconds each drop plays for a slowest rate `rate` (1/s, module docs).
pub(crate) fn play_seconds(rate: f64) -> f64 {
    if rate > 0.0 {
        (SPIN_SLOWER * 100f64.ln() / rate).clamp(MIN_PLAY_S, MAX_PLAY_S)
    } else {
        MAX_PLAY_S
    }
}

/// Seconds each drop plays on a schedule of period `period` (s): its
/// [`play_seconds`], at least a cycle's settling periods
/// ([`super::cycle::settle_seconds`]).
pub(crate) fn drop_seconds(rate: f64, period: f64) -> f64 {
    super::cycle::settle_seconds(play_seconds(rate), period)
}

/// The slowest decay rate (1/s) a design's drops are timed by
/// ([`play_seconds`]): the lifted field's at the stable pose of
/// `analysis` nearest the asked one (none: 0, the longest play); infinite
/// for a cycle of a spun sink and an ellipse ([`super::cycle`]), whose
/// stage lengths already hold the stages' own rates, so its drops play
/// [`MIN_PLAY_S`] or [`super::cycle::SETTLE_PERIODS`] of its periods
/// ([`drop_seconds`]), whichever is longer.
pub(crate) fn play_rate(req: &PoseTarget, analysis: &PoseAnalysis, spun: bool) -> f64 {
    if spun {
        return f64::INFINITY;
    }
    let (n, radius) = (req.part.symmetry(), req.part.radius());
    super::search::nearest_stable(&analysis.equilibria, &req.pose, n, radius)
        .map_or(0.0, |e| -e.rates[0])
}

/// Whether `p` is at the `asked` pose: within [`TOL_MM`] and [`TOL_DEG`]
/// of it, the angle modulo the part's symmetry `n` (the count a pose
/// design's played drops record as `pose_fraction`).
///
/// ```
/// use platefield::pose::design::at_pose;
/// use platefield::dynamics::V2;
/// use platefield::pose::Pose;
/// let asked = Pose { r: V2::new(0.008, 0.006), theta: (-40f64).to_radians() };
/// // 0.8 mm and 2° off: at the pose.
/// let near = Pose { r: V2::new(0.0088, 0.006), theta: (-38f64).to_radians() };
/// assert!(at_pose(&near, &asked, 1));
/// // A half turn off: at the pose only for a part symmetric under it.
/// let turned = Pose { r: asked.r, theta: 140f64.to_radians() };
/// assert!(!at_pose(&turned, &asked, 1) && at_pose(&turned, &asked, 2));
/// ```
pub fn at_pose(p: &Pose, asked: &Pose, n: usize) -> bool {
    let (d, t) = pose_error(p, asked, n);
    d <= 1e-3 * TOL_MM && t.abs().to_degrees() <= TOL_DEG
}

/// Index of the first period from which on the track stays at the pose.
fn settled_from(track: &[Pose], asked: &Pose, n: usize) -> Option<usize> {
    let last_out = track.iter().rposition(|p| !at_pose(p, asked, n));
    match last_out {
        None => Some(0),
        Some(k) if k + 1 < track.len() => Some(k + 1),
        Some(_) => None,
    }
}

/// The median of `times` where `None` is longer than any; `None` when
/// that median is itself `None`.
fn median(mut times: Vec<Option<f64>>) -> Option<f64> {
    times.sort_by(|a, b| match (a, b) {
        (Some(x), Some(y)) => x.total_cmp(y),
        (Some(_), None) => std::cmp::Ordering::Less,
        (None, Some(_)) => std::cmp::Ordering::Greater,
        (None, None) => std::cmp::Ordering::Equal,
    });
    let n = times.len();
    if n == 0 {
        return None;
    }
    match (times[(n - 1) / 2], times[n / 2]) {
        (Some(a), Some(b)) => Some(0.5 * (a + b)),
        _ => None,
    }
}

/// Plays `drops` drops of the pose target's part through `sm` (module docs):
/// `analysis` is the kept schedule's lifted field (its stable poses and
/// predicted basins), `field` names the requested point field and `rate`
/// is the slowest decay rate at the asked pose (1/s); with each drop's
/// end pose (`None`: it lost contact).
pub(crate) fn play_ends(
    req: &PoseTarget,
    sm: &ScheduleMotion,
    settings: &FieldSettings,
    (analysis, field, rate): (&PoseAnalysis, String, f64),
    drops: usize,
) -> (PosePlayed, Vec<Option<Pose>>) {
    let n = req.part.symmetry();
    let duration = drop_seconds(rate, sm.period());
    let starts = drop_starts(&analysis.starts, drops);
    let runs = play_part(&req.part, sm, &starts, &DropPlay::new(settings, duration));
    let period = sm.period();
    let eqs = &analysis.equilibria;
    let stable: Vec<usize> = (0..eqs.len()).filter(|&i| eqs[i].stable).collect();
    let stable_eq: Vec<_> = stable.iter().map(|&i| eqs[i]).collect();
    let mut ends = vec![0usize; stable.len()];
    let mut settle = Vec::with_capacity(runs.len());
    let mut end_poses = Vec::with_capacity(runs.len());
    let (mut at, mut lost, mut time) = (0usize, 0usize, 0.0);
    for run in &runs {
        let Ok((end, track)) = run else {
            lost += 1;
            settle.push(None);
            end_poses.push(None);
            continue;
        };
        time = end.time;
        end_poses.push(Some(end.pose));
        at += usize::from(at_pose(&end.pose, &req.pose, n));
        settle.push(settled_from(track, &req.pose, n).map(|k| (k + 1) as f64 * period));
        if let Some((k, _)) = nearest(&stable_eq, &end.pose, req.part.radius()) {
            ends[k] += 1;
        }
    }
    let total = drops.max(1) as f64;
    let basins = stable
        .iter()
        .zip(&ends)
        .map(|(&i, &c)| PoseBasin {
            pose: [
                eqs[i].pose.r.x,
                eqs[i].pose.r.y,
                eqs[i].pose.theta.to_degrees(),
            ],
            lifted: analysis.basins[i],
            played: c as f64 / total,
        })
        .collect();
    let played = PosePlayed {
        part: req.part_path.clone(),
        pose: [req.pose.r.x, req.pose.r.y, req.pose.theta.to_degrees()],
        symmetry: n,
        field,
        drops,
        duration_s: if runs.is_empty() { duration } else { time },
        tolerance: [TOL_MM, TOL_DEG],
        pose_fraction: at as f64 / total,
        median_settle_s: median(settle),
        lost,
        stable: basins,
        distinct_stable: super::search::distinct_stable(eqs, n).len(),
        over_friction: None,
    };
    (played, end_poses)
}
