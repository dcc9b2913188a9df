use nalgebra::Vector2;
use platefield::basis::{Primitive, PrimitiveKind};
use platefield::dynamics::{Friction, Model, Numerics, PartState, Simulator};
fn main() {
    let p = Primitive::new(PrimitiveKind::DivCircle);
    let m = p.motion();
    let sim = Simulator::new(
        &m,
        Friction::uniform(0.3),
        9.81,
        Model::FULL,
        Numerics {
            steps_per_cycle: 32,
            ..Numerics::default()
        },
    );
    let r0 = Vector2::new(-0.02, -0.02);
    let base = Vector2::new(-0.0016997814783240458, 0.0016097266325578933);
    for i in 0..6 {
        let u = base + Vector2::new(1e-12 * i as f64, 0.0);
        let mut st = PartState::new(r0, u);
        let mut rec = Vec::new();
        let out = sim
            .advance(0.0, 0.03, &mut st, &r0, Some(&mut rec))
            .unwrap();
        println!(
            "i={i} end u={:?} stuck_time={:e} events={}",
            out.state.u.as_slice(),
            out.stuck_time,
            out.events
        );
        if i == 0 || i == 5 {
            for p in rec.iter().take(40) {
                print!(
                    "[{:.5} {:.3e},{:.3e} {}] ",
                    p.t, p.state.u.x, p.state.u.y, p.state.stuck as u8
                );
            }
            println!();
        }
    }
}
