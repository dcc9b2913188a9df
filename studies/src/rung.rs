//! `platefield study rungs`: each default primitive's cheapest model rung
//! within a tolerance of the full model ([`platefield::field::rung`], where
//! the rungs and the rule are stated), force and velocity fields.
//!
//! Compute times are printed by `platefield study rungs`, but never
//! written to `rungs.md`, which is deterministic (fields are bitwise
//! independent of the thread count).

use std::fmt::Write as _;
use std::path::Path;

use platefield::basis::Library;
use platefield::error::{non_negative, Result};
use platefield::field::{FieldKind, FieldSettings, Grid};
use platefield::output::write_atomic;
use platefield_report::table::Table;

use platefield::field::rung::{choose_rung, RungReport, RUNGS};
use platefield::output::significant_percent;

/// The grid of `rungs.md`: 9 × 9 over ±4 cm.
pub(crate) const RUNG_GRID: Grid = Grid {
    x: [-0.04, 0.04],
    y: [-0.04, 0.04],
    n: [9, 9],
};

/// Rung reports for the 8 default primitives on [`RUNG_GRID`], force and
/// velocity fields, default settings: (primitive name, report).
pub(crate) fn default_reports(tolerance: f64) -> Vec<(&'static str, RungReport)> {
    let settings = FieldSettings::default();
    let mut out = Vec::new();
    for kind in [FieldKind::Force, FieldKind::Velocity] {
        for p in Library::default_primitives() {
            let r = choose_rung(&p.motion(), &RUNG_GRID, kind, &settings, tolerance);
            out.push((p.kind.name(), r));
        }
    }
    out
}

/// `rungs.md` for `reports` (as from [`default_reports`]): deterministic,
/// no times.
pub(crate) fn rungs_markdown(reports: &[(&'static str, RungReport)], tolerance: f64) -> String {
    let s = FieldSettings::default();
    let g = RUNG_GRID;
    let mut md = format!(
        "# Model rungs: the cheapest model within tolerance\n\n\
         Each primitive's field computed at every model rung on a {}×{} grid over x ∈ [{}, {}] m, \
         y ∈ [{}, {}] m (μ = {}, {} start phases, {} RK4 steps per cycle), and compared with the \
         full model: relative L2 error ‖F_rung − F_full‖/‖F_full‖ over the samples valid in both. \
         The chosen rung is the cheapest with error ≤ {} and validity flags (contact lost, not \
         converged, frozen assumption broken) identical to full's at every sample. \
         Regenerate: `platefield study rungs --tolerance {tolerance}` (it also prints compute times, \
         which are not written here).\n\n\
         Rungs, cheapest first: `paper` (frozen position, no centripetal, tilt or Coriolis), \
         `paper+moving`, `paper+moving+centripetal+tilt`, `full` (adds Coriolis).\n",
        g.n[0],
        g.n[1],
        g.x[0],
        g.x[1],
        g.y[0],
        g.y[1],
        s.friction.kinetic,
        s.phases,
        s.numerics.steps_per_cycle,
        significant_percent(tolerance),
    );
    for kind in [FieldKind::Force, FieldKind::Velocity] {
        let _ = write!(
            md,
            "\n## {}\n\n",
            match kind {
                FieldKind::Force => "Zero-velocity force fields",
                FieldKind::Velocity => "Steady-state velocity fields",
            }
        );
        let mut table = Table::new(
            ["primitive", "chosen"]
                .into_iter()
                .chain(RUNGS.map(|r| r.0))
                .chain(["why"]),
        );
        for (name, r) in reports.iter().filter(|(_, r)| r.kind == kind) {
            let cells: Vec<String> = r.rungs.iter().map(|x| x.error_text()).collect();
            let mut row = vec![name.to_string(), format!("**{}**", r.rung)];
            row.extend(cells);
            row.push(r.reason.to_string());
            table.row(row);
        }
        md.push_str(&table.markdown());
    }
    md
}

/// Writes `out/rungs.md` for `reports` and returns it.
pub(crate) fn write_reports(
    out: &Path,
    reports: &[(&'static str, RungReport)],
    tolerance: f64,
) -> Result<String> {
    let md = rungs_markdown(reports, tolerance);
    write_atomic(&out.join("rungs.md"), md.as_bytes())?;
    Ok(md)
}

/// Compute times of every rung (s), as a plain-text table for the terminal.
pub(crate) fn times_table(reports: &[(&'static str, RungReport)]) -> String {
    let mut t = format!("{:<14} {:<9}", "compute time", "field");
    for (name, _) in RUNGS {
        let _ = write!(t, " {name:>30}");
    }
    t.push('\n');
    for (name, r) in reports {
        let kind = match r.kind {
            FieldKind::Force => "force",
            FieldKind::Velocity => "velocity",
        };
        let _ = write!(t, "{name:<14} {kind:<9}");
        for x in &r.rungs {
            let _ = write!(t, " {:>29.3}s", x.seconds);
        }
        t.push('\n');
    }
    t
}

/// Default output folder of `platefield study rungs`.
pub const DIR: &str = "results/primitives";

/// `platefield study rungs`: every primitive's rungs at `tolerance`, written to
/// `out/rungs.md`; returns that table, the compute times and the file.
pub fn run(out: &Path, tolerance: f64) -> Result<String> {
    non_negative("--tolerance", tolerance)?;
    let reports = default_reports(tolerance);
    let mut s = write_reports(out, &reports, tolerance)?;
    let _ = write!(s, "\n{}", times_table(&reports));
    let _ = writeln!(s, "wrote {}", out.join("rungs.md").display());
    Ok(s)
}
