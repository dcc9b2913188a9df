//! Single fields of the engine: the CPU time of each on one
//! thread and its wall time on one and two threads, printed (timings move
//! with the machine and its load, so they are never written), and whether
//! the field's bits are the same on one and two threads, written.
//!
//! The CPU column (mean over [`REPEATS`], from /proc/self/stat in 10 ms
//! ticks) is the one to compare on a loaded machine; the fields of a few
//! milliseconds are compared by their best wall time.

use std::time::Instant;

use crate::speed::process_cpu_seconds;
use platefield::basis::{Primitive, PrimitiveKind};
use platefield::field::{Field, FieldKind, FieldSettings, Grid};
use platefield::motion::{Invariance, Motion, Signals};
use platefield_report::table::Table;

/// Runs of each field per thread count.
pub(crate) const REPEATS: usize = 3;

/// One field timed: its motion, grid, kind and steps per cycle, and
/// whether every point is simulated (no reduction by the motion's
/// invariance, `Field::compute_by` with `Invariance::None`).
struct Case {
    name: String,
    motion: Motion,
    grid: Grid,
    kind: FieldKind,
    steps: usize,
    every_point: bool,
}

/// A default primitive's force field on the default 21 × 21 grid.
fn force(kind: PrimitiveKind, steps: usize, every_point: bool) -> Case {
    Case {
        name: format!(
            "{kind:?} force 21×21×30, {steps} steps{}",
            if every_point { ", every point" } else { "" }
        ),
        motion: Primitive::new(kind).motion(),
        grid: Grid::DEFAULT,
        kind: FieldKind::Force,
        steps,
        every_point,
    }
}

/// The fields the docs cite.
fn cases() -> Vec<Case> {
    use PrimitiveKind::*;
    let mut out = vec![
        force(LineSink, 8, false),
        force(LineSink, 8, true),
        force(LineSink, 64, false),
        force(LineSource, 8, false),
        force(Trans, 32, false),
    ];
    for kind in [ScaledCircle, DivCircle, Circle, SkewSink, SkewSource] {
        out.push(force(kind, 64, false));
    }
    out.extend([
        force(ScaledCircle, 16, false),
        force(DivCircle, 32, false),
        force(DivCircle, 16, false),
    ]);
    out.push(Case {
        name: "ScaledCircle velocity 21×21, 64 steps".into(),
        motion: Primitive::new(ScaledCircle).motion(),
        grid: Grid::DEFAULT,
        kind: FieldKind::Velocity,
        steps: 64,
        every_point: false,
    });
    out.push(Case {
        name: "six-signal velocity 9×9, 64 steps".into(),
        motion: Motion::Signals(Signals::example()),
        grid: Grid {
            n: [9, 9],
            ..Grid::DEFAULT
        },
        kind: FieldKind::Velocity,
        steps: 64,
        every_point: false,
    });
    out
}

impl Case {
    fn compute(&self) -> Field {
        let mut settings = FieldSettings::default();
        settings.numerics.steps_per_cycle = self.steps;
        let invariance = if self.every_point {
            Invariance::None
        } else {
            self.motion.invariance()
        };
        Field::compute_by(
            &self.motion,
            &self.grid,
            self.kind,
            &settings,
            invariance,
            &|| {},
        )
    }

    /// Best wall time of [`REPEATS`] runs on `threads` threads, the mean
    /// CPU time per run (NaN where not measurable) and the last field.
    fn time(&self, threads: usize) -> (f64, f64, Option<Field>) {
        let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(threads).build() else {
            return (f64::NAN, f64::NAN, None);
        };
        let (mut best, mut out) = (f64::INFINITY, None);
        let cpu0 = process_cpu_seconds();
        for _ in 0..REPEATS {
            let start = Instant::now();
            out = Some(pool.install(|| self.compute()));
            best = best.min(start.elapsed().as_secs_f64());
        }
        let cpu = match (cpu0, process_cpu_seconds()) {
            (Some(a), Some(b)) => (b - a) / REPEATS as f64,
            _ => f64::NAN,
        };
        (best, cpu, out)
    }
}

/// Whether two fields have the same bits (vectors and validity).
fn same_bits(a: &Field, b: &Field) -> bool {
    let bits = |f: &Field| -> Vec<u64> {
        f.vectors
            .iter()
            .flat_map(|v| [v[0].to_bits(), v[1].to_bits()])
            .collect()
    };
    bits(a) == bits(b) && a.validity == b.validity
}

/// The section of `probes.md`; the timings go to stderr.
pub(crate) fn section() -> String {
    let mut md = String::from(
        "\n## Single fields of the engine\n\n\
         Model full, μ = 0.3. Their CPU time on one thread and wall time on one and two threads \
         are printed by `platefield study probes` (never written: they move with the machine).\n\n",
    );
    let mut table = Table::new(["field", "invalid samples", "same bits on 1 and 2 threads"]);
    let mut timings = Table::new([
        "field",
        "1 thread wall (s)",
        "1 thread CPU (s)",
        "2 threads wall (s)",
    ]);
    for case in cases() {
        let (w1, c1, f1) = case.time(1);
        let (w2, _, f2) = case.time(2);
        timings.row([
            case.name.clone(),
            format!("{w1:.4}"),
            format!("{c1:.4}"),
            format!("{w2:.4}"),
        ]);
        let (invalid, same) = match (&f1, &f2) {
            (Some(a), Some(b)) => (
                (a.validity.len() - a.valid_count()).to_string(),
                if same_bits(a, b) { "yes" } else { "NO" },
            ),
            _ => ("—".into(), "no thread pool"),
        };
        table.row([case.name, invalid, same.to_string()]);
    }
    eprint!("{}", timings.markdown());
    md.push_str(&table.markdown());
    md
}
