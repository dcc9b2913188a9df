//! Writing a verification: `summary.json` and `trajectories.svg` under
//! `OUT/<target>/verify/`, and the terminal summary.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::plot::{LegendEntry, LegendSymbol, Marker, MarkerShape, Overlay, QuiverPlot};
use crate::plot::{LinePlot, Panels, Series};
use platefield::error::{Error, Result};
use platefield::field::Grid;
use platefield::play::measure::{ModelCheck, PointResult};
use platefield::play::sensitivity::{FrictionRow, Sensitivity};
use platefield::request::Attractor;
use platefield::schedule::Schedule;
use platefield::verify::run::{RectangleResult, VerifyReport};
use platefield::verify::Swarm;

/// `summary.json`: everything, per point, per part and per rectangle
/// (deterministic: no timings).
pub(crate) fn summary_json(r: &VerifyReport) -> Result<String> {
    let v = &r.model_check;
    #[derive(Serialize)]
    struct Summary<'a> {
        model_check_error: f64,
        model_check_shape_error: f64,
        #[serde(skip_serializing_if = "Option::is_none")]
        judge: Option<platefield::play::sensitivity::Judged>,
        design_strength: f64,
        converged_fraction: Option<f64>,
        median_time_to_converge_s: Option<f64>,
        median_predicted_time_to_converge_s: Option<f64>,
        time_ratio_measured_over_predicted: Option<f64>,
        rectangles: &'a [RectangleResult],
        target: &'a str,
        schedule_period_s: f64,
        model: &'a str,
        region: &'a Grid,
        model_check: ModelCheckSummary<'a>,
        swarm: &'a Swarm,
        #[serde(skip_serializing_if = "Option::is_none")]
        friction_played: Option<platefield::dynamics::Friction>,
        #[serde(skip_serializing_if = "Option::is_none")]
        friction_sweep: Option<&'a Sensitivity>,
        #[serde(skip_serializing_if = "Option::is_none")]
        replay: Option<&'a platefield::play::replay::ReplayCheck>,
        #[serde(skip_serializing_if = "Option::is_none")]
        tolerance: Option<&'a platefield::design::tolerance::Spread>,
        #[serde(skip_serializing_if = "Option::is_none")]
        sort: Option<&'a platefield::verify::sort_play::SortVerify>,
        #[serde(skip_serializing_if = "Option::is_none")]
        rungs: Option<&'a platefield::schedule::ScheduleRungs>,
        #[serde(skip_serializing_if = "Option::is_none")]
        recorded_rungs: Option<&'a platefield::schedule::RecordedRungs>,
    }
    #[derive(Serialize)]
    struct ModelCheckSummary<'a> {
        points: usize,
        valid_points: usize,
        warmup_periods: u32,
        warmup_periods_played_most: u32,
        unsettled_points: usize,
        periods: u32,
        max_abs_error_m_per_s: f64,
        rms_predicted_m_per_s: f64,
        per_point: &'a [PointResult],
    }
    let summary = Summary {
        model_check_error: v.relative_error,
        model_check_shape_error: v.shape_error,
        judge: r.judge,
        design_strength: r.design_strength,
        converged_fraction: r.swarm.converged_fraction,
        median_time_to_converge_s: r.swarm.median_time_to_converge_s,
        median_predicted_time_to_converge_s: r.swarm.median_predicted_time_s,
        time_ratio_measured_over_predicted: r.swarm.time_ratio,
        rectangles: &r.rectangles,
        target: &r.target,
        schedule_period_s: v.schedule_period_s,
        model: &v.model,
        region: &r.region,
        model_check: ModelCheckSummary {
            points: r.request.points * r.request.points,
            valid_points: v.valid,
            warmup_periods: r.request.warmup,
            warmup_periods_played_most: v.warmup_most,
            unsettled_points: v.unsettled,
            periods: r.request.periods,
            max_abs_error_m_per_s: v.max_abs_error,
            rms_predicted_m_per_s: v.rms_predicted,
            per_point: &v.points,
        },
        swarm: &r.swarm,
        friction_played: r.request.friction.and_then(|f| f.played()),
        friction_sweep: r.friction_sweep.as_ref(),
        replay: r.replay.as_ref(),
        tolerance: r.tolerance.as_ref(),
        sort: r.sort.as_ref(),
        rungs: r.rungs.as_ref(),
        recorded_rungs: r.recorded_rungs.as_ref(),
    };
    let mut text =
        serde_json::to_string_pretty(&summary).map_err(|e| Error::Internal(e.to_string()))?;
    text.push('\n');
    Ok(text)
}

/// The outline of a rectangle of `size` at centre `r`, angle `deg`.
fn outline(size: [f64; 2], r: [f64; 2], deg: f64) -> Vec<[f64; 2]> {
    let (s, c) = deg.to_radians().sin_cos();
    let (a, b) = (0.5 * size[0], 0.5 * size[1]);
    [(-a, -b), (a, -b), (a, b), (-a, b), (-a, -b)]
        .iter()
        .map(|&(x, y)| [r[0] + c * x - s * y, r[1] + s * x + c * y])
        .collect()
}

/// Colours of the trajectory figure.
const SWARM_COLOR: &str = "#2ca02c";
const RECT_COLOR: &str = "#9467bd";
const END_COLOR: &str = "#000000";
const LOST_COLOR: &str = "#d62728";

/// The trajectory figure: realised mean velocity arrows (scaled to 0.6 of
/// the grid spacing and clipped to the axes), swarm paths (thin, start
/// dots, end squares: black converged, red not), rectangle paths with their
/// start (dashed) and end outlines, the attractor (+ or dashed line), and
/// a legend naming each. The axes show the target region plus 8 %; what
/// leaves them is clipped.
pub(crate) fn trajectory_svg(
    name: &str,
    g: &Grid,
    v: &ModelCheck,
    swarm: &Swarm,
    rects: &[RectangleResult],
    size: [f64; 2],
) -> String {
    let pts: Vec<[f64; 2]> = v.points.iter().map(|p| p.start).collect();
    let vecs: Vec<[f64; 2]> = v.points.iter().map(|p| p.realised).collect();
    let pad = |r: [f64; 2]| {
        let m = 0.08 * (r[1] - r[0]).max(1e-3);
        [r[0] - m, r[1] + m]
    };
    let mut plot = QuiverPlot::new(
        format!("{name}: realised mean velocity and part trajectories"),
        pts,
        vecs,
    )
    .invalid(v.points.iter().map(|p| !p.valid).collect())
    .ranges(pad(g.x), pad(g.y))
    .size(640.0 + crate::plot::LEGEND_WIDTH, 680.0)
    .clip()
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
    let scale = 0.6 / crate::plot::AUTO_ARROW_FRACTION * plot.auto_scale();
    if scale.is_finite() && scale > 0.0 {
        plot = plot.scale(scale);
    }
    plot = plot.legend(LegendEntry::new(
        "realised mean velocity",
        crate::plot::ARROW_COLOR,
        LegendSymbol::Arrow,
    ));
    for p in &swarm.parts {
        plot = plot
            .overlay(Overlay {
                width: 0.8,
                ..Overlay::new(p.path.clone()).color(SWARM_COLOR)
            })
            .marker(Marker {
                size: 2.5,
                ..Marker::new(p.start).color(SWARM_COLOR)
            })
            .marker(Marker {
                size: 3.0,
                ..Marker::new(p.end)
                    .shape(MarkerShape::Square)
                    .color(if p.converged { END_COLOR } else { LOST_COLOR })
            });
    }
    if !swarm.parts.is_empty() {
        plot = plot
            .legend(LegendEntry::new(
                "point part path",
                SWARM_COLOR,
                LegendSymbol::Line,
            ))
            .legend(LegendEntry::new(
                "start",
                SWARM_COLOR,
                LegendSymbol::Marker(MarkerShape::Circle),
            ))
            .legend(LegendEntry::new(
                "end (converged)",
                END_COLOR,
                LegendSymbol::Marker(MarkerShape::Square),
            ));
        if swarm.parts.iter().any(|p| !p.converged) {
            plot = plot.legend(LegendEntry::new(
                "end (not converged)",
                LOST_COLOR,
                LegendSymbol::Marker(MarkerShape::Square),
            ));
        }
    }
    let mut any_rect = false;
    for r in rects {
        if let (Some(first), Some(last)) = (r.trajectory.first(), r.trajectory.last()) {
            any_rect = true;
            plot = plot
                .overlay(Overlay::new(r.trajectory.iter().map(|p| p.r).collect()).color(RECT_COLOR))
                .overlay(
                    Overlay::new(outline(size, first.r, first.theta_deg))
                        .color(RECT_COLOR)
                        .dashed(),
                )
                .overlay(Overlay::new(outline(size, last.r, last.theta_deg)).color(END_COLOR));
        }
    }
    if any_rect {
        let dims = format!(
            "{} × {} mm",
            platefield::input::num(1e3 * size[0]),
            platefield::input::num(1e3 * size[1])
        );
        plot = plot
            .legend(LegendEntry::new(
                format!("{dims} rectangle path"),
                RECT_COLOR,
                LegendSymbol::Line,
            ))
            .legend(LegendEntry::new(
                "rectangle start pose",
                RECT_COLOR,
                LegendSymbol::DashedOutline,
            ))
            .legend(LegendEntry::new(
                "rectangle end pose",
                END_COLOR,
                LegendSymbol::Outline,
            ));
    }
    match swarm.attractor {
        Some(Attractor::Point { center, .. }) => {
            plot = plot
                .marker(
                    Marker::new(center)
                        .shape(MarkerShape::Plus)
                        .color(LOST_COLOR),
                )
                .legend(LegendEntry::new(
                    "attractor",
                    LOST_COLOR,
                    LegendSymbol::Marker(MarkerShape::Plus),
                ));
        }
        Some(Attractor::Line {
            point, direction, ..
        }) => {
            let l = (g.x[1] - g.x[0]).hypot(g.y[1] - g.y[0]);
            plot = plot
                .overlay(
                    Overlay::new(vec![
                        [point[0] - l * direction[0], point[1] - l * direction[1]],
                        [point[0] + l * direction[0], point[1] + l * direction[1]],
                    ])
                    .color(LOST_COLOR)
                    .dashed(),
                )
                .legend(LegendEntry::new(
                    "attractor line",
                    LOST_COLOR,
                    LegendSymbol::Dashed,
                ));
        }
        None => {}
    }
    if v.points.iter().any(|p| !p.valid) {
        plot = plot.legend(LegendEntry::new(
            "no realised velocity",
            crate::plot::INVALID_COLOR,
            LegendSymbol::Cross,
        ));
    }
    plot.to_svg()
}

/// Writes `summary.json` and `trajectories.svg` into the folder `dir`
/// (`verify_dir`; both computed before either is written, the folder
/// written whole by `platefield::output::Staged`; `order.md` and other files
/// there are kept); returns the paths.
pub fn write(r: &VerifyReport, dir: &Path) -> Result<Vec<PathBuf>> {
    let text = summary_json(r)?;
    let svg = trajectory_svg(
        &r.target,
        &r.region,
        &r.model_check,
        &r.swarm,
        &r.rectangles,
        r.request.rectangle,
    );
    // A verify folder's products: a run without a sweep drops an earlier
    // run's friction files.
    let products = [
        "summary.json",
        "trajectories.svg",
        "friction.md",
        "friction.svg",
    ];
    let mut files = vec![(products[0], text), (products[1], svg)];
    if let Some(s) = &r.friction_sweep {
        files.push((products[2], friction_md(&r.target, s)));
        files.push((products[3], friction_svg(&r.target, s)));
    }
    let stage = platefield::output::Staged::new(dir)?;
    for (name, text) in &files {
        platefield::output::write_atomic(&stage.path().join(name), text.as_bytes())?;
    }
    stage.commit(&products)?;
    Ok(files.iter().map(|(n, _)| dir.join(n)).collect())
}

/// `friction.md`: the friction sweep's table.
pub(crate) fn friction_md(target: &str, s: &Sensitivity) -> String {
    format!(
        "# Friction sweep: {target}\n\nGenerated by `platefield verify SCHEDULE --friction LO:HI:N`.\n\n{}",
        s.table_md()
    )
}

/// `friction.svg`: realised strength and realised shape error against μ_k,
/// side by side, the design's friction marked.
pub(crate) fn friction_svg(target: &str, s: &Sensitivity) -> String {
    let series = |f: &dyn Fn(&FrictionRow) -> Option<f64>| -> Vec<[f64; 2]> {
        s.rows
            .iter()
            .filter_map(|r| f(r).map(|y| [r.friction.kinetic, y]))
            .collect()
    };
    let strength = series(&|r| r.realised_strength);
    let shape = series(&|r| r.realised_shape_error.map(|e| 100.0 * e));
    let nominal = s.nominal.kinetic;
    let marker = |points: &[[f64; 2]]| {
        let (lo, hi) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p[1]), b.max(p[1]))
            });
        Series::new("designed for", vec![[nominal, lo.min(0.0)], [nominal, hi]]).dashed()
    };
    let panel = |title: &str, y: &str, points: Vec<[f64; 2]>| {
        LinePlot::new(title)
            .labels("kinetic friction μ_k", y)
            .series(marker(&points))
            .series(Series::new("played", points).markers())
    };
    Panels::new(format!("{target}: the design played across friction"))
        .panel(panel("realised strength", "ŝ (× the target)", strength))
        .panel(panel("realised shape error", "%", shape))
        .to_svg()
}

/// The lines of a rung choice ([`platefield::schedule::RecordedRungs`]):
/// `lead` and the rung played, then each segment's choice.
pub(crate) fn rungs_text(lead: &str, r: &platefield::schedule::RecordedRungs) -> String {
    use platefield::output::significant_percent;
    let pc = |e: Option<f64>| significant_percent(e.unwrap_or(f64::NAN));
    let mut out = format!(
        "{lead} {} (the cheapest rung that moves the part within {} of full for every segment, on {}×{} points)\n",
        r.played,
        significant_percent(r.tolerance),
        r.grid.n[0],
        r.grid.n[1]
    );
    for s in &r.segments {
        let _ = writeln!(
            out,
            "  segment {} {}: cheapest {} ({}), played error {}",
            s.segment,
            s.label,
            s.rung,
            pc(s.error),
            pc(s.played_error)
        );
    }
    out
}

/// The terminal summary: the judge, the model check (realised against
/// predicted), invalid points, the swarm and the rectangles.
pub fn summary(r: &VerifyReport) -> String {
    let v = &r.model_check;
    let req = &r.request;
    let mut out = String::new();
    match &r.judge {
        Some(j) => {
            let _ = writeln!(
                out,
                "judge: realised strength {:.4} (designed {:.4}) at realised shape error {:.2} % — the realised field at {} points over the whole region ({} valid), each part held at its point",
                j.realised_strength,
                r.design_strength,
                100.0 * j.shape_error,
                j.points,
                j.valid
            );
        }
        None => {
            let _ = writeln!(
                out,
                "judge: not measured (the schedule records no target to judge against)"
            );
        }
    }
    if let Some(t) = &r.tolerance {
        let _ = writeln!(out, "{}", tolerance_line(t));
    }
    if let Some(rungs) = &r.rungs {
        out.push_str(&rungs_text("model auto: played at", &rungs.record()));
    }
    if let Some(rungs) = &r.recorded_rungs {
        out.push_str(&rungs_text(
            "model: as designed (design --model auto), played at",
            rungs,
        ));
    }
    let few = platefield::design::method::MIN_MEASURED_POINTS;
    if v.valid < few {
        let _ = writeln!(
            out,
            "model check not measured: {} of {} points kept contact and converged, and a strength and shape need at least {few} ({} model; the points below say why)",
            v.valid,
            req.points * req.points,
            v.model,
        );
    } else {
        let _ = writeln!(
        out,
        "model check (moving parts against the design's prediction): error {:.2} % (shape {:.2} %) over {} of {} points ({} model, {} warm-up + {} measured periods of {:.4} s); max |error| {:.3e} m/s, rms |predicted| {:.3e} m/s",
        100.0 * v.relative_error,
        100.0 * v.shape_error,
        v.valid,
        req.points * req.points,
        v.model,
        req.warmup,
        req.periods,
        v.schedule_period_s,
        v.max_abs_error,
        v.rms_predicted
    );
    }
    if v.warmup_most > req.warmup {
        let longer = v
            .points
            .iter()
            .filter(|p| p.warmup_periods > req.warmup)
            .count();
        let _ = writeln!(
            out,
            "warm-up lengthened to up to {} periods at {} of {} points: the start-up transient of a part placed at rest (platefield::play::settle){}",
            v.warmup_most,
            longer,
            v.points.len(),
            if v.unsettled > 0 {
                format!("; NOT settled at {} points within the longest warm-up allowed: their realised velocity still holds part of it", v.unsettled)
            } else {
                String::new()
            }
        );
    }
    for p in v.points.iter().filter(|p| !p.valid) {
        let _ = writeln!(
            out,
            "invalid ({:.4}, {:.4}): {}",
            p.start[0],
            p.start[1],
            p.note.as_deref().unwrap_or("")
        );
    }
    let s = &r.swarm;
    let opt = |x: Option<f64>, unit: &str| x.map_or("n/a".to_string(), |x| format!("{x:.3}{unit}"));
    let _ = match s.converged_fraction {
        Some(f) => writeln!(
            out,
            "swarm of {} parts for {:.2} s: {:.1} % within {:.1} mm of the attractor ({} left the plate); median time to converge {} against {} predicted from the design strength (ratio {})",
            s.parts.len(),
            s.duration_s,
            100.0 * f,
            1e3 * s.tol,
            s.contact_lost,
            opt(s.median_time_to_converge_s, " s"),
            opt(s.median_predicted_time_s, " s"),
            opt(s.time_ratio, ""),
        ),
        None => writeln!(
            out,
            "swarm of {} parts for {:.2} s: the target has no attractor ({} left the plate)",
            s.parts.len(),
            s.duration_s,
            s.contact_lost
        ),
    };
    for (k, rect) in r.rectangles.iter().enumerate() {
        let [x, y, deg] = rect.start_pose;
        let _ = match &rect.summary {
            Some(sum) => writeln!(
                out,
                "rectangle {k} ({:.1} × {:.1} mm) from ({:.1}, {:.1}) mm at {deg:.0}°: ends at ({:.2}, {:.2}) mm, long axis at {:.1}°{}{}",
                1e3 * sum.rectangle.length,
                1e3 * sum.rectangle.width,
                1e3 * x,
                1e3 * y,
                1e3 * sum.end[0],
                1e3 * sum.end[1],
                sum.end_axis_deg,
                rect.distance_to_attractor_m
                    .map_or(String::new(), |d| format!(", {:.2} mm from the attractor", 1e3 * d)),
                rect.angle_to_line_deg
                    .map_or(String::new(), |a| format!(", {a:.1}° to its line")),
            ),
            None => writeln!(
                out,
                "rectangle {k} from ({:.1}, {:.1}) mm at {deg:.0}°: {}",
                1e3 * x,
                1e3 * y,
                rect.note.as_deref().unwrap_or("")
            ),
        };
    }
    out
}

fn friction_text(f: platefield::dynamics::Friction) -> String {
    if f.stat == f.kinetic {
        format!("μ = {}", f.kinetic)
    } else {
        format!("μ_s = {}, μ_k = {}", f.stat, f.kinetic)
    }
}

/// The folder `verify` writes into: `OUT/<target>/verify/` for `--out
/// OUT`, else `verify/` beside the schedule file at `path` (so verifying a
/// design made into another folder does not write into `./results/`).
pub(crate) fn verify_dir(path: &Path, schedule: &Schedule, out: Option<&Path>) -> Result<PathBuf> {
    Ok(match out {
        Some(out) => out.join(schedule.target_folder()?).join("verify"),
        None => path.parent().unwrap_or(Path::new("")).join("verify"),
    })
}

/// `platefield verify`: verifies the schedule at `path`
/// ([`platefield::verify::verify_schedule_file`]), writes its files into
/// `verify_dir` and returns the summary JSON (`json`) or the terminal
/// summary with the files written.
pub fn run(
    path: &Path,
    req: &platefield::verify::VerifyRequest,
    out: Option<&Path>,
    json: bool,
) -> Result<String> {
    // The folder the results go to, checked before the work (reading the
    // schedule is cheap; its errors are the ones verify would give).
    let schedule = Schedule::load(path)?;
    let dir = verify_dir(path, &schedule, out)?;
    platefield::output::check_writable(&dir, "--out")?;
    let r = platefield::verify::verify_schedule_file(path, req)?;
    let files = write(&r, &dir)?;
    if json {
        return summary_json(&r);
    }
    let mut text = summary(&r);
    if let Some(f) = r.request.friction.and_then(|f| f.played()) {
        let _ = writeln!(
            text,
            "played at friction μ_s = μ_k = {} (the schedule's: {})",
            f.kinetic,
            friction_text(schedule.settings.friction)
        );
    }
    if let Some(s) = &r.friction_sweep {
        text.push_str(&s.table_md());
    }
    if let Some(c) = &r.replay {
        text.push_str(&c.text());
    }
    if let Some(v) = &r.sort {
        text.push_str(&crate::sort::verify_text(v));
    }
    for f in files {
        let _ = writeln!(text, "wrote {}", f.display());
    }
    Ok(text)
}

/// The summary's line on a design judged over delivery errors
/// (`verify --tolerance`, and `design` when the target states
/// `shaker.tolerance`).
pub(crate) fn tolerance_line(t: &platefield::design::tolerance::Spread) -> String {
    let [median, p90, worst] = t.shape();
    let [_, _, weakest] = t.strength();
    format!(
        "tolerance: the judge over {} delivery-error draws (each channel's harmonics within ±{} % and ±{}°) at μ_k {}: shape error median {:.2} %, 90th percentile {:.2} %, worst {:.2} %; weakest strength {:.4}{}",
        t.shape_errors.len(),
        100.0 * t.tolerance.amplitude,
        t.tolerance.phase_deg,
        platefield::output::coefficient(t.friction),
        100.0 * median,
        100.0 * p90,
        100.0 * worst,
        weakest,
        if t.primitive_segments > 0 {
            format!(
                " ({} primitive segments played as designed)",
                t.primitive_segments
            )
        } else {
            String::new()
        }
    )
}
