//! Moving point parts played over whole schedule periods with a fixed
//! warm-up: the plays of the model check.
//!
//! A part starts at rest at each start point and moves with the plate's
//! kinematics where it is; it plays a warm-up of at least
//! [`MeasureOptions::warmup_cycles`] primitive cycles and windows of at
//! least [`MeasureOptions::measured_cycles`], both rounded up to whole
//! schedule periods, one window starting at each segment join
//! ([`Windows::EveryJoin`]). Per point: the mean velocity over the windows,
//! the mean position, and each segment's velocity in its schedule context
//! c_i (the mean velocity is Σ f_i c_i exactly, f_i the segment's share of
//! the period).
//!
//! These plays answer whether the simulation does what a design's model
//! says along the parts' own paths
//! ([`super::measure::against_prediction`]). How well a design makes the
//! field over the region it asks for is the judge's question
//! (`crate::design::judge`: parts held at fixed points).

use rayon::prelude::*;
use serde::Serialize;

use super::measure::{play_point, PlayOptions, PointPlay, Windows};
use super::ScheduleMotion;
#[cfg(test)]
use crate::error::Result;
use crate::field::FieldSettings;
#[cfg(test)]
use crate::schedule::Schedule;

/// How long moving parts play a schedule.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeasureOptions {
    /// Primitive cycles played before measuring (rounded up to whole
    /// schedule periods; default 40).
    pub warmup_cycles: u32,
    /// Primitive cycles measured (rounded up to whole schedule periods;
    /// default 20).
    pub measured_cycles: u32,
    /// Lengthen the warm-up where a part's start-up transient outlasts it
    /// (`crate::play::settle`; default false). Off by default: this
    /// measure judges a design against its *target* where the parts are
    /// after a fixed warm-up, and a strong field gathers the parts before a
    /// slow transient dies out (the synthesized motion of `sink_trans`, a
    /// 3 s⁻¹ sink whose transient takes several periods, has every part at
    /// the centre when its settled windows begin); `verify`, which compares
    /// with the steady-state *prediction*, settles.
    pub settle: bool,
}

impl Default for MeasureOptions {
    fn default() -> Self {
        MeasureOptions {
            warmup_cycles: 40,
            measured_cycles: 20,
            settle: false,
        }
    }
}

/// Plays `schedule` from each start point `points[i]`, `i` in `starts`, with
/// the physics of `settings` (in parallel; results in the order of `starts`,
/// [`PointPlay::index`] = i).
#[cfg(test)]
pub(crate) fn play(
    schedule: &Schedule,
    points: &[[f64; 2]],
    starts: &[usize],
    settings: &FieldSettings,
    opts: &MeasureOptions,
) -> Result<Vec<PointPlay>> {
    let sm = ScheduleMotion::from_schedule(schedule)?;
    Ok(play_motion(
        &sm,
        schedule.total_cycles,
        points,
        starts,
        settings,
        opts,
    ))
}

/// `play` for a trajectory `sm` of `per_period` primitive cycles per
/// schedule period (e.g. one segment of a synthesized motion).
pub fn play_motion(
    sm: &ScheduleMotion,
    per_period: u32,
    points: &[[f64; 2]],
    starts: &[usize],
    settings: &FieldSettings,
    opts: &MeasureOptions,
) -> Vec<PointPlay> {
    let per_period = per_period.max(1);
    let warm = opts.warmup_cycles.div_ceil(per_period);
    let meas = opts.measured_cycles.div_ceil(per_period).max(1);
    let v = PlayOptions::from_settings(settings);
    // One kinematics table per segment, shared by every part (a memo).
    let tables = v.player(sm).kinematics_tables();
    starts
        .par_iter()
        .map(|&i| {
            let player = v.player(sm).with_tables(&tables);
            play_point(
                sm,
                &player,
                i,
                points[i],
                (warm, opts.settle),
                meas,
                Windows::EveryJoin,
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::{Primitive, PrimitiveKind};
    use crate::fit::FitMetrics;
    use crate::schedule::Segment;

    /// A schedule of LineSinks at the given (rotation, cycles).
    fn line_sinks(parts: &[(f64, u32)]) -> Schedule {
        let segments: Vec<Segment> = parts
            .iter()
            .map(|&(deg, cycles)| {
                let p = Primitive {
                    rotation_deg: deg,
                    ..Primitive::new(PrimitiveKind::LineSink)
                };
                Segment {
                    label: format!("LineSink@{deg}°"),
                    duration_s: f64::from(cycles) * p.period(),
                    primitive: Some(p),
                    motion: None,
                    ramp_cycles: None,
                    weight: 0.0,
                    cycles,
                }
            })
            .collect();
        let none = FitMetrics {
            relative_l2_error: 0.0,
            mean_angle_error_deg: 0.0,
            max_error: 0.0,
            strength: 1.0,
        };
        Schedule::of_segments("t", segments, FieldSettings::default(), none)
    }

    /// Frozen positions, one motion played in two segments of 1 and 2
    /// cycles: the realised velocity and both contributions are the
    /// steady-state velocity of the cycle map's fixed point (computed
    /// independently by [`Simulator::steady_state`]).
    #[test]
    fn one_motion_realises_its_steady_state() {
        let settings = FieldSettings {
            model: crate::dynamics::Model::FROZEN,
            ..FieldSettings::default()
        };
        let schedule = line_sinks(&[(0.0, 1), (0.0, 2)]);
        let points = [[0.02, 0.01], [-0.03, 0.025]];
        let plays = play(
            &schedule,
            &points,
            &[0, 1],
            &settings,
            &MeasureOptions::default(),
        )
        .expect("play");
        let motion = schedule.segments[0].primitive.as_ref().unwrap().motion();
        let sim = settings.simulator(&motion);
        for (p, play) in points.iter().zip(&plays) {
            assert!(play.note.is_none());
            let v = sim.steady_state(*p).expect("steady state").velocity;
            let scale = v[0].hypot(v[1]);
            assert!(scale > 1e-4, "{v:?}");
            for r in std::iter::once(&play.realised).chain(&play.contributions) {
                let e = (r[0] - v[0]).hypot(r[1] - v[1]);
                assert!(e <= 1e-9 * scale, "{r:?} vs {v:?}");
            }
            // Frozen: the field belongs to the anchor.
            assert_eq!(play.position, *p);
        }
    }

    /// R = Σ f_i c_i exactly (full model, moving parts, two motions).
    #[test]
    fn realised_velocity_is_the_time_weighted_sum_of_contributions() {
        let schedule = line_sinks(&[(0.0, 2), (90.0, 1), (180.0, 3)]);
        let points = [[0.02, 0.01], [-0.01, -0.03]];
        let plays = play(
            &schedule,
            &points,
            &[0, 1],
            &FieldSettings::default(),
            &MeasureOptions::default(),
        )
        .expect("play");
        for play in &plays {
            let mut sum = [0.0; 2];
            for (g, c) in schedule.segments.iter().zip(&play.contributions) {
                let f = g.duration_s / schedule.period_s;
                sum[0] += f * c[0];
                sum[1] += f * c[1];
            }
            let r = play.realised;
            assert!((sum[0] - r[0]).hypot(sum[1] - r[1]) <= 1e-12 * r[0].hypot(r[1]));
        }
    }
}
