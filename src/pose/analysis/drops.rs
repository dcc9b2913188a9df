//! Drops played by the planar simulator: a part placed at rest at a random
//! pose on a plate playing a schedule, simulated by [`PlanarSimulator`]
//! (every support point's own stick-slip, no averaging) for whole schedule
//! periods, and its end pose classified by the nearest stable equilibrium
//! of the lifted field. This is the measured basin the lifted field's
//! prediction ([`crate::pose::settle`]) is judged against.
//!
//! **Schedule.** Segment after segment from phase 0, repeated; rest
//! segments with the plate at rest in the home pose. At a join the part's
//! inertial planar velocity is kept continuous, as for the verified
//! rectangles ([`crate::play::plate_twist`]).
//!
//! **Determinism.** Drops are independent and played in parallel (rayon);
//! each drop's arithmetic does not depend on the thread that plays it, so
//! the results are the same bytes on 1 or 2 threads.

use rayon::prelude::*;

use super::equilibria::{wrap, Equilibrium};
use super::lifted::Pose;
use crate::dynamics::{
    Friction, Model, PartPhysics, PlanarBody, PlanarSimulator, PlanarState, Plate, SlipRule, V2,
};
use crate::play::plate_twist;
use crate::play::{PlayLoss, ScheduleMotion};

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
    /// Support points of the played body ([`played_basins`]): a uniform
    /// support with more is resampled by about this many
    /// ([`crate::part::Part::coarse_body`]); `None` plays the part's own.
    pub samples: Option<usize>,
    /// How a slipping step treats friction (default [`SlipRule::Midpoint`]).
    pub slip_rule: SlipRule,
}

/// Default support points of a played drop ([`DropPlay::samples`]).
pub const DROP_SAMPLES: usize = 36;

/// Default refinement depth of a played drop ([`DropPlay::refine_depth`]).
pub const DROP_REFINE_DEPTH: u32 = 3;

impl DropPlay {
    /// `duration_s` of play with the schedule's settings, 64 steps per
    /// cycle, [`DROP_REFINE_DEPTH`] and [`DROP_SAMPLES`]: a drop's end
    /// pose is then within a fraction of the pose tolerance of finer steps,
    /// deeper refinement and more support points
    /// (`tests/poses.rs` `drop_defaults_are_converged` checks it; its
    /// cost: `docs/parts.md`, **Played drops: speed and order**).
    ///
    /// ```
    /// use platefield::pose::{DropPlay, DROP_SAMPLES};
    /// let play = DropPlay::new(&platefield::field::FieldSettings::default(), 20.0);
    /// assert_eq!((play.steps_per_cycle, play.samples), (64, Some(DROP_SAMPLES)));
    /// ```
    pub fn new(settings: &crate::field::FieldSettings, duration_s: f64) -> DropPlay {
        DropPlay {
            friction: settings.friction,
            gravity: settings.gravity,
            model: settings.model,
            duration_s,
            steps_per_cycle: 64,
            refine_depth: DROP_REFINE_DEPTH,
            samples: Some(DROP_SAMPLES),
            slip_rule: SlipRule::default(),
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
    /// Steps halved because they held a stick-slip event.
    pub refinements: u64,
    /// Newton iterations of the implicit friction solves.
    pub solver_iterations: u64,
}

/// The cycle a rest segment is stepped at: the shortest moving segment's
/// period.
pub(crate) fn rest_cycle(sm: &ScheduleMotion) -> f64 {
    sm.segments()
        .iter()
        .filter_map(|s| s.motion.as_ref().map(|m| m.period()))
        .fold(f64::INFINITY, f64::min)
}

/// Plays `body` from rest at `start` through `sm` for whole periods
/// covering `play.duration_s` (module docs).
pub fn play_drop(
    sm: &ScheduleMotion,
    body: &PlanarBody,
    start: Pose,
    play: &DropPlay,
) -> Result<DropEnd, PlayLoss> {
    play_drop_tracked(sm, body, start, play).map(|(end, _)| end)
}

/// A body's planar simulators for the segments of a schedule: plays it
/// period by period (module docs).
pub(crate) struct PlanarPlayer<'a> {
    segments: &'a [crate::play::PlayedSegment],
    sims: Vec<PlanarSimulator<'a>>,
    gravity: f64,
    model: Model,
}

impl<'a> PlanarPlayer<'a> {
    /// `body` on `sm` with `play`'s physics, steps per cycle and
    /// refinement depth (its duration and samples are the caller's).
    pub(crate) fn new(
        sm: &'a ScheduleMotion,
        body: &PlanarBody,
        play: &DropPlay,
    ) -> PlanarPlayer<'a> {
        let shortest = rest_cycle(sm);
        let sims = sm
            .segments()
            .iter()
            .map(|s| {
                let (plate, step) = match &s.motion {
                    Some(m) => (Plate::Moving(m), m.period()),
                    None => (Plate::Rest, shortest),
                };
                PlanarSimulator::for_body(
                    body.clone(),
                    plate,
                    PartPhysics::new(play.friction, play.gravity, play.model),
                    step / play.steps_per_cycle.max(1) as f64,
                )
                .with_refinement(play.refine_depth)
                .with_slip_rule(play.slip_rule)
            })
            .collect();
        PlanarPlayer {
            segments: sm.segments(),
            sims,
            gravity: play.gravity,
            model: play.model,
        }
    }

    /// Plays one schedule period (number `period`, for a loss's report)
    /// from `s`, the geometry frozen at `anchor` when the model's `moving`
    /// is off. With `joined` the first segment is entered by a join from
    /// the last (a period that follows another); without, `s` starts it
    /// as it is. Returns the period's cost.
    pub(crate) fn play_period(
        &self,
        s: &mut PlanarState,
        period: u32,
        joined: bool,
        anchor: (V2, f64),
    ) -> Result<crate::dynamics::PlanarOutcome, PlayLoss> {
        let mut cost = crate::dynamics::PlanarOutcome::default();
        let n = self.segments.len();
        for (i, seg) in self.segments.iter().enumerate() {
            if joined || i > 0 {
                let from = &self.segments[(i + n - 1) % n];
                let p = if self.model.moving { s.r } else { anchor.0 };
                let (va, wa) = plate_twist(from, self.gravity, self.model.tilt, &p);
                let (vb, wb) = plate_twist(seg, self.gravity, self.model.tilt, &p);
                s.u += va - vb;
                s.omega += wa - wb;
            }
            cost += self.sims[i]
                .advance(0.0, seg.duration, s, anchor, None)
                .map_err(|loss| PlayLoss {
                    segment: i,
                    period,
                    loss,
                })?;
        }
        Ok(cost)
    }
}

/// [`play_drop`], with the pose at the end of every schedule period (the
/// last is the end pose): when a drop came to rest where it ended.
pub(crate) fn play_drop_tracked(
    sm: &ScheduleMotion,
    body: &PlanarBody,
    start: Pose,
    play: &DropPlay,
) -> Result<(DropEnd, Vec<Pose>), PlayLoss> {
    let player = PlanarPlayer::new(sm, body, play);
    let periods = (play.duration_s / sm.period()).ceil().max(1.0) as u32;
    let mut s = PlanarState::at_rest(start.r, start.theta);
    let anchor = (start.r, start.theta);
    let mut cost = crate::dynamics::PlanarOutcome::default();
    let mut track = Vec::with_capacity(periods as usize);
    for period in 0..periods {
        cost += player.play_period(&mut s, period, period > 0, anchor)?;
        track.push(Pose {
            r: s.r,
            theta: s.theta,
        });
    }
    let end = DropEnd {
        pose: Pose {
            r: s.r,
            theta: s.theta,
        },
        time: f64::from(periods) * sm.period(),
        steps: cost.steps,
        refinements: cost.refinements,
        solver_iterations: cost.solver_iterations,
    };
    Ok((end, track))
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
pub(crate) fn nearest(stable: &[Equilibrium], pose: &Pose, radius: f64) -> Option<(usize, f64)> {
    stable
        .iter()
        .map(|e| {
            (e.pose.r - pose.r).norm() / radius.max(f64::MIN_POSITIVE)
                + wrap(e.pose.theta - pose.theta).abs()
        })
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Plays `part` (resampled as [`DropPlay::samples`] asks) from rest at
/// each of `starts` (poses of the part, in parallel) through `sm`: per
/// drop its end and its pose after every schedule period, as poses of the
/// part (the resampled body's centre of mass moved back to the part's).
pub fn play_part(
    part: &crate::part::Part,
    sm: &ScheduleMotion,
    starts: &[Pose],
    play: &DropPlay,
) -> Vec<Result<(DropEnd, Vec<Pose>), PlayLoss>> {
    // The played body's centre of mass sits at `offset` in the part's frame.
    let (body, offset) = play
        .samples
        .and_then(|n| part.coarse_body(n))
        .unwrap_or_else(|| (part.body.clone(), V2::zeros()));
    let at = |theta: f64| {
        let (s, c) = theta.sin_cos();
        V2::new(c * offset.x - s * offset.y, s * offset.x + c * offset.y)
    };
    let back = |p: Pose| Pose {
        r: p.r - at(p.theta),
        theta: p.theta,
    };
    starts
        .par_iter()
        .map(|p| {
            let moved = Pose {
                r: p.r + at(p.theta),
                theta: p.theta,
            };
            play_drop_tracked(sm, &body, moved, play).map(|(mut end, track)| {
                end.pose = back(end.pose);
                (end, track.into_iter().map(back).collect())
            })
        })
        .collect()
}

/// The basins measured by playing an analysis's drops ([`crate::pose::drop_starts`])
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
    /// the metric of `nearest` (|Δr|/R + |Δθ| in rad).
    pub worst: f64,
    /// Drops that lost contact.
    pub lost: usize,
    /// Simulated time per drop (s).
    pub time: f64,
    /// Integrator steps over all drops.
    pub steps: u64,
}

/// Plays the drops of `analysis` (same starts, same order) for `part`
/// (resampled as [`DropPlay::samples`] asks, its poses still the part's)
/// through `sm` and classifies each end by its nearest stable pose.
pub fn played_basins(
    analysis: &crate::pose::PoseAnalysis,
    part: &crate::part::Part,
    sm: &ScheduleMotion,
    play: &DropPlay,
) -> PlayedBasins {
    let eq = &analysis.equilibria;
    let index: Vec<usize> = (0..eq.len()).filter(|&i| eq[i].stable).collect();
    let stable: Vec<Equilibrium> = index.iter().map(|&i| eq[i]).collect();
    let starts = crate::pose::drop_starts(&analysis.starts, analysis.drops);
    let runs: Vec<Result<DropEnd, PlayLoss>> = play_part(part, sm, &starts, play)
        .into_iter()
        .map(|run| run.map(|(end, _)| end))
        .collect();
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
