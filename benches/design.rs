//! Speed of the default design. `cargo bench --bench design`.
//!
//! One cold `design targets/sink.json` (method auto) as the CLI runs it:
//! no basis cache (the library is built), the sequenced fit, the synthesis
//! with its stall rule and the played polish, both candidates played
//! (`platefield::inverse::run` by method `auto`, default options), with
//! rayon's default thread count. Issue 27's goal: ≤ 5 s wall on 2 cores.
//! `platefield design-speed` puts every shipped target and several budgets
//! on a cost-against-quality table (`results/design_speed.md`).

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};

use platefield::design::method::Method;
use platefield::design::DesignOptions;
use platefield::request::Target;
use platefield::synth::progress::ProgressMode;
use platefield::synth::SynthOptions;

fn design(c: &mut Criterion) {
    let target = Target::load(Path::new("targets/sink.json")).expect("targets/sink.json loads");
    let opts = DesignOptions {
        basis: platefield::design::BasisSection {
            cache_dir: None,
            ..Default::default()
        },
        runtime: platefield::work::Runtime::QUIET,
        ..DesignOptions::default()
    };
    let synth = SynthOptions {
        progress: ProgressMode::Quiet,
        ..SynthOptions::default()
    };
    let mut group = c.benchmark_group("design");
    group.sample_size(10);
    group.bench_function("sink_auto_cold", |b| {
        b.iter(|| {
            platefield::inverse::run(&target, &opts.by_method(Method::Auto, &synth))
                .and_then(|o| o.into_method())
                .expect("sink designs")
        })
    });
    group.finish();
}

criterion_group!(benches, design);
criterion_main!(benches);
