use platefield::basis::{Primitive, PrimitiveKind};
use platefield::dynamics::{Model, Numerics};
use platefield::field::{Field, FieldKind, FieldSettings, Grid, Validity};
use platefield::motion::{Motion, Waveform};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let k = PrimitiveKind::from_name(&args[1], "x").unwrap();
    let kind = if args[2] == "f" {
        FieldKind::Force
    } else {
        FieldKind::Velocity
    };
    let mut p = Primitive::new(k);
    if args.len() > 3 {
        p.translation = Some(args[3].parse().unwrap());
    }
    if args.len() > 4 {
        p.amplitude = Some(args[4].parse().unwrap());
    }
    let mut m = p.motion();
    if args.len() > 5 {
        if let Motion::Screw(s) = &mut m {
            s.translation = match args[5].as_str() {
                "sine" => Waveform::Fourier {
                    terms: vec![platefield::motion::FourierTerm {
                        amplitude: p.translation.unwrap() * 209.0 * 209.0,
                        phase: args[6].parse().unwrap(),
                        harmonic: 1,
                    }],
                    offset: 0.0,
                },
                _ => s.translation.clone(),
            };
        }
    }
    let grid = Grid {
        x: [-0.04, 0.04],
        y: [-0.04, 0.04],
        n: [5, 5],
    };
    let s = FieldSettings {
        model: Model::FULL,
        numerics: Numerics {
            steps_per_cycle: 32,
            ..Numerics::default()
        },
        ..FieldSettings::default()
    };
    let f = Field::compute(&m, &grid, kind, &s, &|| {});
    for (i, pt) in grid.points().iter().enumerate() {
        if i % 5 == 0 {
            println!();
        }
        let v = f.vectors[i];
        let tag = match f.validity[i] {
            Validity::Ok => "",
            Validity::ContactLost => "C",
            Validity::NotConverged => "N",
            Validity::FrozenInvalid => "F",
        };
        print!(
            "({:+.1},{:+.1}):{:+.4},{:+.4}{tag}  ",
            pt[0] * 100.,
            pt[1] * 100.,
            v[0],
            v[1]
        );
    }
    println!();
}
