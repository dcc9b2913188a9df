//! Speed of the primitive library. `cargo bench --bench library`.
//!
//! One build of the default 8-primitive zero-velocity force library (21 × 21
//! grid over ±4 cm, 30 start phases, model full) at 32 RK4 steps per cycle,
//! and one with each primitive at its calibrated steps per cycle
//! (`StepsPlan::Calibrated`, every field within 1e-4), with rayon's default
//! thread count. `platefield speed` puts both on a speed-against-error
//! table (`results/library_speed.md`).

use criterion::{criterion_group, criterion_main, Criterion};

use platefield_studies::speed::{build_calibrated_force_library, build_force_library};

fn library(c: &mut Criterion) {
    let mut group = c.benchmark_group("library");
    group.sample_size(10);
    group.bench_function("force_library_32_steps", |b| {
        b.iter(|| build_force_library(32))
    });
    group.bench_function("force_library_calibrated", |b| {
        b.iter(build_calibrated_force_library)
    });
    group.finish();
}

criterion_group!(benches, library);
criterion_main!(benches);
