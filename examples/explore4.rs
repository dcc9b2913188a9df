use nalgebra::Vector2;
use platefield::basis::{Primitive, PrimitiveKind};
use platefield::dynamics::{Friction, Model, Numerics, PartState, Simulator};
fn main() {
    let mut p = Primitive::new(PrimitiveKind::SkewSink);
    p.translation = Some(-0.0003);
    let m = p.motion();
    let n: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(32);
    let sim = Simulator::new(
        &m,
        Friction::uniform(0.3),
        9.81,
        Model::FULL,
        Numerics {
            steps_per_cycle: n,
            ..Numerics::default()
        },
    );
    let r0 = Vector2::new(0.0, 0.0);
    let base = Vector2::new(-0.0108, 0.0129);
    for i in 0..8 {
        let u = base + Vector2::new(1e-9 * i as f64, 0.0);
        let mut st = PartState::new(r0, u);
        let mut rec = Vec::new();
        let out = sim
            .advance(0.0, 0.03, &mut st, &r0, Some(&mut rec))
            .unwrap();
        println!(
            "i={i} end u={:?} r={:?} events={} stuck={:e}",
            out.state.u.as_slice(),
            out.state.r.as_slice(),
            out.events,
            out.stuck_time
        );
    }
}
