use platefield::dynamics::{Friction, Model, Numerics, Simulator, PartState};
use platefield::linesink::{LineSink, Wave};
use nalgebra::Vector2;

#[test]
fn quick() {
    let ls = LineSink { wave: Wave::Square, accel: 180.0, depth: 0.05, period: 0.03, friction: Friction::uniform(0.3), gravity: 9.81 };
    for n in [2, 4, 8, 64, 1000] {
        let num = Numerics { steps_per_cycle: n, ..Numerics::default() };
        let row = &ls.rows(&[0.005], Model::PAPER, num)[0];
        println!("n={n} {:?} {:?}", row.v_ss, row.eq17);
    }
    let m = ls.motion();
    let sim = Simulator::new(&m, ls.friction, 9.81, Model::PAPER, Numerics{steps_per_cycle: 8, ..Numerics::default()});
    let s = sim.steady_state([0.005, 0.0]).unwrap();
    println!("{s:?}");
    let mut st = PartState::new(Vector2::new(0.005, 0.0), Vector2::from(s.start_slip));
    let mut rec = Vec::new();
    sim.advance(0.0, 0.03, &mut st, &Vector2::new(0.005, 0.0), Some(&mut rec)).unwrap();
    for p in rec { println!("{:.6} {:.9} {:.9} {}", p.t, p.state.r.x, p.state.u.x, p.state.stuck); }
}
