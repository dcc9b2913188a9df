//! `platefield verify SCHEDULE.json`: the whole closed-loop check of a
//! designed schedule, written under `OUT/<target>/verify/`.
//!
//! 1. The realised field against the prediction
//!    ([`crate::play::measure::verify_points`]) on an
//!    n × n grid of point parts over the target region.
//! 2. A swarm of point parts over the region for a duration
//!    (`super::swarm`): where they end up, the fraction converged to the
//!    target's attractor, and the time it takes against the time the
//!    design's strength predicts.
//! 3. Uniform rectangles ([`super::rectangles`], 2 cm × 0.5 cm by default)
//!    from several start poses for the swarm's duration: final pose, the
//!    distance to the attractor and, for a line attractor, the angle of the
//!    long side to the line.
//!
//! Everything is computed here and nothing is written: the files
//! (`summary.json`, `trajectories.svg`) are `platefield_report::verify`'s.
//! Before anything is played the work is estimated ([`work_estimate`]) and
//! an overlong verification refused unless `--allow-long`.

use std::path::Path;

use serde::Serialize;

use super::friction::FrictionArg;
use super::judged::JudgedChecks;
use super::rectangles::{play_rectangle, PoseSample, RectangleOptions, RectangleSummary};
use super::swarm::{run_swarm_ticked, Swarm, SwarmOptions};
use crate::dynamics::Model;
use crate::dynamics::Rectangle;
use crate::error::{Error, Result};
use crate::field::Grid;
use crate::play::measure::{verify_points_ticked, ModelCheck, PlayOptions};
use crate::play::sensitivity::Sensitivity;
use crate::play::{ScheduleMotion, V2};
use crate::progress::Progress;
use crate::request::Attractor;
use crate::schedule::Schedule;
use crate::work::{Estimate, Term, PLANAR_POINT_STEP_COST};

/// How long the swarm is played.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Duration {
    /// 1.5 × the longest predicted time to converge from a start point plus
    /// one schedule period, or 10 schedule periods without an attractor;
    /// at most `MAX_AUTO_PERIODS`.
    /// Rectangles play at least `RECT_MIN_AUTO_S`.
    Auto,
    /// At least this many seconds (rounded up to whole schedule periods).
    Seconds(f64),
    /// This many schedule periods.
    Repetitions(u32),
}

/// Longest automatic swarm duration (schedule periods).
pub(crate) const MAX_AUTO_PERIODS: u32 = 200;

/// What `platefield verify` is asked to do.
#[derive(Debug, Clone, PartialEq)]
pub struct VerifyRequest {
    /// Realised-field grid: points per side.
    pub points: usize,
    /// Warm-up periods before the realised field is measured.
    pub warmup: u32,
    /// Periods measured.
    pub periods: u32,
    /// Model override (default: the schedule's own).
    pub model: Option<Model>,
    /// Automatic model: each moving segment's cheapest rung within this
    /// relative L2 tolerance of `full` at the realised grid's points
    /// ([`Schedule::rungs`], the rule in [`crate::field::rung`]), the
    /// schedule played at the cheapest rung acceptable for every segment
    /// (one model per play). Excludes `model`; `None`: no choice.
    pub rung_tolerance: Option<f64>,
    /// Swarm grid: parts per side.
    pub swarm: usize,
    /// Swarm duration.
    pub duration: Duration,
    /// Convergence tolerance (m).
    pub tol: f64,
    /// Rectangle length and width (m).
    pub rectangle: [f64; 2],
    /// Rectangle start poses (0: none).
    pub rectangle_poses: usize,
    /// Progress output and the long-run guard.
    pub runtime: crate::work::Runtime,
    /// Another friction to play at, or a sweep ([`super::friction`];
    /// default: the schedule's own).
    pub friction: Option<FrictionArg>,
    /// The schedule's exported CSV, or an accelerometer recording of it
    /// (header-less, `design::replay::conform`), to replay beside its own
    /// play (`design::replay`, judged in the report layer).
    pub replay: Option<std::path::PathBuf>,
    /// The recording's rate (samples/s) when its rows hold the six
    /// channels without t.
    pub replay_rate: Option<f64>,
    /// Judge the schedule under the shaker's delivery error
    /// ([`crate::design::tolerance`]) within this tolerance, or within the
    /// target's `shaker.tolerance` (`Some(None)`), at the friction where
    /// the design's worst case falls.
    pub tolerance: Option<Option<crate::request::Tolerance>>,
    /// Delivery-error draws of `tolerance`.
    pub draws: usize,
}

impl Default for VerifyRequest {
    fn default() -> Self {
        VerifyRequest {
            points: 5,
            warmup: 1,
            periods: 1,
            model: None,
            rung_tolerance: None,
            swarm: 9,
            duration: Duration::Auto,
            tol: 0.003,
            rectangle: [0.02, 0.005],
            rectangle_poses: 4,
            runtime: crate::work::Runtime::default(),
            friction: None,
            replay: None,
            replay_rate: None,
            tolerance: None,
            draws: crate::design::tolerance::DEFAULT_DRAWS,
        }
    }
}

impl VerifyRequest {
    /// Checks ranges, naming the command-line argument.
    pub(crate) fn validate(&self) -> Result<()> {
        let range = |name: &str, v: u64, lo: u64, hi: u64| -> Result<()> {
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(Error::invalid(
                    name,
                    format!("must be in {lo}..={hi}, got {v}"),
                ))
            }
        };
        // One point per side is the region's centre alone (for most
        // targets the attractor, where the field vanishes): the
        // least-squares strength κ = ⟨R, E⟩/⟨E, E⟩ and the shape error
        // ‖R − κE‖/‖κE‖ of one vector measure its direction and noise, not
        // a field's shape (the sink's reads several hundred per cent). 2
        // per side: the four
        // corners, 8 components for the one fitted scale.
        if self.points < 2 {
            return Err(Error::invalid(
                "--points",
                format!(
                    "must be in 2..=101, got {}: the realised strength and shape error are least-squares fits over the N×N grid of points, and N = 1 is the region's centre alone (usually the attractor, where the field is zero)",
                    self.points
                ),
            ));
        }
        range("--points", self.points as u64, 2, 101)?;
        range("--periods", u64::from(self.periods), 1, 1000)?;
        range("--warmup", u64::from(self.warmup), 0, 1000)?;
        range("--swarm", self.swarm as u64, 1, 101)?;
        match self.duration {
            Duration::Seconds(s) if !(s.is_finite() && s > 0.0 && s <= 3600.0) => {
                return Err(Error::invalid(
                    "--duration",
                    format!("must be in (0, 3600] seconds, got {}", crate::input::num(s)),
                ))
            }
            Duration::Repetitions(n) => range("--repetitions", u64::from(n), 1, 10_000)?,
            _ => {}
        }
        range("--rect-poses", self.rectangle_poses as u64, 0, 64)?;
        for (v, what) in self.rectangle.iter().zip(["length", "width"]) {
            if !(v.is_finite() && *v > 0.0 && *v <= 0.2) {
                return Err(Error::invalid(
                    "--rect",
                    format!(
                        "{what} must be in (0, 0.2] m, got {}",
                        crate::input::num(*v)
                    ),
                ));
            }
        }
        if let Some(t) = self.rung_tolerance {
            if self.model.is_some() {
                return Err(Error::invalid(
                    "--model",
                    "give either a model or auto (a tolerance for the automatic rung), not both",
                ));
            }
            crate::error::non_negative("--model", t)?;
        }
        if !(self.tol.is_finite() && self.tol > 0.0 && self.tol <= 0.1) {
            return Err(Error::invalid(
                "--tol",
                format!("must be in (0, 0.1] m, got {}", crate::input::num(self.tol)),
            ));
        }
        Ok(())
    }
}

/// What a verification produced (written by `crate::report::verify`).
#[derive(Debug, Clone)]
pub struct VerifyReport {
    /// The schedule's target name (a plain folder name).
    pub target: String,
    /// The region verified.
    pub region: Grid,
    /// What was asked.
    pub request: VerifyRequest,
    /// The strength the schedule's design claims (s⁻¹ for linear fields):
    /// its stored `fit.strength`.
    pub design_strength: f64,
    /// The judge of the schedule against the target it records, under the
    /// physics played ([`crate::design::judge`]: the realised field at
    /// frozen points over the whole region); `None` when it records none.
    pub judge: Option<crate::play::sensitivity::Judged>,
    /// The automatic model's rungs per segment (`rung_tolerance`).
    pub rungs: Option<crate::schedule::ScheduleRungs>,
    /// The rungs the schedule records (`design --model auto`), when it is
    /// played at its own model (no `model`, no `rung_tolerance`): its
    /// `settings.model` is their rung played.
    pub recorded_rungs: Option<crate::schedule::RecordedRungs>,
    /// The model check: moving parts against the prediction.
    pub model_check: ModelCheck,
    /// The swarm.
    pub swarm: Swarm,
    /// The rectangles.
    pub rectangles: Vec<RectangleResult>,
    /// The friction sweep (`--friction LO:HI:N`).
    pub friction_sweep: Option<Sensitivity>,
    /// The schedule played and its export replayed (`--replay`), judged
    /// by the report layer like the sweep.
    pub replay: Option<crate::play::replay::ReplayCheck>,
    /// The judge over delivery errors (`--tolerance`).
    pub tolerance: Option<crate::design::tolerance::Spread>,
    /// For a sort's schedule (its target has classes): every class's
    /// swarm at its own friction, the schedule played and the export
    /// replayed (`--replay`) ([`super::sort_play::verify_sort`]).
    pub sort: Option<super::sort_play::SortVerify>,
}

/// `n × n` points over the extent of `g`, row-major (y outer).
pub fn region_points(g: &Grid, n: usize) -> Vec<[f64; 2]> {
    Grid {
        x: g.x,
        y: g.y,
        n: [n, n],
    }
    .points()
}

/// Whole schedule periods the swarm is played.
pub fn swarm_periods(
    duration: Duration,
    period: f64,
    attractor: Option<&Attractor>,
    starts: &[[f64; 2]],
    strength: f64,
    tol: f64,
) -> u32 {
    match duration {
        Duration::Repetitions(n) => n,
        Duration::Seconds(s) => ((s / period - 1e-9).ceil().max(1.0)) as u32,
        Duration::Auto => match attractor {
            Some(a) if strength > 0.0 => {
                let longest = starts
                    .iter()
                    .map(|p| a.predicted_time(*p, strength, tol))
                    .fold(0.0, f64::max);
                ((1.5 * longest / period).ceil() as u32 + 1).min(MAX_AUTO_PERIODS)
            }
            _ => 10,
        },
    }
}

/// With an automatic duration rectangles play at least this long (s):
/// turning a 2 cm strip onto a LineSink's line takes about 10 s
/// (`tests/unit/planar.rs`), longer than a point part needs to reach it.
pub(crate) const RECT_MIN_AUTO_S: f64 = 20.0;

/// Support points along a rectangle's length (its width gets the same
/// spacing, at least one row): 16 along 2 cm resolves the friction torque
/// to about 1 % (`tests/unit/planar.rs`).
pub(crate) const RECT_POINTS_ALONG: usize = 16;

/// A rectangle of `size` = [length, width] sampled by support points at
/// the spacing of [`RECT_POINTS_ALONG`] points along its length.
pub(crate) fn sampled_rectangle(size: [f64; 2]) -> Rectangle {
    let ny = ((RECT_POINTS_ALONG as f64 * size[1] / size[0]).round() as usize)
        .clamp(1, crate::dynamics::MAX_POINTS_PER_SIDE);
    Rectangle::new(size[0], size[1], RECT_POINTS_ALONG, ny)
}

/// `n` start poses (centre, angle in rad) spread over the region: on a
/// circle of 0.6 × the smaller half-extent around the region's centre, at
/// angles 45° + k·360°/n, each rectangle turned by k·(180°/n) + 30°.
pub(crate) fn rectangle_poses(g: &Grid, n: usize) -> Vec<(V2, f64)> {
    let c = V2::new(0.5 * (g.x[0] + g.x[1]), 0.5 * (g.y[0] + g.y[1]));
    let rad = 0.3 * (g.x[1] - g.x[0]).min(g.y[1] - g.y[0]);
    (0..n)
        .map(|k| {
            let phi = std::f64::consts::FRAC_PI_4 + std::f64::consts::TAU * k as f64 / n as f64;
            let theta = (30.0 + 180.0 * k as f64 / n as f64).to_radians();
            (c + V2::new(phi.cos(), phi.sin()) * rad, theta)
        })
        .collect()
}

/// One rectangle of a verification.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RectangleResult {
    /// Start pose and final pose.
    #[serde(flatten)]
    pub summary: Option<RectangleSummary>,
    /// Start centre (m) and angle (degrees), also for a failed run.
    pub start_pose: [f64; 3],
    /// Distance of the final centre to the target's attractor (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distance_to_attractor_m: Option<f64>,
    /// For a line attractor: the angle between the long side and the line
    /// (degrees, in [0, 90]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub angle_to_line_deg: Option<f64>,
    /// Why the run failed (the rectangle left the plate).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// Poses at the start and at every segment end.
    #[serde(skip)]
    pub trajectory: Vec<PoseSample>,
}

/// Plays rectangles of `size` from `poses` for `periods` schedule periods
/// (whole periods, so the final pose is at the end of a cycle), in
/// parallel, collected in input order.
pub(crate) fn run_rectangles(
    sm: &ScheduleMotion,
    size: [f64; 2],
    poses: &[(V2, f64)],
    periods: u32,
    attractor: Option<&Attractor>,
    opts: &RectangleOptions,
    tick: &(dyn Fn() + Sync),
) -> Vec<RectangleResult> {
    use rayon::prelude::*;
    let rect = sampled_rectangle(size);
    let duration = f64::from(periods) * sm.period();
    poses
        .par_iter()
        .map(|&(r, theta)| {
            let start_pose = [r.x, r.y, theta.to_degrees()];
            let played = play_rectangle(sm, &rect, (r, theta), duration, opts);
            tick();
            match played {
                Ok(run) => {
                    let s = run.summary();
                    let angle_to_line_deg = match attractor {
                        Some(Attractor::Line { direction, .. }) => {
                            let line = direction[1].atan2(direction[0]).to_degrees();
                            let d = (s.end_theta_deg - line).rem_euclid(180.0);
                            Some(d.min(180.0 - d))
                        }
                        _ => None,
                    };
                    RectangleResult {
                        distance_to_attractor_m: attractor.map(|a| a.distance(s.end)),
                        angle_to_line_deg,
                        start_pose,
                        note: None,
                        trajectory: run.trajectory,
                        summary: Some(s),
                    }
                }
                Err(e) => RectangleResult {
                    summary: None,
                    start_pose,
                    distance_to_attractor_m: None,
                    angle_to_line_deg: None,
                    note: Some(e.to_string()),
                    trajectory: Vec::new(),
                },
            }
        })
        .collect()
}

/// The work of a verification ([`crate::work`]): RK4 point-part steps of
/// the realised grid (with the settled warm-up at its longest), the
/// prediction, the swarm and the rectangles (each support point of a
/// `sampled_rectangle` step costs [`PLANAR_POINT_STEP_COST`] point-part
/// steps).
pub fn work_estimate(
    schedule: &Schedule,
    req: &VerifyRequest,
    swarm_periods: u32,
    rect_periods: u32,
) -> Estimate {
    let cycles = f64::from(schedule.total_cycles);
    let steps = schedule.settings.numerics.steps_per_cycle as f64;
    let term = |label: &str, parts: f64, periods: u32| {
        Term::new(label)
            .times(parts, "parts")
            .times(f64::from(periods), "periods")
            .times(cycles, "cycles")
            .times(steps, "steps")
    };
    let points = (req.points * req.points) as f64;
    let swarm = (req.swarm * req.swarm) as f64;
    // The prediction at each realised-grid point: the flow of the
    // time-weighted steady-state field over the measured periods, RK4 with
    // step doubling (crate::play::measure::flow_mean_velocity), each field
    // evaluation one steady state per moving segment. Counted at its most
    // doublings with a typical steady state (crate::work::VELOCITY_CYCLES):
    // smooth fields (the sink's) stop doubling earlier and take several
    // times less than estimated; a swirling field (the whirlpool's) needs every
    // doubling and its Circle steady states more cycles, so it takes
    // longer than estimated.
    let moving_segments = schedule
        .segments
        .iter()
        .filter(|s| s.primitive.is_some())
        .count() as f64;
    let r = sampled_rectangle(req.rectangle);
    let moving_parts = req.model.unwrap_or(schedule.settings.model).moving;
    let evaluations = if moving_parts {
        let first = 2 * req.periods.max(1) as usize;
        let most = first.max(2) / 2 * crate::play::measure::FLOW_MAX_STEPS_PER_PERIOD;
        let (mut n, mut sum) = (first, first);
        while n < most {
            n *= 2;
            sum += n;
        }
        (4 * sum + 1) as f64
    } else {
        1.0
    };
    Estimate::new(
        "schedule",
        "verifying it",
        "a shorter schedule (fewer cycles), --points, --swarm, --repetitions/--duration or --rect-poses",
    )
    .plus(term("realised grid", points, req.warmup + req.periods))
    .plus(
        // The start-up transient's frozen play (crate::play::settle), at
        // its longest: the cap, two periods more, and as long again in the
        // lengthened warm-up.
        Term::new("settled warm-up (at most)")
            .times(points, "parts")
            .times(
                2.0 * (f64::from(crate::play::settle::SETTLE_MAX_CYCLES) + 2.0 * cycles),
                "cycles",
            )
            .times(steps, "steps"),
    )
    .plus(
        Term::new("prediction (most doublings)")
            .times(points, "parts")
            .times(evaluations, "flow evaluations")
            .times(moving_segments, "segments")
            .times(crate::work::VELOCITY_CYCLES, "cycles")
            .times(steps, "steps"),
    )
    .plus(term(SWARM_TERM, swarm, swarm_periods))
    .plus(
        Term::new(RECTANGLES_TERM)
            .times(req.rectangle_poses as f64, "parts")
            .times(f64::from(rect_periods), "periods")
            .times(cycles, "cycles")
            .times(
                RectangleOptions::default().steps_per_cycle as f64,
                "planar steps",
            )
            .times(
                (r.nx * r.ny) as f64,
                "support points",
            )
            .times(PLANAR_POINT_STEP_COST, "point steps per support-point step"),
    )
}

/// Terms of [`work_estimate`] played per swarm part and per rectangle;
/// every other term is played per realised-grid point.
const SWARM_TERM: &str = "swarm";
const RECTANGLES_TERM: &str = "rectangles";

/// Progress weights in thousands of RK4 part steps of one realised-grid
/// point, one swarm part and one rectangle: each group's terms of `work`
/// over its part count (`counts`: grid points, swarm parts, rectangles),
/// so that `Σ weight × count` is the estimate and the time left is right
/// whichever group dominates (the rectangles too: without their term the
/// bar would stand at 100 % while they play).
pub fn progress_weights(work: &Estimate, counts: [usize; 3]) -> [u64; 3] {
    let mut steps = [0.0; 3];
    for t in &work.terms {
        let group = match t.label.as_str() {
            SWARM_TERM => 1,
            RECTANGLES_TERM => 2,
            _ => 0,
        };
        steps[group] += t.steps();
    }
    std::array::from_fn(|k| (steps[k] / counts[k].max(1) as f64 / 1e3).ceil().max(1.0) as u64)
}

/// `platefield verify`: loads the schedule at `path` and verifies it by
/// `run` (errors name the file).
///
/// ```no_run
/// use platefield::verify::{verify_schedule_file, VerifyRequest};
/// use platefield::work::Runtime;
/// let req = VerifyRequest { runtime: Runtime::QUIET, ..VerifyRequest::default() };
/// let report = verify_schedule_file(std::path::Path::new("results/synthesized/sink/schedule.json"), &req)?;
/// println!("judged {:?}, designed {}", report.judge, report.design_strength);
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn verify_schedule_file(path: &Path, req: &VerifyRequest) -> Result<VerifyReport> {
    req.validate()?;
    if let Some(f) = &req.friction {
        f.validate()?;
    }
    let schedule = Schedule::load(path)?;
    verify_labelled(&schedule, req, &path.display().to_string())
}

/// Verifies `schedule` in memory with the physics its basis was built with
/// (nothing is written here): the one door of the verification,
/// [`VerifyRequest`] in, [`VerifyReport`] out, the friction sweep and the
/// export's replay included (judged by the design's own check, admitted
/// before anything is played: `judged.rs`). Errors name the schedule by
/// its target.
///
/// Design, verify and export chained in memory (a small grid and few
/// steps per cycle, so that it runs in seconds):
#[cfg(test)]
pub(crate) fn run(schedule: &Schedule, req: &VerifyRequest) -> Result<VerifyReport> {
    req.validate()?;
    if let Some(f) = &req.friction {
        f.validate()?;
    }
    verify_labelled(schedule, req, schedule.target_folder()?)
}

/// [`run`], with errors naming the schedule as `label`.
fn verify_labelled(schedule: &Schedule, req: &VerifyRequest, label: &str) -> Result<VerifyReport> {
    let judged = JudgedChecks::admit(
        schedule,
        req.friction,
        req.replay.as_deref().map(|p| (p, req.replay_rate)),
        &req.runtime,
    )?;
    // A sort's classes: played as long as the design plays them, unless a
    // duration is asked for; admitted before anything is played.
    let sort_periods = match req.duration {
        _ if !super::sort_play::is_sort(schedule) => None,
        Duration::Auto => Some(super::sort_play::verify_periods(schedule, None)?),
        d => Some(swarm_periods(
            d,
            ScheduleMotion::from_schedule(schedule)?.period(),
            None,
            &[],
            0.0,
            req.tol,
        )),
    };
    if let Some(periods) = sort_periods {
        if let Some(e) = super::sort_play::verify_estimate(
            schedule,
            periods,
            judged.replay_file().map(|(f, _)| f.rate),
        )? {
            req.runtime.admit(&e)?;
        }
    }
    let settings = schedule.settings;
    let name = schedule.target_folder()?;
    if schedule.moving_time() <= 0.0 {
        return Err(Error::invalid(
            format!("{label}: segments"),
            "every segment is rest: the plate never moves, so there is no field to verify",
        ));
    }
    let sm = ScheduleMotion::from_schedule(schedule)?;
    let mut opts = PlayOptions {
        warmup_periods: req.warmup,
        periods: req.periods,
        ..PlayOptions::from_settings(&settings)
    };
    if let Some(m) = req.model {
        opts.model = m;
    }
    if let Some(f) = req.friction.and_then(|f| f.played()) {
        opts.friction = f;
    }
    let g = schedule.region();
    // The automatic rung is measured at the realised grid's points, under
    // the friction played.
    let rungs = req.rung_tolerance.map(|tol| {
        let physics = crate::field::FieldSettings {
            friction: opts.friction,
            ..settings
        };
        let grid = Grid {
            n: [req.points, req.points],
            ..g
        };
        schedule.rungs(&grid, &physics, tol)
    });
    if let Some(r) = &rungs {
        opts.model = r.model;
    }
    let attractor = schedule
        .target_spec
        .as_ref()
        .and_then(|t| Attractor::of(&t.field));
    let strength = schedule.fit_quantized.strength;
    let starts = region_points(&g, req.swarm);
    let periods = swarm_periods(
        req.duration,
        sm.period(),
        attractor.as_ref(),
        &starts,
        strength,
        req.tol,
    );
    let rect_periods = match req.duration {
        Duration::Auto => periods.max((RECT_MIN_AUTO_S / sm.period()).ceil() as u32),
        _ => periods,
    };
    let work = work_estimate(schedule, req, periods, rect_periods);
    req.runtime.admit(&work)?;
    let poses = rectangle_poses(&g, req.rectangle_poses);
    let counts = [req.points * req.points, starts.len(), poses.len()];
    let weights = progress_weights(&work, counts);
    let progress = Progress::new(
        "verify",
        "k RK4 steps",
        weights.iter().zip(counts).map(|(w, n)| w * n as u64).sum(),
        req.runtime.progress(),
    );
    let tick_by = |k: usize| {
        let (p, w) = (&progress, weights[k]);
        move || p.inc(w)
    };
    let tick = tick_by(0);
    progress.set_message("realised grid");
    let v = verify_points_ticked(&sm, &region_points(&g, req.points), &opts, &tick);
    if v.valid == 0 {
        let why = v
            .points
            .iter()
            .find_map(|p| p.note.clone())
            .unwrap_or_default();
        return Err(Error::ContactLost(format!(
            "{label}: no realised field: all {} parts left the plate or had no steady state (first: {why})",
            v.points.len()
        )));
    }
    if v.rms_predicted == 0.0 {
        // Nothing moves in the prediction (every segment too gentle for
        // the parts to slip): the relative and shape errors are 0/0.
        return Err(Error::Unreachable(format!(
            "{label}: no predicted field: the time-weighted steady-state field is zero at all {} valid points (the parts stick to the plate in every segment), so there is nothing to verify",
            v.valid
        )));
    }
    progress.set_message("swarm");
    let swarm = run_swarm_ticked(
        &sm,
        &starts,
        attractor,
        &SwarmOptions {
            verify: opts,
            periods,
            tol: req.tol,
            strength,
        },
        &tick_by(1),
    );

    let rect_opts = RectangleOptions {
        friction: opts.friction,
        gravity: opts.gravity,
        model: crate::dynamics::Model {
            moving: true,
            ..opts.model
        },
        ..RectangleOptions::default()
    };
    progress.set_message("rectangles");
    let rectangles = run_rectangles(
        &sm,
        req.rectangle,
        &poses,
        rect_periods,
        attractor.as_ref(),
        &rect_opts,
        &tick_by(2),
    );
    progress.finish();
    let (friction_sweep, replay) = judged.run(schedule)?;
    let sort = match sort_periods {
        Some(periods) => {
            super::sort_play::verify_sort(schedule, judged.replay_file(), periods, &req.runtime)?
        }
        None => None,
    };
    let tolerance = delivery_spread(schedule, req, &settings)?;
    Ok(VerifyReport {
        target: name.to_string(),
        region: g,
        request: req.clone(),
        design_strength: strength,
        judge: match &schedule.target_spec {
            Some(t) => {
                let physics = crate::field::FieldSettings {
                    friction: opts.friction,
                    model: opts.model,
                    ..settings
                };
                Some(crate::design::judge::judge_check(
                    t,
                    &t.sample()?,
                    schedule,
                    &physics,
                )?)
            }
            None => None,
        },
        recorded_rungs: match (&rungs, req.model) {
            (None, None) => schedule.rungs.clone(),
            _ => None,
        },
        rungs,
        model_check: v,
        swarm,
        rectangles,
        friction_sweep,
        replay,
        tolerance,
        sort,
    })
}

/// The judge over delivery errors asked for (`--tolerance`), at the
/// friction played (`--friction MU`), else where the design's worst case
/// over its range falls, else the schedule's own.
fn delivery_spread(
    schedule: &Schedule,
    req: &VerifyRequest,
    settings: &crate::field::FieldSettings,
) -> Result<Option<crate::design::tolerance::Spread>> {
    let Some(asked) = req.tolerance else {
        return Ok(None);
    };
    let target = schedule.target_spec.as_ref().ok_or_else(|| {
        Error::invalid(
            "--tolerance",
            "the schedule records no target to judge against",
        )
    })?;
    let tol = asked
        .or_else(|| target.shaker.as_ref().and_then(|s| s.tolerance))
        .ok_or_else(|| {
            Error::invalid(
                "--tolerance",
                "the schedule's target states no shaker.tolerance: give it as AMPLITUDE:PHASE_DEG (e.g. 0.05:5)",
            )
        })?;
    tol.validate("--tolerance")
        .map_err(|e| Error::invalid("--tolerance", e.to_string()))?;
    let sampled = target.sample()?;
    req.runtime
        .admit(&crate::design::tolerance::spread_estimate(
            target, &sampled, schedule, req.draws,
        ))?;
    let physics = crate::design::tolerance::judged_at(
        schedule,
        settings,
        req.friction.and_then(|f| f.played()),
    );
    crate::design::tolerance::spread(target, &sampled, schedule, &physics, (&tol, req.draws))
        .map(Some)
}

#[cfg(test)]
mod tests {
    /// A worked example of `verify::run::run`.
    #[test]
    fn example_run() -> Result<(), crate::Error> {
        use crate::design::{BasisSection, DesignOptions, Method};
        use crate::inverse::{self, DesignOutcome};
        use crate::request::Target;
        use crate::schedule::export;
        use crate::verify::{self, Duration, VerifyRequest};
        use crate::work::Runtime;

        let target = Target::from_json_str(
            r#"{"name": "sink", "field": {"kind": "sink"},
                "grid": {"x": [-0.03, 0.03], "y": [-0.03, 0.03], "n": [7, 7]}}"#,
        )?;
        let mut options = DesignOptions {
            method: Method::Sequence,
            basis: BasisSection {
                rotation_step_deg: 45.0,
                cache_dir: None,
                ..BasisSection::default()
            },
            runtime: Runtime::QUIET,
            ..DesignOptions::default()
        };
        options.settings.numerics.steps_per_cycle = 16;
        options.settings.phases = 4;
        let DesignOutcome::Method(outcome) = inverse::run(&target, &options)? else {
            unreachable!("a target without classes or closed loop is designed by its method")
        };
        let schedule = &outcome.kept().schedule;

        let request = VerifyRequest {
            points: 3,
            swarm: 2,
            duration: Duration::Repetitions(1),
            rectangle_poses: 0,
            runtime: Runtime::QUIET,
            ..VerifyRequest::default()
        };
        let report = verify::run(schedule, &request)?;
        assert_eq!(report.model_check.points.len(), 9);

        let csv = export::signals_csv(schedule, 2_000.0)?;
        assert!(csv.lines().count() > 100);
        Ok(())
    }
}
