use platefield::basis::{Primitive, PrimitiveKind};
use platefield::dynamics::{Friction, Model, Numerics, Simulator};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let k = PrimitiveKind::from_name(&args[1], "x").unwrap();
    let x: f64 = args[2].parse().unwrap();
    let y: f64 = args[3].parse().unwrap();
    let p = Primitive::new(k);
    let m = p.motion();
    for n in [32, 64, 128, 256, 1024] {
        let sim = Simulator::new(
            &m,
            Friction::uniform(0.3),
            9.81,
            Model::FULL,
            Numerics {
                steps_per_cycle: n,
                max_iterations: 200,
                ..Numerics::default()
            },
        );
        println!("{n}: {:?}", sim.steady_state([x, y]));
    }
}
