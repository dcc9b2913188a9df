//! Spin candidates judged by play: probes from spread starts, each also
//! turned by 180°, on the spun sink and then on the cycle `design` ships,
//! their ends clustered.
//!
//! **Why.** The lifted field of a spun sink ([`super::spin`]) is rough:
//! on one of the bracket's spins it gives one stable pose, yet about a
//! quarter of the played drops come to rest at a second pose far from the
//! asked one (measured: `docs/parts.md`, **Measurements behind the pose design's choices**).
//!
//! **What is judged.** What `design` keeps: the candidate's cycle with
//! the ellipse ([`super::cycle`]), placed and scaled. The probes first
//! play [`PROBE_S`] on the centred spun sink alone, whose largest cluster
//! is where the cycle's ellipse stage is placed; the cycle is then placed
//! so that this rest falls on the asked pose ([`super::placement`]: the
//! ellipse stage rests there, so the cycle's played rest does up to the
//! correction `design` makes after), scaled into the shaker limits as the
//! shipped schedule is, and played as long as a design's drops play it
//! (`super::play::MIN_PLAY_S`, or [`super::cycle::SETTLE_PERIODS`] of
//! its periods when longer) from starts over the region the drops come
//! from. The candidate's score, pose and turn below are that play's; its
//! pose is taken back to the centred motion.
//!
//! **Measure.** [`PROBES`] drops at `probe_starts`: a 4 × 4 grid over
//! the region inset by the part's radius, angles stepped by the golden
//! angle, and each of those starts again turned by 180°. An end's cluster
//! is the ends within [`super::TOL_MM`] and [`super::TOL_DEG`] of it
//! (modulo the part's symmetry); the candidate's score is the largest
//! cluster's share of the probes and its played pose that cluster's mean.
//! A drop lost, at a second pose or still moving at the end of its play
//! counts against it.
//!
//! **Why the 180° twins.** The elliptic stage alone has two rests 180°
//! apart for a part without a 180° symmetry (a linear field turns a part by
//! its second moments only, [`super::placement`]); the spin stage must
//! bring every drop into the half-turn around the asked one. A drop that
//! the spin leaves in the other half ends at the rival rest, flipped by
//! 180° (the misses of the bracket's shipped design, and the one drop of
//! twelve the independent simulator put there: `docs/parts.md`). With
//! angles stepped by the golden angle alone, a probe seldom starts in that
//! rival basin; twinning each start with its half turn probes every
//! start position from both halves of orientation, so a spin with a rival
//! attractor shows it in its share.
//!
//! **Over a friction range.** When the pose target states a friction range,
//! the probes also play at its two ends: a candidate's score is its least
//! share over the three frictions, and its `turn` how far its played pose
//! moves from the low end to the high one, in tolerances (the larger of
//! |Δr|/1 mm and |Δθ|/3°). Only a candidate that turns by at most
//! [`MAX_TURN`] tolerances can be kept: the correction centres the
//! placement between the ends (`pose::design::correct`), so a turn of at most
//! twice the tolerance leaves both ends within it. Otherwise `design`
//! keeps the elliptic sink alone. (Judged alone, the triangle's strongest
//! spin turned its rest 17.6° over μ 0.24–0.36; in its cycle the ellipse
//! sets the pose, which moved 2.5°.)
//!
//! **Stage lengths.** The cycle is first placed with its derived stages
//! ([`super::cycle::Stages`]); its spin stage's hand-over is then played
//! ([`super::handover`]) and the cycle placed again with the spin stage
//! that long and the ellipse stage as long as its torque takes from the
//! hand-over's worst turn (`cycle::Stages::handed_over`). A spin
//! that brings no part from the ellipse's rival rest into the kept half at
//! any time up to [`super::cycle::MAX_STAGE_S`] cannot select, and is not
//! played.
//!
//! **Choice** (`choose`): among the candidates with a lifted stable pose
//! (`super::spin::try_all`) and a cycle no longer than
//! [`super::cycle::MAX_STAGE_S`] allows ([`super::cycle::Stages`]), the
//! largest share, then (over a range) the least turn, then the shortest
//! cycle (the settle time is counted in its periods), then the tightest
//! cluster
//! (least mean |Δr|/1 mm + |Δθ|/3° of its members from its mean: the most
//! nearly settled), then the earlier in [`super::spin::CANDIDATES`]; kept
//! when that share is at least [`MIN_SHARE`]. When none is kept, `design`
//! screens the lattice again with r* halved (`super::spin`,
//! **Refinement**), and when that keeps none either it keeps the elliptic
//! sink, whose two poses 180° apart hold about half the drops each.

use super::cycle::{cycle, settle_seconds, slowest_rate, EllipseStage, Stages};
use super::handover::Handover;
use super::placement::Placement;
use super::search::{pose_error, wrap_symmetric};
use super::spin::{spun, Spin};
use super::PoseTarget;
use crate::dynamics::{Friction, V2};
use crate::error::Result;
use crate::play::ScheduleMotion;
use crate::pose::{play_part, DropPlay, Pose, Region};
use crate::schedule::Schedule;

/// Grid starts per candidate: a 4 × 4 grid.
pub const GRID: usize = 16;
/// Probe drops per candidate: each grid start and its 180° twin.
pub const PROBES: usize = 2 * GRID;
/// Seconds each probe plays on the spun sink alone.
pub const PROBE_S: f64 = 60.0;
/// Seconds each probe plays on the placed cycle (at least
/// [`super::cycle::SETTLE_PERIODS`] of its periods): as long as a design's
/// drops play a cycle (`super::play::MIN_PLAY_S`).
pub const CYCLE_S: f64 = super::play::MIN_PLAY_S;
/// Least share of the probes at one pose for a spin to be kept: 24 of 32,
/// well above the elliptic sink's half.
pub const MIN_SHARE: f64 = 0.75;
/// Most a kept spin's played pose may move over a stated friction range,
/// in tolerances (module docs): twice the tolerance, centred.
pub const MAX_TURN: f64 = 2.0;

/// A candidate judged by play.
#[derive(Debug, Clone, PartialEq)]
pub struct Screened {
    /// The spin.
    pub spin: Spin,
    /// Its cycle's stage lengths: when it hands parts over, the spin stage
    /// as measured by its hand-over and the ellipse stage from its worst
    /// turn (`Stages::handed_over`), else `Stages::derive`'s; `None`
    /// for a spin whose lifted field turns too slowly, which is not played.
    pub stages: Option<Stages>,
    /// Its spin stage's hand-over, measured on the placed cycle
    /// ([`super::handover`]); `None` when not measured. A spin whose worst
    /// part stays outside the kept half ([`super::cycle::ELLIPSE_TURN_DEG`]
    /// from the asked pose) at every time cannot select, and is not played.
    pub handover: Option<Handover>,
    /// The spun sink's own played rest (its probes' largest cluster),
    /// where its cycle's ellipse stage is placed; `None` when every probe
    /// lost contact.
    pub spin_rest: Option<Pose>,
    /// Share of the probes in the largest cluster of ends (0 … 1).
    pub score: f64,
    /// Mean of |Δr|/1 mm + |Δθ|/3° of that cluster's members from its mean.
    pub spread: f64,
    /// That cluster's mean pose, played on the placed cycle and taken back
    /// to the centred motion; `None` when every probe lost contact.
    pub pose: Option<Pose>,
    /// With a friction range: how far the played pose moves from its low
    /// end to its high one, in tolerances (module docs); `None` for an
    /// exact friction, infinite when an end has no cluster.
    pub turn: Option<f64>,
}

impl Screened {
    /// A candidate whose spun sink lost every probe (or, with no
    /// `stages`, was too slow to play): no cycle was played.
    fn unplayed(spin: Spin, stages: Option<Stages>, handover: Option<Handover>) -> Screened {
        Screened {
            spin,
            stages,
            handover,
            spin_rest: None,
            score: 0.0,
            spread: f64::INFINITY,
            pose: None,
            turn: None,
        }
    }
}

/// The probe starts over `region` (module docs): a 4 × 4 grid of centres
/// at the cell middles, the k-th turned by k golden angles, then the same
/// [`GRID`] starts again turned by 180° (wrapped to (−π, π]).
pub(crate) fn probe_starts(region: &Region) -> Vec<Pose> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let grid: Vec<Pose> = (0..GRID)
        .map(|k| {
            let (i, j) = ((k % 4) as f64, (k / 4) as f64);
            let r = region.at((i + 0.5) / 4.0, (j + 0.5) / 4.0);
            Pose {
                r,
                theta: crate::pose::wrap(k as f64 * golden),
            }
        })
        .collect();
    let twins = grid.iter().map(|p| Pose {
        r: p.r,
        theta: crate::pose::wrap(p.theta + std::f64::consts::PI),
    });
    grid.iter().copied().chain(twins).collect()
}

/// The largest cluster of `ends` (module docs): its share of `total`, its
/// mean pose (θ averaged as offsets modulo the symmetry `n` from the
/// cluster's seed) and its spread (module docs).
///
/// ```
/// use platefield::pose::design::screen::largest_cluster;
/// use platefield::pose::Pose;
/// let ends = [Pose::new(0.0, 0.0, 0.0), Pose::new(0.0002, 0.0, 0.02), Pose::new(0.01, 0.0, 2.0)];
/// let (share, pose, spread) = largest_cluster(&ends, 1, 4).unwrap();
/// assert_eq!(share, 0.5);
/// // each member 0.1 mm and 0.01 rad (0.573°) from the mean
/// assert!((spread - (0.1 + 0.01f64.to_degrees() / 3.0)).abs() < 1e-9);
/// assert!((pose.r.x - 0.0001).abs() < 1e-15 && (pose.theta - 0.01).abs() < 1e-15);
/// ```
pub fn largest_cluster(ends: &[Pose], n: usize, total: usize) -> Option<(f64, Pose, f64)> {
    largest_cluster_within(ends, n, total, [super::TOL_MM, super::TOL_DEG])
}

/// [`largest_cluster`] with ends within `tol` (mm, degrees) of the seed
/// counted as one cluster, and the spread in units of `tol`.
pub(crate) fn largest_cluster_within(
    ends: &[Pose],
    n: usize,
    total: usize,
    tol: [f64; 2],
) -> Option<(f64, Pose, f64)> {
    let off = |a: &Pose, b: &Pose| {
        let (d, t) = pose_error(a, b, n);
        (1e3 * d / tol[0], t.abs().to_degrees() / tol[1])
    };
    let near = |a: &Pose, b: &Pose| {
        let (d, t) = off(a, b);
        d <= 1.0 && t <= 1.0
    };
    let members = |seed: &Pose| ends.iter().filter(|e| near(e, seed)).collect::<Vec<_>>();
    // The first seed with the most members (ties to the earlier drop).
    let seed = ends
        .iter()
        .enumerate()
        .max_by(|a, b| {
            let (ca, cb) = (members(a.1).len(), members(b.1).len());
            ca.cmp(&cb).then(b.0.cmp(&a.0))
        })?
        .1;
    let m = members(seed);
    let k = m.len() as f64;
    let (r, dt) = m.iter().fold((V2::zeros(), 0.0), |(r, dt), e| {
        (r + e.r, dt + wrap_symmetric(e.theta - seed.theta, n))
    });
    let pose = Pose {
        r: r / k,
        theta: crate::pose::wrap(seed.theta + dt / k),
    };
    let spread = m
        .iter()
        .map(|e| off(e, &pose))
        .map(|(d, t)| d + t)
        .sum::<f64>()
        / k;
    Some((k / total.max(1) as f64, pose, spread))
}

/// The probes' end poses on `schedule` played for [`PROBE_S`] (at
/// least [`super::cycle::SETTLE_PERIODS`] of its periods) at `friction`
/// (`None`: the schedule's own), `None` for a probe that lost contact.
///
/// # Errors
/// A schedule that cannot be played.
pub fn probe_ends(
    req: &PoseTarget,
    schedule: &Schedule,
    friction: Option<Friction>,
) -> Result<Vec<Option<Pose>>> {
    probe_ends_for(req, schedule, friction, PROBE_S)
}

/// [`probe_ends`] played for `seconds` (at least
/// [`super::cycle::SETTLE_PERIODS`] of the schedule's periods).
fn probe_ends_for(
    req: &PoseTarget,
    schedule: &Schedule,
    friction: Option<Friction>,
    seconds: f64,
) -> Result<Vec<Option<Pose>>> {
    let mut schedule = schedule.clone();
    if let Some(f) = friction {
        schedule.settings.friction = f;
    }
    let sm = ScheduleMotion::from_schedule(&schedule)?;
    let starts = probe_starts(&req.region.inset(req.part.radius()));
    let play = DropPlay::new(&schedule.settings, settle_seconds(seconds, sm.period()));
    Ok(play_part(&req.part, &sm, &starts, &play)
        .into_iter()
        .map(|run| run.ok().map(|(end, _)| end.pose))
        .collect())
}

/// The largest cluster of the probes' ends on `schedule` played for
/// `seconds` at `friction` (module docs).
fn cluster_at(
    req: &PoseTarget,
    schedule: &Schedule,
    friction: Option<Friction>,
    seconds: f64,
) -> Result<Option<(f64, Pose, f64)>> {
    let ends: Vec<Pose> = probe_ends_for(req, schedule, friction, seconds)?
        .into_iter()
        .flatten()
        .collect();
    Ok(largest_cluster(&ends, req.part.symmetry(), PROBES))
}

/// The cycle of `spun` whose spin stage rests at `rest` (centred) with
/// `ellipse` played for `stages`, placed so that `rest` falls on the
/// asked pose and scaled into the shaker limits, as `design` ships it
/// (module docs); with that placement.
///
/// # Errors
/// `spun` or `ellipse` is not one six-signal motion; a placed stage over a
/// limit of 0.
pub(crate) fn placed_cycle(
    req: &PoseTarget,
    (spun, ellipse): (&Schedule, &EllipseStage),
    rest: &Pose,
    stages: Stages,
) -> Result<(Schedule, Placement)> {
    let centred = cycle(spun, ellipse, rest, stages)?;
    let placement = Placement::onto(rest, &req.pose, req.part.symmetry());
    Ok((placement.schedule(&centred, None)?, placement))
}

/// `spin` added to the centred `sink` and judged by play in its placed
/// cycle with `ellipse` played for `stages` (module docs), over the pose
/// target's friction range when it states one.
///
/// # Errors
/// `sink` or `ellipse` is not one six-signal motion.
pub fn screen(
    req: &PoseTarget,
    sink: &Schedule,
    ellipse: &EllipseStage,
    (spin, stages): (Spin, Stages),
) -> Result<Screened> {
    let spun = spun(sink, spin)?;
    let Some(alone) = cluster_at(req, &spun, None, PROBE_S)? else {
        return Ok(Screened::unplayed(spin, Some(stages), None));
    };
    let (placed, placement) = placed_cycle(req, (&spun, ellipse), &alone.1, stages)?;
    let handover = super::handover::handover(req, &placed)?;
    let (stages, (placed, placement)) = match handover {
        Some(h) if h.worst_deg >= super::cycle::ELLIPSE_TURN_DEG => {
            return Ok(Screened::unplayed(spin, Some(stages), handover));
        }
        Some(h) => {
            let starts = req.region.inset(req.part.radius());
            let timed = Stages::handed_over((h.seconds, h.worst_deg), ellipse.rate(), &starts);
            (timed, placed_cycle(req, (&spun, ellipse), &alone.1, timed)?)
        }
        None => (stages, (placed, placement)),
    };
    let best = cluster_at(req, &placed, None, CYCLE_S)?;
    let mut score = best.map_or(0.0, |b| b.0);
    let turn = match req.friction_ends() {
        None => None,
        Some(ends) => {
            let [lo, hi] = [
                cluster_at(req, &placed, Some(ends[0]), CYCLE_S)?,
                cluster_at(req, &placed, Some(ends[1]), CYCLE_S)?,
            ];
            score = [lo, hi]
                .iter()
                .fold(score, |s, c| s.min(c.map_or(0.0, |c| c.0)));
            // A placement is rigid: distances and turns between the two
            // ends' poses are the centred motion's.
            Some(match (lo, hi) {
                (Some(a), Some(b)) => {
                    let (d, t) = pose_error(&a.1, &b.1, req.part.symmetry());
                    (1e3 * d / super::TOL_MM).max(t.abs().to_degrees() / super::TOL_DEG)
                }
                _ => f64::INFINITY,
            })
        }
    };
    Ok(Screened {
        spin,
        stages: Some(stages),
        handover,
        spin_rest: Some(alone.1),
        score,
        spread: best.map_or(f64::INFINITY, |b| b.2),
        pose: best.map(|b| placement.unapply(&b.1)),
        turn,
    })
}

/// The stage lengths of `tried`'s cycle with `ellipse` for `req`'s drops
/// ([`Stages::derive`]): `None` when its lifted field has no stable pose or
/// turns too slowly.
pub(crate) fn stages_of(
    req: &PoseTarget,
    ellipse: &EllipseStage,
    tried: &super::spin::Tried,
) -> Option<Stages> {
    let starts = req.region.inset(req.part.radius());
    Stages::derive(slowest_rate(&tried.stable), ellipse.rate(), &starts)
}

/// Every candidate of `tried` with a lifted stable pose added to the
/// centred `sink` and judged by play in its cycle with `ellipse` (those
/// turning too slowly for [`super::cycle::MAX_STAGE_S`] listed unplayed),
/// and the kept one (module docs).
///
/// # Errors
/// `sink` is not one six-signal motion.
pub(crate) fn choose(
    req: &PoseTarget,
    (sink, ellipse): (&Schedule, &EllipseStage),
    tried: &[super::spin::Tried],
) -> Result<(Vec<Screened>, Option<Screened>)> {
    let screened = tried
        .iter()
        .filter(|t| !t.stable.is_empty())
        .map(|t| match stages_of(req, ellipse, t) {
            Some(stages) => screen(req, sink, ellipse, (t.spin, stages)),
            None => Ok(Screened::unplayed(t.spin, None, None)),
        })
        .collect::<Result<Vec<_>>>()?;
    let kept = best(&within_turn(&screened))
        .filter(|s| s.score >= MIN_SHARE)
        .cloned();
    Ok((screened, kept))
}

/// The candidates whose pose turns by at most [`MAX_TURN`] tolerances
/// over the friction range (all of them for an exact friction).
fn within_turn(screened: &[Screened]) -> Vec<Screened> {
    screened
        .iter()
        .filter(|s| s.turn.is_none_or(|t| t <= MAX_TURN))
        .cloned()
        .collect()
}

/// The largest share, then (over a friction range) the least turn, then
/// the shortest cycle, then the least spread, then the earliest.
fn best(screened: &[Screened]) -> Option<&Screened> {
    let turn = |s: &Screened| s.turn.unwrap_or(0.0);
    let period = |s: &Screened| s.stages.map_or(f64::INFINITY, |t| t.period());
    screened.iter().rev().max_by(|a, b| {
        a.score
            .total_cmp(&b.score)
            .then(turn(b).total_cmp(&turn(a)))
            .then(period(b).total_cmp(&period(a)))
            .then(b.spread.total_cmp(&a.spread))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn screened(score: f64, spread: f64, alpha: f64) -> Screened {
        Screened {
            spin: Spin {
                alpha,
                phase: 0.0,
                translation: 0.25,
            },
            stages: None,
            handover: None,
            spin_rest: None,
            score,
            spread,
            pose: None,
            turn: None,
        }
    }

    /// The largest share wins, then the least spread, then the earlier.
    #[test]
    fn best_takes_share_then_spread_then_order() {
        let s = [
            screened(0.875, 0.1, 1.0),
            screened(1.0, 0.5, 2.0),
            screened(1.0, 0.3, 3.0),
            screened(1.0, 0.3, 4.0),
        ];
        assert_eq!(best(&s).unwrap().spin.alpha, 3.0);
        assert_eq!(best(&s[..2]).unwrap().spin.alpha, 2.0);
        assert_eq!(best(&s[..1]).unwrap().spin.alpha, 1.0);
        assert!(best(&[]).is_none());
    }

    /// Among equal shares the shorter cycle wins before the tighter
    /// cluster; a candidate without stages (too slow, not played) loses.
    #[test]
    fn equal_shares_keep_the_shorter_cycle() {
        let timed = |spread: f64, alpha: f64, stages: Option<(f64, f64)>| Screened {
            stages: stages.map(|(spin_s, ellipse_s)| Stages { spin_s, ellipse_s }),
            ..screened(1.0, spread, alpha)
        };
        let s = [
            timed(0.0, 1.0, Some((30.0, 5.0))),
            timed(0.5, 2.0, Some((10.0, 5.0))),
            timed(0.0, 3.0, None),
        ];
        assert_eq!(best(&s).unwrap().spin.alpha, 2.0);
        assert_eq!(best(&[s[0].clone(), s[2].clone()]).unwrap().spin.alpha, 1.0);
    }

    /// Over a friction range only a candidate whose pose turns by at most
    /// [`MAX_TURN`] tolerances can be kept, however large its share; among
    /// equal shares the least turn wins before the least spread (the
    /// bracket's range: 900 × 0.25 turning 1.31 before 1200 × 0.4 turning
    /// 1.90 with the tighter cluster).
    #[test]
    fn a_range_keeps_only_a_spin_that_turns_little() {
        let turning = |score: f64, turn: Option<f64>, spread: f64, alpha: f64| Screened {
            turn,
            ..screened(score, spread, alpha)
        };
        let s = [
            turning(1.0, Some(2.5), 0.1, 1.0),
            turning(0.8, Some(1.5), 0.1, 2.0),
        ];
        assert_eq!(best(&within_turn(&s)).unwrap().spin.alpha, 2.0);
        assert_eq!(best(&s).unwrap().spin.alpha, 1.0);
        let bracket = [
            turning(1.0, Some(1.31), 0.02, 900.0),
            turning(1.0, Some(1.90), 0.00, 1200.0),
        ];
        assert_eq!(best(&within_turn(&bracket)).unwrap().spin.alpha, 900.0);
    }

    /// Each of the last [`GRID`] starts is its grid start's 180° twin: the
    /// same centre (within 1e-15 m) and θ + π wrapped into (−π, π] (within
    /// 1e-12 rad), so every grid start is probed from both halves of
    /// orientation.
    #[test]
    fn each_grid_start_has_its_half_turn_twin() {
        let s = probe_starts(&Region {
            x: [-0.03, 0.01],
            y: [-0.02, 0.02],
        });
        assert_eq!((s.len(), PROBES), (32, 2 * GRID));
        for (a, b) in s[..GRID].iter().zip(&s[GRID..]) {
            assert!((a.r - b.r).norm() < 1e-15);
            assert!(b.theta > -std::f64::consts::PI && b.theta <= std::f64::consts::PI);
            let turned = (b.theta - a.theta).rem_euclid(std::f64::consts::TAU);
            assert!((turned - std::f64::consts::PI).abs() < 1e-12, "{turned}");
        }
    }

    /// Two clusters of three and two ends among six drops: the larger
    /// wins, its share out of all six; symmetry 2 joins ends 180° apart.
    #[test]
    fn largest_cluster_counts_modulo_symmetry() {
        let p = |x: f64, t: f64| Pose::new(x, 0.0, t.to_radians());
        let ends = [
            p(0.0, 10.0),
            p(0.0, 11.0),
            p(0.01, 50.0),
            p(0.0, 12.0),
            p(0.01, 51.0),
        ];
        let (share, pose, _) = largest_cluster(&ends, 1, 6).unwrap();
        assert_eq!(share, 0.5);
        assert!((pose.theta.to_degrees() - 11.0).abs() < 1e-9);
        let turned = [p(0.0, 10.0), p(0.0, 190.5), p(0.01, 50.0)];
        assert_eq!(largest_cluster(&turned, 2, 3).unwrap().0, 2.0 / 3.0);
        assert_eq!(largest_cluster(&turned, 1, 3).unwrap().0, 1.0 / 3.0);
    }

    /// A worked example of `pose::design::screen::probe_starts`.
    #[test]
    fn example_probe_starts() {
        use crate::pose::design::screen::{probe_starts, GRID, PROBES};
        use crate::pose::Region;
        let s = probe_starts(&Region {
            x: [-0.02, 0.02],
            y: [-0.02, 0.02],
        });
        assert_eq!(s.len(), PROBES);
        assert!((s[0].r.x + 0.015).abs() < 1e-15 && s[0].theta == 0.0);
        // The twin of the first start: the same centre, turned by a half turn.
        assert!((s[GRID].r - s[0].r).norm() < 1e-15);
        assert!((s[GRID].theta.abs() - std::f64::consts::PI).abs() < 1e-12);
    }
}
