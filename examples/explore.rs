use platefield::basis::{table1, Primitive, PrimitiveKind};
use platefield::dynamics::{Model, Numerics};
use platefield::field::{Field, FieldKind, FieldSettings, Grid};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let kinds: Vec<PrimitiveKind> = if args.len() > 1 {
        args[1..]
            .iter()
            .map(|a| PrimitiveKind::from_name(a, "x").unwrap())
            .collect()
    } else {
        PrimitiveKind::ALL.to_vec()
    };
    let grid = Grid {
        x: [-0.04, 0.04],
        y: [-0.04, 0.04],
        n: [9, 9],
    };
    for k in kinds {
        let p = Primitive::new(k);
        for kind in [FieldKind::Force, FieldKind::Velocity] {
            let s = FieldSettings {
                model: Model::FULL,
                numerics: Numerics {
                    steps_per_cycle: 32,
                    ..Numerics::default()
                },
                ..FieldSettings::default()
            };
            let t = std::time::Instant::now();
            let f = Field::compute(&p.motion(), &grid, kind, &s, &|| {});
            let fit = table1::fit(k, &f);
            println!(
                "{:12} {:?} valid {}/{} max {:.4} fit {:?} r2 {:.4} ({:.2}s)",
                k.name(),
                kind,
                f.valid_count(),
                grid.len(),
                f.max_magnitude(),
                fit.coefficients,
                fit.r2,
                t.elapsed().as_secs_f64()
            );
        }
    }
}
