//! Speed against error of the field engine, for every primitive and both
//! field kinds: `platefield study engine-speed` writes `results/engine_speed.md`,
//! `engine_speed.csv` and `engine_speed_{force,velocity}.svg`.
//!
//! Each of the eight default primitives' zero-velocity force field and
//! steady-state velocity field (model full, μ = 0.3, [`FieldSettings`]
//! defaults otherwise) is computed on a small grid ([`GRID`], 11 × 11 over
//! ±4 cm, 30 start phases for force fields) at `STEPS` RK4 steps per
//! cycle and against a reference at `REFERENCE_STEPS`. For each: the
//! relative L2 error over samples valid in both ([`relative_l2`]), the wall
//! and CPU time of the field (timings only in the markdown; the csv holds
//! the deterministic numbers), and the observed order log₂(e(n)/e(2n)).
//! The reference's own error is estimated by Richardson extrapolation from
//! the order between the two finest step counts: where that order is low
//! (2-D slips) the finest errors are bounded below by it and are indicative
//! only.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use super::speed::{load_average, process_cpu_seconds};
use platefield::basis::{Library, Primitive};
use platefield::error::Result;
use platefield::field::rung::relative_l2;
use platefield::field::{Field, FieldKind, FieldSettings, Grid};
use platefield::output::write_atomic;
use platefield_report::plot::{LegendPosition, LinePlot, Series};
use platefield_report::table::Table;

/// Default output folder.
pub const DIR: &str = "results";
/// Steps per cycle measured.
pub(crate) const STEPS: [usize; 6] = [8, 16, 32, 64, 128, 256];
/// Steps per cycle of the reference.
pub(crate) const REFERENCE_STEPS: usize = 1024;
/// The grid: 11 × 11 over ±4 cm.
pub const GRID: Grid = Grid {
    x: [-0.04, 0.04],
    y: [-0.04, 0.04],
    n: [11, 11],
};
/// The error target.
pub(crate) const TARGET_ERROR: f64 = 1e-4;

/// What is measured.
#[derive(Debug, Clone)]
pub struct Config {
    /// Primitives (default parameters of each kind).
    pub primitives: Vec<Primitive>,
    /// Field kinds.
    pub kinds: Vec<FieldKind>,
    /// Sampling grid.
    pub grid: Grid,
    /// Start phases of force fields.
    pub phases: usize,
    /// Steps per cycle measured, ascending.
    pub steps: Vec<usize>,
    /// Steps per cycle of the reference.
    pub reference: usize,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            primitives: Library::default_primitives(),
            kinds: vec![FieldKind::Force, FieldKind::Velocity],
            grid: GRID,
            phases: FieldSettings::default().phases,
            steps: STEPS.to_vec(),
            reference: REFERENCE_STEPS,
        }
    }
}

/// One primitive's error against steps for one field kind.
#[derive(Debug, Clone)]
pub struct Curve {
    /// Primitive name.
    pub name: String,
    /// Field kind.
    pub kind: FieldKind,
    /// Steps per cycle, as in [`Config::steps`].
    pub steps: Vec<usize>,
    /// Relative L2 error against the reference at each step count.
    pub errors: Vec<f64>,
    /// Samples valid in both at each step count.
    pub compared: Vec<usize>,
    /// Wall time of each field (s).
    pub seconds: Vec<f64>,
    /// CPU time of each field over all threads (s, 10 ms resolution), where
    /// the platform reports it.
    pub cpu: Vec<Option<f64>>,
    /// Wall time of the reference (s).
    pub reference_seconds: f64,
}

impl Curve {
    /// log₂(e(n)/e(2n)) between consecutive step counts (step counts that
    /// double; NaN where an error is zero or missing).
    pub fn orders(&self) -> Vec<f64> {
        self.errors
            .windows(2)
            .zip(self.steps.windows(2))
            .map(|(e, s)| (e[0] / e[1]).ln() / (s[1] as f64 / s[0] as f64).ln())
            .collect()
    }

    /// Richardson estimate of the reference's own error from the order
    /// between the two finest step counts (NaN when that order is not
    /// positive).
    pub(crate) fn reference_error(&self, reference: usize) -> f64 {
        let p = self.orders().last().copied().unwrap_or(f64::NAN);
        let (n, e) = (
            *self.steps.last().unwrap_or(&1) as f64,
            *self.errors.last().unwrap_or(&f64::NAN),
        );
        if p.is_finite() && p > 0.0 {
            e / ((reference as f64 / n).powf(p) - 1.0)
        } else {
            f64::NAN
        }
    }

    /// Fewest measured steps per cycle with error ≤ `target`.
    pub(crate) fn steps_for(&self, target: f64) -> Option<usize> {
        self.steps
            .iter()
            .zip(&self.errors)
            .find(|(_, e)| **e <= target)
            .map(|(s, _)| *s)
    }
}

fn timed(
    motion: &platefield::motion::Motion,
    config: &Config,
    kind: FieldKind,
    steps: usize,
) -> (Field, f64, Option<f64>) {
    let mut settings = FieldSettings {
        phases: config.phases,
        ..FieldSettings::default()
    };
    settings.numerics.steps_per_cycle = steps;
    let cpu0 = process_cpu_seconds();
    let start = Instant::now();
    let field = Field::compute(motion, &config.grid, kind, &settings, &|| {});
    let wall = start.elapsed().as_secs_f64();
    let cpu = match (cpu0, process_cpu_seconds()) {
        (Some(a), Some(b)) => Some(b - a),
        _ => None,
    };
    (field, wall, cpu)
}

/// Measures every (primitive, kind) curve of `config`.
pub fn measure(config: &Config) -> Vec<Curve> {
    let mut curves = Vec::new();
    for kind in &config.kinds {
        for p in &config.primitives {
            let motion = p.motion();
            let (reference, reference_seconds, _) = timed(&motion, config, *kind, config.reference);
            let mut curve = Curve {
                name: p.kind.name().to_string(),
                kind: *kind,
                steps: config.steps.clone(),
                errors: Vec::new(),
                compared: Vec::new(),
                seconds: Vec::new(),
                cpu: Vec::new(),
                reference_seconds,
            };
            for &steps in &config.steps {
                let (field, wall, cpu) = timed(&motion, config, *kind, steps);
                let (e, n) = relative_l2(&field, &reference);
                curve.errors.push(e);
                curve.compared.push(n);
                curve.seconds.push(wall);
                curve.cpu.push(cpu);
            }
            curves.push(curve);
        }
    }
    curves
}

fn sci(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2e}")
    } else {
        "n/a".into()
    }
}

fn kind_name(kind: FieldKind) -> &'static str {
    match kind {
        FieldKind::Force => "force",
        FieldKind::Velocity => "velocity",
    }
}

/// The csv: one row per (kind, primitive, steps) with the error, the
/// samples compared and the observed order from the previous step count
/// (no timings: the file is deterministic).
pub fn csv(curves: &[Curve]) -> String {
    let mut s = String::from(
        "kind,primitive,steps_per_cycle,relative_l2_error,samples_compared,observed_order\n",
    );
    for c in curves {
        let orders = c.orders();
        for i in 0..c.steps.len() {
            let order = if i == 0 {
                String::new()
            } else {
                format!("{:.4}", orders[i - 1])
            };
            let _ = writeln!(
                s,
                "{},{},{},{:.6e},{},{}",
                kind_name(c.kind),
                c.name,
                c.steps[i],
                c.errors[i],
                c.compared[i],
                order
            );
        }
    }
    s
}

/// Log-log plot of error against steps per cycle for one kind.
pub fn plot(curves: &[Curve], kind: FieldKind, reference: usize) -> LinePlot {
    let mut p = LinePlot::new(format!(
        "{} fields, 11×11: relative L2 error against a {reference}-step reference",
        kind_name(kind)
    ))
    .labels("RK4 steps per cycle", "relative L2 error")
    .log_log()
    .size(720.0, 480.0)
    .legend(LegendPosition::BottomLeft);
    for c in curves.iter().filter(|c| c.kind == kind) {
        let pts = c
            .steps
            .iter()
            .zip(&c.errors)
            .map(|(s, e)| [*s as f64, *e])
            .collect();
        p = p.series(Series::new(c.name.clone(), pts).markers());
    }
    let steps: Vec<f64> = curves
        .first()
        .map(|c| c.steps.iter().map(|s| *s as f64).collect())
        .unwrap_or_default();
    p.series(
        Series::new(
            "target 1e-4",
            steps.iter().map(|s| [*s, TARGET_ERROR]).collect(),
        )
        .color("#888888")
        .dashed(),
    )
}

/// The report.
pub(crate) fn markdown(config: &Config, curves: &[Curve]) -> String {
    let g = config.grid;
    let threads = rayon::current_num_threads();
    let load = load_average().map_or(String::new(), |l| {
        format!(" 1-minute load average at the end: {l}.")
    });
    let mut md = format!(
        "# Field engine: speed against error, every primitive\n\n\
         Each default primitive's zero-velocity force field ({} start phases) and steady-state \
         velocity field on {}×{} points over ±4 cm, model full, μ = 0.3, against a \
         {}-step-per-cycle reference; relative L2 error over samples valid in both. Times: wall \
         and CPU (all threads, 10 ms resolution) of one field with rayon on {threads} threads, on \
         a machine shared with other jobs: they vary with its load, the errors do not.{load} \
         Data: `engine_speed.csv`; plots: `engine_speed_force.svg`, `engine_speed_velocity.svg`.\n",
        config.phases, g.n[0], g.n[1], config.reference
    );
    for kind in &config.kinds {
        let of_kind: Vec<&Curve> = curves.iter().filter(|c| c.kind == *kind).collect();
        error_tables(config, *kind, &of_kind, &mut md);
        time_table(config, *kind, &of_kind, &mut md);
    }
    let _ = writeln!(
        md,
        "\nWhere the observed order between the finest step counts is low (the 2-D slips), \
         the reference's own error (Richardson estimate above) is of the order of the finest \
         errors, which are then indicative only. Regenerate: `platefield study engine-speed` (a few \
         minutes)."
    );
    md
}

/// One field kind's error table and observed orders.
fn error_tables(config: &Config, kind: FieldKind, of_kind: &[&Curve], md: &mut String) {
    let _ = write!(
        md,
        "\n## {} fields\n\nRelative L2 error against steps per cycle:\n\n",
        kind_name(kind)
    );
    let mut table = Table::new(
        std::iter::once("primitive".to_string())
            .chain(config.steps.iter().map(|s| s.to_string()))
            .chain([
                "reference's own error (est.)".into(),
                "fewest steps ≤ 1e-4".into(),
            ]),
    );
    for c in of_kind {
        let mut row = vec![c.name.to_string()];
        row.extend(c.errors.iter().map(|e| sci(*e)));
        row.push(sci(c.reference_error(config.reference)));
        row.push(
            c.steps_for(TARGET_ERROR)
                .map_or("none measured".into(), |s| s.to_string()),
        );
        table.row(row);
    }
    md.push_str(&table.markdown());
    md.push_str("\nObserved order log₂(e(n)/e(2n)):\n\n");
    let pairs = config
        .steps
        .windows(2)
        .map(|w| format!("{}→{}", w[0], w[1]));
    let mut table = Table::new(std::iter::once("primitive".to_string()).chain(pairs));
    for c in of_kind {
        let mut row = vec![c.name.to_string()];
        row.extend(c.orders().iter().map(|p| {
            if p.is_finite() {
                format!("{p:.2}")
            } else {
                "n/a".into()
            }
        }));
        table.row(row);
    }
    md.push_str(&table.markdown());
}

/// One field kind's times, and the target against them.
fn time_table(config: &Config, kind: FieldKind, of_kind: &[&Curve], md: &mut String) {
    md.push_str("\nWall time / CPU time of one field (s):\n\n");
    let mut table = Table::new(
        std::iter::once("primitive".to_string())
            .chain(config.steps.iter().map(|s| s.to_string()))
            .chain(["reference".into()]),
    );
    for c in of_kind {
        let mut row = vec![c.name.to_string()];
        row.extend(c.seconds.iter().zip(&c.cpu).map(|(w, cpu)| {
            format!(
                "{w:.3} / {}",
                cpu.map_or("n/a".into(), |x| format!("{x:.2}"))
            )
        }));
        row.push(format!("{:.3}", c.reference_seconds));
        table.row(row);
    }
    md.push_str(&table.markdown());
    let at64: Vec<String> = of_kind
        .iter()
        .filter_map(|c| {
            let i = c.steps.iter().position(|s| *s == 64)?;
            Some(format!("{} {}", c.name, sci(c.errors[i])))
        })
        .collect();
    let met = of_kind
        .iter()
        .filter(|c| c.steps_for(TARGET_ERROR).is_some_and(|s| s <= 64))
        .count();
    let _ = writeln!(
        md,
        "\nThe issue's target — ≤ 1e-4 at ≤ 64 steps per cycle — is met by {met} of {} \
         primitives' {} fields. At 64 steps: {}.",
        of_kind.len(),
        kind_name(kind),
        at64.join(", ")
    );
}

/// `platefield study engine-speed`: measures [`Config::default`] and writes the
/// report, csv and plots under `out`.
pub fn run(out: &Path) -> Result<String> {
    let config = Config::default();
    let curves = measure(&config);
    let md = markdown(&config, &curves);
    write_atomic(&out.join("engine_speed.csv"), csv(&curves).as_bytes())?;
    for kind in &config.kinds {
        let svg = plot(&curves, *kind, config.reference).to_svg();
        write_atomic(
            &out.join(format!("engine_speed_{}.svg", kind_name(*kind))),
            svg.as_bytes(),
        )?;
    }
    write_atomic(&out.join("engine_speed.md"), md.as_bytes())?;
    let mut s = md;
    let _ = writeln!(
        s,
        "wrote {}, engine_speed.csv, engine_speed_force.svg, engine_speed_velocity.svg",
        out.join("engine_speed.md").display()
    );
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use platefield::basis::PrimitiveKind;

    /// On a tiny grid the study's LineSink force curve (1-D slip) shows
    /// RK4's fourth order, and the csv and plot carry every point.
    #[test]
    fn linesink_force_converges_at_fourth_order() {
        let config = Config {
            primitives: vec![Primitive::new(PrimitiveKind::LineSink)],
            kinds: vec![FieldKind::Force],
            grid: Grid {
                x: [0.01, 0.03],
                y: [0.0, 0.01],
                n: [2, 2],
            },
            phases: 3,
            steps: vec![8, 16, 32],
            reference: 512,
        };
        let curves = measure(&config);
        assert_eq!(curves.len(), 1);
        let c = &curves[0];
        assert_eq!(c.compared, vec![4, 4, 4]);
        let orders = c.orders();
        println!("errors {:?} orders {orders:?}", c.errors);
        assert!(orders.iter().all(|p| *p > 3.3), "{orders:?}");
        let csv = csv(&curves);
        assert_eq!(csv.lines().count(), 4);
        assert!(csv.contains("force,LineSink,16,"));
        let svg = plot(&curves, FieldKind::Force, 512).to_svg();
        platefield_report::plot::test_support::assert_well_formed(&svg);
        assert!(svg.matches("<circle").count() >= 3);
    }
}
