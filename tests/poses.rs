//! Equilibrium poses of planar parts (issue 28): the lifted field's zeros
//! and stability against closed forms, basins against the θ dynamics.

use std::path::Path;

use platefield::dynamics::V2;
use platefield::part::Part;
use platefield::pose::{equilibria, settle, wrap, LiftedField, Pose, Region};
use platefield::request::Target;

fn rectangle() -> Part {
    Part::load(Path::new("targets/parts/rectangle.json")).unwrap()
}

const REGION: Region = Region {
    x: [-0.03, 0.03],
    y: [-0.03, 0.03],
};

/// The elliptic sink −(0.3 x', y') in axes turned by `phi` (rad).
fn ellipse(phi: f64) -> impl Fn(V2) -> V2 + Sync {
    let (s, c) = phi.sin_cos();
    move |p: V2| {
        let (x, y) = (c * p.x + s * p.y, -s * p.x + c * p.y);
        let (vx, vy) = (-0.3 * x, -y);
        V2::new(c * vx - s * vy, s * vx + c * vy)
    }
}

/// Distance of angle `a` from `b` in degrees, modulo 360°.
fn off_deg(a: f64, b: f64) -> f64 {
    wrap(a - b).to_degrees().abs()
}

/// Rectangle in an elliptic sink (−0.3x, −y), the ellipse turned by
/// 0°, 30°, 75° and −50°: stable at φ and φ + 180° (long side along the
/// weaker contraction), unstable at φ ± 90°, at the centre. The closed form
/// (module docs of pose::lifted): in a linear field ω depends on θ alone,
/// ω = −(1 − 0.3)/2 · (I_xx − I_yy)/I · sin 2(θ − φ).
#[test]
fn rectangle_in_an_elliptic_sink() {
    let part = rectangle();
    for phi_deg in [0.0f64, 30.0, 75.0, -50.0] {
        let phi = phi_deg.to_radians();
        let field = ellipse(phi);
        let lifted = LiftedField::new(&field, &part.body);
        let eq = equilibria(&lifted, &REGION);
        assert_eq!(eq.len(), 4, "φ = {phi_deg}: {eq:?}");
        for e in &eq {
            assert!(e.pose.r.norm() < 1e-9, "{e:?}");
            let to_axis =
                off_deg(e.pose.theta, phi).min(off_deg(e.pose.theta, phi + std::f64::consts::PI));
            let to_normal = off_deg(e.pose.theta, phi + std::f64::consts::FRAC_PI_2)
                .min(off_deg(e.pose.theta, phi - std::f64::consts::FRAC_PI_2));
            if e.stable {
                assert!(
                    to_axis < 1.0,
                    "φ = {phi_deg}: stable at {}",
                    e.pose.theta.to_degrees()
                );
            } else {
                assert!(
                    to_normal < 1.0,
                    "φ = {phi_deg}: unstable at {}",
                    e.pose.theta.to_degrees()
                );
            }
        }
        assert_eq!(eq.iter().filter(|e| e.stable).count(), 2);
        // The spin rate's closed form at 45° from the axis.
        let ixx: f64 = part.body.points().iter().map(|p| p.x * p.x).sum();
        let iyy: f64 = part.body.points().iter().map(|p| p.y * p.y).sum();
        let t = lifted.twist(Pose::new(0.004, -0.002, phi + std::f64::consts::FRAC_PI_4));
        let want = -0.35 * (ixx - iyy) / (ixx + iyy);
        assert!((t.omega - want).abs() < 1e-12, "{} vs {want}", t.omega);
    }
}

/// Basins: in a linear field θ evolves alone (previous test), so a drop
/// settles at φ exactly when it starts within 90° of φ, else at φ + 180°.
/// 200 drops integrated along the lifted field: every drop ends at the
/// stable pose its start angle predicts, and each basin holds 50 % ± 10
/// points (binomial, 200 drops: σ = 3.5 points).
#[test]
fn basins_follow_the_start_angle() {
    let part = rectangle();
    let phi = 30f64.to_radians();
    let field = ellipse(phi);
    let lifted = LiftedField::new(&field, &part.body);
    let eq = equilibria(&lifted, &REGION);
    let stable: Vec<_> = eq.iter().copied().filter(|e| e.stable).collect();
    let mut seed = 7u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut counts = [0usize; 2];
    for _ in 0..200 {
        let start = Pose {
            r: REGION.at(0.2 + 0.6 * next(), 0.2 + 0.6 * next()),
            theta: wrap(std::f64::consts::TAU * next()),
        };
        let k = settle(&lifted, start, &stable, &REGION).expect("settles");
        let want = if off_deg(start.theta, phi) < 90.0 {
            phi
        } else {
            phi + std::f64::consts::PI
        };
        assert!(
            off_deg(stable[k].pose.theta, want) < 1e-3,
            "{start:?} → {:?}",
            stable[k]
        );
        counts[k] += 1;
    }
    assert!(
        counts.iter().all(|&c| (80..=120).contains(&c)),
        "{counts:?}"
    );
}

/// The same rectangle in a target's elliptic sink, the sum of two line
/// sinks (rates 1 across the line at 20°, 0.3 across the line at 110°):
/// the target's requested field as the point field.
#[test]
fn rectangle_in_a_target_ellipse() {
    let target = Target::from_json_str(
        r#"{"name": "ellipse", "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 21]},
            "field": {"kind": "sum", "terms": [
              {"field": {"kind": "line_sink", "angle": 20, "strength": 1}},
              {"field": {"kind": "line_sink", "angle": 110, "strength": 0.3}}]}}"#,
    )
    .unwrap();
    let part = rectangle();
    let lifted = LiftedField::new(&target.field, &part.body);
    let eq = equilibria(&lifted, &REGION);
    let stable: Vec<f64> = eq
        .iter()
        .filter(|e| e.stable)
        .map(|e| e.pose.theta)
        .collect();
    assert_eq!((eq.len(), stable.len()), (4, 2), "{eq:?}");
    for t in stable {
        assert!(off_deg(t, 20f64.to_radians()).min(off_deg(t, 200f64.to_radians())) < 1.0);
    }
}
