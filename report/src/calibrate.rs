//! `platefield calibrate`: the calibration's JSON, `report.md` and its two
//! plots (observed against fitted paths; the likelihood over μ).

use std::fmt::Write as _;
use std::path::Path;

use platefield::calibrate::{
    calibrate, CalibrateOptions, Calibration, CalibrationRun, ParamEstimate, Tracks,
};
use platefield::error::{Error, Result};
use platefield::schedule::Schedule;

use crate::plot::{LegendPosition, LinePlot, Series, PALETTE};

/// Calibrates the parts of the tracks file `tracks` observed under the
/// schedule `schedule`, writes `OUT/calibration.json`, `report.md`,
/// `trajectories.svg` and `likelihood.svg` (all or none), and returns the
/// calibration's JSON (what the command prints).
///
/// # Errors
/// Bad input (naming the file, line and column), a failed fit, a file
/// that cannot be written.
pub fn run(
    schedule: &Path,
    tracks: &Path,
    options: &CalibrateOptions,
    out: &Path,
) -> Result<String> {
    let sched = Schedule::load(schedule)?;
    let observed = Tracks::load(tracks)?;
    let run = calibrate(&sched, &observed, options)?;
    let json = serde_json::to_string_pretty(&run.calibration)
        .map_err(|e| Error::invalid("calibration", format!("cannot be written as JSON: {e}")))?
        + "\n";
    let md = report(
        &run.calibration,
        &crate::invocation("calibrate SCHEDULE TRACKS"),
    );
    let paths = trajectories(&run).to_svg();
    let like = likelihood(&run.calibration).to_svg();
    std::fs::create_dir_all(out).map_err(|source| Error::Io {
        path: out.display().to_string(),
        source,
    })?;
    let files = [
        (out.join("calibration.json"), json.as_bytes()),
        (out.join("report.md"), md.as_bytes()),
        (out.join("trajectories.svg"), paths.as_bytes()),
        (out.join("likelihood.svg"), like.as_bytes()),
    ];
    let refs: Vec<(&Path, &[u8])> = files.iter().map(|(p, b)| (p.as_path(), *b)).collect();
    platefield::output::write_all_atomic(&refs)?;
    Ok(json)
}

/// One estimate as text: value ± 95 % half-width, or why not.
fn estimate(p: &ParamEstimate) -> String {
    match (p.value, p.interval) {
        (Some(v), Some([lo, hi])) => format!("{v:.4} (95 %: {lo:.4} – {hi:.4})"),
        (Some(v), None) => format!("{v} ({})", p.note.as_deref().unwrap_or("fixed")),
        _ => p.note.clone().unwrap_or_else(|| "not estimated".into()),
    }
}

/// `report.md`.
fn report(c: &Calibration, command: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Calibration: {} from {}\n", c.target, c.tracks);
    let _ = writeln!(s, "Regenerate: `{command}`\n");
    let _ = writeln!(
        s,
        "{} parts, {} frames. Model: {} ({}). Position noise estimated from the tracks alone: {}.\n",
        c.parts,
        c.frames,
        c.model,
        c.model_reason,
        c.noise_m
            .map_or("none (no three evenly spaced frames)".into(), |n| format!(
                "{:.3} mm",
                n * 1e3
            ))
    );
    for (k, class) in c.classes.iter().enumerate() {
        let _ = writeln!(s, "## Class {k}: {} part(s)\n", class.parts.len());
        let _ = writeln!(s, "| parameter | estimate |\n|---|---|");
        let _ = writeln!(s, "| μ_k | {} |", estimate(&class.mu_k));
        let _ = writeln!(s, "| μ_s | {} |", estimate(&class.mu_s));
        let _ = writeln!(s, "| amplitude scale | {} |", estimate(&class.scale));
        let _ = writeln!(
            s,
            "\nResidual {:.3} mm RMS per coordinate over {} coordinates{}.",
            class.residual_rms_m * 1e3,
            class.coordinates,
            class
                .residual_over_noise
                .map_or(String::new(), |r| format!(", {r:.2} × the tracks' noise"))
        );
        if !class.model_bias.is_empty() {
            let removed: Vec<String> = class
                .model_bias
                .iter()
                .zip(&class.model_slope)
                .map(|((name, b), (_, slope))| format!("{name} {b:+.4} (slope {slope:.3})"))
                .collect();
            let _ = writeln!(
                s,
                "\nThe field model's bias removed (the parts replayed by the exact simulator): {}.",
                removed.join(", ")
            );
        }
        if !class.not_separable.is_empty() {
            let _ = writeln!(
                s,
                "\nNot determined by these tracks: {}.",
                class.not_separable.join("; ")
            );
        }
        let _ = writeln!(s, "\nParts: {}.\n", class.parts.join(", "));
        if !class.joined.is_empty() {
            let _ = writeln!(
                s,
                "Joined (their own fits do not determine μ; left out of the class's fit): {}.\n",
                class.joined.join(", ")
            );
        }
    }
    let _ = writeln!(s, "## Each part alone (μ_s = μ_k, scale 1)\n\n| part | frames | μ | standard error | class |\n|---|---|---|---|---|");
    for p in &c.per_part {
        let _ = writeln!(
            s,
            "| {} | {} | {:.3} | {} | {} |",
            p.part,
            p.frames,
            p.mu,
            p.standard_error
                .map_or("— (lattice end)".into(), |e| format!("{e:.3}")),
            p.class
        );
    }
    let _ = writeln!(
        s,
        "\n`trajectories.svg`: observed positions (dots) against the fitted paths (lines). `likelihood.svg`: Δχ² over μ (μ_s = μ_k, scale 1) on the field model's lattice, per class fitted on the field, and the profile about each class's estimate (on the field: mapped through the bias correction; by replays: the Gauss–Newton quadratic); Δχ² < 3.84 is the noise model's 95 % interval, before the tracks' own scatter widens it.\n\n{} velocity fields computed, {} parts replayed; the classes fitted at {} RK4 steps per cycle.",
        c.fields_computed, c.replays, c.steps_per_cycle
    );
    s
}

/// Observed (markers) against fitted (lines) paths, in mm.
fn trajectories(run: &CalibrationRun) -> LinePlot {
    let mut plot = LinePlot::new("observed (dots) and fitted (lines) paths")
        .labels("x (mm)", "y (mm)")
        .legend(LegendPosition::Hidden);
    let mm = |v: &[[f64; 2]]| {
        v.iter()
            .map(|p| [p[0] * 1e3, p[1] * 1e3])
            .collect::<Vec<_>>()
    };
    for (i, (_, obs, fit)) in run.paths.iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        plot = plot
            .series(Series::new("", mm(obs)).color(color).markers_only())
            .series(Series::new("", mm(fit)).color(color));
    }
    plot
}

/// Δχ² over μ: the lattice per class and the fine profiles.
fn likelihood(c: &Calibration) -> LinePlot {
    let mut plot = LinePlot::new("likelihood over μ: Δχ² = ΔRSS / σ̂²").labels("μ", "Δχ²");
    for (k, curve) in c.likelihood.iter().enumerate() {
        plot = plot.series(Series::new(format!("class {k}, lattice"), curve.clone()).markers());
    }
    for (k, curve) in c.profile.iter().enumerate() {
        plot = plot
            .series(Series::new(format!("class {k}, about the estimate"), curve.clone()).dashed());
    }
    plot.log_y = false;
    plot.y_range = Some([
        0.0,
        c.likelihood
            .iter()
            .flatten()
            .map(|p| p[1])
            .fold(10.0, f64::max)
            .min(1e4),
    ]);
    plot
}
