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

/// The lifted and the averaged fields against the planar simulation on
/// the LineSink primitive (full model, μ = 0.3): the point-part velocity
/// field on a grid (0.5 mm in x; the motion moves lines along y alike),
/// the rectangle (64 support points) played from rest at 20 poses for 10
/// cycles, then 24 measured cycles (the part moving). Prints each pose's
/// twists; errors are relative to the RMS of the simulated translation
/// and spin over the 20 poses.
///
/// Measured: the averaged field (the rigid part's periodic slip at the
/// window's mean pose, frozen) agrees within 2.3 % RMS in translation (the
/// window's spread of pose: the part drifts up to 7 mm in it) and 0.1 % in
/// spin. The lifted field (point field integrated over the support):
/// translation 0.6 %; spin with the right sign at every pose but 2.3 times
/// the rate (RMS error 129 %), and 7.6 % with the fitted damping tensor
/// B = diag(1, 4) across the oscillation. The equilibria of a field whose
/// vectors are parallel to the oscillation (as here) do not depend on B.
#[test]
fn lifted_field_against_simulation() {
    use platefield::basis::{Primitive, PrimitiveKind};
    use platefield::field::{Field, FieldKind, FieldSettings, Grid};
    use platefield::pose::{check_twist, AveragedField, GridField, LiftCheck, Measure, Twist};
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
    // spin error 23 % at 3, 7.4 % at 4, 9.7 % at 4.5, 15 % at 5, over 3 warm-up
    // cycles; 7.6 % at 4 over the 10 here).
    let damped = LiftedField::new(&point, &part.body)
        .with_damping(nalgebra::Matrix2::new(1.0, 0.0, 0.0, 4.0));
    let averaged = AveragedField::new(&part.body, &motion, settings.physics()).unwrap();
    let measure = Measure {
        warm_up: 10,
        cycles: 24,
        steps_per_cycle: 64,
    };
    let starts: Vec<Pose> = (0..20)
        .map(|i| {
            let x = -0.02 + 0.04 * ((i * 7) % 20) as f64 / 19.0;
            Pose::new(x, 0.0, (i as f64 * 17.0 - 160.0).to_radians())
        })
        .collect();
    let checks: Vec<_> = starts
        .par_iter()
        .map(|p| check_twist(&iso, &part.body, &motion, settings.physics(), *p, &measure).unwrap())
        .collect();
    let poses: Vec<Pose> = checks.iter().map(|c| c.pose).collect();
    let simulated: Vec<Twist> = checks.iter().map(|c| c.simulated).collect();
    // Relative RMS errors of `model` against the simulation.
    let errors = |model: &dyn Fn(Pose) -> Twist| {
        let scale = |f: &dyn Fn(&Twist) -> f64| {
            (simulated.iter().map(|t| f(t).powi(2)).sum::<f64>() / 20.0).sqrt()
        };
        let (sv, sw) = (scale(&|t| t.v.norm()), scale(&|t| t.omega));
        let (mut ev, mut ew) = (0.0, 0.0);
        for (p, s) in poses.iter().zip(&simulated) {
            let m = model(*p);
            assert!(m.omega * s.omega > 0.0, "spin sign at {p:?}: {m:?} {s:?}");
            ev += ((s.v - m.v).norm() / sv).powi(2);
            ew += ((s.omega - m.omega) / sw).powi(2);
        }
        ((ev / 20.0).sqrt(), (ew / 20.0).sqrt())
    };
    for (p, s) in poses.iter().zip(&simulated) {
        let a = averaged.twist(*p).unwrap();
        assert!(a.converged, "{p:?}");
        println!(
            "x {:+.4} θ {:+7.1}°  v sim {:+.3e} averaged {:+.3e} lifted {:+.3e}  ω sim {:+.4} averaged {:+.4} lifted {:+.4}",
            p.r.x, p.theta.to_degrees(), s.v.x, a.twist.v.x, iso.twist(*p).v.x,
            s.omega, a.twist.omega, iso.twist(*p).omega
        );
    }
    let a = errors(&|p| averaged.twist(p).unwrap().twist);
    let l = errors(&|p| iso.twist(p));
    let d = errors(&|p| damped.twist(p));
    println!("RMS relative errors (translation, spin): averaged {a:.4?}, lifted {l:.4?}, lifted with B {d:.4?}");
    assert!(a.0 < 0.05 && a.1 < 0.05, "averaged field {a:?}");
    assert!(l.0 < 0.03 && l.1 > 1.0 && l.1 < 1.6, "lifted field {l:?}");
    assert!(d.0 < 0.03 && d.1 < 0.08, "lifted field with B {d:?}");
    // The check `poses` prints: the lifted field against the averaged one.
    let check = LiftCheck::run(&iso, &averaged, &poses);
    let (ct, cs) = (check.translation_rms.unwrap(), check.spin_rms.unwrap());
    assert!(ct < 0.05 && cs > 1.0 && cs < 1.6, "{ct} {cs}");
}

/// The designed schedule of `target` (results/<target>/schedule.json, by
/// `design targets/<target>.json --method sequence`), its point field
/// (time-weighted segment fields) and region.
fn designed(
    target: &str,
) -> (
    platefield::schedule::Schedule,
    platefield::pose::GridField,
    Region,
) {
    let s =
        platefield::schedule::Schedule::load(Path::new(&format!("results/{target}/schedule.json")))
            .unwrap();
    let grid = s.target_spec.as_ref().and_then(|t| t.grid).unwrap();
    let field = platefield::pose::schedule_field(&s, &grid).unwrap();
    let region = Region {
        x: grid.x,
        y: grid.y,
    };
    (s, field, region)
}

/// The drops of `analysis` played by the planar simulator for `seconds`
/// through `schedule` (`part`, the defaults of `DropPlay::new`).
fn played(
    analysis: &platefield::pose::PoseAnalysis,
    part: &Part,
    schedule: &platefield::schedule::Schedule,
    seconds: f64,
) -> platefield::pose::PlayedBasins {
    let sm = platefield::play::ScheduleMotion::from_schedule(schedule).unwrap();
    let play = platefield::pose::DropPlay::new(&schedule.settings, seconds);
    platefield::pose::played_basins(analysis, part, &sm, &play)
}

/// Cost of played drops (run with `--ignored --nocapture`): DROPS drops
/// (default 100) of the shipped rectangle for 20 s on the designed ellipse
/// with the defaults (`DropPlay::new`); the process's CPU time (user +
/// sys) and the wall time on the threads rayon has.
#[test]
#[ignore]
fn drop_cost_report() {
    let n: usize = std::env::var("DROPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(100);
    let cpu = || {
        // SAFETY: a valid out-pointer to an rusage.
        let mut u: libc::rusage = unsafe { std::mem::zeroed() };
        unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) };
        let t = |v: libc::timeval| v.tv_sec as f64 + 1e-6 * v.tv_usec as f64;
        t(u.ru_utime) + t(u.ru_stime)
    };
    let (schedule, field, region) = designed("ellipse");
    let part = rectangle();
    let a = platefield::pose::analyse(&part, &field, region, n);
    let (c, t) = (cpu(), std::time::Instant::now());
    let p = played(&a, &part, &schedule, 20.0);
    let (cpu_s, wall) = (cpu() - c, t.elapsed().as_secs_f64());
    println!(
        "{n} drops × {:.2} s simulated: {cpu_s:.1} s CPU, {wall:.1} s wall on {} threads; {:.0} steps per drop; agreement {:.3}, lost {}",
        p.time,
        rayon::current_num_threads(),
        p.steps as f64 / n as f64,
        p.agreement,
        p.lost
    );
}

/// Stable and unstable poses of the rectangle on the DESIGNED ellipses
/// (−0.3x, −y) and the same turned by 30° (schedules of line sinks and
/// skew sinks; point field: the time-weighted segment fields): stable
/// with the long side along the weaker contraction (φ, φ + 180°),
/// unstable across it (φ ± 90°), within 1°, near the centre.
#[test]
fn rectangle_on_the_designed_ellipses() {
    let part = rectangle();
    for (target, phi_deg) in [("ellipse", 0.0f64), ("ellipse_30", 30.0)] {
        let (_, field, region) = designed(target);
        let a = platefield::pose::analyse(&part, &field, region, 200);
        let phi = phi_deg.to_radians();
        let half = std::f64::consts::FRAC_PI_2;
        for e in &a.equilibria {
            println!(
                "{target}: x {:+.3} mm y {:+.3} mm θ {:+8.3}° stable {}",
                1e3 * e.pose.r.x,
                1e3 * e.pose.r.y,
                e.pose.theta.to_degrees(),
                e.stable
            );
        }
        let near = |want: f64| {
            a.equilibria
                .iter()
                .filter(|e| e.pose.r.norm() < 0.003)
                .map(|e| (e.stable, off_deg(e.pose.theta, want)))
                .min_by(|x, y| x.1.total_cmp(&y.1))
                .unwrap()
        };
        for (want, stable) in [
            (phi, true),
            (phi + 2.0 * half, true),
            (phi + half, false),
            (phi - half, false),
        ] {
            let (s, off) = near(want);
            assert!(
                s == stable && off < 1.0,
                "{target}: {} {off}° {s}",
                want.to_degrees()
            );
        }
        assert_eq!(a.equilibria.iter().filter(|e| e.stable).count(), 2);
        assert!(a.unsettled == 0.0, "{}", a.unsettled);
    }
}

/// A few drops played by the planar simulator (the rectangle, 10 s on the
/// designed ellipse, the drop defaults) end at the stable pose the lifted field predicts
/// for each; the 200-drop comparison is `played_basins_match_prediction`.
#[test]
fn played_drops_end_where_predicted() {
    let part = Part::from_json_str(
        r#"{"name": "r", "polygon": [[-0.01, -0.0025], [0.01, -0.0025], [0.01, 0.0025], [-0.01, 0.0025]],
            "support": {"uniform": {"samples": 64}}}"#,
    )
    .unwrap();
    let (schedule, field, region) = designed("ellipse");
    let a = platefield::pose::analyse(&part, &field, region, 4);
    let p = played(&a, &part, &schedule, 10.0);
    assert_eq!(p.lost, 0);
    assert_eq!(p.ends, a.ends, "played {:?} predicted {:?}", p.ends, a.ends);
}

/// Issue 28: basins of ≥ 200 drops played by the planar simulator (the
/// rectangle, 20 s each, the drop defaults of `DropPlay::new`) on the
/// designed ellipse and on it turned by 30°, against the lifted field's
/// prediction from the same starts: every basin within 5 percentage
/// points. Measured (ellipse_30): predicted 52.0/48.0 %, played 53.5/46.5 %,
/// per-drop agreement 91.5 %, none lost; (ellipse) predicted and played
/// 49.5/50.5 %, per-drop agreement 100 %, none lost. 20 min for both on a
/// heavily loaded 2-core machine:
/// `cargo test --release --test poses played_basins_match_prediction -- --ignored --nocapture`.
#[test]
#[ignore]
fn played_basins_match_prediction() {
    let part = Part::from_json_str(
        r#"{"name": "r", "polygon": [[-0.01, -0.0025], [0.01, -0.0025], [0.01, 0.0025], [-0.01, 0.0025]],
            "support": {"uniform": {"samples": 64}}}"#,
    )
    .unwrap();
    for target in ["ellipse_30", "ellipse"] {
        let (schedule, field, region) = designed(target);
        let a = platefield::pose::analyse(&part, &field, region, 200);
        let p = played(&a, &part, &schedule, 20.0);
        println!(
            "{target}: predicted {:?} played {:?}; per-drop agreement {:.3}, worst end distance {:.3}, lost {}, unsettled (predicted) {:.3}",
            a.basins, p.basins, p.agreement, p.worst, p.lost, a.unsettled
        );
        assert_eq!(p.lost, 0);
        for (x, y) in a.basins.iter().zip(&p.basins) {
            assert!(
                (x - y).abs() <= 0.05,
                "{target}: {:?} vs {:?}",
                a.basins,
                p.basins
            );
        }
    }
}

/// Convergence order of the planar scheme on a drop (run with `--ignored
/// --nocapture`): the rectangle (SAMPLES support points, default 16) from
/// (1 cm, −0.5 cm, 40°) for 3 s on the designed ellipse at 16…1024 steps
/// per cycle, refinement depth 0, 3 and 10, against 4096 steps per cycle
/// (depth 10): error |q_h − q_ref| on the end pose (x, y, R θ) and the
/// observed order log2(e_h / e_h/2).
#[test]
#[ignore]
fn drop_order_report() {
    use rayon::prelude::*;
    let samples: usize = std::env::var("SAMPLES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(16);
    let part = rectangle_with(samples);
    let (schedule, _, _) = designed("ellipse");
    let sm = platefield::play::ScheduleMotion::from_schedule(&schedule).unwrap();
    let start = Pose::new(0.01, -0.005, 40f64.to_radians());
    let r = part.radius();
    let spcs = [16usize, 32, 64, 128, 256, 512, 1024];
    let mut runs = vec![(4096usize, 10u32)];
    for depth in [0u32, 3, 10] {
        runs.extend(spcs.iter().map(|&spc| (spc, depth)));
    }
    let ends: Vec<platefield::pose::DropEnd> = runs
        .par_iter()
        .map(|&(spc, depth)| {
            let mut play = platefield::pose::DropPlay::new(&schedule.settings, 3.0);
            play.steps_per_cycle = spc;
            play.refine_depth = depth;
            platefield::pose::play_drop(&sm, &part.body, start, &play).unwrap()
        })
        .collect();
    let diff = |a: &platefield::pose::DropEnd, b: &platefield::pose::DropEnd| {
        ((a.pose.r - b.pose.r).norm_squared() + (r * (a.pose.theta - b.pose.theta)).powi(2)).sqrt()
    };
    let mut last: Option<f64> = None;
    for (&(spc, depth), end) in runs.iter().zip(&ends).skip(1) {
        let e = diff(end, &ends[0]);
        let order = last.filter(|_| spc > spcs[0]).map(|l| (l / e).log2());
        println!(
            "{samples} points, depth {depth:2}, {spc:4} steps/cycle: error {e:.3e} m, order {}, {:.0} steps per cycle",
            order.map_or("-".to_string(), |o| format!("{o:.2}")),
            end.steps as f64 / (end.time / 0.030)
        );
        last = Some(e);
    }
}

/// Issue 28, unknown support: the bound (poses that may rest for some
/// support, `pose::Bounds`) of the bracket with 3 unknown contacts on the
/// designed ellipse contains every equilibrium of 20 random admissible
/// supports (3 points uniform in the part, weights uniform in [0.1, 1]),
/// found by the lifted field of each; and it is a bound, not everything:
/// of a 12 × 12 × 12 scan of the region it keeps a minority, none with the
/// part off the field's zero.
#[test]
fn unknown_support_bounds_contain_random_supports() {
    use platefield::dynamics::PlanarBody;
    use platefield::pose::Bounds;
    let part = Part::from_json_str(
        r#"{"name": "bracket", "polygon": [[0, 0], [0.03, 0], [0.03, 0.005], [0.005, 0.005], [0.005, 0.02], [0, 0.02]],
            "support": {"unknown": {"contacts": 3}}}"#,
    )
    .unwrap();
    let (_, field, region) = designed("ellipse");
    let bounds = Bounds::new(&part, &field);
    let mut seed = 2028u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let lo = part
        .polygon
        .iter()
        .fold(V2::repeat(f64::INFINITY), |m, p| m.inf(p));
    let hi = part
        .polygon
        .iter()
        .fold(V2::repeat(f64::NEG_INFINITY), |m, p| m.sup(p));
    let mut found = 0;
    for _ in 0..20 {
        let mut pts = Vec::new();
        while pts.len() < 3 {
            let p = V2::new(lo.x + (hi.x - lo.x) * next(), lo.y + (hi.y - lo.y) * next());
            if platefield::part::contains(&part.polygon, &p) {
                pts.push(p);
            }
        }
        let weights: Vec<f64> = (0..3).map(|_| 0.1 + 0.9 * next()).collect();
        let (body, c) = PlanarBody::centred(&pts, &weights);
        let lifted = LiftedField::new(&field, &body);
        for e in equilibria(&lifted, &region) {
            let (s, co) = e.pose.theta.sin_cos();
            let pose = Pose {
                r: e.pose.r - V2::new(co * c.x - s * c.y, s * c.x + co * c.y),
                theta: e.pose.theta,
            };
            assert!(bounds.may_rest(pose), "{pts:?} {weights:?}: {e:?}");
            found += 1;
        }
    }
    assert!(found >= 20, "{found} equilibria");
    let kept = bounds.scan(&region, [12, 12, 12]);
    let far = kept
        .iter()
        .filter(|p| p.r.norm() > part.radius() + 0.004)
        .count();
    println!(
        "{found} equilibria of 20 supports, all inside; bound keeps {} of 1728 scanned poses, {far} with the centre beyond R + 4 mm",
        kept.len()
    );
    assert!(kept.len() < 1728 / 2 && !kept.is_empty() && far == 0);
}

/// CPU seconds of the calling thread.
fn thread_cpu() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: a valid out-pointer to a timespec.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
    t.tv_sec as f64 + 1e-9 * t.tv_nsec as f64
}

/// The 2 × 0.5 cm rectangle with `samples` uniform support points.
fn rectangle_with(samples: usize) -> Part {
    Part::from_json_str(&format!(
        r#"{{"name": "r", "polygon": [[-0.01, -0.0025], [0.01, -0.0025], [0.01, 0.0025], [-0.01, 0.0025]],
            "support": {{"uniform": {{"samples": {samples}}}}}}}"#
    ))
    .unwrap()
}

/// Speed and accuracy of one played drop (run with `--ignored --nocapture`):
/// the rectangle from (1 cm, −0.5 cm, 40°) for SECONDS (default 20) on the
/// designed ellipse, by support samples, steps per cycle and refinement
/// depth; CPU time of the drop's thread and its end pose against the same
/// support at 256 steps per cycle (depth 10) and against 256 support points.
#[test]
#[ignore]
fn drop_speed_report() {
    use rayon::prelude::*;
    let seconds: f64 = std::env::var("SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20.0);
    let (schedule, field, region) = designed("ellipse");
    let sm = platefield::play::ScheduleMotion::from_schedule(&schedule).unwrap();
    let start = Pose::new(0.01, -0.005, 40f64.to_radians());
    let mut runs = vec![(256usize, 256usize, 10u32), (256, 64, 10)];
    for samples in [16usize, 36, 64] {
        runs.push((samples, 256, 10));
        for spc in [32usize, 64] {
            for depth in [0u32, 3, 10] {
                runs.push((samples, spc, depth));
            }
        }
    }
    let ends: Vec<_> = runs
        .par_iter()
        .map(|&(samples, spc, depth)| {
            let part = rectangle_with(samples);
            let mut play = platefield::pose::DropPlay::new(&schedule.settings, seconds);
            play.steps_per_cycle = spc;
            play.refine_depth = depth;
            let t = thread_cpu();
            let end = platefield::pose::play_drop(&sm, &part.body, start, &play).unwrap();
            (end, thread_cpu() - t)
        })
        .collect();
    let reference = |samples: usize| {
        let i = runs.iter().position(|r| *r == (samples, 256, 10)).unwrap();
        ends[i].0.pose
    };
    let off = |a: &Pose, b: &Pose| {
        (
            1e3 * (a.r - b.r).norm(),
            wrap(a.theta - b.theta).to_degrees().abs(),
        )
    };
    for (&(samples, spc, depth), (end, cpu)) in runs.iter().zip(&ends) {
        let cycles = end.time / 0.030;
        let (dr, dt) = off(&end.pose, &reference(samples));
        let (sr, st) = off(&end.pose, &reference(256));
        println!(
            "samples {samples:3} spc {spc:3} depth {depth:2}: {cpu:6.2} s CPU, {:5.1} steps/cycle, {:5.1} halvings/cycle, {:4.1} Newton/step; end ({:+.3}, {:+.3}) mm {:+.2}°; vs fine steps {dr:.3} mm {dt:.3}°, vs 256 points {sr:.3} mm {st:.3}°",
            end.steps as f64 / cycles,
            end.refinements as f64 / cycles,
            end.solver_iterations as f64 / end.steps as f64,
            1e3 * end.pose.r.x,
            1e3 * end.pose.r.y,
            end.pose.theta.to_degrees(),
        );
    }
    for samples in [16usize, 36, 64, 256] {
        let a = platefield::pose::analyse(&rectangle_with(samples), &field, region, 0);
        for e in a.equilibria.iter().filter(|e| e.stable) {
            println!(
                "lifted field, {samples} points: stable ({:+.4}, {:+.4}) mm {:+.3}°",
                1e3 * e.pose.r.x,
                1e3 * e.pose.r.y,
                e.pose.theta.to_degrees()
            );
        }
    }
}

/// The rectangle with 16 support points dropped at (1 cm, −0.5 cm, 40°)
/// and played 3 s on the designed ellipse, once per run (steps per cycle,
/// refinement depth, slip rule), in parallel; and the part's radius.
fn ellipse_drops(
    runs: &[(usize, u32, platefield::dynamics::SlipRule)],
) -> (Vec<platefield::pose::DropEnd>, f64) {
    use rayon::prelude::*;
    let part = rectangle_with(16);
    let (schedule, _, _) = designed("ellipse");
    let sm = platefield::play::ScheduleMotion::from_schedule(&schedule).unwrap();
    let start = Pose::new(0.01, -0.005, 40f64.to_radians());
    let ends = runs
        .par_iter()
        .map(|&(spc, depth, rule)| {
            let mut play = platefield::pose::DropPlay::new(&schedule.settings, 3.0);
            play.steps_per_cycle = spc;
            play.refine_depth = depth;
            play.slip_rule = rule;
            platefield::pose::play_drop(&sm, &part.body, start, &play).unwrap()
        })
        .collect();
    (ends, part.radius())
}

/// The planar scheme's order on a played drop dominated by stick-slip
/// events, measured: the rectangle (16 support points) from (1 cm, −0.5 cm,
/// 40°) for 3 s on the designed ellipse at 16…1024 steps per cycle without
/// event refinement, against 4096 steps per cycle with refinement depth 10.
/// The least-squares slope of log error against log step is the order:
/// first order (measured 1.1; single halvings scatter, the erratic
/// event-timing error), as the midpoint corrector leaves the steps that
/// hold an event to the Moreau–Jean step (the backward rule gives the same
/// to 10 %, `planar_order_report`; between events the scheme is second
/// order, `tests/planar.rs` `circular_slip_is_second_order_between_events`).
/// PlayedRest depth 10 at 64 steps per cycle cuts the error about 40-fold
/// (0.30 mm → 8 µm).
#[test]
fn planar_scheme_is_first_order_at_events() {
    use platefield::dynamics::SlipRule;
    let spcs = [16usize, 32, 64, 128, 256, 512, 1024];
    let mut runs = vec![
        (4096usize, 10u32, SlipRule::Midpoint),
        (64, 10, SlipRule::Midpoint),
    ];
    runs.extend(spcs.iter().map(|&spc| (spc, 0, SlipRule::Midpoint)));
    let (ends, r) = ellipse_drops(&runs);
    let ends: Vec<Pose> = ends.iter().map(|e| e.pose).collect();
    let error = |p: &Pose| {
        ((p.r - ends[0].r).norm_squared() + (r * (p.theta - ends[0].theta)).powi(2)).sqrt()
    };
    let points: Vec<(f64, f64)> = spcs
        .iter()
        .zip(&ends[2..])
        .map(|(&spc, p)| ((1.0 / spc as f64).ln(), error(p).ln()))
        .collect();
    let n = points.len() as f64;
    let (mx, my) = (
        points.iter().map(|p| p.0).sum::<f64>() / n,
        points.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let order = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
        / points.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>();
    let refined = error(&ends[1]) / error(&ends[4]);
    println!("order {order:.3}; refinement at 64 steps per cycle: error × {refined:.4}");
    assert!((0.8..=1.4).contains(&order), "order {order}");
    assert!(refined < 0.1, "{refined}");
}

/// The planar scheme's error on a played drop by slip rule and refinement
/// depth (printed): the rectangle from (1 cm, −0.5 cm, 40°) for 3 s on the
/// designed ellipse at 16…1024 steps per cycle against 8192 (midpoint,
/// depth 10). Measured at 64 steps per cycle: depth 0 3.0e-4 m (backward
/// 3.0e-4), depth 3 5.5e-5 (5.7e-5), depth 10 8.1e-6 (8.2e-6); at depth 3
/// the midpoint rule takes 1.07 times the backward rule's Newton
/// iterations.
/// About 8 s of CPU:
/// `cargo test --release --test poses -- --ignored --nocapture planar_order_report`.
#[test]
#[ignore]
fn planar_order_report() {
    use platefield::dynamics::SlipRule;
    let spcs = [16usize, 32, 64, 128, 256, 512, 1024];
    let mut runs = vec![(8192usize, 10u32, SlipRule::Midpoint)];
    for rule in [SlipRule::Midpoint, SlipRule::Backward] {
        for depth in [0u32, 3, 10] {
            runs.extend(spcs.iter().map(|&spc| (spc, depth, rule)));
        }
    }
    let (ends, r) = ellipse_drops(&runs);
    let reference = ends[0].pose;
    for (run, end) in runs.iter().zip(&ends).skip(1) {
        let p = end.pose;
        let e =
            ((p.r - reference.r).norm_squared() + (r * (p.theta - reference.theta)).powi(2)).sqrt();
        println!(
            "{:?} depth {:2} {:5} steps/cycle: error {e:.3e} m; {} steps, {} halvings, {} Newton",
            run.2, run.1, run.0, end.steps, end.refinements, end.solver_iterations
        );
    }
}

/// The played drop's defaults (`DropPlay::new`: 64 steps per cycle,
/// refinement depth 3, the shipped rectangle resampled to 36 support
/// points) against 256 steps per cycle, depth 10 and 64 support points,
/// on a 20 s drop from (1 cm, −0.5 cm, 40°) on the designed ellipse: the
/// end pose within 0.05 mm and 0.3° (measured 0.016 mm, 0.10°), at most 140
/// steps per cycle and 5 Newton iterations per step (measured 125, 4.3:
/// 3.9 under the backward slip rule, the midpoint corrector's steps taking
/// one solve each where the slip stays smooth; 10 s of CPU per drop before
/// the slipping fast path and the coarser drop defaults,
/// `drop_speed_report`).
#[test]
fn drop_defaults_are_converged() {
    use rayon::prelude::*;
    let (schedule, _, _) = designed("ellipse");
    let sm = platefield::play::ScheduleMotion::from_schedule(&schedule).unwrap();
    let start = Pose::new(0.01, -0.005, 40f64.to_radians());
    let defaults = platefield::pose::DropPlay::new(&schedule.settings, 20.0);
    let (coarse, offset) = rectangle().coarse_body(defaults.samples.unwrap()).unwrap();
    assert_eq!(coarse.points().len(), 36);
    assert!(offset.norm() < 1e-15);
    let mut fine = defaults;
    fine.steps_per_cycle = 256;
    fine.refine_depth = 10;
    let fine_body = rectangle_with(64).body;
    let cases = [(&coarse, defaults), (&fine_body, fine)];
    let ends: Vec<platefield::pose::DropEnd> = cases
        .par_iter()
        .map(|(body, play)| platefield::pose::play_drop(&sm, body, start, play).unwrap())
        .collect();
    let (a, b) = (ends[0].pose, ends[1].pose);
    let (dr, dt) = (
        1e3 * (a.r - b.r).norm(),
        wrap(a.theta - b.theta).to_degrees().abs(),
    );
    let cycle = sm
        .segments()
        .iter()
        .filter_map(|s| s.motion.as_ref().map(|m| m.period()))
        .fold(f64::INFINITY, f64::min);
    let cycles = ends[0].time / cycle;
    let per_cycle = ends[0].steps as f64 / cycles;
    let newton = ends[0].solver_iterations as f64 / ends[0].steps as f64;
    println!("{dr:.4} mm {dt:.4}°, {per_cycle:.1} steps per cycle, {newton:.2} Newton per step");
    assert!(dr < 0.05 && dt < 0.3, "{dr} mm {dt}°");
    assert!(per_cycle <= 140.0 && newton <= 5.0, "{per_cycle} {newton}");
}

/// The averaged field's equilibria are where the played part rests: the
/// triangle and the rectangle on the designed ellipse turned by 30° (a
/// sequenced schedule of five primitives). Each stable equilibrium refined from the lifted one
/// ([`platefield::pose::played_rests`]) is played for 30 s by the planar
/// simulator from rest (`DropPlay::new`'s defaults): it ends within
/// 0.05 mm and 0.1° of where it started (measured 0.006 mm, 0.01°). From
/// the lifted equilibrium (12.6° for the triangle, 25.4° for the
/// rectangle, and 2.3 mm away: the lifted spin is too fast and the lifted
/// field leaves out the joins) the part turns toward the refined one, at
/// least halfway there in 30 s (measured 7° of 12.6°).
///
/// The default run plays the rectangle, whose two stable poses are one
/// placement turned by π (one is refined and played); the triangle too
/// (about 7 s of CPU more): `cargo test --release --test poses --
/// --ignored averaged_equilibria`.
#[test]
fn averaged_equilibria_are_played_rests() {
    averaged_equilibria_played(&["rectangle"]);
}

/// [`averaged_equilibria_are_played_rests`] for the triangle.
#[test]
#[ignore = "about 7 s of CPU: cargo test --release --test poses -- --ignored averaged_equilibria"]
fn averaged_equilibria_are_played_rests_for_the_triangle() {
    averaged_equilibria_played(&["triangle"]);
}

/// The check of [`averaged_equilibria_are_played_rests`] for each part
/// of `names` (`targets/parts/<name>.json`). As `platefield poses` does
/// (`pose::poses`), but only the lifted field's stable equilibria are
/// refined: each refinement is its own Newton run, the same with or
/// without the others, and the unstable two would cost as much again
/// (`tests/cli_poses.rs` checks that refinement keeps each equilibrium's
/// stability, the unstable ones' too).
fn averaged_equilibria_played(names: &[&str]) {
    use platefield::pose::{
        analyse, play_part, played_rests, AveragedField, DropPlay, RestOutcome,
    };
    let (schedule, field, region) = designed("ellipse_30");
    let sm = platefield::play::ScheduleMotion::from_schedule(&schedule).unwrap();
    let play = DropPlay::new(&schedule.settings, 30.0);
    for &name in names {
        let part = Part::load(Path::new(&format!("targets/parts/{name}.json"))).unwrap();
        let analysis = analyse(&part, &field, region, 20);
        let lifted: Vec<_> = analysis
            .equilibria
            .iter()
            .filter(|e| e.stable)
            .copied()
            .collect();
        assert_eq!(lifted.len(), 2, "{name}: {:?}", analysis.equilibria);
        // A part with 180° symmetry (the rectangle) has its two stable
        // poses as one placement turned by π: the same r, θ + π. One is
        // refined and played; the other would repeat it bit for bit.
        let lifted = if part.symmetry().is_multiple_of(2) {
            let (a, b) = (lifted[0].pose, lifted[1].pose);
            assert!((a.r - b.r).norm() < 1e-9, "{name}: {a:?} {b:?}");
            assert!(
                (off_deg(a.theta, b.theta) - 180.0).abs() < 1e-6,
                "{name}: {a:?} {b:?}"
            );
            vec![lifted[0]]
        } else {
            lifted
        };
        let averaged = AveragedField::for_part(&part, sm.clone(), schedule.settings.physics());
        for r in played_rests(&averaged, &lifted, &analysis.region, &|| {}) {
            let RestOutcome::Found { equilibrium: e, .. } = r.outcome else {
                panic!("{r:?}");
            };
            assert!(e.stable, "{name}: {r:?}");
            let ends = play_part(&part, &sm, &[e.pose, r.from.pose], &play);
            let at = |k: usize| ends[k].as_ref().unwrap().0.pose;
            let (rest, turned) = (at(0), at(1));
            println!(
                "refined {e:?}: played from it to {rest:?}, from the lifted {:?} to {turned:?}",
                r.from.pose
            );
            assert!((rest.r - e.pose.r).norm() < 5e-5 && off_deg(rest.theta, e.pose.theta) < 0.1);
            let lifted_off = off_deg(r.from.pose.theta, e.pose.theta);
            assert!(lifted_off > 5.0 && off_deg(turned.theta, e.pose.theta) < 0.5 * lifted_off);
        }
    }
}
