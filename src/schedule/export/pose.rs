//! `platefield export --format pose` and `--format cycle`: the design as
//! a hexapod's wave table of poses, and as the one steady cycle of
//! accelerations a 6-DOF plate controller iterates on.
//!
//! **Pose** ([`poses`]): per point t, the plate centre's x, y, z (m) and
//! the orientation R = exp(\[θ\]×) as the fixed-axis x-y-z angles
//! (roll about the world x, then pitch about the world y, then yaw about
//! the world z: R = R_z(yaw) R_y(pitch) R_x(roll), the angle set of
//! hexapod controllers such as PI's U, V, W; `rotation::xyz_angles`).
//! A schedule of one steady six-signal motion is one steady cycle of
//! N = round(rate·T) points, t_k = kT/N: the table loops exactly (point N
//! would be point 0), and it starts at the cycle's pose at t = 0, not at
//! home (move there before playing it). Any other schedule is one schedule
//! period on the CSV export's grid, from home back to home (its segments
//! are rest-to-rest). The values are the design's exact poses, not the
//! held samples' integral.
//!
//! **Cycle** ([`cycle`]): a schedule of one steady six-signal motion as N
//! point values a(kT/N) of its six accelerations (linear and world angular,
//! the export's channels): the periodic signal a controller transforms per
//! harmonic. The linear channels are sums of harmonics, so for N above
//! twice the highest one their mean over the cycle (the velocity change
//! per cycle over T) is zero to round-off; the angular ones hold the
//! exact rotation's higher harmonics as well (second order in the tilt
//! angles: their mean aliases from harmonics N, 2N, …, below 1e-12 of
//! the peak at N ≥ 16 per harmonic).

use std::fmt::Write as _;

use super::peaks::KinematicPeaks;
use super::{segment_motions, spans, steady_signals, world_acceleration, Schedule, FRAME};
use crate::error::{Error, Result};
use crate::motion::sample_hold::{self, CentreState};
use crate::motion::{rotation, Motion, V3};

/// Most points per cycle of `--format cycle`.
pub const MAX_CYCLE_POINTS: usize = 1_000_000;

/// A design's poses at uniform times (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Poses {
    /// Time between points (s).
    pub dt: f64,
    /// Per point: x, y, z (m), roll, pitch, yaw (rad).
    pub points: Vec<[f64; 6]>,
    /// True for one steady cycle (starting off home), false for a schedule
    /// period from home to home.
    pub steady: bool,
    /// Peak acceleration, velocity and stroke of the motion.
    pub peaks: KinematicPeaks,
}

/// The pose at a centre state: x, y, z and the x-y-z angles.
fn pose_row(s: &CentreState) -> [f64; 6] {
    let [roll, pitch, yaw] = rotation::xyz_angles(&rotation::orientation(&V3::new(
        s.pose[3], s.pose[4], s.pose[5],
    )));
    [s.pose[0], s.pose[1], s.pose[2], roll, pitch, yaw]
}

/// The poses of `schedule` at (about) `rate` points/s (see the module
/// documentation).
///
/// ```
/// use platefield::schedule::export::pose::poses;
/// use platefield::schedule::Schedule;
///
/// let s = Schedule::load(std::path::Path::new("results/sequenced/sink/schedule.json")).unwrap();
/// let p = poses(&s, 2000.0).unwrap();
/// assert!(!p.steady && p.points[0].iter().all(|x| *x == 0.0));
/// ```
///
/// # Errors
/// An invalid schedule or rate (as `export`).
pub fn poses(schedule: &Schedule, rate: f64) -> Result<Poses> {
    schedule.validate()?;
    let schedule = &schedule.with_segments(schedule.segments.clone());
    if let Some(signals) = steady_signals(schedule) {
        let motion = Motion::Signals(signals.clone());
        let steady = sample_hold::periodic(&motion, rate)?;
        let n = steady.samples_per_period;
        let points = (0..n)
            .map(|k| pose_row(&sample_hold::centre_state(&motion, k as f64 * steady.dt)))
            .collect();
        let highest = signals.highest_harmonic();
        return Ok(Poses {
            dt: steady.dt,
            points,
            steady: true,
            peaks: KinematicPeaks::of_plate(&motion, highest),
        });
    }
    let motions = segment_motions(schedule);
    let (_, dt, states) = sample_hold::sequence_states(&spans(schedule, &motions), rate)?;
    let held = super::export(schedule, rate, super::DEFAULT_STEADY_CYCLES)?;
    Ok(Poses {
        dt,
        points: states[..states.len() - 1].iter().map(pose_row).collect(),
        steady: false,
        peaks: held.peaks(),
    })
}

impl Poses {
    /// Per axis the largest |value| over the points.
    pub(crate) fn extremes(&self) -> [f64; 6] {
        crate::motion::sample_hold::axis_extremes(&self.points)
    }

    /// The CSV `export --format pose` writes: comment lines (`# `) stating
    /// the layout, the angle set, the frame and the peaks, then
    /// `t_s,x_m,y_m,z_m,roll_x_rad,pitch_y_rad,yaw_z_rad` rows.
    pub fn to_csv(&self) -> String {
        let layout = if self.steady {
            format!(
                "one steady cycle of {} points, {:.9} s apart (T = {:.9} s): loop it (the point after the last is the first); it starts at the cycle's pose at t = 0, not at home: move there first",
                self.points.len(),
                self.dt,
                self.dt * self.points.len() as f64
            )
        } else {
            format!(
                "one schedule period of {} points, {:.9} s apart, from home back to home: loop it",
                self.points.len(),
                self.dt
            )
        };
        let e = self.extremes();
        let mut out = format!("# platefield export --format pose: {layout}\n");
        out.push_str("# angles: fixed-axis x-y-z (roll about the world x, then pitch about the world y, then yaw about the world z: R = Rz(yaw)·Ry(pitch)·Rx(roll)); the orientation is the design's R = exp([θ]×)\n");
        let _ = writeln!(out, "# {FRAME}");
        let _ = writeln!(
            out,
            "# pose peaks of these points: |x|, |y|, |z| [{:.6e}, {:.6e}, {:.6e}] m, |roll|, |pitch|, |yaw| [{:.6e}, {:.6e}, {:.6e}] rad",
            e[0], e[1], e[2], e[3], e[4], e[5]
        );
        out.push_str(&self.peaks.header(if self.steady {
            "the steady motion"
        } else {
            "the schedule period as played"
        }));
        out.push_str("t_s,x_m,y_m,z_m,roll_x_rad,pitch_y_rad,yaw_z_rad\n");
        for (k, r) in self.points.iter().enumerate() {
            let _ = writeln!(
                out,
                "{:.9},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e}",
                k as f64 * self.dt,
                r[0],
                r[1],
                r[2],
                r[3],
                r[4],
                r[5]
            );
        }
        out
    }
}

/// One steady cycle of a six-signal design's accelerations (see the module
/// documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Cycle {
    /// Period T (s).
    pub period: f64,
    /// N point values a(kT/N): linear (m/s²) then world angular (rad/s²).
    pub points: Vec<[f64; 6]>,
    /// Peak acceleration, velocity and stroke of the steady motion.
    pub peaks: KinematicPeaks,
}

/// The steady cycle of `schedule`'s one six-signal motion at `n` points.
///
/// ```
/// use platefield::schedule::export::pose::cycle;
/// use platefield::schedule::Schedule;
///
/// let s = Schedule::load(std::path::Path::new("results/synthesized/sink/schedule.json")).unwrap();
/// let c = cycle(&s, 256).unwrap();
/// let mean: f64 = c.points.iter().map(|a| a[0]).sum::<f64>() / 256.0;
/// assert!(mean.abs() < 1e-12 * c.peaks.acceleration[0]);
/// ```
///
/// # Errors
/// An invalid schedule, one that is not a single steady six-signal motion
/// (names `--format`), or `n` below 2·(highest harmonic) + 1 or above
/// [`MAX_CYCLE_POINTS`] (names `--points`).
pub fn cycle(schedule: &Schedule, n: usize) -> Result<Cycle> {
    schedule.validate()?;
    let Some(signals) = steady_signals(schedule) else {
        return Err(Error::invalid(
            "--format",
            "cycle needs a schedule of one steady six-signal motion (a synthesized design); a sequence of primitives or ramped motions is one looped schedule period: export it with --format csv (or pose)",
        ));
    };
    let highest = signals.highest_harmonic();
    let least = 2 * highest as usize + 1;
    if n < least || n > MAX_CYCLE_POINTS {
        return Err(Error::invalid(
            "--points",
            format!(
                "must be in {least}..={MAX_CYCLE_POINTS} (above twice the motion's highest harmonic, {highest}), got {n}"
            ),
        ));
    }
    let motion = Motion::Signals(signals.clone());
    let points = (0..n)
        .map(|k| {
            let (l, a) = world_acceleration(&motion, signals.period * k as f64 / n as f64);
            [l.x, l.y, l.z, a.x, a.y, a.z]
        })
        .collect();
    Ok(Cycle {
        period: signals.period,
        points,
        peaks: KinematicPeaks::of_plate(&motion, highest),
    })
}

impl Cycle {
    /// Per channel the mean of the points (the velocity change per cycle
    /// over T: zero for a closed cycle).
    pub(crate) fn means(&self) -> [f64; 6] {
        let n = self.points.len() as f64;
        std::array::from_fn(|i| self.points.iter().map(|a| a[i]).sum::<f64>() / n)
    }

    /// The CSV `export --format cycle` writes: comment lines (`# `) stating
    /// the cycle, the frame, the peaks and the channel means, then
    /// `t_s` and the six channels of the CSV export, one row per point.
    pub fn to_csv(&self) -> String {
        let n = self.points.len();
        let mut out = format!(
            "# platefield export --format cycle: one steady cycle, T = {} s, {n} point values a(kT/N) of the six accelerations (not held means), to loop: the point after the last is the first; ramp it in from rest (the CSV export's ramp does)\n",
            self.period
        );
        let _ = writeln!(out, "# {FRAME}");
        out.push_str(&self.peaks.header("the steady motion"));
        let m = self.means();
        let _ = writeln!(
            out,
            "# channel means (velocity change per cycle over T): [{:.3e}, {:.3e}, {:.3e}] m/s², [{:.3e}, {:.3e}, {:.3e}] rad/s²",
            m[0], m[1], m[2], m[3], m[4], m[5]
        );
        out.push_str("t_s,");
        out.push_str(&super::CHANNELS.join(","));
        out.push('\n');
        for (k, a) in self.points.iter().enumerate() {
            let _ = writeln!(
                out,
                "{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e}",
                self.period * k as f64 / n as f64,
                a[0],
                a[1],
                a[2],
                a[3],
                a[4],
                a[5]
            );
        }
        out
    }
}

#[cfg(test)]
#[path = "../../../tests/unit/pose_export.rs"]
mod pose_export_tests;
