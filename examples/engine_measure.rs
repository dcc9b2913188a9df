//! Timings of the field engine (issue 12): CPU time of single fields on one
//! thread and wall time on two, with a hash of each field's bits so that two
//! builds of the engine can be compared for bitwise equality.
//!
//! `cargo run --release --example engine_measure [-- REPEATS [NAME-PART]]`
//!
//! The CPU column (mean over the repeats, from /proc/self/stat in 10 ms
//! ticks: use 10 or more repeats) is the one to compare on a loaded machine.

use std::time::Instant;

use platefield::basis::{Library, Primitive, PrimitiveKind};
use platefield::field::{Field, FieldKind, FieldSettings, Grid};
use platefield::motion::{Motion, Signals};

fn six_signal_motion() -> Motion {
    Motion::Signals(Signals::example())
}

/// FNV-1a over the bits of every vector and validity.
fn hash(f: &Field) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    let mut eat = |x: u64| {
        for b in x.to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x100000001b3);
        }
    };
    for (v, ok) in f.vectors.iter().zip(&f.validity) {
        eat(v[0].to_bits());
        eat(v[1].to_bits());
        eat(*ok as u64);
    }
    h
}

/// CPU time of this process (user + system, s; 10 ms ticks), from
/// /proc/self/stat (Linux), or None.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Best wall time of `repeats` runs on `threads` threads, the mean CPU time
/// per run (all threads; NaN where not measurable) and the last field.
fn time(threads: usize, repeats: usize, f: &(dyn Fn() -> Field + Sync)) -> (f64, f64, Field) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let mut best = f64::INFINITY;
    let mut out = None;
    let cpu0 = cpu_seconds();
    for _ in 0..repeats {
        let start = Instant::now();
        let field = pool.install(f);
        best = best.min(start.elapsed().as_secs_f64());
        out = Some(field);
    }
    let cpu = match (cpu0, cpu_seconds()) {
        (Some(a), Some(b)) => (b - a) / repeats as f64,
        _ => f64::NAN,
    };
    (best, cpu, out.expect("at least one repeat"))
}

fn main() {
    let repeats: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    let only = std::env::args().nth(2).unwrap_or_default();
    let six = Grid {
        n: [9, 9],
        ..Grid::DEFAULT
    };
    let cases: Vec<(String, Motion, Grid, FieldKind, usize)> = vec![
        (
            "LineSink force 21x21x30, 8 steps".into(),
            Primitive::new(PrimitiveKind::LineSink).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            8,
        ),
        (
            "LineSink force 21x21x30, 8 steps, every point".into(),
            Primitive::new(PrimitiveKind::LineSink).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            8,
        ),
        (
            "LineSink force 21x21x30, 64 steps".into(),
            Primitive::new(PrimitiveKind::LineSink).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            64,
        ),
        (
            "LineSource force 21x21x30, 8 steps".into(),
            Primitive::new(PrimitiveKind::LineSource).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            8,
        ),
        (
            "Trans force 21x21x30, 32 steps".into(),
            Primitive::new(PrimitiveKind::Trans).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            32,
        ),
        (
            "ScaledCircle force 21x21x30, 64 steps".into(),
            Primitive::new(PrimitiveKind::ScaledCircle).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            64,
        ),
        (
            "DivCircle force 21x21x30, 64 steps".into(),
            Primitive::new(PrimitiveKind::DivCircle).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            64,
        ),
        (
            "Circle force 21x21x30, 64 steps".into(),
            Primitive::new(PrimitiveKind::Circle).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            64,
        ),
        (
            "SkewSink force 21x21x30, 64 steps".into(),
            Primitive::new(PrimitiveKind::SkewSink).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            64,
        ),
        (
            "SkewSource force 21x21x30, 64 steps".into(),
            Primitive::new(PrimitiveKind::SkewSource).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            64,
        ),
        (
            "ScaledCircle force 21x21x30, 16 steps".into(),
            Primitive::new(PrimitiveKind::ScaledCircle).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            16,
        ),
        (
            "DivCircle force 21x21x30, 32 steps".into(),
            Primitive::new(PrimitiveKind::DivCircle).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            32,
        ),
        (
            "DivCircle force 21x21x30, 16 steps".into(),
            Primitive::new(PrimitiveKind::DivCircle).motion(),
            Grid::DEFAULT,
            FieldKind::Force,
            16,
        ),
        (
            "ScaledCircle velocity 21x21, 64 steps".into(),
            Primitive::new(PrimitiveKind::ScaledCircle).motion(),
            Grid::DEFAULT,
            FieldKind::Velocity,
            64,
        ),
        (
            "six-signal velocity 9x9, 64 steps".into(),
            six_signal_motion(),
            six,
            FieldKind::Velocity,
            64,
        ),
    ];
    if "library".contains(&only) || only.is_empty() {
        for steps in [8, 16, 32, 64] {
            let mut settings = FieldSettings::default();
            settings.numerics.steps_per_cycle = steps;
            let primitives = Library::default_primitives();
            let build = || {
                primitives
                    .iter()
                    .map(|p| {
                        Field::compute(
                            &p.motion(),
                            &Grid::DEFAULT,
                            FieldKind::Force,
                            &settings,
                            &|| {},
                        )
                    })
                    .collect::<Vec<_>>()
            };
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(2)
                .build()
                .expect("thread pool");
            let mut best = f64::INFINITY;
            let cpu0 = cpu_seconds();
            for _ in 0..repeats {
                let start = Instant::now();
                let fields = pool.install(build);
                best = best.min(start.elapsed().as_secs_f64());
                assert_eq!(fields.len(), 8);
            }
            let cpu = match (cpu0, cpu_seconds()) {
                (Some(a), Some(b)) => (b - a) / repeats as f64,
                _ => f64::NAN,
            };
            println!(
                "library: 8 force fields 21x21x30 at {steps} steps, 2 threads: {best:.3} s wall, \
                 {cpu:.2} s CPU"
            );
        }
    }
    println!(
        "| field | 1 thread wall (s) | 1 thread CPU (s) | 2 threads wall (s) | bits 1 thread | bits 2 threads |"
    );
    println!("|---|---|---|---|---|---|");
    for (name, motion, grid, kind, steps) in cases.iter().map(|(a, b, c, d, e)| (a, b, c, *d, *e)) {
        if !name.contains(&only) {
            continue;
        }
        let mut settings = FieldSettings::default();
        settings.numerics.steps_per_cycle = steps;
        // "every point": no reduction by the motion's invariance (what a
        // per-point engine costs, `Field::compute_every_point`).
        let run = || {
            if name.contains("every point") {
                Field::compute_every_point(motion, grid, kind, &settings, &|| {})
            } else {
                Field::compute(motion, grid, kind, &settings, &|| {})
            }
        };
        let (t1, c1, f1) = time(1, repeats, &run);
        let (t2, _, f2) = time(2, repeats, &run);
        let bad = f1.validity.len() - f1.valid_count();
        println!(
            "| {name} | {t1:.4} | {c1:.4} | {t2:.4} | {:016x} | {:016x} | invalid {bad}",
            hash(&f1),
            hash(&f2)
        );
    }
}
