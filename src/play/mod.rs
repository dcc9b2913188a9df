//! Playing a schedule: its exact plate trajectory and point parts under it.
//!
//! A [`crate::schedule::Schedule`] is played exactly, segment after segment:
//! segment i runs `cycles` whole periods of its primitive's [`Motion`]
//! (from [`crate::basis::Primitive::motion`]) and a rest segment holds the
//! plate at rest in the home pose. [`ScheduleMotion`] is that trajectory;
//! [`Player`] drives point parts through it with the exact stick-slip
//! integrator of [`crate::dynamics`], one cached [`Simulator`] per segment,
//! each called with segment-local time (every segment starts at phase 0).
//!
//! **Joins.** The plate pose is continuous at a join (every waveform used
//! here starts and ends a cycle in the home pose, q(0) = q(T) = 0). The
//! plate *velocity* is continuous for rest-to-rest primitives but jumps for
//! other waveforms (a sine's q'(0) ≠ 0). The part's tangential inertial
//! velocity is kept continuous across a join: with v_A, v_B the plate
//! velocities at the part (at the kinematics point: the current position,
//! or the anchor for the frozen model) at the end of segment A and the start
//! of segment B, the slip velocity becomes u_B = u_A + v_A,t − v_B,t, and a
//! part that was stuck slips when the jump is not zero. The normal
//! component of a jump is an impact that this point model does not resolve
//! (its friction impulse is neglected); for rest-to-rest primitives there
//! is no jump at all. Parts are placed on the plate at rest relative to it
//! (u = 0) at the start of the first segment.
//!
//! **Rest segments** (plate at rest in the home pose, N = g exactly) are
//! integrated in closed form: a slipping part decelerates at μ_k g against
//! its slip direction until it stops, and then stays stuck.
//!
//! [`replay`] plays a schedule's exported signal file instead of its
//! motions: the held samples a controller plays, cut into the schedule's
//! segments.
//!
//! [`measure`] plays moving point parts and compares their mean velocity
//! with the field a schedule is meant to realise: the model check of
//! `verify` and the order search ([`windowed`]: the same over fixed
//! warm-ups). The judge, which holds its parts, is
//! `crate::design::judge`.

pub mod lag;
pub mod measure;
pub mod replay;
pub mod sensitivity;
pub(crate) mod settle;
pub mod windowed;

pub use measure::grid_points;
pub use measure::verify_points;
pub use measure::{ModelCheck, PlayOptions, PointResult};

use crate::dynamics::{
    ContactLoss, Friction, KinematicsTable, Model, Numerics, PartPhysics, PartState, Simulator,
};
use crate::error::{positive, Error, Result};
use crate::motion::{Motion, V3};
use crate::schedule::{Schedule, Segment};

use serde::{Deserialize, Serialize};

pub use crate::dynamics::V2;

/// One segment of a played schedule.
#[derive(Debug, Clone, PartialEq)]
pub struct PlayedSegment {
    /// Label, e.g. `LineSink@90°` or `Rest`.
    pub label: String,
    /// The plate motion; `None` = the plate at rest in the home pose.
    pub motion: Option<Motion>,
    /// Whole cycles of `motion` (0 for rest segments).
    pub cycles: u32,
    /// Duration (s): `cycles` periods, or the rest time.
    pub duration: f64,
}

/// The plate's in-plane velocity at plate point `p` and its vertical spin
/// at the start (and, by periodicity, the end) of segment `seg` (what a
/// part at rest on the plate carries across a join).
pub(crate) fn plate_twist(seg: &PlayedSegment, gravity: f64, tilt: bool, p: &V2) -> (V2, f64) {
    match &seg.motion {
        None => (V2::zeros(), 0.0),
        Some(m) => {
            let k = m.kinematics(0.0, gravity, tilt);
            let v = k.velocity_at(&V3::new(p.x, p.y, 0.0));
            (V2::new(v.x, v.y), k.omega.z)
        }
    }
}

impl PlayedSegment {
    /// `cycles` whole periods of `motion`.
    pub fn moving(label: impl Into<String>, motion: Motion, cycles: u32) -> PlayedSegment {
        let duration = f64::from(cycles) * motion.period();
        PlayedSegment {
            label: label.into(),
            motion: Some(motion),
            cycles,
            duration,
        }
    }

    /// The plate at rest for `duration` seconds.
    pub fn rest(duration: f64) -> PlayedSegment {
        PlayedSegment {
            label: "Rest".into(),
            motion: None,
            cycles: 0,
            duration,
        }
    }

    /// The played form of segment `i` of a designed schedule: its
    /// primitive's motion (rotation and shift applied) or its six-signal
    /// motion for its whole cycles, or rest for its `duration_s` when it
    /// has neither.
    pub(crate) fn from_segment(seg: &Segment, i: usize) -> Result<PlayedSegment> {
        seg.validate_motion(&format!("schedule.segments[{i}]"))?;
        match seg.plate_motion() {
            Some(m) => Ok(PlayedSegment::moving(seg.label.clone(), m, seg.cycles)),
            None => {
                let d = seg.duration_s;
                if !(d.is_finite() && d >= 0.0) {
                    return Err(Error::invalid(
                        format!("schedule.segments[{i}].duration_s"),
                        format!("must be a finite number ≥ 0, got {d}"),
                    ));
                }
                Ok(PlayedSegment::rest(d))
            }
        }
    }
}

/// The plate trajectory of a schedule: segments played in order, repeated
/// with period Σ durations.
#[derive(Debug, Clone, PartialEq)]
pub struct ScheduleMotion {
    segments: Vec<PlayedSegment>,
    period: f64,
}

impl ScheduleMotion {
    /// A trajectory from segments (validated: at least one segment of
    /// positive duration, valid motions, finite durations).
    pub fn new(segments: Vec<PlayedSegment>) -> Result<ScheduleMotion> {
        let segments: Vec<PlayedSegment> =
            segments.into_iter().filter(|s| s.duration > 0.0).collect();
        if segments.is_empty() {
            return Err(Error::invalid(
                "schedule.segments",
                "must hold at least one segment of positive duration",
            ));
        }
        for (i, s) in segments.iter().enumerate() {
            positive(&format!("schedule.segments[{i}].duration_s"), s.duration)?;
            if let Some(m) = &s.motion {
                m.validate(&format!("schedule.segments[{i}].primitive"))?;
            }
        }
        let period = segments.iter().map(|s| s.duration).sum();
        Ok(ScheduleMotion { segments, period })
    }

    /// The trajectory of a designed schedule: each segment's primitive
    /// motion (rotation and shift applied) for its whole cycles; segments
    /// without a primitive are rest for their `duration_s`.
    pub fn from_schedule(schedule: &Schedule) -> Result<ScheduleMotion> {
        let out = schedule
            .segments
            .iter()
            .enumerate()
            .map(|(i, seg)| PlayedSegment::from_segment(seg, i))
            .collect::<Result<Vec<_>>>()?;
        ScheduleMotion::new(out)
    }

    /// The segments (those of zero duration are dropped).
    pub fn segments(&self) -> &[PlayedSegment] {
        &self.segments
    }

    /// Schedule period (s): one pass through all segments.
    pub fn period(&self) -> f64 {
        self.period
    }

    /// Time (s) per period in which the plate moves (rest segments excluded).
    pub fn moving_time(&self) -> f64 {
        self.segments
            .iter()
            .filter(|s| s.motion.is_some())
            .map(|s| s.duration)
            .sum()
    }

    /// Time fraction of each segment.
    pub(crate) fn fractions(&self) -> Vec<f64> {
        self.segments
            .iter()
            .map(|s| s.duration / self.period)
            .collect()
    }

    /// A player for point parts under this trajectory.
    pub fn player(&self, physics: PartPhysics, numerics: Numerics) -> Player<'_> {
        let PartPhysics {
            friction,
            gravity,
            model,
        } = physics;
        let sims = self
            .segments
            .iter()
            .map(|s| {
                s.motion
                    .as_ref()
                    .map(|m| Simulator::new(m, physics, numerics))
            })
            .collect();
        Player {
            schedule: self,
            sims,
            friction,
            gravity,
            model,
            numerics,
            join: Join::Inertial,
        }
    }
}

/// Where and when a played part lost contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayLoss {
    /// Segment index.
    pub segment: usize,
    /// Schedule period index (0 = the first played period).
    pub period: u32,
    /// The loss, in segment-local time.
    pub loss: ContactLoss,
}

impl std::fmt::Display for PlayLoss {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "schedule period {}, segment {}: {}",
            self.period, self.segment, self.loss
        )
    }
}

/// Plays a [`ScheduleMotion`] on point parts (one cached simulator per segment).
#[derive(Debug, Clone)]
pub struct Player<'a> {
    schedule: &'a ScheduleMotion,
    sims: Vec<Option<Simulator<'a>>>,
    friction: Friction,
    gravity: f64,
    model: Model,
    numerics: Numerics,
    join: Join,
}

/// What is kept continuous where the plate velocity jumps at a join.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Join {
    /// The part's tangential inertial velocity (physical; the default).
    Inertial,
    /// The slip velocity u relative to the plate (unphysical: the part
    /// jumps with the plate). Kept only to measure what that mistake does.
    Slip,
}

impl<'a> Player<'a> {
    /// The same player with another join rule.
    pub(crate) fn with_join(mut self, join: Join) -> Player<'a> {
        self.join = join;
        self
    }

    /// The trajectory played.
    pub(crate) fn schedule(&self) -> &'a ScheduleMotion {
        self.schedule
    }

    /// The plate kinematics each moving segment's simulator asks for over
    /// the segment ([`KinematicsTable`]; `None` for rest): every period
    /// plays each segment over the same span, so one table serves every
    /// period of every part ([`Player::with_tables`]).
    pub(crate) fn kinematics_tables(&self) -> Vec<Option<KinematicsTable<'a>>> {
        self.sims
            .iter()
            .zip(&self.schedule.segments)
            .map(|(sim, seg)| {
                sim.as_ref()
                    .map(|s| KinematicsTable::new(s, &[(0.0, seg.duration)]))
            })
            .collect()
    }

    /// The same player reading the plate kinematics from `tables`
    /// ([`Player::kinematics_tables`] of a player of the same schedule and
    /// physics): a memo, the parts' paths are bitwise unchanged
    /// (`tests::tabled_plays_are_the_direct_ones`).
    pub(crate) fn with_tables(mut self, tables: &'a [Option<KinematicsTable<'a>>]) -> Player<'a> {
        for (sim, table) in self.sims.iter_mut().zip(tables) {
            *sim = sim.take().map(|s| match table {
                Some(t) => s.with_table(t),
                None => s,
            });
        }
        self
    }

    /// The simulator of segment `i` (`None` for rest).
    pub fn simulator(&self, i: usize) -> Option<&Simulator<'a>> {
        self.sims[i].as_ref()
    }

    /// The model switches.
    pub(crate) fn model(&self) -> Model {
        self.model
    }

    /// The same player with the part's position frozen in the plate
    /// kinematics (the model's `moving` off; see [`Model::FROZEN`]).
    pub(crate) fn frozen(&self) -> Player<'a> {
        let model = Model {
            moving: false,
            ..self.model
        };
        self.schedule
            .player(
                PartPhysics::new(self.friction, self.gravity, model),
                self.numerics,
            )
            .with_join(self.join)
    }

    /// Tangential plate velocity at plate point `p` at the start (and, by
    /// periodicity, the end) of segment `i`.
    pub(crate) fn join_velocity(&self, i: usize, p: &V2) -> V2 {
        match &self.schedule.segments[i].motion {
            None => V2::zeros(),
            Some(m) => {
                let k = m.kinematics(0.0, self.gravity, self.model.tilt);
                let v = k.velocity_at(&V3::new(p.x, p.y, 0.0));
                V2::new(v.x, v.y)
            }
        }
    }

    /// Applies the join from segment `from` to segment `to`: the part's
    /// tangential inertial velocity is kept continuous.
    pub fn join(&self, from: usize, to: usize, state: &mut PartState, anchor: &V2) {
        if self.join == Join::Slip {
            return;
        }
        let p = if self.model.moving { state.r } else { *anchor };
        let jump = self.join_velocity(from, &p) - self.join_velocity(to, &p);
        if jump != V2::zeros() {
            state.u += jump;
            state.stuck = false;
        }
    }

    /// Plays segment `i` from its start to its end; returns the time stuck.
    pub fn play_segment(
        &self,
        i: usize,
        state: &mut PartState,
        anchor: &V2,
    ) -> Result<f64, ContactLoss> {
        let seg = &self.schedule.segments[i];
        match &self.sims[i] {
            Some(sim) => Ok(sim
                .advance(0.0, seg.duration, state, anchor, None)?
                .stuck_time),
            None => Ok(rest(state, seg.duration, self.friction, self.gravity)),
        }
    }

    /// Plays `periods` whole schedule periods. `first` is the number of
    /// the first period played: period 0 starts without a join (the part is
    /// placed on the plate), later periods start with the join from the
    /// last segment. `visit(t, segment_end_index, state)` is called at the
    /// start (index `None`, t = 0) and after every segment (t from the start
    /// of this call, s).
    pub fn play_periods(
        &self,
        state: &mut PartState,
        anchor: &V2,
        first: u32,
        periods: u32,
        mut visit: impl FnMut(f64, Option<usize>, &PartState),
    ) -> Result<(), PlayLoss> {
        let n = self.schedule.segments.len();
        let mut t = 0.0;
        visit(t, None, state);
        for k in first..first + periods {
            for i in 0..n {
                if k > 0 || i > 0 {
                    self.join(if i == 0 { n - 1 } else { i - 1 }, i, state, anchor);
                }
                self.play_segment(i, state, anchor)
                    .map_err(|loss| PlayLoss {
                        segment: i,
                        period: k,
                        loss,
                    })?;
                t += self.schedule.segments[i].duration;
                visit(t, Some(i), state);
            }
        }
        Ok(())
    }
}

/// The plate at rest in the home pose for `duration`: N = g, a slipping
/// part decelerates at μ_k g against its slip until it stops and then
/// sticks (exact). Returns the time stuck.
pub fn rest(state: &mut PartState, duration: f64, friction: Friction, gravity: f64) -> f64 {
    let speed = state.u.norm();
    if speed == 0.0 {
        state.stuck = true;
        return duration;
    }
    let decel = friction.kinetic * gravity;
    let stop = if decel > 0.0 {
        speed / decel
    } else {
        f64::INFINITY
    };
    let dir = state.u / speed;
    if stop <= duration {
        state.r += dir * (0.5 * speed * stop);
        state.u = V2::zeros();
        state.stuck = true;
        duration - stop
    } else {
        state.r += dir * (speed * duration - 0.5 * decel * duration * duration);
        state.u = dir * (speed - decel * duration);
        state.stuck = false;
        0.0
    }
}

/// Whole periods of length `period` that cover at least `cycles` cycles
/// of length `cycle` (at least one).
pub fn periods_for(cycles: u32, cycle: f64, period: f64) -> u32 {
    let n = (f64::from(cycles) * cycle / period - 1e-9).ceil();
    if n.is_finite() && n >= 1.0 {
        n.min(f64::from(u32::MAX)) as u32
    } else {
        1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whole periods covering a number of cycles: at least one, and exact
    /// multiples are not rounded up by rounding error.
    #[test]
    fn periods_cover_the_cycles() {
        let t = 2.0 * std::f64::consts::PI / 209.0;
        assert_eq!(periods_for(40, t, 32.0 * t), 2);
        assert_eq!(periods_for(40, t, 20.0 * t), 2);
        assert_eq!(periods_for(40, t, 41.0 * t), 1);
        assert_eq!(periods_for(40, t, 13.0 * t), 4);
        assert_eq!(periods_for(0, t, t), 1);
    }

    /// The kinematics tables are a memo: a part played four periods of a
    /// two-segment schedule ends at the same bits with and without them,
    /// and it moved.
    #[test]
    fn tabled_plays_are_the_direct_ones() {
        use crate::dynamics::{PartState, V2};
        use crate::field::FieldSettings;
        use crate::motion::{Motion, Signals};
        let sm = ScheduleMotion::new(vec![
            PlayedSegment::moving("signals", Motion::Signals(Signals::example()), 3),
            PlayedSegment::rest(0.01),
        ])
        .expect("a valid schedule");
        let options = PlayOptions::from_settings(&FieldSettings::default());
        let tables = options.player(&sm).kinematics_tables();
        let play = |tabled: bool| {
            let player = options.player(&sm);
            let player = if tabled {
                player.with_tables(&tables)
            } else {
                player
            };
            let anchor = V2::new(0.02, -0.01);
            let mut state = PartState::new(anchor, V2::zeros());
            player
                .play_periods(&mut state, &anchor, 0, 4, |_, _, _| ())
                .expect("a played schedule");
            state
        };
        let (direct, tabled) = (play(false), play(true));
        assert_eq!(direct.r.x.to_bits(), tabled.r.x.to_bits());
        assert_eq!(direct.r.y.to_bits(), tabled.r.y.to_bits());
        assert_ne!(direct.r, V2::new(0.02, -0.01));
    }
}
