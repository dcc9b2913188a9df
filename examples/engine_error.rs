//! Relative L2 error of force and velocity fields against a 1024-step
//! reference on the `engine-speed` grid (11 × 11, 30 phases), at 8–64 steps
//! per cycle, for the primitives whose stop and break-away paths the engine
//! speed-ups touched (the same numbers as `results/engine_speed.md`, faster).
//!
//! `cargo run --release --example engine_error`

use platefield::basis::{Primitive, PrimitiveKind};
use platefield::field::{Field, FieldKind, FieldSettings};
use platefield::studies::engine_speed::GRID;
use platefield::studies::rung::relative_l2;
fn main() {
    for name in ["LineSink", "LineSource", "Trans", "SkewSink", "DivCircle"] {
        let kind = PrimitiveKind::from_name(name, "name").expect("a primitive name");
        let motion = Primitive::new(kind).motion();
        for fk in [FieldKind::Force, FieldKind::Velocity] {
            let field = |steps: usize| {
                let mut s = FieldSettings::default();
                s.numerics.steps_per_cycle = steps;
                Field::compute(&motion, &GRID, fk, &s, &|| {})
            };
            let reference = field(1024);
            let mut line = format!("{name} {fk:?}:");
            for steps in [8, 16, 32, 64] {
                let (e, _) = relative_l2(&field(steps), &reference);
                line += &format!(" {steps}:{e:.3e}");
            }
            println!("{line}");
        }
    }
}
