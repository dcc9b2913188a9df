//! Speed of the field engine on what synthesis and design spend their time
//! on (issue 12). `cargo bench --bench engine`.
//!
//! * `six_signal_velocity_9x9`: the steady-state velocity field of a
//!   six-signal motion ([`Signals::example`]) on 9 × 9 points over ±4 cm —
//!   the unit synthesis evaluates hundreds of.
//! * `linesink_force_21x21x30_8_steps`: one force field at the issue's
//!   LineSink comparison point (8 steps per cycle, error ≈ 6e-5).
//! * `design_sink_cold`: `design` of `targets/sink.json` with no basis
//!   cache (every basis field simulated), default options.

use criterion::{criterion_group, criterion_main, Criterion};

use platefield::basis::{Primitive, PrimitiveKind};
use platefield::design::{design, DesignOptions};
use platefield::field::{Field, FieldKind, FieldSettings, Grid};
use platefield::motion::{Motion, Signals};
use platefield::request::Target;

fn fields(c: &mut Criterion) {
    let six = Motion::Signals(Signals::example());
    let grid9 = Grid {
        n: [9, 9],
        ..Grid::DEFAULT
    };
    let settings = FieldSettings::default();
    c.bench_function("six_signal_velocity_9x9", |b| {
        b.iter(|| Field::compute(&six, &grid9, FieldKind::Velocity, &settings, &|| {}))
    });
    let sink = Primitive::new(PrimitiveKind::LineSink).motion();
    let mut coarse = FieldSettings::default();
    coarse.numerics.steps_per_cycle = 8;
    c.bench_function("linesink_force_21x21x30_8_steps", |b| {
        b.iter(|| Field::compute(&sink, &Grid::DEFAULT, FieldKind::Force, &coarse, &|| {}))
    });
}

fn cold_design(c: &mut Criterion) {
    let target =
        Target::load(std::path::Path::new("targets/sink.json")).expect("targets/sink.json");
    let opts = DesignOptions {
        basis: platefield::design::BasisSection {
            cache_dir: None,
            ..Default::default()
        },
        runtime: platefield::work::Runtime::QUIET,
        ..DesignOptions::default()
    };
    let mut group = c.benchmark_group("design");
    group.sample_size(10);
    group.bench_function("design_sink_cold", |b| {
        b.iter(|| design(&target, &opts).expect("design"))
    });
    group.finish();
}

criterion_group!(benches, fields, cold_design);
criterion_main!(benches);
