use platefield::basis::Library;
use platefield::dynamics::Numerics;
use platefield::field::{Field, FieldKind, FieldSettings, Grid};
fn main() {
    let grid = Grid::DEFAULT;
    let only = std::env::var("P").unwrap_or_default();
    let prims: Vec<_> = Library::default_primitives()
        .into_iter()
        .filter(|p| only.is_empty() || only.contains(p.kind.name()))
        .collect();
    let build = |n: usize| -> (Vec<Field>, f64) {
        let mut model = platefield::dynamics::Model::FULL;
        if let Ok(m) = std::env::var("M") {
            model.centripetal = m.contains('c');
            model.tilt = m.contains('t');
            model.coriolis = m.contains('o');
            model.moving = m.contains('m');
        }
        let s = FieldSettings {
            model,
            numerics: Numerics {
                steps_per_cycle: n,
                ..Numerics::default()
            },
            ..FieldSettings::default()
        };
        let t = std::time::Instant::now();
        let f: Vec<Field> = prims
            .iter()
            .map(|p| {
                let t = std::time::Instant::now();
                let f = Field::compute(&p.motion(), &grid, FieldKind::Force, &s, &|| {});
                if n < 100 {
                    print!("{} {:.3}s ", p.kind.name(), t.elapsed().as_secs_f64());
                }
                f
            })
            .collect();
        (f, t.elapsed().as_secs_f64())
    };
    let (reference, tr) = build(256);
    println!("ref {tr:.2}s");
    for n in [8, 16, 32, 64] {
        let (f, t) = build(n);
        let mut worst: f64 = 0.0;
        for (a, b) in f.iter().zip(&reference) {
            let num: f64 = a
                .vectors
                .iter()
                .zip(&b.vectors)
                .map(|(x, y)| (x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2))
                .sum::<f64>()
                .sqrt();
            let den: f64 = b
                .vectors
                .iter()
                .map(|y| y[0] * y[0] + y[1] * y[1])
                .sum::<f64>()
                .sqrt();
            worst = worst.max(num / den);
            print!("{:.1e} ", num / den);
        }
        println!("steps {n}: {t:.3}s worst rel err {worst:.2e}");
    }
}
