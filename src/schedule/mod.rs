//! Schedules: what `platefield design` writes to `schedule.json`, and what
//! `export`, `verify` and `order` read back.
//!
//! A schedule is a sequence of segments, each a primitive plate motion or a
//! six-signal motion (the scene `signals` format, e.g. a synthesized one,
//! [`crate::synth`]) played for whole cycles, or the plate at rest,
//! repeated with the schedule period. The file also records the design's fit, its solver
//! facts, the basis it was fitted on and the simulation settings the basis
//! was built with (typed: `BasisInfo`, [`FieldSettings`]).
//!
//! **One loader.** [`Schedule::load`] is the only way a command reads a
//! schedule: serde with unknown keys rejected (errors carry the JSON path,
//! e.g. `segments[1].primitive.omega`), then `Schedule::validate` (ranges
//! and physics), then the derived quantities are recomputed from the
//! segments ([`Schedule::derive`]): a moving segment lasts `cycles` periods
//! of its primitive or motion, and `period_s` and `total_cycles` are sums over the
//! segments. The `duration_s`, `period_s` and `total_cycles` written in a
//! file are for the reader; they are never trusted, so `export` and
//! `verify` play the same thing from one file. A rest segment has neither a
//! primitive nor a motion and keeps its `duration_s`.
//!
//! **Six-signal segments.** A segment may hold `"motion": {"period": T,
//! "linear": {...}, "angular": {...}}` ([`crate::motion::Signals`], the
//! scene file's `signals` object) instead of a `primitive`; never both. Its
//! signals are validated by the scene validators (errors name
//! `segments[i].motion.linear.x[0].amplitude` etc.). The key is optional:
//! it is left out when absent, so a schedule of primitives only is written
//! without it.
//!
//! `mod@quantize` turns time fractions into whole cycles; [`export`] writes
//! the six controller signals of a schedule.

pub mod export;
pub(crate) mod played;
pub(crate) mod quantize;
mod rungs;

use std::path::Path;

use serde::{Deserialize, Serialize, Serializer};

use crate::basis::Primitive;
use crate::error::{non_negative, Error, Result};
use crate::field::{FieldKind, FieldSettings, Validity};
use crate::fit::FitMetrics;
use crate::motion::{Motion, Ramped, Signals};
use crate::request::Target;

pub use played::AxisPeaks;
pub use played::Method;
pub use played::Played;
pub use played::PoseAtFriction;
pub(crate) use played::PoseBasin;
pub use played::PoseOverFriction;
pub use played::PosePlayed;
pub(crate) use quantize::quantize;
pub(crate) use quantize::Quantized;
pub use quantize::{DEFAULT_MIN_CYCLES, DEFAULT_QUANTIZATION_TOL};
pub use rungs::{RecordedRungs, RecordedSegmentRung, ScheduleRungs, SegmentRung};

/// Most cycles of one segment (about 50 minutes of plate motion at the
/// paper's 30 ms cycle).
pub(crate) const MAX_SEGMENT_CYCLES: u32 = 100_000;
/// Longest schedule period (s).
pub const MAX_PERIOD_S: f64 = 3600.0;

/// One segment of a schedule.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Segment {
    /// Human-readable label, e.g. `LineSink@90°`.
    pub label: String,
    /// The primitive with all its parameters (rotation, shift included);
    /// `None` for a rest segment (plate at rest in the home pose) or a
    /// six-signal segment.
    pub primitive: Option<Primitive>,
    /// A six-signal motion (scene `signals` format) played instead of a
    /// primitive; `None` (and absent from the file) otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<Signals>,
    /// For a six-signal segment among other moving segments: cycles of the
    /// smooth ramp-in from rest and of the ramp-out back to rest, inside
    /// the segment's `cycles` ([`crate::motion::Ramped`]). `None` (absent
    /// from the file) plays the motion steadily: the one moving segment of
    /// a schedule, repeated.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ramp_cycles: Option<u32>,
    /// Time fraction from the fit (continuous).
    pub weight: f64,
    /// Whole cycles.
    pub cycles: u32,
    /// Duration (s): `cycles` periods of the primitive (derived on load),
    /// or the rest time of a rest segment.
    pub duration_s: f64,
}

impl Segment {
    /// The plate motion this segment plays: its primitive's motion
    /// (rotation and shift applied) or its six signals; `None` for rest.
    pub fn plate_motion(&self) -> Option<Motion> {
        match (&self.primitive, &self.motion) {
            (Some(p), _) => Some(p.motion()),
            (None, Some(s)) => Some(match self.ramp_cycles {
                None => Motion::Signals(s.clone()),
                Some(ramp) => Motion::Ramped(Ramped {
                    signals: s.clone(),
                    ramp,
                    cycles: self.cycles,
                }),
            }),
            (None, None) => None,
        }
    }

    /// The periodic motion this segment plays between its ramps (the
    /// primitive's motion or its six signals without the ramp window): what
    /// a steady-state field of the segment is computed on. `None` for rest.
    pub(crate) fn steady_motion(&self) -> Option<Motion> {
        match (&self.primitive, &self.motion) {
            (Some(p), _) => Some(p.motion()),
            (None, Some(s)) => Some(Motion::Signals(s.clone())),
            (None, None) => None,
        }
    }

    /// True when the plate moves during this segment.
    pub fn is_moving(&self) -> bool {
        self.primitive.is_some() || self.motion.is_some()
    }

    /// Period (s) of one cycle of the segment's motion (`None` for rest).
    pub fn cycle_period(&self) -> Option<f64> {
        match (&self.primitive, &self.motion) {
            (Some(p), _) => Some(p.period()),
            (None, Some(s)) => Some(s.period),
            (None, None) => None,
        }
    }

    /// Validates the segment's primitive or motion (not both), naming
    /// `{at}.primitive…` or `{at}.motion…`, and its ramp (only on a
    /// six-signal motion, 1 ≤ ramp ≤ cycles/2, `{at}.ramp_cycles`).
    pub(crate) fn validate_motion(&self, at: &str) -> Result<()> {
        if let Some(ramp) = self.ramp_cycles {
            if self.motion.is_none() {
                return Err(Error::invalid(
                    format!("{at}.ramp_cycles"),
                    "only a six-signal segment (with a `motion`) is ramped",
                ));
            }
            Ramped::check(ramp, self.cycles, at)?;
        }
        match (&self.primitive, &self.motion) {
            (Some(_), Some(_)) => Err(Error::invalid(
                format!("{at}.motion"),
                "a segment holds a primitive or a six-signal motion, not both",
            )),
            (Some(p), None) => crate::scene::validate_primitive(p, &format!("{at}.primitive")),
            (None, Some(s)) => crate::scene::validate_signals(s, &format!("{at}.motion")),
            (None, None) => Ok(()),
        }
    }
}

/// Solver facts recorded with a schedule (no timings: the file changes only
/// when its content does).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverInfo {
    /// Fit mode.
    pub mode: String,
    /// Solver status.
    pub status: String,
    /// Interior-point iterations.
    pub iterations: u32,
    /// KKT residual of the verified solution.
    pub kkt_residual: f64,
    /// Gap to the independent solver.
    pub independent_gap: f64,
}

/// Why a column was left out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ExclusionReason {
    /// Invalid somewhere in the region: the most common flag.
    Invalid(Validity),
    /// A rotated copy of an isotropic primitive (see the module docs).
    IsotropicCopy {
        /// Label of the copy kept (rotation 0, same shift).
        copy_of: String,
        /// Relative L2 change of the source field under this copy's
        /// rotation ([`crate::basis::symmetry::rotation_asymmetry`]).
        rotation_change: f64,
    },
    /// Its peak acceleration, velocity or stroke on an axis exceeds the
    /// target's `shaker` limit ([`export::peaks::KinematicPeaks`]).
    OverLimit {
        /// Axis (`linear.x`, …, `angular.z`), followed by ` velocity` or
        /// ` stroke` when that is the limit exceeded.
        axis: String,
        /// The primitive's peak on that axis (m/s² or rad/s²; m/s or rad/s;
        /// m or rad).
        peak: f64,
        /// The limit.
        limit: f64,
    },
}

impl std::fmt::Display for ExclusionReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExclusionReason::Invalid(v) => write!(f, "{v}"),
            ExclusionReason::IsotropicCopy {
                copy_of,
                rotation_change,
            } => write!(
                f,
                "isotropic: rotated copy of {copy_of} (field changes by {rotation_change:.1e})"
            ),
            ExclusionReason::OverLimit { axis, peak, limit } => write!(
                f,
                "over the shaker limit: {axis} peak {peak:.4} > {limit:.4}"
            ),
        }
    }
}

/// A basis column left out of the fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExcludedColumn {
    /// Invalid samples in the region.
    pub invalid_samples: usize,
    /// Primitive name with rotation and shift.
    pub label: String,
    /// Why: for invalid columns, the most common flag.
    pub reason: ExclusionReason,
}

/// A basis column kept although it is invalid at some target points
/// (`--keep-invalid`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct KeptColumn {
    /// Indices of the target points where the column is invalid.
    pub invalid_points: Vec<usize>,
    /// Primitive name with rotation and shift.
    pub label: String,
}

/// What the schedule was fitted on (fields in alphabetical order, as the
/// file has always listed them).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BasisInfo {
    /// Usable columns.
    pub columns: usize,
    /// Columns left out.
    pub excluded: Vec<ExcludedColumn>,
    /// Columns kept with invalid points.
    pub(crate) kept_with_invalid_points: Vec<KeptColumn>,
    /// Field kind of the columns.
    pub kind: FieldKind,
    /// Rotation step of the basis copies (degrees).
    pub rotation_step_deg: f64,
    /// Horizontal shifts of the basis copies (m).
    pub shifts: Vec<[f64; 2]>,
}

/// A designed schedule, as written to `schedule.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Schedule {
    /// Target name.
    pub target: String,
    /// The target itself (field, grid, weights, mask), so that
    /// verification knows the region and the attractor; absent in schedules
    /// written before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target_spec: Option<Target>,
    /// Segments in playing order (rest segments have no primitive).
    pub segments: Vec<Segment>,
    /// Total cycles (including rest); derived.
    pub total_cycles: u32,
    /// Schedule period (s): one pass through all segments; derived.
    pub period_s: f64,
    /// Minimum cycles per segment used.
    pub min_cycles: u32,
    /// Fit metrics of the continuous time fractions.
    pub fit: FitMetrics,
    /// Fit metrics of the whole-cycle schedule.
    pub fit_quantized: FitMetrics,
    /// Field quantisation error ‖A(q − f)‖/‖A f‖.
    pub quantization_error: f64,
    /// True when the best achievable fit is poor (relative error > 0.5).
    pub poor_fit: bool,
    /// Solver facts.
    pub solver: SolverInfo,
    /// Basis facts: field kind, columns used, columns excluded.
    pub(crate) basis: BasisInfo,
    /// Simulation settings the basis was built with, and the physics the
    /// schedule is played at; under `design --model`, `model` is the model
    /// the design was judged at (the basis is built at the options' own,
    /// full by default), and `rungs` says why.
    #[serde(serialize_with = "keys_sorted")]
    pub settings: FieldSettings,
    /// How `design` chose this schedule and what it realises when played
    /// (absent in schedules written before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub played: Option<Played>,
    /// The model rungs `design --model auto` chose ([`RecordedRungs`]):
    /// the schedule is played at `settings.model`, the rung recorded here;
    /// absent when the design chose none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rungs: Option<RecordedRungs>,
}

/// Serialises `value` with its object keys in alphabetical order (the
/// order `schedule.json` has always used for the settings).
fn keys_sorted<T: Serialize, S: Serializer>(value: &T, s: S) -> Result<S::Ok, S::Error> {
    serde_json::to_value(value)
        .map_err(serde::ser::Error::custom)?
        .serialize(s)
}

impl Schedule {
    /// Every moving segment plays one cycle period T (to 1e-9 of it): the
    /// design fits primitives (and a six-signal motion) of one period,
    /// `export` lays every segment on one sample grid Δt = T/round(rate·T),
    /// and `verify` plays whole periods. The period the most moving segments
    /// share is the schedule's (on a tie, the primitives' default period
    /// 2π/ω₀, then the first segment's), and the first segment off it is
    /// named at the key that sets its period (`segments[i].primitive.omega`
    /// or `segments[i].motion.period`), so an edited segment is named
    /// whichever its place.
    fn check_one_cycle_period(&self) -> Result<()> {
        let periods: Vec<(usize, f64)> = self
            .segments
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.cycle_period().map(|t| (i, t)))
            .collect();
        let same = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
        let default = Primitive::new(crate::basis::PrimitiveKind::Trans).period();
        let rank = |t: f64| {
            let shared = periods.iter().filter(|(_, u)| same(t, *u)).count();
            (shared, same(t, default))
        };
        // `max_by_key` keeps the last of equal keys: look from the end so
        // that the first segment wins a full tie.
        let Some(&(_, period)) = periods.iter().rev().max_by_key(|(_, t)| rank(*t)) else {
            return Ok(());
        };
        match periods.iter().find(|(_, t)| !same(*t, period)) {
            None => Ok(()),
            Some(&(i, t)) => {
                let key = if self.segments[i].primitive.is_some() {
                    "primitive.omega"
                } else {
                    "motion.period"
                };
                Err(Error::invalid(
                    format!("segments[{i}].{key}"),
                    format!(
                        "the segment plays cycles of {} s, the schedule's other moving segments {} s: every moving segment must play one cycle period (export lays all on one sample grid)",
                        crate::input::num(t),
                        crate::input::num(period)
                    ),
                ))
            }
        }
    }

    /// Reads, validates and derives a schedule file (see the module
    /// documentation). Errors name the file and the JSON path.
    pub fn load(path: &Path) -> Result<Schedule> {
        let text = crate::input::read_input(path).map_err(|e| Error::Io {
            path: path.display().to_string(),
            source: e,
        })?;
        Schedule::from_json_str(&text, &path.display().to_string())
    }

    /// [`Schedule::load`] from text; `origin` (a file name) prefixes error paths.
    pub fn from_json_str(text: &str, origin: &str) -> Result<Schedule> {
        let mut schedule: Schedule = crate::input::from_str(text, "schedule")
            .map_err(|e| Error::invalid(format!("{origin}: {}", e.path), e.message))?;
        schedule.validate().map_err(|e| prefix_origin(e, origin))?;
        schedule.derive();
        Ok(schedule)
    }

    /// Checks ranges and physics (errors name the JSON path): at least one
    /// segment of positive duration; moving segments with a valid primitive
    /// (the scene ranges, [`crate::scene::validate_primitive`])
    /// and 1..=`MAX_SEGMENT_CYCLES` cycles; rest segments with a finite
    /// duration ≥ 0; a period of at most [`MAX_PERIOD_S`]; weights finite
    /// and ≥ 0; valid settings and target.
    pub(crate) fn validate(&self) -> Result<()> {
        if self.segments.is_empty() {
            return Err(Error::invalid(
                "segments",
                "must hold at least one segment, got []",
            ));
        }
        let mut period = 0.0;
        for (i, seg) in self.segments.iter().enumerate() {
            let at = format!("segments[{i}]");
            non_negative(&format!("{at}.weight"), seg.weight)?;
            seg.validate_motion(&at)?;
            match seg.cycle_period() {
                Some(cycle) => {
                    if !(1..=MAX_SEGMENT_CYCLES).contains(&seg.cycles) {
                        return Err(Error::invalid(
                            format!("{at}.cycles"),
                            format!("must be in 1..={MAX_SEGMENT_CYCLES}, got {}", seg.cycles),
                        ));
                    }
                    period += f64::from(seg.cycles) * cycle;
                }
                None => period += non_negative(&format!("{at}.duration_s"), seg.duration_s)?,
            }
        }
        let moving = self.segments.iter().filter(|s| s.is_moving()).count();
        if moving > 1 {
            if let Some(i) = self
                .segments
                .iter()
                .position(|s| s.motion.is_some() && s.ramp_cycles.is_none())
            {
                return Err(Error::invalid(
                    format!("segments[{i}].ramp_cycles"),
                    format!("a six-signal segment among {moving} moving segments must ramp in from rest and out to rest (ramp_cycles ≥ 1); the plate would jump at its joins"),
                ));
            }
        }
        self.check_one_cycle_period()?;
        if period.is_nan() || period <= 0.0 {
            return Err(Error::invalid(
                "segments",
                "must hold at least one segment of positive duration",
            ));
        }
        if period > MAX_PERIOD_S {
            return Err(Error::invalid(
                "segments",
                format!("the schedule period is {period:.4e} s, more than {MAX_PERIOD_S} s"),
            ));
        }
        self.validate_settings()
    }

    /// The settings' checks of [`Schedule::validate`] (the scene's ranges:
    /// friction, numerics, each six-signal motion resolved by the steps,
    /// the steady-state iterations, gravity) and the target's.
    fn validate_settings(&self) -> Result<()> {
        let s = &self.settings;
        // The scene's one friction validation (a schedule is played like a scene).
        crate::scene::FrictionSpec::exact(s.friction).validate("settings.friction")?;
        s.numerics.validate("settings.numerics")?;
        for (i, seg) in self.segments.iter().enumerate() {
            if let Some(m) = &seg.motion {
                crate::scene::validate_resolved(
                    &crate::motion::Motion::Signals(m.clone()),
                    &format!("segments[{i}].motion"),
                    s.numerics.steps_per_cycle,
                    "settings.numerics.steps_per_cycle",
                )?;
            }
        }
        // The scene's bound: every cycle-map evaluation of a steady state
        // that does not converge is played (1e9 ran for hours).
        let iterations = &crate::scene::MAX_ITERATIONS;
        if !iterations.contains(&s.numerics.max_iterations) {
            return Err(Error::invalid(
                "settings.numerics.max_iterations",
                format!(
                    "must be in {}..={}, got {}",
                    iterations.start(),
                    iterations.end(),
                    s.numerics.max_iterations
                ),
            ));
        }
        // The scene's range of gravity (1e-300 passed as "positive").
        let (g_min, g_max) = (crate::scene::GRAVITY_MIN, crate::scene::GRAVITY);
        if !(g_min..=g_max).contains(&s.gravity) {
            return Err(Error::invalid(
                "settings.gravity",
                format!(
                    "must be in [{}, {}] m/s², got {}",
                    crate::input::num(g_min),
                    crate::input::num(g_max),
                    crate::input::num(s.gravity)
                ),
            ));
        }
        if let Some(t) = &self.target_spec {
            t.validate()?;
        }
        if let Some(r) = &self.rungs {
            r.validate(self)?;
        }
        Ok(())
    }

    /// Recomputes the derived quantities from the segments: a moving
    /// segment's duration (`cycles` periods of its primitive or motion),
    /// the total cycles and the period.
    pub fn derive(&mut self) {
        for seg in &mut self.segments {
            if let Some(cycle) = seg.cycle_period() {
                seg.duration_s = f64::from(seg.cycles) * cycle;
            }
        }
        self.total_cycles = self
            .segments
            .iter()
            .fold(0u32, |n, s| n.saturating_add(s.cycles));
        self.period_s = self.segments.iter().map(|s| s.duration_s).sum();
    }

    /// A schedule built by hand from `segments` (not by a fit): `fit` is the
    /// field it claims (both metrics), no basis, solver mode `"none"`, a
    /// minimum of 1 cycle per segment; derived quantities computed.
    pub(crate) fn of_segments(
        target: &str,
        segments: Vec<Segment>,
        settings: FieldSettings,
        fit: FitMetrics,
    ) -> Schedule {
        let mut s = Schedule {
            target: target.into(),
            target_spec: None,
            segments,
            total_cycles: 0,
            period_s: 0.0,
            min_cycles: 1,
            fit,
            fit_quantized: fit,
            quantization_error: 0.0,
            poor_fit: false,
            solver: SolverInfo {
                mode: "none".into(),
                status: "built by hand".into(),
                iterations: 0,
                kkt_residual: 0.0,
                independent_gap: 0.0,
            },
            basis: BasisInfo {
                columns: 0,
                excluded: Vec::new(),
                kept_with_invalid_points: Vec::new(),
                kind: FieldKind::Velocity,
                rotation_step_deg: 0.0,
                shifts: Vec::new(),
            },
            settings,
            played: None,
            rungs: None,
        };
        s.derive();
        s
    }

    /// The same schedule with other segments (derived quantities recomputed).
    pub fn with_segments(&self, segments: Vec<Segment>) -> Schedule {
        let mut out = Schedule {
            segments,
            ..self.clone()
        };
        out.derive();
        out
    }

    /// The region the schedule is verified over (`verify`, `design
    /// --model auto`'s rung points, `calibrate`'s tracks): the target's
    /// grid; for a grid-less `sampled` target, the region its basis was
    /// resampled on (`crate::request::scattered_grid`: the samples'
    /// bounding box rounded outward to its lattice); ±3 cm when the
    /// schedule records no target.
    ///
    /// ```
    /// use platefield::schedule::Schedule;
    /// let s = Schedule::load("results/sink/schedule.json".as_ref())?;
    /// assert_eq!(Some(s.region()), s.target_spec.as_ref().and_then(|t| t.grid));
    /// # Ok::<(), platefield::Error>(())
    /// ```
    pub fn region(&self) -> crate::field::Grid {
        const UNRECORDED: crate::field::Grid = crate::field::Grid {
            x: [-0.03, 0.03],
            y: [-0.03, 0.03],
            n: [5, 5],
        };
        match self.target_spec.as_ref().map(|t| (&t.grid, &t.field)) {
            Some((Some(g), _)) => *g,
            Some((None, crate::request::FieldSpec::Sampled { points, .. })) => {
                crate::request::scattered_grid(points)
            }
            _ => UNRECORDED,
        }
    }

    /// Time (s) per period in which the plate moves.
    pub(crate) fn moving_time(&self) -> f64 {
        self.segments
            .iter()
            .filter(|s| s.is_moving())
            .map(|s| s.duration_s)
            .sum()
    }

    /// The target name, checked to be a plain folder name (results go to
    /// `OUT/<target>/`).
    pub fn target_folder(&self) -> Result<&str> {
        let name = self.target.as_str();
        crate::request::plain_folder_name(name, "target")?;
        Ok(name)
    }

    /// The schedule's fingerprint: the first 16 hex digits of the SHA-256
    /// of its segments as compact JSON (what its export plays; the design
    /// report beside them does not count). `export` writes it in the
    /// CSV's header and `verify --replay` checks it.
    pub(crate) fn fingerprint(&self) -> String {
        use sha2::{Digest, Sha256};
        let json = serde_json::to_string(&self.segments).unwrap_or_default();
        Sha256::digest(json.as_bytes())
            .iter()
            .take(8)
            .map(|b| format!("{b:02x}"))
            .collect()
    }

    /// The schedule as pretty JSON with a final newline.
    pub fn to_json(&self) -> Result<String> {
        let mut text =
            serde_json::to_string_pretty(self).map_err(|e| Error::Internal(e.to_string()))?;
        text.push('\n');
        Ok(text)
    }
}

/// Prefixes the field of an [`Error::Invalid`] with the file it came from.
fn prefix_origin(e: Error, origin: &str) -> Error {
    match e {
        Error::Invalid { field, message } => Error::invalid(format!("{origin}: {field}"), message),
        e => e,
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `schedule::Schedule::fingerprint`.
    #[test]
    fn example_schedule_fingerprint() -> Result<(), crate::Error> {
        use crate::schedule::Schedule;
        let s = Schedule::load("results/synthesized/sink/schedule.json".as_ref())?;
        let f = s.fingerprint();
        assert_eq!(f.len(), 16);
        let mut other = s.clone();
        other.segments[0].cycles += 1;
        assert_ne!(other.fingerprint(), f);
        Ok(())
    }
}
