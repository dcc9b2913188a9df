//! The placement corrected by play: the lifted field of the designed
//! schedule's predicted point field places the pose only as well as that
//! field and the lifted model hold, and played drops end millimetres
//! away (`results/poses.md` says why). So the kept candidate is placed
//! again on played drops: [`PROBES`] drops started at and around the asked
//! pose are played for [`PROBE_S`]; their mean end (modulo the part's
//! symmetry) moves the candidate by the same turn-and-shift step as the
//! lifted placement ([`super::search::replace`]), at most [`ROUNDS`]
//! designs, until the mean end is within [`DONE_MM`] and [`DONE_DEG`].
//! The round whose mean end is nearest is kept.

use super::search::{pose_error, replace, trial_at, wrap_symmetric, Trial};
use super::PoseRequest;
use crate::design::DesignOptions;
use crate::dynamics::V2;
use crate::error::Result;
use crate::field::Grid;
use crate::play::ScheduleMotion;
use crate::pose::{play_part, DropPlay, Pose};

/// Probe drops per round.
pub const PROBES: usize = 4;
/// Seconds each probe plays.
pub const PROBE_S: f64 = 40.0;
/// Most designs.
pub const ROUNDS: usize = 3;
/// Done when the probes' mean end is this close (mm) …
pub const DONE_MM: f64 = 0.2;
/// … and this close (degrees).
pub const DONE_DEG: f64 = 0.5;

/// One round: where the candidate was and where its probes ended.
#[derive(Debug, Clone, PartialEq)]
pub struct Round {
    /// Centre (m) of the requested field.
    pub center: V2,
    /// Its angle (degrees).
    pub angle: f64,
    /// The probes' mean end (θ the asked one plus the mean error modulo
    /// symmetry).
    pub end: Pose,
    /// Its error: |Δr| (mm), Δθ (degrees).
    pub error: (f64, f64),
}

/// The probe starts around `asked`: at it, and 2 mm and 5° off it.
fn probe_starts(asked: &Pose) -> Vec<Pose> {
    let off: [(f64, f64, f64); 4] = [
        (0.0, 0.0, 0.0),
        (2.0, 0.0, 5.0),
        (0.0, 2.0, -5.0),
        (-2.0, -2.0, 0.0),
    ];
    off.iter()
        .take(PROBES)
        .map(|(x, y, t)| {
            Pose::new(
                asked.r.x + 1e-3 * x,
                asked.r.y + 1e-3 * y,
                asked.theta + t.to_radians(),
            )
        })
        .collect()
}

/// The probes of `trial` played: their mean end, `None` when one lost
/// contact.
fn probe(req: &PoseRequest, trial: &Trial) -> Result<Option<Pose>> {
    let schedule = &trial.design.schedule;
    let sm = ScheduleMotion::from_schedule(schedule)?;
    let starts = probe_starts(&req.pose);
    let play = DropPlay::new(&schedule.settings, PROBE_S);
    let n = req.part.symmetry();
    let (mut r, mut dt) = (V2::zeros(), 0.0);
    for run in play_part(&req.part, &sm, &starts, &play) {
        let Ok((end, _)) = run else {
            return Ok(None);
        };
        r += end.pose.r;
        dt += wrap_symmetric(end.pose.theta - req.pose.theta, n);
    }
    let k = starts.len() as f64;
    Ok(Some(Pose {
        r: r / k,
        theta: req.pose.theta + dt / k,
    }))
}

/// `trial` placed again on played probes (module docs): the trial kept
/// and every round.
pub fn correct(
    req: &PoseRequest,
    opts: &DesignOptions,
    trial: Trial,
) -> Result<(Trial, Vec<Round>)> {
    let grid = req.target.grid.unwrap_or(Grid::DEFAULT);
    let n = req.part.symmetry();
    let mut rounds: Vec<Round> = Vec::new();
    let (mut best, mut best_err) = (trial.clone(), f64::INFINITY);
    let mut current = trial;
    for round in 0..ROUNDS {
        let Some(end) = probe(req, &current)? else {
            break;
        };
        let (d, t) = pose_error(&end, &req.pose, n);
        let (mm, deg) = (1e3 * d, t.to_degrees());
        rounds.push(Round {
            center: current.center,
            angle: current.angle,
            end,
            error: (mm, deg),
        });
        let err = mm / super::TOL_MM + deg.abs() / super::TOL_DEG;
        if err < best_err {
            (best, best_err) = (current.clone(), err);
        }
        if (mm <= DONE_MM && deg.abs() <= DONE_DEG) || round + 1 == ROUNDS {
            break;
        }
        let (c, angle) = replace(current.center, current.angle, &end, &req.pose, n);
        let designs = current.designs;
        current = trial_at(req, opts, (current.family, c, angle), &grid)?;
        current.designs = designs + 1;
    }
    Ok((best, rounds))
}
