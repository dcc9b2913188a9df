//! Issue 28, route A (`pose::design::spin`): a rotation about the vertical
//! mixed with the in-plane translation in one motion makes the synthesized
//! sink's point field nonlinear at the part's scale and gives the bracket
//! one stable pose (measured numbers in docs/parts.md).

#[path = "common/affine.rs"]
mod affine;

use platefield::field::{Field, FieldKind, FieldSettings, Grid};
use platefield::motion::{Axes, FourierTerm, Motion, Signals};
use platefield::pose::design::spin::{Spin, CANDIDATES};
use platefield::pose::design::PoseTarget;
use platefield::pose::{equilibria, Equilibrium, GridField, LiftedField};

/// The plate region the fields are measured on (m): ±4 cm.
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

/// The isotropic sink `design` synthesizes for targets/pose_bracket.json
/// (its centred motion, as printed by the synthesis on this branch).
fn synthesized_sink() -> Signals {
    Signals {
        period: 0.030_063_087_594_160_7,
        linear: Axes {
            x: vec![
                term(45.266_439, std::f64::consts::FRAC_PI_2, 1),
                term(0.452_664, 0.0, 2),
            ],
            y: vec![term(45.275_488, 0.009_999_7, 1)],
            z: Vec::new(),
        },
        angular: Axes {
            x: vec![term(82.739_718, 1.668_121_2, 1)],
            y: vec![term(82.739_718, 0.097_324_9, 1)],
            z: Vec::new(),
        },
    }
}

/// The sink with `spin` (none for `None`): its field on `GRID`.
fn field(spin: Option<Spin>) -> Field {
    let mut motion = synthesized_sink();
    if let Some(s) = spin {
        s.apply(&mut motion);
    }
    let f = Field::compute(
        &Motion::Signals(motion),
        &GRID,
        FieldKind::Velocity,
        &FieldSettings::default(),
        &|| {},
    );
    assert_eq!(f.valid_count(), GRID.len(), "contact lost");
    f
}

/// The bracket's pose request (`PF_TARGET`'s instead when set, for the
/// explorations).
fn request() -> PoseTarget {
    let target = std::env::var("PF_TARGET").unwrap_or("targets/pose_bracket.json".into());
    PoseTarget::load(std::path::Path::new(&target))
        .unwrap()
        .unwrap()
}

/// The stable poses of [`request`]'s part in `f`'s lifted field over its
/// region.
fn bracket_stable(f: &Field) -> Vec<Equilibrium> {
    let req = request();
    let g = GridField::new(f);
    let eqs = equilibria(&LiftedField::new(&g, &req.part.body), &req.region);
    eqs.into_iter().filter(|e| e.stable).collect()
}

/// The residual measure against closed forms: an affine field leaves
/// nothing; v = (x², 0) on the 17-point symmetric grid is fitted by its
/// mean, a²·Σk²/(8²·17)·2 = 0.375 a² (k = −8…8), so the largest residual
/// is a² − 0.375 a² = 0.625 of the largest speed a².
#[test]
fn affine_residual_matches_closed_forms() {
    let ps = affine::points(&GRID);
    let exact: Vec<[f64; 2]> = ps
        .iter()
        .map(|p| [0.01 + 2.0 * p.x - p.y, -0.02 + 0.5 * p.y + 3.0 * p.x])
        .collect();
    let r = affine::affine_residual(&GRID, &exact);
    assert!(r < 1e-12, "{r}");
    let square: Vec<[f64; 2]> = ps.iter().map(|p| [p.x * p.x, 0.0]).collect();
    let r = affine::affine_residual(&GRID, &square);
    assert!((r - 0.625).abs() < 1e-12, "{r}");
}

/// The synthesized sink is affine to 6 % over ±4 cm (measured 3.5 % with
/// its translation scaled by 0.25) and leaves the bracket's orientation
/// neutral (no stable pose: an isotropic linear sink does not turn a
/// part); with the spin the bracket keeps (`pose::design::screen`: α =
/// 1200 rad/s² at −1.6 rad, translation × 0.4, r* ≈ 14 mm) the residual
/// exceeds 50 % (measured 67 %) and the bracket has exactly one stable
/// pose, decaying faster than 0.1 1/s (measured 0.41 1/s; the time-shared
/// DivCircle route: 0.0028–0.013). (One lifted pose is not enough: the
/// spin of session 7 also had one, and 26 % of its played drops rested at
/// a second pose, docs/parts.md.)
#[test]
fn spin_makes_the_sink_nonlinear_and_the_bracket_pose_unique() {
    let spin = CANDIDATES[2];
    assert_eq!(
        (spin.alpha, spin.phase, spin.translation),
        (1200.0, -1.6, 0.4)
    );
    let mut plain = spin;
    plain.alpha = 0.0;
    let flat = field(Some(plain));
    let r0 = affine::affine_residual(&GRID, &flat.vectors);
    assert!(r0 < 0.06, "{r0}");
    assert!(bracket_stable(&flat).is_empty());
    let spun = field(Some(spin));
    let r1 = affine::affine_residual(&GRID, &spun.vectors);
    let stable = bracket_stable(&spun);
    eprintln!("affine residual {r0:.3} → {r1:.3}; bracket stable {stable:?}");
    assert!(r1 > 0.5, "{r1}");
    assert_eq!(stable.len(), 1, "{stable:?}");
    assert!(-stable[0].rates[0] > 0.1, "{stable:?}");
}

/// Exploration: `PF_SPIN="alpha,phase,translation;..."` prints each spun
/// sink's affine residual and the bracket's stable poses
/// (`cargo test --release --test pose_rotation -- --ignored --nocapture`).
#[test]
#[ignore = "exploration: PF_SPIN=alpha,phase,translation;..."]
fn explore_spin() {
    let spec = std::env::var("PF_SPIN").unwrap_or("1200,-0.8,0.25".into());
    for item in spec.split(';') {
        let v: Vec<f64> = item.split(',').map(|s| s.parse().unwrap()).collect();
        let f = field(Some(Spin {
            alpha: v[0],
            phase: v[1],
            translation: v[2],
        }));
        let r = affine::affine_residual(&GRID, &f.vectors);
        eprintln!(
            "spin {item}: affine residual {r:.3}, top {:.4} m/s",
            f.max_magnitude()
        );
        for e in bracket_stable(&f) {
            eprintln!("  bracket stable {:?}", e);
        }
    }
}

/// The pose target at `path` designed as `design` does, quietly, with
/// [`platefield::pose::design::DROPS`] drops.
fn designed(path: &str) -> platefield::pose::design::PoseDesign {
    use platefield::pose::design::{design_pose, DROPS};
    let req = PoseTarget::load(std::path::Path::new(path))
        .unwrap()
        .unwrap();
    let opts = platefield::design::DesignOptions {
        runtime: platefield::work::Runtime::QUIET,
        ..Default::default()
    };
    design_pose(&req, &opts, DROPS).unwrap()
}

/// The shipped cycles' spin stages hand parts over (`pose::design::handover`):
/// the spin stage of `results/poses/<part>/schedule.json`, played as shipped
/// (its cycles, its ramps) from the ellipse stage's two rests, the asked
/// pose and the same turned by 180°, at the part's μ 0.3 and at μ ± 20 %,
/// ends in the kept half, within 90° of the asked angle
/// (`cycle::ELLIPSE_TURN_DEG`), where the ellipse stage takes it to the
/// asked pose. Measured: the bracket's worst 20.3°, the triangle's 58.4°
/// (at μ × 1.2; its spin brings the six within 49° at best when played
/// steadily, and the shipped stage ramps in and out). Before the spin
/// stage was measured, the bracket's shipped stage (8.7 s) left a part
/// 151° away.
#[test]
fn shipped_spin_stages_hand_parts_over() {
    use platefield::play::ScheduleMotion;
    use platefield::pose::design::cycle::ELLIPSE_TURN_DEG;
    use platefield::pose::design::search::pose_error;
    use platefield::pose::{play_part, DropPlay, Pose};
    use platefield::schedule::Schedule;
    for part in ["bracket", "triangle"] {
        let req = PoseTarget::load(std::path::Path::new(&format!("targets/pose_{part}.json")))
            .unwrap()
            .unwrap();
        let path = format!("results/poses/{part}/schedule.json");
        let mut spin = Schedule::load(std::path::Path::new(&path)).unwrap();
        spin.segments.truncate(1);
        spin.segments[0].weight = 1.0;
        spin.derive();
        let stage = spin.segments[0].duration_s;
        let rival = Pose {
            r: req.pose.r,
            theta: req.pose.theta + std::f64::consts::PI,
        };
        let nominal = spin.settings.friction;
        for k in [1.0, 0.8, 1.2] {
            let mut at = spin.clone();
            at.settings.friction.stat = k * nominal.stat;
            at.settings.friction.kinetic = k * nominal.kinetic;
            let sm = ScheduleMotion::from_schedule(&at).unwrap();
            assert!((sm.period() - stage).abs() < 1e-9);
            let play = DropPlay::new(&at.settings, stage);
            for run in play_part(&req.part, &sm, &[req.pose, rival], &play) {
                let (end, _) = run.unwrap();
                let turn = pose_error(&end.pose, &req.pose, req.part.symmetry()).1;
                assert!(
                    turn.abs().to_degrees() < ELLIPSE_TURN_DEG,
                    "{part} at μ × {k}: {:.1}° after the {stage:.1} s spin stage",
                    turn.to_degrees()
                );
            }
        }
    }
}

/// The bracket's pose target designed whole on the spin route: the screen
/// keeps, by its placed cycle with the ellipse (`pose::design::cycle`),
/// 4800 rad/s² with the translation × 0.15 (measured: 32 of 32 probes at
/// one pose; of the 7 candidates only it and 1200 × 0.6 hand parts over,
/// `pose::design::handover`), its spin stage measured by its hand-over and
/// its ellipse stage timed from the hand-over's worst turn (the kept
/// schedule's period their sum), and at least 95 % of 100 drops end at the pose
/// (measured 100 %; 79 % when the spin stage was the lifted estimate,
/// 8.7 s, which left a fifth of the drops at the rival rest 180° away).
/// The median settle is one period (measured 22.9 s: 18.0 s + 4.9 s; the
/// issue's 20 s is not met). The screen's probes, each start also turned
/// by 180°, see a rival rest: their share lies within 3 probes (3/32) of
/// the drops' share, which start elsewhere. About 4 min of CPU:
/// `cargo test --release --test pose_rotation -- --ignored bracket`.
#[test]
#[ignore = "minutes of CPU: cargo test --release --test pose_rotation -- --ignored bracket"]
fn bracket_pose_design_on_the_spin_route() {
    use platefield::pose::design::DROPS;
    let d = designed("targets/pose_bracket.json");
    assert_eq!(d.spin, Some(CANDIDATES[4]));
    assert_eq!(d.screened.len(), CANDIDATES.len());
    let screened = d.screened[4].score;
    let stages = d.stages.unwrap();
    assert_eq!(d.screened[4].stages, Some(stages));
    let schedule = &d.method.kept().schedule;
    assert_eq!(schedule.segments.len(), 2);
    assert!((schedule.period_s - stages.period()).abs() < 0.1);
    let p = schedule.played.as_ref().unwrap().pose.as_ref().unwrap();
    assert_eq!((p.drops, p.lost), (DROPS, 0));
    assert!(p.pose_fraction >= 0.95, "{}", p.pose_fraction);
    assert!(
        (screened - p.pose_fraction).abs() <= 3.0 / 32.0,
        "screen {screened}, drops {}",
        p.pose_fraction
    );
    let settle = p.median_settle_s.unwrap();
    assert!((settle - schedule.period_s).abs() < 0.1, "{settle} s");
}

/// The triangle's pose target designed whole: a cycle (`pose::design::cycle`)
/// of the spin the screen keeps (4800 rad/s², translation × 0.15; the three
/// spins of 1200 rad/s² turn it too slowly for a 40 s stage and are not
/// played) and the ellipse puts at least 95 % of 100 drops within 1 mm
/// and 3° of (−10 mm, 6 mm, 60°) (measured 100 %) with a median settle of
/// one period, at most 30 s (measured 24.0 s: its spin stage, measured by
/// its hand-over, is 18.6 s). About 6 min of CPU: `cargo test --release --test
/// pose_rotation -- --ignored triangle`.
#[test]
#[ignore = "minutes of CPU: cargo test --release --test pose_rotation -- --ignored triangle"]
fn triangle_pose_design_in_a_cycle() {
    let d = designed("targets/pose_triangle.json");
    assert_eq!(d.spin, Some(CANDIDATES[4]));
    assert!(d.screened.iter().take(3).all(|s| s.stages.is_none()));
    let schedule = &d.method.kept().schedule;
    assert_eq!(schedule.segments.len(), 2);
    let p = schedule.played.as_ref().unwrap().pose.as_ref().unwrap();
    assert!(p.lost <= 2, "{} lost", p.lost);
    assert!(p.pose_fraction >= 0.95, "{}", p.pose_fraction);
    let settle = p.median_settle_s.unwrap();
    assert!(
        settle <= 30.0 && (settle - schedule.period_s).abs() < 0.1,
        "{settle} s"
    );
}

/// Exploration: where a pose design's drops end. `PF_SCHEDULE` a kept
/// `schedule.json` of `PF_TARGET` (default targets/pose_bracket.json),
/// played `PF_DROPS` drops (default 100) for `PF_SECONDS` (default 120):
/// per drop not at the pose its start, its error at the end and 20 s
/// before (`cargo test --release --test pose_rotation -- --ignored
/// --nocapture explore_ends`).
#[test]
#[ignore = "exploration: PF_SCHEDULE=…/schedule.json"]
fn explore_ends() {
    use platefield::pose::design::search::pose_error;
    use platefield::pose::{drop_starts, play_part, DropPlay};
    let env = |k: &str, d: &str| std::env::var(k).unwrap_or(d.into());
    let req = request();
    let s = platefield::schedule::Schedule::load(std::path::Path::new(&env(
        "PF_SCHEDULE",
        "/tmp/p8/b/pose_bracket/schedule.json",
    )))
    .unwrap();
    let sm = platefield::play::ScheduleMotion::from_schedule(&s).unwrap();
    let drops: usize = env("PF_DROPS", "100").parse().unwrap();
    let secs: f64 = env("PF_SECONDS", "120").parse().unwrap();
    let starts = drop_starts(&req.region.inset(req.part.radius()), drops);
    let runs = play_part(&req.part, &sm, &starts, &DropPlay::new(&s.settings, secs));
    let n = req.part.symmetry();
    let per_20 = (20.0 / sm.period()).round() as usize;
    for (i, (run, st)) in runs.iter().zip(&starts).enumerate() {
        let Ok((_, track)) = run else {
            eprintln!("drop {i}: lost");
            continue;
        };
        let err = |k: usize| {
            let (d, t) = pose_error(&track[k], &req.pose, n);
            (d * 1e3, t.to_degrees())
        };
        let last = track.len() - 1;
        let (e1, e0) = (err(last), err(last.saturating_sub(per_20)));
        let tag = if e1.0 <= 1.0 && e1.1.abs() <= 3.0 {
            "AT"
        } else {
            "OUT"
        };
        let pr = |p: &platefield::pose::Pose| {
            format!(
                "({:+.1} mm, {:+.1} mm, {:+.0}°)",
                p.r.x * 1e3,
                p.r.y * 1e3,
                p.theta.to_degrees()
            )
        };
        eprintln!(
            "drop {i} {tag}: start {} end {} err {:.2} mm {:+.1}° (20 s before {:.2} mm {:+.1}°)",
            pr(st),
            pr(&track[last]),
            e1.0,
            e1.1,
            e0.0,
            e0.1
        );
    }
}

/// Exploration: spins judged by play (`pose::design::screen`) on the
/// centred sink `design` synthesizes for `PF_TARGET` (default the
/// bracket's): `PF_SPIN="alpha,phase,translation;..."` (default the
/// candidates) prints each one's score and its cycle's played pose
/// (`PF_ENDS=1`: and every probe's end on the spun sink alone)
/// (`cargo test --release --test pose_rotation -- --ignored --nocapture explore_screen`).
#[test]
#[ignore = "exploration: PF_SPIN=alpha,phase,translation;..."]
fn explore_screen() {
    use platefield::pose::design::{placement, screen};
    let req = request();
    let opts = platefield::design::DesignOptions {
        runtime: platefield::work::Runtime::QUIET,
        ..Default::default()
    };
    let method =
        placement::synthesize_centred(&req, placement::family(true), &opts, &opts.synthesis)
            .unwrap();
    let sink = method.kept().schedule.clone();
    let ellipse =
        placement::synthesize_centred(&req, placement::family(false), &opts, &opts.synthesis)
            .unwrap();
    let grid = req.target.grid.unwrap_or(Grid::DEFAULT);
    let stage = platefield::pose::design::cycle::EllipseStage::new(
        &req,
        ellipse.kept().schedule.clone(),
        &grid,
    )
    .unwrap();
    let spins: Vec<Spin> = match std::env::var("PF_SPIN") {
        Ok(spec) => spec
            .split(';')
            .map(|item| {
                let v: Vec<f64> = item.split(',').map(|s| s.parse().unwrap()).collect();
                Spin {
                    alpha: v[0],
                    phase: v[1],
                    translation: v[2],
                }
            })
            .collect(),
        Err(_) => CANDIDATES.to_vec(),
    };
    let v: Vec<f64> = std::env::var("PF_STAGE_S")
        .unwrap_or("10,5".into())
        .split(',')
        .map(|s| s.parse().unwrap())
        .collect();
    let stages = platefield::pose::design::cycle::Stages {
        spin_s: v[0],
        ellipse_s: v[1],
    };
    for spin in spins {
        let s = screen::screen(&req, &sink, &stage, (spin, stages)).unwrap();
        eprintln!(
            "spin {} {} {}: score {:.3} spread {:.3} pose {:?}",
            spin.alpha, spin.phase, spin.translation, s.score, s.spread, s.pose
        );
        if std::env::var("PF_ENDS").is_ok() {
            let spun = platefield::pose::design::spin::spun(&sink, spin).unwrap();
            for e in screen::probe_ends(&req, &spun, None)
                .unwrap()
                .iter()
                .flatten()
            {
                eprintln!(
                    "  end ({:+.2} mm, {:+.2} mm, {:+.1}°)",
                    1e3 * e.r.x,
                    1e3 * e.r.y,
                    e.theta.to_degrees()
                );
            }
        }
    }
}

/// Exploration: each `PF_SPIN` candidate's played basins on the centred
/// motion from `PF_DROPS` (default 64) drops spread as `design`'s are,
/// 60 s each: the largest cluster's share and the second's
/// (`cargo test --release --test pose_rotation -- --ignored --nocapture explore_basins`).
#[test]
#[ignore = "exploration: PF_SPIN=alpha,phase,translation;... PF_DROPS=n PF_RATIO=r"]
fn explore_basins() {
    use platefield::pose::design::{placement, screen, spin::spun};
    use platefield::pose::{drop_starts, play_part, DropPlay, Pose};
    let req = request();
    // PF_RATIO: the synthesized ellipse's α/β (1: the isotropic sink).
    let family = platefield::pose::design::search::Family::Ellipse {
        ratio: std::env::var("PF_RATIO")
            .unwrap_or("1".into())
            .parse()
            .unwrap(),
    };
    let opts = platefield::design::DesignOptions {
        runtime: platefield::work::Runtime::QUIET,
        ..Default::default()
    };
    let method = placement::synthesize_centred(&req, family, &opts, &opts.synthesis).unwrap();
    let sink = method.kept().schedule.clone();
    let drops: usize = std::env::var("PF_DROPS")
        .unwrap_or("64".into())
        .parse()
        .unwrap();
    let spec = std::env::var("PF_SPIN").unwrap_or("4800,-1.6,0.15".into());
    for item in spec.split(';') {
        let v: Vec<f64> = item.split(',').map(|s| s.parse().unwrap()).collect();
        let spin = Spin {
            alpha: v[0],
            phase: v[1],
            translation: v[2],
        };
        let s = spun(&sink, spin).unwrap();
        let sm = platefield::play::ScheduleMotion::from_schedule(&s).unwrap();
        let starts = drop_starts(&req.region.inset(req.part.radius()), drops);
        let runs = play_part(&req.part, &sm, &starts, &DropPlay::new(&s.settings, 60.0));
        let mut ends: Vec<Pose> = runs.iter().flatten().map(|(e, _)| e.pose).collect();
        let lost = drops - ends.len();
        let n = req.part.symmetry();
        let mut shares = Vec::new();
        while let Some((share, pose, _)) = screen::largest_cluster(&ends, n, drops) {
            shares.push(format!(
                "{:.0} % at ({:+.1}, {:+.1}, {:+.0}°)",
                100.0 * share,
                1e3 * pose.r.x,
                1e3 * pose.r.y,
                pose.theta.to_degrees()
            ));
            ends.retain(|e| {
                let (d, t) = platefield::pose::design::search::pose_error(e, &pose, n);
                1e3 * d > 1.0 || t.abs().to_degrees() > 3.0
            });
            if shares.len() == 3 {
                break;
            }
        }
        eprintln!(
            "spin {} {} {}: {} lost; {}",
            spin.alpha,
            spin.phase,
            spin.translation,
            lost,
            shares.join("; ")
        );
    }
}

/// The cycle of a spun sink and the ellipse (`pose::design::cycle`):
/// `PF_SPIN_A` (default 4800,-1.6,0.15) on the isotropic sink, its probes'
/// main rest, and its cycle with the ellipse placed there, the stages
/// `PF_STAGE_S` seconds (default the library's 40,20); `PF_DROPS` drops
/// (default 64) for `PF_SECONDS` (default 160) at each μ of `PF_MU`
/// (default 0.3; `PF_ALONE=1`: the spun sink alone too): the shares at
/// the three largest rests (`cargo test --release --test pose_rotation --
/// --ignored --nocapture explore_cycle`).
#[test]
#[ignore = "exploration: PF_TARGET, PF_SPIN_A, PF_STAGE_S, PF_MU"]
fn explore_cycle() {
    use platefield::pose::design::cycle::{cycle, EllipseStage, Stages};
    use platefield::pose::design::{placement, screen, search::pose_error, spin::spun};
    use platefield::pose::{drop_starts, play_part, DropPlay, Pose};
    use platefield::schedule::Schedule;
    let env = |k: &str, d: &str| std::env::var(k).unwrap_or(d.into());
    let req = request();
    let n = req.part.symmetry();
    let opts = platefield::design::DesignOptions {
        runtime: platefield::work::Runtime::QUIET,
        ..Default::default()
    };
    let synth = |spin: bool| {
        placement::synthesize_centred(&req, placement::family(spin), &opts, &opts.synthesis)
            .unwrap()
            .kept()
            .schedule
            .clone()
    };
    let grid = req.target.grid.unwrap_or(Grid::DEFAULT);
    let (sink, ellipse) = (
        synth(true),
        EllipseStage::new(&req, synth(false), &grid).unwrap(),
    );
    let drops: usize = env("PF_DROPS", "64").parse().unwrap();
    let secs: f64 = env("PF_SECONDS", "160").parse().unwrap();
    let stages: Vec<f64> = env("PF_STAGE_S", "10,5")
        .split(',')
        .map(|s| s.parse().unwrap())
        .collect();
    let starts = drop_starts(&req.region.inset(req.part.radius()), drops);
    let say = |what: &str, s: &Schedule, secs: f64| -> Pose {
        let sm = platefield::play::ScheduleMotion::from_schedule(s).unwrap();
        let runs = play_part(&req.part, &sm, &starts, &DropPlay::new(&s.settings, secs));
        let mut ends: Vec<Pose> = runs.iter().flatten().map(|(e, _)| e.pose).collect();
        let lost = drops - ends.len();
        let mut out = Vec::new();
        while let Some((share, pose, _)) = screen::largest_cluster(&ends, n, drops) {
            out.push((share, pose));
            ends.retain(|e| {
                let (d, t) = pose_error(e, &pose, n);
                1e3 * d > 1.0 || t.abs().to_degrees() > 3.0
            });
            if out.len() == 3 {
                break;
            }
        }
        let text: Vec<String> = out
            .iter()
            .map(|(f, p)| {
                format!(
                    "{:.0} % at ({:+.1}, {:+.1}, {:+.1}°)",
                    100.0 * f,
                    1e3 * p.r.x,
                    1e3 * p.r.y,
                    p.theta.to_degrees()
                )
            })
            .collect();
        eprintln!("{what}: {lost} lost; {}", text.join("; "));
        out[0].1
    };
    for spin in env("PF_SPIN_A", "4800,-1.6,0.15").split(';') {
        let v: Vec<f64> = spin.split(',').map(|s| s.parse().unwrap()).collect();
        let spin = Spin {
            alpha: v[0],
            phase: v[1],
            translation: v[2],
        };
        eprintln!("spin {spin:?}");
        let a = spun(&sink, spin).unwrap();
        let rest = say("spun sink alone", &a, 60.0);
        // How long the spun sink alone takes each drop into (and keeps it
        // in) the half-turn of 60° about its rest, and within 1 mm / 3°.
        let sm = platefield::play::ScheduleMotion::from_schedule(&a).unwrap();
        let runs = play_part(&req.part, &sm, &starts, &DropPlay::new(&a.settings, 60.0));
        let mut half = Vec::new();
        let mut tight = Vec::new();
        for (_, track) in runs.iter().flatten() {
            let stay = |ok: &dyn Fn(&Pose) -> bool| match track.iter().rposition(|p| !ok(p)) {
                None => 0.0,
                Some(k) if k + 1 < track.len() => (k + 1) as f64 * sm.period(),
                Some(_) => f64::INFINITY,
            };
            half.push(stay(&|p: &Pose| {
                pose_error(p, &rest, n).1.abs().to_degrees() <= 60.0
            }));
            tight.push(stay(&|p: &Pose| {
                let (d, t) = pose_error(p, &rest, n);
                1e3 * d <= 1.0 && t.abs().to_degrees() <= 3.0
            }));
        }
        for (what, v) in [("within 60°", &mut half), ("within 1 mm, 3°", &mut tight)] {
            v.sort_by(f64::total_cmp);
            let q = |f: f64| v[((v.len() - 1) as f64 * f).round() as usize];
            eprintln!(
                "  spun sink alone, {what} of its rest from: quartiles {:.1} / {:.1} / {:.1}, 90 % {:.1}, max {:.1} s",
                q(0.25), q(0.5), q(0.75), q(0.9), q(1.0)
            );
        }
        let stages = Stages {
            spin_s: stages[0],
            ellipse_s: stages[1],
        };
        let mut c = cycle(&a, &ellipse, &rest, stages).unwrap();
        for mu in env("PF_MU", "0.3").split(',') {
            let friction = platefield::dynamics::Friction::uniform(mu.parse().unwrap());
            if std::env::var("PF_ALONE").is_ok() {
                let mut alone = a.clone();
                alone.settings.friction = friction;
                say(&format!("spun sink alone at μ {mu}"), &alone, 60.0);
            }
            c.settings.friction = friction;
            say(&format!("cycle {stages:?} s at μ {mu}"), &c, secs);
        }
    }
}

/// Stage lengths of a shipped cycle (`PF_TARGET`, its schedule in
/// `results/poses/<part>/schedule.json`): each stage's lifted equilibria
/// and rates alone, then the cycle replayed with each `PF_STAGES` pair
/// (`"spin,ellipse;…"` s) for `PF_SECONDS` from `PF_DROPS` drops at each
/// `PF_MU`: share at the asked pose and the settle times' quartiles
/// (`cargo test --release --test pose_rotation -- --ignored --nocapture
/// explore_stages`).
#[test]
#[ignore = "exploration: PF_TARGET, PF_STAGES, PF_DROPS, PF_SECONDS, PF_MU"]
fn explore_stages() {
    use platefield::pose::design::at_pose;
    use platefield::pose::{drop_starts, play_part, schedule_field, DropPlay};
    use platefield::schedule::Schedule;
    let env = |k: &str, d: &str| std::env::var(k).unwrap_or(d.into());
    let req = request();
    let n = req.part.symmetry();
    let name = std::path::Path::new(&req.part_path)
        .file_stem()
        .unwrap()
        .to_string_lossy()
        .to_string();
    let path = format!("results/poses/{name}/schedule.json");
    let shipped: Schedule = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let grid = req.target.grid.unwrap_or(Grid::DEFAULT);
    for (i, seg) in shipped.segments.iter().enumerate() {
        let mut one = shipped.clone();
        one.segments = vec![seg.clone()];
        one.segments[0].weight = 1.0;
        one.derive();
        let f = schedule_field(&one, &grid).unwrap();
        let eqs = equilibria(&LiftedField::new(&f, &req.part.body), &req.region);
        for e in &eqs {
            eprintln!(
                "stage {i}: ({:+.2}, {:+.2}) mm {:+.1}° stable {} rates {:.3?}",
                1e3 * e.pose.r.x,
                1e3 * e.pose.r.y,
                e.pose.theta.to_degrees(),
                e.stable,
                e.rates
            );
        }
    }
    let drops: usize = env("PF_DROPS", "24").parse().unwrap();
    let secs: f64 = env("PF_SECONDS", "60").parse().unwrap();
    let starts = drop_starts(&req.region.inset(req.part.radius()), drops);
    for stages in env("PF_STAGES", "40,20").split(';') {
        let st: Vec<f64> = stages.split(',').map(|s| s.parse().unwrap()).collect();
        let mut c = shipped.clone();
        for (seg, s) in c.segments.iter_mut().zip(&st) {
            let p = seg.cycle_period().unwrap();
            seg.cycles = ((s / p).round() as u32).max(2 * seg.ramp_cycles.unwrap_or(0));
            seg.duration_s = f64::from(seg.cycles) * p;
        }
        c.derive();
        for mu in env("PF_MU", "0.3").split(',') {
            c.settings.friction = platefield::dynamics::Friction::uniform(mu.parse().unwrap());
            let sm = platefield::play::ScheduleMotion::from_schedule(&c).unwrap();
            let runs = play_part(&req.part, &sm, &starts, &DropPlay::new(&c.settings, secs));
            let mut settle: Vec<f64> = Vec::new();
            let mut at = 0;
            for (end, track) in runs.iter().flatten() {
                at += usize::from(at_pose(&end.pose, &req.pose, n));
                let last_out = track.iter().rposition(|p| !at_pose(p, &req.pose, n));
                settle.push(match last_out {
                    None => sm.period(),
                    Some(k) if k + 1 < track.len() => (k + 2) as f64 * sm.period(),
                    Some(_) => f64::INFINITY,
                });
            }
            settle.sort_by(f64::total_cmp);
            let q = |f: f64| settle[((settle.len() - 1) as f64 * f).round() as usize];
            eprintln!(
                "stages {stages} (period {:.2} s) μ {mu}: {at}/{drops} at the pose; settle quartiles {:.1} / {:.1} / {:.1} s; lost {}",
                sm.period(),
                q(0.25),
                q(0.5),
                q(0.75),
                drops - settle.len()
            );
        }
    }
}

/// A part of the pose family (`results/pose_family/polygon_0.json`, a
/// triangle 1.7 cm across, nearly equilateral) designed whole. No spin of
/// `spin::CANDIDATES` hands it over to the ellipse, so the screen tries
/// the lattice again with r* halved (`spin::Spin::finer`) and keeps one of
/// those; the ellipse stage is as long as its torque takes from the
/// hand-over's worst turn (`cycle::Stages::handed_over`). At least 95 % of
/// 100 drops end at the pose (measured 100 %; the elliptic sink alone,
/// kept before the refinement, held 49 %). About 2.5 minutes of CPU:
/// `cargo test --release --test pose_rotation -- --ignored compact_part`.
#[test]
#[ignore = "2.5 minutes of CPU: cargo test --release --test pose_rotation -- --ignored compact_part"]
fn a_compact_part_gets_a_spin_of_half_the_r_star() {
    use platefield::pose::design::spin::CANDIDATES;
    let d = designed("results/pose_family/polygon_0.json");
    let kept = d.spin.expect("a spin is kept");
    assert!(!CANDIDATES.contains(&kept), "{kept:?}");
    assert!(CANDIDATES.iter().any(|c| c.finer() == kept), "{kept:?}");
    let schedule = &d.method.kept().schedule;
    let p = schedule.played.as_ref().unwrap().pose.as_ref().unwrap();
    assert!(p.pose_fraction >= 0.95, "{}", p.pose_fraction);
}

/// Exploration: a cycle's spin stage and whole cycle over μ ± 20 %.
/// `PF_SCHEDULE` a kept cycle's `schedule.json` of `PF_TARGET`, played
/// from the asked pose and the same turned by 180° at μ × 0.8, 1 and 1.2:
/// each part's turn from the asked pose at the end of the spin stage as
/// shipped (ramped) and at each of 4 periods' ends of the whole cycle,
/// its ellipse stage's cycles scaled by `PF_ELLIPSE_SCALE` (default 1)
/// (`cargo test --release --test pose_rotation -- --ignored --nocapture
/// explore_band`).
#[test]
#[ignore = "exploration: PF_TARGET=…json PF_SCHEDULE=…/schedule.json"]
fn explore_band() {
    use platefield::play::ScheduleMotion;
    use platefield::pose::design::search::pose_error;
    use platefield::pose::{play_part, DropPlay, Pose};
    use platefield::schedule::Schedule;
    let env = |k: &str| std::env::var(k).unwrap();
    let req = PoseTarget::load(std::path::Path::new(&env("PF_TARGET")))
        .unwrap()
        .unwrap();
    let mut whole = Schedule::load(std::path::Path::new(&env("PF_SCHEDULE"))).unwrap();
    let scale: f64 = std::env::var("PF_ELLIPSE_SCALE").map_or(1.0, |s| s.parse().unwrap());
    let ellipse = &mut whole.segments[1];
    let period = ellipse.motion.as_ref().unwrap().period;
    ellipse.cycles = (f64::from(ellipse.cycles) * scale).round() as u32;
    ellipse.duration_s = f64::from(ellipse.cycles) * period;
    let total: f64 = whole.segments.iter().map(|s| s.duration_s).sum();
    for seg in &mut whole.segments {
        seg.weight = seg.duration_s / total;
    }
    whole.derive();
    let mut spin = whole.clone();
    spin.segments.truncate(1);
    spin.segments[0].weight = 1.0;
    spin.derive();
    let rival = Pose {
        r: req.pose.r,
        theta: req.pose.theta + std::f64::consts::PI,
    };
    let n = req.part.symmetry();
    let turn = |p: &Pose| pose_error(p, &req.pose, n).1.to_degrees();
    let nominal = whole.settings.friction;
    for k in [0.8, 1.0, 1.2] {
        let at = |s: &Schedule| {
            let mut s = s.clone();
            s.settings.friction.stat = k * nominal.stat;
            s.settings.friction.kinetic = k * nominal.kinetic;
            s
        };
        let (sp, wh) = (at(&spin), at(&whole));
        let sm = ScheduleMotion::from_schedule(&sp).unwrap();
        let play = DropPlay::new(&sp.settings, sm.period());
        let ends: Vec<String> = play_part(&req.part, &sm, &[req.pose, rival], &play)
            .into_iter()
            .map(|r| format!("{:.1}", turn(&r.unwrap().0.pose)))
            .collect();
        let sm = ScheduleMotion::from_schedule(&wh).unwrap();
        let play = DropPlay::new(&wh.settings, 4.0 * sm.period());
        let tracks: Vec<String> = play_part(&req.part, &sm, &[req.pose, rival], &play)
            .into_iter()
            .map(|r| {
                let (_, track) = r.unwrap();
                track
                    .iter()
                    .map(|p| format!("{:.1}", turn(p)))
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .collect();
        println!("μ × {k}: spin stage ends {ends:?}; periods {tracks:?}");
    }
}
