//! Synthetic camera tracks: point parts played through a schedule by the
//! exact stick-slip simulator ([`crate::play`]: every segment's motion,
//! the joins, rest in closed form), observed at a frame rate with Gaussian
//! position noise and missing frames. What the tests, the coverage study
//! and `platefield calibrate --simulate` calibrate against: the full
//! replay, not the field model the estimator uses.

use rayon::prelude::*;

use super::tracks::{Frame, Track, Tracks};
use crate::dynamics::{Friction, PartPhysics, PartState, V2};
use crate::error::{Error, Result};
use crate::field::Grid;
use crate::play::{rest, PlayedSegment, Player, ScheduleMotion};
use crate::rng::SplitMix64;
use crate::schedule::Schedule;

/// What to simulate.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackSimulation {
    /// Each part's friction; the part count is its length.
    pub frictions: Vec<Friction>,
    /// Track duration (s), from t = 0 (the schedule's start).
    pub seconds: f64,
    /// Frames per second.
    pub fps: f64,
    /// Position noise per axis, one standard deviation (m).
    pub noise: f64,
    /// Fraction of frames missing (each frame dropped independently).
    pub missing: f64,
    /// Amplitude scale the motion is played at.
    pub scale: f64,
    /// Seed: the same seed, the same tracks.
    pub seed: u64,
}

impl TrackSimulation {
    /// Checks the settings: positive duration, rate and scale, noise ≥ 0,
    /// missing fraction within [0, 0.9).
    ///
    /// # Errors
    /// The first setting out of range, named.
    pub(crate) fn validate(&self) -> Result<()> {
        let sim = self;
        crate::error::positive("seconds", sim.seconds)?;
        crate::error::positive("fps", sim.fps)?;
        crate::error::positive("scale", sim.scale)?;
        if !(sim.noise >= 0.0 && sim.noise.is_finite()) {
            return Err(Error::invalid(
                "noise",
                format!("must be ≥ 0 m, got {}", sim.noise),
            ));
        }
        if !(0.0..0.9).contains(&sim.missing) {
            return Err(Error::invalid(
                "missing",
                format!("must be within [0, 0.9), got {}", sim.missing),
            ));
        }
        Ok(())
    }

    /// `parts` parts at `friction`, 30 frames per second over 10 s, 0.2 mm
    /// noise, 5 % of frames missing, the motion as sent.
    pub fn new(friction: Friction, parts: usize, seed: u64) -> TrackSimulation {
        TrackSimulation {
            frictions: vec![friction; parts],
            seconds: 10.0,
            fps: 30.0,
            noise: 2e-4,
            missing: 0.05,
            scale: 1.0,
            seed,
        }
    }
}

/// Tracks of `sim` on `schedule`'s motion, parts dropped uniformly over the
/// middle 80 % of `region` at rest on the plate. A part's track ends at
/// its last frame inside `region` (it left the plate region).
///
/// ```
/// use platefield::calibrate::{simulate_tracks, TrackSimulation};
/// use platefield::dynamics::Friction;
/// use platefield::schedule::Schedule;
/// let schedule = Schedule::load(std::path::Path::new("results/squeeze_trans/schedule.json"))?;
/// let region = schedule.region();
/// let mut sim = TrackSimulation::new(Friction::uniform(0.3), 2, 7);
/// sim.seconds = 0.5;
/// let tracks = simulate_tracks(&schedule, &region, &sim)?;
/// assert_eq!(tracks.tracks.len(), 2);
/// assert!(tracks.tracks[0].frames.len() > 10);
/// # Ok::<(), platefield::Error>(())
/// ```
///
/// # Errors
/// The schedule is invalid, a part loses contact, or the settings are out
/// of range.
pub fn simulate_tracks(
    schedule: &Schedule,
    region: &Grid,
    sim: &TrackSimulation,
) -> Result<Tracks> {
    sim.validate()?;
    let sm = schedule_motion(schedule, sim.scale)?;
    let frames = (sim.seconds * sim.fps).round() as usize;
    let times: Vec<f64> = (0..frames).map(|k| k as f64 / sim.fps).collect();
    let tracks = sim
        .frictions
        .par_iter()
        .enumerate()
        .map(|(i, &friction)| {
            let mut rng =
                SplitMix64::new(sim.seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ (i as u64 + 1));
            let at = |lo: f64, hi: f64, u: f64| lo + (hi - lo) * (0.1 + 0.8 * u);
            let r0 = V2::new(
                at(region.x[0], region.x[1], rng.uniform()),
                at(region.y[0], region.y[1], rng.uniform()),
            );
            let truth = play(schedule, &sm, friction, r0, &times)?;
            let mut out = Vec::new();
            for (&t, r) in times.iter().zip(truth) {
                if !inside(region, &r) {
                    break;
                }
                let noisy = [
                    r.x + sim.noise * rng.gaussian(),
                    r.y + sim.noise * rng.gaussian(),
                ];
                let clamp = |v: f64, g: [f64; 2]| v.clamp(g[0], g[1]);
                let keep = rng.uniform() >= sim.missing;
                if keep {
                    out.push(Frame {
                        t,
                        r: [clamp(noisy[0], region.x), clamp(noisy[1], region.y)],
                        line: 0,
                    });
                }
            }
            Ok(Track {
                part: format!("p{:02}", i + 1),
                frames: out,
            })
        })
        .collect::<Result<Vec<Track>>>()?;
    Ok(Tracks::from_tracks(
        tracks
            .into_iter()
            .filter(|t| t.frames.len() >= super::tracks::MIN_FRAMES)
            .collect(),
    ))
}

/// `schedule`'s segments as played, every motion's amplitudes × `scale`.
pub(crate) fn schedule_motion(schedule: &Schedule, scale: f64) -> Result<ScheduleMotion> {
    let segments = schedule
        .segments
        .iter()
        .enumerate()
        .map(|(i, seg)| {
            let mut p = PlayedSegment::from_segment(seg, i)?;
            p.motion = p.motion.map(|m| m.amplitude_scaled(scale)).transpose()?;
            Ok(p)
        })
        .collect::<Result<Vec<_>>>()?;
    ScheduleMotion::new(segments)
}

/// Noise-free tracks by the exact simulator (`play_on_grid`): part `k` put down at rest at
/// `parts[k].1` at t = 0 (the schedule's start) at `friction`, the motion
/// played at `scale` × its amplitudes, observed at the times `parts[k].2`
/// (increasing, ≥ 0) until it leaves `region`; tracks left with fewer
/// than three frames are dropped. What the calibration's bias correction
/// replays near its estimate ([`super::estimate::binding`]).
///
/// # Errors
/// The schedule is invalid, the scale is not positive, or a part loses
/// contact.
pub(crate) fn replay_tracks(
    schedule: &Schedule,
    region: &Grid,
    friction: Friction,
    scale: f64,
    parts: &[(String, [f64; 2], Vec<f64>)],
) -> Result<Vec<Track>> {
    crate::error::positive("scale", scale)?;
    let sm = schedule_motion(schedule, scale)?;
    let tracks = parts
        .par_iter()
        .map(|(part, r0, times)| {
            let truth = play_on_grid(schedule, &sm, friction, V2::from(*r0), times)?;
            let frames = times
                .iter()
                .zip(truth)
                .take_while(|(_, r)| inside(region, r))
                .map(|(&t, r)| Frame {
                    t,
                    r: [r.x, r.y],
                    line: 0,
                })
                .collect();
            Ok(Track {
                part: part.clone(),
                frames,
            })
        })
        .collect::<Result<Vec<Track>>>()?;
    Ok(tracks
        .into_iter()
        .filter(|t| t.frames.len() >= super::tracks::MIN_FRAMES)
        .collect())
}

/// Whether `r` lies within `region` (edges included).
fn inside(region: &Grid, r: &V2) -> bool {
    (region.x[0]..=region.x[1]).contains(&r.x) && (region.y[0]..=region.y[1]).contains(&r.y)
}

/// A player of `sm` for a part at `friction` under `schedule`'s settings.
fn player<'a>(schedule: &Schedule, sm: &'a ScheduleMotion, friction: Friction) -> Player<'a> {
    let settings = schedule.settings;
    let physics = PartPhysics::new(friction, settings.gravity, settings.model);
    sm.player(physics, settings.numerics)
}

/// As [`play`], with each segment advanced whole on its own fixed-step grid,
/// so that one table of the plate's kinematics per segment serves every
/// step of every period ([`crate::play::Player::with_tables`]: a memo, the
/// steps are bitwise what they would be without it), and each frame
/// reached from the grid step before it by one partial step off the grid.
/// [`play`] instead ends a step at every frame, so that its grid restarts
/// there and no two periods share an instant; both are the same RK4
/// integration to its error ([`super::replay::steps_for`] measures that
/// error on these replays). A fraction of [`play`]'s CPU on the shipped
/// schedules (measured: `docs/calibrate.md`, **Replays**): the kinematics
/// are evaluated once per segment instead of at every step.
pub(crate) fn play_on_grid(
    schedule: &Schedule,
    sm: &ScheduleMotion,
    friction: Friction,
    r0: V2,
    times: &[f64],
) -> Result<Vec<V2>> {
    let settings = schedule.settings;
    let plain = player(schedule, sm, friction);
    let tables = plain.kinematics_tables();
    let player = plain.with_tables(&tables);
    let segs = sm.segments();
    let lost = |loss| Error::ContactLost(format!("a simulated part loses contact: {loss}"));
    let mut state = PartState::new(r0, V2::zeros());
    let mut out = Vec::with_capacity(times.len());
    let mut record = Vec::new();
    let (mut i, mut seg_start) = (0usize, 0.0f64);
    while out.len() < times.len() {
        let duration = segs[i].duration;
        let end = seg_start + duration;
        let begin = state;
        let inside = |k: usize| times.get(k).is_some_and(|&t| t < end);
        match player.simulator(i) {
            Some(sim) => {
                record.clear();
                sim.advance(0.0, duration, &mut state, &r0, Some(&mut record))
                    .map_err(lost)?;
                while inside(out.len()) {
                    let local = times[out.len()] - seg_start;
                    let j = record.partition_point(|p| p.t <= local);
                    let (from, mut at) = match j {
                        0 => (0.0, begin),
                        _ => (record[j - 1].t, record[j - 1].state),
                    };
                    if local > from {
                        sim.advance(from, local, &mut at, &r0, None).map_err(lost)?;
                    }
                    out.push(at.r);
                }
            }
            None => {
                while inside(out.len()) {
                    let mut at = begin;
                    rest(
                        &mut at,
                        times[out.len()] - seg_start,
                        friction,
                        settings.gravity,
                    );
                    out.push(at.r);
                }
                rest(&mut state, duration, friction, settings.gravity);
            }
        }
        let next = (i + 1) % segs.len();
        player.join(i, next, &mut state, &r0);
        seg_start = end;
        i = next;
    }
    Ok(out)
}

/// The positions at `times` (increasing, from 0) of a part placed at rest
/// on the plate at `r0` at t = 0, played through `sm` at `friction`.
pub(crate) fn play(
    schedule: &Schedule,
    sm: &ScheduleMotion,
    friction: Friction,
    r0: V2,
    times: &[f64],
) -> Result<Vec<V2>> {
    let settings = schedule.settings;
    let player = player(schedule, sm, friction);
    let segs = sm.segments();
    let mut state = PartState::new(r0, V2::zeros());
    let (mut i, mut local, mut seg_start) = (0usize, 0.0f64, 0.0f64);
    let mut out = Vec::with_capacity(times.len());
    for &t in times {
        loop {
            let end = seg_start + segs[i].duration;
            let stop = t.min(end);
            let span = stop - (seg_start + local);
            if span > 0.0 {
                match player.simulator(i) {
                    Some(s) => {
                        s.advance(local, local + span, &mut state, &r0, None)
                            .map_err(|loss| {
                                Error::ContactLost(format!(
                                    "a simulated part loses contact: {loss}"
                                ))
                            })?;
                    }
                    None => {
                        rest(&mut state, span, friction, settings.gravity);
                    }
                }
                local += span;
            }
            if t < end {
                break;
            }
            let next = (i + 1) % segs.len();
            player.join(i, next, &mut state, &r0);
            seg_start = end;
            local = 0.0;
            i = next;
        }
        out.push(state.r);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    /// A worked example of `calibrate::simulate::replay_tracks`.
    #[test]
    fn example_replay_tracks() -> Result<(), crate::Error> {
        use crate::calibrate::simulate::replay_tracks;
        use crate::dynamics::Friction;
        use crate::schedule::Schedule;
        let schedule = Schedule::load(std::path::Path::new("results/squeeze_trans/schedule.json"))?;
        let region = schedule.region();
        let times: Vec<f64> = (10..40).map(|k| k as f64 / 30.0).collect();
        let parts = vec![("a".to_string(), [0.0, 0.0], times)];
        let tracks = replay_tracks(&schedule, &region, Friction::uniform(0.3), 1.0, &parts)?;
        assert_eq!(tracks[0].frames.len(), 30);
        assert!((tracks[0].frames[0].t - 1.0 / 3.0).abs() < 1e-12);
        Ok(())
    }
}
