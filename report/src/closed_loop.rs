//! Writing a closed-loop design: the terminal summary, `closed_loop.md`,
//! `closed_loop.json`, the closed-loop `schedule.json` (the open-loop one
//! kept as `schedule_open_loop.json`) and a "Closed loop" section appended
//! to `report.md`.

use std::fmt::Write as _;
use std::path::Path;

use super::design as report;
use platefield::design::closed_loop::{ClosedLoop, LoopCandidate};
use platefield::design::Design;
use platefield::error::{Error, Result};
use platefield::output::write_atomic;
use platefield::request::Target;
use platefield::work::Stop;

fn pct(x: f64) -> String {
    format!("{:.1} %", 100.0 * x)
}

fn line(name: &str, c: &LoopCandidate) -> String {
    let e = &c.error;
    let d = &e.decomposition;
    format!(
        "{name}: realised error {} (promise s = {:.4}), realised shape error {} (realised strength ŝ = {:.4}); error parts: isotropic {}, rotational {}, anisotropic {}, offset {}, remainder {}",
        pct(e.error),
        e.strength,
        pct(e.shape_error),
        e.realised_strength,
        pct(d.isotropic),
        pct(d.rotational),
        pct(d.anisotropic),
        pct(d.offset),
        pct(d.remainder)
    )
}

/// The summary's first line: the closed-loop schedule as the judge
/// measured it (what `schedule.json`'s `"played"` holds).
pub fn headline(d: &Design, target: &Target, cl: &ClosedLoop) -> String {
    let s = cl.schedule(target, &d.target.weights);
    match &s.played {
        Some(p) => super::method::headline_of("closed loop", p, &s),
        None => String::new(),
    }
}

/// Why the re-fit stopped, in words.
fn stop_text(cl: &ClosedLoop) -> String {
    match cl.stop {
        Stop::Converged => "the re-fit returns a schedule already played (converged)".into(),
        Stop::NoGain => "two re-fits without improvement".into(),
        Stop::Iterations => "iteration cap".into(),
        Stop::NotRun => "no re-fit asked".into(),
        Stop::Failed => format!(
            "re-fit failed: {}",
            cl.refit_failure.as_deref().unwrap_or("unknown")
        ),
        Stop::Spent => "budget spent".into(),
    }
}

/// A short summary for the terminal.
pub fn summary(cl: &ClosedLoop) -> String {
    let mut out = format!(
        "closed loop: judged at {} held points; {} schedules played in {:.1} s; re-fit stopped: {}\n",
        cl.points,
        cl.played,
        cl.seconds,
        stop_text(cl)
    );
    let _ = writeln!(out, "  {}", line("before", cl.before()));
    let _ = writeln!(out, "  {}", line("after ", cl.after()));
    let _ = writeln!(
        out,
        "  after, against the open-loop promise s₀ = {:.4}: {}; best: #{} ({}, {})",
        cl.design_strength,
        pct(cl.after().error_vs_design),
        cl.best,
        cl.after().stage.name(),
        cl.after().promise
    );
    let _ = writeln!(out, "  schedule: {}", cl.after().order);
    out
}

/// A row of the before/after table: its name and how to show a candidate.
type Row = (&'static str, fn(&LoopCandidate) -> String);

/// `closed_loop.md`.
pub(crate) fn markdown(cl: &ClosedLoop) -> String {
    let mut md = intro(cl);
    md.push_str("## Before and after\n\n| | before | after |\n|---|---|---|\n");
    let (b, a) = (cl.before(), cl.after());
    let rows: [Row; 11] = [
        ("realised error", |c| pct(c.error.error)),
        ("promised strength s", |c| {
            format!("{:.4}", c.error.strength)
        }),
        ("realised strength ŝ", |c| {
            format!("{:.4}", c.error.realised_strength)
        }),
        ("realised shape error", |c| pct(c.error.shape_error)),
        ("error vs the open-loop promise s₀", |c| {
            pct(c.error_vs_design)
        }),
        ("isotropic part", |c| pct(c.error.decomposition.isotropic)),
        ("rotational part", |c| pct(c.error.decomposition.rotational)),
        ("anisotropic part", |c| {
            pct(c.error.decomposition.anisotropic)
        }),
        ("offset part", |c| pct(c.error.decomposition.offset)),
        ("remainder", |c| pct(c.error.decomposition.remainder)),
        ("points", |c| c.error.valid.to_string()),
    ];
    for (name, f) in rows {
        let _ = writeln!(md, "| {name} | {} | {} |", f(b), f(a));
    }
    let _ = writeln!(md, "\nBefore: `{}`.\n\nAfter: `{}`.\n", b.order, a.order);
    md.push_str(
        "## Every schedule played\n\n| # | stage | order (segment×cycles) | promise | s | realised error | ŝ | shape error | vs s₀ | note |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (i, c) in cl.candidates.iter().enumerate() {
        let _ = writeln!(
            md,
            "| {i}{} | {} | {} | {} | {:.4} | {} | {:.4} | {} | {} | {} |",
            if i == cl.best { " (best)" } else { "" },
            c.stage.name(),
            c.order,
            c.promise,
            c.error.strength,
            pct(c.error.error),
            c.error.realised_strength,
            pct(c.error.shape_error),
            pct(c.error_vs_design),
            c.rejected.map(|r| r.to_string()).unwrap_or_default()
        );
    }
    md
}

/// The title and the paragraph on how every schedule was played and
/// measured.
fn intro(cl: &ClosedLoop) -> String {
    let mut md = format!("# Closed-loop design for target \"{}\"\n\n", cl.target);
    let _ = write!(
        md,
        "Regenerate: `platefield design <target file> --closed-loop` (with the same options).\n\n\
         Every schedule below is judged as `design` judges (`platefield::design::judge`): \
         a point part held at each of {} points of a regular sub-grid over the whole target \
         region (masked points left out), with the physics the design's basis was built with, \
         its velocity played from rest through whole schedule periods until periodic; R is its \
         mean velocity over the last period.\n\n\
         * **realised error** ‖R − s t‖/‖s t‖: the realised field against the promise s·t (s the \
         strength the schedule's design claims, t the target; the target's weights and mask), so \
         a schedule that realises s·t exactly scores 0;\n\
         * **realised strength** ŝ = ⟨R, t⟩/⟨t, t⟩ and **realised shape error** \
         ‖R − ŝ t‖/‖ŝ t‖, which no choice of strength can lower;\n\
         * **vs s₀**: the realised error against the open-loop promise s₀ = {:.4};\n\
         * error parts (of R − s t, relative to ‖s t‖): affine least-squares decomposition into \
         isotropic (for a sink target: strength), rotational (swirl), anisotropic (shear), \
         offset, and the remainder.\n\n\
         Stages: *design* is the open-loop schedule; *order* plays the same segments and cycles \
         in another order (the weights are unchanged, so the promise it supports is its realised \
         strength ŝ); *re-fit* re-fits the time fractions to the segments' realised velocities in \
         their schedule context and is judged against the re-fit's strength. The best eligible \
         schedule (lowest realised error, the open-loop one included) is kept. Re-fit stopped: {}.\n\n",
        cl.points,
        cl.design_strength,
        stop_text(cl)
    );
    md
}

/// The "Closed loop" section appended to `report.md`.
pub(crate) fn report_section(cl: &ClosedLoop) -> String {
    let (b, a) = (cl.before(), cl.after());
    format!(
        "\n## Closed loop\n\n`schedule.json` is the closed-loop schedule; the open-loop one is \
         `schedule_open_loop.json`; details in `closed_loop.md`.\n\n\
         | | before | after |\n|---|---|---|\n\
         | realised error ‖R − s t‖/‖s t‖ | {} | {} |\n\
         | promised strength s | {:.4} | {:.4} |\n\
         | realised strength ŝ | {:.4} | {:.4} |\n\
         | realised shape error ‖R − ŝ t‖/‖ŝ t‖ | {} | {} |\n\n\
         After: `{}` ({}, {}).\n",
        pct(b.error.error),
        pct(a.error.error),
        b.error.strength,
        a.error.strength,
        b.error.realised_strength,
        a.error.realised_strength,
        pct(b.error.shape_error),
        pct(a.error.shape_error),
        a.order,
        a.stage.name(),
        a.promise
    )
}

/// The closed-loop schedule ([`ClosedLoop::schedule`]) as pretty JSON.
pub(crate) fn schedule_json(d: &Design, target: &Target, cl: &ClosedLoop) -> Result<String> {
    pretty(&cl.schedule(target, &d.target.weights))
}

fn pretty<T: serde::Serialize>(v: &T) -> Result<String> {
    let mut s = serde_json::to_string_pretty(v).map_err(|e| Error::Internal(e.to_string()))?;
    s.push('\n');
    Ok(s)
}

/// Writes the open-loop files ([`report::write`]), then replaces
/// `schedule.json` by the closed-loop schedule and `report.md` by the
/// report with the closed-loop section, and writes `schedule_open_loop.json`,
/// `closed_loop.md` and `closed_loop.json`, all under `dir`.
pub fn write(d: &Design, target: &Target, cl: &ClosedLoop, dir: &Path) -> Result<()> {
    report::write(d, dir)?;
    write_atomic(
        &dir.join("schedule_open_loop.json"),
        report::schedule_json(d).as_bytes(),
    )?;
    write_atomic(
        &dir.join("schedule.json"),
        schedule_json(d, target, cl)?.as_bytes(),
    )?;
    write_atomic(&dir.join("closed_loop.json"), pretty(cl)?.as_bytes())?;
    write_atomic(&dir.join("closed_loop.md"), markdown(cl).as_bytes())?;
    let mut md = report::report_md(d);
    md.push_str(&report_section(cl));
    write_atomic(&dir.join("report.md"), md.as_bytes())?;
    Ok(())
}
