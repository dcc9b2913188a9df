//! The realised velocity field of a schedule against the design's prediction.
//!
//! For each start point p a point part is placed on the plate (at rest
//! relative to it), the schedule is played for `warmup_periods` whole
//! schedule periods, and then for `periods` more; the **realised** velocity
//! is the displacement over the measured periods divided by their duration.
//! The **prediction** is the time-weighted combination Σ_i f_i V_i(q) of the
//! segments' steady-state velocity fields ([`Simulator::steady_state`], same
//! model), with f_i = duration_i / schedule period and rest contributing 0.
//!
//! Where the prediction is evaluated (q):
//! * **frozen** model (`moving` off): the kinematics are held at p, so q = p
//!   and the comparison is exact: it measures the joining and ordering
//!   effects alone.
//! * **free** model (`moving` on, the default [`Model::FULL`]): the part
//!   drifts (about 1 mm/s with the paper's settings), so q is its mean
//!   position over the measured periods, the time-weighted (trapezoidal)
//!   mean of its positions at the segment joins. The residual then also
//!   holds the field's curvature over the drift, which is second order in
//!   the drift.
//!
//! The reported error is the relative L2 error over the valid points,
//! ‖realised − predicted‖ / ‖predicted‖. A point whose part leaves the plate
//! or whose steady state does not converge is invalid, listed with the
//! reason, and left out.

use rayon::prelude::*;
use serde::Serialize;

use super::{Join, ScheduleMotion, V2};
use crate::dynamics::{Friction, Model, Numerics, PartState};
use crate::field::{FieldSettings, Grid};

/// Settings of a verification run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerifyOptions {
    /// Friction coefficients.
    pub friction: Friction,
    /// Gravity (m/s²).
    pub gravity: f64,
    /// Model switches (default [`Model::FULL`]).
    pub model: Model,
    /// Integrator settings.
    pub numerics: Numerics,
    /// Schedule periods played before measuring (default 1).
    pub warmup_periods: u32,
    /// Schedule periods measured (default 1).
    pub periods: u32,
    /// Join rule where the plate velocity jumps (default inertial).
    pub join: Join,
}

impl Default for VerifyOptions {
    fn default() -> Self {
        VerifyOptions::from_settings(&FieldSettings::default())
    }
}

impl VerifyOptions {
    /// Physics from field settings (e.g. those a schedule's basis was built
    /// with), 1 warm-up and 1 measured period.
    pub fn from_settings(s: &FieldSettings) -> VerifyOptions {
        VerifyOptions {
            friction: s.friction,
            gravity: s.gravity,
            model: s.model,
            numerics: s.numerics,
            warmup_periods: 1,
            periods: 1,
            join: Join::Inertial,
        }
    }
}

/// The comparison at one start point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PointResult {
    /// Start position (m).
    pub start: [f64; 2],
    /// Where the prediction is evaluated: the start (frozen) or the mean
    /// position over the measured periods (free) (m).
    pub position: [f64; 2],
    /// Realised mean velocity over the measured periods (m/s).
    pub realised: [f64; 2],
    /// Time-weighted steady-state prediction at `position` (m/s).
    pub predicted: [f64; 2],
    /// False when the part left the plate or a steady state failed.
    pub valid: bool,
    /// Why the point is invalid.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// A verification run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verification {
    /// Relative L2 error ‖realised − predicted‖/‖predicted‖ over valid points.
    pub relative_error: f64,
    /// Largest |realised − predicted| over valid points (m/s).
    pub max_abs_error: f64,
    /// RMS of |predicted| over valid points (m/s).
    pub rms_predicted: f64,
    /// Number of valid points.
    pub valid: usize,
    /// Schedule period (s).
    pub schedule_period_s: f64,
    /// Warm-up periods.
    pub warmup_periods: u32,
    /// Measured periods.
    pub periods: u32,
    /// Model name.
    pub model: String,
    /// Per point.
    pub points: Vec<PointResult>,
}

impl Verification {
    /// `Ok` when every point is valid, else a [`Error::Physical`] naming
    /// `context`, how many points are invalid and the first reason.
    pub fn require_all_valid(&self, context: &str) -> crate::error::Result<()> {
        let n = self.points.len();
        if self.valid == n {
            return Ok(());
        }
        let why = self
            .points
            .iter()
            .find_map(|p| p.note.clone())
            .unwrap_or_default();
        Err(crate::error::Error::Physical(format!(
            "{context}: {} of {n} points invalid: {why}",
            n - self.valid
        )))
    }
}

/// `n × n` points over ±`half` (m), row-major (y outer).
pub fn grid_points(n: usize, half: f64) -> Vec<[f64; 2]> {
    Grid {
        x: [-half, half],
        y: [-half, half],
        n: [n, n],
    }
    .points()
}

/// Relative L2 error of `a` against `b` (‖a − b‖/‖b‖; 0/0 = 0).
pub fn relative_l2(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        num += (x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2);
        den += y[0] * y[0] + y[1] * y[1];
    }
    if num == 0.0 {
        0.0
    } else {
        (num / den).sqrt()
    }
}

fn one_point(sm: &ScheduleMotion, p: [f64; 2], opts: &VerifyOptions) -> PointResult {
    let player = sm
        .player(opts.friction, opts.gravity, opts.model, opts.numerics)
        .with_join(opts.join);
    let anchor = V2::from(p);
    let mut state = PartState::new(anchor, V2::zeros());
    let invalid = |note: String| PointResult {
        start: p,
        position: p,
        realised: [0.0; 2],
        predicted: [0.0; 2],
        valid: false,
        note: Some(note),
    };
    if let Err(e) = player.play_periods(&mut state, &anchor, 0, opts.warmup_periods, |_, _, _| {}) {
        return invalid(e.to_string());
    }
    let r0 = state.r;
    // Trapezoidal time-mean of the positions at the joins.
    let mut last: Option<(f64, V2)> = None;
    let mut weighted = V2::zeros();
    let played = player.play_periods(
        &mut state,
        &anchor,
        opts.warmup_periods,
        opts.periods,
        |t, _, s| {
            if let Some((t0, r_prev)) = last {
                weighted += (r_prev + s.r) * (0.5 * (t - t0));
            }
            last = Some((t, s.r));
        },
    );
    if let Err(e) = played {
        return invalid(e.to_string());
    }
    let time = f64::from(opts.periods) * sm.period();
    let realised = (state.r - r0) / time;
    let q = if opts.model.moving {
        weighted / time
    } else {
        anchor
    };
    let mut predicted = V2::zeros();
    for (i, f) in sm.fractions().iter().enumerate() {
        if let Some(sim) = player.simulator(i) {
            match sim.steady_state([q.x, q.y]) {
                Ok(s) => predicted += V2::from(s.velocity) * *f,
                Err(e) => {
                    return PointResult {
                        position: [q.x, q.y],
                        realised: [realised.x, realised.y],
                        ..invalid(format!("steady state of segment {i}: {e}"))
                    }
                }
            }
        }
    }
    PointResult {
        start: p,
        position: [q.x, q.y],
        realised: [realised.x, realised.y],
        predicted: [predicted.x, predicted.y],
        valid: true,
        note: None,
    }
}

/// Plays `sm` from every start point (in parallel) and compares the realised
/// mean velocities with the time-weighted steady-state prediction.
pub fn verify_points(
    sm: &ScheduleMotion,
    points: &[[f64; 2]],
    opts: &VerifyOptions,
) -> Verification {
    let results: Vec<PointResult> = points.par_iter().map(|p| one_point(sm, *p, opts)).collect();
    let ok: Vec<&PointResult> = results.iter().filter(|r| r.valid).collect();
    let real: Vec<[f64; 2]> = ok.iter().map(|r| r.realised).collect();
    let pred: Vec<[f64; 2]> = ok.iter().map(|r| r.predicted).collect();
    let max_abs_error = ok
        .iter()
        .map(|r| (r.realised[0] - r.predicted[0]).hypot(r.realised[1] - r.predicted[1]))
        .fold(0.0, f64::max);
    let rms_predicted = if ok.is_empty() {
        0.0
    } else {
        (pred.iter().map(|v| v[0] * v[0] + v[1] * v[1]).sum::<f64>() / ok.len() as f64).sqrt()
    };
    Verification {
        relative_error: if ok.is_empty() {
            f64::NAN
        } else {
            relative_l2(&real, &pred)
        },
        max_abs_error,
        rms_predicted,
        valid: ok.len(),
        schedule_period_s: sm.period(),
        warmup_periods: opts.warmup_periods,
        periods: opts.periods,
        model: opts.model.name(),
        points: results,
    }
}
