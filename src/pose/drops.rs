//! Drops played by the planar simulator: a part placed at rest at a random
//! pose on a plate playing a schedule, simulated by [`PlanarSimulator`]
//! (every support point's own stick-slip, no averaging) for whole schedule
//! periods, and its end pose classified by the nearest stable equilibrium
//! of the lifted field. This is the measured basin the lifted field's
//! prediction ([`super::settle`]) is judged against.
//!
//! **Schedule.** Segment after segment from phase 0, repeated; rest
//! segments with the plate at rest in the home pose. At a join the part's
//! inertial planar velocity is kept continuous, as for the verified
//! rectangles ([`crate::verify::plate_twist`]).
//!
//! **Determinism.** Drops are independent and played in parallel (rayon);
//! each drop's arithmetic does not depend on the thread that plays it, so
//! the results are the same bytes on 1 or 2 threads.

use rayon::prelude::*;

use super::equilibria::{wrap, Equilibrium};
use super::lifted::Pose;
use crate::dynamics::{
    Friction, Model, PlanarBody, PlanarSimulator, PlanarState, Plate, PLANAR_REFINE_DEPTH,
};
use crate::play::{PlayLoss, ScheduleMotion};
use crate::verify::plate_twist;

/// How drops are played.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DropPlay {
    /// Friction coefficients.
    pub friction: Friction,
    /// Gravity (m/s²).
    pub gravity: f64,
    /// Model switches.
    pub model: Model,
    /// Least simulated time (s); played as whole schedule periods.
    pub duration_s: f64,
    /// Planar integrator steps per cycle of each moving segment.
    pub steps_per_cycle: usize,
    /// How many times a step holding a stick-slip event may be halved.
    pub refine_depth: u32,
}

impl DropPlay {
    /// `duration_s` of play with the schedule's settings, 64 steps per
    /// cycle and the default event refinement.
    pub fn new(settings: &crate::field::FieldSettings, duration_s: f64) -> DropPlay {
        DropPlay {
            friction: settings.friction,
            gravity: settings.gravity,
            model: settings.model,
            duration_s,
            steps_per_cycle: 64,
            refine_depth: PLANAR_REFINE_DEPTH,
        }
    }
}

/// Where one drop ended and what it cost.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DropEnd {
    /// The end pose (θ unwrapped: the total turn is kept).
    pub pose: Pose,
    /// Simulated time (s).
    pub time: f64,
    /// Integrator steps taken (refined halves included).
    pub steps: u64,
}

/// Plays `body` from rest at `start` through `sm` for whole periods
/// covering `play.duration_s` (module docs).
pub fn play_drop(
    sm: &ScheduleMotion,
    body: &PlanarBody,
    start: Pose,
    play: &DropPlay,
) -> Result<DropEnd, PlayLoss> {
    let segments = sm.segments();
    let shortest = segments
        .iter()
        .filter_map(|s| s.motion.as_ref().map(|m| m.period()))
        .fold(f64::INFINITY, f64::min);
    let sims: Vec<PlanarSimulator> = segments
        .iter()
        .map(|s| {
            let (plate, step) = match &s.motion {
                Some(m) => (Plate::Moving(m), m.period()),
                None => (Plate::Rest, shortest),
            };
            PlanarSimulator::for_body(
                body.clone(),
                plate,
                play.friction,
                play.gravity,
                play.model,
                step / play.steps_per_cycle.max(1) as f64,
            )
            .with_refinement(play.refine_depth)
        })
        .collect();
    let periods = (play.duration_s / sm.period()).ceil().max(1.0) as u32;
    let mut s = PlanarState::at_rest(start.r, start.theta);
    let anchor = (start.r, start.theta);
    let mut steps = 0;
    let n = segments.len();
    for period in 0..periods {
        for (i, seg) in segments.iter().enumerate() {
            if period > 0 || i > 0 {
                let from = &segments[(i + n - 1) % n];
                let p = if play.model.moving { s.r } else { anchor.0 };
                let (va, wa) = plate_twist(from, play.gravity, play.model.tilt, &p);
                let (vb, wb) = plate_twist(seg, play.gravity, play.model.tilt, &p);
                s.u += va - vb;
                s.omega += wa - wb;
            }
            let out = sims[i]
                .advance(0.0, seg.duration, &mut s, anchor, None)
                .map_err(|loss| PlayLoss {
                    segment: i,
                    period,
                    loss,
                })?;
            steps += out.steps;
        }
    }
    Ok(DropEnd {
        pose: Pose {
            r: s.r,
            theta: s.theta,
        },
        time: f64::from(periods) * sm.period(),
        steps,
    })
}

/// Every start played (in parallel, module docs), in the order given.
pub fn play_drops(
    sm: &ScheduleMotion,
    body: &PlanarBody,
    starts: &[Pose],
    play: &DropPlay,
) -> Vec<Result<DropEnd, PlayLoss>> {
    starts
        .par_iter()
        .map(|s| play_drop(sm, body, *s, play))
        .collect()
}

/// The stable equilibrium nearest to `pose` in the metric
/// |Δr| / `radius` + |Δθ| (θ modulo 360°), with that distance.
pub fn nearest(stable: &[Equilibrium], pose: &Pose, radius: f64) -> Option<(usize, f64)> {
    stable
        .iter()
        .map(|e| {
            (e.pose.r - pose.r).norm() / radius.max(f64::MIN_POSITIVE)
                + wrap(e.pose.theta - pose.theta).abs()
        })
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The basins measured by playing an analysis's drops ([`super::drop_starts`])
/// with the planar simulator.
#[derive(Debug, Clone, PartialEq)]
pub struct PlayedBasins {
    /// Per drop: the index in the analysis's `equilibria` of the stable
    /// pose nearest to its end, `None` when it lost contact.
    pub ends: Vec<Option<usize>>,
    /// Fraction of the drops ending nearest to each equilibrium (0 for the
    /// unstable ones).
    pub basins: Vec<f64>,
    /// Fraction of the drops whose played end is the lifted field's
    /// predicted one (the per-drop agreement; a basin differs from its
    /// prediction by at most 1 − this).
    pub agreement: f64,
    /// Largest distance of a played end from its nearest stable pose, in
    /// the metric of [`nearest`] (|Δr|/R + |Δθ| in rad).
    pub worst: f64,
    /// Drops that lost contact.
    pub lost: usize,
    /// Simulated time per drop (s).
    pub time: f64,
    /// Integrator steps over all drops.
    pub steps: u64,
}

/// Plays the drops of `analysis` (same starts, same order) for `part`
/// through `sm` and classifies each end by its nearest stable pose.
pub fn played_basins(
    analysis: &super::PoseAnalysis,
    part: &crate::part::Part,
    sm: &ScheduleMotion,
    play: &DropPlay,
) -> PlayedBasins {
    let eq = &analysis.equilibria;
    let index: Vec<usize> = (0..eq.len()).filter(|&i| eq[i].stable).collect();
    let stable: Vec<Equilibrium> = index.iter().map(|&i| eq[i]).collect();
    let starts = super::drop_starts(&analysis.starts, analysis.drops);
    let runs = play_drops(sm, &part.body, &starts, play);
    let radius = part.radius();
    let mut worst: f64 = 0.0;
    let (mut steps, mut time) = (0, 0.0);
    let ends: Vec<Option<usize>> = runs
        .iter()
        .map(|run| {
            let end = run.as_ref().ok()?;
            steps += end.steps;
            time = end.time;
            let (k, d) = nearest(&stable, &end.pose, radius)?;
            worst = worst.max(d);
            Some(index[k])
        })
        .collect();
    let n = ends.len().max(1) as f64;
    let basins = (0..eq.len())
        .map(|i| ends.iter().filter(|e| **e == Some(i)).count() as f64 / n)
        .collect();
    let same = ends
        .iter()
        .zip(&analysis.ends)
        .filter(|(a, b)| a.is_some() && a == b)
        .count();
    PlayedBasins {
        lost: runs.iter().filter(|r| r.is_err()).count(),
        agreement: same as f64 / n,
        ends,
        basins,
        worst,
        time,
        steps,
    }
}
