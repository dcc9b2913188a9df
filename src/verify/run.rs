//! `platefield verify SCHEDULE.json`: the whole closed-loop check of a
//! designed schedule, written under `OUT/<target>/verify/`.
//!
//! 1. The realised field against the prediction ([`super::realised`]) on an
//!    n × n grid of point parts over the target region.
//! 2. A swarm of point parts over the region for a duration
//!    ([`super::swarm`]): where they end up, the fraction converged to the
//!    target's attractor, and the time it takes against the time the
//!    design's strength predicts.
//! 3. Files: `summary.json` (everything, per point and per part),
//!    `trajectories.svg` (the realised field, the parts' paths, the
//!    attractor). Everything is computed before anything is written, and
//!    each file is written atomically.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::realised::{verify_points, Verification, VerifyOptions};
use super::swarm::{run_swarm, Swarm, SwarmOptions};
use super::ScheduleMotion;
use crate::design::Schedule;
use crate::dynamics::Model;
use crate::error::{Error, Result};
use crate::field::{FieldSettings, Grid};
use crate::plot::{Marker, MarkerShape, Overlay, QuiverPlot};
use crate::target::Attractor;

/// How long the swarm is played.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Duration {
    /// 1.5 × the longest predicted time to converge from a start point plus
    /// one schedule period, or 10 schedule periods without an attractor;
    /// at most [`MAX_AUTO_PERIODS`].
    Auto,
    /// At least this many seconds (rounded up to whole schedule periods).
    Seconds(f64),
    /// This many schedule periods.
    Repetitions(u32),
}

/// Longest automatic swarm duration (schedule periods).
pub const MAX_AUTO_PERIODS: u32 = 200;

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
    /// Swarm grid: parts per side.
    pub swarm: usize,
    /// Swarm duration.
    pub duration: Duration,
    /// Convergence tolerance (m).
    pub tol: f64,
}

impl Default for VerifyRequest {
    fn default() -> Self {
        VerifyRequest {
            points: 5,
            warmup: 1,
            periods: 1,
            model: None,
            swarm: 9,
            duration: Duration::Auto,
            tol: 0.003,
        }
    }
}

impl VerifyRequest {
    /// Checks ranges, naming the command-line argument.
    pub fn validate(&self) -> Result<()> {
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
        range("--points", self.points as u64, 1, 101)?;
        range("--periods", u64::from(self.periods), 1, 1000)?;
        range("--warmup", u64::from(self.warmup), 0, 1000)?;
        range("--swarm", self.swarm as u64, 1, 101)?;
        match self.duration {
            Duration::Seconds(s) if !(s.is_finite() && s > 0.0 && s <= 3600.0) => {
                return Err(Error::invalid(
                    "--duration",
                    format!("must be in (0, 3600] seconds, got {s}"),
                ))
            }
            Duration::Repetitions(n) => range("--repetitions", u64::from(n), 1, 10_000)?,
            _ => {}
        }
        if !(self.tol.is_finite() && self.tol > 0.0 && self.tol <= 0.1) {
            return Err(Error::invalid(
                "--tol",
                format!("must be in (0, 0.1] m, got {}", self.tol),
            ));
        }
        Ok(())
    }
}

/// What a verification produced.
#[derive(Debug, Clone)]
pub struct VerifyReport {
    /// Realised field against the prediction.
    pub verification: Verification,
    /// The swarm.
    pub swarm: Swarm,
    /// The summary JSON written.
    pub summary_json: String,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// Reads a `schedule.json` written by `platefield design`.
pub fn load_schedule(path: &Path) -> Result<Schedule> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: path.display().to_string(),
        source: e,
    })?;
    serde_json::from_str(&text).map_err(|e| {
        Error::invalid(
            path.display().to_string(),
            format!("not a platefield schedule: {e}"),
        )
    })
}

/// The physics a schedule's basis was built with (validated).
pub fn schedule_settings(schedule: &Schedule, path: &Path) -> Result<FieldSettings> {
    let settings: FieldSettings =
        serde_json::from_value(schedule.settings.clone()).map_err(|e| {
            Error::invalid(
                format!("{}: settings", path.display()),
                format!("not platefield field settings: {e}"),
            )
        })?;
    settings.friction.validate("settings.friction")?;
    settings.numerics.validate("settings.numerics")?;
    crate::error::positive("settings.gravity", settings.gravity)?;
    Ok(settings)
}

/// The schedule's target name, checked to be a plain folder name (results
/// go to `OUT/<target>/`).
pub fn target_folder(schedule: &Schedule) -> Result<&str> {
    let name = schedule.target.as_str();
    if name.trim().is_empty() || name.contains(['/', '\\']) || name.starts_with('.') {
        return Err(Error::invalid(
            "schedule.target",
            format!("must be a plain folder name, got \"{name}\""),
        ));
    }
    Ok(name)
}

/// The region verified: the target's grid, or ±3 cm when the schedule does
/// not record one.
pub fn region(schedule: &Schedule) -> Grid {
    match schedule.target_spec.as_ref().and_then(|t| t.grid.as_ref()) {
        Some(g) => Grid {
            x: g.x,
            y: g.y,
            n: g.n,
        },
        None => Grid {
            x: [-0.03, 0.03],
            y: [-0.03, 0.03],
            n: [5, 5],
        },
    }
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

/// The trajectory figure: realised mean velocity arrows, part paths (start
/// dots, end squares), the attractor (+) when there is one.
pub fn trajectory_svg(name: &str, g: &Grid, v: &Verification, swarm: &Swarm) -> String {
    let pts: Vec<[f64; 2]> = v.points.iter().map(|p| p.start).collect();
    let vecs: Vec<[f64; 2]> = v.points.iter().map(|p| p.realised).collect();
    let mut plot = QuiverPlot::new(
        format!("{name}: realised mean velocity and part trajectories"),
        pts,
        vecs,
    )
    .invalid(v.points.iter().map(|p| !p.valid).collect())
    .ranges(g.x, g.y)
    .size(640.0, 680.0)
    .caption(format!(
        "{} parts, {:.1} s; converged: {}; realised vs predicted field {:.1} %",
        swarm.parts.len(),
        swarm.duration_s,
        swarm
            .converged_fraction
            .map_or("n/a (no attractor)".to_string(), |f| format!(
                "{:.1} % within {:.1} mm",
                100.0 * f,
                1e3 * swarm.tol
            )),
        100.0 * v.relative_error
    ));
    for p in &swarm.parts {
        plot = plot
            .overlay(Overlay::new(p.path.clone()).color("#2ca02c"))
            .marker(Marker::new(p.start).color("#2ca02c"))
            .marker(
                Marker::new(p.end)
                    .shape(MarkerShape::Square)
                    .color(if p.converged { "#000000" } else { "#d62728" }),
            );
    }
    match swarm.attractor {
        Some(Attractor::Point { center, .. }) => {
            plot = plot.marker(
                Marker::new(center)
                    .shape(MarkerShape::Plus)
                    .color("#d62728")
                    .label("attractor"),
            );
        }
        Some(Attractor::Line {
            point, direction, ..
        }) => {
            let l = (g.x[1] - g.x[0]).hypot(g.y[1] - g.y[0]);
            plot = plot.overlay(
                Overlay::new(vec![
                    [point[0] - l * direction[0], point[1] - l * direction[1]],
                    [point[0] + l * direction[0], point[1] + l * direction[1]],
                ])
                .color("#d62728")
                .dashed(),
            );
        }
        None => {}
    }
    plot.to_svg()
}

/// `platefield verify`: runs `req` on the schedule at `path` with the
/// physics its basis was built with and writes `OUT/<target>/verify/`.
pub fn verify_schedule_file(path: &Path, req: &VerifyRequest, out: &Path) -> Result<VerifyReport> {
    req.validate()?;
    let schedule = load_schedule(path)?;
    let settings = schedule_settings(&schedule, path)?;
    let name = target_folder(&schedule)?;
    if let Some(t) = &schedule.target_spec {
        t.validate()?;
    }
    let sm = ScheduleMotion::from_schedule(&schedule)?;
    let mut opts = VerifyOptions {
        warmup_periods: req.warmup,
        periods: req.periods,
        ..VerifyOptions::from_settings(&settings)
    };
    if let Some(m) = req.model {
        opts.model = m;
    }
    let g = region(&schedule);
    let v = verify_points(&sm, &region_points(&g, req.points), &opts);

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
    let swarm = run_swarm(
        &sm,
        &starts,
        attractor,
        &SwarmOptions {
            verify: opts,
            periods,
            tol: req.tol,
            strength,
        },
    );

    #[derive(Serialize)]
    struct Summary<'a> {
        realised_vs_predicted_relative_error: f64,
        converged_fraction: Option<f64>,
        median_time_to_converge_s: Option<f64>,
        median_predicted_time_to_converge_s: Option<f64>,
        time_ratio_measured_over_predicted: Option<f64>,
        rectangles: Vec<serde_json::Value>,
        target: &'a str,
        schedule_period_s: f64,
        model: &'a str,
        region: &'a Grid,
        realised_field: RealisedSummary<'a>,
        swarm: &'a Swarm,
    }
    #[derive(Serialize)]
    struct RealisedSummary<'a> {
        points: usize,
        valid_points: usize,
        warmup_periods: u32,
        periods: u32,
        max_abs_error_m_per_s: f64,
        rms_predicted_m_per_s: f64,
        per_point: &'a [super::PointResult],
    }
    let summary = Summary {
        realised_vs_predicted_relative_error: v.relative_error,
        converged_fraction: swarm.converged_fraction,
        median_time_to_converge_s: swarm.median_time_to_converge_s,
        median_predicted_time_to_converge_s: swarm.median_predicted_time_s,
        time_ratio_measured_over_predicted: swarm.time_ratio,
        rectangles: Vec::new(),
        target: name,
        schedule_period_s: v.schedule_period_s,
        model: &v.model,
        region: &g,
        realised_field: RealisedSummary {
            points: req.points * req.points,
            valid_points: v.valid,
            warmup_periods: req.warmup,
            periods: req.periods,
            max_abs_error_m_per_s: v.max_abs_error,
            rms_predicted_m_per_s: v.rms_predicted,
            per_point: &v.points,
        },
        swarm: &swarm,
    };
    let mut text =
        serde_json::to_string_pretty(&summary).map_err(|e| Error::Physical(e.to_string()))?;
    text.push('\n');
    let svg = trajectory_svg(name, &g, &v, &swarm);
    let dir = out.join(name).join("verify");
    let files = vec![dir.join("summary.json"), dir.join("trajectories.svg")];
    crate::output::write_atomic(&files[0], text.as_bytes())?;
    crate::output::write_atomic(&files[1], svg.as_bytes())?;
    Ok(VerifyReport {
        verification: v,
        swarm,
        summary_json: text,
        files,
    })
}
