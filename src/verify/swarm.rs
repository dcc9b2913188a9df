//! Where point parts end up under a schedule, and how long they take.
//!
//! A swarm of point parts is started on a grid over the target region, each
//! placed on the plate at rest relative to it, and the schedule is played
//! for whole schedule periods ([`crate::play::Player`], inertial velocity
//! continuous at joins) with the kinematics evaluated where each part is
//! (the `moving` switch is forced on: a part's destination depends on the
//! field along its path). Positions are recorded at every segment end.
//!
//! **Convergence.** For a target with an [`Attractor`] (a sink's centre, a
//! line sink's line), a part has converged when its distance to the
//! attractor is within `tol` at the end and stays within it from some time
//! on; its time to converge is that time, located by linear interpolation
//! of the distance between the two segment ends that bracket the last
//! crossing of `tol` (segment ends are at most one segment apart, so the
//! interpolation error is below one segment's duration).
//!
//! **Prediction.** The design promises the target field scaled by its
//! achieved strength σ; along it a part reaches `tol` after
//! ln(d₀/tol)/(σ s) ([`Attractor::predicted_time`]). The swarm reports the
//! median of measured and of predicted times over the parts that start
//! outside `tol` and converge, and their ratio.
//!
//! A part that leaves the plate is reported with where and when, and counts
//! as not converged.

use rayon::prelude::*;
use serde::Serialize;

use crate::dynamics::PartState;
use crate::play::{ScheduleMotion, V2};
use crate::request::Attractor;

use crate::play::PlayOptions;

/// Settings of a swarm run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwarmOptions {
    /// Physics and numerics (the `moving` switch is forced on).
    pub verify: PlayOptions,
    /// Whole schedule periods played.
    pub periods: u32,
    /// Convergence tolerance on the distance to the attractor (m).
    pub tol: f64,
    /// The design's achieved strength σ (scales the target's rate).
    pub strength: f64,
}

/// One part of the swarm.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SwarmPart {
    /// Start position (m).
    pub start: [f64; 2],
    /// Final position (m) (where contact was lost, for an invalid part).
    pub end: [f64; 2],
    /// Distance to the attractor at the start and at the end (m).
    pub distance: [f64; 2],
    /// Within `tol` of the attractor at the end and from its convergence time on.
    pub converged: bool,
    /// Time to converge (s); `None` if it did not (0 if it started within `tol`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_to_converge_s: Option<f64>,
    /// Time the design's field predicts (s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub predicted_time_s: Option<f64>,
    /// Why the part is invalid (left the plate).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// Positions at the start and at every segment end (m).
    #[serde(skip)]
    pub path: Vec<[f64; 2]>,
}

/// A swarm run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Swarm {
    /// The target's attractor, if any.
    pub attractor: Option<Attractor>,
    /// Convergence tolerance (m).
    pub tol: f64,
    /// Time played (s).
    pub duration_s: f64,
    /// Fraction of all parts converged (`None` without an attractor).
    pub converged_fraction: Option<f64>,
    /// Parts that left the plate.
    pub contact_lost: usize,
    /// Median measured time to converge over converged parts that started
    /// outside `tol` (s).
    pub median_time_to_converge_s: Option<f64>,
    /// Median predicted time over the same parts (s).
    pub median_predicted_time_s: Option<f64>,
    /// Measured over predicted median.
    pub time_ratio: Option<f64>,
    /// Per part.
    pub parts: Vec<SwarmPart>,
}

/// Median of a non-empty list (mean of the middle two for even length).
pub(crate) fn median(values: &[f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

/// Time at which the distance series `(t, d)` last comes within `tol` and
/// stays there (linear interpolation across the last crossing); `None` if
/// it ends outside.
pub(crate) fn convergence_time(series: &[(f64, f64)], tol: f64) -> Option<f64> {
    let (&(_, d_end), _) = series.split_last()?;
    if d_end > tol {
        return None;
    }
    match series.iter().rposition(|&(_, d)| d > tol) {
        None => Some(series[0].0),
        Some(k) => {
            let (t0, d0) = series[k];
            let (t1, d1) = series[k + 1];
            Some(t0 + (t1 - t0) * (d0 - tol) / (d0 - d1))
        }
    }
}

fn one_part(
    sm: &ScheduleMotion,
    start: [f64; 2],
    attractor: Option<&Attractor>,
    opts: &SwarmOptions,
) -> SwarmPart {
    let player = opts.verify.moving_player(sm);
    let anchor = V2::from(start);
    let mut state = PartState::new(anchor, V2::zeros());
    let mut path = Vec::new();
    let mut series = Vec::new();
    let dist = |p: [f64; 2]| attractor.map_or(f64::NAN, |a| a.distance(p));
    let played = player.play_periods(&mut state, &anchor, 0, opts.periods, |t, _, s| {
        let p = [s.r.x, s.r.y];
        path.push(p);
        series.push((t, dist(p)));
    });
    let end = [state.r.x, state.r.y];
    let predicted = attractor.map(|a| a.predicted_time(start, opts.strength, opts.tol));
    match played {
        Err(loss) => SwarmPart {
            start,
            end: loss.loss.position,
            distance: [dist(start), dist(loss.loss.position)],
            converged: false,
            time_to_converge_s: None,
            predicted_time_s: predicted,
            note: Some(loss.to_string()),
            path,
        },
        Ok(()) => {
            let time = attractor.and_then(|_| convergence_time(&series, opts.tol));
            SwarmPart {
                start,
                end,
                distance: [dist(start), dist(end)],
                converged: time.is_some(),
                time_to_converge_s: time,
                predicted_time_s: predicted,
                note: None,
                path,
            }
        }
    }
}

/// Plays `sm` on point parts started at `starts` (in parallel, collected in
/// input order) and summarises where they end up.
pub fn run_swarm(
    sm: &ScheduleMotion,
    starts: &[[f64; 2]],
    attractor: Option<Attractor>,
    opts: &SwarmOptions,
) -> Swarm {
    run_swarm_ticked(sm, starts, attractor, opts, &|| ())
}

/// [`run_swarm`], calling `tick` after each part is played (progress).
pub(crate) fn run_swarm_ticked(
    sm: &ScheduleMotion,
    starts: &[[f64; 2]],
    attractor: Option<Attractor>,
    opts: &SwarmOptions,
    tick: &(dyn Fn() + Sync),
) -> Swarm {
    let parts: Vec<SwarmPart> = starts
        .par_iter()
        .map(|p| {
            let part = one_part(sm, *p, attractor.as_ref(), opts);
            tick();
            part
        })
        .collect();
    let timed: Vec<&SwarmPart> = parts
        .iter()
        .filter(|p| p.converged && p.distance[0] > opts.tol)
        .collect();
    let measured: Vec<f64> = timed.iter().filter_map(|p| p.time_to_converge_s).collect();
    let predicted: Vec<f64> = timed.iter().filter_map(|p| p.predicted_time_s).collect();
    let median_time_to_converge_s = median(&measured);
    let median_predicted_time_s = median(&predicted);
    let time_ratio = match (median_time_to_converge_s, median_predicted_time_s) {
        (Some(m), Some(p)) if p > 0.0 => Some(m / p),
        _ => None,
    };
    Swarm {
        attractor,
        tol: opts.tol,
        duration_s: f64::from(opts.periods) * sm.period(),
        converged_fraction: attractor.map(|_| {
            parts.iter().filter(|p| p.converged).count() as f64 / parts.len().max(1) as f64
        }),
        contact_lost: parts.iter().filter(|p| p.note.is_some()).count(),
        median_time_to_converge_s,
        median_predicted_time_s,
        time_ratio,
        parts,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn convergence_time_interpolates_the_last_crossing() {
        let s = [(0.0, 5.0), (1.0, 2.0), (2.0, 4.0), (3.0, 2.0), (4.0, 1.0)];
        // Last sample above 3 is t = 2 (d = 4); next is d = 2: crossing at 2.5.
        assert_eq!(convergence_time(&s, 3.0), Some(2.5));
        assert_eq!(convergence_time(&s, 0.5), None);
        assert_eq!(convergence_time(&s, 6.0), Some(0.0));
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median(&[]), None);
    }
}
