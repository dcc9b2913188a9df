use platefield::basis::{Primitive, PrimitiveKind};
use platefield::dynamics::{Friction, Model, Numerics, Simulator};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let k = PrimitiveKind::from_name(&args[1], "x").unwrap();
    let x: f64 = args[2].parse().unwrap();
    let y: f64 = args[3].parse().unwrap();
    let p = Primitive::new(k);
    let m = p.motion();
    for model in [Model::PAPER, Model::FULL] {
        for it in [20usize, 200, 2000] {
            let sim = Simulator::new(
                &m,
                Friction::uniform(0.3),
                9.81,
                model,
                Numerics {
                    steps_per_cycle: 32,
                    max_iterations: it,
                    ..Numerics::default()
                },
            );
            println!("{:?} {it}: {:?}", model.name(), sim.steady_state([x, y]));
        }
    }
}
