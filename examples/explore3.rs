use platefield::basis::{Primitive, PrimitiveKind};
use platefield::dynamics::{Friction, Model, Numerics, Simulator};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let k = PrimitiveKind::from_name(&args[1], "x").unwrap();
    let x: f64 = args[2].parse().unwrap();
    let y: f64 = args[3].parse().unwrap();
    let mut p = Primitive::new(k);
    if args.len() > 4 {
        p.translation = Some(args[4].parse().unwrap());
    }
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
    println!("{:?}", sim.steady_state([x, y]));
}
