//! Issue 28, route A: rotation about the vertical mixed with the in-plane
//! translation in one motion (exploration; numbers in docs/parts.md).

use nalgebra::{Matrix3, Vector3};
use platefield::dynamics::V2;
use platefield::field::{Field, FieldKind, FieldSettings, Grid};
use platefield::motion::{Axes, FourierTerm, Motion, Signals};
use platefield::part::Part;
use platefield::pose::{equilibria, GridField, LiftedField, Region};

const GRID: Grid = Grid {
    x: [-0.04, 0.04],
    y: [-0.04, 0.04],
    n: [17, 17],
};

fn term(amplitude: f64, phase: f64, harmonic: u32) -> FourierTerm {
    FourierTerm {
        amplitude,
        phase,
        harmonic,
    }
}

/// The shipped sink's synthesized motion (results/sink/schedule.json) with a
/// rotation about z of amplitude `alpha` (rad/s²) and phase `phase`.
fn sink_with_spin(alpha: f64, phase: f64, scale: f64) -> Motion {
    Motion::Signals(Signals {
        period: 0.030_063_087_594_160_7,
        linear: Axes {
            x: vec![term(10.918 * scale, 1.570_796, 1), term(0.108, 0.0, 2)],
            y: vec![term(10.920 * scale, 0.0, 1)],
            z: Vec::new(),
        },
        angular: Axes {
            x: vec![term(154.98, 2.038_837_8, 1)],
            y: vec![term(154.98, 0.468_041_5, 1)],
            z: vec![term(alpha, phase, 1)],
        },
    })
}

fn points() -> Vec<V2> {
    let at = |r: [f64; 2], n: usize, k: usize| r[0] + (r[1] - r[0]) * k as f64 / (n - 1) as f64;
    (0..GRID.n[1])
        .flat_map(|j| {
            (0..GRID.n[0]).map(move |i| V2::new(at(GRID.x, GRID.n[0], i), at(GRID.y, GRID.n[1], j)))
        })
        .collect()
}

fn affine_residual(field: &Field) -> f64 {
    let ps = points();
    let rows: Vec<Vector3<f64>> = ps.iter().map(|p| Vector3::new(1.0, p.x, p.y)).collect();
    let normal: Matrix3<f64> = rows.iter().map(|r| r * r.transpose()).sum();
    let inv = normal.try_inverse().expect("a 2-D grid");
    let mut worst: f64 = 0.0;
    for c in 0..2 {
        let rhs: Vector3<f64> = rows.iter().zip(&field.vectors).map(|(r, v)| r * v[c]).sum();
        let coef = inv * rhs;
        for (r, v) in rows.iter().zip(&field.vectors) {
            worst = worst.max((v[c] - coef.dot(r)).abs());
        }
    }
    worst / field.max_magnitude()
}

#[test]
#[ignore = "exploration: PF_SPIN=alpha,phase,scale;..."]
fn explore_spin() {
    let spec = std::env::var("PF_SPIN").unwrap_or("0,0,1".into());
    let bracket = Part::load(std::path::Path::new("targets/parts/bracket.json")).unwrap();
    let triangle = Part::load(std::path::Path::new("targets/parts/triangle.json")).unwrap();
    let region = Region {
        x: [-0.025, 0.025],
        y: [-0.025, 0.025],
    };
    for item in spec.split(';') {
        let v: Vec<f64> = item.split(',').map(|s| s.parse().unwrap()).collect();
        let motion = sink_with_spin(v[0], v[1], v[2]);
        let f = Field::compute(&motion, &GRID, FieldKind::Velocity, &FieldSettings::default(), &|| {});
        let valid = f.valid_count();
        let res = affine_residual(&f);
        let g = GridField::new(&f);
        eprintln!("spin {item}: valid {valid}/{}, affine residual {res:.3}, top {:.4} m/s", GRID.len(), f.max_magnitude());
        for (name, part) in [("bracket", &bracket), ("triangle", &triangle)] {
            let eqs = equilibria(&LiftedField::new(&g, &part.body), &region);
            for e in eqs.iter().filter(|e| e.stable) {
                eprintln!(
                    "  {name} stable ({:.2}, {:.2}) mm {:.1}° rates {:?}",
                    1e3 * e.pose.r.x,
                    1e3 * e.pose.r.y,
                    e.pose.theta.to_degrees(),
                    e.rates
                );
            }
        }
        if std::env::var("PF_DUMP").is_ok() {
            for (p, v) in points().iter().zip(&f.vectors) {
                eprintln!("    {:.3} {:.3} {:.5} {:.5}", p.x, p.y, v[0], v[1]);
            }
        }
    }
}

/// The centred elliptic motion `design` synthesizes for the bracket, with a
/// spin added: PF_SPIN=alpha,phase;...
#[test]
#[ignore = "exploration"]
fn explore_spin_on_ellipse() {
    use platefield::design::pose::{placement, PoseRequest};
    let req = PoseRequest::load(std::path::Path::new("targets/pose_bracket.json"))
        .unwrap()
        .unwrap();
    let opts = platefield::design::DesignOptions::default();
    let method = placement::synthesize_centred(&req, &opts, &opts.synthesis).unwrap();
    let schedule = method.kept().schedule.clone();
    let motion = schedule.segments[0].motion.clone().unwrap();
    eprintln!("{}", serde_json::to_string(&motion).unwrap());
    let triangle = Part::load(std::path::Path::new("targets/parts/triangle.json")).unwrap();
    let spec = std::env::var("PF_SPIN").unwrap_or("0,0".into());
    for item in spec.split(';') {
        let v: Vec<f64> = item.split(',').map(|s| s.parse().unwrap()).collect();
        let mut s = motion.clone();
        s.angular.z = vec![term(v[0], v[1], 1)];
        let k = v.get(2).copied().unwrap_or(1.0);
        for t in s.linear.x.iter_mut().chain(s.linear.y.iter_mut()) {
            t.amplitude *= k;
        }
        let f = Field::compute(&Motion::Signals(s), &GRID, FieldKind::Velocity, &FieldSettings::default(), &|| {});
        let g = GridField::new(&f);
        eprintln!("spin {item}: valid {}/{}, affine residual {:.3}, top {:.4}", f.valid_count(), GRID.len(), affine_residual(&f), f.max_magnitude());
        for (name, part) in [("bracket", &req.part), ("triangle", &triangle)] {
            let eqs = equilibria(&LiftedField::new(&g, &part.body), &req.region);
            for e in eqs.iter().filter(|e| e.stable) {
                eprintln!("  {name} stable ({:.2}, {:.2}) mm {:.1}° rates {:?}", 1e3 * e.pose.r.x, 1e3 * e.pose.r.y, e.pose.theta.to_degrees(), e.rates);
            }
        }
    }
}
