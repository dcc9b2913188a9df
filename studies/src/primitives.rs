//! `platefield study primitives`: each primitive's fields as JSON and quiver
//! plots, and `table1.md`, the fits to the paper's Table I.

use platefield_report::plot::field_quiver;
use std::fmt::Write as _;
use std::path::Path;

use super::table1;
use platefield::basis::{Library, LibraryEntry, StepsPlan};
use platefield::error::Result;
use platefield::field::{FieldKind, FieldSettings, Grid};
use platefield::output::write_atomic;
use platefield_report::table::Table;

fn json_bytes(v: &serde_json::Value) -> Vec<u8> {
    let mut s = serde_json::to_string_pretty(v).unwrap_or_default();
    s.push('\n');
    s.into_bytes()
}

/// Writes `<Name>.json`, `<Name>.velocity.json`, `<Name>.svg`,
/// `<Name>.velocity.svg` and `table1.md` under `out`; returns table1.md.
pub(crate) fn write_primitives(lib: &Library, out: &Path) -> Result<String> {
    let s = &lib.settings;
    let mut md = format!(
        "# Primitive fields against the paper's Table I\n\n\
         Grid {}; model `{}`; μ_s = {}, μ_k = {}; \
         {} start phases; {} RK4 steps per cycle{}. Regenerate: `platefield study primitives`.\n\n\
         Least-squares fit of each field to its Table I form over the valid samples \
         (Circle: outside 1 cm of its axis). R² is uncentred (the forms have no constant \
         term): R² = 1 − Σ|f − f̂|²/Σ|f|². Coefficients in s⁻² m⁻ᵏ (force) and s⁻¹ m⁻ᵏ \
         (velocity) for a form of degree k in position. *Signs* checks a > 0 \
         (for DivCircle, a > 0; b is reported).\n\n",
        lib.grid.describe(),
        s.model.name(),
        s.friction.stat,
        s.friction.kinetic,
        s.phases,
        s.numerics.steps_per_cycle,
        if lib
            .entries
            .iter()
            .all(|e| e.force_steps == s.numerics.steps_per_cycle)
        {
            String::new()
        } else {
            format!(
                " (force fields at their calibrated counts: {})",
                lib.force_steps_list()
            )
        }
    );
    let mut table = Table::new([
        "primitive",
        "form",
        "force: coefficients",
        "force R²",
        "velocity: coefficients",
        "velocity R²",
        "valid (force, velocity)",
        "signs",
    ]);
    for e in &lib.entries {
        let name = e.primitive.kind.name();
        write_entry_files(e, s, out)?;
        let (ff, fv) = (
            table1::fit(e.primitive.kind, &e.force),
            table1::fit(e.primitive.kind, &e.velocity),
        );
        let coef = |c: &[f64]| {
            c.iter()
                .map(|x| format!("{x:.4}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let signs_ok = ff.signs_ok && fv.signs_ok;
        table.row([
            name.to_string(),
            ff.form.to_string(),
            coef(&ff.coefficients),
            format!("{:.4}", ff.r2),
            coef(&fv.coefficients),
            format!("{:.4}", fv.r2),
            format!(
                "{}/{}, {}/{}",
                e.force.valid_count(),
                e.force.vectors.len(),
                e.velocity.valid_count(),
                e.velocity.vectors.len()
            ),
            if signs_ok { "ok" } else { "WRONG" }.to_string(),
        ]);
    }
    md.push_str(&table.markdown());
    write_atomic(&out.join("table1.md"), md.as_bytes())?;
    Ok(md)
}

/// One primitive's files: its force and velocity fields as JSON and quiver
/// plots.
fn write_entry_files(e: &LibraryEntry, s: &FieldSettings, out: &Path) -> Result<()> {
    let name = e.primitive.kind.name();
    // The force field's own settings (its steps per cycle may be its
    // calibrated count, not the library's).
    let mut force_settings = *s;
    force_settings.numerics.steps_per_cycle = e.force_steps;
    write_atomic(
        &out.join(format!("{name}.json")),
        &json_bytes(&e.force.to_json(&force_settings)),
    )?;
    write_atomic(
        &out.join(format!("{name}.velocity.json")),
        &json_bytes(&e.velocity.to_json(s)),
    )?;
    write_atomic(
        &out.join(format!("{name}.svg")),
        field_quiver(&e.force, &format!("{name}: zero-velocity force field"))
            .to_svg()
            .as_bytes(),
    )?;
    write_atomic(
        &out.join(format!("{name}.velocity.svg")),
        field_quiver(&e.velocity, &format!("{name}: steady-state velocity field"))
            .to_svg()
            .as_bytes(),
    )?;
    Ok(())
}

/// Default output folder of `platefield study primitives`.
pub const DIR: &str = "results/primitives";

/// The study's work on an `n` × `n` grid at `steps` steps per cycle under
/// `plan`, relative to its defaults (the default grid and steps,
/// uniform): the sum over the default primitives of their force and
/// velocity fields' terms (`platefield::work::field_term`: samples × cycles ×
/// steps) at the steps `plan` gives each.
///
/// ```
/// use platefield::basis::StepsPlan;
/// use platefield_studies::primitives::work_factor;
/// assert_eq!(work_factor(21, 64, StepsPlan::Uniform), 1.0);
/// assert!((work_factor(42, 32, StepsPlan::Uniform) - 2.0).abs() < 1e-12);
/// assert!(work_factor(21, 64, StepsPlan::Calibrated) < 1.0);
/// ```
pub fn work_factor(n: usize, steps: usize, plan: StepsPlan) -> f64 {
    let work = |n: usize, steps: usize, plan: StepsPlan| -> f64 {
        let grid = Grid {
            n: [n, n],
            ..Grid::DEFAULT
        };
        let mut settings = FieldSettings::default();
        settings.numerics.steps_per_cycle = steps;
        let term = |p: &platefield::basis::Primitive, kind: FieldKind| {
            let mut s = settings;
            s.numerics.steps_per_cycle = plan.steps(p, kind, &grid, &settings);
            platefield::work::field_term("", 1.0, "field", (n * n) as f64, kind, &s).steps()
        };
        Library::default_primitives()
            .iter()
            .map(|p| term(p, FieldKind::Force) + term(p, FieldKind::Velocity))
            .sum()
    };
    let defaults = FieldSettings::default().numerics.steps_per_cycle;
    work(n, steps, plan) / work(Grid::DEFAULT.n[0], defaults, StepsPlan::Uniform)
}

/// `platefield study primitives`: simulates the default library on an `n × n`
/// grid over ±4 cm at `steps` RK4 steps per cycle (force fields as `plan`
/// says) and writes it under `out`; returns table1.md and a line with the
/// build time.
pub fn run(out: &Path, n: usize, steps: usize, plan: StepsPlan, quiet: bool) -> Result<String> {
    let grid = Grid {
        n: [n, n],
        ..Grid::DEFAULT
    };
    grid.validate("--grid")?;
    let mut settings = FieldSettings::default();
    settings.numerics.steps_per_cycle = steps;
    settings.numerics.validate("--steps")?;
    let start = std::time::Instant::now();
    let lib = Library::build(
        &Library::default_primitives(),
        &grid,
        &settings,
        plan,
        platefield::progress::ProgressMode::quiet_if(quiet),
    );
    let elapsed = start.elapsed().as_secs_f64();
    let mut table = write_primitives(&lib, out)?;
    let _ = writeln!(
        table,
        "\nbuilt {} primitives × 2 fields on {n}×{n} in {elapsed:.2} s (force fields at {} steps per cycle); wrote {}",
        lib.entries.len(),
        lib.force_steps_list(),
        out.display()
    );
    Ok(table)
}
