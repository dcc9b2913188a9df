//! Writing a design: `schedule.json`, `fit.svg` (target, achieved,
//! residual) and `report.md` under `results/<target name>/`.

use std::fmt::Write as _;
use std::path::Path;

use crate::plot::{LegendEntry, LegendSymbol, Panels, QuiverPlot, INVALID_COLOR};
use platefield::design::Design;
use platefield::error::Result;
use platefield::output::write_atomic;

/// The schedule as pretty JSON (deterministic bytes).
pub(crate) fn schedule_json(d: &Design) -> String {
    d.schedule.to_json().unwrap_or_default()
}

/// A short readable summary for the terminal.
pub fn summary(d: &Design) -> String {
    let s = &d.schedule;
    let mut out = format!(
        "target \"{}\": {} basis fields ({} left out: {}), mode {}, solver {} in {} iterations\n",
        s.target,
        d.basis.columns.len(),
        d.basis.excluded.len(),
        left_out_counts(&d.basis.excluded),
        s.solver.mode,
        s.solver.status,
        s.solver.iterations
    );
    let _ = writeln!(
        out,
        "fit: relative L2 error {:.2} %, mean angle error {:.2}°, max error {:.3e}, strength {:.4}",
        100.0 * s.fit.relative_l2_error,
        s.fit.mean_angle_error_deg,
        s.fit.max_error,
        s.fit.strength
    );
    let _ = writeln!(
        out,
        "schedule: {} cycles ({:.3} s), min {} per segment, quantised error {:.2} % (field quantisation {:.2} %)",
        s.total_cycles,
        s.period_s,
        s.min_cycles,
        100.0 * s.fit_quantized.relative_l2_error,
        100.0 * s.quantization_error
    );
    for seg in &s.segments {
        let _ = writeln!(
            out,
            "  {:>5} cycles  {:<28} weight {:.4}",
            seg.cycles, seg.label, seg.weight
        );
    }
    if s.poor_fit {
        let _ = writeln!(
            out,
            "POOR FIT: no combination of the allowed primitives reaches this target (relative error {:.0} %); the schedule is the best achievable",
            100.0 * s.fit.relative_l2_error
        );
    }
    if let Some(search) = &d.order_search {
        let b = search.chosen();
        let _ = writeln!(
            out,
            "order search: {} candidates, best {} with {} rest cycles per join (realised vs predicted {:.2} %, moving fraction {:.3}) in {:.1} s",
            search.candidates.len(),
            b.sequence,
            b.rest_cycles,
            100.0 * b.relative_error,
            b.moving_fraction,
            d.order_time_s
        );
    }
    let _ = writeln!(
        out,
        "time: basis {:.3} s ({}), fit and schedule {:.3} s (conic solver {:.4} s)",
        d.basis_time_s, d.cache_status, d.fit_time_s, d.solution.solve_time_s
    );
    out
}

/// The report in Markdown.
pub(crate) fn report_md(d: &Design) -> String {
    let s = &d.schedule;
    let mut md = format!("# Design for target \"{}\"\n\n", s.target);
    let _ = write!(
        md,
        "Regenerate: `{}`.\n\n## Fit\n\n| metric | value |\n|---|---|\n",
        super::invocation("design <target file>")
    );
    let _ = writeln!(md, "| mode | {} |", s.solver.mode);
    let _ = writeln!(md, "| relative L2 error | {:.4} |", s.fit.relative_l2_error);
    let _ = writeln!(
        md,
        "| mean angle error (deg, magnitude-weighted) | {:.3} |",
        s.fit.mean_angle_error_deg
    );
    let _ = writeln!(md, "| worst-point error | {:.4e} |", s.fit.max_error);
    let _ = writeln!(md, "| achieved strength | {:.5} |", s.fit.strength);
    let _ = writeln!(
        md,
        "| solver status, iterations | {}, {} |",
        s.solver.status, s.solver.iterations
    );
    let _ = writeln!(
        md,
        "| KKT residual, gap to independent NNLS | {:.2e}, {:.2e} |",
        s.solver.kkt_residual, s.solver.independent_gap
    );
    let _ = writeln!(
        md,
        "| basis | {} fields, {} left out |",
        d.basis.columns.len(),
        d.basis.excluded.len()
    );
    if s.poor_fit {
        md.push_str("\n**Poor fit**: no combination of the allowed primitives reaches this target; this is the best achievable.\n");
    }
    md.push_str(
        "\n## Schedule\n\n| segment | weight | cycles | duration (s) |\n|---|---|---|---|\n",
    );
    for seg in &s.segments {
        let _ = writeln!(
            md,
            "| {} | {:.4} | {} | {:.4} |",
            seg.label, seg.weight, seg.cycles, seg.duration_s
        );
    }
    let _ = writeln!(
        md,
        "\n{} cycles in all ({:.3} s), at least {} per segment. Whole-cycle schedule: relative error {:.4} (field quantisation error {:.4}).",
        s.total_cycles, s.period_s, s.min_cycles, s.fit_quantized.relative_l2_error, s.quantization_error
    );
    md.push_str("\n## Fewer primitives\n\nBest fit found with at most k of the segments the full fit uses.\n\n| k | relative error | segments |\n|---|---|---|\n");
    for row in &d.sparsity {
        let _ = writeln!(
            md,
            "| {} | {:.4} | {} |",
            row.k,
            row.relative_error,
            row.labels.join(", ")
        );
    }
    md.push_str(&excluded_md(&d.basis.excluded));
    md
}

/// How many basis fields were left out for each kind of reason, in one
/// phrase ("150 invalid in the region, 18 over the shaker limits"); "none"
/// when none was.
fn left_out_counts(excluded: &[platefield::schedule::ExcludedColumn]) -> String {
    use platefield::schedule::ExclusionReason as R;
    let count = |f: fn(&R) -> bool| excluded.iter().filter(|e| f(&e.reason)).count();
    let kinds = [
        (
            count(|r| matches!(r, R::Invalid(_))),
            "invalid in the region",
        ),
        (
            count(|r| matches!(r, R::IsotropicCopy { .. })),
            "rotated copies of isotropic fields",
        ),
        (
            count(|r| matches!(r, R::OverLimit { .. })),
            "over the shaker limits",
        ),
    ];
    let parts: Vec<String> = kinds
        .iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect();
    if parts.is_empty() {
        "none".into()
    } else {
        parts.join(", ")
    }
}

/// The basis fields left out, as counts by reason (each field, its invalid
/// samples and the reason in full are in `schedule.json`'s
/// `basis.excluded`); empty when none was.
pub(crate) fn excluded_md(excluded: &[platefield::schedule::ExcludedColumn]) -> String {
    use platefield::schedule::ExclusionReason as R;
    if excluded.is_empty() {
        return String::new();
    }
    // (reason, count, first field) in order of first appearance.
    let mut rows: Vec<(String, usize, &str)> = Vec::new();
    for e in excluded {
        let reason = match &e.reason {
            R::Invalid(v) => format!("invalid in the region: {v}"),
            R::IsotropicCopy { .. } => "rotated copy of an isotropic field".to_string(),
            R::OverLimit { axis, .. } => format!("over the shaker limit on {axis}"),
        };
        match rows.iter_mut().find(|r| r.0 == reason) {
            Some(r) => r.1 += 1,
            None => rows.push((reason, 1, &e.label)),
        }
    }
    let mut md = format!(
        "\n## Basis fields left out\n\n{} fields, by reason (every field with its invalid samples: `basis.excluded` in the sequenced design's schedule.json).\n\n| reason | fields | first |\n|---|---|---|\n",
        excluded.len()
    );
    for (reason, n, first) in rows {
        let _ = writeln!(md, "| {reason} | {n} | {first} |");
    }
    md
}

/// The realised strength `schedule` was played at (the headline's), if
/// it records its play.
pub(crate) fn realised_strength(schedule: &platefield::schedule::Schedule) -> Option<f64> {
    schedule.played.as_ref().and_then(|p| p.realised_strength)
}

/// The fit figure: target (scaled by the strength), achieved, residual;
/// `realised`: the strength the kept design was played at, for the title.
pub(crate) fn fit_svg(d: &Design, realised: Option<f64>) -> String {
    fit_figure(
        &d.schedule.target,
        &d.target,
        d.schedule.fit.strength,
        realised.or_else(|| realised_strength(&d.schedule)),
        "achieved (schedule)",
        &d.achieved_quantized,
    )
}

/// Three panels at the points of `target`: the target scaled by
/// `strength` (the prediction's), `achieved` (titled `label`) and their
/// difference; masked points marked by a red × with its legend. The title
/// states the predicted strength and, when the design was played, the
/// `realised` one its headline reports.
pub(crate) fn fit_figure(
    name: &str,
    target: &platefield::request::SampledTarget,
    strength: f64,
    realised: Option<f64>,
    label: &str,
    achieved: &[[f64; 2]],
) -> String {
    let s = strength;
    let pts = target.points.clone();
    let scaled: Vec<[f64; 2]> = target
        .vectors
        .iter()
        .map(|v| [s * v[0], s * v[1]])
        .collect();
    let resid: Vec<[f64; 2]> = achieved
        .iter()
        .zip(&scaled)
        .map(|(a, t)| [a[0] - t[0], a[1] - t[1]])
        .collect();
    let masked: Vec<bool> = target.weights.iter().map(|w| *w == 0.0).collect();
    let short = label.split(' ').next().unwrap_or(label);
    let strengths = match realised {
        Some(r) => format!("predicted strength {s:.3}; realised {r:.4}"),
        None => format!("predicted strength {s:.3}"),
    };
    let mut target_panel = QuiverPlot::new("target (scaled)", pts.clone(), scaled)
        .invalid(masked.clone())
        .auto_caption();
    if masked.iter().any(|m| *m) {
        target_panel = target_panel.legend(LegendEntry::new(
            "masked (weight 0)",
            INVALID_COLOR,
            LegendSymbol::Cross,
        ));
    }
    Panels::new(format!(
        "{name}: target × {s:.3} ({strengths}), {short}, residual"
    ))
    .panel(target_panel)
    .panel(QuiverPlot::new(label, pts.clone(), achieved.to_vec()).auto_caption())
    .panel(
        QuiverPlot::new("residual", pts, resid)
            .invalid(masked)
            .auto_caption(),
    )
    .to_svg()
}

/// The order search as markdown (`None` when it was not run).
pub(crate) fn order_md(d: &Design) -> Option<String> {
    d.order_search.as_ref().map(|search| {
        format!(
            "# Segment order and rest: {}

Generated by `platefield design --order-search` ({} points over the target region); the schedule in schedule.json is played in the chosen order.

{}",
            d.schedule.target,
            search.points,
            super::order::order_table(search)
        )
    })
}

/// Writes schedule.json, fit.svg and report.md under `dir`, and order.md
/// when the order search ran.
pub fn write(d: &Design, dir: &Path) -> Result<()> {
    write_atomic(&dir.join("schedule.json"), schedule_json(d).as_bytes())?;
    write_atomic(&dir.join("fit.svg"), fit_svg(d, None).as_bytes())?;
    write_atomic(&dir.join("report.md"), report_md(d).as_bytes())?;
    if let Some(md) = order_md(d) {
        write_atomic(&dir.join("order.md"), md.as_bytes())?;
    }
    Ok(())
}
