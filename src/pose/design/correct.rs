//! The placement corrected by play, on one fixed motion.
//!
//! The lifted field places the part only as well as the point field and
//! the lifted model hold; the played equilibrium of the placed motion is
//! measured and the placement corrected. Since a placement turns and
//! shifts the whole physics ([`super::placement`]), the played rest pose
//! moves with it exactly as the lifted one does: [`PROBES`] drops from
//! starts spread over the region ([`FROM_GRID`]) are played for
//! [`PROBE_S`], their mean end
//! (modulo the part's symmetry, or half a turn for the elliptic sink
//! alone, whose two rests 180° apart a part without that symmetry cannot
//! tell: `rest_symmetry`; over the largest group of ends within
//! [`SAME_REST`] of one another, so that probes resting at two poses are
//! never averaged into a pose between them, which no probe reached) is
//! taken back to the centred motion and
//! the placement moved onto the asked pose (`Placement::corrected`,
//! gain 1, halved whenever a round ends farther than the best so far: a
//! damped step). The motion is never redesigned, so the rest pose cannot
//! jump. At most [`ROUNDS`] rounds, until within [`DONE_MM`] and
//! [`DONE_DEG`]; the best round is kept.
//!
//! **Why spread starts.** The drops a design is judged by start anywhere
//! in the region, and where they rest can depend on where they come
//! from: on the triangle's strongest spin, probes started near the asked
//! pose rest on it while drops from spread starts rest several degrees
//! off it, outside the tolerance (measured: `docs/parts.md`, **Measurements behind the pose
//! design's choices**). Probes from
//! spread starts measure the rest the drops reach.
//!
//! **Over a friction range.** When the pose target states a friction range,
//! the probes play at its two ends and the round's end is the midpoint
//! of the two groups' ends: the placement puts the middle of the played
//! rest poses over the range on the asked pose, not the nominal μ's rest.
//! A rest pose that turns with μ by less than twice the tolerance over
//! the range then stays within it at both ends. On the bracket placed at
//! the nominal μ, the low end falls outside the tolerance; centred over the
//! range on a spin whose rest turns nearly the tolerance's span, it still
//! does; so the spin screen over the range ([`super::screen`]) keeps the
//! spin that turns least, which centred holds every drop within the
//! tolerance at both ends and the middle (`targets/pose_bracket_range.json`;
//! measured: `docs/parts.md`, **Measurements behind the pose design's choices**).
//!
//! **Turning rate.** Each probe's angle error against its end, recorded
//! every schedule period, decays as e^{−kt} near the pose; k is fitted by
//! least squares to ln |Δθ| over the samples with
//! [`RATE_BAND_DEG`]`[0]` < |Δθ| < [`RATE_BAND_DEG`]`[1]`, and the probes'
//! median reported beside the lifted field's −∂θ'/∂θ at its stable pose.

use super::placement::Placement;
use super::screen::largest_cluster_within;
use super::search::{pose_error, wrap_symmetric};
use super::PoseTarget;
use crate::dynamics::Friction;
use crate::error::Result;
use crate::play::ScheduleMotion;
use crate::pose::{play_part, DropPlay, Pose};
use crate::schedule::Schedule;

/// Probe drops per round.
pub const PROBES: usize = 4;
/// Seconds each probe plays: as long as the screen's, time for a part
/// dropped at the region's edge to come to rest (the shipped designs'
/// median settle times: `results/poses_friction.md`).
pub const PROBE_S: f64 = super::screen::PROBE_S;
/// The correction's starts among the screen's 4 × 4 grid
/// (`super::screen::probe_starts`, row-major): one in each row and
/// each column, at four different angles.
pub const FROM_GRID: [usize; PROBES] = [1, 7, 8, 14];
/// Most rounds.
pub const ROUNDS: usize = 4;
/// Done when the probes' mean end is this close (mm) …
pub const DONE_MM: f64 = 0.05;
/// … and this close (degrees).
pub const DONE_DEG: f64 = 0.2;
/// Probe ends within this (mm, degrees) of one another rest at one pose:
/// wider than the tolerance, as probes of [`PROBE_S`] may not have
/// settled. Without it, the triangle's probes on a strong spin end far on
/// either side of the asked angle while their mean sits on it
/// (`docs/parts.md`).
pub const SAME_REST: [f64; 2] = [5.0, 15.0];
/// The angle errors (degrees) a turning rate is fitted over.
pub const RATE_BAND_DEG: [f64; 2] = [0.3, 20.0];

/// One round: the placement and where its probes ended.
#[derive(Debug, Clone, PartialEq)]
pub struct Round {
    /// The placement played.
    pub placement: Placement,
    /// The probes' mean end (θ the asked one plus the mean error modulo
    /// symmetry).
    pub end: Pose,
    /// Its error: |Δr| (mm), Δθ (degrees).
    pub error: (f64, f64),
    /// The probes' median played turning rate (1/s), when fitted.
    pub turning_rate: Option<f64>,
    /// Share of the probes in the group whose mean is `end` (0 … 1).
    pub together: f64,
}

/// The probe starts (module docs): [`FROM_GRID`]'s cells of the screen's
/// grid over the region inset by the part's radius.
fn probe_starts(req: &PoseTarget) -> Vec<Pose> {
    let grid = super::screen::probe_starts(&req.region.inset(req.part.radius()));
    FROM_GRID.iter().map(|&k| grid[k]).collect()
}

/// The turning rate of one track (module docs): `None` with fewer than 3
/// samples in the band.
pub(crate) fn turning_rate(track: &[Pose], end: &Pose, n: usize, period: f64) -> Option<f64> {
    let [lo, hi] = RATE_BAND_DEG.map(f64::to_radians);
    let pts: Vec<(f64, f64)> = track
        .iter()
        .enumerate()
        .filter_map(|(k, p)| {
            let e = wrap_symmetric(p.theta - end.theta, n).abs();
            (e > lo && e < hi).then(|| ((k + 1) as f64 * period, e.ln()))
        })
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let m = pts.len() as f64;
    let (st, sl) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    let (tm, lm) = (st / m, sl / m);
    let (num, den) = pts.iter().fold((0.0, 0.0), |a, p| {
        (a.0 + (p.0 - tm) * (p.1 - lm), a.1 + (p.0 - tm).powi(2))
    });
    (den > 0.0).then(|| -num / den)
}

/// The median of `xs` (`None` when empty).
pub(crate) fn median(mut xs: Vec<f64>) -> Option<f64> {
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    (n > 0).then(|| 0.5 * (xs[(n - 1) / 2] + xs[n / 2]))
}

/// The frictions the probes play: the ends of the pose target's friction
/// range when it states one (module docs, "Over a friction range"), else
/// the schedule's own (`None`).
fn probe_frictions(req: &PoseTarget) -> Vec<Option<Friction>> {
    match req.friction_ends() {
        Some(ends) => ends.map(Some).to_vec(),
        None => vec![None],
    }
}

/// The probes of `origin` placed by `p`: the mean end of their largest
/// group at one rest pose (at two frictions: the midpoint of the two),
/// the least share of the probes in such a group and the median turning
/// rate, `None` when one lost contact.
fn probe(
    req: &PoseTarget,
    (origin, n): (&Schedule, usize),
    p: &Placement,
) -> Result<Option<(Pose, f64, Option<f64>)>> {
    let mut schedule = p.schedule(origin, None)?;
    let starts = probe_starts(req);
    let (mut groups, mut rates) = (Vec::new(), Vec::new());
    for friction in probe_frictions(req) {
        if let Some(f) = friction {
            schedule.settings.friction = f;
        }
        let sm = ScheduleMotion::from_schedule(&schedule)?;
        let seconds = super::cycle::settle_seconds(PROBE_S, sm.period());
        let play = DropPlay::new(&schedule.settings, seconds);
        let mut ends = Vec::new();
        for run in play_part(&req.part, &sm, &starts, &play) {
            let Ok((end, track)) = run else {
                return Ok(None);
            };
            rates.extend(turning_rate(&track, &end.pose, n, sm.period()));
            ends.push(end.pose);
        }
        let Some(group) = largest_cluster_within(&ends, n, ends.len(), SAME_REST) else {
            return Ok(None);
        };
        groups.push(group);
    }
    let share = groups.iter().map(|g| g.0).fold(1.0, f64::min);
    let end = match groups.as_slice() {
        [(_, a, _), (_, b, _)] => Pose {
            r: 0.5 * (a.r + b.r),
            theta: a.theta + 0.5 * wrap_symmetric(b.theta - a.theta, n),
        },
        _ => groups[0].1,
    };
    Ok(Some((end, share, median(rates))))
}

/// The symmetry order the rest poses of a placed motion repeat by: the
/// part's own, doubled for the elliptic sink alone on a part without a
/// 180° symmetry, whose two rests lie 180° apart ([`super::placement`]:
/// a linear field turns a part by its second moments only); a cycle's
/// spin tells those two apart ([`super::cycle`]).
pub(crate) fn rest_symmetry(part: usize, cycle: bool) -> usize {
    if cycle || part % 2 == 0 {
        part
    } else {
        2 * part
    }
}

/// `start` corrected on played probes (module docs), poses compared
/// modulo the motion's rest symmetry `n` ([`rest_symmetry`]: with the
/// ellipse alone, a probe at the rest 180° from the asked pose is as
/// close as one on it, and the correction moves the nearer rest onto the
/// asked pose rather than turning the motion by half a turn each round):
/// the best placement and every round.
///
/// # Errors
/// `origin` is not one six-signal motion.
pub(crate) fn correct(
    req: &PoseTarget,
    (origin, n): (&Schedule, usize),
    start: Placement,
) -> Result<(Placement, Vec<Round>)> {
    let mut rounds: Vec<Round> = Vec::new();
    let (mut best, mut best_end, mut best_err) = (start, req.pose, f64::INFINITY);
    let (mut current, mut gain) = (start, 1.0);
    for round in 0..ROUNDS {
        let Some((end, together, turning_rate)) = probe(req, (origin, n), &current)? else {
            break;
        };
        let (d, t) = pose_error(&end, &req.pose, n);
        let (mm, deg) = (1e3 * d, t.to_degrees());
        rounds.push(Round {
            placement: current,
            end,
            error: (mm, deg),
            turning_rate,
            together,
        });
        let err = mm / super::TOL_MM + deg.abs() / super::TOL_DEG;
        if err < best_err {
            (best, best_end, best_err) = (current, end, err);
        } else {
            gain *= 0.5;
        }
        let (bd, bt) = pose_error(&best_end, &req.pose, n);
        if (1e3 * bd <= DONE_MM && bt.abs().to_degrees() <= DONE_DEG) || round + 1 == ROUNDS {
            break;
        }
        current = best.corrected(&best_end, &req.pose, n, gain);
    }
    Ok((best, rounds))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::V2;

    /// The ellipse alone repeats its rests by half a turn; a cycle, or a
    /// part with a 180° symmetry, by the part's own symmetry.
    #[test]
    fn rest_symmetry_doubles_only_the_ellipse_alone_on_odd_parts() {
        assert_eq!(rest_symmetry(1, false), 2);
        assert_eq!(rest_symmetry(3, false), 6);
        assert_eq!(rest_symmetry(2, false), 2);
        assert_eq!(rest_symmetry(4, false), 4);
        assert_eq!(rest_symmetry(1, true), 1);
        assert_eq!(rest_symmetry(3, true), 3);
    }

    /// A probe at the ellipse's rival rest, 178° from the asked pose: the
    /// correction modulo the part's symmetry 1 turns the motion by about
    /// half a turn; modulo the rest symmetry 2 by the 2° that put the
    /// nearer rest on the pose.
    #[test]
    fn the_rival_rest_is_corrected_by_the_small_turn() {
        let asked = Pose::new(0.0, 0.0, 0.0);
        let end = Pose::new(0.0, 0.0, 178f64.to_radians());
        let turn = |n| {
            Placement::IDENTITY
                .corrected(&end, &asked, n, 1.0)
                .angle
                .to_degrees()
        };
        assert!((turn(1).abs() - 178.0).abs() < 1e-9, "{}", turn(1));
        assert!((turn(2) - 2.0).abs() < 1e-9, "{}", turn(2));
    }

    /// An angle error decaying as 15° e^{−0.8 t} (sampled every 0.3 s,
    /// about a rest pose at 170° and wrapped modulo 180°) gives back 0.8
    /// 1/s: only the samples inside the band enter the fit.
    #[test]
    fn turning_rate_fits_an_exponential_decay() {
        let end = Pose::new(0.0, 0.0, 170f64.to_radians());
        let track: Vec<Pose> = (1..=60)
            .map(|k| {
                let t = 0.3 * k as f64;
                let e = 15f64.to_radians() * (-0.8 * t).exp();
                Pose::new(0.0, 0.0, end.theta + e - std::f64::consts::PI)
            })
            .collect();
        let k = turning_rate(&track, &end, 2, 0.3).unwrap();
        assert!((k - 0.8).abs() < 1e-9, "{k}");
        assert_eq!(turning_rate(&track[..2], &end, 2, 0.3), None);
    }

    /// A target with a friction range probes at its two ends; an exact
    /// friction at the schedule's own.
    #[test]
    fn probes_play_the_range_ends() {
        let path = std::path::Path::new("targets/pose_bracket.json");
        let mut req = PoseTarget::load(path).unwrap().unwrap();
        assert_eq!(probe_frictions(&req), vec![None]);
        req.target.friction = Some(crate::request::FrictionSpec::range(0.24, 0.36));
        let mu: Vec<f64> = probe_frictions(&req)
            .iter()
            .map(|f| f.unwrap().kinetic)
            .collect();
        assert_eq!(mu, vec![0.24, 0.36]);
    }

    /// Probes resting at two poses about 102° either side of the asked 60°
    /// (the triangle's case) are not averaged onto it: the first group
    /// (ties to the earlier probe) is the end, 162.25°, with half the
    /// probes; all four within [`SAME_REST`] are one group.
    #[test]
    fn probes_at_two_rests_are_not_averaged() {
        let at = |deg: f64| Pose::new(0.0, 0.0, deg.to_radians());
        let ends = [at(162.0), at(-43.0), at(162.5), at(-42.0)];
        let (share, end, _) = largest_cluster_within(&ends, 1, 4, SAME_REST).unwrap();
        assert_eq!(share, 0.5);
        assert!((end.theta.to_degrees() - 162.25).abs() < 1e-12, "{end:?}");
        let near = [at(60.0), at(70.0), at(52.0), at(63.0)];
        let (share, end, _) = largest_cluster_within(&near, 1, 4, SAME_REST).unwrap();
        assert_eq!(share, 1.0);
        assert!((end.theta.to_degrees() - 61.25).abs() < 1e-12, "{end:?}");
    }

    /// A correction with gain 1 takes the placed rest pose onto the asked
    /// one; gain ½ moves the placement half way.
    #[test]
    fn correction_moves_the_rest_pose_onto_the_asked_one() {
        let p = Placement {
            angle: 0.4,
            shift: V2::new(0.01, -0.005),
        };
        let centred_rest = Pose::new(0.001, 0.002, -0.1);
        let end = p.apply(&centred_rest);
        let asked = Pose::new(0.012, -0.008, 0.5);
        let full = p.corrected(&end, &asked, 1, 1.0);
        let (d, t) = pose_error(&full.apply(&centred_rest), &asked, 1);
        assert!(d < 1e-15 && t.abs() < 1e-15, "{d} {t}");
        let half = p.corrected(&end, &asked, 1, 0.5);
        assert!((half.angle - 0.5 * (p.angle + full.angle)).abs() < 1e-15);
        assert!((half.shift - 0.5 * (p.shift + full.shift)).norm() < 1e-15);
    }
}
