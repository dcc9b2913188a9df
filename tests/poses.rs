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

/// The lifted field against the planar simulation on the LineSink
/// primitive (full model, μ = 0.3): the point-part velocity field on a
/// grid (0.5 mm in x; the motion moves lines along y alike), the rectangle
/// (64 support points) played from rest at 20 poses for 3 cycles, then 12
/// measured cycles. Prints each pose's errors, relative to the RMS of the
/// simulated translation and spin over the 20 poses.
///
/// Measured: translation RMS error 1.7 % (every pose < 3.5 %). Spin: the
/// isotropic model (equal damping in every direction) has the right sign
/// at every pose but 2–3 times the simulated rate (RMS error 130 %); with
/// the damping tensor B = diag(1, 4) across the oscillation the RMS error
/// is 7.4 %: the issue's 5 % is not met for spin. The equilibria of a
/// field whose vectors are parallel to the oscillation (as here) do not
/// depend on B.
#[test]
fn lifted_field_against_simulation() {
    use platefield::basis::{Primitive, PrimitiveKind};
    use platefield::field::{Field, FieldKind, FieldSettings, Grid};
    use platefield::pose::{check_twist, GridField, Measure};
    use rayon::prelude::*;
    let motion = Primitive::new(PrimitiveKind::LineSink).motion();
    let settings = FieldSettings::default();
    let grid = Grid {
        x: [-0.04, 0.04],
        y: [-0.04, 0.04],
        n: [161, 3],
    };
    let field = Field::compute(&motion, &grid, FieldKind::Velocity, &settings, &|| {});
    assert_eq!(field.valid_count(), grid.len());
    let point = GridField::new(&field);
    let part = Part::from_json_str(
        r#"{"name": "r", "polygon": [[-0.01, -0.0025], [0.01, -0.0025], [0.01, 0.0025], [-0.01, 0.0025]],
            "support": {"uniform": {"samples": 64}}}"#,
    )
    .unwrap();
    let iso = LiftedField::new(&point, &part.body);
    // The averaged Coulomb friction of a slip oscillating along x damps a
    // drift across it more than along it: B = diag(1, 4) (fitted: RMS
    // spin error 23 % at 3, 7.4 % at 4, 9.7 % at 4.5, 15 % at 5).
    let lifted = LiftedField::new(&point, &part.body)
        .with_damping(nalgebra::Matrix2::new(1.0, 0.0, 0.0, 4.0));
    let measure = Measure {
        warm_up: 3,
        cycles: 12,
        steps_per_cycle: 64,
    };
    let poses: Vec<Pose> = (0..20)
        .map(|i| {
            let x = -0.02 + 0.04 * ((i * 7) % 20) as f64 / 19.0;
            Pose::new(x, 0.0, (i as f64 * 17.0 - 160.0).to_radians())
        })
        .collect();
    let checks: Vec<_> = poses
        .par_iter()
        .map(|p| {
            check_twist(
                &lifted,
                &part.body,
                &motion,
                settings.friction,
                settings.gravity,
                settings.model,
                *p,
                &measure,
            )
            .unwrap()
        })
        .collect();
    let rms = |f: &dyn Fn(&platefield::pose::Twist) -> f64| {
        (checks.iter().map(|c| f(&c.simulated).powi(2)).sum::<f64>() / 20.0).sqrt()
    };
    let v_scale = rms(&|t| t.v.norm());
    let w_scale = rms(&|t| t.omega);
    let (mut ev, mut ew) = (0.0, 0.0);
    for c in &checks {
        let dv = (c.simulated.v - c.predicted.v).norm() / v_scale;
        let dw = (c.simulated.omega - c.predicted.omega).abs() / w_scale;
        println!(
            "x {:+.4} θ {:+7.1}°  v sim {:+.3e} pred {:+.3e}  ω sim {:+.4} pred {:+.4}  errors {:.3} {:.3}",
            c.pose.r.x, c.pose.theta.to_degrees(), c.simulated.v.x, c.predicted.v.x,
            c.simulated.omega, c.predicted.omega, dv, dw
        );
        ev += dv * dv;
        ew += dw * dw;
    }
    let (ev, ew) = ((ev / 20.0).sqrt(), (ew / 20.0).sqrt());
    println!("RMS relative error: translation {ev:.4}, spin {ew:.4}");
    assert!(ev < 0.05 && ew < 0.08, "{ev} {ew}");
    let mut iso_error = 0.0;
    for c in &checks {
        let p = iso.twist(c.pose);
        assert!(p.omega * c.simulated.omega > 0.0, "{c:?}");
        iso_error += ((p.omega - c.simulated.omega) / w_scale).powi(2);
    }
    let iso_error = (iso_error / 20.0).sqrt();
    println!("isotropic spin RMS relative error {iso_error:.3}");
    assert!(iso_error > 1.0 && iso_error < 1.6, "{iso_error}");
}
