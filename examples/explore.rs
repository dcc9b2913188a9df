use platefield::basis::{table1, Primitive, PrimitiveKind};
use platefield::dynamics::{Model, Numerics};
use platefield::field::{Field, FieldKind, FieldSettings, Grid};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let k = PrimitiveKind::from_name(&args[1], "x").unwrap();
    let n: usize = std::env::var("N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(9);
    let grid = Grid {
        x: [-0.04, 0.04],
        y: [-0.04, 0.04],
        n: [n, n],
    };
    for v in &args[2..] {
        let mut p = Primitive::new(k);
        let x: f64 = v.parse().unwrap();
        if std::env::var("T").is_ok() {
            p.translation = Some(x)
        } else {
            p.amplitude = Some(x)
        }
        for kind in [FieldKind::Force, FieldKind::Velocity] {
            let s = FieldSettings {
                model: Model::FULL,
                numerics: Numerics {
                    steps_per_cycle: 32,
                    ..Numerics::default()
                },
                ..FieldSettings::default()
            };
            let f = Field::compute(&p.motion(), &grid, kind, &s, &|| {});
            let fit = table1::fit(k, &f);
            println!(
                "{:12} {v} {:?} valid {}/{} max {:.4} fit {:?} r2 {:.4}",
                k.name(),
                kind,
                f.valid_count(),
                grid.len(),
                f.max_magnitude(),
                fit.coefficients,
                fit.r2
            );
        }
    }
}
