use nalgebra::Vector2;
use platefield::basis::{Primitive, PrimitiveKind};
use platefield::dynamics::{Friction, Model, Numerics, PartState, Simulator};
use platefield::motion::V3;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let k = PrimitiveKind::from_name(&args[1], "x").unwrap();
    let x: f64 = args[2].parse().unwrap();
    let y: f64 = args[3].parse().unwrap();
    let ph: f64 = args[4].parse().unwrap();
    let p = Primitive::new(k);
    let m = p.motion();
    let model = Model {
        centripetal: false,
        tilt: true,
        coriolis: false,
        moving: false,
    };
    let r0 = Vector2::new(x, y);
    for n in [8, 16, 32, 64, 128, 256, 1024, 4096, 16384] {
        let sim = Simulator::new(
            &m,
            Friction::uniform(0.3),
            9.81,
            model,
            Numerics {
                steps_per_cycle: n,
                ..Numerics::default()
            },
        );
        let t0 = ph * 0.03;
        let kk = m.kinematics(t0, 9.81, true);
        let v = kk.velocity_at(&V3::new(x, y, 0.0));
        let mut st = PartState::new(r0, -Vector2::new(v.x, v.y));
        let mut rec = Vec::new();
        let out = sim
            .advance(t0, t0 + m.period(), &mut st, &r0, Some(&mut rec))
            .unwrap();
        if n == 8 || n == 16384 {
            for p in rec.iter().filter(|p| p.t > t0 + 0.004 && p.t < t0 + 0.0125) {
                if n == 8 || ((p.t - t0) / 0.03 * 16384.0).round() as i64 % 64 == 0 {
                    println!(
                        "  t={:.6} u={:.6e},{:.6e} |u|={:.3e}",
                        (p.t - t0) / 0.03,
                        p.state.u.x,
                        p.state.u.y,
                        p.state.u.norm()
                    );
                }
            }
        }
        println!(
            "{n}: u={:.12e},{:.12e} events={} stuck={:.9e}",
            out.state.u.x, out.state.u.y, out.events, out.stuck_time
        );
    }
}
