//! Speed of the forward model. `cargo bench --bench simulator`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};

use platefield::dynamics::{Friction, Model, Numerics, PartPhysics, Simulator};
use platefield_studies::linesink::{LineSink, Wave};

fn shaker(wave: Wave, accel: f64, depth: f64) -> LineSink {
    LineSink {
        wave,
        accel,
        depth,
        period: 0.03,
        friction: Friction::uniform(0.3),
        gravity: 9.81,
    }
}

/// One steady-state velocity at the default tolerance (64 steps per cycle,
/// fixed point to 1e-11 μgT): the unit of every velocity field.
fn steady_state(c: &mut Criterion) {
    for (name, ls, model) in [
        (
            "steady_square_paper",
            shaker(Wave::Square, 180.0, 0.05),
            Model::PAPER,
        ),
        (
            "steady_sine_h5_full",
            shaker(Wave::Sine, 220.0, 0.05),
            Model::FULL,
        ),
        (
            "steady_sine_h1_paper_sticking",
            shaker(Wave::Sine, 220.0, 0.01),
            Model::PAPER,
        ),
    ] {
        let motion = ls.motion();
        let sim = Simulator::new(
            &motion,
            PartPhysics::new(ls.friction, 9.81, model),
            Numerics::default(),
        );
        c.bench_function(name, |b| {
            b.iter(|| sim.steady_state(black_box([0.02, 0.0])))
        });
    }
}

criterion_group!(benches, steady_state);
criterion_main!(benches);
